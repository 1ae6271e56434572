// Shared by every shader: the per-frame globals (std140, `render::camera::Globals` on the CPU
// side, keep both in sync), the sky from its environment map, and the tone mapping.

layout(set = 0, binding = 0, std140) uniform Globals {
    // Per eye: projection (reversed-Z, infinite far) × view.
    mat4 view_proj[2];
    // Per eye: inverse of projection × view rotation (no translation): clip → world direction.
    mat4 sky_from_clip[2];
    // Per eye: world position of the eye (xyz).
    vec4 eye_pos[2];
    // xyz: the viewer the LOD measured morph distances from; w: simulation time (s).
    vec4 lod_viewer;
    // xyz: unit direction towards the sun; w: the sea's significant wave height (m).
    vec4 sun;
    // Patch size L (m) of cascades 0..3.
    vec4 patch_size;
    // Distance (m) at which each cascade's displacement starts fading out of the mesh.
    vec4 fade_start;
    // Distance (m) at which it is gone (its waves would alias on the coarser mesh there).
    vec4 fade_end;
    // x: cascade count, y: FFT grid side N, z: 1 / fog distance (1/m), w: 1 = paint the sky magenta
    // (tests: any magenta below the horizon is a crack), 2 = paint it with the tone-map test
    // ramp.
    vec4 params;
    // Specular anti-aliasing. x: slope variance of the waves too short for any cascade;
    // y: 1 = on; z: Toksvig variance of level-0 normals (the material's); w: GGX alpha^2 of
    // level-0 smoothness.
    vec4 specular_aa;
    // Per whitecap level (`sim::whitecaps`): the window's centre x, z (m), the lattice spacing
    // (m) and the level's mean coverage (negative: whitecaps off).
    vec4 whitecaps[2];
    // The sun disc's radiance (rgb, kcd/m²), w: the cosine of its angular radius.
    vec4 sun_radiance;
    // Sun illuminance at normal incidence (rgb, klux), w: exposure (kcd/m² to tonemap input).
    vec4 sun_illuminance;
    // The sky dome's illuminance on a horizontal surface (rgb, klux), w: env-map levels.
    vec4 sky_illuminance;
    // Per-frame constants the shaders would otherwise divide by per pixel (a division costs a
    // reciprocal on the special-function unit): 1 / patch size (1/m) of cascades 0..3...
    vec4 inv_patch_size;
    // ...log2 of each patch's ratio to the finest (mip-level offsets from the finest's)...
    vec4 lod_offset;
    // ...x, y: 1 / each whitecap level's side (1/m); z: half a texel of the cascades (0.5 / N);
    // w: 1 / the crest height light starts to shine through (1/m, from the wave height).
    vec4 derived;
    // rgb: the radiance of a white Lambertian surface facing up, lit by the sun and the sky
    // (horizontal illuminance / π, kcd/m²): the water body's, foam's and bubbles' light scale.
    vec4 diffuse;
    // The interaction layer (`sim::interaction`): world x, z of its cell (0, 0) (m), 1 / its
    // side (1/m), half a cell in texture units (w; negative: no layer).
    vec4 interaction;
    // x, y: the distances (m) where the layer's displacement of the mesh starts and ends fading.
    vec4 interaction_fade;
    // x, y: unit direction (x, z) the wind blows toward; z: 1 / the foam pattern's stretch
    // along it; w: 1 = foam lit on its normal (0: as level foam, for comparisons).
    vec4 foam_streak;
    // Detail slopes (`sim::detail`, the foam pattern's G and B): x: 1 / the tile's side (1/m);
    // y: decoded slope per unit of code (0: off); z: the detail's mip level less the finest
    // cascade's.
    vec4 detail;
    // xy: how far (m) the surface's mean drift has carried the foam (`sim::whitecaps`): the
    // whitecap maps, the foam pattern and the bubbles are drawn at rest position - xy.
    vec4 foam_drift;
    // x: the most taps the normal maps' anisotropic sampler takes now (1: the trilinear
    // sampler is read; `render::ocean::anisotropy`).
    vec4 filtering;
    // rgb: the sun's disc as the display shows it (its radiance exposed and tone-mapped).
    vec4 sun_display;
    // Per eye, for the waterline: the unit direction the eye looks along (xyz) and the near
    // plane's distance (w, m).
    vec4 waterline[2];
    // Under the surface: x the side the view is drawn from (0 above, 1 below, 2 per pixel from
    // its point on the near plane); y how deep (m) the eyes are (negative above the water).
    vec4 underwater;
    // The comfort vignette's strength (x, 0 to 1; `render::ocean::vignette`).
    vec4 vignette;
    // The mesh's collapse by its thickness on the screen (`lod::ScreenCollapse::uniform`): a
    // lattice spacing h at distance d is h (x + y d) / d^2 halves of z pixels thick (z: where
    // a lattice starts collapsing); lattices of level w and coarser collapse.
    vec4 lod_screen;
} g;

// The interaction layer (`render::ocean::interaction`): h (m), ∂h/∂x, ∂h/∂z, foam; clamped,
// zero at its edges.
layout(set = 0, binding = 7) uniform mediump sampler2DArray u_interaction;

// The layer at world `xz`, zero without one.
mediump vec4 interaction_at(vec2 xz) {
    if (g.interaction.w < 0.0) {
        return vec4(0.0);
    }
    vec2 uv = (xz - g.interaction.xy) * g.interaction.z + g.interaction.w;
    return textureLod(u_interaction, vec3(uv, 0.0), 0.0);
}

