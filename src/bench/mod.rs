//! `vr-ocean bench`: per-stage simulation times next to FFT baselines measured in the same run.
//! Shared machines are noisy, so results are medians and the verdicts are ratios.

#[cfg(feature = "fftw")]
pub mod fftw;
#[cfg(feature = "baselines")]
mod rustfft_2d;

use std::time::{Duration, Instant};

use crate::sim::config::OceanConfig;
use crate::sim::fft::{force_backend, forced_backend, Backend, Fft2d, UnavailableBackend};
use crate::sim::grid::{GridSize, SplitField};
use crate::sim::params::Derivatives;
use crate::sim::simd::{cap_tier, tier_cap};
use crate::sim::step::{SimCore, SimError, Surfaces};

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// Grid sides to run.
    pub sizes: Vec<GridSize>,
    /// Thread counts to run each size with.
    pub threads: Vec<usize>,
    /// SIMD tiers to run each size on, in the order given: the FFT on that backend and the
    /// element-wise kernels at its [`Backend::element_tier`]. Empty: every tier this CPU has,
    /// fastest first ([`all_tiers`]).
    pub tiers: Vec<Backend>,
    /// Derivative modes to run each tier and thread count with (empty: the config's).
    pub derivatives: Vec<Derivatives>,
    /// Timed repetitions per measurement (after warm-up).
    pub iterations: usize,
    /// Wave parameters and cascades (the grid is replaced by each size).
    pub config: OceanConfig,
    /// Also time rustfft and FFTW (when compiled in). Their buffers crowd the shared cache,
    /// which disturbs multi-thread scaling measured in the same rounds, so scaling runs skip them.
    pub baselines: bool,
}

/// Every SIMD tier this CPU runs, fastest first (the default of [`BenchOptions::tiers`]).
pub fn all_tiers() -> Vec<Backend> {
    Backend::available().into_iter().rev().collect()
}

/// Median times (ms) for one grid size, SIMD tier and thread count.
#[derive(Clone, Debug, Default)]
pub struct BenchRow {
    /// Grid side.
    pub n: usize,
    /// Worker threads.
    pub threads: usize,
    /// Stage 1, spectrum generation (on demand, not per frame).
    pub spectrum_ms: f64,
    /// Stage 2 per step.
    pub evolve_ms: f64,
    /// Stages 3-4 per step (four inverse 2D FFTs per cascade).
    pub fft_ms: f64,
    /// Stages 5-6+ per step.
    pub surface_ms: f64,
    /// Stages 2-6 of a step (evolve + FFT + surface, summed per run): the step of the
    /// performance goals.
    pub step_ms: f64,
    /// Everything `SimCore::step` times ([`crate::sim::StageTimes::total`]), stages after the
    /// surface included.
    pub total_ms: f64,
    /// Our batch of four inverse 2D FFTs alone.
    pub ours_fft4_ms: f64,
    /// rustfft, four 2D inverse transforms rows then columns (single thread rows only).
    pub rustfft4_ms: Option<f64>,
    /// FFTW FFTW_PATIENT, four 2D inverse transforms (single thread rows only).
    pub fftw4_ms: Option<f64>,
    /// The FFT backend that ran (the SIMD tier of the row).
    pub backend: String,
    /// How the step took its derivatives (spectral: 4 FFTs per cascade, finite: 2).
    pub derivatives: Option<Derivatives>,
}

fn median_ms(samples: &mut [Duration]) -> f64 {
    samples.sort();
    samples[samples.len() / 2].as_secs_f64() * 1e3
}

/// Parts of one timed run: [evolve, fft, surface, stages 2-6, total] (unused parts zero).
type Parts = [Duration; PARTS];

/// Number of parts a contender reports per run.
const PARTS: usize = 5;

/// Index of the FFT time in [`Parts`] (the only part the FFT-only contenders fill).
const FFT_PART: usize = 1;

/// A run that times only an FFT.
fn fft_only(d: Duration) -> Parts {
    let mut p = [Duration::ZERO; PARTS];
    p[FFT_PART] = d;
    p
}

/// One timed thing.
type Contender<'a> = Box<dyn FnMut() -> Parts + Send + 'a>;

/// Consecutive runs of one contender per round; the first [`BLOCK_WARMUP`] of each block are
/// discarded (the previous contender's idle Rayon workers are still spinning then, and caches
/// hold its data).
const BLOCK: usize = 8;
/// Runs discarded at the start of each block.
const BLOCK_WARMUP: usize = 2;

