//! Runtime ISA dispatch for the element-wise stages (evolution, surface, mips).
//!
//! Their loops are plain Rust that the compiler vectorizes; [`dispatch!`] compiles a kernel a
//! second time for AVX2 on x86-64 CPUs that have it (8 lanes instead of SSE2's 4, plus
//! `roundps`, `pmulld`, `vcvt*` conversions). Rust never contracts a·b + c into an FMA, so both
//! builds, and the NEON build on aarch64, compute identical bits.

/// True when this x86-64 CPU runs AVX2 and FMA (cached by std after the first call).
#[cfg(target_arch = "x86_64")]
#[inline]
pub fn has_avx2() -> bool {
    std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
}

/// `dispatch!(vis fn name(arg: Ty, ...) => kernel);` defines `name`, which calls the
/// `#[inline(always)]` function `kernel` compiled for AVX2 + FMA when the CPU has them and for
/// the target's baseline otherwise.
macro_rules! dispatch {
    ($(#[$m:meta])* $vis:vis fn $name:ident($($arg:ident : $ty:ty),* $(,)?) => $kernel:path) => {
        $(#[$m])*
        $vis fn $name($($arg: $ty),*) {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2,fma")]
                unsafe fn wide($($arg: $ty),*) {
                    $kernel($($arg),*)
                }
                if $crate::sim::simd::has_avx2() {
                    // SAFETY: the CPU supports AVX2 and FMA, checked just above.
                    return unsafe { wide($($arg),*) };
                }
            }
            $kernel($($arg),*)
        }
    };
}
pub(crate) use dispatch;
