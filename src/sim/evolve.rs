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
//! the real and imaginary outputs. With [`Derivatives::Finite`](crate::sim::Derivatives) only
//! h, X and Z are made, in two transforms: h + i·X and Z + i·0 ([`evolve_finite`]); the
//! surface stage takes the slopes by central differences.
//!
//! The horizontal displacement is D = +λ·(X, Z): for a wave h = a·cos θ, X = −a·uₓ·sin θ, so points move toward the crest (x' = x − λ·a·sin θ, the
//! Gerstner trochoid: sharp crests, flat troughs, J < 1 on crests). The thesis's eq. 25 and 44
//! each carry a minus sign; applied together with this table's X they would pull points away
//! from crests, which folds the sea in its troughs.

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

/// The four packed spectra at one wave vector and at its mirror −k, from h̃(k) and the wave
/// vector. Each field packs two real fields A + i·B whose spectra are Hermitian, so with
/// Ã(k) = (ar, ai) and B̃(k) = (br, bi): C(k) = (ar − bi, ai + br) and
/// C(−k) = conj Ã + i·conj B̃ = (ar + bi, br − ai). Returns ([C(k)], [C(−k)]) as 8 floats each
/// (re, im of fields 0..4).
#[inline(always)]
fn packed_pair(hr: f32, hi: f32, ux: f32, uz: f32, kx: f32, kz: f32) -> ([f32; 8], [f32; 8]) {
    // (Ã, B̃) per field, from the table in the module docs.
    let pairs = [
        ((hr, hi), (-ux * hi, ux * hr)),                       // h, X
        ((-uz * hi, uz * hr), (-kx * hi, kx * hr)),            // Z, ∂h/∂x
        ((-kz * hi, kz * hr), (-kx * ux * hr, -kx * ux * hi)), // ∂h/∂z, ∂X/∂x
        (
            (-kz * uz * hr, -kz * uz * hi),
            (-kz * ux * hr, -kz * ux * hi),
        ), // ∂Z/∂z, ∂X/∂z
    ];
    pack(pairs)
}

/// [`packed_pair`] for the finite-difference mode: fields h + i·X and Z + i·0 in the first
/// four floats (the rest zero).
#[inline(always)]
fn packed_pair_finite(hr: f32, hi: f32, ux: f32, uz: f32) -> ([f32; 8], [f32; 8]) {
    pack([
        ((hr, hi), (-ux * hi, ux * hr)),   // h, X
        ((-uz * hi, uz * hr), (0.0, 0.0)), // Z, nothing
    ])
}

/// C(k) and C(−k) of fields A + i·B from their (Ã, B̃) at k (see [`packed_pair`]), field f in
/// floats 2f and 2f + 1; floats past the fields stay zero.
#[inline(always)]
fn pack<const F: usize>(pairs: [((f32, f32), (f32, f32)); F]) -> ([f32; 8], [f32; 8]) {
    let mut at = [0.0; 8];
    let mut mirror = [0.0; 8];
    for (f, ((ar, ai), (br, bi))) in pairs.into_iter().enumerate() {
        at[2 * f] = ar - bi;
        at[2 * f + 1] = ai + br;
        mirror[2 * f] = ar + bi;
        mirror[2 * f + 1] = br - ai;
    }
    (at, mirror)
}

/// Inputs and constants shared by the rows of one step.
#[derive(Clone, Copy)]
struct EvolveConsts {
    phase: LoopPhase,
    dk: f32,
    half: f32,
}

/// What every texel of one row reads.
#[derive(Clone, Copy)]
struct RowInputs<'a> {
    s: [&'a [f32]; 4],
    harm: &'a [u32],
    phase: LoopPhase,
    dk: f32,
    half: f32,
    gz: f32,
    kz: f32,
}

