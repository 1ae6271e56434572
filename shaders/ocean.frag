#version 450
// Water shading in linear HDR (kcd/m², the sky's units), exposed and tonemapped here (Khronos
// PBR Neutral) into the sRGB target (issue 14), after the Atlas talk's water model:
// - normals from the cascades' RGBA8 mip chains (eq. 50-53; the pixel's own samples
//   anisotropic where the device has it, `render::ocean::anisotropy`) and, near the viewer, the
//   waves shorter than the finest cascade (`sim::detail`, where a pixel still sees them);
// - the sky reflected from the prefiltered environment map (mip by roughness), weighted by
//   Fresnel averaged over the slopes the normal does not show (Bruneton et al. 2010), the rest
//   going to the water body: back-scattered light (greener at grazing views), bubbles below
//   the foam (parallax), and the sun through thin crests, tinted by water's absorption;
// - the sun's glint after Cox & Munk: a Student-t lobe with a Gaussian's core and Smith's
//   masking-shadowing of Gaussian slopes (`sun_highlight`);
// - foam: the whitecap coverage thresholds a tiling two-scale pattern (a share c of the
//   surface turns white), both carried by the surface's drift (`sim::drift`), lit on the
//   wave's normal, rougher water around it; with anti-aliasing the pattern is read at two
//   taps over the pixel's footprint (`filtered_foam`); fog to the sky at the horizon.
//
// Specular anti-aliasing (g.specular_aa.y = 1). With no temporal filter in a headset, the far
// sea must not sparkle. The distribution is filtered, not sampled (issue 43): the lobe widens
// by the slope variance the pixel cannot show (below), over normal maps read anisotropically
// along the footprint on a GPU; on the headsets that alone holds the aliasing gate. Where a
// device has headroom (the desktop; g.filtering.y = 1) the highlight is also supersampled:
// - where the finest cascade is minified (its texels under half a pixel), the terms that
//   alias, those of the surface (the Fresnel weight of the reflected sky and the sun's narrow
//   highlight, both changing fast with a normal that changes within the pixel), are averaged
//   over the pixel's own sample and three sub-pixel positions, each from mips chosen for a
//   third of the pixel's extent. Only the cascades whose texels are under a pixel there are
//   sampled again; the others, the sky's radiance (prefiltered, smooth) and the dim rest (the
//   water body, foam, fog) come from the pixel's own sample. Issue 28: supersampling the whole
//   water model at four positions cost 1.6x the pass on lavapipe; this costs 1.3-1.4x for the same
//   far-band error facing the sun (docs/notes/gpu-cost-model.md has the levers tried);
// - the slope variance a shading sample still cannot show widens the GGX lobe: filtered out of
//   the normal maps (Toksvig: an averaged normal is shorter; the variance (1 - |n|)/|n| beyond
//   the level-0, material shortening), of the waves no cascade shows (Bruneton, Neyret &
//   Holzschuch 2010; on the CPU, at least what Cox & Munk's observed slopes leave of the
//   cascades'), and the normal's change across the footprint (Tokuyoshi & Kaplanyan 2019,
//   clamped).
//
// Precision (issue 28): bounded, smooth values are `mediump` (the cascades' and foam's texels,
// slopes, coverage, the water body, the Fresnel weight, the tone map), run at twice the FP32
// rate on Adreno; coordinates, the shading normal, the sun's highlight and its GGX α² stay in
// full precision (docs/notes/gpu-cost-model.md says why each).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// The counting variant's tally (its layout below, `COUNT_*`), declared before the shared code
// so that the tone curve's knee can be tallied in it.
#ifdef COUNT_PATHS
layout(set = 0, binding = 6, std430) buffer PathTally {
    uint tally[46];
} t_paths;
// Tally of fragments through the tone curve's knee (`COUNT_KNEE`).
#define KNEE_TAKEN() atomicAdd(t_paths.tally[43], 1u)
#endif
// A cost variant takes the knee only where it is asked to (`COST_KNEE`, the knee's own
// variant) or takes every branch (the union).
#ifdef COST_PATH
#if defined(COST_KNEE) || COST_PATH == 7
#define TAKES_KNEE(cond) true
#else
#define TAKES_KNEE(cond) false
#endif
#endif
#include "common.glsl"
#include "water.glsl"

