//! The ocean pass: its uniforms (eyes, sun, cascades and their fade distances) and its
//! recording: at most 16 instanced patch draws, the skirt, the solids (at most three instanced
//! draws), the sky and the comfort vignette when the view is moved, for both eyes with
//! multiview or for one eye per pass without.
//!
//! One pipeline draws the ocean (push constant `mode`: patches, skirt, sky), another the
//! solids, which share its depth buffer so the water hides their submerged parts. The sky is a
//! viewport-sized quad at depth 1e-7 drawn last under the `GREATER` test, so it fills only
//! pixels no ocean covers and never needs clipping (lavapipe's multiview put clipped
//! primitives of view 1 into layer 0).

use ash::vk;

use super::frame::FrameInput;
use super::mesh::MeshBuffers;
use super::pipelines::{Pipelines, Push};
use super::sky_map::SkyLight;
use super::RendererSettings;
use crate::lod::{LodSettings, OceanLod, ScreenCollapse};
use crate::render::barrier::Access;
use crate::render::camera::Globals;
use crate::render::targets::resolve_eye;
use crate::sim::detail::{DETAIL_TEXELS, DETAIL_TILE_M};
use crate::sim::whitecaps::WHITECAP_TEXELS;
use crate::sim::{pack, OceanConfig};

/// The smallest roughness of the sun's highlight (a mirror-like sea keeps the sun a few pixels
/// wide); mirrored in `shaders/ocean.frag`.
pub const MIN_ROUGHNESS: f32 = 0.06;

/// What the pass's uniforms take from the configuration, fixed at creation. The patch sizes
/// are not: they come with each step's surfaces (the coarsest follows the wind).
#[derive(Clone, Copy, Debug)]
pub(super) struct PassConstants {
    grid: u32,
    cascades: usize,
    lod: LodSettings,
    /// Vertices per patch side (V + 1 in the thesis's terms: the push constant `grid_v`).
    pub vertices_per_side: u32,
}

impl PassConstants {
    /// For `config`'s cascades drawn on the LOD of `lod`.
    pub fn new(config: &OceanConfig, lod: &LodSettings) -> Self {
        Self {
            grid: config.grid.n() as u32,
            cascades: config.patch_sizes.len(),
            lod: *lod,
            vertices_per_side: lod.vertices(),
        }
    }

