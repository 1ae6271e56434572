//! Our inverse 2D FFT: f32, split complex, N×N for N a power of two in 16..=1024.
//!
//! # Design
//! A planner ([`Fft2d`]) sits above one generic kernel (`kernel.rs`, its first stage in
//! `first_stage.rs`) instantiated per SIMD backend (`scalar.rs`, `x86.rs`, `neon.rs`), chosen
//! at runtime (`backend.rs`).
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
//! A Hermitian spectrum's real result can come as row pairs ([`Output::RealRowPairs`], the
//! finite-difference mode's Z): pass 1's first stage folds spectrum rows r and r + N/2 into one
//! (the column transform's first radix-2 step, even and odd outputs packed as re and im), so
//! pass 1 runs length-N/2 column transforms and pass 2 half the strips. Measured alone at
//! N = 256 it takes 0.66-0.70 of a complex transform (docs/notes/fft-128bit.md).
//!
//! Scratch content after a call is unspecified. `SimCore` owns 2 scratch fields up to N = 256
//! with two or more threads (the four transforms go in two groups: fewer fork-joins), else 1
//! (cache; see `scratch_fields` in `step.rs`); the grouping never changes the bits.
//!
//! Everything size-dependent (twiddles, stage list, output permutation) is built in
//! [`Fft2d::new`]. Each thread keeps one working buffer of N × 128 bytes (128 KiB at
//! N = 1024), made the first time the thread meets a grid that large
//! ([`Fft2d::prepare_threads`] makes it up front) and never cleared: a pass's first stage
//! writes every row before any stage reads one. After that, transforms allocate nothing.

mod backend;
mod butterfly;
mod first_stage;
mod kernel;
#[cfg(target_arch = "aarch64")]
mod neon;
mod plan;
mod scalar;
#[cfg(test)]
mod tests;
#[cfg(target_arch = "x86_64")]
mod x86;

use std::cell::RefCell;
use std::ops::Range;

use rayon::prelude::*;

use crate::sim::grid::{GridSize, SplitField, Support};
use backend::Imp;
pub use backend::{force_backend, forced_backend, Backend, UnavailableBackend};
use kernel::Job;
use plan::{CRow, Plan, STRIP};

/// A planned inverse 2D FFT of one grid size on one backend. Immutable after [`Fft2d::new`], so
/// one instance can be shared by all threads.
pub struct Fft2d {
    size: GridSize,
    backend: Backend,
    imp: Imp,
    plan: Plan,
    /// The length-N/2 plan of a folded transform's first pass ([`Output::RealRowPairs`]);
    /// `None` at N = 16, whose folded output is made from the whole transform.
    half: Option<Plan>,
    /// i·exp(+2πi·r/N) for r < N/2 as (re, im) pairs: the fold's factors ([`kernel::Job::fold`]).
    fold: Vec<f32>,
}