/// Runs `contenders` in rounds, a block of [`BLOCK`] consecutive runs each per round, so slow
/// drifts of a shared machine hit all of them alike while every kept run is warm. Returns the
/// per-part medians (ms) of each contender over about `iterations` kept runs.
fn interleaved(contenders: &mut [Contender<'_>], iterations: usize) -> Vec<[f64; PARTS]> {
    let mut samples: Vec<Vec<Parts>> = vec![Vec::new(); contenders.len()];
    let rounds = iterations.div_ceil(BLOCK - BLOCK_WARMUP);
    for _ in 0..rounds {
        for (c, s) in contenders.iter_mut().zip(&mut samples) {
            for run in 0..BLOCK {
                let d = c();
                if run >= BLOCK_WARMUP {
                    s.push(d);
                }
            }
        }
    }
    samples
        .into_iter()
        .map(|s| {
            std::array::from_fn(|k| {
                let mut part: Vec<Duration> = s.iter().map(|d| d[k]).collect();
                median_ms(&mut part)
            })
        })
        .collect()
}

fn pool(threads: usize) -> Result<rayon::ThreadPool, SimError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| SimError::Threads(e.to_string()))
}

/// Why a benchmark could not run.
#[derive(Debug)]
pub enum BenchError {
    /// The simulation could not start.
    Sim(SimError),
    /// A SIMD tier this CPU lacks was asked for.
    Tier(UnavailableBackend),
}

