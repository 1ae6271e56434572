//! `vr-ocean bench`: per-stage simulation times next to FFT baselines measured in the same run.
//! Shared machines are noisy, so results are medians and the verdicts are ratios.

#[cfg(feature = "fftw")]
pub mod fftw;
#[cfg(feature = "baselines")]
mod rustfft_2d;

use std::time::{Duration, Instant};

use crate::sim::fft::Fft2d;
use crate::sim::grid::{GridSize, SplitField};
use crate::sim::params::OceanConfig;
use crate::sim::pipeline::{SimCore, SimError, Surfaces};

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// Grid sides to run.
    pub sizes: Vec<GridSize>,
    /// Thread counts to run each size with.
    pub threads: Vec<usize>,
    /// Timed repetitions per measurement (after warm-up).
    pub iterations: usize,
    /// Wave parameters and cascades (the grid is replaced by each size).
    pub config: OceanConfig,
}

/// Median times (ms) for one grid size and thread count.
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
    /// The whole step.
    pub step_ms: f64,
    /// Our batch of four inverse 2D FFTs alone.
    pub ours_fft4_ms: f64,
    /// rustfft, four 2D inverse transforms rows then columns (single thread rows only).
    pub rustfft4_ms: Option<f64>,
    /// FFTW FFTW_PATIENT, four 2D inverse transforms (single thread rows only).
    pub fftw4_ms: Option<f64>,
    /// The FFT backend that ran.
    pub backend: String,
}

fn median_ms(samples: &mut [Duration]) -> f64 {
    samples.sort();
    samples[samples.len() / 2].as_secs_f64() * 1e3
}

/// Median of `iterations` timed runs of `run`, each after an untimed `setup` (which refills the
/// inputs, so repeated in-place transforms never overflow).
fn time_n<S>(
    iterations: usize,
    state: &mut S,
    mut setup: impl FnMut(&mut S),
    mut run: impl FnMut(&mut S),
) -> f64 {
    let mut samples: Vec<Duration> = (0..iterations + 3)
        .map(|_| {
            setup(state);
            let t = Instant::now();
            run(state);
            t.elapsed()
        })
        .skip(3)
        .collect();
    median_ms(&mut samples)
}

/// Runs every size × thread count. Baselines run in the single-thread rows.
pub fn run(opts: &BenchOptions) -> Result<Vec<BenchRow>, SimError> {
    let mut rows = Vec::new();
    for &grid in &opts.sizes {
        for &threads in &opts.threads {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| SimError::Threads(e.to_string()))?;
            let mut cfg = opts.config.clone();
            cfg.grid = grid;
            let row = pool.install(|| measure(&cfg, threads, opts.iterations))?;
            rows.push(row);
        }
    }
    Ok(rows)
}

fn measure(cfg: &OceanConfig, threads: usize, iterations: usize) -> Result<BenchRow, SimError> {
    let mut core = SimCore::new(cfg.clone())?;
    let mut out = Surfaces::new(cfg);
    let n = cfg.grid.n();
    let mut row = BenchRow {
        n,
        threads,
        backend: core.fft().backend().to_string(),
        ..BenchRow::default()
    };
    let mut spectrum: Vec<Duration> = (0..iterations.clamp(1, 5))
        .map(|_| core.regenerate_spectrum())
        .collect();
    row.spectrum_ms = median_ms(&mut spectrum);
    let (mut ev, mut ff, mut su, mut st) = (vec![], vec![], vec![], vec![]);
    let mut t = 0.0;
    for i in 0..iterations + 3 {
        t += 1.0 / 72.0;
        core.step(t, &mut out);
        let s = core.timings();
        if i >= 3 {
            ev.push(s.evolve);
            ff.push(s.fft);
            su.push(s.surface);
            st.push(s.total());
        }
    }
    row.evolve_ms = median_ms(&mut ev);
    row.fft_ms = median_ms(&mut ff);
    row.surface_ms = median_ms(&mut su);
    row.step_ms = median_ms(&mut st);

    let fft = Fft2d::new(cfg.grid);
    let input = test_field(cfg.grid);
    let fields: Vec<SplitField> = (0..4).map(|_| input.clone()).collect();
    let scratch: Vec<SplitField> = (0..4).map(|_| SplitField::zeros(cfg.grid)).collect();
    row.ours_fft4_ms = time_n(
        iterations,
        &mut (fields, scratch),
        |(f, _)| f.iter_mut().for_each(|f| f.clone_from(&input)),
        |(f, s)| fft.inverse_batch(f, s),
    );
    if threads == 1 {
        #[cfg(feature = "baselines")]
        {
            let mut b = rustfft_2d::RustFft2d::new(n, 4);
            row.rustfft4_ms = Some(time_n(
                iterations,
                &mut b,
                |b| b.refill(),
                |b| b.inverse_all(),
            ));
        }
        #[cfg(feature = "fftw")]
        {
            row.fftw4_ms = fftw_best_ms(n, &input, iterations);
        }
    }
    Ok(row)
}

