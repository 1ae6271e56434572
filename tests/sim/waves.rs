//! One wave's shape and motion through the public API: the loop period, a single mode's
//! phase speed, the trochoid a choppy wave makes and the points it gathers under the crests.

use vr_ocean::sim::evolve::{self, LoopPhase, OutsideSupport};
use vr_ocean::sim::fft::Fft2d;
use vr_ocean::sim::spectrum::{self, PackedSpectrum};
use vr_ocean::sim::surface::{self, CascadeSurface, FloatCopies, SurfaceParams, Transformed};
use vr_ocean::sim::{
    dispersion, AlignedBuf, FoamParams, GridSize, OceanConfig, SimCore, SplitField, Support,
};

use crate::helpers::{rms, step};

#[test]
fn animation_repeats_after_the_loop_period() {
    let cfg = OceanConfig::default_cascades(64).unwrap();
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let period = cfg.waves.loop_period as f64;
    for t in [0.0, 3.7, 123.25] {
        let a = step(&mut core, &cfg, t);
        let b = step(&mut core, &cfg, t + period);
        let c = step(&mut core, &cfg, t + 7.0 * period);
        for ((ca, cb), cc) in a.cascades.iter().zip(&b.cascades).zip(&c.cascades) {
            let scale = rms(ca.displacement.iter().map(|d| d[1])) as f32;
            assert!(scale > 0.0);
            for ((x, y), z) in ca
                .displacement
                .iter()
                .zip(&cb.displacement)
                .zip(&cc.displacement)
            {
                for k in 0..3 {
                    assert!((x[k] - y[k]).abs() <= 1e-4 * scale, "t={t}: {x:?} vs {y:?}");
                    assert!((x[k] - z[k]).abs() <= 1e-4 * scale, "t={t}: {x:?} vs {z:?}");
                }
            }
        }
        // And it does move in between.
        let d = step(&mut core, &cfg, t + 0.5 * period);
        let moved = a.cascades[0]
            .displacement
            .iter()
            .zip(&d.cascades[0].displacement)
            .any(|(x, y)| (x[1] - y[1]).abs() > 1e-3);
        assert!(moved);
    }
}

/// A spectrum with one mode h₀(k) = amplitude at texel (col, row) and nothing else.
fn single_mode(
    grid: GridSize,
    col: usize,
    row: usize,
    amplitude: f32,
    harmonic: u32,
) -> PackedSpectrum {
    let n = grid.n();
    let mut s: [AlignedBuf; 4] = std::array::from_fn(|_| AlignedBuf::zeros(grid.texels()));
    let mut harm = vec![0u32; grid.texels()];
    // S' = (a + c, b + d, b − d, c − a) with (a, b) = h₀(k) and (c, d) = conj h₀(−k) = 0 at k;
    // at −k: (a, b) = 0 and (c, d) = conj h₀(k).
    let i = row * n + col;
    let m = ((n - row) & (n - 1)) * n + ((n - col) & (n - 1));
    s[0][i] = amplitude;
    s[3][i] = -amplitude;
    s[0][m] = amplitude;
    s[3][m] = amplitude;
    harm[i] = harmonic;
    harm[m] = harmonic;
    let mut spectrum = PackedSpectrum {
        grid,
        s,
        harmonic: harm,
        expected_variance: 2.0 * (amplitude as f64).powi(2),
        slopes: Default::default(),
        stokes_drift: [0.0; 2],
        support: Support::full(grid),
    };
    spectrum.support = spectrum.find_support();
    spectrum
}

/// Height field of a packed spectrum at time t, through the real evolve → FFT → surface path.
fn heights(spec: &PackedSpectrum, patch: f32, t: f64, period: f32) -> Vec<f32> {
    surface_of(spec, patch, t, period, 0.0)
        .displacement
        .iter()
        .map(|d| d[1])
        .collect()
}

/// The whole surface (with f32 copies) of a packed spectrum at time t and choppiness λ.
fn surface_of(
    spec: &PackedSpectrum,
    patch: f32,
    t: f64,
    period: f32,
    choppiness: f32,
) -> CascadeSurface {
    let grid = spec.grid;
    let fft = Fft2d::new(grid);
    let mut fields: [SplitField; 4] = std::array::from_fn(|_| SplitField::zeros(grid));
    let mut scratch: [SplitField; 4] = std::array::from_fn(|_| SplitField::zeros(grid));
    // The step's path: only the spectrum's support is evolved, read and transformed.
    let at = LoopPhase::new(t, period);
    evolve::evolve(spec, patch, at, &mut fields, OutsideSupport::Unwritten);
    fft.inverse_batch_support(&mut fields, &mut scratch, &spec.support);
    let mut out = CascadeSurface::new(grid, patch, FloatCopies::Keep);
    let mut foam = AlignedBuf::zeros(grid.texels());
    let p = SurfaceParams {
        choppiness,
        roughness: 0.0,
        foam: FoamParams::default(),
        dt: 0.0,
    };
    surface::finalize(Transformed::Spectral(&fields), &mut foam, p, t, &mut out);
    out
}

