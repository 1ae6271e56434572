//! Which instruction-set implementation of the kernel runs: the backends, their detection on
//! this CPU, and the process-wide override benchmarks use to measure a lower tier.

use std::sync::atomic::{AtomicU8, Ordering};

use crate::sim::simd::Tier;

#[cfg(target_arch = "aarch64")]
use super::neon;
#[cfg(target_arch = "x86_64")]
use super::x86;

/// An instruction-set implementation of the kernel. All variants exist on every target so code
/// can name them portably; [`Backend::available`] lists the ones this CPU can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Backend {
    /// Portable code over `[f32; 4]` (whatever the compiler makes of it). Runs everywhere.
    Scalar,
    /// x86_64 SSE2, 4 lanes, no FMA. Always present on x86_64.
    Sse2,
    /// x86_64 AVX2 + FMA, 8 lanes.
    Avx2,
    /// x86_64 AVX-512F, 16 lanes.
    Avx512,
    /// aarch64 NEON (AdvSIMD), 4 lanes with FMA. Always present on aarch64.
    Neon,
}

impl Backend {
    /// Every backend, in the order of [`Backend::available`] on the target that has it.
    pub const ALL: [Backend; 5] = [
        Backend::Scalar,
        Backend::Sse2,
        Backend::Avx2,
        Backend::Avx512,
        Backend::Neon,
    ];

    /// The backend named as [`Backend`]'s `Display` writes it (`scalar`, `sse2`, `avx2`,
    /// `avx512`, `neon`), ASCII case ignored.
    pub fn from_name(name: &str) -> Option<Backend> {
        Self::ALL
            .into_iter()
            .find(|b| b.to_string().eq_ignore_ascii_case(name.trim()))
    }

    /// Whether this CPU (and target) can run the backend.
    pub fn is_available(self) -> bool {
        Imp::new(self).is_some()
    }

    /// The tier of the element-wise kernels ([`crate::sim::simd`]) that goes with this FFT
    /// backend: the same vector width where one exists (AVX2, AVX-512), else the target's
    /// baseline (SSE2 on x86-64, NEON on aarch64: the element-wise kernels have no tier below it).
    pub fn element_tier(self) -> Tier {
        match self {
            Backend::Avx512 => Tier::Avx512,
            Backend::Avx2 => Tier::Avx2,
            Backend::Scalar | Backend::Sse2 | Backend::Neon => Tier::Baseline,
        }
    }

    /// The backend [`super::Fft2d::new`] plans on: the one [`force_backend`] set, else [`Backend::detect`].
    pub fn preferred() -> Backend {
        forced_backend().unwrap_or_else(Backend::detect)
    }

    /// The fastest backend this CPU supports. On x86_64 the preference is
    /// AVX-512 > AVX2 > SSE2 (AVX-512 measured faster than AVX2 on Zen 5, see `benches/fft.rs`);
    /// on aarch64 NEON.
    pub fn detect() -> Backend {
        Self::available()
            .into_iter()
            .last()
            .unwrap_or(Backend::Scalar)
    }

    /// Every backend this CPU can run, slowest first (Scalar is always first).
    pub fn available() -> Vec<Backend> {
        let mut v = vec![Backend::Scalar];
        #[cfg(target_arch = "x86_64")]
        {
            v.push(Backend::Sse2);
            if x86::Avx2::detect().is_some() {
                v.push(Backend::Avx2);
            }
            if x86::Avx512::detect().is_some() {
                v.push(Backend::Avx512);
            }
        }
        #[cfg(target_arch = "aarch64")]
        if neon::Neon::detect().is_some() {
            v.push(Backend::Neon);
        }
        v
    }
}

impl std::fmt::Display for Backend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Backend::Scalar => "scalar",
            Backend::Sse2 => "sse2",
            Backend::Avx2 => "avx2",
            Backend::Avx512 => "avx512",
            Backend::Neon => "neon",
        })
    }
}