// The choices a pixel makes, and the probes of `vr-ocean gpu-budget` (`render::budget`).
// Normally every choice is the pixel's own. A cost variant (COST_PATH defined, built by
// `shaders/shader_table.rs` and optimized) takes fixed ones with COST_CASCADES cascades, so that
// after inlining and unrolling its one straight-line function is that path's work: 1 the sky,
// 2 water shaded once, 3 water with its highlight supersampled (COST_RESAMPLED of the finest
// cascades sampled again), 4 water shaded once with foam, 5 water without anti-aliasing, 6
// water shaded once with the detail near the viewer; 7 the union of every path (each branch
// taken, as a device that runs both sides of every branch whatever its lanes chose pays for
// each fragment: `render::budget::calibration`; the side of the surface is a choice a whole
// view makes but at the waterline, so the union leaves the view from below out); 8 the
// surface seen from below, 9 the water where a ray from below meets nothing (issue 45). The counting variant (COUNT_PATHS) tallies
// in a storage buffer which paths the pixels took.
// Every loop is unrolled ([[unroll]], constant bounds: cascade loops run to MAX_CASCADES and
// skip the cascades beyond the count), so per-cascade arrays stay in registers; a loop bounded
// by the uniform count left lavapipe indexing them in memory (3x the pass's time).
#define UNROLL [[unroll]]
#ifdef COST_PATH
// The cost variants unroll the sub-samples too (one straight-line function to count); the
// pipeline's shader keeps them a loop: one copy of each sample's code, where lavapipe's
// inlined texture code would otherwise grow fourfold.
#define UNROLL_SUBSAMPLES [[unroll]]
#define CASCADE_COUNT COST_CASCADES
#define TAKES_SKY(cond) (COST_PATH == 1 || COST_PATH == 7)
#define TAKES_PLAIN(cond) (COST_PATH == 5 || COST_PATH == 7)
#define TAKES_SUPERSAMPLING(cond) (COST_PATH == 3 || COST_PATH == 7)
#define TAKES_FOAM(cond) (COST_PATH == 4 || COST_PATH == 7)
#define TAKES_DETAIL(cond) (COST_PATH == 6 || COST_PATH == 7)
#define RESAMPLES(c, cond) ((c) >= COST_CASCADES - COST_RESAMPLED)
#if COST_PATH == 7
// The union takes the other side of each choice too, and keeps what every side made (a
// maximum: a few operations), so that the optimizer leaves each side's work to count.
#define OTHERWISE if (true)
#define SKY_DONE
#define SET_COLOUR(x) colour = max(colour, (x))
#define SET_OUTPUT(x) o_colour = max(o_colour, (x))
#endif
// A cost variant reads the trilinear sampler: an anisotropic sample's extra taps are texture
// work the counting variant tallies (COUNT_ANISO_TAPS), not instructions.
#define READS_ANISOTROPIC(cond) false
#else
#define UNROLL_SUBSAMPLES [[dont_unroll]]
#define CASCADE_COUNT int(g.params.x)
#define TAKES_SKY(cond) (cond)
#define TAKES_PLAIN(cond) (cond)
#define TAKES_SUPERSAMPLING(cond) (cond)
#define TAKES_FOAM(cond) (cond)
#define TAKES_DETAIL(cond) (cond)
#define RESAMPLES(c, cond) (cond)
#define READS_ANISOTROPIC(cond) (cond)
#endif
#ifndef OTHERWISE
#define OTHERWISE else
#define SKY_DONE return;
#define SET_COLOUR(x) colour = (x)
#define SET_OUTPUT(x) o_colour = (x)
#endif
#ifdef COUNT_PATHS
// The counting variant reads the trilinear sampler too and tallies the taps the anisotropic
// one would take (Mesa 22.3's lavapipe made the pass ~50x slower at 4 taps, BENCHMARKS.md).
#undef READS_ANISOTROPIC
#define READS_ANISOTROPIC(cond) false
#endif
// Under fixed foveation (a fragment density map, `FRAGMENT_DENSITY`), a peripheral fragment
// covers several pixels (gl_FragSizeEXT) and is shown at that coarser rate anyway: its surface
// is shaded once, with the variance of its whole footprint, never supersampled.
#ifdef FRAGMENT_DENSITY
#extension GL_EXT_fragment_invocation_density : require
#define FULL_DENSITY (gl_FragSizeEXT.x * gl_FragSizeEXT.y == 1)
#else
#define FULL_DENSITY true
#endif
// Tallies of `render::budget::PathCounts`, in this order.
const uint COUNT_SKY = 0u;
const uint COUNT_SINGLE = 1u;
const uint COUNT_SUPERSAMPLED = 2u;
const uint COUNT_FOAM = 3u;
const uint COUNT_PLAIN = 4u;
const uint COUNT_RESAMPLES = 5u;
const uint COUNT_DETAIL = 6u;
const uint COUNT_ANISO_TAPS = 7u;
// Then the fragments by their triangle's area on the screen: bin 0 under half a pixel, bin k
// in [2^(k-2), 2^(k-1)) pixels, the last from 8192 pixels up, the sky's (`PathCounts::by_area`);
// then the lanes they would be shaded on in blocks of 2, 4 and 8 pixels a side, in quarters
// (`PathCounts::quarter_lanes`).
const uint COUNT_AREAS = 8u;
const int AREA_BINS = 16;
const uint COUNT_LANES = 24u;
const int LANE_TALLIES = 3;
// Then by the triangle's thickness (twice its area over its longest edge): bin 0 under a
// quarter pixel, bin k in [2^(k-3), 2^(k-2)) pixels (`PathCounts::by_thickness`).
const uint COUNT_THICKNESS = 27u;
// Then the fragments whose colour went through the tone curve's knee (`KNEE_TAKEN`).
const uint COUNT_KNEE = 43u;
// Then the fragments drawn from under the water (issue 45): the surface seen from below, and
// the water itself where the ray meets nothing (the sky's fragments).
const uint COUNT_BELOW = 44u;
const uint COUNT_DEPTHS = 45u;
#ifdef COUNT_PATHS
// A shader with side effects would otherwise run before the depth test: keep it where the
// real one runs (it writes no depth and discards nothing, so early tests change no image).
layout(early_fragment_tests) in;
#define COUNT(what, n) atomicAdd(t_paths.tally[what], n)
#else
#define COUNT(what, n)
#endif

layout(set = 0, binding = 2) uniform mediump sampler2DArray u_normal_foam;
// The same through the anisotropic sampler (`render::ocean::anisotropy`; the trilinear one
// where the device has none), read for the pixel's own samples when g.filtering.x > 1.
layout(set = 0, binding = 8) uniform mediump sampler2DArray u_normal_aniso;
// Whitecap coverage of the whole surface, one layer per level, toroidal (`sim::whitecaps`).
layout(set = 0, binding = 3) uniform mediump sampler2DArray u_whitecaps;

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec2 v_xz;
layout(location = 2) flat in vec3 v_eye;
layout(location = 3) flat in uint v_sky;
// The mesh's cell (m), read by the counting variant only (declared by all, so that the vertex
// shader's output always has a reader).
layout(location = 4) flat in float v_cell;
layout(location = 5) in mediump vec3 v_fog;
layout(location = 0) out vec4 o_colour;

// Smallest highlight roughness (`render::ocean::pass::MIN_ROUGHNESS`).
const float MIN_ROUGHNESS = 0.06;
// ...and seen at grazing angles, whose light crossed only the thin upper layer and the sides
// of the waves (less of the red and the green absorbed).
const vec3 WATER_BODY_GRAZING = vec3(0.004, 0.022, 0.022);
// Light through a crest: the path (m) it crosses, the share of the sun's light the crest
// sends on toward the eye (forward scattering), and the colour of sea water's scattering
// (∝ λ^-2 at 650, 550 and 450 nm, between pure water's λ^-4.3 and particles' λ^-1).
const float CREST_PATH = 1.5;
// Light scattered out of a lifted crest toward the eye from any direction (issue 29): the
// water near a crest is thin sideways, so light entering its lit faces leaves again after a
// short path, little absorbed: an irradiance reflectance of the order of the deep water's
// own (1-3 % in the green-blue: the scattering coefficient of clear ocean water, 0.01-0.05/m,
// over a ~1 m crest, Morel 1974), tinted by the absorption of that path, added on a crest in
// proportion to its lift squared (zero below the mean sea).
const vec3 CREST_SCATTER = vec3(0.003, 0.022, 0.026);
const float CREST_TRANSMITTANCE = 1.0;
// Diffuse albedo of foam (fresh foam is 0.5-0.8 over the visible).
const vec3 FOAM_ALBEDO = vec3(0.75, 0.78, 0.8);
// Screen-space filter: variance of the pixel footprint and the largest added alpha^2
// (Tokuyoshi & Kaplanyan 2019), for the supersampled path's own sample...
const float PIXEL_VARIANCE = 0.25;
// ...and for a pixel shaded once, whose normal maps' samples (anisotropic on a GPU) already
// average its footprint: the change of that average between pixels is mostly variance their
// length has shown (Toksvig). A quarter of the kernel measured least far-band error against
// the supersampled reference (issue 43, `tests/render_aliasing.rs`, Mesa 25 lavapipe with 4
// taps: facing the sun 0.591x no-AA at 0.25, 0.561 at 0.125, 0.558 at 0.0625, 0.570 at 0;
// 0.68 at 0.5).
const float FILTERED_PIXEL_VARIANCE = 0.0625;
const float MAX_KERNEL_ALPHA2 = 0.18;
// Sub-pixel positions (in pixels) of the supersampled surface besides the pixel's own sample at
// its centre: a triangle around it.
const int SUBSAMPLE_COUNT = 3;
const vec2 SUBSAMPLES[SUBSAMPLE_COUNT] =
    vec2[SUBSAMPLE_COUNT](vec2(0.0, -0.35), vec2(0.3, 0.175), vec2(-0.3, 0.175));
