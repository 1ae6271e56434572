//! Criterion benchmarks of the simulation pipeline: each stage and the whole step for
//! N = 128, 256, 512 on 1 and 2 threads (one cascade = four inverse 2D FFTs per step; the
//! `_finite` stages and step are the central-difference mode's: h + i·X and Z, the latter as
//! row pairs, about 1.7 FFTs' work).
//! `default_scene` is the headset's: the default three cascades at N = 256 in the central-
//! difference mode, whitecap maps included, and the whitecap update alone.
//! `cargo bench --bench sim`; FFT-only comparisons with rustfft and FFTW are in `benches/fft.rs`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

use vr_ocean::sim::evolve::{self, LoopPhase, OutsideSupport};
use vr_ocean::sim::fft::{Fft2d, Output};
use vr_ocean::sim::spectrum::PackedSpectrum;
use vr_ocean::sim::surface::{self, CascadeSurface, FloatCopies, SurfaceParams, Transformed};
use vr_ocean::sim::whitecaps::{WhitecapInput, WhitecapState};
use vr_ocean::sim::{AlignedBuf, Derivatives, OceanConfig, SimCore, SplitField, Support, Surfaces};

fn stages(c: &mut Criterion) {
    for n in [128u32, 256, 512] {
        for threads in [1usize, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let cfg = OceanConfig::single(n, 250.0).unwrap();
            let grid = cfg.grid;
            let spec = cfg.cascade_specs()[0];
            let spectrum = pool.install(|| PackedSpectrum::generate(&cfg.waves, &spec));
            let fft = Fft2d::new(grid);
            let mut fields: [SplitField; 4] = std::array::from_fn(|_| SplitField::zeros(grid));
            let mut scratch: [SplitField; 4] = std::array::from_fn(|_| SplitField::zeros(grid));
            let mut out = CascadeSurface::new(grid, 250.0, FloatCopies::Skip);
            let mut foam = AlignedBuf::zeros(grid.texels());
            let params = SurfaceParams {
                choppiness: cfg.waves.choppiness,
                roughness: cfg.waves.roughness,
                foam: cfg.waves.foam,
                dt: 1.0 / 72.0,
            };
            let id = |what: &str| BenchmarkId::new(what, format!("N{n}/t{threads}"));
            let mut g = c.benchmark_group("sim");
            g.bench_function(id("stage1_spectrum"), |b| {
                b.iter(|| pool.install(|| PackedSpectrum::generate(&cfg.waves, &spec)))
            });
            g.bench_function(id("stage2_evolve"), |b| {
                b.iter(|| {
                    pool.install(|| {
                        let at = LoopPhase::new(3.0, 200.0);
                        evolve::evolve(&spectrum, 250.0, at, &mut fields, OutsideSupport::Zeroed)
                    })
                })
            });
            g.bench_function(id("stage3_4_fft4"), |b| {
                b.iter(|| pool.install(|| fft.inverse_batch(&mut fields, &mut scratch)))
            });
            g.bench_function(id("stage5_6_surface"), |b| {
                b.iter(|| {
                    pool.install(|| {
                        surface::finalize(
                            Transformed::Spectral(&fields),
                            &mut foam,
                            params,
                            3.0,
                            &mut out,
                        )
                    })
                })
            });
            let mut finite: [SplitField; 2] = std::array::from_fn(|_| SplitField::zeros(grid));
            g.bench_function(id("stage2_evolve_finite"), |b| {
                b.iter(|| {
                    pool.install(|| {
                        evolve::evolve_finite(
                            &spectrum,
                            250.0,
                            LoopPhase::new(3.0, 200.0),
                            &mut finite,
                            OutsideSupport::Zeroed,
                        )
                    })
                })
            });
            g.bench_function(id("stage3_4_fft2"), |b| {
                // As the step: h + i·X whole, Z as row pairs.
                let outputs = [Output::Complex, Output::RealRowPairs];
                let whole = Support::full(grid);
                b.iter(|| {
                    pool.install(|| {
                        let scratch = &mut scratch[..2];
                        fft.inverse_batch_support_as(&mut finite, &outputs, scratch, &whole)
                    })
                })
            });
            g.bench_function(id("stage5_6_surface_finite"), |b| {
                b.iter(|| {
                    pool.install(|| {
                        surface::finalize(
                            Transformed::Finite(&finite),
                            &mut foam,
                            params,
                            3.0,
                            &mut out,
                        )
                    })
                })
            });
            for (name, derivatives) in [
                ("step", Derivatives::Spectral),
                ("step_finite", Derivatives::Finite),
            ] {
                let cfg = OceanConfig {
                    derivatives,
                    ..cfg.clone()
                };
                let mut core = pool.install(|| SimCore::new(cfg.clone()).unwrap());
                let mut surfaces = Surfaces::new(&cfg);
                let mut t = 0.0;
                g.bench_function(id(name), |b| {
                    b.iter(|| {
                        t += 1.0 / 72.0;
                        pool.install(|| core.step(t, &mut surfaces))
                    })
                });
            }
            g.finish();
        }
    }
}

/// The headset's scene: [`OceanConfig::default_cascades`] at N = 256 with central differences
/// (the Android default), the whole step with its whitecap maps, and the maps' update alone.
fn default_scene(c: &mut Criterion) {
    let cfg = OceanConfig {
        derivatives: Derivatives::Finite,
        ..OceanConfig::default_cascades(256).unwrap()
    };
    for threads in [1usize, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let id = |what: &str| BenchmarkId::new(what, format!("N256x3/t{threads}"));
        let mut g = c.benchmark_group("default_scene");
        let mut core = pool.install(|| SimCore::new(cfg.clone()).unwrap());
        let mut surfaces = Surfaces::new(&cfg);
        let mut t = 0.0;
        g.bench_function(id("step"), |b| {
            b.iter(|| {
                t += 1.0 / 72.0;
                pool.install(|| core.step(t, &mut surfaces))
            })
        });
        let mut state = WhitecapState::new(cfg.grid);
        let mut caps = surfaces.whitecaps.clone();
        g.bench_function(id("whitecaps"), |b| {
            b.iter(|| {
                let input = WhitecapInput {
                    cascades: &surfaces.cascades,
                    focus: [12.0, -30.0],
                    foam: cfg.waves.foam,
                    wind_speed: cfg.waves.wind_speed,
                    drift: [0.3, 0.1],
                    dt: 1.0 / 72.0,
                };
                pool.install(|| state.update(input, &mut caps))
            })
        });
        g.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = stages, default_scene
}
criterion_main!(benches);
