//! Measurements of a layer's field for tests and tools: the azimuthal profile of a ring, its
//! zero crossings and crests, and the half-angle of a wake. They read a plain [`FieldView`],
//! so an exported `.npy` and a live layer are measured by the same code.

use super::InteractionLayer;

/// A square height field on a regular grid: row = z, column = x.
#[derive(Clone, Copy, Debug)]
pub struct FieldView<'a> {
    /// Heights (m), row-major, `cells`².
    pub heights: &'a [f32],
    /// Cells a side.
    pub cells: usize,
    /// Cell side (m).
    pub cell_m: f32,
    /// World (x, z) of cell (0, 0) (m).
    pub origin: [f32; 2],
}

impl<'a> FieldView<'a> {
    /// The drawn field of a live layer.
    pub fn of(l: &'a InteractionLayer) -> Self {
        Self {
            heights: l.heights(),
            cells: l.config().cells.n(),
            cell_m: l.config().cell_m,
            origin: l.origin_m(),
        }
    }

    /// Every cell as (world x, world z, height).
    fn cells(&self) -> impl Iterator<Item = (f32, f32, f32)> + '_ {
        let n = self.cells;
        self.heights.iter().enumerate().map(move |(i, &h)| {
            (
                self.origin[0] + (i % n) as f32 * self.cell_m,
                self.origin[1] + (i / n) as f32 * self.cell_m,
                h,
            )
        })
    }
}

/// Azimuthal mean of the height around world (x0, z0) in `bins` rings of `bin` m.
pub fn radial_profile(f: &FieldView, x0: f32, z0: f32, bin: f32, bins: usize) -> Vec<f32> {
    let (mut sum, mut count) = (vec![0.0f64; bins], vec![0usize; bins]);
    for (x, z, h) in f.cells() {
        let b = ((x - x0).hypot(z - z0) / bin) as usize;
        if b < bins {
            sum[b] += h as f64;
            count[b] += 1;
        }
    }
    sum.iter()
        .zip(&count)
        .map(|(s, &k)| if k > 0 { (*s / k as f64) as f32 } else { 0.0 })
        .collect()
}

/// Zero crossings of a profile in bins of `bin` m (interpolated radius, m).
pub fn zero_crossings(p: &[f32], bin: f32) -> Vec<f32> {
    let mut out = Vec::new();
    for i in 1..p.len() {
        if (p[i - 1] < 0.0) != (p[i] < 0.0) && p[i - 1] != p[i] {
            let t = p[i - 1] / (p[i - 1] - p[i]);
            out.push((i as f32 - 0.5 + t) * bin);
        }
    }
    out
}

/// Local maxima of a profile above `floor` (radius, m; parabolic peak).
pub fn crests(p: &[f32], bin: f32, floor: f32) -> Vec<f32> {
    (1..p.len().saturating_sub(1))
        .filter(|&i| p[i] > floor && p[i] >= p[i - 1] && p[i] > p[i + 1])
        .map(|i| {
            let d = p[i - 1] - 2.0 * p[i] + p[i + 1];
            let off = if d != 0.0 {
                0.5 * (p[i - 1] - p[i + 1]) / d
            } else {
                0.0
            };
            (i as f32 + 0.5 + off) * bin
        })
        .collect()
}

/// One half-wave of a ring: between two zero crossings `inner` and `outer` (m), its measured
/// wavelength 2·(outer − inner) and Cauchy-Poisson's 8π·r²/(g·t²) at the middle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfWave {
    /// Inner crossing (m).
    pub inner: f32,
    /// Outer crossing (m).
    pub outer: f32,
    /// Measured wavelength (m).
    pub measured: f32,
    /// Predicted wavelength (m).
    pub predicted: f32,
}

/// The half-waves of the ring around (x0, z0) at `t` s after an impulsive start, where
/// Cauchy-Poisson's asymptotics apply and the source excites the waves: wavelengths from
/// `shortest` m at the inner crossing, phase g·t²/(4r) ≥ 2π at the outer one (stationary
/// phase), within `reach` m, with at least 3 % of the ring's peak. Profile bins of 4 cm.
pub fn ring_half_waves(
    f: &FieldView,
    x0: f32,
    z0: f32,
    t: f32,
    g: f32,
    shortest: f32,
    reach: f32,
) -> Vec<HalfWave> {
    let bin = 0.04;
    let p = radial_profile(f, x0, z0, bin, (reach / bin) as usize + 1);
    let peak = p.iter().map(|v| v.abs()).fold(0.0, f32::max);
    let lambda_at = |r: f32| 8.0 * std::f32::consts::PI * r * r / (g * t * t);
    zero_crossings(&p, bin)
        .windows(2)
        .filter_map(|w| {
            let (a, b) = (w[0], w[1]);
            let between = p[(a / bin) as usize..(b / bin) as usize]
                .iter()
                .map(|v| v.abs())
                .fold(0.0, f32::max);
            let phase = g * t * t / (4.0 * b);
            let keep = lambda_at(a) >= shortest
                && phase >= std::f32::consts::TAU
                && b <= reach
                && between >= 0.03 * peak;
            keep.then(|| HalfWave {
                inner: a,
                outer: b,
                measured: 2.0 * (b - a),
                predicted: lambda_at(0.5 * (a + b)),
            })
        })
        .collect()
}

/// Mean square height of the wake behind a source at (x0, z0) moving along +x, over
/// downstream distances `near..far` m, per degree of angle from its track (0-89°).
pub fn wake_profile(f: &FieldView, x0: f32, z0: f32, near: f32, far: f32) -> Vec<f32> {
    let (mut sum, mut count) = ([0.0f64; 90], [0usize; 90]);
    for (x, z, h) in f.cells() {
        let (d, y) = (x0 - x, (z - z0).abs());
        if d < near || d > far {
            continue;
        }
        let b = y.atan2(d).to_degrees() as usize;
        if b < 90 {
            sum[b] += (h as f64).powi(2);
            count[b] += 1;
        }
    }
    (0..90)
        .map(|b| {
            if count[b] > 0 {
                (sum[b] / count[b] as f64) as f32
            } else {
                0.0
            }
        })
        .collect()
}

/// The wake's half-angle (degrees) behind a source at (x0, z0) moving along +x, 3-15 m
/// behind it: outward from the peak of [`wake_profile`], where the mean square falls to 0.44
/// of the peak. In the Airy-function theory of the cusp the caustic (the geometric Kelvin
/// line) carries Ai(0)²/max Ai² = 0.44 of the peak intensity just inside it. `None` when the
/// profile has no peak with a fall after it.
pub fn wake_half_angle(f: &FieldView, x0: f32, z0: f32) -> Option<f32> {
    let profile = wake_profile(f, x0, z0, 3.0, 15.0);
    let peak = (0..profile.len()).max_by(|&a, &b| profile[a].total_cmp(&profile[b]))?;
    let level = 0.44 * profile[peak];
    let i = (peak..profile.len()).find(|&i| profile[i] < level)?;
    if i == 0 || profile[peak] <= 0.0 {
        return None;
    }
    // Bin i − 1 is at or above the level, bin i below: interpolate between their centres.
    let t = (profile[i - 1] - level) / (profile[i - 1] - profile[i]);
    Some(i as f32 - 0.5 + t)
}
