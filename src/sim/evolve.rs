//! Stage 2 (thesis 4.2.2): evolve the packed spectrum to time t (eq. 24) and build the spectra
//! of the eight real fields the surface needs, two per complex transform.
//!
//! With h̃ = h̃(k, t), u = k/|k| (eq. 28) and the FFT computing Σ X(k)·e^{ik·x}:
//!
//! | field | real part            | imaginary part             |
//! |-------|----------------------|----------------------------|
//! | 0     | h        ← h̃         | X  ← i·uₓ·h̃ (eq. 25, 30)   |
//! | 1     | Z ← i·u_z·h̃          | ∂h/∂x ← i·kₓ·h̃             |
//! | 2     | ∂h/∂z ← i·k_z·h̃      | ∂X/∂x ← −kₓ·uₓ·h̃           |
//! | 3     | ∂Z/∂z ← −k_z·u_z·h̃   | ∂X/∂z ← −k_z·uₓ·h̃          |
//!
//! Each field's spectrum is Hermitian, so packing A + i·B into one transform yields A and B as
//! the real and imaginary outputs. The horizontal displacement is D = −λ·(X, Z) (eq. 44).

use rayon::prelude::*;

use crate::sim::grid::SplitField;
use crate::sim::simd::dispatch;
use crate::sim::spectrum::PackedSpectrum;
use crate::sim::trig::sincos_turns;

/// Bits of the loop phase handled exactly in integer arithmetic.
const PHASE_BITS: u32 = 12;

/// The loop phase u = (t mod T)/T split so that frac(n·u) is exact to f32 precision for any
/// harmonic n: u = hi/2¹² + lo, where n·hi is computed in integers.
#[derive(Clone, Copy, Debug)]
pub struct LoopPhase {
    hi: u32,
    lo: f32,
}

impl LoopPhase {
    /// Phase of time `t` (s) within loop period `period` (s). Times a whole period apart give
    /// identical phases (to f64 rounding of t mod T), which makes h(t + T) = h(t).
    pub fn new(t: f64, period: f32) -> Self {
        let u = (t / period as f64).rem_euclid(1.0);
        let scaled = u * (1u32 << PHASE_BITS) as f64;
        let hi = (scaled.floor() as u32).min((1 << PHASE_BITS) - 1);
        let lo = ((scaled - hi as f64) / (1u32 << PHASE_BITS) as f64) as f32;
        Self { hi, lo }
    }

    /// frac(n·u) in turns for harmonic `n`.
    #[inline(always)]
    fn turns(self, n: u32) -> f32 {
        // Through i32: both values are < 2²⁴, and i32 → f32 is one SIMD instruction.
        let exact = (n.wrapping_mul(self.hi) & ((1 << PHASE_BITS) - 1)) as i32 as f32
            * (1.0 / (1u32 << PHASE_BITS) as f32);
        exact + n as i32 as f32 * self.lo
    }
}

/// h̃(k, t) = S'xy·cos φ + S'zw·sin φ (eq. 24) with φ = ω't.
///
/// Expanding eq. 17 directly gives Im h̃ = (b+d)·cos φ + (a−c)·sin φ; the S' of eq. 22,
/// (a+c, b+d, b−d, c−a), negates the sine terms, i.e. it evaluates eq. 17 at −φ:
/// h̃ = h₀(k)·e^{−iω't} + h₀*(−k)·e^{iω't}. That is the convention we want: each component
/// h₀(k)·e^{i(k·x − ωt)} travels along k, with the wind the counter-wave suppression (eq. 8-9)
/// favours. The single-mode test pins the direction down.
#[inline(always)]
fn evolved(s: &[&[f32]; 4], col: usize, sin: f32, cos: f32) -> (f32, f32) {
    (
        s[0][col] * cos + s[2][col] * sin,
        s[1][col] * cos + s[3][col] * sin,
    )
}

/// The height spectrum h̃(k, t) alone (eq. 24), for checks and height-only uses.
pub fn height_spectrum(spectrum: &PackedSpectrum, phase: LoopPhase, out: &mut SplitField) {
    let n = spectrum.grid.n();
    let (re, im) = out.planes_mut();
    re.par_chunks_mut(n)
        .zip(im.par_chunks_mut(n))
        .enumerate()
        .for_each(|(row, (re, im))| {
            let base = row * n;
            let s = [
                &spectrum.s[0][base..base + n],
                &spectrum.s[1][base..base + n],
                &spectrum.s[2][base..base + n],
                &spectrum.s[3][base..base + n],
            ];
            for col in 0..n {
                let (sin, cos) = sincos_turns(phase.turns(spectrum.harmonic[base + col]));
                (re[col], im[col]) = evolved(&s, col, sin, cos);
            }
        });
}