// Mip level of the finest cascade above which a pixel's surface is supersampled.
const float SUPERSAMPLE_FROM_LOD = 1.0;
// Mip level from which a cascade is sampled again at the sub-pixel positions (its texels under
// a pixel: below that its normal changes smoothly across the pixel, and the pixel's own sample
// stands for it).
const float RESAMPLE_FROM_LOD = 0.0;
// The most cascades (`render::ocean::MAX_CASCADES`).
const int MAX_CASCADES = 4;

// Texels per side of a whitecap level (`sim::whitecaps::WHITECAP_TEXELS`).
const float WHITECAP_TEXELS = 256.0;

// The foam pattern (`render::ocean::foam_pattern`): uniform over [0, 1] at every mip, drawn at
// two scales (m per tile): the large one shapes the patches, the small one, turned, breaks
// their edges. The weights of the two in the sum the coverage thresholds.
// One layer (the renderer's image views are arrays).
layout(set = 0, binding = 5) uniform mediump sampler2DArray u_foam_pattern;
const float FOAM_TILE_LARGE = 6.0;
const float FOAM_TILE_SMALL = 2.1;
const float FOAM_WEIGHT_LARGE = 0.65;
const mat2 FOAM_TURN = mat2(0.8, 0.6, -0.6, 0.8);
// Half-width of the threshold's soft edge (pattern units): feathered edges and thin foam, 46 %
// of visibly foamed pixels partial at 20 m/s (0.03 gave hard chips: 15 %; issue 29,
// `tests/render_foam.rs`).
const float FOAM_EDGE = 0.14;
// Mip level of the large tile's pattern at which its cells (~23 texels) shrink to a pixel:
// from there the drawn foam fades to the coverage itself (the area's share).
const float FOAM_FADE_FROM_LOD = 3.0;
const float FOAM_FADE_TO_LOD = 4.5;
// Sub-surface bubbles left by breaking: seen at this depth (m) through the surface (parallax),
// over a wider area than the foam, returning this share of the light that reaches them (a
// few times the water's own: a pale turquoise under the foam, not a second foam).
const float BUBBLE_DEPTH = 0.35;
const float BUBBLE_TILE = 4.3;
const float BUBBLE_SPREAD = 2.0;
const float BUBBLE_REFLECTANCE = 0.06;
// GGX α² the whitecap coverage adds to the water around the foam (broken, rough water).
const float FOAM_ROUGHNESS_A2 = 0.25;

// The whitecap coverage at `xz`, a rest position less the drift (`g.foam_drift`): the fine
// level inside its window, fading to the coarse level toward its edge, and beyond both to the
// coarse level's mean. Sampled with the pixel's footprint (`dx`, `dy`), so the mips give the
// area's coverage far away.
mediump float whitecap_coverage(vec2 xz, vec2 dx, vec2 dy) {
    mediump float cover = g.whitecaps[1].w;
    UNROLL for (int l = 1; l >= 0; --l) {
        vec4 level = g.whitecaps[l];
        float inv_side = g.derived[l];
        vec2 uv = xz * inv_side + 0.5 / WHITECAP_TEXELS;
        mediump float c =
            textureGrad(u_whitecaps, vec3(uv, float(l)), dx * inv_side, dy * inv_side).r;
        mediump vec2 d = abs(xz - level.xy) * (2.0 * inv_side);
        cover = mix(cover, c, 1.0 - smoothstep(0.8, 0.95, max(d.x, d.y)));
    }
    return cover;
}

// The value t a share `c` of n = a·u₁ + b·u₂ exceeds, u₁, u₂ uniform on [0, 1] and
// independent, a = FOAM_WEIGHT_LARGE ≥ b: the inverse of the sum's (trapezoidal) distribution,
// so thresholding the two-scale pattern at t whitens a share c of the surface.
mediump float share_threshold(mediump float c) {
    const float a = FOAM_WEIGHT_LARGE;
    const float b = 1.0 - FOAM_WEIGHT_LARGE;
    const float tail = b / (2.0 * a);
    if (c < tail) {
        return 1.0 - sqrt(2.0 * a * b * c);
    }
    if (c > 1.0 - tail) {
        return sqrt(2.0 * a * b * (1.0 - c));
    }
    return a * (1.0 - c) + 0.5 * b;
}

// The foam drawn at `xz` for coverage `c`: the two-scale pattern above share_threshold(c), so
// rising coverage eats into the pattern (flecks, then a web, then a sheet with holes); where
// the footprint (`dx`, `dy`) outgrows the pattern's cells, the coverage itself.
mediump float drawn_foam(vec2 xz, vec2 dx, vec2 dy, mediump float c) {
    // Both scales in the wind's frame, squeezed along it (`g.foam_streak`): in a strong wind
    // the cells are drawn out into streaks (Beaufort 7-9: "foam blown in streaks along the
    // direction of the wind").
    vec2 along = g.foam_streak.xy;
    mat2 streak = mat2(g.foam_streak.z, 0.0, 0.0, 1.0)
        * mat2(along.x, -along.y, along.y, along.x);
    vec2 w = streak * xz;
    vec2 wdx = streak * dx;
    vec2 wdy = streak * dy;
    vec2 large = w / FOAM_TILE_LARGE;
    vec2 small = FOAM_TURN * w / FOAM_TILE_SMALL + 0.37;
    mediump float u1 = textureGrad(u_foam_pattern, vec3(large, 0.0), wdx / FOAM_TILE_LARGE,
                                   wdy / FOAM_TILE_LARGE).r;
    mediump float u2 = textureGrad(u_foam_pattern, vec3(small, 0.0),
                                   FOAM_TURN * wdx / FOAM_TILE_SMALL,
                                   FOAM_TURN * wdy / FOAM_TILE_SMALL).r;
    mediump float n = FOAM_WEIGHT_LARGE * u1 + (1.0 - FOAM_WEIGHT_LARGE) * u2;
    mediump float t = share_threshold(clamp(c, 0.0, 1.0));
    mediump float sharp = smoothstep(t - FOAM_EDGE, t + FOAM_EDGE, n) * smoothstep(0.0, 0.005, c);
    float texels = max(length(wdx), length(wdy)) * (256.0 / FOAM_TILE_LARGE);
    mediump float far = smoothstep(FOAM_FADE_FROM_LOD, FOAM_FADE_TO_LOD,
                                   log2(max(texels, 1e-6)));
    return mix(sharp, c, far);
}

