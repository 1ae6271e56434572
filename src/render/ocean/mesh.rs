//! The meshes the pass draws, uploaded once: the LOD's patch grid with its 16 stitch index sets
//! (eq. 65-68), the skirt of every possible ring level (section 5.7), the sky's quad and the
//! solids' unit meshes ([`super::solids`]), in one vertex and one index buffer.

use ash::vk;

use super::solids::{Shape, SolidVertex, UnitMesh};
use crate::lod::{OceanLod, StitchFlags};
use crate::render::context::GpuContext;
use crate::render::error::RenderError;
use crate::render::memory::Buffer;

/// Where each mesh lives in the shared vertex and index buffers.
pub(super) struct MeshLayout {
    /// First index of each stitch configuration's index set.
    pub patch_first_index: [u32; 16],
    /// Index count of each stitch configuration.
    pub patch_index_count: [u32; 16],
    /// Per ring level (from the boundary level): byte offset of the skirt's vertices.
    pub skirt_vertex_offset: Vec<u64>,
    /// Per ring level: first index of the skirt.
    pub skirt_first_index: Vec<u32>,
    /// Per ring level: index count of the skirt.
    pub skirt_index_count: Vec<u32>,
    /// Per ring level: the skirt's inner vertex count (the vertex shader's push constant).
    pub skirt_inner: Vec<u32>,
    /// The lowest ring level a skirt exists for.
    pub boundary_level: u32,
    /// First index of the sky's two triangles.
    pub sky_first_index: u32,
    /// First index and count of the comfort vignette's rings ([`super::vignette`]).
    pub vignette_indices: (u32, u32),
    /// Byte offset of the solids' vertices (`SolidVertex`).
    pub solid_vertex_offset: u64,
    /// Per [`Shape`] (in [`Shape::ALL`] order): first index, index count and vertex offset
    /// (in solid vertices from `solid_vertex_offset`).
    pub solid_draws: [(u32, u32, i32); 3],
}

/// The device-local vertex and index buffers and what is where in them.
pub(super) struct MeshBuffers {
    /// Positions (12-byte vec3), then the solids' vertices (24 bytes each).
    pub vertices: Buffer,
    /// u16 indices.
    pub indices: Buffer,
    /// Offsets and counts.
    pub layout: MeshLayout,
}

impl MeshBuffers {
    /// Builds the meshes of `lod` and uploads them through a staging buffer (waits for the
    /// copy: set-up only). Nothing is left behind when a step fails.
    pub fn new(ctx: &GpuContext, lod: &OceanLod) -> Result<Self, RenderError> {
        let (verts, idx, layout) = gather(lod);
        let vbytes: &[u8] = bytemuck::cast_slice(&verts);
        let ibytes: &[u8] = bytemuck::cast_slice(&idx);
        let dst = vk::BufferUsageFlags::TRANSFER_DST;
        let mut vertices = Buffer::new(
            ctx,
            vbytes.len() as u64,
            vk::BufferUsageFlags::VERTEX_BUFFER | dst,
            false,
        )?;
        let mut indices = match Buffer::new(
            ctx,
            ibytes.len() as u64,
            vk::BufferUsageFlags::INDEX_BUFFER | dst,
            false,
        ) {
            Ok(b) => b,
            Err(e) => {
                vertices.destroy(ctx);
                return Err(e);
            }
        };
        if let Err(e) = upload(ctx, vbytes, ibytes, &vertices, &indices) {
            vertices.destroy(ctx);
            indices.destroy(ctx);
            return Err(e);
        }
        Ok(Self {
            vertices,
            indices,
            layout,
        })
    }

    /// Frees both buffers. The GPU must be done with them.
    pub fn destroy(&mut self, ctx: &GpuContext) {
        self.vertices.destroy(ctx);
        self.indices.destroy(ctx);
    }
}

