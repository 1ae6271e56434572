//! Grid sizes and the aligned planar buffers every stage works on.

use std::ops::Range;

use crate::base::ParamError;

/// Side length N of an N×N simulation grid: always a power of two in
/// [`GridSize::MIN`, `GridSize::MAX`] (the FFT sizes of thesis eq. 2), so code holding one never
/// re-checks it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct GridSize(u32);

impl GridSize {
    /// Smallest supported grid side.
    pub const MIN: u32 = 16;
    /// Largest supported grid side.
    pub const MAX: u32 = 1024;

    /// Validates `n`: a power of two in [16, 1024], else a [`ParamError`] naming `grid`.
    pub fn new(n: u32) -> Result<Self, ParamError> {
        if n.is_power_of_two() && (Self::MIN..=Self::MAX).contains(&n) {
            Ok(Self(n))
        } else {
            Err(ParamError::new(
                "grid",
                n as f64,
                "a power of two from 16 to 1024",
            ))
        }
    }

    /// The side length N.
    #[inline]
    pub fn n(self) -> usize {
        self.0 as usize
    }

    /// log2(N), the number of radix-2 stages (thesis eq. 36).
    #[inline]
    pub fn log2(self) -> u32 {
        self.0.trailing_zeros()
    }

    /// N², the texel count of one field.
    #[inline]
    pub fn texels(self) -> usize {
        self.n() * self.n()
    }

    /// Number of mip levels including the base, log2(N) + 1 (thesis section 3.9).
    #[inline]
    pub fn mip_levels(self) -> u32 {
        self.log2() + 1
    }
}

impl std::fmt::Display for GridSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// One cache line of f32s; the allocation unit of [`AlignedBuf`].
#[derive(Clone, Copy, Default, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
struct Line([f32; 16]);

/// A zero-initialised f32 buffer aligned to 64 bytes, so SIMD kernels (up to AVX-512) may use
/// aligned loads and rows of N ≥ 16 floats never straddle cache lines.
#[derive(Clone, Default)]
pub struct AlignedBuf {
    lines: Vec<Line>,
    len: usize,
}

impl AlignedBuf {
    /// `len` zeros.
    pub fn zeros(len: usize) -> Self {
        Self {
            lines: vec![Line::default(); len.div_ceil(16)],
            len,
        }
    }

    /// Number of f32 elements.
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when the buffer holds no elements.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl std::ops::Deref for AlignedBuf {
    type Target = [f32];
    #[inline]
    fn deref(&self) -> &[f32] {
        &bytemuck::cast_slice::<Line, f32>(&self.lines)[..self.len]
    }
}

impl std::ops::DerefMut for AlignedBuf {
    #[inline]
    fn deref_mut(&mut self) -> &mut [f32] {
        &mut bytemuck::cast_slice_mut::<Line, f32>(&mut self.lines)[..self.len]
    }
}

/// A complex N×N field in split (planar) form: real and imaginary planes, row-major.
/// Split form lets SIMD lanes hold neighbouring columns with no shuffles.
#[derive(Clone)]
pub struct SplitField {
    /// Real parts, `re[row * N + col]`.
    pub re: AlignedBuf,
    /// Imaginary parts, same layout.
    pub im: AlignedBuf,
    size: GridSize,
}

impl SplitField {
    /// A zeroed field of side `size`.
    pub fn zeros(size: GridSize) -> Self {
        Self {
            re: AlignedBuf::zeros(size.texels()),
            im: AlignedBuf::zeros(size.texels()),
            size,
        }
    }

    /// The grid side.
    #[inline]
    pub fn size(&self) -> GridSize {
        self.size
    }

    /// Both planes mutably at once.
    #[inline]
    pub fn planes_mut(&mut self) -> (&mut [f32], &mut [f32]) {
        (&mut self.re, &mut self.im)
    }
}

/// The rectangle of an N×N field outside which every value is zero. A cascade's spectrum is
/// zero outside its band ([`crate::sim::spectrum::cascade_bands`]), and the coarse cascades'
/// bands end far below their Nyquist: at N = 256 the default sea's two coarse spectra hold
/// their non-zeros within ~22 texels of the centre. The evolution skips the other rows and the
/// FFT's first pass the column strips that lie outside [`Support::cols`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Support {
    /// Rows that may hold non-zeros (empty if none does).
    pub rows: Range<usize>,
    /// Columns that may hold non-zeros (empty if none does).
    pub cols: Range<usize>,
}

impl Support {
    /// The whole field of side `size`.
    pub fn full(size: GridSize) -> Self {
        Self {
            rows: 0..size.n(),
            cols: 0..size.n(),
        }
    }

    /// No value at all.
    pub fn empty() -> Self {
        Self {
            rows: 0..0,
            cols: 0..0,
        }
    }

    /// Whether it holds no value.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty() || self.cols.is_empty()
    }

    /// The smallest support holding both.
    pub fn union(&self, o: &Support) -> Support {
        if self.is_empty() {
            return o.clone();
        }
        if o.is_empty() {
            return self.clone();
        }
        Support {
            rows: self.rows.start.min(o.rows.start)..self.rows.end.max(o.rows.end),
            cols: self.cols.start.min(o.cols.start)..self.cols.end.max(o.cols.end),
        }
    }

    /// The smallest support of a field of side `size` where `nonzero(row, col)` says which
    /// values are non-zero.
    pub fn of(size: GridSize, nonzero: impl Fn(usize, usize) -> bool) -> Self {
        let n = size.n();
        let (mut rows, mut cols) = ((n, 0), (n, 0));
        for r in 0..n {
            for c in 0..n {
                if nonzero(r, c) {
                    rows = (rows.0.min(r), rows.1.max(r + 1));
                    cols = (cols.0.min(c), cols.1.max(c + 1));
                }
            }
        }
        if rows.0 >= rows.1 {
            return Self {
                rows: 0..0,
                cols: 0..0,
            };
        }
        Self {
            rows: rows.0..rows.1,
            cols: cols.0..cols.1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn support_is_the_bounding_box_of_the_non_zeros() {
        let g = GridSize::new(16).unwrap();
        let s = Support::of(g, |r, c| (r, c) == (3, 9) || (r, c) == (7, 5));
        assert_eq!(
            s,
            Support {
                rows: 3..8,
                cols: 5..10
            }
        );
        assert_eq!(
            Support::of(g, |_, _| false),
            Support {
                rows: 0..0,
                cols: 0..0
            }
        );
        assert_eq!(Support::of(g, |_, _| true), Support::full(g));
    }

    #[test]
    fn grid_size_accepts_powers_of_two_in_range_only() {
        for n in [16, 32, 64, 128, 256, 512, 1024] {
            let g = GridSize::new(n).unwrap();
            assert_eq!(g.n(), n as usize);
            assert_eq!(1 << g.log2(), n);
        }
        for n in [0, 1, 8, 15, 17, 100, 2048, 3000] {
            let e = GridSize::new(n).unwrap_err();
            assert_eq!(e.parameter, "grid");
        }
    }

    #[test]
    fn aligned_buf_is_64_byte_aligned() {
        for len in [1, 16, 17, 1000] {
            let b = AlignedBuf::zeros(len);
            assert_eq!(b.len(), len);
            assert_eq!(b.as_ptr() as usize % 64, 0);
            assert!(b.iter().all(|&x| x == 0.0));
        }
    }
}
