//! Our inverse 2D FFT: f32, split complex, N×N for N a power of two in 16..=1024.
//!
//! # Design
//! A planner ([`Fft2d`]) sits above one generic kernel (`kernel.rs`) instantiated per SIMD
//! backend (`scalar.rs`, `x86.rs`, `neon.rs`), chosen at runtime.
//!
//! The 2D transform is two passes, field → scratch → field, of one kernel. A pass walks its
//! source in strips of 16 adjacent columns; SIMD lanes hold adjacent columns, so the column FFT
//! (radix-4 decimation in frequency, the last stage radix 8 for odd log2 N) is purely vertical
//! SIMD with broadcast twiddles and no shuffles. The first stage reads the source directly; the
//! rest run in a small contiguous working buffer that stays in L1. The strip is then written
//! transposed (in-register LANES×LANES block transposes, reading rows in output order to undo
//! the digit reversal). Pass 1 writes the transposed strips into `scratch` as 16×16 tiles so that
//! pass 2 reads them in 1 KiB runs rather than 64-byte lines a row apart (worth a few percent);
//! pass 2 writes plain rows, so the field ends in natural row-major order with no separate
//! transpose or bit-reversal pass.
//!
//! Fields that are zero outside a [`Support`] (the coarse cascades' spectra) go through
//! [`Fft2d::inverse_batch_support`]: pass 1 transforms only the strips that meet its columns and
//! reads only its rows; pass 2 reads only the intermediate rows of its columns (zeros stand in
//! for the rest, which is never read nor written).
//!
//! Scratch content after a call is unspecified. `SimCore` owns 2 scratch fields up to N = 256
//! with two or more threads (the four transforms go in two groups: fewer fork-joins), else 1
//! (cache; see `scratch_fields` in `step.rs`); the grouping never changes the bits.
//!
//! Everything size-dependent (twiddles, stage list, output permutation) is built in
//! [`Fft2d::new`]; transforms allocate nothing and only use a stack working buffer of
//! N × 128 bytes (128 KiB at N = 1024).

mod kernel;
#[cfg(target_arch = "aarch64")]
mod neon;
mod plan;
mod scalar;
#[cfg(test)]
mod tests;
#[cfg(target_arch = "x86_64")]
mod x86;

use std::ops::Range;
use std::sync::atomic::{AtomicU8, Ordering};

use rayon::prelude::*;

use crate::sim::grid::{GridSize, SplitField, Support};
use crate::sim::simd::Tier;
use kernel::Job;
use plan::{CRow, Plan, STRIP};

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

    /// The backend [`Fft2d::new`] plans on: the one [`force_backend`] set, else [`Backend::detect`].
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
const NOT_FORCED: u8 = 0;

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

/// Makes every later [`Fft2d::new`] (and so every `SimCore` created afterwards) plan on `b`
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
fn forced_code(b: Backend) -> u8 {
    let i = Backend::ALL
        .iter()
        .position(|&x| x == b)
        .expect("ALL lists every backend");
    i as u8 + 1
}

/// The backend [`FORCED`] value `code` stands for.
fn backend_of_code(code: u8) -> Option<Backend> {
    code.checked_sub(1)
        .and_then(|i| Backend::ALL.get(i as usize).copied())
}

