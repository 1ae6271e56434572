//! Inverse 2D FFT throughput: a batch of four N×N complex f32 inverse transforms, single thread,
//! for N = 128, 256, 512.
//!
//! - `ours/<backend>`: `Fft2d::inverse_batch` on a one-thread rayon pool, every available backend.
//! - `rustfft`: rows, transpose, rows, transpose back, on interleaved `Complex<f32>`.
//! - `fftw_patient/*` (feature `fftw`): system libfftw3f planned with FFTW_PATIENT outside the
//!   timing: `many4_*` is one `fftwf_plan_many_dft` with howmany = 4, `single_*` one 2D plan per
//!   array executed in turn; `inplace`/`outofplace` as named.
//!
//! Every timed iteration starts from the same input (re-copied untimed, so data is cache-warm
//! as it is in the ocean after the spectrum step); only the transforms are timed.
//!
//! Run: `cargo bench --features fftw --bench fft -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use rustfft::num_complex::Complex;
use vr_ocean::sim::fft::{Backend, Fft2d};
use vr_ocean::sim::{GridSize, SplitField};

/// Transforms per batch, as in the ocean (four displacement/slope fields per cascade).
const BATCH: usize = 4;

/// Deterministic pseudo-random values in [-1, 1).
fn values(len: usize, seed: u64) -> Vec<f32> {
    let mut s = seed;
    (0..len)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        })
        .collect()
}

/// Times `iters` runs of `run` on `state`, calling `reset` on it untimed before each.
fn timed<T>(
    iters: u64,
    state: &mut T,
    mut reset: impl FnMut(&mut T),
    mut run: impl FnMut(&mut T),
) -> Duration {
    let mut total = Duration::ZERO;
    for _ in 0..iters {
        reset(state);
        let t = Instant::now();
        run(black_box(&mut *state));
        total += t.elapsed();
    }
    total
}

fn bench_size(c: &mut Criterion, n: usize) {
    let size = GridSize::new(n as u32).unwrap();
    let texels = n * n;
    let re = values(texels * BATCH, 1);
    let im = values(texels * BATCH, 2);
    let mut group = c.benchmark_group(format!("inverse2d_x4/{n}"));

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for backend in Backend::available() {
        let fft = Fft2d::with_backend(size, backend).unwrap();
        let mut fields: Vec<SplitField> = (0..BATCH).map(|_| SplitField::zeros(size)).collect();
        let mut scratch: Vec<SplitField> = (0..BATCH).map(|_| SplitField::zeros(size)).collect();
        group.bench_function(format!("ours/{backend}"), |b| {
            b.iter_custom(|iters| {
                pool.install(|| {
                    timed(
                        iters,
                        &mut (&mut fields, &mut scratch),
                        |(fields, _)| {
                            for (i, f) in fields.iter_mut().enumerate() {
                                f.re.copy_from_slice(&re[i * texels..(i + 1) * texels]);
                                f.im.copy_from_slice(&im[i * texels..(i + 1) * texels]);
                            }
                        },
                        |(fields, scratch)| fft.inverse_batch(fields, scratch),
                    )
                })
            })
        });
    }

    {
        let fft = rustfft::FftPlanner::<f32>::new().plan_fft_inverse(n);
        let input: Vec<Complex<f32>> = re
            .iter()
            .zip(&im)
            .map(|(&r, &i)| Complex::new(r, i))
            .collect();
        let mut data = input.clone();
        let mut tmp = vec![Complex::default(); texels * BATCH];
        let mut fft_scratch = vec![Complex::default(); fft.get_inplace_scratch_len()];
        group.bench_function("rustfft", |b| {
            b.iter_custom(|iters| {
                timed(
                    iters,
                    &mut data,
                    |data| data.copy_from_slice(&input),
                    |data| {
                        fft.process_with_scratch(data, &mut fft_scratch);
                        for (d, t) in data.chunks_exact(texels).zip(tmp.chunks_exact_mut(texels)) {
                            transpose(d, t, n);
                        }
                        fft.process_with_scratch(&mut tmp, &mut fft_scratch);
                        for (t, d) in tmp.chunks_exact(texels).zip(data.chunks_exact_mut(texels)) {
                            transpose(t, d, n);
                        }
                    },
                )
            })
        });
    }

    #[cfg(feature = "fftw")]
    {
        use vr_ocean::bench::fftw::{Layout, Plan, FFTW_PATIENT};
        for (name, layout, in_place) in [
            ("many4_inplace", Layout::Many, true),
            ("many4_outofplace", Layout::Many, false),
            ("single_inplace", Layout::Single, true),
            ("single_outofplace", Layout::Single, false),
        ] {
            let Some(mut plan) = Plan::new(n, BATCH, layout, in_place, FFTW_PATIENT) else {
                eprintln!("FFTW could not plan {name} for N={n}; skipped");
                continue;
            };
            group.bench_function(format!("fftw_patient/{name}"), |b| {
                b.iter_custom(|iters| {
                    let mut total = Duration::ZERO;
                    for _ in 0..iters {
                        for ((d, &r), &i) in plan.input_mut().iter_mut().zip(&re).zip(&im) {
                            *d = [r, i];
                        }
                        let t = Instant::now();
                        plan.execute();
                        total += t.elapsed();
                    }
                    black_box(plan.output());
                    total
                })
            });
        }
    }
    group.finish();
}

/// Cache-blocked out-of-place transpose of an n×n matrix.
fn transpose(src: &[Complex<f32>], dst: &mut [Complex<f32>], n: usize) {
    const B: usize = 16;
    for rb in (0..n).step_by(B) {
        for cb in (0..n).step_by(B) {
            for r in rb..rb + B {
                for c in cb..cb + B {
                    dst[c * n + r] = src[r * n + c];
                }
            }
        }
    }
}

fn benches(c: &mut Criterion) {
    for n in [128, 256, 512] {
        bench_size(c, n);
    }
}

criterion_group!(fft_benches, benches);
criterion_main!(fft_benches);
