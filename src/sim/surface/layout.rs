//! One cascade's published surface ([`CascadeSurface`]) and the layout of its float mip chain:
//! the data the row loop (`mod.rs`) and the mip chain (`mips.rs`) both write.

use half::f16;

use crate::sim::grid::GridSize;
use crate::sim::pack;

/// Everything one cascade publishes per step, in GPU upload formats plus float copies for CPU
/// queries and export. Allocated once; every step overwrites it in place.
pub struct CascadeSurface {
    /// Grid side.
    pub grid: GridSize,
    /// Patch size L (m): texel (c, r) sits at world (c, r)·L/N, repeating every L.
    pub patch: f32,
    /// The patch whose waves this cascade shows, for the renderer's distance fades: `patch`,
    /// except while a sea-state change hands the waves of one patch to another
    /// ([`crate::sim::retune`]), when it moves smoothly from the old patch to the new.
    pub fade_patch: f32,
    /// (Dx, h, Dz, J) per texel in metres (J dimensionless), row-major: the displaced surface
    /// point of texel x is x + (Dx, h, Dz). Full precision with [`FloatCopies::Keep`]; empty
    /// with [`FloatCopies::Skip`], where `displacement_f16` is the only copy.
    pub displacement: Vec<[f32; 4]>,
    /// The same as RGBA16F for the vertex shader (always present).
    pub displacement_f16: Vec<[f16; 4]>,
    /// RGBA8 normal/foam/smoothness chain (eq. 50-51), mip m at [`pack::mip_offset`].
    pub normal_foam: Vec<u32>,
    /// Level-0 roughness-scaled normal xyz and foam with [`FloatCopies::Keep`]; else empty.
    pub(super) base_floats: Vec<[f32; 4]>,
    /// Float mips behind `normal_foam` from level 1: unnormalized, roughness-scaled normal
    /// xyz and foam as four planes per level (see [`CascadeSurface::mip_floats`]), so the 2×2
    /// averages vectorize without de- and re-interleaving.
    pub(super) mip_chain: Vec<f32>,
    /// Largest |Dx|, |h|, |Dz| over the patch (m): pads LOD bounding boxes.
    pub max_displacement: [f32; 3],
    /// Simulation time (s) these fields show.
    pub time: f64,
    pub(super) row_max: Vec<[f32; 3]>,
}

/// Whether a surface keeps full-precision f32 copies of its level-0 fields: the displacement
/// and the normals and foam. The renderer needs only RGBA16F and RGBA8; each f32 copy costs a
/// 16-byte-per-texel stream every step (2 × 4 MiB at N = 512), so only export and checks keep
/// them. Height queries use the f32 displacement when kept, else the RGBA16F one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FloatCopies {
    /// Also store `displacement` and level-0 float normals and foam
    /// ([`CascadeSurface::base_normals`]).
    Keep,
    /// Level 0 exists only in the GPU formats.
    Skip,
}

impl CascadeSurface {
    /// Zeroed surface for one cascade.
    pub fn new(grid: GridSize, patch: f32, base: FloatCopies) -> Self {
        let chain = pack::mip_chain_len(grid);
        let kept = |len| match base {
            FloatCopies::Keep => len,
            FloatCopies::Skip => 0,
        };
        Self {
            grid,
            patch,
            fade_patch: patch,
            displacement: vec![[0.0; 4]; kept(grid.texels())],
            displacement_f16: vec![[f16::ZERO; 4]; grid.texels()],
            normal_foam: vec![0; chain],
            base_floats: vec![[0.0; 4]; kept(grid.texels())],
            mip_chain: vec![0.0; 4 * (chain - grid.texels())],
            max_displacement: [0.0; 3],
            time: 0.0,
            row_max: vec![[0.0; 3]; grid.n()],
        }
    }

    /// Whether this surface keeps f32 copies of level 0.
    pub(super) fn keeps_floats(&self) -> bool {
        !self.base_floats.is_empty()
    }

    /// Level-0 roughness-scaled normals (xyz) and foam (w), row-major, when kept.
    pub fn base_normals(&self) -> Option<&[[f32; 4]]> {
        self.keeps_floats().then_some(&self.base_floats[..])
    }

    /// Unnormalized float mip `level` ≥ 1 as averaged (eq. 52): the planes of normal x, y, z
    /// and foam, each row-major with side N/2^level.
    pub fn mip_floats(&self, level: u32) -> [&[f32]; 4] {
        let (block, area) = mip_block(self.grid, level);
        let planes = &self.mip_chain[block..block + 4 * area];
        std::array::from_fn(|q| &planes[q * area..(q + 1) * area])
    }
}

/// Where float mip `level` ≥ 1 starts in [`CascadeSurface::mip_chain`], and its texel count.
pub(super) fn mip_block(grid: GridSize, level: u32) -> (usize, usize) {
    let side = grid.n() >> level;
    let start = 4 * (pack::mip_offset(grid, level) - grid.texels());
    (start, side * side)
}

/// The four planes of a float mip block of `area` texels each.
pub(super) fn planes_mut(block: &mut [f32], area: usize) -> [&mut [f32]; 4] {
    let mut planes = block.chunks_exact_mut(area);
    std::array::from_fn(|_| planes.next().expect("a block holds four planes"))
}