impl std::fmt::Display for BenchError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BenchError::Sim(e) => e.fmt(f),
            BenchError::Tier(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for BenchError {}

impl From<SimError> for BenchError {
    fn from(e: SimError) -> Self {
        BenchError::Sim(e)
    }
}

impl From<UnavailableBackend> for BenchError {
    fn from(e: UnavailableBackend) -> Self {
        BenchError::Tier(e)
    }
}

/// Runs `f` with new FFT plans forced onto `tier` and the element-wise kernels capped at its
/// [`Backend::element_tier`], then restores both settings. `tier` must be available.
fn at_tier<R>(tier: Backend, f: impl FnOnce() -> R) -> R {
    let (forced, cap) = (forced_backend(), tier_cap());
    force_backend(Some(tier)).expect("tiers are checked before measuring");
    cap_tier(tier.element_tier());
    let r = f();
    cap_tier(cap);
    force_backend(forced).expect("it was forced before, so it is available");
    r
}

/// Runs every size: all tiers, thread counts and baselines of one size are interleaved (see
/// `interleaved`). Baselines are single-threaded and reported in the 1-thread rows.
///
/// # Errors
/// A tier this CPU lacks ([`BenchError::Tier`], checked before anything runs), or a pool or
/// simulation that cannot start.
pub fn run(opts: &BenchOptions) -> Result<Vec<BenchRow>, BenchError> {
    let tiers = if opts.tiers.is_empty() {
        all_tiers()
    } else {
        opts.tiers.clone()
    };
    if let Some(&wanted) = tiers.iter().find(|b| !b.is_available()) {
        return Err(UnavailableBackend {
            wanted,
            available: Backend::available(),
        }
        .into());
    }
    let modes = if opts.derivatives.is_empty() {
        vec![opts.config.derivatives]
    } else {
        opts.derivatives.clone()
    };
    let mut rows = Vec::new();
    for &grid in &opts.sizes {
        let mut cfg = opts.config.clone();
        cfg.grid = grid;
        rows.extend(measure(
            &cfg,
            &opts.threads,
            &tiers,
            &modes,
            opts.iterations,
            opts.baselines,
        )?);
    }
    Ok(rows)
}

fn measure(
    cfg: &OceanConfig,
    threads: &[usize],
    tiers: &[Backend],
    modes: &[Derivatives],
    iterations: usize,
    baselines: bool,
) -> Result<Vec<BenchRow>, SimError> {
    let n = cfg.grid.n();
    let input = test_field(cfg.grid);
    let ffts: Vec<Fft2d> = tiers
        .iter()
        .map(|&b| Fft2d::with_backend(cfg.grid, b).expect("tiers are checked before measuring"))
        .collect();
    let mut rows = Vec::new();
    let pools = threads
        .iter()
        .map(|&t| pool(t))
        .collect::<Result<Vec<_>, _>>()?;
    // Stage 1 does not depend on the tier: measured once per thread count.
    let mut spectrum_ms = vec![None; threads.len()];
    let mut contenders: Vec<Contender<'_>> = Vec::new();
    // Per row: its step contender; per (tier, thread count): the FFT-only contender.
    let mut row_step = Vec::new();
    let mut row_fft = Vec::new();
    for (&tier, fft) in tiers.iter().zip(&ffts) {
        for (i, (&t, pool_t)) in threads.iter().zip(&pools).enumerate() {
            for (m, &mode) in modes.iter().enumerate() {
                let cfg = OceanConfig {
                    derivatives: mode,
                    ..cfg.clone()
                };
                let mut core = at_tier(tier, || pool_t.install(|| SimCore::new(cfg.clone())))?;
                debug_assert_eq!(core.fft().backend(), tier);
                let spectrum_ms = *spectrum_ms[i].get_or_insert_with(|| {
                    let mut d: Vec<Duration> = (0..3)
                        .map(|_| pool_t.install(|| core.regenerate_spectrum()))
                        .collect();
                    median_ms(&mut d)
                });
                rows.push(BenchRow {
                    n,
                    threads: t,
                    spectrum_ms,
                    backend: tier.to_string(),
                    derivatives: Some(mode),
                    ..BenchRow::default()
                });
                // The modes' step contenders, then the FFT-only one.
                row_step.push(contenders.len());
                row_fft.push(contenders.len() + modes.len() - m);
                let mut out = Surfaces::new(&cfg);
                let mut time = 0.0;
                contenders.push(Box::new(move || {
                    time += 1.0 / 72.0;
                    at_tier(tier, || pool_t.install(|| core.step(time, &mut out)));
                    let s = core.timings();
                    [
                        s.evolve,
                        s.fft,
                        s.surface,
                        s.evolve + s.fft + s.surface,
                        s.total(),
                    ]
                }));
            }
            let mut fields: Vec<SplitField> = (0..4).map(|_| input.clone()).collect();
            // As in the pipeline: one scratch field, the fields transformed one after another.
            let mut scratch = [SplitField::zeros(cfg.grid)];
            let input = &input;
            contenders.push(Box::new(move || {
                // Refill and time on the pool's thread, as FFTW refills and runs on its own:
                // the inputs then sit in the transforming core's cache for both.
                let d = pool_t.install(|| {
                    fields.iter_mut().for_each(|f| f.clone_from(input));
                    let start = Instant::now();
                    fft.inverse_batch(&mut fields, &mut scratch);
                    start.elapsed()
                });
                fft_only(d)
            }));
        }
    }
    let ours = contenders.len();
    #[cfg(feature = "baselines")]
    if baselines {
        let mut b = rustfft_2d::RustFft2d::new(n, 4);
        contenders.push(Box::new(move || {
            b.refill();
            let start = Instant::now();
            b.inverse_all();
            fft_only(start.elapsed())
        }));
    }
    #[cfg(feature = "fftw")]
    if baselines {
        contenders.extend(fftw_contenders(n, &input));
    }
    let _ = baselines;
    // Baselines run on the single-thread pool's worker, like our single-thread contenders, so
    // every contender is timed on the same thread and core.
    if let Some(single) = threads.iter().position(|&t| t == 1).map(|i| &pools[i]) {
        for c in &mut contenders[ours..] {
            let mut inner = std::mem::replace(c, Box::new(|| [Duration::ZERO; PARTS]));
            *c = Box::new(move || single.install(&mut inner));
        }
    }
    let medians = interleaved(&mut contenders, iterations);
    for ((row, &step), &fft) in rows.iter_mut().zip(&row_step).zip(&row_fft) {
        let [ev, ff, su, st, total] = medians[step];
        (row.evolve_ms, row.fft_ms, row.surface_ms) = (ev, ff, su);
        (row.step_ms, row.total_ms) = (st, total);
        row.ours_fft4_ms = medians[fft][FFT_PART];
    }
    let baseline_ms = medians[ours..].iter().map(|m| m[FFT_PART]);
    // rustfft's row comes first when it ran; FFTW's set-ups follow.
    #[cfg(feature = "baselines")]
    let (rustfft4_ms, baseline_ms) = {
        let mut rest = baseline_ms;
        (if baselines { rest.next() } else { None }, rest)
    };
    #[cfg(not(feature = "baselines"))]
    let rustfft4_ms = None;
    // FFTW's best set-up.
    let fftw4_ms = baseline_ms.reduce(f64::min);
    for row in rows.iter_mut().filter(|r| r.threads == 1 && baselines) {
        (row.rustfft4_ms, row.fftw4_ms) = (rustfft4_ms, fftw4_ms);
    }
    Ok(rows)
}

/// FFTW_PATIENT's four set-ups for four n×n inverse transforms (one `plan_many_dft` or four 2D
/// plans, in place or out of place); the report takes the fastest, so the baseline is FFTW at
/// its best here.
#[cfg(feature = "fftw")]
fn fftw_contenders<'a>(n: usize, input: &'a SplitField) -> Vec<Contender<'a>> {
    use fftw::{Layout, Plan, FFTW_PATIENT};
    let setups = [
        (Layout::Many, true),
        (Layout::Many, false),
        (Layout::Single, true),
        (Layout::Single, false),
    ];
    let mut out: Vec<Contender<'a>> = Vec::new();
    for (layout, in_place) in setups {
        let Some(mut plan) = Plan::new(n, 4, layout, in_place, FFTW_PATIENT) else {
            continue;
        };
        out.push(Box::new(move || {
            for (i, d) in plan.input_mut().iter_mut().enumerate() {
                let j = i % (n * n);
                *d = [input.re[j], input.im[j]];
            }
            let start = Instant::now();
            plan.execute();
            fft_only(start.elapsed())
        }));
    }
    out
}

