//! The Quest edge: the APK's native entry point and what ties Android's activity lifecycle to
//! the OpenXR frame loop. Thin on purpose: everything else is the same library the desktop
//! runs.
//!
//! * [`activity`]: the activity's state from its lifecycle events and what the frame loop does
//!   about them (pure, tested on the host).
//! * [`options`]: the settings the APK starts with (pure, tested on the host).
//! * `frame_loop` (Android only): `ActivityFrameLoop`, a [`FrameLoop`](crate::xr::FrameLoop)
//!   that wraps [`OpenXr`](crate::xr::openxr::OpenXr) and pumps android-activity's events.
//! * `entry` (Android only): `android_main`, called by android-activity's
//!   `ANativeActivity_onCreate` on its own thread: logcat (tag `vr-ocean`), a panic hook that
//!   logs the panic, the OpenXR backend from the activity's Java VM and Activity, then
//!   [`app::run`](crate::app::run).

pub mod activity;
pub mod options;

#[cfg(target_os = "android")]
mod entry;
#[cfg(target_os = "android")]
pub mod frame_loop;

// The verification link without the NDK (`cargo xtask apk --verify-without-ndk`): bionic has
// no `_Unwind_*` before API 30, so the pure-Rust unwinder provides them.
#[cfg(all(target_os = "android", feature = "verify-without-ndk"))]
use unwinding as _;

/// The logcat tag of every line the app writes (`adb logcat -s vr-ocean`).
pub const LOG_TAG: &str = "vr-ocean";