#[test]
fn a_long_crested_choppy_wave_is_a_trochoid_with_narrow_crests() {
    // One mode along +x: h = a·cos(k·x − ωt). Choppy waves move points toward the crest
    // (Gerstner): x' = x − λ·a·sin(k·x − ωt), so crests are narrower than troughs.
    let grid = GridSize::new(64).unwrap();
    let (n, patch, period, lambda) = (64usize, 100.0f32, 200.0f32, 1.0f32);
    let (col, row) = (n / 2 + 2, n / 2);
    let (kx, _) = spectrum::wave_vector(col, row, grid, patch);
    let k = kx.abs();
    // Steepness a·k = 0.4: clearly choppy, not folded.
    let a = 0.4 / k as f32;
    let harmonic = dispersion::loop_harmonic(dispersion::omega(k, None), period);
    let spec = single_mode(grid, col, row, a / 2.0, harmonic);
    let s = surface_of(&spec, patch, 7.3, period, lambda);
    let d = s.displacement.clone();
    let texel = patch / n as f32;
    // Every row is the same profile; check it is the trochoid x' = x − λ·(∂/∂(kx))h, i.e.
    // Dx = −λ·a·sin θ where h = a·cos θ.
    let first = &d[..n];
    let (mut sum_sq_err, mut sum_sq) = (0.0f64, 0.0f64);
    for (c, t) in first.iter().enumerate() {
        // θ from the height and the sign of the slope: h = a cos θ, ∂h/∂x = −a·k·sin θ, so
        // the trochoid's Dx = λ·(∂h/∂x)/k.
        let next = first[(c + 1) % n][1];
        let prev = first[(c + n - 1) % n][1];
        let slope = (next - prev) / (2.0 * texel);
        // Central differences of a sampled cosine shrink the slope by sin(kΔ)/(kΔ).
        let kd = k as f32 * texel;
        let expect_dx = lambda * slope / k as f32 * kd / kd.sin();
        sum_sq_err += ((t[0] - expect_dx) as f64).powi(2);
        sum_sq += (expect_dx as f64).powi(2);
        assert!(t[2].abs() < 1e-4 * a, "no displacement across the crests");
    }
    let rel = (sum_sq_err / sum_sq).sqrt();
    assert!(
        rel < 1e-3,
        "Dx is not the trochoid's −λ·a·sin θ: relative error {rel}"
    );
    // Widths of crest (h > 0) and trough (h < 0) in displaced coordinates, from the zero
    // crossings of h interpolated along the displaced x.
    let xs: Vec<f32> = first
        .iter()
        .enumerate()
        .map(|(c, t)| c as f32 * texel + t[0])
        .collect();
    let mut crossings = Vec::new();
    for c in 0..n {
        let (h0, h1) = (first[c][1], first[(c + 1) % n][1]);
        if (h0 > 0.0) != (h1 > 0.0) {
            let x1 = if c + 1 == n { xs[0] + patch } else { xs[c + 1] };
            let x = xs[c] + (x1 - xs[c]) * h0 / (h0 - h1);
            crossings.push((x, h0 > 0.0));
        }
    }
    assert_eq!(crossings.len(), 4, "two wavelengths in the patch");
    let (mut crest, mut trough) = (0.0f32, 0.0f32);
    for i in 0..4 {
        let (x0, leaving_crest) = crossings[i];
        let x1 = crossings[(i + 1) % 4].0 + if i == 3 { patch } else { 0.0 };
        if leaving_crest {
            trough += x1 - x0;
        } else {
            crest += x1 - x0;
        }
    }
    // Trochoid: crest = L/2 − 2λa, trough = L/2 + 2λa per wavelength L (a·k = 0.4, λ = 1:
    // crest / trough = (π − 0.8) / (π + 0.8) ≈ 0.59).
    let wavelength = std::f32::consts::TAU / k as f32;
    let expect_crest = 2.0 * (wavelength / 2.0 - 2.0 * lambda * a);
    eprintln!("crest {crest} m, trough {trough} m, trochoid crest {expect_crest} m");
    assert!(
        crest < 0.7 * trough,
        "crests ({crest} m) must be narrower than troughs ({trough} m)"
    );
    assert!(
        (crest / expect_crest - 1.0).abs() < 0.01,
        "crest width {crest} m, trochoid {expect_crest} m"
    );
}

