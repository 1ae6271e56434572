//! The same numbers whichever way they are computed: any thread count, any SIMD tier, the
//! sparse path that skips a spectrum's zeros, with or without the f32 copies.

use vr_ocean::sim::evolve::{self, LoopPhase, OutsideSupport};
use vr_ocean::sim::fft::{Fft2d, Output};
use vr_ocean::sim::spectrum::PackedSpectrum;
use vr_ocean::sim::surface::CascadeSurface;
use vr_ocean::sim::{GridSize, OceanConfig, SimCore, SplitField, Surfaces};

use crate::helpers::{spec_of, step};

#[test]
fn results_are_identical_for_any_thread_count() {
    let cfg = OceanConfig::default_cascades(128).unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut core = SimCore::new(cfg.clone()).unwrap();
            let mut out = Surfaces::with_float_copies(&cfg);
            for i in 0..3 {
                core.step(1.0 + i as f64 / 72.0, &mut out);
            }
            out
        })
    };
    let a = run(1);
    for threads in [2, 4] {
        let b = run(threads);
        for (x, y) in a.cascades.iter().zip(&b.cascades) {
            let bits = |s: &CascadeSurface| -> Vec<u32> {
                s.displacement
                    .iter()
                    .flatten()
                    .map(|v| v.to_bits())
                    .collect()
            };
            assert_eq!(bits(x), bits(y), "{threads} threads");
            assert_eq!(x.normal_foam, y.normal_foam, "{threads} threads");
        }
    }
}

#[test]
fn every_simd_tier_computes_the_same_bits() {
    use vr_ocean::sim::simd::{active_tier, cap_tier, Tier};
    let cfg = OceanConfig::default_cascades(64).unwrap();
    let run = |tier: Tier| {
        cap_tier(tier);
        let mut core = SimCore::new(cfg.clone()).unwrap();
        let out = step(&mut core, &cfg, 7.25);
        let used = active_tier();
        cap_tier(Tier::Avx512);
        let bits: Vec<u32> = out
            .cascades
            .iter()
            .flat_map(|c| c.displacement.iter().flatten().map(|v| v.to_bits()))
            .collect();
        let rgba: Vec<u32> = out
            .cascades
            .iter()
            .flat_map(|c| c.normal_foam.clone())
            .collect();
        (used, bits, rgba)
    };
    let (base_tier, base, base_rgba) = run(Tier::Baseline);
    assert_eq!(base_tier, Tier::Baseline);
    for tier in [Tier::Avx2, Tier::Avx512] {
        let (used, bits, rgba) = run(tier);
        assert!(
            bits == base && rgba == base_rgba,
            "{used:?} differs from the baseline"
        );
    }
}

#[test]
fn keeping_float_copies_changes_nothing_else() {
    let cfg = OceanConfig::default_cascades(64).unwrap();
    let mut a = Surfaces::new(&cfg);
    let mut b = Surfaces::with_float_copies(&cfg);
    let mut core_a = SimCore::new(cfg.clone()).unwrap();
    let mut core_b = SimCore::new(cfg.clone()).unwrap();
    core_a.step(3.0, &mut a);
    core_b.step(3.0, &mut b);
    for (x, y) in a.cascades.iter().zip(&b.cascades) {
        assert!(x.base_normals().is_none());
        let base = y.base_normals().unwrap();
        assert_eq!(x.normal_foam, y.normal_foam);
        for level in 1..x.grid.mip_levels() {
            assert_eq!(x.mip_floats(level), y.mip_floats(level));
        }
        // Level 1 is the unnormalized average of level 0 (eq. 52).
        let n = x.grid.n();
        let l1 = y.mip_floats(1);
        for i in (0..l1[0].len()).step_by(7) {
            let (r, c) = (i / (n / 2), i % (n / 2));
            let at = |rr: usize, cc: usize| base[(2 * r + rr) * n + 2 * c + cc];
            for (k, plane) in l1.iter().enumerate() {
                let avg = 0.25 * (at(0, 0)[k] + at(0, 1)[k] + at(1, 0)[k] + at(1, 1)[k]);
                assert!((avg - plane[i]).abs() < 1e-6);
            }
        }
    }
}

