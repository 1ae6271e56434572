//! Wave following: a small buoy rides a single long swell with the swell's heave amplitude and
//! period, and in the default sea its height tracks the water's `height_at` at its centre.
//!
//! The swell is one Fourier mode of the simulation's own pipeline (a packed spectrum with a
//! single h₀, evolved, inverse-FFT'd and finalized into a [`Surfaces`] every physics step, with
//! the default choppiness), so the bodies read it through the same batched height queries
//! (`height_at`'s heights) as they read the app's sea.

use glam::Vec3;
use vr_ocean::physics::{BodyId, BodySpec, Floaters, PhysicsConfig, Pose, PHYSICS_DT};
use vr_ocean::sim::evolve::{self, LoopPhase, OutsideSupport};
use vr_ocean::sim::fft::Fft2d;
use vr_ocean::sim::spectrum::{self, PackedSpectrum};
use vr_ocean::sim::surface::{self, SurfaceParams, Transformed};
use vr_ocean::sim::{
    dispersion, AlignedBuf, FoamParams, GridSize, OceanConfig, SimCore, SplitField, Support,
    Surfaces,
};

/// One long-crested swell along +x through the simulation's evolve → FFT → surface path.
struct Swell {
    spectrum: PackedSpectrum,
    patch: f32,
    period: f32,
    choppiness: f32,
    fft: Fft2d,
    fields: [SplitField; 4],
    scratch: [SplitField; 4],
    foam: AlignedBuf,
    surfaces: Surfaces,
    /// Amplitude (m) and angular frequency (rad/s, as quantized by the loop period).
    amplitude: f32,
    omega: f64,
    wavelength: f32,
}

impl Swell {
    /// A swell of `amplitude` (m) whose wavelength is `patch / modes` (m).
    fn new(patch: f32, modes: usize, amplitude: f32, choppiness: f32) -> Self {
        let n = 64usize;
        let grid = GridSize::new(n as u32).unwrap();
        let period = 200.0f32;
        let (col, row) = (n / 2 + modes, n / 2);
        let (kx, _) = spectrum::wave_vector(col, row, grid, patch);
        let harmonic = dispersion::loop_harmonic(dispersion::omega(kx.abs(), None), period);
        // h₀(k) = a/2 at k and its conjugate at −k: h = a·cos(k·x − ωt). The packing
        // S' = (a + c, b + d, b − d, c − a) follows tests/sim/waves.rs.
        let mut s: [AlignedBuf; 4] = std::array::from_fn(|_| AlignedBuf::zeros(grid.texels()));
        let i = row * n + col;
        let m = ((n - row) & (n - 1)) * n + ((n - col) & (n - 1));
        let h0 = 0.5 * amplitude;
        s[0][i] = h0;
        s[3][i] = -h0;
        s[0][m] = h0;
        s[3][m] = h0;
        let mut harm = vec![0u32; grid.texels()];
        harm[i] = harmonic;
        harm[m] = harmonic;
        let mut spectrum = PackedSpectrum {
            grid,
            s,
            harmonic: harm,
            expected_variance: 2.0 * (h0 as f64).powi(2),
            slopes: Default::default(),
            stokes_drift: [0.0; 2],
            support: Support::full(grid),
        };
        spectrum.support = spectrum.find_support();
        let cfg = OceanConfig::single(n as u32, patch).unwrap();
        Self {
            spectrum,
            patch,
            period,
            choppiness,
            fft: Fft2d::new(grid),
            fields: std::array::from_fn(|_| SplitField::zeros(grid)),
            scratch: std::array::from_fn(|_| SplitField::zeros(grid)),
            foam: AlignedBuf::zeros(grid.texels()),
            surfaces: Surfaces::new(&cfg),
            amplitude,
            omega: harmonic as f64 * std::f64::consts::TAU / period as f64,
            wavelength: patch / modes as f32,
        }
    }

