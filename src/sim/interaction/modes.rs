//! The exact step of every Fourier mode: a rotation of (ĥ, φ̂) by ω·dt, with
//! ω² = g·|k| + (σ/ρ)·|k|³, and the layer's energy from the same values.
//!
//! The field arrives as W = conj(Z), Z the forward transform of z = h + iφ (the layer keeps
//! h − iφ between steps, whose inverse transform is W). For the pair (k, −k):
//! ĥ_k = (Z_k + conj(Z₋ₖ))/2, φ̂_k = (Z_k − conj(Z₋ₖ))/(2i); after the rotation
//! Z'_k = ĥ'_k + i·φ̂'_k and Z'₋ₖ = conj(ĥ'_k) + i·conj(φ̂'_k), ready for the inverse transform
//! back to N²·(h + iφ). The mean (k = 0) and the Nyquist row and column are zeroed: the mean
//! does not move, and a checkerboard is no wave.

use crate::sim::grid::{AlignedBuf, GridSize, SplitField};

/// Per mode k (rows 0..=N/2; the partner −k has the same |k|): cos ωdt, (|k|/ω)·sin ωdt,
/// (ω/|k|)·sin ωdt and the energy weights ω²/|k| and |k|. Zero at the mean and the Nyquist
/// row and column, which the update thereby zeroes.
pub(super) struct ModeTable {
    n: usize,
    cos: AlignedBuf,
    to_h: AlignedBuf,
    to_phi: AlignedBuf,
    weight_h: AlignedBuf,
    weight_phi: AlignedBuf,
    /// Energy of each row pair (J, before the common factor), summed in order afterwards.
    row_energy: Vec<f64>,
}

impl ModeTable {
    /// Tables for an N × N layer of `cell_m` cells stepped by `dt`.
    pub(super) fn new(size: GridSize, cell_m: f32, dt: f32, gravity: f32, tension: f32) -> Self {
        let n = size.n();
        let len = (n / 2 + 1) * n;
        let mut t = Self {
            n,
            cos: AlignedBuf::zeros(len),
            to_h: AlignedBuf::zeros(len),
            to_phi: AlignedBuf::zeros(len),
            weight_h: AlignedBuf::zeros(len),
            weight_phi: AlignedBuf::zeros(len),
            row_energy: vec![0.0; n / 2 + 1],
        };
        let dk = 2.0 * std::f64::consts::PI / (n as f64 * cell_m as f64);
        let signed = |i: usize| {
            if i < n / 2 {
                i as f64
            } else {
                i as f64 - n as f64
            }
        };
        for r in 0..=n / 2 {
            for c in 0..n {
                if (r == 0 && c == 0) || r == n / 2 || c == n / 2 {
                    continue;
                }
                let k = dk * signed(r).hypot(signed(c));
                let w2 = gravity as f64 * k + tension as f64 * k * k * k;
                let w = w2.sqrt();
                let (s, co) = (w * dt as f64).sin_cos();
                let i = r * n + c;
                t.cos[i] = co as f32;
                t.to_h[i] = (k / w * s) as f32;
                t.to_phi[i] = (w / k * s) as f32;
                t.weight_h[i] = (w2 / k) as f32;
                t.weight_phi[i] = k as f32;
            }
        }
        t
    }