// The foam over a pixel of footprint (`dx`, `dy`) with anti-aliasing (issue 43): the mean of
// two taps of `drawn_foam`, one on each half of the footprint's long axis, each read over half
// the footprint in both directions. A threshold of a blurred pattern is not the share of the
// pattern above it: read over a far pixel's whole footprint (along the view, at grazing, tens
// of the pattern's texels) the pattern's mip is a grey the threshold keeps or drops whole, so
// far foam came out as smooth coverage or blotches where the pixel holds flecks. Two sharper
// reads average toward the share: the far band's error facing away from the sun (flecks on
// breaking crests, the 3x3 reference's) 0.857 -> 0.68 of no-AA's on the headsets' shading
// (`tests/render/aliasing.rs`); one read with the same finer mip measured 0.81.
mediump float filtered_foam(vec2 xz, vec2 dx, vec2 dy, mediump float c) {
    bool x_long = dot(dx, dx) > dot(dy, dy);
    vec2 half_long = 0.5 * (x_long ? dx : dy);
    vec2 half_short = 0.5 * (x_long ? dy : dx);
    return 0.5 * (drawn_foam(xz - 0.5 * half_long, half_long, half_short, c)
                  + drawn_foam(xz + 0.5 * half_long, half_long, half_short, c));
}

// Detail near the viewer (issue 29, item 2): the waves shorter than the finest cascade
// (`sim::detail`: 12.6 cm down to the 1.7 cm gravity-capillary minimum, unit slope variance,
// in the foam pattern's G and B), scaled to the sea's unresolved slope deviation (`g.detail.y`).
// Two layers of the tile, the second turned and 2^0.25 finer, drift at about the band's phase
// speeds (0.23-0.3 m/s), one along the wind and one across it, so the ripples change as they
// cross instead of sliding as one picture.
const float DETAIL_SCALE_2 = 1.1892071;
const mat2 DETAIL_TURN = mat2(-0.5, 0.8660254, -0.8660254, -0.5);
const float DETAIL_SPEED_1 = 0.25;
const float DETAIL_SPEED_2 = 0.3;
// The band spans log2(12.6 / 1.7) = 2.9 octaves of equal slope variance, the shortest wave 4.4
// of the tile's texels and the longest 32: at the tile's mip level L the waves longer than
// 2^(L+1) texels remain, a share (5 − (L + 1)) / 2.9 of the variance; none from level 4.
const float DETAIL_GONE_LOD = 4.0;
const float DETAIL_OCTAVES = 2.86;

// The detail's slope (n.xz / n.y, as a cascade's) at world `xz`, footprint (`dx`, `dy`).
mediump vec2 detail_slope(vec2 xz, vec2 dx, vec2 dy) {
    float t = g.lod_viewer.w;
    vec2 along = g.foam_streak.xy;
    vec2 across = vec2(-along.y, along.x);
    float inv_tile = g.detail.x;
    vec2 uv1 = xz * inv_tile - along * (DETAIL_SPEED_1 * t * inv_tile);
    mat2 m2 = DETAIL_TURN * DETAIL_SCALE_2;
    vec2 uv2 = m2 * (xz * inv_tile) - across * (DETAIL_SPEED_2 * t * inv_tile);
    mediump vec2 s1 = textureGrad(u_foam_pattern, vec3(uv1, 0.0), dx * inv_tile,
                                  dy * inv_tile).gb;
    mediump vec2 s2 = textureGrad(u_foam_pattern, vec3(uv2, 0.0), m2 * dx * inv_tile,
                                  m2 * dy * inv_tile).gb;
    // Codes to slopes: `g.detail.y` per unit (the code range times the sea's deviation);
    // the second layer's slope back to the world's frame (its chain rule: transpose(m2)), the
    // two weighted to keep the variance: 1 + 2^0.5 = 2.41.
    mediump vec2 slope = (s1 * 2.0 - 1.0) + transpose(m2) * (s2 * 2.0 - 1.0);
    // −∇h, as the cascades store it.
    return slope * (-g.detail.y * 0.6435943);
}

// Bubbles under the surface at `xz` seen along unit `v` through normal `n`: the pattern on a
// plane BUBBLE_DEPTH below, reached along the refracted ray (it slides against the foam as the
// head moves), thresholded by the wider bubble coverage. The share of that plane lit.
mediump float bubbles_under(vec2 xz, mediump vec3 v, mediump vec3 n, vec2 dx, vec2 dy,
                            mediump float c) {
    mediump vec3 t = refract(-v, n, 1.0 / 1.33);
    vec2 under = xz + t.xz / max(-t.y, 0.25) * BUBBLE_DEPTH;
    mediump float u = textureGrad(u_foam_pattern, vec3(under / BUBBLE_TILE + 0.61, 0.0),
                                  dx / BUBBLE_TILE, dy / BUBBLE_TILE).r;
    mediump float share = min(BUBBLE_SPREAD * c, 1.0);
    return smoothstep(1.0 - share - 0.1, 1.0 - share + 0.1, u) * smoothstep(0.0, 0.005, c);
}

// The slope variance (1 − |n|)/|n| of an averaged normal (Toksvig) whose length smoothness `s`
// encodes (eq. 53 inverted): u²·p(u), u = 1 − s, a fit within 0.6 % of the exact form
// (`sim::pack::TOKSVIG_FIT`), which would cost a square root and a division per texel.
mediump float toksvig_variance(mediump float s) {
    mediump float u = 1.0 - s;
    mediump float p = 0.29176 + u * (-0.03476 + u * (0.30023 + u * (-0.36776 + u * 0.30845)));
    return u * u * p;
}

#ifdef COUNT_PATHS
// The taps an anisotropic sample of cascade `c` takes over the footprint (`dx`, `dy`, m) (the
// Vulkan specification's model: the longer derivative over the shorter, in texels, rounded up,
// at most g.filtering.x; one where the texture is magnified), for the GPU budget.
uint anisotropic_taps(vec2 dx, vec2 dy, int c) {
    float texels = g.params.y * g.inv_patch_size[c];
    float a = length(dx) * texels;
    float b = length(dy) * texels;
    float major = max(a, b);
    float minor = max(min(a, b), 1.0);
    return major <= 1.0 ? 1u : uint(min(ceil(major / minor), g.filtering.x));
}
#endif

// One cascade's normal-map texel decoded: its slope (n.xz / n.y), foam (eq. 51), smoothness
// (eq. 53) and the slope variance its filtering hid (Toksvig, beyond the level-0 material's).
struct CascadeSample {
    mediump vec2 slope;
    mediump float foam;
    mediump float smoothness;
    mediump float filtered;
};

CascadeSample decode_cascade(mediump vec4 t) {
    CascadeSample s;
    mediump vec2 nxz = t.rg * 2.0 - 1.0;
    // n.xz / n.y, n.y = sqrt(1 - |n.xz|²) (floored).
    s.slope = nxz * inversesqrt(max(1.0 - dot(nxz, nxz), 0.05));
    s.foam = t.b;
    s.smoothness = t.a;
    s.filtered = max(toksvig_variance(t.a) - g.specular_aa.z, 0.0);
    return s;
}

// The water at one shading position.
struct Water {
    vec3 n;                    // shading normal
    mediump float foam;        // foam coverage
    mediump float smoothness;  // roughest cascade's smoothness
    mediump float filtered;    // slope variance filtered out of the normal maps (Toksvig)
};