#[test]
fn choppy_displacement_gathers_points_under_the_crests() {
    // On a random sea the Jacobian is lowest on crests (points converge there, whitecaps on
    // top) and highest in troughs: h and J are negatively correlated.
    let mut cfg = OceanConfig::single(256, 200.0).unwrap();
    cfg.waves.wind_speed = 12.0;
    cfg.waves.choppiness = 1.0;
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let s = step(&mut core, &cfg, 30.0);
    let d = &s.cascades[0].displacement;
    let n = d.len() as f64;
    let mean = |f: &dyn Fn(&[f32; 4]) -> f64| d.iter().map(f).sum::<f64>() / n;
    let (mh, mj) = (mean(&|t| t[1] as f64), mean(&|t| t[3] as f64));
    let cov = mean(&|t| (t[1] as f64 - mh) * (t[3] as f64 - mj));
    let vh = mean(&|t| (t[1] as f64 - mh).powi(2));
    let vj = mean(&|t| (t[3] as f64 - mj).powi(2));
    let corr = cov / (vh * vj).sqrt();
    let mut by_height: Vec<&[f32; 4]> = d.iter().collect();
    by_height.sort_by(|a, b| a[1].total_cmp(&b[1]));
    let one_percent = by_height.len() / 100;
    let mean_j = |v: &[&[f32; 4]]| v.iter().map(|t| t[3] as f64).sum::<f64>() / v.len() as f64;
    let (j_troughs, j_crests) = (
        mean_j(&by_height[..one_percent]),
        mean_j(&by_height[by_height.len() - one_percent..]),
    );
    eprintln!(
        "corr(h, J) = {corr:.3}, mean J: highest 1 % {j_crests:.3}, lowest 1 % {j_troughs:.3}"
    );
    assert!(
        corr < -0.3,
        "corr(h, J) = {corr:.3}: crests must be compressed"
    );
    assert!(
        j_crests < 1.0 && j_troughs > 1.0,
        "mean J over the highest 1 %: {j_crests:.3} (< 1), lowest 1 %: {j_troughs:.3} (> 1)"
    );
}

#[test]
fn a_single_mode_travels_along_k_at_the_phase_speed() {
    let grid = GridSize::new(64).unwrap();
    let (n, patch, period) = (64usize, 100.0f32, 200.0f32);
    // k = 2π/L·(3, 2): texel (col, row) = (N/2 + 3, N/2 + 2).
    let (col, row) = (n / 2 + 3, n / 2 + 2);
    let (kx, kz) = spectrum::wave_vector(col, row, grid, patch);
    let k = (kx * kx + kz * kz).sqrt();
    let omega = dispersion::omega(k, None);
    let harmonic = dispersion::loop_harmonic(omega, period);
    let omega_q = harmonic as f64 * std::f64::consts::TAU / period as f64;
    assert!(omega - omega_q < std::f64::consts::TAU / period as f64);
    let spec = single_mode(grid, col, row, 0.5, harmonic);
    // Project h(x, t) on e^{−ik·x}: the phase of the result is −ω't + const for a wave moving
    // along +k.
    let phase_at = |t: f64| {
        let h = heights(&spec, patch, t, period);
        let (mut re, mut im) = (0.0f64, 0.0f64);
        for r in 0..n {
            for c in 0..n {
                let (x, z) = (
                    c as f64 * patch as f64 / n as f64,
                    r as f64 * patch as f64 / n as f64,
                );
                let a = -(kx * x + kz * z);
                re += h[r * n + c] as f64 * a.cos();
                im += h[r * n + c] as f64 * a.sin();
            }
        }
        // Amplitude check: h = 2·A·cos(k·x − ωt), so |projection| = A·N².
        assert!(((re * re + im * im).sqrt() / (0.5 * (n * n) as f64) - 1.0).abs() < 1e-4);
        im.atan2(re)
    };
    let dt = 0.05;
    let (p0, p1) = (phase_at(10.0), phase_at(10.0 + dt));
    let mut dphi = p1 - p0;
    if dphi > std::f64::consts::PI {
        dphi -= std::f64::consts::TAU;
    }
    if dphi < -std::f64::consts::PI {
        dphi += std::f64::consts::TAU;
    }
    let measured_omega = -dphi / dt;
    assert!(
        (measured_omega / omega_q - 1.0).abs() < 1e-4,
        "ω measured {measured_omega}, quantized {omega_q}"
    );
    // Phase speed c = ω/k, positive: the crest moves along +k.
    let c = measured_omega / k;
    let c_theory = omega / k;
    assert!(c > 0.0);
    assert!((c / c_theory - 1.0).abs() < 0.01, "c {c} vs {c_theory}");
}