    /// This frame's uniform block (std140, mirrored in `shaders/common.glsl`).
    pub fn globals(
        &self,
        input: &FrameInput<'_>,
        settings: &RendererSettings,
        light: &SkyLight,
        collapse: &ScreenCollapse,
    ) -> Globals {
        let mut g: Globals = bytemuck::Zeroable::zeroed();
        g.set_eyes(input.eyes);
        let (side, depth) = super::Underwater::of(&input.surfaces.cascades, input.eyes);
        g.underwater = [side.code(), depth, 0.0, 0.0];
        let vignette = if input.vignette.is_finite() {
            input.vignette.clamp(0.0, 1.0)
        } else {
            0.0
        };
        g.vignette = [vignette, 0.0, 0.0, 0.0];
        g.lod_screen = collapse.uniform();
        let viewer = (input.eyes[0].position + input.eyes[1].position) * 0.5;
        g.lod_viewer = viewer.extend(input.surfaces.time() as f32).to_array();
        g.sun = light
            .sun_direction
            .extend(input.surfaces.significant_height)
            .to_array();
        g.sun_radiance = light.sun_radiance.extend(light.sun_cos_radius).to_array();
        g.sun_illuminance = light.sun_illuminance.extend(light.exposure).to_array();
        g.sun_display = super::sky_map::displayed(light.sun_radiance, light.exposure)
            .extend(1.0)
            .to_array();
        g.sky_illuminance = light.sky_illuminance.extend(light.levels as f32).to_array();
        let horizontal =
            light.sun_illuminance * light.sun_direction.y.max(0.0) + light.sky_illuminance;
        g.diffuse = (horizontal / std::f32::consts::PI).extend(0.0).to_array();
        let mut patch_sizes = [1.0; 4];
        let mut fade_patches = [1.0; 4];
        for ((p, f), c) in patch_sizes
            .iter_mut()
            .zip(&mut fade_patches)
            .zip(&input.surfaces.cascades)
        {
            *p = c.patch;
            *f = c.fade_patch;
        }
        let fade = cascade_fades(&self.lod, collapse, &fade_patches[..self.cascades]);
        let finest = patch_sizes[self.cascades.clamp(1, 4) - 1];
        for ((inv, offset), &l) in g
            .inv_patch_size
            .iter_mut()
            .zip(g.lod_offset.iter_mut())
            .zip(&patch_sizes)
        {
            *inv = 1.0 / l;
            *offset = (l / finest).log2();
        }
        g.patch_size = patch_sizes;
        g.fade_start = fade[0];
        g.fade_end = fade[1];
        g.interaction = [0.0, 0.0, 0.0, -1.0];
        if let Some(l) = settings.drawn_layer(input.interaction) {
            let [ox, oz] = l.origin_m();
            let side = l.config().side_m();
            g.interaction = [ox, oz, 1.0 / side, 0.5 / l.config().cells.n() as f32];
            // Faded from the mesh as a cascade of the layer's side would be.
            let [[start, ..], [end, ..]] = cascade_fades(&self.lod, collapse, &[side]);
            g.interaction_fade = [start, end, 0.0, 0.0];
        }
        let (wind, toward) = input.surfaces.wind;
        let stretch = if settings.foam_streaks {
            super::foam_streak_stretch(wind)
        } else {
            1.0
        };
        let foam_lit = if settings.foam_lit { 1.0 } else { 0.0 };
        g.foam_streak = [toward[0], toward[1], 1.0 / stretch, foam_lit];
        let drift = input.surfaces.whitecaps.drift;
        g.foam_drift = [drift[0], drift[1], 0.0, 0.0];
        g.params = [
            self.cascades as f32,
            self.grid as f32,
            1.0 / settings.fog_distance,
            if settings.sky_marker {
                1.0
            } else if settings.tonemap_ramp {
                2.0
            } else {
                0.0
            },
        ];
        let len0 = input.surfaces.base_normal_length;
        let rough0 = (1.0 - pack::smoothness(len0)).max(MIN_ROUGHNESS);
        g.specular_aa = [
            input.surfaces.unresolved_slope_variance,
            if settings.specular_aa { 1.0 } else { 0.0 },
            (1.0 - len0) / len0,
            rough0.powi(4),
        ];
        // Detail slopes: their deviation is the unresolved one (what the lobe widens with), the
        // code's ±1 spanning ±DETAIL_RANGE unit deviations.
        g.detail = [
            1.0 / DETAIL_TILE_M,
            if settings.detail {
                super::foam_pattern::DETAIL_RANGE * input.surfaces.unresolved_slope_variance.sqrt()
            } else {
                0.0
            },
            ((finest / self.grid as f32) / (DETAIL_TILE_M / DETAIL_TEXELS as f32)).log2(),
            0.0,
        ];
        // Light shines through a crest from half the significant wave height (at least 5 cm).
        g.derived[2] = 0.5 / self.grid as f32;
        g.derived[3] = 1.0 / (0.5 * input.surfaces.significant_height).max(0.05);
        for (l, (w, level)) in g
            .whitecaps
            .iter_mut()
            .zip(&input.surfaces.whitecaps.levels)
            .enumerate()
        {
            g.derived[l] = 1.0 / (level.spacing * WHITECAP_TEXELS as f32);
            // The window holds lattice points origin..origin + T: its centre is half a texel
            // before origin + T/2.
            let half = WHITECAP_TEXELS as f32 / 2.0 - 0.5;
            *w = [
                (level.origin[0] as f32 + half) * level.spacing,
                (level.origin[1] as f32 + half) * level.spacing,
                level.spacing,
                level.mean,
            ];
            if !settings.whitecaps {
                // A negative mean tells the shader to draw no whitecaps.
                w[3] = -1.0;
            }
        }
        g
    }
}