// The pixel's own sample of every cascade (the hardware's derivatives pick the mips), kept per
// cascade for the supersampled highlight, which replaces only the minified ones.
struct PixelCascades {
    CascadeSample c[MAX_CASCADES];
    // The interaction layer's slope and the detail's (n.xz / n.y, as a cascade's: −∇h) at the
    // pixel.
    mediump vec2 layer_slope;
};

// Sums the cascades' slopes, combines foam as independent coverage, keeps the roughest
// smoothness.
Water water_of(PixelCascades p, int cascades) {
    Water w;
    mediump vec2 slope = p.layer_slope;
    mediump float clear = 1.0;
    w.smoothness = 1.0;
    w.filtered = 0.0;
    UNROLL for (int c = 0; c < MAX_CASCADES; ++c) {
        if (c < cascades) {
            slope += p.c[c].slope;
            clear *= 1.0 - p.c[c].foam;
            w.smoothness = min(w.smoothness, p.c[c].smoothness);
            w.filtered += p.c[c].filtered;
        }
    }
    // The normal in full precision: the sun's highlight is narrower than half precision's steps
    // near 1 (n·h).
    highp vec3 up = vec3(slope.x, 1.0, slope.y);
    w.n = normalize(up);
    w.foam = 1.0 - clear;
    return w;
}

// The foam at one pixel, computed once and shared by its shading samples: the whitecap
// coverage (the area's share foamed), the share of the pixel drawn white, and the share of
// the bubble plane below that is lit.
struct Foam {
    mediump float coverage;
    mediump float drawn;
    mediump float bubbles;
    mediump vec3 light;  // the foam's radiance where drawn (`foam_light`)
};

// A shading sample's lobe: α², the slope variance the normal does not show (full precision:
// the sun's highlight), α and 1/α (one reciprocal square root), and √α, the GGX roughness the
// sky map's levels are prefiltered for; shared by the sky's lookup, the mean Fresnel and the
// highlight.
struct Lobe {
    float a2;
    float alpha;
    float inv_alpha;
    mediump float rough;
};

Lobe lobe_of(float a2) {
    Lobe l;
    l.a2 = a2;
    l.inv_alpha = inversesqrt(a2);
    l.alpha = a2 * l.inv_alpha;
    l.rough = sqrt(l.alpha);
    return l;
}

// Reflectance of water averaged over the slopes the normal does not show, a Gaussian of
// standard deviation σ_v along the view (Bruneton, Neyret & Holzschuch 2010, their fit): at
// grazing views the slopes turn facets toward the eye, so a rough sea reflects less of the sky
// than Schlick's flat-surface value. σ_v² = α²/2 for the isotropic lobe of GGX α² `a2`, so
// σ_v = α/√2 and σ_v^1.5 = 2^-0.75 α √α; exp(−2.69 σ_v) on σ_v ∈ [0, 1/√2] as a cubic (within
// 2 % of it, in an exponent): one division and the power's two operations are all it takes of
// the special-function unit.
mediump float mean_fresnel(mediump float ndotv, Lobe l) {
    mediump float sigma_v = 0.70710678 * l.alpha;
    mediump float e = 0.99651359 + sigma_v * (-2.58551814 + sigma_v * (2.88795488
        + sigma_v * -1.31754012));
    mediump float f = pow(1.0 - ndotv, 5.0 * e)
        / (1.0 + 22.7 * 0.59460356 * l.alpha * l.rough);
    return WATER_F0 + (1.0 - WATER_F0) * f;
}

// GGX α² at a shading sample of smoothness `smoothness`; `unshown`: slope variance the normal
// does not show (specular anti-aliasing: the unresolved waves' and what filtering hid), < 0 for
// the plain shading (which still counts `tail`, the unresolved waves' not drawn as detail).
// Broken water around foam of coverage `coverage` is rougher.
float sample_a2(float smoothness, float unshown, float coverage, float tail) {
    // Smoothness 1 is a mirror, clamped so the sun stays a few pixels wide. The slopes no
    // cascade shows (the observed total's remainder) roughen it in every path: they are the
    // sea's, not a filter's.
    float rough = max(1.0 - smoothness, MIN_ROUGHNESS);
    float a2 = rough * rough * rough * rough + tail;
    if (unshown >= 0.0) {
        // The level-0 look, plus the slope variance this sample cannot show.
        a2 = min(g.specular_aa.w + unshown, 1.0);
    }
    return min(a2 + FOAM_ROUGHNESS_A2 * coverage, 1.0);
}

// What the sun's highlight needs of the view alone, the same for every normal of a pixel:
// the view, the half vector and Schlick's Fresnel at it.
struct SunView {
    vec3 v;
    vec3 hv;
    float fresnel;
};

SunView sun_view(vec3 v) {
    SunView s;
    s.v = v;
    s.hv = normalize(g.sun.xyz + v);
    float x = 1.0 - max(dot(v, s.hv), 0.0);
    float x2 = x * x;
    s.fresnel = WATER_F0 + (1.0 - WATER_F0) * x2 * x2 * x;
    return s;
}

// The sun's highlight on normal `n` for lobe `l`, per unit of the sun's illuminance: Cox &
// Munk's (1954) glint, D F G2 / (4 n·v), with Schlick F at the half vector.
// - D: the slopes a Student-t, p(s) ∝ (1 + s²/(3α²))^−4 (peak 1/(π α²), a Gaussian's of
//   variance α²): GGX is the family's m = 2 member (infinite variance, its tails brighten a
//   sea far from the sun's path), a Gaussian (Cox & Munk's measured sea) its limit; m = 4
//   keeps a Gaussian's core at one multiply more than GGX and leaves tails between the two,
//   which the specular AA's error against the supersampled reference needs (the Gaussian
//   limit aliased more: 0.601x no-AA facing the sun against 0.573, desktop shading).
// - G2: Smith's height-correlated masking-shadowing of Gaussian slopes, 1 / (1 + Λv + Λl),
//   Λ(a) ≈ (1 − a √π / 3)³ / (2 √π a) for a = cot θ / α (the expansion's first terms,
//   1 / (2√π a) − 1/2 + ..., tapered to zero where the exact Λ nearly is: within 0.006 of it
//   for every a), one division for the whole; cos θ stands for cot θ, as it is at grazing
//   angles, where Λ matters. GGX's Smith term (Hammon's form, before) masked a
//   grazing view and a low sun nearly twice as much (Λ 3.1 against 1.5 at 1.5°): the glitter
//   column under a 1.5° sun was half of Cox & Munk's and darker than the sky beside the sun
//   (issue 43).
float sun_highlight(vec3 n, SunView s, Lobe l) {
    // n·v and n·l; the sun below the facet's horizon gives a = 0 and no glint.
    vec2 c = vec2(max(dot(n, s.v), 1e-3), max(dot(n, g.sun.xyz), 0.0));
    vec2 a = c * l.inv_alpha;
    vec2 t = max(1.0 - 0.59081795 * a, 0.0);
    vec2 t3 = t * t * t;
    float aa = a.x * a.y;
    // D = 3 / (π 3α² cos⁴θh) · x⁻⁴, x = 1 + tan²θh / (3α²) = dd / (3α² cos²θh) with
    // dd = cos²θh (3α² − 1) + 1 (GGX's, at 3α²): D = 3 (3α²)³ cos⁴θh / (π dd⁴).
    float ndoth = max(dot(n, s.hv), 0.0);
    float c2 = ndoth * ndoth;
    float k = 3.0 * l.a2;
    float dd = c2 * (k - 1.0) + 1.0;
    float dd2 = dd * dd;
    // G2 / (4 n·v) = a_v a_l / (4 n·v (a_v a_l + (t_v³ a_l + t_l³ a_v) / (2√π))).
    return s.fresnel * (3.0 / (4.0 * PI)) * (k * k * k) * (c2 * c2) * aa
        / (dd2 * dd2 * c.x * (aa + 0.28209479 * (t3.x * a.y + t3.y * a.x)));
}