/// [`force_backend`]'s choice: 0 for none, else 1 + the index in [`Backend::ALL`].
static FORCED: AtomicU8 = AtomicU8::new(NOT_FORCED);

/// [`FORCED`] when no backend is forced.
pub(super) const NOT_FORCED: u8 = 0;

/// A backend this CPU cannot run was asked for ([`force_backend`], `vr-ocean bench --tiers`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnavailableBackend {
    /// The backend asked for.
    pub wanted: Backend,
    /// What this CPU runs instead ([`Backend::available`]).
    pub available: Vec<Backend>,
}

impl std::fmt::Display for UnavailableBackend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<String> = self.available.iter().map(|b| b.to_string()).collect();
        write!(
            f,
            "SIMD tier {} is not available on this CPU or target (available: {})",
            self.wanted,
            names.join(", ")
        )
    }
}

impl std::error::Error for UnavailableBackend {}

/// Makes every later [`super::Fft2d::new`] (and so every `SimCore` created afterwards) plan on `b`
/// instead of the fastest backend, process-wide; `None` restores the default. Plans made before
/// keep their backend. For benchmarks that measure a lower tier on a CPU that has a higher one
/// (the 128-bit SSE2 path stands in for the headset's NEON); the element-wise kernels have
/// their own cap ([`crate::sim::simd::cap_tier`], see [`Backend::element_tier`]).
///
/// # Errors
/// [`UnavailableBackend`] (and nothing changes) if this CPU or target cannot run `b`.
pub fn force_backend(b: Option<Backend>) -> Result<(), UnavailableBackend> {
    let code = match b {
        None => NOT_FORCED,
        Some(b) if b.is_available() => forced_code(b),
        Some(wanted) => {
            return Err(UnavailableBackend {
                wanted,
                available: Backend::available(),
            })
        }
    };
    FORCED.store(code, Ordering::Relaxed);
    Ok(())
}

/// The backend [`force_backend`] set, if any.
pub fn forced_backend() -> Option<Backend> {
    backend_of_code(FORCED.load(Ordering::Relaxed))
}

/// [`FORCED`]'s encoding of `b`.
pub(super) fn forced_code(b: Backend) -> u8 {
    let i = Backend::ALL
        .iter()
        .position(|&x| x == b)
        .expect("ALL lists every backend");
    i as u8 + 1
}

/// The backend [`FORCED`] value `code` stands for.
pub(super) fn backend_of_code(code: u8) -> Option<Backend> {
    code.checked_sub(1)
        .and_then(|i| Backend::ALL.get(i as usize).copied())
}

/// The selected backend together with its proof-of-support token.
#[derive(Clone, Copy, Debug)]
pub(super) enum Imp {
    Scalar,
    #[cfg(target_arch = "x86_64")]
    Sse2(x86::Sse2),
    #[cfg(target_arch = "x86_64")]
    Avx2(x86::Avx2),
    #[cfg(target_arch = "x86_64")]
    Avx512(x86::Avx512),
    #[cfg(target_arch = "aarch64")]
    Neon(neon::Neon),
}

impl Imp {
    pub(super) fn new(b: Backend) -> Option<Imp> {
        match b {
            Backend::Scalar => Some(Imp::Scalar),
            #[cfg(target_arch = "x86_64")]
            Backend::Sse2 => Some(Imp::Sse2(x86::Sse2::new())),
            #[cfg(target_arch = "x86_64")]
            Backend::Avx2 => x86::Avx2::detect().map(Imp::Avx2),
            #[cfg(target_arch = "x86_64")]
            Backend::Avx512 => x86::Avx512::detect().map(Imp::Avx512),
            #[cfg(target_arch = "aarch64")]
            Backend::Neon => neon::Neon::detect().map(Imp::Neon),
            #[allow(unreachable_patterns)]
            _ => None,
        }
    }
}