/// One row of the evolution: inputs, outputs and the row's constants.
struct EvolveRow<'a> {
    s: [&'a [f32]; 4],
    harm: &'a [u32],
    out: [&'a mut [f32]; 8],
    phase: LoopPhase,
    dk: f32,
    gz: f32,
    half: f32,
}

#[inline(always)]
fn evolve_row_kernel(row: EvolveRow<'_>) {
    let n = row.harm.len();
    let s = [
        &row.s[0][..n],
        &row.s[1][..n],
        &row.s[2][..n],
        &row.s[3][..n],
    ];
    let [r0, i0, r1, i1, r2, i2, r3, i3] = row.out;
    // Exact-length slices let the compiler drop bounds checks and vectorize.
    let (r0, i0, r1, i1) = (&mut r0[..n], &mut i0[..n], &mut r1[..n], &mut i1[..n]);
    let (r2, i2, r3, i3) = (&mut r2[..n], &mut i2[..n], &mut r3[..n], &mut i3[..n]);
    let (dk, gz, half) = (row.dk, row.gz, row.half);
    let kz = gz * dk;
    for col in 0..n {
        let (sin, cos) = sincos_turns(row.phase.turns(row.harm[col]));
        let (hr, hi) = evolved(&s, col, sin, cos);
        // Unit wave direction with the DC-safe rsqrt of eq. 28 (grid units).
        let gx = col as i32 as f32 - half;
        let inv = 1.0 / (gx * gx + gz * gz).max(1.0).sqrt();
        let (ux, uz) = (gx * inv, gz * inv);
        let kx = gx * dk;
        // Field 0: h̃·(1 − uₓ).
        let f = 1.0 - ux;
        r0[col] = hr * f;
        i0[col] = hi * f;
        // Field 1: h̃·(−kₓ + i·u_z).
        r1[col] = -hr * kx - hi * uz;
        i1[col] = hr * uz - hi * kx;
        // Field 2: i·h̃·(k_z − kₓ·uₓ).
        let g = kz - kx * ux;
        r2[col] = -hi * g;
        i2[col] = hr * g;
        // Field 3: −k_z·h̃·(u_z + i·uₓ).
        let (p, q) = (kz * uz, kz * ux);
        r3[col] = hi * q - hr * p;
        i3[col] = -(hr * q + hi * p);
    }
}

dispatch!(fn evolve_row(row: EvolveRow<'_>) => evolve_row_kernel);

/// Writes the four packed field spectra at loop phase `phase` (eq. 24) for a cascade of patch
/// size `patch` (m). Parallel over rows on the current Rayon pool; element-wise, so the output
/// is the same for any thread count.
pub fn evolve(
    spectrum: &PackedSpectrum,
    patch: f32,
    phase: LoopPhase,
    fields: &mut [SplitField; 4],
) {
    let n = spectrum.grid.n();
    let dk = std::f32::consts::TAU / patch;
    let half = (n / 2) as f32;
    let [f0, f1, f2, f3] = fields;
    let (r0, i0) = f0.planes_mut();
    let (r1, i1) = f1.planes_mut();
    let (r2, i2) = f2.planes_mut();
    let (r3, i3) = f3.planes_mut();
    let outs = r0
        .par_chunks_mut(n)
        .zip(i0.par_chunks_mut(n))
        .zip(r1.par_chunks_mut(n).zip(i1.par_chunks_mut(n)))
        .zip(r2.par_chunks_mut(n).zip(i2.par_chunks_mut(n)))
        .zip(r3.par_chunks_mut(n).zip(i3.par_chunks_mut(n)))
        .enumerate();
    outs.for_each(|(row, ((((r0, i0), (r1, i1)), (r2, i2)), (r3, i3)))| {
        let base = row * n;
        evolve_row(EvolveRow {
            s: [
                &spectrum.s[0][base..base + n],
                &spectrum.s[1][base..base + n],
                &spectrum.s[2][base..base + n],
                &spectrum.s[3][base..base + n],
            ],
            harm: &spectrum.harmonic[base..base + n],
            out: [r0, i0, r1, i1, r2, i2, r3, i3],
            phase,
            dk,
            gz: row as f32 - half,
            half,
        });
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loop_phase_repeats_after_a_period() {
        for t in [0.0, 1.234, 57.5, 199.999] {
            let a = LoopPhase::new(t, 200.0);
            let b = LoopPhase::new(t + 200.0, 200.0);
            let c = LoopPhase::new(t + 2000.0, 200.0);
            for n in [0u32, 1, 7, 1000, 5000, 100_000] {
                let (x, y, z) = (a.turns(n), b.turns(n), c.turns(n));
                assert!((x - y).abs() < 1e-5 && (x - z).abs() < 1e-5, "{t} {n}");
            }
        }
    }

    #[test]
    fn loop_phase_is_accurate_for_large_harmonics() {
        for t in [3.3f64, 123.456, 199.0] {
            let p = LoopPhase::new(t, 200.0);
            for n in [1u32, 999, 4097, 65_535] {
                let exact = (n as f64 * t / 200.0).fract();
                let got = (p.turns(n) as f64).rem_euclid(1.0);
                let err = (got - exact).abs();
                let err = err.min((err - 1.0).abs());
                assert!(err < 4e-6, "t {t} n {n}: {got} vs {exact}");
            }
        }
    }
}