// The light of the water body toward the eye along `v` at height `height` (m above the mean
// sea), normal `n`: light scattered back up by the water (greener at grazing views, which see
// the light that crossed the thin upper layer), the bubbles below the foam, and the sun through
// thin crests between the eye and the sun (strongest high on a wave whose back faces the sun),
// each tinted by the absorption along its path. Dim and smooth: shaded once per pixel.
mediump vec3 water_body(vec3 n_full, Foam f, vec3 v_full, float height) {
    // Half precision throughout: dim, smooth light.
    mediump vec3 n = n_full;
    mediump vec3 v = v_full;
    mediump float ndotv = max(dot(n, v), 1e-3);
    mediump vec3 l = g.sun.xyz;
    mediump vec3 diffuse = g.diffuse.rgb;
    mediump vec3 sun = g.sun_illuminance.rgb;
    mediump float grazing = (1.0 - ndotv) * (1.0 - ndotv);
    const vec3 bubbles = BUBBLE_REFLECTANCE * exp(-PURE_WATER_ABSORPTION * 2.0 * BUBBLE_DEPTH);
    mediump vec3 reflectance = mix(WATER_BODY_REFLECTANCE, WATER_BODY_GRAZING, grazing)
        + f.bubbles * bubbles;
    mediump vec3 body = reflectance * diffuse;
    mediump float crest_height = height * g.derived.w;
    mediump float crest = clamp(crest_height, 0.0, 1.0);
    body += CREST_SCATTER * (crest * crest) * diffuse;
    mediump float behind = max(dot(-v, l), 0.0);
    behind *= behind;
    behind *= behind;
    mediump float back = 0.5 - 0.5 * dot(l, n);
    mediump float back_lit = back * back;
    const vec3 crest_tint = WATER_SCATTER_COLOUR * exp(-PURE_WATER_ABSORPTION * CREST_PATH);
    body += sun * (CREST_TRANSMITTANCE / PI * crest * behind * back_lit) * crest_tint;
    return body;
}

// `surface_light` with the sky's reflected radiance `reflected` given.
vec3 surface_over(vec3 n, mediump vec3 body, mediump vec3 reflected, SunView sv, Lobe l) {
    mediump float fresnel = mean_fresnel(max(dot(n, sv.v), 1e-3), l);
    mediump vec3 over = mix(body, reflected, fresnel);
    return over + g.sun_illuminance.rgb * sun_highlight(n, sv, l);
}

// The water's surface over its `body` light, seen along `v` with normal `n` and lobe `l`:
// the sky reflected (from the map level prefiltered for this roughness, the ray kept above the
// horizon) over the body, weighted by the mean Fresnel; and the sun's highlight. The terms
// that change fast with the normal: supersampled where the cascades are minified.
vec3 surface_light(vec3 n, mediump vec3 body, SunView sv, Lobe l) {
    vec3 r = reflect(-sv.v, n);
    r.y = abs(r.y);
    return surface_over(n, body, sky_env(r, l.rough), sv, l);
}

// Foam: a diffuse white layer over the share of the pixel it covers, lit on its own normal
// `n` (issue 29, item 4; the wave's, at the pixel): the sun by n·l, the sky by the share of the
// dome it faces, (1 + n_y)/2 for a sky of even radiance, so that foam on a face turned to the
// sun is brighter than on its back. Level foam gets what a horizontal white surface does
// (`g.diffuse`), which `g.foam_streak.w` = 0 keeps everywhere (for comparisons).
mediump vec3 foam_light(vec3 n) {
    mediump vec3 sun = g.sun_illuminance.rgb * max(dot(n, g.sun.xyz), 0.0);
    mediump vec3 sky = g.sky_illuminance.rgb * (0.5 + 0.5 * n.y);
    return FOAM_ALBEDO * mix(g.diffuse.rgb, (sun + sky) * (1.0 / PI), g.foam_streak.w);
}

// The foam over the water's `colour` (its light `f.light` made where there is foam).
vec3 with_foam(vec3 colour, Foam f) {
    return mix(colour, f.light, f.drawn);
}

// The surface's light over the pixel's `body` and `reflected` sky, averaged over the pixel's
// `own` and the sub-pixel positions: cascades whose texels are under a pixel (`resample`) are
// sampled again there from the mips of a third of the pixel's footprint (the finest cascade's
// level `sub_lod`; an explicit level costs less than explicit gradients), the others keep the
// pixel's sample `p`. `unshown`: the slope variance every sub-sample adds to its filtered one
// (unresolved waves, the footprint's normal change).
vec3 supersampled_surface(PixelCascades p, int cascades, bool resample[MAX_CASCADES], vec2 dx,
                          vec2 dy, float sub_lod, mediump vec3 body, mediump vec3 reflected,
                          vec3 own, SunView sv, float unshown, mediump float coverage) {
    mediump vec2 pixel_slope = p.layer_slope;
    UNROLL for (int c = 0; c < MAX_CASCADES; ++c) {
        if (c < cascades) {
            pixel_slope += p.c[c].slope;
        }
    }
    float half_texel = g.derived.z;
    vec3 sum = own;
    UNROLL_SUBSAMPLES for (int i = 0; i < SUBSAMPLE_COUNT; ++i) {
        vec2 xz = v_xz + SUBSAMPLES[i].x * dx + SUBSAMPLES[i].y * dy;
        mediump vec2 slope = pixel_slope;
        mediump float smoothness = 1.0;
        mediump float filtered = 0.0;
        UNROLL for (int c = 0; c < MAX_CASCADES; ++c) {
            if (c < cascades) {
                CascadeSample s = p.c[c];
                if (resample[c]) {
                    vec2 uv = xz * g.inv_patch_size[c] + half_texel;
                    mediump vec4 t = textureLod(u_normal_foam, vec3(uv, float(c)),
                                                sub_lod - g.lod_offset[c]);
                    s = decode_cascade(t);
                    slope += s.slope - p.c[c].slope;
                }
                smoothness = min(smoothness, s.smoothness);
                filtered += s.filtered;
            }
        }
        highp vec3 up = vec3(slope.x, 1.0, slope.y);
        vec3 n = normalize(up);
        Lobe l = lobe_of(sample_a2(smoothness, filtered + unshown, coverage, 0.0));
        sum += surface_over(n, body, reflected, sv, l);
    }
    return sum * (1.0 / float(SUBSAMPLE_COUNT + 1));
}

