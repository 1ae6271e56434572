#version 450
// The whole pass in one pipeline: the ocean mesh, i.e. quadtree patches (instanced, one draw
// per stitch configuration) and the horizon skirt, geomorphed exactly as `lod::morph` (the
// reference the LOD's watertightness tests run) and displaced by the cascades' RGBA16F
// (Dx, h, Dz, J) textures; and the sky, a full-screen triangle just in front of the far plane
// drawn last, so it fills only pixels no ocean covers. (A separate sky pipeline rendered only
// into the first view with lavapipe's multiview.)
#ifdef MULTIVIEW
#extension GL_EXT_multiview : require
#endif
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
// The cost variant of `vr-ocean gpu-budget` (`render::budget`): a fixed cascade count and the
// cascade loop unrolled, so that the optimized module is one straight-line function.
#ifdef COST_CASCADES
#extension GL_EXT_control_flow_attributes : require
#define UNROLL [[unroll]]
#define CASCADE_COUNT COST_CASCADES
#else
#define UNROLL
#define CASCADE_COUNT int(g.params.x)
#endif

// eye: the eye of this pass (two-pass fallback only); mode: 0 = patch, 1 = skirt, 2 = sky;
// inner_count: skirt vertices on its inner edge; grid_v: V, cells per patch side.
layout(push_constant) uniform Push {
    uint eye;
    uint mode;
    uint inner_count;
    uint grid_v;
} pc;

layout(set = 0, binding = 1) uniform sampler2DArray u_displacement;

// Patch: unit-grid position (u, 0, v) in [-0.5, 0.5]^2 (eq. 67). Skirt: metres from the centre.
layout(location = 0) in vec3 a_pos;
// `lod::PatchInstance`, 40 bytes per instance.
layout(location = 1) in vec2 i_centre;
layout(location = 2) in float i_size;
layout(location = 3) in uint i_level;
layout(location = 4) in vec2 i_morph;
layout(location = 5) in vec2 i_coarse_morph;
// The stitch flags choose the draw's index set; the vertices' positions do not read them (the
// morph chain moves a stitched edge's kept vertices with the coarser neighbour).
layout(location = 6) in uint i_stitch;
layout(location = 7) in float i_vertex_spacing;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec2 v_xz;
layout(location = 2) flat out vec3 v_eye;
// 1 for the sky: v_world is then a view direction.
layout(location = 3) flat out uint v_sky;
// The mesh's cell (m) at this vertex's rest position: the counting pass sizes its triangles on
// the screen with it (`render::budget`; 0 for the sky).
layout(location = 4) flat out float v_cell;
// The fog's colour toward this vertex (`fog_colour`, the sky's horizon at its azimuth): looked
// up once a vertex, not once a fragment (it changes only with azimuth, slowly).
layout(location = 5) out mediump vec3 v_fog;

// Depth of the sky (reversed Z, depth = near / distance): 500 km away, behind the farthest
// skirt vertex (10 S <= 82 km), in front of the cleared far plane so the GREATER test passes.
const float SKY_DEPTH = 1e-7;


// k(d, r) = clamp((d - start) / (end - start), 0, 1); level 0 never morphs (empty range).
float morph_factor(vec2 r, float d) {
    return r.y > r.x ? clamp((d - r.x) / (r.y - r.x), 0.0, 1.0) : 0.0;
}

// Where lattice vertex (i, j) goes at full morph, in spacings (`lod::morph::morph_step`): none
// when both are even; -1 along the odd axis when one is odd; when both are odd, along the
// parent's fan diagonal: (-1, -1) if (i + j) & 3 == 2, else (-1, +1). Two's-complement `&` and
// arithmetic `>>` on int, as in Rust.
// Without branches (selects): -1 along each odd axis gives the first three cases and
// (-1, -1); the fourth's other diagonal is a select.
vec2 morph_step(ivec2 ij) {
    ivec2 odd = ij & 1;
    bool other_diagonal = (odd.x & odd.y) == 1 && ((ij.x + ij.y) & 3) != 2;
    return other_diagonal ? vec2(-1.0, 1.0) : -vec2(odd);
}

// The lattices a vertex's morph walks up at most (`lod::ScreenCollapse::CHAIN_STEPS`).
const int CHAIN_STEPS = 3;