/// The packed spectra at column `col` of the row and at its mirror (see [`packed_pair`];
/// [`packed_pair_finite`] with `FINITE`).
#[inline(always)]
fn texel<const FINITE: bool>(row: &RowInputs<'_>, col: usize) -> ([f32; 8], [f32; 8]) {
    let (sin, cos) = sincos_turns(row.phase.turns(row.harm[col]));
    let (hr, hi) = evolved(&row.s, col, sin, cos);
    // Unit wave direction with the DC-safe rsqrt of eq. 28 (grid units).
    let gx = col as i32 as f32 - row.half;
    let gz = row.gz;
    let inv = 1.0 / (gx * gx + gz * gz).max(1.0).sqrt();
    if FINITE {
        packed_pair_finite(hr, hi, gx * inv, gz * inv)
    } else {
        packed_pair(hr, hi, gx * inv, gz * inv, gx * row.dk, row.kz)
    }
}

/// Row r into `o*` and, with `MIRROR`, row N − r into `m*` (pass empty slices otherwise);
/// with `FINITE` only planes 0-3 (`o4..o7`, `m4..m7` empty).
/// Column c of row r maps to column (N − c) mod N of row N − r; column 0 (Nyquist, zero in
/// every field) is done before the loop so the mirror stores run backwards contiguously. The
/// planes are separate arguments so the compiler knows they do not alias and vectorizes.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn evolve_rows_kernel<const MIRROR: bool, const FINITE: bool>(
    row: RowInputs<'_>,
    o0: &mut [f32],
    o1: &mut [f32],
    o2: &mut [f32],
    o3: &mut [f32],
    o4: &mut [f32],
    o5: &mut [f32],
    o6: &mut [f32],
    o7: &mut [f32],
    m0: &mut [f32],
    m1: &mut [f32],
    m2: &mut [f32],
    m3: &mut [f32],
    m4: &mut [f32],
    m5: &mut [f32],
    m6: &mut [f32],
    m7: &mut [f32],
) {
    let n = row.harm.len();
    let row = RowInputs {
        s: row.s.map(|p| &p[..n]),
        ..row
    };
    let (o0, o1, o2, o3) = (&mut o0[..n], &mut o1[..n], &mut o2[..n], &mut o3[..n]);
    let hi = if FINITE { 0 } else { n };
    let (o4, o5, o6, o7) = (&mut o4[..hi], &mut o5[..hi], &mut o6[..hi], &mut o7[..hi]);
    let m = if MIRROR { n } else { 0 };
    let mhi = if FINITE { 0 } else { m };
    let (m0, m1, m2, m3) = (&mut m0[..m], &mut m1[..m], &mut m2[..m], &mut m3[..m]);
    let (m4, m5, m6, m7) = (
        &mut m4[..mhi],
        &mut m5[..mhi],
        &mut m6[..mhi],
        &mut m7[..mhi],
    );
    let (at, mir) = texel::<FINITE>(&row, 0);
    (o0[0], o1[0], o2[0], o3[0]) = (at[0], at[1], at[2], at[3]);
    if !FINITE {
        (o4[0], o5[0], o6[0], o7[0]) = (at[4], at[5], at[6], at[7]);
    }
    if MIRROR {
        (m0[0], m1[0], m2[0], m3[0]) = (mir[0], mir[1], mir[2], mir[3]);
        if !FINITE {
            (m4[0], m5[0], m6[0], m7[0]) = (mir[4], mir[5], mir[6], mir[7]);
        }
    }
    for col in 1..n {
        let (at, mir) = texel::<FINITE>(&row, col);
        (o0[col], o1[col], o2[col], o3[col]) = (at[0], at[1], at[2], at[3]);
        if !FINITE {
            (o4[col], o5[col], o6[col], o7[col]) = (at[4], at[5], at[6], at[7]);
        }
        if MIRROR {
            let mc = n - col;
            (m0[mc], m1[mc], m2[mc], m3[mc]) = (mir[0], mir[1], mir[2], mir[3]);
            if !FINITE {
                (m4[mc], m5[mc], m6[mc], m7[mc]) = (mir[4], mir[5], mir[6], mir[7]);
            }
        }
    }
}