#ifdef COUNT_PATHS
// How big this fragment's triangle is on the screen: the mesh cell's legs and diagonal (rest
// space, m) mapped to the screen by the inverse of the screen derivatives of the rest position.
// Two things small triangles cost a device, tallied for the calibration to price
// (`render::budget::calibration`):
// - its area (pixels): a triangle's set-up is shared by its fragments;
// - the lanes it is shaded on if the device shades in blocks of B x B pixels (B = 2: a GPU's
//   quads; 4: lavapipe's), partly empty along its edges: `render::budget::calibration::
//   triangle_lanes` (the blocks a triangle of area A and bounding box W x H at a random place
//   covers a sample of; there, the formula and its test against sampled triangles). Added per
//   fragment in quarters of a lane.
const float BLOCK_SIDES[LANE_TALLIES] = float[LANE_TALLIES](2.0, 4.0, 8.0);
const float BLOCK_SHRINK[LANE_TALLIES] = float[LANE_TALLIES](0.75, 1.0, 2.0);
void count_size() {
    vec2 dx = dFdx(v_xz);
    vec2 dy = dFdy(v_xz);
    float det = dx.x * dy.y - dy.x * dx.y;
    uint area_bin = uint(AREA_BINS - 1);
    uint thin_bin = uint(AREA_BINS - 1);
    float area = 1e9;
    float widths = 0.0;
    if (v_sky == 0u && v_cell > 0.0 && abs(det) > 1e-30) {
        // Screen pixels per metre of rest space along x and z (the inverse Jacobian).
        vec2 per_x = vec2(dy.y, -dx.y) / det;
        vec2 per_z = vec2(-dy.x, dx.x) / det;
        float h = v_cell;
        area = 0.5 * h * h / abs(det);
        float longest = h * max(max(length(per_x), length(per_z)), length(per_x - per_z));
        // The triangle (0, a, b) of the cell's legs, and its bounding box.
        vec2 a = per_x * h;
        vec2 b = per_z * h;
        vec2 box = max(vec2(0.0), max(a, b)) - min(vec2(0.0), min(a, b));
        widths = box.x + box.y;
        area_bin = uint(clamp(int(floor(log2(max(area, 1e-9)))) + 2, 0, AREA_BINS - 1));
        float thickness = 2.0 * area / max(longest, 1e-30);
        thin_bin = uint(clamp(int(floor(log2(max(thickness, 1e-9)))) + 3, 0, AREA_BINS - 1));
    }
    atomicAdd(t_paths.tally[COUNT_AREAS + area_bin], 1u);
    atomicAdd(t_paths.tally[COUNT_THICKNESS + thin_bin], 1u);
    float fragments = max(1.0, area + 0.35 * widths);
    for (int i = 0; i < LANE_TALLIES; ++i) {
        float b = BLOCK_SIDES[i];
        float g = b - BLOCK_SHRINK[i];
        float lanes = max(b * b, area + g * widths + g * g);
        // A large triangle's fragments: one lane each (its edges are a vanishing share).
        float per_fragment = v_sky != 0u ? 1.0 : min(lanes / fragments, 1024.0);
        atomicAdd(t_paths.tally[COUNT_LANES + uint(i)], uint(4.0 * per_fragment + 0.5));
    }
}
#endif

#include "underwater.glsl"
#ifdef UNDERWATER
// The meniscus over what the pixel shows (the variant drawn from the air and the cost
// variants: none; the latter's underwater paths are 8 and 9).
#define MENISCUS(x) with_meniscus((x), wl)
#else
#define MENISCUS(x) (x)
#endif

