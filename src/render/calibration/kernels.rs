//! The calibration kernels: what each one draws and which work it measures. The fragment
//! shaders are `shaders/calibrate.frag` built per kernel (`render::shaders::calibration`); the
//! geometry is `shaders/calibrate.vert`'s (one triangle over the viewport, or a grid of small
//! ones).

use crate::render::shaders;

/// A fragment shader of the calibration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Shader {
    /// Nothing but the fragment's write.
    Base,
    /// FP32 arithmetic (fma, min, add).
    Alu,
    /// The same arithmetic in relaxed precision.
    Relaxed,
    /// Special functions (inverse square root, exp2).
    Special,
    /// Trilinear samples of an RGBA8 array with mips.
    Trilinear,
    /// The same through the anisotropic sampler, a 4:1 footprint.
    Anisotropic,
    /// Trilinear samples and FP32 arithmetic mixed as the water mixes them.
    Mixed,
    /// Samples at an explicit level of detail that differs from lane to lane.
    Lod,
    /// Samples with explicit gradients.
    Grad,
    /// Level-of-detail queries.
    Query,
    /// The explicit-level samples behind a branch no lane takes.
    Branch,
}

impl Shader {
    /// Every kernel shader, in the order the calibration runs them.
    pub const ALL: [Shader; 11] = [
        Shader::Base,
        Shader::Alu,
        Shader::Relaxed,
        Shader::Special,
        Shader::Trilinear,
        Shader::Anisotropic,
        Shader::Mixed,
        Shader::Lod,
        Shader::Grad,
        Shader::Query,
        Shader::Branch,
    ];

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Shader::Base => "base",
            Shader::Alu => "alu",
            Shader::Relaxed => "relaxed",
            Shader::Special => "special",
            Shader::Trilinear => "trilinear",
            Shader::Anisotropic => "anisotropic",
            Shader::Mixed => "mixed",
            Shader::Lod => "lod",
            Shader::Grad => "grad",
            Shader::Query => "query",
            Shader::Branch => "branch",
        }
    }

    /// Its SPIR-V (optimized, straight-line: `render::budget::spirv` counts it).
    pub fn spirv(self) -> &'static [u32] {
        use shaders::calibration as c;
        match self {
            Shader::Base => c::BASE,
            Shader::Alu => c::ALU,
            Shader::Relaxed => c::RELAXED,
            Shader::Special => c::SPECIAL,
            Shader::Trilinear => c::TRILINEAR,
            Shader::Anisotropic => c::ANISOTROPIC,
            Shader::Mixed => c::MIXED,
            Shader::Lod => c::LOD,
            Shader::Grad => c::GRAD,
            Shader::Query => c::QUERY,
            Shader::Branch => c::BRANCH,
        }
    }

    /// The pipeline's label in compiler statistics.
    pub fn label(self) -> &'static str {
        match self {
            Shader::Base => "calibration: base",
            Shader::Alu => "calibration: alu",
            Shader::Relaxed => "calibration: relaxed",
            Shader::Special => "calibration: special",
            Shader::Trilinear => "calibration: trilinear",
            Shader::Anisotropic => "calibration: anisotropic",
            Shader::Mixed => "calibration: mixed",
            Shader::Lod => "calibration: lod",
            Shader::Grad => "calibration: grad",
            Shader::Query => "calibration: query",
            Shader::Branch => "calibration: branch",
        }
    }
}

/// What a calibration pass draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Geometry {
    /// Nothing: the pass clears, resolves and stores its targets only.
    Empty,
    /// One triangle over the viewport: every pixel one fragment, quads full.
    FullScreen,
    /// Square cells of this many pixels a side tiling the viewport, two triangles each.
    Grid(u32),
}

/// One calibration pass: a shader over some geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Kernel {
    /// The fragment shader.
    pub shader: Shader,
    /// What it draws.
    pub geometry: Geometry,
}

impl Kernel {
    /// Its name in reports: the shader's, with the geometry's unless full-screen.
    pub fn name(&self) -> String {
        match self.geometry {
            Geometry::Empty => "empty".into(),
            Geometry::FullScreen => self.shader.name().into(),
            Geometry::Grid(cell) => format!("{} on {cell} px cells", self.shader.name()),
        }
    }

    /// The grid's cells across and down an eye of `width` × `height` pixels (the push
    /// constant `grid.xy`; `[0, 0]` for one triangle over the viewport).
    pub fn cells(&self, width: u32, height: u32) -> [u32; 2] {
        match self.geometry {
            Geometry::Grid(cell) => [width.div_ceil(cell), height.div_ceil(cell)],
            _ => [0, 0],
        }
    }

    /// The vertices of its draw in an eye of `width` × `height` pixels (0: no draw).
    pub fn vertices(&self, width: u32, height: u32) -> u32 {
        match self.geometry {
            Geometry::Empty => 0,
            Geometry::FullScreen => 3,
            Geometry::Grid(_) => {
                let [x, y] = self.cells(width, height);
                6 * x * y
            }
        }
    }
}

/// The small-triangle cells the calibration draws (pixels a side; triangles of half that
/// squared): the ocean's far band draws triangles of a pixel or less, its near water hundreds
/// of pixels.
pub const GRID_CELLS: [u32; 6] = [32, 16, 8, 4, 2, 1];

/// The shaders drawn on every grid: the base one (set-up, rasterization and writes of small
/// triangles) and a heavy one (how much more shading small triangles cost per fragment: the
/// lanes their partly covered quads or blocks waste): samples at a level of detail of each
/// lane's own, the work every device measured takes longest over (a GPU's arithmetic can hide
/// behind its rasterizer).
pub const GRID_SHADERS: [Shader; 2] = [Shader::Base, Shader::Lod];

/// Every pass of a calibration, in order: the empty pass, each shader over the viewport, then
/// the grid shaders on grids of small triangles, largest cells first.
pub fn all() -> Vec<Kernel> {
    let mut out = vec![Kernel {
        shader: Shader::Base,
        geometry: Geometry::Empty,
    }];
    out.extend(Shader::ALL.iter().map(|&shader| Kernel {
        shader,
        geometry: Geometry::FullScreen,
    }));
    for cell in GRID_CELLS {
        out.extend(GRID_SHADERS.iter().map(|&shader| Kernel {
            shader,
            geometry: Geometry::Grid(cell),
        }));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_cover_the_eye_and_names_differ() {
        let k = Kernel {
            shader: Shader::Base,
            geometry: Geometry::Grid(4),
        };
        assert_eq!(k.cells(1440, 1586), [360, 397]);
        assert_eq!(k.vertices(1440, 1586), 6 * 360 * 397);
        let names: std::collections::HashSet<String> = all().iter().map(Kernel::name).collect();
        assert_eq!(names.len(), all().len());
    }
}