/// Every mesh's vertices and indices in one list each, and where each one starts.
fn gather(lod: &OceanLod) -> (Vec<[f32; 3]>, Vec<u16>, MeshLayout) {
    let mesh = lod.mesh();
    let st = lod.settings();
    let mut verts: Vec<[f32; 3]> = mesh.positions().to_vec();
    let mut idx: Vec<u16> = Vec::new();
    let mut layout = MeshLayout {
        patch_first_index: [0; 16],
        patch_index_count: [0; 16],
        skirt_vertex_offset: Vec::new(),
        skirt_first_index: Vec::new(),
        skirt_index_count: Vec::new(),
        skirt_inner: Vec::new(),
        boundary_level: st.boundary_level(),
        sky_first_index: 0,
        vignette_indices: (0, 0),
        solid_vertex_offset: 0,
        solid_draws: [(0, 0, 0); 3],
    };
    for k in 0..16u8 {
        let set = mesh.indices(StitchFlags::from_bits(k));
        layout.patch_first_index[k as usize] = idx.len() as u32;
        layout.patch_index_count[k as usize] = set.len() as u32;
        idx.extend_from_slice(set);
    }
    for ring in st.boundary_level()..=st.max_level() {
        let skirt = lod.skirt_for_ring(ring);
        layout.skirt_vertex_offset.push((verts.len() * 12) as u64);
        layout.skirt_first_index.push(idx.len() as u32);
        layout.skirt_index_count.push(skirt.indices().len() as u32);
        layout.skirt_inner.push(skirt.inner_vertex_count());
        verts.extend_from_slice(skirt.positions());
        idx.extend_from_slice(skirt.indices());
    }
    layout.sky_first_index = idx.len() as u32;
    idx.extend_from_slice(&[0, 1, 2, 2, 1, 3]);
    let rings = super::vignette::ring_indices();
    layout.vignette_indices = (idx.len() as u32, rings.len() as u32);
    idx.extend_from_slice(&rings);
    layout.solid_vertex_offset = (verts.len() * 12) as u64;
    let mut solid_vertices = 0;
    for (draw, shape) in layout.solid_draws.iter_mut().zip(Shape::ALL) {
        let mesh = UnitMesh::of(shape);
        *draw = (idx.len() as u32, mesh.indices.len() as u32, solid_vertices);
        solid_vertices += mesh.vertices.len() as i32;
        idx.extend_from_slice(&mesh.indices);
        // A solid vertex is two vec3s: position, normal.
        for v in &mesh.vertices {
            let v: &SolidVertex = v;
            verts.push(v.position);
            verts.push(v.normal);
        }
    }
    if idx.len() % 2 == 1 {
        idx.push(0);
    }
    (verts, idx, layout)
}

/// Copies the bytes into the two device-local buffers through a temporary staging buffer.
fn upload(
    ctx: &GpuContext,
    vbytes: &[u8],
    ibytes: &[u8],
    vertices: &Buffer,
    indices: &Buffer,
) -> Result<(), RenderError> {
    let mut staging = Buffer::new(
        ctx,
        (vbytes.len() + ibytes.len()) as u64,
        vk::BufferUsageFlags::TRANSFER_SRC,
        true,
    )?;
    staging.bytes_mut()[..vbytes.len()].copy_from_slice(vbytes);
    staging.bytes_mut()[vbytes.len()..].copy_from_slice(ibytes);
    let copies = [
        (vertices.raw, 0, vbytes.len()),
        (indices.raw, vbytes.len(), ibytes.len()),
    ];
    let result = crate::render::one_shot(ctx, |cmd| {
        for (dst, src_offset, size) in copies {
            let region = vk::BufferCopy {
                src_offset: src_offset as u64,
                dst_offset: 0,
                size: size as u64,
            };
            // SAFETY: `cmd` is recording; both buffers are alive and the region lies inside
            // both.
            unsafe { ctx.device.cmd_copy_buffer(cmd, staging.raw, dst, &[region]) };
        }
    });
    staging.destroy(ctx);
    result
}