/// The selected backend together with its proof-of-support token.
#[derive(Clone, Copy, Debug)]
enum Imp {
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
    fn new(b: Backend) -> Option<Imp> {
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

/// A planned inverse 2D FFT of one grid size on one backend. Immutable after [`Fft2d::new`], so
/// one instance can be shared by all threads.
pub struct Fft2d {
    size: GridSize,
    backend: Backend,
    imp: Imp,
    plan: Plan,
}

impl Fft2d {
    /// Plans the inverse FFT of `size` on the fastest backend of this CPU ([`Backend::detect`]),
    /// or the one [`force_backend`] set ([`Backend::preferred`]).
    pub fn new(size: GridSize) -> Fft2d {
        Self::with_backend(size, Backend::preferred())
            .or_else(|| Self::with_backend(size, Backend::Scalar))
            .expect("the scalar backend is always available")
    }

    /// Plans the inverse FFT of `size` on backend `b`; `None` if this CPU (or target) lacks it.
    /// Used by tests and benchmarks to compare backends.
    pub fn with_backend(size: GridSize, b: Backend) -> Option<Fft2d> {
        Some(Fft2d {
            size,
            backend: b,
            imp: Imp::new(b)?,
            plan: Plan::new(size.n()),
        })
    }

    /// The grid size this plan transforms.
    pub fn size(&self) -> GridSize {
        self.size
    }

    /// The backend this plan runs on.
    pub fn backend(&self) -> Backend {
        self.backend
    }

    /// Unnormalized inverse 2D DFT in place:
    /// `x[r][c] = Σ_{kr,kc} X[kr][kc]·exp(+2πi·(kr·r + kc·c)/N)`, natural order in and out.
    /// `scratch` (same size) receives the intermediate result (in an internal tiled layout); its
    /// contents on entry are ignored and on exit are unspecified.
    ///
    /// Allocates nothing; uses a stack working buffer of N × 128 bytes (at most 128 KiB).
    ///
    /// # Panics
    /// If `field` or `scratch` is not of this plan's size.
    pub fn inverse(&self, field: &mut SplitField, scratch: &mut SplitField) {
        self.check(field, scratch);
        with_local(self.size.n(), |local| {
            let n = self.size.n();
            let (dre, dim) = scratch.planes_mut();
            self.run(pass_job(field, dre, dim, 0, &Pass::whole(n, true)), local);
            let (dre, dim) = field.planes_mut();
            self.run(
                pass_job(scratch, dre, dim, 0, &Pass::whole(n, false)),
                local,
            );
        });
    }

    /// [`Fft2d::inverse`] on every field, in parallel over (field, group of column strips) on the
    /// current rayon pool. `scratch` holds 1 to `fields.len()` scratch fields: the fields are
    /// transformed in groups of `scratch.len()`, group after group, so one scratch field per
    /// thread suffices and stays in cache from one field to the next. Each strip is computed by
    /// the same code whatever the thread count or grouping, so results are bit-identical to
    /// calling `inverse` on each field. Allocates nothing beyond rayon's own task bookkeeping;
    /// each task uses a stack working buffer like `inverse`.
    ///
    /// # Panics
    /// If `scratch` is empty or longer than `fields` (while `fields` is not empty), or any field
    /// is not of this plan's size.
    pub fn inverse_batch(&self, fields: &mut [SplitField], scratch: &mut [SplitField]) {
        self.inverse_batch_support(fields, scratch, &Support::full(self.size));
    }

    /// [`Fft2d::inverse_batch`] of fields that are zero outside `support`, which it neither
    /// reads nor needs written: the first pass transforms only the column strips that meet
    /// `support.cols`, reading only the rows `support.rows`; the second reads only the
    /// intermediate rows of the columns `support.cols` (the rest are zero). The default sea's
    /// two coarse cascades at N = 256 need 4 of 16 strips of ~45 rows in the first pass and
    /// ~45 of 256 rows in the second. The butterflies are those of `inverse_batch` on the
    /// same values, so the result differs from it at most in the sign of zeros.
    ///
    /// # Panics
    /// As `inverse_batch`, and if `support` reaches past the grid.
    pub fn inverse_batch_support(
        &self,
        fields: &mut [SplitField],
        scratch: &mut [SplitField],
        support: &Support,
    ) {
        if fields.is_empty() {
            return;
        }
        assert!(
            (1..=fields.len()).contains(&scratch.len()),
            "inverse_batch needs 1 to {} scratch fields, got {}",
            fields.len(),
            scratch.len()
        );
        for f in fields.iter() {
            self.check(f, &scratch[0]);
        }
        for s in scratch.iter() {
            self.check(&fields[0], s);
        }
        let n = self.size.n();
        assert!(
            support.rows.end <= n && support.cols.end <= n,
            "inverse_batch_support: {support:?} reaches past the grid side {n}"
        );
        // Pass 2's source rows are the field's columns; the intermediate of the strips pass 1
        // skips is never written, and never read.
        let first = Pass {
            first: true,
            strips: live_strips(&support.cols),
            rows: support.rows.clone(),
        };
        let second = Pass {
            rows: support.cols.clone(),
            ..Pass::whole(n, false)
        };
        let group = scratch.len();
        for fields in fields.chunks_mut(group) {
            fields
                .par_iter_mut()
                .zip(scratch.par_iter_mut())
                .for_each(|(f, s)| {
                    self.pass_par(f, s, &first, group);
                    self.pass_par(s, f, &second, group);
                });
        }
    }

    /// One pass `src` → `dst` over `pass.strips`, split into rayon tasks (`group` fields run
    /// at once); the other strips' destination is left as it was.
    fn pass_par(&self, src: &SplitField, dst: &mut SplitField, pass: &Pass, group: usize) {
        let strips = pass.strips.clone();
        // Split the pass only as far as needed to give every thread about two tasks: each task
        // clears its own working buffer, so fewer, larger tasks are cheaper. Every strip is
        // computed identically whatever the split, so results don't depend on it.
        let threads = rayon::current_num_threads();
        let count = strips.len().max(1);
        let tasks = (2 * threads).div_ceil(group).min(count);
        let strips_per_task = count.div_ceil(tasks);
        let n = self.size.n();
        let per_strip = STRIP * n;
        let (dre, dim) = dst.planes_mut();
        let live = strips.start * per_strip..strips.end * per_strip;
        let chunk = per_strip * strips_per_task;
        dre[live.clone()]
            .par_chunks_mut(chunk)
            .zip(dim[live].par_chunks_mut(chunk))
            .enumerate()
            .for_each(|(i, (dre, dim))| {
                with_local(n, |local| {
                    let first_strip = strips.start + i * strips_per_task;
                    self.run(pass_job(src, dre, dim, first_strip, pass), local)
                })
            });
    }

    fn check(&self, field: &SplitField, scratch: &SplitField) {
        assert!(
            field.size() == self.size && scratch.size() == self.size,
            "Fft2d of size {} given a field of size {} and scratch of size {}",
            self.size,
            field.size(),
            scratch.size()
        );
    }

    /// Runs one job on this plan's backend.
    fn run(&self, job: Job<'_>, local: &mut [CRow]) {
        match self.imp {
            Imp::Scalar => scalar::pass(&self.plan, job, local),
            #[cfg(target_arch = "x86_64")]
            Imp::Sse2(t) => x86::pass_sse2(t, &self.plan, job, local),
            #[cfg(target_arch = "x86_64")]
            Imp::Avx2(t) => x86::pass_avx2(t, &self.plan, job, local),
            #[cfg(target_arch = "x86_64")]
            Imp::Avx512(t) => x86::pass_avx512(t, &self.plan, job, local),
            #[cfg(target_arch = "aarch64")]
            Imp::Neon(t) => neon::pass_neon(t, &self.plan, job, local),
        }
    }
}

/// The column strips that meet columns `live`.
fn live_strips(live: &Range<usize>) -> Range<usize> {
    if live.is_empty() {
        0..0
    } else {
        live.start / STRIP..live.end.div_ceil(STRIP)
    }
}

/// One pass of a 2D transform: which one, the strips it transforms and the source rows that
/// may hold non-zeros.
#[derive(Clone, Debug)]
struct Pass {
    /// Pass 1 (field → intermediate) or pass 2.
    first: bool,
    /// The strips transformed; the others' destination is not written.
    strips: Range<usize>,
    /// The source rows read; the others are taken as zero.
    rows: Range<usize>,
}

impl Pass {
    /// Every strip and every row of an `n`-grid.
    fn whole(n: usize, first: bool) -> Pass {
        Pass {
            first,
            strips: 0..n / STRIP,
            rows: 0..n,
        }
    }
}

/// The job that transforms `src`'s strips `first_strip..` into `dst_re`/`dst_im`.
fn pass_job<'a>(
    src: &'a SplitField,
    dst_re: &'a mut [f32],
    dst_im: &'a mut [f32],
    first_strip: usize,
    pass: &Pass,
) -> Job<'a> {
    Job {
        src_re: &src.re,
        src_im: &src.im,
        dst_re,
        dst_im,
        first_strip,
        src_rows: pass.rows.clone(),
        first_pass: pass.first,
    }
}

/// Calls `f` with a zeroed stack working buffer of `n` rows (128 bytes each), sized in tiers so
/// small grids don't pay for clearing the 128 KiB a 1024 grid needs (a tier per size from 128:
/// a 128 grid cleared 32 KiB per task for its 16).
fn with_local<R>(n: usize, f: impl FnOnce(&mut [CRow]) -> R) -> R {
    if n <= 64 {
        let mut buf = [CRow::ZERO; 64];
        f(&mut buf[..n])
    } else if n <= 128 {
        let mut buf = [CRow::ZERO; 128];
        f(&mut buf[..n])
    } else if n <= 256 {
        let mut buf = [CRow::ZERO; 256];
        f(&mut buf[..n])
    } else if n <= 512 {
        let mut buf = [CRow::ZERO; 512];
        f(&mut buf[..n])
    } else {
        let mut buf = [CRow::ZERO; 1024];
        f(&mut buf[..n])
    }
}