/// Per cascade, the distances (m) where its displacement starts and ends fading from the mesh.
///
/// A level-l patch (vertex spacing s_l/V) is split once the viewer is nearer than K·s_l to its
/// square ([`LodSettings::split_distance`]), so at distance d the mesh spacing is at most about
/// d/(K·V); with a factor 2 for vertices up to a patch diagonal beyond the square, 2d/(K·V).
/// The collapse by the screen can make it coarser sooner ([`ScreenCollapse::spacing_bound`]).
/// A cascade of patch L keeps its displacement while that spacing is under L/8 and is gone
/// where it reaches L/4, beyond which its shorter waves would alias into noise on the coarser
/// mesh (the normals, sampled per pixel with mips, still show them).
fn cascade_fades(
    st: &LodSettings,
    collapse: &ScreenCollapse,
    patch_sizes: &[f32],
) -> [[f32; 4]; 2] {
    let mut out = [[f32::MAX; 4], [f32::MAX; 4]];
    let kv = st.preset().split_scale() * st.vertices() as f32;
    for (c, &l) in patch_sizes.iter().enumerate() {
        let end = (l * kv / 8.0).min(collapse.distance_of_spacing(l / 4.0));
        out[0][c] = 0.5 * end;
        out[1][c] = end;
    }
    out
}

/// Everything one pass's recording reads.
pub(super) struct PassRecorder<'a> {
    pub device: &'a ash::Device,
    /// A command buffer in the recording state.
    pub cmd: vk::CommandBuffer,
    pub pipelines: &'a Pipelines,
    pub mesh: &'a MeshBuffers,
    /// The slot's instance buffer (the LOD's instances, then the skirt's).
    pub instances: vk::Buffer,
    /// The slot's solid instances, grouped by shape.
    pub solids: vk::Buffer,
    /// The slot's descriptor set.
    pub set: vk::DescriptorSet,
    /// Where in the eye image to draw: the whole image, or a centred part of it when the
    /// GPU-time governor lowers the render scale (same projection, fewer pixels).
    pub area: vk::Rect2D,
    pub vertices_per_side: u32,
    /// Some of the frame is drawn from under the water ([`super::Underwater`] not `Above`):
    /// the ocean pipeline with the water's paths from below ([`Pipelines::ocean_under`]).
    pub under: bool,
    /// Draw the comfort vignette last ([`super::vignette`]; its strength is in the globals).
    pub vignette: bool,
    /// Two passes with MSAA: resolve each eye after its pass, from this multisampled image
    /// into layer `eye` of this eye image.
    pub resolve_after: Option<ResolveAfter>,
}

/// The images of a resolve after the pass.
#[derive(Clone, Copy, Debug)]
pub(super) struct ResolveAfter {
    /// The multisampled colour (1 layer), in `TRANSFER_SRC_OPTIMAL` after the pass.
    pub msaa: vk::Image,
    /// The eye image (2 layers).
    pub target: vk::Image,
}

