//! What the Quest APK is: the Rust target and minimum API level, the app's ids, the Android
//! framework it is linked against without an SDK.

/// The Rust target of the Quest.
pub const ANDROID_TARGET: &str = "aarch64-linux-android";

/// The minimum API level (Quest OS is Android 10 and later).
pub const MIN_API: u32 = 29;

/// The application id in `android/AndroidManifest.xml`.
pub const PACKAGE: &str = "com.vrocean.ocean";

/// The launchable activity (Android's own NativeActivity).
pub const ACTIVITY: &str = "android.app.NativeActivity";

/// The logcat tag of the app (`vr_ocean::android::LOG_TAG`).
pub const LOG_TAG: &str = "vr-ocean";

/// Debian's `framework-res.apk` of API 29 (package `android-framework-res`).
pub const DEBIAN_FRAMEWORK_RES: &str = "/usr/share/android-framework-res/framework-res.apk";