// The morph chain (`lod::morph::chain_offset`): vertex `idx` of the level-`level` lattice
// (spacing `hh`) slides toward the next coarser lattice's vertex by k_0, the larger of the
// CDLOD factor of range `first` and the screen's; that vertex toward the next by k_1
// (`second`'s or the screen's), and on by the screen's alone. The screen's factor of a
// lattice (`lod::ScreenCollapse::factor`) rises from 0 where it is z pixels thick to 1 at
// z / 2, where the next one's starts: with c its thickness in units of z / 2, clamp(2 - c),
// c doubling with each lattice; only lattices of level w and coarser collapse. Every vertex
// two patches (or a patch and the skirt) share walks the same chain from the same lattice
// point at the same distance, so the surface stays watertight at any k.
vec2 morph_chain(ivec2 idx, float hh, int level, float d, vec2 first, vec2 second) {
    // The distance at least 1 mm: under an eye on the water (H = 0) the point below it is
    // thick, not 0 / 0.
    float dd = max(d, 1e-3);
    float c = hh * (g.lod_screen.x + g.lod_screen.y * dd) / (dd * dd);
    float k_first = morph_factor(first, d);
    float k_second = morph_factor(second, d);
    vec2 offset = vec2(0.0);
    UNROLL for (int j = 0; j < CHAIN_STEPS; ++j) {
        float k = float(level - j) >= g.lod_screen.w ? clamp(2.0 - c, 0.0, 1.0) : 0.0;
        k = max(k, j == 0 ? k_first : (j == 1 ? k_second : 0.0));
        vec2 st = morph_step(idx);
        offset += hh * k * st;
        idx = (idx + ivec2(st)) >> 1;
        hh *= 2.0;
        c *= 2.0;
    }
    return offset;
}

vec4 ocean_vertex(uint eye);

void main() {
#ifdef MULTIVIEW
    uint eye = gl_ViewIndex;
#else
    uint eye = pc.eye;
#endif
    v_eye = g.eye_pos[eye].xyz;
    if (pc.mode == 2u) {
        // A quad exactly covering the viewport (vertices 0-3): nothing to clip. (llvmpipe's
        // clipper dropped the view's layer of a clipped full-screen triangle.)
        vec2 ndc = vec2(float(gl_VertexIndex & 1), float((gl_VertexIndex >> 1) & 1)) * 2.0 - 1.0;
        vec4 w = g.sky_from_clip[eye] * vec4(ndc, 1.0, 1.0);
        v_world = w.xyz / w.w;
        // The sky's normalized device coordinates (the tone-map test ramp runs along x).
        v_xz = ndc;
        v_sky = 1u;
        v_cell = 0.0;
        v_fog = vec3(0.0);
        gl_Position = vec4(ndc, SKY_DEPTH, 1.0);
    } else {
        v_sky = 0u;
        gl_Position = ocean_vertex(eye);
    }
}

// Position of a patch or skirt vertex; also writes v_world and v_xz.
vec4 ocean_vertex(uint eye) {
    vec2 p0;
    vec2 p;
    float d;
    if (pc.mode == 0u) {
        float v = float(pc.grid_v);
        p0 = i_centre + i_size * a_pos.xz;
        float h = i_size / v;
        v_cell = h;
        d = distance(vec3(p0.x, 0.0, p0.y), g.lod_viewer.xyz);
        ivec2 ij = ivec2(round((a_pos.xz + 0.5) * v));
        // The first step is the patch's own CDLOD morph, the second its coarser neighbour's
        // (the vertices of a stitched edge, even ones, follow it; elsewhere it is 0); the
        // screen's collapse may take either further.
        p = p0 + morph_chain(ij, h, int(i_level), d, i_morph, i_coarse_morph);
    } else {
        p0 = i_centre + a_pos.xz;
        v_cell = i_vertex_spacing;
        d = distance(vec3(p0.x, 0.0, p0.y), g.lod_viewer.xyz);
        p = p0;
        if (uint(gl_VertexIndex) < pc.inner_count) {
            // The ring patches' stitched outer edge: their chain from its second step.
            float hh = 2.0 * i_vertex_spacing;
            ivec2 ij = ivec2(round(a_pos.xz / hh));
            p += morph_chain(ij, hh, int(i_level) - 1, d, i_coarse_morph, vec2(0.0));
        }
    }
    // Each cascade fades out with distance before its waves alias on the coarser mesh. The
    // fade depends only on the undisplaced lattice point, which both patches sharing a vertex
    // agree on, so it never opens a crack.
    vec3 disp = vec3(0.0);
    int cascades = CASCADE_COUNT;
    float half_texel = g.derived.z;
    UNROLL for (int c = 0; c < cascades; ++c) {
        float fade = 1.0 - smoothstep(g.fade_start[c], g.fade_end[c], d);
        vec2 uv = p * g.inv_patch_size[c] + half_texel;
        disp += fade * textureLod(u_displacement, vec3(uv, float(c)), 0.0).xyz;
    }
    // The interaction layer's waves (rings, wakes), faded from the mesh like a cascade.
    disp.y += (1.0 - smoothstep(g.interaction_fade.x, g.interaction_fade.y, d))
        * interaction_at(p).x;
    vec3 world = vec3(p.x, 0.0, p.y) + disp;
    v_world = world;
    v_xz = p;
    v_fog = fog_colour(world - g.eye_pos[eye].xyz);
    return g.view_proj[eye] * vec4(world, 1.0);
}
