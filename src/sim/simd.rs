//! Runtime ISA dispatch for the element-wise stages (evolution, surface, mips).
//!
//! Their loops are plain Rust that the compiler vectorizes; `dispatch!` compiles a kernel again
//! for AVX-512 (16 lanes, 32 registers: no spills in the evolution loop) and for AVX2 (8 lanes)
//! on x86-64 CPUs that have them, besides the baseline (SSE2's 4 lanes; NEON on aarch64). Rust
//! never contracts a·b + c into an FMA and the kernels use only correctly rounded operations, so
//! every build computes identical bits.

use std::sync::atomic::{AtomicU8, Ordering};

/// An instruction-set tier of the element-wise kernels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
#[repr(u8)]
pub enum Tier {
    /// The target's baseline (SSE2 on x86-64, NEON on aarch64).
    Baseline = 0,
    /// AVX2 + FMA.
    Avx2 = 1,
    /// AVX-512 F/VL/BW/DQ.
    Avx512 = 2,
}

static CAP: AtomicU8 = AtomicU8::new(Tier::Avx512 as u8);

/// Caps the tier the kernels may use (default: the best the CPU has). For tests and
/// benchmarks that compare tiers; results are identical at every tier.
pub fn cap_tier(tier: Tier) {
    CAP.store(tier as u8, Ordering::Relaxed);
}

/// The cap [`cap_tier`] last set ([`Tier::Avx512`], no cap, by default).
pub fn tier_cap() -> Tier {
    match CAP.load(Ordering::Relaxed) {
        0 => Tier::Baseline,
        1 => Tier::Avx2,
        _ => Tier::Avx512,
    }
}

/// The tier the kernels run at now: the best the CPU supports, within [`cap_tier`].
pub fn active_tier() -> Tier {
    let cap = CAP.load(Ordering::Relaxed);
    #[cfg(target_arch = "x86_64")]
    {
        if cap >= Tier::Avx512 as u8 && has_avx512() {
            return Tier::Avx512;
        }
        if cap >= Tier::Avx2 as u8 && has_avx2() {
            return Tier::Avx2;
        }
    }
    let _ = cap;
    Tier::Baseline
}

/// True when this x86-64 CPU runs the AVX-512 subsets the kernels are built for.
#[cfg(target_arch = "x86_64")]
#[inline]
pub fn has_avx512() -> bool {
    std::is_x86_feature_detected!("avx512f")
        && std::is_x86_feature_detected!("avx512vl")
        && std::is_x86_feature_detected!("avx512bw")
        && std::is_x86_feature_detected!("avx512dq")
        && has_avx2()
}

/// True when this x86-64 CPU runs AVX2 and FMA (cached by std after the first call).
#[cfg(target_arch = "x86_64")]
#[inline]
pub fn has_avx2() -> bool {
    std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
}

/// `dispatch!(vis fn name(arg: Ty, ...) => kernel);` defines `name`, which calls the
/// `#[inline(always)]` function `kernel` compiled for AVX-512, else AVX2 + FMA, when the CPU has
/// them, and for the target's baseline otherwise.
macro_rules! dispatch {
    ($(#[$m:meta])* $vis:vis fn $name:ident($($arg:ident : $ty:ty),* $(,)?) => $kernel:path) => {
        $(#[$m])*
        $vis fn $name($($arg: $ty),*) {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma")]
                unsafe fn wider($($arg: $ty),*) {
                    $kernel($($arg),*)
                }
                #[target_feature(enable = "avx2,fma")]
                unsafe fn wide($($arg: $ty),*) {
                    $kernel($($arg),*)
                }
                match $crate::sim::simd::active_tier() {
                    // SAFETY: `active_tier` only returns tiers the CPU supports.
                    $crate::sim::simd::Tier::Avx512 => return unsafe { wider($($arg),*) },
                    // SAFETY: as above.
                    $crate::sim::simd::Tier::Avx2 => return unsafe { wide($($arg),*) },
                    $crate::sim::simd::Tier::Baseline => {}
                }
            }
            $kernel($($arg),*)
        }
    };
}
pub(crate) use dispatch;
