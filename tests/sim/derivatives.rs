//! The two derivative modes ([`Derivatives`]): central differences computed right (against an
//! independent f64 difference of the surface they publish), their error against the spectral
//! derivatives on the default sea, and the same determinism contract as the spectral mode.

use vr_ocean::sim::surface::{unit, CascadeSurface};
use vr_ocean::sim::{Derivatives, OceanConfig, SimCore, Surfaces};

/// The default three cascades on an `n`-grid in derivative mode `d`.
fn sea(n: u32, d: Derivatives) -> OceanConfig {
    OceanConfig {
        derivatives: d,
        ..OceanConfig::default_cascades(n).unwrap()
    }
}

/// One step at time `t` with float copies kept.
fn surfaces(cfg: &OceanConfig, t: f64) -> Surfaces {
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let mut out = Surfaces::with_float_copies(cfg);
    core.step(t, &mut out);
    out
}

/// Jacobian and unit normal of the displaced surface at texel (r, c) by central differences
/// (eq. 45-46) of the published f32 displacement, in f64, neighbours wrapping.
fn reference(s: &CascadeSurface, r: usize, c: usize) -> (f64, [f64; 3]) {
    let n = s.grid.n();
    let d = |r: usize, c: usize| s.displacement[(r % n) * n + c % n].map(f64::from);
    let inv_2dx = n as f64 / (2.0 * s.patch as f64);
    let (right, left) = (d(r, c + 1), d(r, c + n - 1));
    let (up, down) = (d(r + 1, c), d(r + n - 1, c));
    // ∂P/∂x and ∂P/∂z of P = x + (Dx, h, Dz).
    let px = [
        1.0 + (right[0] - left[0]) * inv_2dx,
        (right[1] - left[1]) * inv_2dx,
        (right[2] - left[2]) * inv_2dx,
    ];
    let pz = [
        (up[0] - down[0]) * inv_2dx,
        (up[1] - down[1]) * inv_2dx,
        1.0 + (up[2] - down[2]) * inv_2dx,
    ];
    let j = px[0] * pz[2] - pz[0] * px[2];
    let cross = [
        pz[1] * px[2] - pz[2] * px[1],
        pz[2] * px[0] - pz[0] * px[2],
        pz[0] * px[1] - pz[1] * px[0],
    ];
    let flip = if j < 0.0 { -1.0 } else { 1.0 };
    let l = (cross[0].powi(2) + cross[1].powi(2) + cross[2].powi(2)).sqrt();
    (j, cross.map(|v| v * flip / l))
}

/// Angle (degrees) between two unit vectors.
fn angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    dot.clamp(-1.0, 1.0).acos().to_degrees()
}

#[test]
fn finite_mode_takes_central_differences_of_the_surface_it_publishes() {
    // Every texel, the patch edges included (they wrap): a sign, row or scale error in the
    // kernel shows up as degrees, f32 rounding as hundredths where a fold is near (the
    // normal's direction is ill-conditioned there: 0.023 deg measured).
    let cfg = sea(64, Derivatives::Finite);
    let out = surfaces(&cfg, 7.25);
    for (i, s) in out.cascades.iter().enumerate() {
        let n = s.grid.n();
        let normals = s.base_normals().expect("float copies kept");
        let (mut worst_angle, mut worst_j) = (0.0f64, 0.0f64);
        for r in 0..n {
            for c in 0..n {
                let (j, normal) = reference(s, r, c);
                let got = unit(normals[r * n + c]).map(f64::from);
                worst_angle = worst_angle.max(angle_deg(got, normal));
                worst_j = worst_j.max((s.displacement[r * n + c][3] as f64 - j).abs());
            }
        }
        eprintln!("cascade {i}: worst normal {worst_angle:.5} deg, worst J {worst_j:.2e}");
        assert!(
            worst_angle < 0.1,
            "cascade {i}: normal off by {worst_angle} deg"
        );
        assert!(worst_j < 1e-4, "cascade {i}: Jacobian off by {worst_j}");
    }
}

/// Percentile `p` (0..1) of `v` (sorted in place).
fn percentile(v: &mut [f64], p: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p) as usize]
}