void main() {
#ifdef COUNT_PATHS
    count_size();
#endif
#ifdef UNDERWATER
    // The side of the surface the pixel is drawn from (issue 45), decided in uniform control
    // flow with the rest position's derivatives the view from below needs. Only in the
    // variant bound for frames some of which are under the water (`UNDERWATER`): lavapipe runs
    // both sides of a branch behind a uniform, and paid 12-18 % of its pass for this above
    // the water.
    Waterline wl;
    wl.below = false;
    wl.line = 0.0;
    if (g.underwater.x > 0.5) {
        vec3 ray = v_sky != 0u ? normalize(v_world) : normalize(v_world - v_eye);
        wl = ocean_waterline(ray);
        vec2 rest_dx = dFdx(v_xz);
        vec2 rest_dy = dFdy(v_xz);
        if (wl.below) {
            COUNT(v_sky != 0u ? COUNT_DEPTHS : COUNT_BELOW, 1u);
            o_colour = vec4(MENISCUS(display(underwater_colour(ray, rest_dx, rest_dy))), 1.0);
            return;
        }
    }
#elif defined(COST_PATH) && COST_PATH == 8
    // The surface seen from below.
    {
        vec3 ray = normalize(v_world - v_eye);
        o_colour = vec4(display(surface_from_below(ray, distance(v_world, v_eye), dFdx(v_xz),
                                                   dFdy(v_xz))), 1.0);
        return;
    }
#elif defined(COST_PATH) && COST_PATH == 9
    // The water itself, where a ray from under the water meets nothing.
    {
        o_colour = vec4(display(depths_radiance(normalize(v_world), g.underwater.y)), 1.0);
        return;
    }
#endif
    if (TAKES_SKY(v_sky != 0u)) {
        COUNT(COUNT_SKY, 1u);
        vec3 d = normalize(v_world);
#ifndef COST_PATH
        // The tests' paints (never in a user's run, so not in the cost variants: a uniform
        // branch no wave takes).
        if (g.params.w > 1.5) {
            // `render::ocean::TONEMAP_RAMP_TOP` at the right edge.
            o_colour = vec4(tonemap(vec3(0.75 * (v_xz.x + 1.0))), 1.0);
        } else if (g.params.w > 0.5) {
            o_colour = vec4(1.0, 0.0, 1.0, 1.0);
        } else
#endif
        {
            o_colour = vec4(MENISCUS(sky_display(d)), 1.0);
        }
        SKY_DONE
    }
    vec3 view = v_eye - v_world;
    // One reciprocal square root for the view's direction and length.
    float view2 = max(dot(view, view), 1e-8);
    float inv_dist = inversesqrt(view2);
    float dist = view2 * inv_dist;
    vec3 v = view * inv_dist;
    vec2 dx = dFdx(v_xz);
    vec2 dy = dFdy(v_xz);

    // Everything that takes implicit derivatives happens here, in uniform control flow: the
    // pixel's own sample of each cascade (the hardware picks the mips), the normal's change
    // across the pixel, and the finest cascade's mip level.
    int cascades = CASCADE_COUNT;
    float half_texel = g.derived.z;
    PixelCascades p;
    mediump vec4 layer = interaction_at(v_xz);
    p.layer_slope = -layer.yz;
    // The finest cascade's level of detail (unclamped: the sub-samples' levels and the
    // detail's derive from it), as the sampler finds it: log2 of the longer of the footprint's
    // axes in texels (Vulkan's ρ_max), from the derivatives taken above rather than by a query
    // of the texture unit.
    vec2 finest_uv = v_xz * g.inv_patch_size[cascades - 1] + half_texel;
    float lod = textureQueryLod(u_normal_foam, finest_uv).y;
    // Detail where its tile's mips still show some of it; the lobe keeps only what they do not.
    mediump float shown = g.detail.y > 0.0
        ? clamp((DETAIL_GONE_LOD - lod - g.detail.z) * (1.0 / DETAIL_OCTAVES), 0.0, 1.0) : 0.0;
    if (TAKES_DETAIL(shown > 0.0)) {
        COUNT(COUNT_DETAIL, 1u);
        p.layer_slope += detail_slope(v_xz, dx, dy);
    }
    // Anisotropic or trilinear: a uniform choice, so the implicit derivatives stay defined.
    bool anisotropic = READS_ANISOTROPIC(g.filtering.x > 1.0);
    UNROLL for (int c = 0; c < MAX_CASCADES; ++c) {
        if (c < cascades) {
            vec3 at = vec3(v_xz * g.inv_patch_size[c] + half_texel, float(c));
            mediump vec4 texel;
            if (anisotropic) {
                texel = texture(u_normal_aniso, at);
            } else {
                texel = texture(u_normal_foam, at);
            }
#ifdef COUNT_PATHS
            if (g.filtering.x > 1.0) {
                COUNT(COUNT_ANISO_TAPS, anisotropic_taps(dx, dy, c) - 1u);
            }
#endif
            p.c[c] = decode_cascade(texel);
        }
    }
    Water w = water_of(p, cascades);
    // The normal's change across the pixel, in its horizontal components: the vertical one is
    // second order in the slope (|n| = 1: dn_y = −(n_x dn_x + n_z dn_z) / n_y), two
    // derivatives fewer for the texture unit (the sunset gallery view: within 3 codes of 255).
    mediump vec2 dnx = dFdx(w.n.xz);
    mediump vec2 dny = dFdy(w.n.xz);

    // Foam coverage: the whole surface's whitecaps, or each cascade's own foam (eq. 51) when
    // whitecaps are off. Where there is none, the pattern and the bubbles are not looked at
    // (both are zero at zero coverage); explicit gradients keep them valid in this branch.
    Foam f;
    // Foam floats: where the water now at this rest position was when the drift started.
    vec2 floated = v_xz - g.foam_drift.xy;
    f.coverage = g.whitecaps[1].w < 0.0 ? w.foam : whitecap_coverage(floated, dx, dy);
    // The interaction layer's foam (splashes, breaking ripples) as independent coverage.
    f.coverage = 1.0 - (1.0 - f.coverage) * (1.0 - layer.w);
    f.drawn = 0.0;
    f.bubbles = 0.0;
    f.light = vec3(0.0);
    if (TAKES_FOAM(f.coverage > 0.0)) {
        COUNT(COUNT_FOAM, 1u);
        // The plain shading (the supersampled reference's) reads the pattern once. `max`: the
        // cost model's union of paths keeps both sides' work (f.drawn is 0 before).
        if (TAKES_PLAIN(g.specular_aa.y < 0.5)) {
            f.drawn = drawn_foam(floated, dx, dy, f.coverage);
        } OTHERWISE {
            f.drawn = max(f.drawn, filtered_foam(floated, dx, dy, f.coverage));
        }
        f.bubbles = bubbles_under(floated, v, w.n, dx, dy, f.coverage);
        f.light = foam_light(w.n);
    }
    float height = v_world.y;

    vec3 colour = vec3(0.0);
    SunView sv = sun_view(v);
    // The slopes no cascade shows (the observed total's remainder, `sim::spectrum::
    // unresolved_slope_variance`) roughen every sample, near or far, less what the detail draws.
    float tail = g.specular_aa.x * (1.0 - shown);
    mediump vec3 body = water_body(w.n, f, v, height);
    if (TAKES_PLAIN(g.specular_aa.y < 0.5)) {
        COUNT(COUNT_PLAIN, 1u);
        Lobe l = lobe_of(sample_a2(w.smoothness, -1.0, f.coverage, tail));
        SET_COLOUR(surface_light(w.n, body, sv, l));
    } OTHERWISE {
        mediump float change = dot(dnx, dnx) + dot(dny, dny);
        mediump float kernel = min(2.0 * PIXEL_VARIANCE * change, MAX_KERNEL_ALPHA2);
        if (TAKES_SUPERSAMPLING(lod > SUPERSAMPLE_FROM_LOD && FULL_DENSITY && g.filtering.y > 0.5)) {
            // Each sub-sample filters a third of the pixel's extent (mips log2(3) levels
            // finer), its variance terms scaled to that footprint: the normal's change across
            // it is a ninth of that across the pixel. A cascade's mip level is the finest's
            // less log2 of its patch's ratio to the finest patch (`g.lod_offset`).
            bool resample[MAX_CASCADES];
            UNROLL for (int c = 0; c < MAX_CASCADES; ++c) {
                resample[c] = c < cascades
                    && RESAMPLES(c, lod - g.lod_offset[c] > RESAMPLE_FROM_LOD);
                COUNT(COUNT_RESAMPLES, resample[c] ? 1u : 0u);
            }
            COUNT(COUNT_SUPERSAMPLED, 1u);
            // The sky reflected once, along the pixel's normal from the map level of the
            // pixel's whole footprint: smooth, prefiltered light, whose weight (Fresnel) and
            // the sun's highlight are what change within the pixel.
            Lobe l = lobe_of(sample_a2(w.smoothness, w.filtered + tail + kernel, f.coverage, tail));
            vec3 r = reflect(-v, w.n);
            r.y = abs(r.y);
            mediump vec3 reflected = sky_env(r, l.rough);
            vec3 own = surface_over(w.n, body, reflected, sv, l);
            // log2(3): a third of the pixel's extent.
            SET_COLOUR(supersampled_surface(p, cascades, resample, dx, dy, lod - 1.5849625,
                                            body, reflected, own, sv,
                                            tail + kernel * (1.0 / 9.0), f.coverage));
        } OTHERWISE {
            COUNT(COUNT_SINGLE, 1u);
            mediump float filtered_kernel = min(2.0 * FILTERED_PIXEL_VARIANCE * change,
                                                MAX_KERNEL_ALPHA2);
            Lobe l = lobe_of(sample_a2(w.smoothness, w.filtered + tail + filtered_kernel,
                                       f.coverage, tail));
            SET_COLOUR(surface_light(w.n, body, sv, l));
        }
    }
    colour = with_foam(colour, f);

    // Fog to the sky at the horizon, its colour looked up by the vertices.
    mediump float fog = 1.0 - exp(-dist * g.params.z);
    colour = mix(colour, v_fog, fog);
    SET_OUTPUT(vec4(MENISCUS(display(colour)), 1.0));
}