/// What [`Fft2d::inverse_batch_support_as`] makes of one field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// The whole complex result, natural order (as [`Fft2d::inverse`]).
    Complex,
    /// For a Hermitian spectrum, whose result x is real: x's rows 2p and 2p + 1 as the real
    /// and imaginary plane of row p < N/2 (rows N/2.. are left unspecified). The spectrum's
    /// rows r and r + N/2 are folded into one (the first radix-2 step of the column transform,
    /// the even and odd outputs packed as one complex row), so both passes run over half the
    /// rows: 0.66-0.70 of the time of [`Output::Complex`] at N = 256 (0.6 at 512, 0.85 at 128;
    /// pass 1 still reads every spectrum row).
    RealRowPairs,
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
        let n = size.n();
        let fold = (0..n / 2)
            .flat_map(|r| {
                let (s, c) = (2.0 * std::f64::consts::PI * r as f64 / n as f64).sin_cos();
                [-s as f32, c as f32]
            })
            .collect();
        Some(Fft2d {
            size,
            backend: b,
            imp: Imp::new(b)?,
            plan: Plan::new(n),
            half: (n >= 32).then(|| Plan::new(n / 2)),
            fold,
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

    /// Gives every thread of the current Rayon pool its working buffer for this size now, so
    /// that no transform allocates later (each thread keeps one, grown on first use).
    pub fn prepare_threads(&self) {
        let n = self.size.n();
        rayon::broadcast(|_| grow_local(n));
    }

    /// Unnormalized inverse 2D DFT in place:
    /// `x[r][c] = Σ_{kr,kc} X[kr][kc]·exp(+2πi·(kr·r + kc·c)/N)`, natural order in and out.
    /// `scratch` (same size) receives the intermediate result (in an internal tiled layout); its
    /// contents on entry are ignored and on exit are unspecified.
    ///
    /// Allocates nothing once this thread has its working buffer (N × 128 bytes, at most
    /// 128 KiB; see the module doc).
    ///
    /// # Panics
    /// If `field` or `scratch` is not of this plan's size.
    pub fn inverse(&self, field: &mut SplitField, scratch: &mut SplitField) {
        self.check(field, scratch);
        with_local(self.size.n(), |local| {
            let (dre, dim) = scratch.planes_mut();
            let first = self.whole(true);
            self.run(pass_job(field, dre, dim, 0, &first), local);
            let (dre, dim) = field.planes_mut();
            let second = self.whole(false);
            self.run(pass_job(scratch, dre, dim, 0, &second), local);
        });
    }

    /// [`Fft2d::inverse`] on every field, in parallel over (field, group of column strips) on the
    /// current rayon pool. `scratch` holds 1 to `fields.len()` scratch fields: the fields are
    /// transformed in groups of `scratch.len()`, group after group, so one scratch field per
    /// thread suffices and stays in cache from one field to the next. Each strip is computed by
    /// the same code whatever the thread count or grouping, so results are bit-identical to
    /// calling `inverse` on each field. Allocates nothing beyond rayon's own task bookkeeping;
    /// each task uses its thread's working buffer like `inverse`.
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
        self.batch(fields, |_| Output::Complex, scratch, support);
    }

    /// [`Fft2d::inverse_batch_support`] with field i made as `outputs[i]` says: a Hermitian
    /// spectrum's real result as [`Output::RealRowPairs`] costs about 0.7 of a complex
    /// transform. Bit-identical for any thread count and grouping, as `inverse_batch`.
    ///
    /// # Panics
    /// As [`Fft2d::inverse_batch_support`], and if `outputs` is not as long as `fields`.
    pub fn inverse_batch_support_as(
        &self,
        fields: &mut [SplitField],
        outputs: &[Output],
        scratch: &mut [SplitField],
        support: &Support,
    ) {
        assert_eq!(
            outputs.len(),
            fields.len(),
            "inverse_batch_support_as needs one output per field"
        );
        self.batch(fields, |i| outputs[i], scratch, support);
    }

    /// The batch transform behind the public entry points; `output(i)` for field i.
    fn batch(
        &self,
        fields: &mut [SplitField],
        output: impl Fn(usize) -> Output + Sync,
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
            strips: live_strips(&support.cols),
            rows: support.rows.clone(),
            ..self.whole(true)
        };
        let second = Pass {
            rows: support.cols.clone(),
            ..self.whole(false)
        };
        // The folded transform: pass 1 reads the N rows as N/2 folded ones and writes an
        // intermediate of N/2 columns, which pass 2 turns into N/2 rows.
        let folded = self.half.as_ref().map(|half| {
            let first = Pass {
                plan: half,
                fold: Some(&self.fold[..]),
                ..first.clone()
            };
            let second = Pass {
                strips: 0..n / 2 / STRIP,
                width: n / 2,
                ..second.clone()
            };
            (first, second)
        });
        let group = scratch.len();
        for (g, fields) in fields.chunks_mut(group).enumerate() {
            fields
                .par_iter_mut()
                .zip(scratch.par_iter_mut())
                .enumerate()
                .for_each(|(i, (f, s))| match (output(g * group + i), &folded) {
                    (Output::RealRowPairs, Some((first, second))) => {
                        self.pass_par(f, s, first, group);
                        self.pass_par(s, f, second, group);
                    }
                    (out, _) => {
                        self.pass_par(f, s, &first, group);
                        self.pass_par(s, f, &second, group);
                        if out == Output::RealRowPairs {
                            pair_rows(f);
                        }
                    }
                });
        }
    }

    /// Pass 1 or 2 of the whole N×N complex transform.
    fn whole(&self, first: bool) -> Pass<'_> {
        let n = self.size.n();
        Pass {
            first,
            strips: 0..n / STRIP,
            rows: 0..n,
            width: n,
            plan: &self.plan,
            fold: None,
        }
    }

    /// One pass `src` → `dst` over `pass.strips`, split into rayon tasks (`group` fields run
    /// at once); the other strips' destination is left as it was.
    fn pass_par(&self, src: &SplitField, dst: &mut SplitField, pass: &Pass, group: usize) {
        let strips = pass.strips.clone();
        // Split the pass only as far as needed to give every thread about two tasks (one task
        // on one thread: nothing to balance): each task has its fork-join's cost, so
        // fewer, larger tasks are cheaper. Every strip is computed identically whatever the
        // split, so results don't depend on it.
        let threads = rayon::current_num_threads();
        let count = strips.len().max(1);
        let per_thread = if threads == 1 { 1 } else { 2 };
        let tasks = (per_thread * threads).div_ceil(group).min(count);
        let strips_per_task = count.div_ceil(tasks);
        let n = pass.plan.n;
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
                    self.run(pass_job(src, dre, dim, first_strip, pass), local);
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

    /// Runs one job of a pass planned by `plan` on this plan's backend.
    fn run(&self, (plan, job): (&Plan, Job<'_>), local: &mut [CRow]) {
        match self.imp {
            Imp::Scalar => scalar::pass(plan, job, local),
            #[cfg(target_arch = "x86_64")]
            Imp::Sse2(t) => x86::pass_sse2(t, plan, job, local),
            #[cfg(target_arch = "x86_64")]
            Imp::Avx2(t) => x86::pass_avx2(t, plan, job, local),
            #[cfg(target_arch = "x86_64")]
            Imp::Avx512(t) => x86::pass_avx512(t, plan, job, local),
            #[cfg(target_arch = "aarch64")]
            Imp::Neon(t) => neon::pass_neon(t, plan, job, local),
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

/// One pass of a 2D transform: which one, the strips it transforms, the source rows that
/// may hold non-zeros, and its shape.
#[derive(Clone)]
struct Pass<'a> {
    /// Pass 1 (field → intermediate) or pass 2.
    first: bool,
    /// The strips transformed; the others' destination is not written.
    strips: Range<usize>,
    /// The source rows read; the others are taken as zero.
    rows: Range<usize>,
    /// See [`Job::width`].
    width: usize,
    /// The column transform (length N, or N/2 in a folded pass 1).
    plan: &'a Plan,
    /// See [`Job::fold`].
    fold: Option<&'a [f32]>,
}

/// The job that transforms `src`'s strips `first_strip..` into `dst_re`/`dst_im`, with the
/// plan it runs.
fn pass_job<'a>(
    src: &'a SplitField,
    dst_re: &'a mut [f32],
    dst_im: &'a mut [f32],
    first_strip: usize,
    pass: &Pass<'a>,
) -> (&'a Plan, Job<'a>) {
    let job = Job {
        src_re: &src.re,
        src_im: &src.im,
        dst_re,
        dst_im,
        first_strip,
        src_rows: pass.rows.clone(),
        first_pass: pass.first,
        width: pass.width,
        fold: pass.fold,
    };
    (pass.plan, job)
}

/// [`Output::RealRowPairs`] from a whole transform's real plane (N = 16, which has no half
/// plan): row 2p + 1 into the imaginary plane's row p, then row 2p into the real plane's row p
/// (p ascending reads each row before it is overwritten).
fn pair_rows(f: &mut SplitField) {
    let n = f.size().n();
    let (re, im) = f.planes_mut();
    for p in 0..n / 2 {
        im[p * n..(p + 1) * n].copy_from_slice(&re[(2 * p + 1) * n..(2 * p + 2) * n]);
        re.copy_within(2 * p * n..(2 * p + 1) * n, p * n);
    }
}

thread_local! {
    /// This thread's working buffer. Zeroed only when it grows: a pass's first stage writes
    /// all N rows before any stage reads one, so tasks need not clear it (clearing a stack
    /// buffer per task cost 2-4 % of the FFT: 32 KiB per task at N = 256).
    static LOCAL: RefCell<Vec<CRow>> = const { RefCell::new(Vec::new()) };
}

/// Grows this thread's working buffer to `n` rows (allocates only the first time a thread
/// meets a larger grid).
fn grow_local(n: usize) {
    with_local(n, |_| ());
}

/// Calls `f` with this thread's working buffer of `n` rows (128 bytes each), grown on first
/// use; a stack buffer if the thread's is in use (no caller nests today).
fn with_local<R>(n: usize, f: impl FnOnce(&mut [CRow]) -> R) -> R {
    let mut f = Some(f);
    let done = LOCAL
        .try_with(|b| {
            let mut b = b.try_borrow_mut().ok()?;
            if b.len() < n {
                b.resize(n, CRow::ZERO);
            }
            let f = f.take()?;
            Some(f(&mut b[..n]))
        })
        .ok()
        .flatten();
    match (done, f) {
        (Some(r), _) => r,
        (None, Some(f)) => with_stack_local(n, f),
        (None, None) => unreachable!("f runs at most once"),
    }
}

/// Calls `f` with a zeroed stack working buffer of `n` rows, sized in tiers so small grids
/// don't pay for clearing the 128 KiB a 1024 grid needs.
fn with_stack_local<R>(n: usize, f: impl FnOnce(&mut [CRow]) -> R) -> R {
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