/// A field of bounded pseudo-random values (transforms of it stay finite).
fn test_field(grid: GridSize) -> SplitField {
    let mut f = SplitField::zeros(grid);
    let mut x = 0x2545_f491_4f6c_dd1du64;
    let (re, im) = f.planes_mut();
    for v in re.iter_mut().chain(im.iter_mut()) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        *v = (x >> 40) as f32 / (1u64 << 24) as f32 - 0.5;
    }
    f
}

/// The table `vr-ocean bench` prints, with the ratios the project's performance goals use:
/// "step" is stages 2-6 (evolve + FFT + surface), "total" all `SimCore::step` times.
pub fn format_table(rows: &[BenchRow]) -> String {
    let mut s = String::new();
    s.push_str(
        "   N thr backend  deriv    | stage1   evolve      fft  surface     step    total | ours4  rustfft4    fftw4 | fft4/fftw step/fftw4\n",
    );
    let opt = |v: Option<f64>| v.map_or("       -".to_string(), |v| format!("{v:8.3}"));
    for r in rows {
        let ratio = |a: f64| {
            r.fftw4_ms
                .map_or("     -".to_string(), |f| format!("{:6.2}", a / f))
        };
        s.push_str(&format!(
            "{:4} {:3} {:8} {:8} | {:6.2} {:8.3} {:8.3} {:8.3} {:8.3} {:8.3} | {:6.3} {} {} | {}    {}\n",
            r.n,
            r.threads,
            r.backend,
            r.derivatives.map_or("-".to_string(), |d| d.to_string()),
            r.spectrum_ms,
            r.evolve_ms,
            r.fft_ms,
            r.surface_ms,
            r.step_ms,
            r.total_ms,
            r.ours_fft4_ms,
            opt(r.rustfft4_ms),
            opt(r.fftw4_ms),
            ratio(r.ours_fft4_ms),
            ratio(r.step_ms),
        ));
    }
    // Thread scaling: step time at 1 thread over step time at each other count, per tier.
    for r in rows.iter().filter(|r| r.threads > 1) {
        let one = rows.iter().find(|o| {
            o.n == r.n && o.backend == r.backend && o.derivatives == r.derivatives && o.threads == 1
        });
        if let Some(one) = one {
            s.push_str(&format!(
                "N={} {} {} speed-up {} threads vs 1: step {:.2}x, fft {:.2}x\n",
                r.n,
                r.backend,
                r.derivatives.map_or("-".to_string(), |d| d.to_string()),
                r.threads,
                one.step_ms / r.step_ms,
                one.ours_fft4_ms / r.ours_fft4_ms
            ));
        }
    }
    s.push_str(
        "times are medians in ms; stage1 runs on demand, the rest every step; step = evolve + fft + \
         surface (stages 2-6), total = everything SimCore::step times; each tier runs the FFT on \
         that backend and the element-wise kernels at the matching width (the x86-64 baseline, \
         SSE2, for sse2 and scalar)\n",
    );
    s
}