macro_rules! rows_variant {
    ($name:ident, $mirror:literal, $finite:literal) => {
        dispatch!(
            #[allow(clippy::too_many_arguments)]
            fn $name(
                row: RowInputs<'_>,
                o0: &mut [f32],
                o1: &mut [f32],
                o2: &mut [f32],
                o3: &mut [f32],
                o4: &mut [f32],
                o5: &mut [f32],
                o6: &mut [f32],
                o7: &mut [f32],
                m0: &mut [f32],
                m1: &mut [f32],
                m2: &mut [f32],
                m3: &mut [f32],
                m4: &mut [f32],
                m5: &mut [f32],
                m6: &mut [f32],
                m7: &mut [f32],
            ) => evolve_rows_kernel::<$mirror, $finite>
        );
    };
}
rows_variant!(evolve_pair_rows, true, false);
rows_variant!(evolve_single_row, false, false);
rows_variant!(evolve_pair_rows_finite, true, true);
rows_variant!(evolve_single_row_finite, false, true);

/// Runs one row (`mirror` empty: the row is its own mirror) or a mirrored pair, all eight
/// planes or (`FINITE`) the first four.
fn evolve_rows<const FINITE: bool>(
    row: RowInputs<'_>,
    out: [&mut [f32]; 8],
    mirror: [&mut [f32]; 8],
) {
    let [o0, o1, o2, o3, o4, o5, o6, o7] = out;
    let [m0, m1, m2, m3, m4, m5, m6, m7] = mirror;
    let run = match (m0.is_empty(), FINITE) {
        (true, false) => evolve_single_row,
        (false, false) => evolve_pair_rows,
        (true, true) => evolve_single_row_finite,
        (false, true) => evolve_pair_rows_finite,
    };
    run(
        row, o0, o1, o2, o3, o4, o5, o6, o7, m0, m1, m2, m3, m4, m5, m6, m7,
    )
}

/// The same row of 8 planes as one item: a parallel iterator over rows of all planes at once.
fn rows8(
    planes: [&mut [f32]; 8],
    n: usize,
) -> impl IndexedParallelIterator<Item = [&mut [f32]; 8]> {
    let [a, b, c, d, e, f, g, h] = planes;
    a.par_chunks_mut(n)
        .zip(b.par_chunks_mut(n))
        .zip(c.par_chunks_mut(n))
        .zip(d.par_chunks_mut(n))
        .zip(e.par_chunks_mut(n))
        .zip(f.par_chunks_mut(n))
        .zip(g.par_chunks_mut(n))
        .zip(h.par_chunks_mut(n))
        .map(|(((((((a, b), c), d), e), f), g), h)| [a, b, c, d, e, f, g, h])
}

/// [`rows8`] over the first four planes (the rest are empty), for the finite mode.
fn rows4(
    planes: [&mut [f32]; 8],
    n: usize,
) -> impl IndexedParallelIterator<Item = [&mut [f32]; 8]> {
    let [a, b, c, d, ..] = planes;
    a.par_chunks_mut(n)
        .zip(b.par_chunks_mut(n))
        .zip(c.par_chunks_mut(n))
        .zip(d.par_chunks_mut(n))
        .map(|(((a, b), c), d)| {
            let mut row: [&mut [f32]; 8] = Default::default();
            [row[0], row[1], row[2], row[3]] = [a, b, c, d];
            row
        })
}

/// What [`evolve`] writes in the rows outside the spectrum's
/// [`support`](PackedSpectrum::support), which are zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutsideSupport {
    /// Zeros: the whole field is written (for [`Fft2d::inverse_batch`]).
    ///
    /// [`Fft2d::inverse_batch`]: crate::sim::fft::Fft2d::inverse_batch
    Zeroed,
    /// Nothing: for [`Fft2d::inverse_batch_support`], which reads none of them.
    ///
    /// [`Fft2d::inverse_batch_support`]: crate::sim::fft::Fft2d::inverse_batch_support
    Unwritten,
}

/// Writes the four packed field spectra at loop phase `phase` (eq. 24) for a cascade of patch
/// size `patch` (m). Rows r and N − r are computed together (Hermitian symmetry), so the
/// evolution and its spectrum reads cover half the grid. Rows outside the spectrum's
/// [`support`](PackedSpectrum::support) are not evolved, only written as `outside` says.
/// Parallel over row pairs on the current Rayon pool; element-wise, so the output is the same
/// for any thread count.
pub fn evolve(
    spectrum: &PackedSpectrum,
    patch: f32,
    phase: LoopPhase,
    fields: &mut [SplitField; 4],
    outside: OutsideSupport,
) {
    let [f0, f1, f2, f3] = fields;
    let (r0, i0) = f0.planes_mut();
    let (r1, i1) = f1.planes_mut();
    let (r2, i2) = f2.planes_mut();
    let (r3, i3) = f3.planes_mut();
    let planes = [r0, i0, r1, i1, r2, i2, r3, i3];
    evolve_planes::<false>(spectrum, patch, phase, planes, outside);
}