    /// The surfaces at time `t` (s).
    fn at(&mut self, t: f64) -> &Surfaces {
        evolve::evolve(
            &self.spectrum,
            self.patch,
            LoopPhase::new(t, self.period),
            &mut self.fields,
            OutsideSupport::Unwritten,
        );
        let support = &self.spectrum.support;
        self.fft
            .inverse_batch_support(&mut self.fields, &mut self.scratch, support);
        let p = SurfaceParams {
            choppiness: self.choppiness,
            roughness: 0.1,
            foam: FoamParams::default(),
            dt: PHYSICS_DT,
        };
        surface::finalize(
            Transformed::Spectral(&self.fields),
            &mut self.foam,
            p,
            t,
            &mut self.surfaces.cascades[0],
        );
        &self.surfaces
    }
}

/// Mean, amplitude (√2 × RMS about the mean: a sine's amplitude) and mean period between
/// upward crossings of the mean (linearly interpolated) of a series sampled every `dt`.
fn oscillation(series: &[f32], dt: f32) -> (f32, f32, f32) {
    let n = series.len() as f64;
    let mean = (series.iter().map(|&y| y as f64).sum::<f64>() / n) as f32;
    let var = series
        .iter()
        .map(|&y| ((y - mean) as f64).powi(2))
        .sum::<f64>()
        / n;
    let mut ups = Vec::new();
    for (i, w) in series.windows(2).enumerate() {
        let (a, b) = (w[0] - mean, w[1] - mean);
        if a < 0.0 && b >= 0.0 {
            ups.push((i as f32 + a / (a - b)) * dt);
        }
    }
    let period = if ups.len() >= 2 {
        (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f32
    } else {
        f32::NAN
    };
    (mean, (2.0 * var).sqrt() as f32, period)
}

/// A buoy's centre height in calm water: its waterline offset.
fn calm_height(spec: BodySpec) -> f32 {
    let calm = Surfaces::new(&OceanConfig::single(64, 100.0).unwrap());
    let mut w = open_sea();
    let id = w.spawn(spec, Pose::at(Vec3::ZERO)).unwrap();
    for _ in 0..(30.0 / PHYSICS_DT) as usize {
        w.step(&calm);
    }
    w.pose(id).unwrap().position.y
}

fn small_buoy() -> BodySpec {
    BodySpec::buoy(0.6, 0.8, 300.0).unwrap()
}

#[test]
fn a_buoy_heaves_with_a_long_swell() {
    // A 50 m swell (83 buoy diameters), 0.5 m amplitude (steepness a·k = 0.063), choppy.
    let mut swell = Swell::new(100.0, 2, 0.5, 0.9);
    let spec = small_buoy();
    let rest = calm_height(spec);
    let mut world = open_sea();
    let start = Vec3::new(10.0, rest, 3.0);
    let id: BodyId = world.spawn(spec, Pose::at(start)).unwrap();
    let (settle, window) = ((20.0 / PHYSICS_DT) as usize, (80.0 / PHYSICS_DT) as usize);
    let (mut heave, mut water, mut drift) = (Vec::new(), Vec::new(), 0.0f32);
    for step in 0..settle + window {
        let t = step as f64 * PHYSICS_DT as f64;
        let s = swell.at(t);
        world.step(s);
        if step >= settle {
            let p = world.pose(id).unwrap().position;
            heave.push(p.y - rest);
            water.push(s.height_at(start.x, start.z));
            drift = drift.max(Vec3::new(p.x - start.x, 0.0, p.z - start.z).length());
        }
    }
    let (b_mean, b_amp, b_period) = oscillation(&heave, PHYSICS_DT);
    let (w_mean, w_amp, w_period) = oscillation(&water, PHYSICS_DT);
    let t_wave = (std::f64::consts::TAU / swell.omega) as f32;
    println!(
        "swell λ = {} m, a = {} m, T = {t_wave:.3} s; water at the start point: amplitude \
         {w_amp:.4} m, period {w_period:.3} s, mean {w_mean:.4} m; buoy heave: amplitude \
         {b_amp:.4} m ({:+.1} %), period {b_period:.3} s ({:+.1} %), mean {b_mean:.4} m; \
         horizontal excursion up to {drift:.2} m",
        swell.wavelength,
        swell.amplitude,
        100.0 * (b_amp / w_amp - 1.0),
        100.0 * (b_period / w_period - 1.0),
    );
    // The swell itself is what it should be (the check that the harness is right).
    assert!((w_amp / swell.amplitude - 1.0).abs() < 0.03, "{w_amp}");
    assert!((w_period / t_wave - 1.0).abs() < 0.01, "{w_period}");
    // The buoy follows it within 10 %.
    assert!(
        (b_amp / w_amp - 1.0).abs() < 0.10,
        "heave amplitude {b_amp} m vs the wave's {w_amp} m"
    );
    assert!(
        (b_period / w_period - 1.0).abs() < 0.10,
        "heave period {b_period} s vs the wave's {w_period} s"
    );
    // It rides at its waterline on average and stays near where it was put (no Stokes drift).
    assert!(b_mean.abs() < 0.05, "mean heave {b_mean} m");
    assert!(drift < 2.0 * swell.amplitude, "wandered {drift} m");
}

#[test]
fn in_the_default_sea_a_buoy_tracks_height_at_its_centre() {
    // The default sea (default waves and cascades) on a 128² grid, stepped at 45 Hz (every
    // second physics step). Gates: the buoy's height above its calm waterline minus
    // height_at at its centre averages within ±3 cm of zero and its rms is under 20 % of the
    // water's own rms there (measured: −0.5 cm, 9.5 %): what remains is the hull averaging
    // waves shorter than itself and the lag of a 45 Hz sea.
    let cfg = OceanConfig::default_cascades(128).unwrap();
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let mut surfaces = Surfaces::new(&cfg);
    let spec = small_buoy();
    let rest = calm_height(spec);
    let mut world = open_sea();
    core.step(0.0, &mut surfaces);
    let xz = (7.0, -4.0);
    let start = Vec3::new(xz.0, surfaces.height_at(xz.0, xz.1) + rest, xz.1);
    let id = world.spawn(spec, Pose::at(start)).unwrap();
    let (settle, window) = ((10.0 / PHYSICS_DT) as usize, (60.0 / PHYSICS_DT) as usize);
    let (mut diff, mut eta) = (Vec::new(), Vec::new());
    for step in 0..settle + window {
        if step % 2 == 0 {
            core.step(step as f64 * PHYSICS_DT as f64, &mut surfaces);
        }
        world.step(&surfaces);
        if step >= settle {
            let p = world.pose(id).unwrap().position;
            let h = surfaces.height_at(p.x, p.z);
            diff.push(p.y - rest - h);
            eta.push(h);
        }
    }
    let (d_mean, d_amp, _) = oscillation(&diff, PHYSICS_DT);
    let (e_mean, e_amp, e_period) = oscillation(&eta, PHYSICS_DT);
    let d_rms = d_amp / 2.0f32.sqrt();
    let e_rms = e_amp / 2.0f32.sqrt();
    println!(
        "default sea: water under the buoy: rms {e_rms:.3} m about {e_mean:.3} m, mean period \
         {e_period:.2} s; buoy height − waterline − height_at: mean {d_mean:+.4} m, rms \
         {d_rms:.4} m ({:.1} % of the water's rms)",
        100.0 * d_rms / e_rms
    );
    assert!(
        d_mean.abs() < 0.03,
        "mean offset {d_mean} m from height_at at its centre"
    );
    assert!(
        d_rms < 0.2 * e_rms,
        "rms {d_rms} m from height_at vs the water's {e_rms} m"
    );
}

/// A world without the deck: bodies alone on the sea.
fn open_sea() -> Floaters {
    Floaters::new(PhysicsConfig {
        deck: None,
        ..PhysicsConfig::default()
    })
    .unwrap()
}