#[test]
fn finite_differences_stay_near_the_spectral_derivatives() {
    // The default sea at the default grid: the finite mode flattens each cascade's finest
    // waves by sin(kΔ)/(kΔ) and nothing else. The table is in docs/notes/fft-128bit.md.
    let t = 7.25;
    let spectral = surfaces(&sea(256, Derivatives::Spectral), t);
    let finite = surfaces(&sea(256, Derivatives::Finite), t);
    for (i, (a, b)) in spectral.cascades.iter().zip(&finite.cascades).enumerate() {
        let (na, nb) = (a.base_normals().unwrap(), b.base_normals().unwrap());
        let mut angles: Vec<f64> = na
            .iter()
            .zip(nb)
            .map(|(x, y)| angle_deg(unit(*x).map(f64::from), unit(*y).map(f64::from)))
            .collect();
        let (mut dj2, mut j2, mut dh) = (0.0f64, 0.0f64, 0.0f32);
        for (x, y) in a.displacement.iter().zip(&b.displacement) {
            dj2 += ((x[3] - y[3]) as f64).powi(2);
            j2 += ((x[3] - 1.0) as f64).powi(2);
            dh = dh.max(
                (x[0] - y[0])
                    .abs()
                    .max((x[1] - y[1]).abs())
                    .max((x[2] - y[2]).abs()),
            );
        }
        let rms_angle = (angles.iter().map(|a| a * a).sum::<f64>() / angles.len() as f64).sqrt();
        let p99 = percentile(&mut angles, 0.99);
        let j_rel = (dj2 / j2).sqrt();
        eprintln!(
            "cascade {i} ({} m): normal error rms {rms_angle:.3} deg, p99 {p99:.3} deg; \
             Jacobian rms error {:.1} % of its spread; displacement differs by {dh:.1e} m",
            a.patch,
            100.0 * j_rel
        );
        // The same displacement (h and Dx come out of the same transform; Dz's rounds apart).
        assert!(
            dh < 1e-4 * a.max_displacement[1].max(1e-3),
            "displacement {dh} m"
        );
        // The default sea measures at most 1.5 deg rms, 4.0 deg p99 and 31 % (the finest
        // cascade, whose waves reach its Nyquist); a wrong sign or spacing gives tens of
        // degrees and a Jacobian error of the order of its spread.
        assert!(
            rms_angle < 2.5 && p99 < 6.0,
            "cascade {i}: {rms_angle} / {p99} deg"
        );
        assert!(
            j_rel < 0.5,
            "cascade {i}: Jacobian error {j_rel} of its spread"
        );
    }
}

#[test]
fn finite_mode_is_identical_for_any_thread_count_and_tier() {
    use vr_ocean::sim::simd::{cap_tier, Tier};
    let cfg = sea(128, Derivatives::Finite);
    let run = |threads: usize, tier: Tier| {
        cap_tier(tier);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let out = pool.install(|| {
            let mut core = SimCore::new(cfg.clone()).unwrap();
            let mut out = Surfaces::with_float_copies(&cfg);
            for i in 0..3 {
                core.step(1.0 + i as f64 / 72.0, &mut out);
            }
            out
        });
        cap_tier(Tier::Avx512);
        let bits: Vec<u32> = out
            .cascades
            .iter()
            .flat_map(|c| c.displacement.iter().flatten().map(|v| v.to_bits()))
            .chain(out.cascades.iter().flat_map(|c| c.normal_foam.clone()))
            .collect();
        bits
    };
    let base = run(1, Tier::Baseline);
    for (threads, tier) in [(2, Tier::Baseline), (1, Tier::Avx2), (3, Tier::Avx512)] {
        assert!(
            run(threads, tier) == base,
            "{threads} threads at {tier:?} differ from 1 thread at the baseline"
        );
    }
}

#[test]
fn the_slope_central_differences_lose_is_what_the_spectrum_predicts() {
    // Without choppiness the normal is (−∂h/∂x, 1, −∂h/∂z): the mean square slope each mode
    // shows is measurable, and its expectation is `SlopeVariance` (resolved for spectral
    // derivatives, resolved_finite for central differences). The finite mode hands the
    // difference to the renderer's roughness, so it must be the right amount.
    use vr_ocean::sim::spectrum::PackedSpectrum;
    let mut cfg = sea(256, Derivatives::Spectral);
    cfg.waves.choppiness = 0.0;
    let finest = cfg.patch_sizes.len() - 1;
    let spec = cfg.cascade_specs()[finest];
    let expected = PackedSpectrum::generate(&cfg.waves, &spec).slopes;
    let measured = |d: Derivatives| {
        let out = surfaces(
            &OceanConfig {
                derivatives: d,
                ..cfg.clone()
            },
            3.5,
        );
        let normals = out.cascades[finest].base_normals().unwrap();
        let sum: f64 = normals
            .iter()
            .map(|n| {
                let (sx, sz) = (n[0] as f64 / n[1] as f64, n[2] as f64 / n[1] as f64);
                sx * sx + sz * sz
            })
            .sum();
        (
            sum / normals.len() as f64,
            out.unresolved_slope_variance as f64,
        )
    };
    let (spectral, rough_s) = measured(Derivatives::Spectral);
    let (finite, rough_f) = measured(Derivatives::Finite);
    let predicted = expected.resolved_finite / expected.resolved;
    eprintln!(
        "finest cascade: mean square slope spectral {spectral:.5} (expected {:.5}), finite \
         {finite:.5} (expected {:.5}); measured ratio {:.3}, predicted {predicted:.3}; \
         roughness variance {rough_s:.5} -> {rough_f:.5}",
        expected.resolved,
        expected.resolved_finite,
        finite / spectral
    );
    assert!(
        ((finite / spectral) / predicted - 1.0).abs() < 0.03,
        "central differences keep {:.3} of the slope variance, the spectrum says {predicted:.3}",
        finite / spectral
    );
    assert!(
        predicted < 0.9,
        "the finest cascade's waves reach its Nyquist: differences must lose slope"
    );
    // What the finite mode loses comes back as roughness (the whole loss when the spectrum
    // tail, not Cox & Munk's total, sets the roughness).
    assert!(rough_f > rough_s, "roughness {rough_s} -> {rough_f}");
}
