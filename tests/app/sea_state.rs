//! The sea a wind makes (issue 14, item 5): significant height of the default configuration
//! against the fetch-limited and fully developed growth laws, and the coarsest cascade growing
//! so the peak wavelength fits in it. Run with `--nocapture` for the table in BENCHMARKS.md.

use vr_ocean::sim::spectrum::jonswap;
use vr_ocean::sim::{OceanConfig, SeaState, SimCore, Surfaces, DEFAULT_FETCH_KM};

/// The default sea (three cascades of 256², JONSWAP, default fetch) at `wind` m/s.
fn default_sea(wind: f32, seed: u64) -> OceanConfig {
    let mut cfg = OceanConfig::default_cascades(256).unwrap();
    cfg.waves.wind_speed = wind;
    cfg.waves.seed = seed;
    cfg.fit_patches();
    cfg.validate().unwrap();
    cfg
}

/// Height variance (m²) of the summed cascades, averaged over `times`: the cascades are
/// independent, so the variances add.
fn measured_variance(cfg: &OceanConfig, times: &[f64]) -> f64 {
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let mut out = Surfaces::with_float_copies(cfg);
    let mut total = 0.0;
    for &t in times {
        core.step(t, &mut out);
        for c in &out.cascades {
            let n = c.displacement.len() as f64;
            let mean = c.displacement.iter().map(|d| d[1] as f64).sum::<f64>() / n;
            total += c
                .displacement
                .iter()
                .map(|d| (d[1] as f64 - mean).powi(2))
                .sum::<f64>()
                / n;
        }
    }
    total / times.len() as f64
}

#[test]
fn significant_height_follows_the_growth_law() {
    let fetch_m = DEFAULT_FETCH_KM as f64 * 1000.0;
    println!("wind  law Hs  expected Hs  measured Hs  ratio  coarsest patch  peak wavelength");
    let mut rows = Vec::new();
    for wind in [5.0f32, 10.0, 15.0, 20.0] {
        let law = jonswap::significant_height(wind, fetch_m);
        // Four seeds, five instants each: the coarsest cascade holds a few dozen energetic
        // modes, so one draw's Hs scatters by ~10 %.
        let seeds = [1u64, 2, 3, 4];
        let mut expected = 0.0;
        let mut measured = 0.0;
        let mut patch = 0.0;
        let mut peak = 0.0;
        for &seed in &seeds {
            let cfg = default_sea(wind, seed);
            let core = SimCore::new(cfg.clone()).unwrap();
            expected += core.expected_variances().sum::<f64>();
            measured += measured_variance(&cfg, &[0.0, 11.0, 23.5, 37.0, 61.0]);
            patch = cfg.patch_sizes[0];
            peak = cfg.waves.peak_wavelength();
        }
        let n = seeds.len() as f64;
        let (hs_expected, hs_measured) = (4.0 * (expected / n).sqrt(), 4.0 * (measured / n).sqrt());
        let ratio = hs_measured / law;
        println!(
            "{wind:>4}  {law:>6.2}  {hs_expected:>11.2}  {hs_measured:>11.2}  {ratio:>5.2}  \
             {patch:>12.1} m  {peak:>13.1} m"
        );
        rows.push((wind, law, hs_expected, hs_measured, patch, peak));
    }
    for (wind, law, expected, measured, patch, peak) in rows {
        // The gate: within 25 % of the law for the default fetch.
        assert!(
            (measured / law - 1.0).abs() <= 0.25,
            "{wind} m/s: Hs {measured:.2} m vs the law's {law:.2} m"
        );
        // The grid's discretized spectrum itself is close to the law.
        assert!(
            (expected / law - 1.0).abs() <= 0.15,
            "{wind} m/s: expected Hs {expected:.2} m vs {law:.2} m"
        );
        // The peak wavelength fits in the coarsest patch at least twice.
        assert!(
            patch as f64 >= 2.0 * peak,
            "{wind} m/s: patch {patch} m, peak wavelength {peak:.0} m"
        );
    }
}

#[test]
fn the_coarsest_patch_follows_a_live_wind_change() {
    let cfg = default_sea(8.0, 1);
    assert_eq!(
        cfg.patch_sizes[0], 257.0,
        "a breeze keeps the default tiling"
    );
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let mut waves = cfg.waves;
    waves.wind_speed = 20.0;
    // At once: the smooth change (built over steps, then blended) is tests/app/sea_state_blend.rs's.
    core.set_waves_at_once(SeaState::new(waves).unwrap())
        .unwrap();
    let grown = core.config().patch_sizes[0];
    assert!(grown > 400.0, "20 m/s: coarsest patch {grown} m");
    // The next step's surfaces carry the new patch (the renderer reads it from there).
    let mut out = Surfaces::new(&cfg);
    core.step(1.0, &mut out);
    assert_eq!(out.cascades[0].patch, grown);
    // And the height of the gale is that of the gale, not of the breeze's patch.
    let law = jonswap::significant_height(20.0, DEFAULT_FETCH_KM as f64 * 1000.0);
    let hs = 4.0 * core.expected_variances().sum::<f64>().sqrt();
    assert!((hs / law - 1.0).abs() < 0.15, "Hs {hs:.2} vs {law:.2}");
}