/// [`evolve`] for [`Derivatives::Finite`](crate::sim::Derivatives): the spectra of h + i·X and
/// Z + i·0 only (the surface stage differences them), half the planes and transforms.
pub fn evolve_finite(
    spectrum: &PackedSpectrum,
    patch: f32,
    phase: LoopPhase,
    fields: &mut [SplitField; 2],
    outside: OutsideSupport,
) {
    let [f0, f1] = fields;
    let (r0, i0) = f0.planes_mut();
    let (r1, i1) = f1.planes_mut();
    let mut planes: [&mut [f32]; 8] = Default::default();
    [planes[0], planes[1], planes[2], planes[3]] = [r0, i0, r1, i1];
    evolve_planes::<true>(spectrum, patch, phase, planes, outside);
}

/// A row outside the support, written as `outside` says (the empty planes of the finite mode
/// stay empty).
fn outside_row(rows: [&mut [f32]; 8], outside: OutsideSupport) {
    if outside == OutsideSupport::Zeroed {
        for plane in rows {
            plane.fill(0.0);
        }
    }
}

/// The common body of [`evolve`] and [`evolve_finite`] (`FINITE`: planes 4-7 are empty).
fn evolve_planes<const FINITE: bool>(
    spectrum: &PackedSpectrum,
    patch: f32,
    phase: LoopPhase,
    planes: [&mut [f32]; 8],
    outside: OutsideSupport,
) {
    let n = spectrum.grid.n();
    let live = |r: usize| spectrum.support.rows.contains(&r);
    let half = n / 2;
    let k = EvolveConsts {
        phase,
        dk: std::f32::consts::TAU / patch,
        half: half as f32,
    };
    let used = if FINITE { 4 } else { 8 };
    // Each plane: row 0 | rows 1..N/2 | row N/2 | rows N/2+1..N.
    let mut row0: [&mut [f32]; 8] = Default::default();
    let mut top: [&mut [f32]; 8] = Default::default();
    let mut mid: [&mut [f32]; 8] = Default::default();
    let mut bottom: [&mut [f32]; 8] = Default::default();
    for (i, plane) in planes.into_iter().take(used).enumerate() {
        let (a, rest) = plane.split_at_mut(n);
        let (b, rest) = rest.split_at_mut((half - 1) * n);
        let (c, d) = rest.split_at_mut(n);
        (row0[i], top[i], mid[i], bottom[i]) = (a, b, c, d);
    }
    let row_of = |r: usize| -> RowInputs<'_> {
        let b = r * n;
        let gz = r as f32 - k.half;
        RowInputs {
            s: std::array::from_fn(|c| &spectrum.s[c][b..b + n]),
            harm: &spectrum.harmonic[b..b + n],
            phase: k.phase,
            dk: k.dk,
            half: k.half,
            gz,
            kz: gz * k.dk,
        }
    };
    // The two rows that are their own mirror: the Nyquist row 0 and k_z = 0.
    for (r, out) in [(0, row0), (half, mid)] {
        if live(r) {
            evolve_rows::<FINITE>(row_of(r), out, Default::default());
        } else {
            outside_row(out, outside);
        }
    }
    // Rows 1..N/2 ascending pair with rows N−1..N/2+1 descending.
    let pair = |(j, (out, mirror)): (usize, _)| {
        if live(j + 1) || live(n - 1 - j) {
            evolve_rows::<FINITE>(row_of(j + 1), out, mirror);
        } else {
            outside_row(out, outside);
            outside_row(mirror, outside);
        }
    };
    if FINITE {
        rows4(top, n)
            .zip(rows4(bottom, n).rev())
            .enumerate()
            .for_each(pair);
    } else {
        rows8(top, n)
            .zip(rows8(bottom, n).rev())
            .enumerate()
            .for_each(pair);
    }
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