    /// Rotates every mode of `field` (W in, Z' out) and returns Σ_k (ω²/|k|)·|ĥ_k|² +
    /// |k|·|φ̂_k|² over all k (unnormalized transform values).
    pub(super) fn rotate(&mut self, field: &mut SplitField) -> f64 {
        let n = self.n;
        let half = n / 2;
        let mut row_energy = std::mem::take(&mut self.row_energy);
        let (re, im) = field.planes_mut();
        // Row 0 pairs column c with N − c inside itself; row N/2 is the Nyquist row.
        let mut e0 = 0.0f32;
        for c in 1..half {
            let j = n - c;
            let (zk, zm, de) = self.pair(c, [re[c], im[c]], [re[j], im[j]]);
            [re[c], im[c]] = zk;
            [re[j], im[j]] = zm;
            e0 += de;
        }
        for i in [0, half] {
            re[i] = 0.0;
            im[i] = 0.0;
        }
        row_energy[0] = e0 as f64;
        row_energy[half] = 0.0;
        re[half * n..(half + 1) * n].fill(0.0);
        im[half * n..(half + 1) * n].fill(0.0);
        // Rows r and N − r, 0 < r < N/2, in parallel: element (r, c) pairs with
        // (N − r, (N − c) mod N).
        let (re_top, re_bottom) = re.split_at_mut(half * n);
        let (im_top, im_bottom) = im.split_at_mut(half * n);
        let this = &*self;
        re_top[n..]
            .chunks_mut(n)
            .zip(im_top[n..].chunks_mut(n))
            .zip(re_bottom[n..].chunks_mut(n).rev())
            .zip(im_bottom[n..].chunks_mut(n).rev())
            .zip(row_energy[1..half].iter_mut())
            .enumerate()
            .for_each(|(i, ((((tr, ti), br), bi), energy))| {
                // The partner row reversed ((N − c) mod N at c) into a local copy, so that the
                // loop below is element-wise (and vectorizes).
                let mut pr = [0.0f32; MAX_N];
                let mut pi = [0.0f32; MAX_N];
                let mut e = [0.0f32; MAX_N];
                for c in 0..n {
                    let j = (n - c) & (n - 1);
                    pr[c] = br[j];
                    pi[c] = bi[j];
                }
                let row = (i + 1) * n;
                let rows = row..row + n;
                let (cos, th, tp) = (
                    &this.cos[rows.clone()],
                    &this.to_h[rows.clone()],
                    &this.to_phi[rows.clone()],
                );
                let (wh, wp) = (&this.weight_h[rows.clone()], &this.weight_phi[rows]);
                for c in 0..n {
                    let (zk, zm, de) = rotate_pair(
                        [cos[c], th[c], tp[c], wh[c], wp[c]],
                        [tr[c], ti[c]],
                        [pr[c], pi[c]],
                    );
                    [tr[c], ti[c]] = zk;
                    [pr[c], pi[c]] = zm;
                    e[c] = de;
                }
                for c in 0..n {
                    let j = (n - c) & (n - 1);
                    br[j] = pr[c];
                    bi[j] = pi[c];
                }
                *energy = e[..n].iter().sum::<f32>() as f64;
            });
        let total = row_energy.iter().sum();
        self.row_energy = row_energy;
        total
    }

    /// [`rotate_pair`] with mode `t`'s table entries.
    #[inline(always)]
    fn pair(&self, t: usize, wk: [f32; 2], wm: [f32; 2]) -> ([f32; 2], [f32; 2], f32) {
        let tab = [
            self.cos[t],
            self.to_h[t],
            self.to_phi[t],
            self.weight_h[t],
            self.weight_phi[t],
        ];
        rotate_pair(tab, wk, wm)
    }
}

/// Largest side a layer may have (its rows are copied to the stack).
pub(super) const MAX_N: usize = 512;

/// One pair: W_k and W₋ₖ in, Z'_k and Z'₋ₖ out, with twice the mode's energy (k and −k);
/// `tab` is (cos ωdt, (|k|/ω)·sin ωdt, (ω/|k|)·sin ωdt, ω²/|k|, |k|).
#[inline(always)]
fn rotate_pair(tab: [f32; 5], wk: [f32; 2], wm: [f32; 2]) -> ([f32; 2], [f32; 2], f32) {
    let [c, th, tp, weight_h, weight_phi] = tab;
    // p = conj(W_k) = Z_k, q = W₋ₖ = conj(Z₋ₖ).
    let (pr, pi) = (wk[0], -wk[1]);
    let (qr, qi) = (wm[0], wm[1]);
    let (ar, ai) = (0.5 * (pr + qr), 0.5 * (pi + qi));
    let (br, bi) = (0.5 * (pi - qi), -0.5 * (pr - qr));
    let (hr, hi) = (c * ar + th * br, c * ai + th * bi);
    let (fr, fi) = (c * br - tp * ar, c * bi - tp * ai);
    let energy = 2.0 * (weight_h * (ar * ar + ai * ai) + weight_phi * (br * br + bi * bi));
    ([hr - fi, hi + fr], [hr + fi, fr - hi], energy)
}