/// Monahan & O'Muircheartaigh (1980): whitecap fraction W = 3.84e-6·U^3.41.
fn monahan(wind: f32) -> f64 {
    3.84e-6 * (wind as f64).powf(3.41)
}

/// Mean whitecap coverage of the fine level (±64 m around the origin) and of the coarse one
/// (±256 m) of the default sea at `wind`, averaged over the last `average` seconds of
/// `duration` seconds stepped at `rate` Hz. The mean coverage is the area the renderer draws
/// white: it whitens a share c of a texel of coverage c (`render::ocean::foam_pattern`,
/// measured in pixels by `tests/render/foam.rs`). The mean of seas `seeds`: one sea's ±64 m
/// breaks where its few largest crests happen to meet (at 12 m/s, four seeds measured 0.96 to
/// 3.91 % after a minute).
fn whitecap_coverage(
    wind: f32,
    duration: f64,
    average: f64,
    rate: f64,
    seeds: &[u64],
) -> (f64, f64) {
    let (mut fine, mut coarse) = (0.0, 0.0);
    for &seed in seeds {
        let (f, c) = one_sea_coverage(wind, seed, duration, average, rate);
        fine += f / seeds.len() as f64;
        coarse += c / seeds.len() as f64;
    }
    (fine, coarse)
}

/// [`whitecap_coverage`] of the sea of `seed`.
fn one_sea_coverage(wind: f32, seed: u64, duration: f64, average: f64, rate: f64) -> (f64, f64) {
    let cfg = default_sea(wind, seed);
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let mut out = Surfaces::new(&cfg);
    let steps = (duration * rate) as usize;
    let (mut mean, mut coarse, mut count) = (0.0, 0.0, 0);
    for i in 0..=steps {
        let t = i as f64 / rate;
        core.step(t, &mut out);
        if t >= duration - average {
            mean += out.whitecaps.levels[0].mean as f64;
            coarse += out.whitecaps.levels[1].mean as f64;
            count += 1;
        }
    }
    (mean / count as f64, coarse / count as f64)
}

#[test]
fn whitecap_coverage_follows_monahan() {
    println!("wind  Monahan W  fine level  coarse level  fine / W");
    let mut rows = Vec::new();
    for wind in [8.0f32, 12.0, 16.0, 20.0] {
        // After a minute of simulated time: the mean over its last 20 s, three seas.
        let (fine, coarse) = whitecap_coverage(wind, 60.0, 20.0, 10.0, &[1, 2, 3]);
        let w = monahan(wind);
        println!(
            "{wind:>4}  {:>7.2} %  {:>8.2} %  {:>10.2} %  {:>8.2}",
            100.0 * w,
            100.0 * fine,
            100.0 * coarse,
            fine / w
        );
        rows.push((wind, w, fine, coarse));
    }
    for (wind, w, fine, coarse) in &rows {
        // The gate: the mean coverage within a factor of two of Monahan's law.
        assert!(
            (0.5..=2.0).contains(&(fine / w)),
            "{wind} m/s: coverage {:.2} % vs Monahan's {:.2} %",
            100.0 * fine,
            100.0 * w
        );
        // The far level shows the same sea (its lattice filters more, its threshold differs).
        assert!(
            (0.5..=2.0).contains(&(coarse / fine)),
            "{wind} m/s: coarse level {:.2} % vs fine {:.2} %",
            100.0 * coarse,
            100.0 * fine
        );
    }
    assert!(
        rows.windows(2).all(|p| p[1].2 > p[0].2),
        "coverage does not grow with the wind: {rows:?}"
    );
}

#[test]
fn whitecaps_can_be_switched_off() {
    let mut means = Vec::new();
    for on in [true, false] {
        let mut cfg = default_sea(20.0, 1);
        cfg.whitecaps = on;
        let mut core = SimCore::new(cfg.clone()).unwrap();
        let mut out = Surfaces::new(&cfg);
        for i in 0..30 {
            core.step(i as f64 / 10.0, &mut out);
        }
        means.push(out.whitecaps.levels[0].mean);
    }
    assert!(means[0] > 0.01, "a gale without whitecaps: {means:?}");
    assert_eq!(means[1], 0.0, "whitecaps computed although off: {means:?}");
}