impl PassRecorder<'_> {
    /// Records one render pass into `framebuffer` (both eyes with multiview, else eye `eye`):
    /// the LOD's patch draws, the skirt (instance `skirt_instance`), the solids (per shape:
    /// first instance and count), the sky and, when asked, the comfort vignette. Returns the
    /// draws recorded.
    pub fn record(
        &self,
        framebuffer: vk::Framebuffer,
        eye: u32,
        lod: &OceanLod,
        skirt_instance: u32,
        solids: &[(u32, u32); 3],
    ) -> u32 {
        let (d, cmd, p) = (self.device, self.cmd, self.pipelines);
        let ocean = if self.under { p.ocean_under } else { p.ocean };
        let clear = [
            vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: [0.0, 0.0, 0.0, 1.0],
                },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 0.0,
                    stencil: 0,
                },
            },
        ];
        let area = self.area;
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(p.render_pass)
            .framebuffer(framebuffer)
            .render_area(area)
            .clear_values(&clear);
        let viewport = vk::Viewport {
            x: area.offset.x as f32,
            y: area.offset.y as f32,
            width: area.extent.width as f32,
            height: area.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        let mut push = Push {
            eye,
            mode: 0,
            inner_count: 0,
            grid_v: self.vertices_per_side,
        };
        let layout = &self.mesh.layout;
        let mut draws = 0;
        // SAFETY: `cmd` is recording outside a render pass; the framebuffer, pipeline,
        // buffers and set are alive and match the render pass; every draw's index range lies
        // in the index buffer (`MeshLayout`) and its instances in the slot's buffer.
        unsafe {
            d.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
            d.cmd_set_viewport(cmd, 0, &[viewport]);
            d.cmd_set_scissor(cmd, 0, &[area]);
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, ocean);
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                p.layout,
                0,
                &[self.set],
                &[],
            );
            let vertices = self.mesh.vertices.raw;
            d.cmd_bind_vertex_buffers(cmd, 0, &[vertices, self.instances], &[0, 0]);
            d.cmd_bind_index_buffer(cmd, self.mesh.indices.raw, 0, vk::IndexType::UINT16);
            self.push(&push);
            for draw in lod.draws() {
                let k = draw.stitch.bits() as usize;
                d.cmd_draw_indexed(
                    cmd,
                    layout.patch_index_count[k],
                    draw.instance_count,
                    layout.patch_first_index[k],
                    0,
                    draw.first_instance,
                );
                draws += 1;
            }
            let ring = (lod.tree().ring_level() - layout.boundary_level) as usize;
            push.mode = 1;
            push.inner_count = layout.skirt_inner[ring];
            self.push(&push);
            let offset = layout.skirt_vertex_offset[ring];
            d.cmd_bind_vertex_buffers(cmd, 0, &[vertices], &[offset]);
            d.cmd_draw_indexed(
                cmd,
                layout.skirt_index_count[ring],
                1,
                layout.skirt_first_index[ring],
                0,
                skirt_instance,
            );
            draws += 1;
            if solids.iter().any(|s| s.1 > 0) {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.solids);
                let offset = layout.solid_vertex_offset;
                d.cmd_bind_vertex_buffers(cmd, 0, &[vertices, self.solids], &[offset, 0]);
                for (&(first_instance, count), &(first, indices, vertex_offset)) in
                    solids.iter().zip(&layout.solid_draws)
                {
                    if count > 0 {
                        d.cmd_draw_indexed(
                            cmd,
                            indices,
                            count,
                            first,
                            vertex_offset,
                            first_instance,
                        );
                        draws += 1;
                    }
                }
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, ocean);
            }
            // The sky: mode 2 of the ocean's pipeline, vertices from gl_VertexIndex (indexed
            // with 0, 1, 2: lavapipe's multiview drew a non-indexed draw into the first view
            // only). Its draw reads both vertex bindings, so the ocean's are bound again.
            d.cmd_bind_vertex_buffers(cmd, 0, &[vertices, self.instances], &[0, 0]);
            push.mode = 2;
            self.push(&push);
            d.cmd_draw_indexed(cmd, 6, 1, layout.sky_first_index, 0, 0);
            draws += 1;
            if self.vignette {
                // Vertices from the index alone; the pipeline reads no vertex buffers.
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.vignette);
                let (first, count) = layout.vignette_indices;
                d.cmd_draw_indexed(cmd, count, 1, first, 0, 0);
                draws += 1;
            }
            d.cmd_end_render_pass(cmd);
        }
        if let Some(r) = self.resolve_after {
            // The layer's last reader was a copy or blit of an earlier frame.
            resolve_eye(d, cmd, r.msaa, r.target, eye, area, Access::TransferRead);
        }
        draws
    }

    fn push(&self, push: &Push) {
        // SAFETY: `cmd` is recording and the range matches the layout's push constant range.
        unsafe {
            self.device.cmd_push_constants(
                self.cmd,
                self.pipelines.layout,
                vk::ShaderStageFlags::VERTEX,
                0,
                bytemuck::bytes_of(push),
            )
        };
    }
}