/// Fields of `grid` filled with NaN: whatever the step does not write must not reach a result.
fn nan_fields<const F: usize>(grid: GridSize) -> [SplitField; F] {
    std::array::from_fn(|_| {
        let mut f = SplitField::zeros(grid);
        f.re.fill(f32::NAN);
        f.im.fill(f32::NAN);
        f
    })
}

/// Whether two sets of fields are equal as numbers (zeros may differ in sign: a skipped strip's
/// zeros are written, a transformed one's computed).
fn same_values(a: &[SplitField], b: &[SplitField]) -> bool {
    a.iter().zip(b).all(|(a, b)| {
        a.re.iter().zip(b.re.iter()).all(|(x, y)| x == y)
            && a.im.iter().zip(b.im.iter()).all(|(x, y)| x == y)
    })
}

/// The default sea's two coarse spectra are zero outside a small square (their bands end far
/// below their Nyquist): the step evolves only its rows, and the FFT reads only those rows and
/// its columns; the fields are the same as the whole-grid path's, in both derivative modes.
/// Whatever the sparse path leaves unwritten holds NaN, so a read of it would show.
#[test]
fn sparse_spectra_skip_their_zeros_and_change_nothing() {
    let cfg = OceanConfig::default_cascades(256).unwrap();
    let (grid, n) = (cfg.grid, cfg.grid.n());
    let fft = Fft2d::new(grid);
    let at = LoopPhase::new(4.5, cfg.waves.loop_period);
    for i in 0..cfg.patch_sizes.len() {
        let spec = PackedSpectrum::generate(&cfg.waves, &spec_of(&cfg, i));
        let patch = cfg.patch_sizes[i];
        let support = spec.support.clone();
        if i < 2 {
            assert!(
                support.rows.len() <= n / 4 && support.cols.len() <= n / 4,
                "cascade {i}: support {support:?} is not the small square the skipping is for"
            );
        }
        let mut scratch = [SplitField::zeros(grid)];

        let mut want: [SplitField; 4] = std::array::from_fn(|_| SplitField::zeros(grid));
        evolve::evolve(&spec, patch, at, &mut want, OutsideSupport::Zeroed);
        for (r, c) in (0..n * n).map(|t| (t / n, t % n)) {
            if !(support.rows.contains(&r) && support.cols.contains(&c)) {
                let zero = want
                    .iter()
                    .all(|f| f.re[r * n + c] == 0.0 && f.im[r * n + c] == 0.0);
                assert!(
                    zero,
                    "cascade {i}: texel ({r}, {c}) outside {support:?} is not zero"
                );
            }
        }
        fft.inverse_batch(&mut want, &mut scratch);
        let mut got = nan_fields::<4>(grid);
        evolve::evolve(&spec, patch, at, &mut got, OutsideSupport::Unwritten);
        fft.inverse_batch_support(&mut got, &mut nan_fields::<1>(grid), &support);
        assert!(
            same_values(&got, &want),
            "cascade {i}, spectral: the fields differ"
        );

        // The finite mode's Z comes as row pairs: rows N/2.. are not part of the result.
        let outputs = [Output::Complex, Output::RealRowPairs];
        let mut want: [SplitField; 2] = std::array::from_fn(|_| SplitField::zeros(grid));
        evolve::evolve_finite(&spec, patch, at, &mut want, OutsideSupport::Zeroed);
        let whole = vr_ocean::sim::Support::full(grid);
        fft.inverse_batch_support_as(&mut want, &outputs, &mut scratch, &whole);
        let mut got = nan_fields::<2>(grid);
        evolve::evolve_finite(&spec, patch, at, &mut got, OutsideSupport::Unwritten);
        fft.inverse_batch_support_as(&mut got, &outputs, &mut nan_fields::<1>(grid), &support);
        let half = grid.texels() / 2;
        let same_half =
            |a: &[f32], b: &[f32]| a[..half].iter().zip(&b[..half]).all(|(x, y)| x == y);
        assert!(
            same_values(&got[..1], &want[..1])
                && same_half(&got[1].re, &want[1].re)
                && same_half(&got[1].im, &want[1].im),
            "cascade {i}, finite: the fields differ"
        );
    }
}