/// FFTW_PATIENT's best time (ms) for four n×n inverse transforms over its four set-ups (one
/// `plan_many_dft` or four 2D plans, in place or out of place), so the baseline is FFTW at its
/// fastest here.
#[cfg(feature = "fftw")]
fn fftw_best_ms(n: usize, input: &SplitField, iterations: usize) -> Option<f64> {
    use fftw::{Layout, Plan, FFTW_PATIENT};
    let setups = [
        (Layout::Many, true),
        (Layout::Many, false),
        (Layout::Single, true),
        (Layout::Single, false),
    ];
    let mut best: Option<f64> = None;
    for (layout, in_place) in setups {
        let Some(mut plan) = Plan::new(n, 4, layout, in_place, FFTW_PATIENT) else {
            continue;
        };
        let fill = |plan: &mut Plan| {
            for (i, d) in plan.input_mut().iter_mut().enumerate() {
                let j = i % (n * n);
                *d = [input.re[j], input.im[j]];
            }
        };
        let ms = time_n(iterations, &mut plan, fill, |p| p.execute());
        best = Some(best.map_or(ms, |b: f64| b.min(ms)));
    }
    best
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

/// The table `vr-ocean bench` prints, with the ratios the project's performance goals use.
pub fn format_table(rows: &[BenchRow]) -> String {
    let mut s = String::new();
    s.push_str(
        "   N thr backend  | stage1   evolve      fft  surface     step | ours4  rustfft4    fftw4 | fft4/fftw step/fftw4\n",
    );
    let opt = |v: Option<f64>| v.map_or("       -".to_string(), |v| format!("{v:8.3}"));
    for r in rows {
        let ratio = |a: f64| {
            r.fftw4_ms
                .map_or("     -".to_string(), |f| format!("{:6.2}", a / f))
        };
        s.push_str(&format!(
            "{:4} {:3} {:8} | {:6.2} {:8.3} {:8.3} {:8.3} {:8.3} | {:6.3} {} {} | {}    {}\n",
            r.n,
            r.threads,
            r.backend,
            r.spectrum_ms,
            r.evolve_ms,
            r.fft_ms,
            r.surface_ms,
            r.step_ms,
            r.ours_fft4_ms,
            opt(r.rustfft4_ms),
            opt(r.fftw4_ms),
            ratio(r.ours_fft4_ms),
            ratio(r.step_ms),
        ));
    }
    // Thread scaling: step time at 1 thread over step time at each other count.
    for r in rows.iter().filter(|r| r.threads > 1) {
        if let Some(one) = rows.iter().find(|o| o.n == r.n && o.threads == 1) {
            s.push_str(&format!(
                "N={} speed-up {} threads vs 1: step {:.2}x, fft {:.2}x\n",
                r.n,
                r.threads,
                one.step_ms / r.step_ms,
                one.ours_fft4_ms / r.ours_fft4_ms
            ));
        }
    }
    s.push_str("times are medians in ms; stage1 runs on demand, the rest every step\n");
    s
}