const float PI = 3.14159265;

// The sky's prefiltered environment map (`render::ocean::sky_map`, Preetham, kcd/m²): u the
// diamond angle of the horizontal direction over 4 (0, ¼, ½, ¾ toward +x, +z, −x, −z; REPEAT),
// v = sqrt(sin(elevation)) (row 0 the horizon, CLAMP), level m prefiltered for GGX roughness
// m / (levels − 1). The sun disc is not in it. No inverse trigonometry (`render::sky::bake`).
layout(set = 0, binding = 4) uniform mediump sampler2DArray u_sky;

// Env-map coordinates of unit direction `d`; below the horizon it reads the horizon.
vec2 sky_uv(vec3 d) {
    float s = abs(d.x) + abs(d.z);
    float t = s > 0.0 ? d.z / s : 0.0;
    float q = d.x >= 0.0 ? (d.z >= 0.0 ? t : 4.0 + t) : 2.0 - t;
    return vec2(q * 0.25, sqrt(clamp(d.y, 0.0, 1.0)));
}

// Sky radiance (linear sRGB, kcd/m²) along unit `d`, prefiltered for GGX roughness `rough`
// (the sky without the sun stays within half precision's range).
mediump vec3 sky_env(vec3 d, float rough) {
    float level = clamp(rough, 0.0, 1.0) * (g.sky_illuminance.w - 1.0);
    return textureLod(u_sky, vec3(sky_uv(d), 0.0), level).rgb;
}

// How much of a pixel along unit `d` the sun's disc covers, its edge a hundredth of its radius
// wide.
float sun_coverage(vec3 d) {
    float c = dot(d, g.sun.xyz);
    float edge = 0.01 * (1.0 - g.sun_radiance.w);
    return smoothstep(g.sun_radiance.w - edge, g.sun_radiance.w + edge, c);
}

// The sun's disc seen along unit `d` (kcd/m²).
vec3 sun_disc(vec3 d) {
    return g.sun_radiance.rgb * sun_coverage(d);
}

// The sky along unit `d` as the display shows it (what `display` gives of the map's level 0 and the sun's disc, or the fog's
// horizon below it): the map's second layer, baked exposed and through the tone curve, with
// the sun's disc (tone-mapped once on the CPU) over it by its coverage. The sun's disc is tens
// of thousands of times the sky's radiance, so where it covers a pixel at all the curve gives
// the disc's own colour.
mediump vec3 sky_display(vec3 d) {
    mediump vec3 shown = textureLod(u_sky, vec3(sky_uv(d), 1.0), 0.0).rgb;
    return d.y >= 0.0 ? mix(shown, g.sun_display.rgb, sun_coverage(d)) : shown;
}


// The radiance distant things fade to along `d`: the sky at the horizon at the same azimuth,
// so the ocean meets the sky without a seam (the map's horizon row: `sky_uv` needs no unit
// vector for that).
mediump vec3 fog_colour(vec3 d) {
    return sky_env(vec3(d.x, 0.0, d.z), 0.0);
}

// Illuminance on a horizontal surface from the sun and the sky (klux).
vec3 horizontal_illuminance() {
    return g.diffuse.rgb * PI;
}

// Khronos PBR Neutral tone mapping: linear in, linear out in [0, 1] (the sRGB target encodes).
// Below 0.76 colours pass unchanged but for a small black offset; above, the peak is
// compressed toward 1 and desaturated so the brightest lights go white, not clipped hues.
// The knee is a branch of its own (about half the curve's instructions): the water shader's
// cost variants fix it (`TAKES_KNEE`, taken only by `COST_KNEE`'s and the union) and its
// counting variant tallies the fragments that take it (`KNEE_TAKEN`), so that the GPU budget
// prices the knee where the light reaches it, not everywhere.
#ifndef TAKES_KNEE
#define TAKES_KNEE(cond) (cond)
#endif
#ifndef KNEE_TAKEN
#define KNEE_TAKEN()
#endif
const float PBR_NEUTRAL_START = 0.8 - 0.04;
const float PBR_NEUTRAL_DESATURATION = 0.15;
mediump vec3 tonemap(mediump vec3 c) {
    mediump float x = min(c.r, min(c.g, c.b));
    mediump float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    c -= offset;
    mediump float peak = max(c.r, max(c.g, c.b));
    if (!TAKES_KNEE(peak >= PBR_NEUTRAL_START)) {
        return c;
    }
    KNEE_TAKEN();
    const float d = 1.0 - PBR_NEUTRAL_START;
    mediump float new_peak = 1.0 - d * d / (peak + d - PBR_NEUTRAL_START);
    c *= new_peak / peak;
    mediump float grey = 1.0 - 1.0 / (PBR_NEUTRAL_DESATURATION * (peak - new_peak) + 1.0);
    return mix(c, vec3(new_peak), grey);
}

// Radiance (kcd/m²) to what the sRGB target stores: exposed, then tonemapped (in half
// precision, the exposed value held under its largest finite value: the sun's disc is
// brighter; either way it maps to white).
const float HALF_MAX = 65000.0;
vec3 display(vec3 radiance) {
    return tonemap(min(max(radiance, vec3(0.0)) * g.sun_illuminance.w, vec3(HALF_MAX)));
}
