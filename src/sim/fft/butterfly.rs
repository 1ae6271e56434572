//! The FFT's vocabulary: the vector operations a backend provides ([`Simd`]), complex
//! vectors and twiddles, the radix-4 and radix-8 butterflies and the working rows' loads and
//! stores. A leaf of the FFT room: the first stage and the later stages both build on it.

use super::plan::{CRow, STRIP};

/// The vector operations the kernel needs. Implemented by zero-sized "proof" tokens: a value of
/// an implementing type exists only if the CPU supports the instructions its methods use, which is
/// what makes the methods safe to call. All methods are `#[inline(always)]` so they compile into
/// the `#[target_feature]` entry point that instantiates the kernel.
pub(super) trait Simd: Copy {
    /// f32 lanes per vector.
    const LANES: usize;
    /// The vector type.
    type V: Copy;
    /// All lanes `x`.
    fn splat(self, x: f32) -> Self::V;
    /// Loads `s[..LANES]` (panics if `s` is shorter; callers pass slices the compiler can size).
    fn load(self, s: &[f32]) -> Self::V;
    /// Stores into `s[..LANES]` (panics if `s` is shorter).
    fn store(self, s: &mut [f32], v: Self::V);
    /// `a + b`.
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a - b`.
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a * b`.
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a * b + c` (fused where the backend has FMA).
    fn mul_add(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    /// `c - a * b` (fused where the backend has FMA). NEON has this one as a single
    /// instruction (`fmls`) but not `a * b - c`, which cost it a negation per complex product.
    fn neg_mul_add(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    /// LANES vectors: a LANES×LANES block of f32, one row per vector.
    type Block: Copy + AsRef<[Self::V]> + AsMut<[Self::V]>;
    /// A block of zeros.
    fn zero_block(self) -> Self::Block;
    /// The transposed block: lane t of output vector c is lane c of input vector t.
    fn transpose(self, b: Self::Block) -> Self::Block;
}

/// A split complex vector: LANES adjacent columns.
#[derive(Clone, Copy)]
pub(super) struct C<V> {
    pub re: V,
    pub im: V,
}

/// A complex twiddle factor, broadcast to all lanes.
#[derive(Clone, Copy)]
pub(super) struct Tw<V> {
    pub re: V,
    pub im: V,
}

#[inline(always)]
pub(super) fn cmul<S: Simd>(s: S, a: C<S::V>, w: Tw<S::V>) -> C<S::V> {
    C {
        re: s.neg_mul_add(a.im, w.im, s.mul(a.re, w.re)),
        im: s.mul_add(a.re, w.im, s.mul(a.im, w.re)),
    }
}

/// Radix-4 inverse butterfly (no twiddles): `y_k = Σ_p x_p·i^(pk)`.
#[inline(always)]
pub(super) fn bfly4<S: Simd>(s: S, x: [C<S::V>; 4]) -> [C<S::V>; 4] {
    let [a, b, c, d] = x;
    let t0 = C {
        re: s.add(a.re, c.re),
        im: s.add(a.im, c.im),
    };
    let t1 = C {
        re: s.sub(a.re, c.re),
        im: s.sub(a.im, c.im),
    };
    let t2 = C {
        re: s.add(b.re, d.re),
        im: s.add(b.im, d.im),
    };
    let t3 = C {
        re: s.sub(b.re, d.re),
        im: s.sub(b.im, d.im),
    };
    [
        C {
            re: s.add(t0.re, t2.re),
            im: s.add(t0.im, t2.im),
        },
        // t1 + i·t3
        C {
            re: s.sub(t1.re, t3.im),
            im: s.add(t1.im, t3.re),
        },
        C {
            re: s.sub(t0.re, t2.re),
            im: s.sub(t0.im, t2.im),
        },
        // t1 - i·t3
        C {
            re: s.add(t1.re, t3.im),
            im: s.sub(t1.im, t3.re),
        },
    ]
}

/// Twiddles of radix-4 butterfly `j` of a stage, broadcast.
#[inline(always)]
pub(super) fn tw4<S: Simd>(s: S, tw: &[f32], j: usize) -> [Tw<S::V>; 3] {
    let w = &tw[6 * j..6 * j + 6];
    [
        Tw {
            re: s.splat(w[0]),
            im: s.splat(w[1]),
        },
        Tw {
            re: s.splat(w[2]),
            im: s.splat(w[3]),
        },
        Tw {
            re: s.splat(w[4]),
            im: s.splat(w[5]),
        },
    ]
}

#[inline(always)]
pub(super) fn load_row<S: Simd>(s: S, row: &CRow, o: usize) -> C<S::V> {
    C {
        re: s.load(&row.re[o..]),
        im: s.load(&row.im[o..]),
    }
}

#[inline(always)]
pub(super) fn store_row<S: Simd>(s: S, row: &mut CRow, o: usize, v: C<S::V>) {
    s.store(&mut row.re[o..], v.re);
    s.store(&mut row.im[o..], v.im);
}

/// Splits `rows` into four equal quarters.
#[inline(always)]
pub(super) fn quarters(rows: &mut [CRow]) -> [&mut [CRow]; 4] {
    let q = rows.len() / 4;
    let (a, rest) = rows.split_at_mut(q);
    let (b, rest) = rest.split_at_mut(q);
    let (c, d) = rest.split_at_mut(q);
    [a, b, c, &mut d[..q]]
}

/// Floats in one STRIP×STRIP tile of the intermediate layout.
pub(super) const TILE: usize = STRIP * STRIP;

/// Radix-8 inverse butterfly (no twiddles): `y_k = Σ_p x_p·ω^(pk)`, `ω = exp(+2πi/8)`, as a
/// radix-2 split (`a_p = x_p + x_(p+4)`, `b_p = (x_p − x_(p+4))·ω^p`) followed by two radix-4
/// butterflies giving the even and the odd outputs.
#[inline(always)]
pub(super) fn bfly8<S: Simd>(s: S, x: [C<S::V>; 8]) -> [C<S::V>; 8] {
    let add = |a: C<S::V>, b: C<S::V>| C {
        re: s.add(a.re, b.re),
        im: s.add(a.im, b.im),
    };
    let sub = |a: C<S::V>, b: C<S::V>| C {
        re: s.sub(a.re, b.re),
        im: s.sub(a.im, b.im),
    };
    let a = [
        add(x[0], x[4]),
        add(x[1], x[5]),
        add(x[2], x[6]),
        add(x[3], x[7]),
    ];
    let [d0, d1, d2, d3] = [
        sub(x[0], x[4]),
        sub(x[1], x[5]),
        sub(x[2], x[6]),
        sub(x[3], x[7]),
    ];
    let [e0, e1, e2, e3] = bfly4(s, a);
    // Odd outputs: radix 4 over b = [d0, d1·ω, i·d2, d3·ω³] with ω = (1+i)/√2, ω³ = (−1+i)/√2.
    let h = s.splat(std::f32::consts::FRAC_1_SQRT_2);
    let u = s.sub(d1.re, d1.im); // √2·Re(d1·ω)
    let v = s.add(d1.re, d1.im); // √2·Im(d1·ω)
    let w = s.add(d3.re, d3.im); // −√2·Re(d3·ω³)
    let z = s.sub(d3.re, d3.im); // √2·Im(d3·ω³)
                                 // b0 ± b2 with b2 = i·d2.
    let t0 = C {
        re: s.sub(d0.re, d2.im),
        im: s.add(d0.im, d2.re),
    };
    let t1 = C {
        re: s.add(d0.re, d2.im),
        im: s.sub(d0.im, d2.re),
    };
    // b1 ± b3.
    let t2 = C {
        re: s.mul(s.sub(u, w), h),
        im: s.mul(s.add(v, z), h),
    };
    let t3 = C {
        re: s.mul(s.add(u, w), h),
        im: s.mul(s.sub(v, z), h),
    };
    let o1 = add(t0, t2);
    let o5 = sub(t0, t2);
    // t1 ± i·t3
    let o3 = C {
        re: s.sub(t1.re, t3.im),
        im: s.add(t1.im, t3.re),
    };
    let o7 = C {
        re: s.add(t1.re, t3.im),
        im: s.sub(t1.im, t3.re),
    };
    [e0, o1, e1, o3, e2, o5, e3, o7]
}
