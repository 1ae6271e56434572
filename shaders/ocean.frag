#version 450
// Water shading in linear HDR (kcd/m², the sky's units), exposed and tonemapped here (Khronos
// PBR Neutral) into the sRGB target (issue 14), after the Atlas talk's water model:
// - normals from the cascades' RGBA8 mip chains (eq. 50-53);
// - the sky reflected from the prefiltered environment map (mip by roughness), weighted by
//   Fresnel averaged over the slopes the normal does not show (Bruneton et al. 2010), the rest
//   going to the water body: back-scattered light (greener at grazing views), bubbles below
//   the foam (parallax), and the sun through thin crests, tinted by water's absorption;
// - a GGX sun highlight with height-correlated Smith masking-shadowing;
// - foam: the whitecap coverage thresholds a tiling two-scale pattern (a share c of the
//   surface turns white), rougher water around it; fog to the sky at the horizon.
//
// Specular anti-aliasing (g.specular_aa.y = 1). With no temporal filter in a headset, the far
// sea must not sparkle:
// - where the finest cascade is minified (its texels smaller than a pixel), the pixel is
//   shaded at four sub-pixel positions (a rotated grid) from mips chosen for a third of the
//   pixel's extent, and the colours averaged: supersampling only where shading aliases;
// - the slope variance a shading sample still cannot show widens the GGX lobe: filtered out of
//   the normal maps (Toksvig: an averaged normal is shorter; the variance (1 - |n|)/|n| beyond
//   the level-0, material shortening), of the waves no cascade shows (Bruneton, Neyret &
//   Holzschuch 2010; on the CPU, at least what Cox & Munk's observed slopes leave of the
//   cascades'), and the normal's change across the footprint (Tokuyoshi & Kaplanyan 2019,
//   clamped).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(set = 0, binding = 2) uniform sampler2DArray u_normal_foam;
// Whitecap coverage of the whole surface, one layer per level, toroidal (`sim::whitecaps`).
layout(set = 0, binding = 3) uniform sampler2DArray u_whitecaps;

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec2 v_xz;
layout(location = 2) flat in vec3 v_eye;
layout(location = 3) flat in uint v_sky;
layout(location = 0) out vec4 o_colour;

// Smallest highlight roughness (`render::ocean::pass::MIN_ROUGHNESS`).
const float MIN_ROUGHNESS = 0.06;
// Water's reflectance at normal incidence: ((1 - 1.33) / (1 + 1.33))^2.
const float WATER_F0 = 0.02;
// Irradiance reflectance of the water body (the light scattered back up out of deep ocean
// water, per channel): about 1-2 % in the blue-green, almost none in the red.
const vec3 WATER_BODY_REFLECTANCE = vec3(0.002, 0.014, 0.022);
// ...and seen at grazing angles, whose light crossed only the thin upper layer and the sides
// of the waves (less of the red and the green absorbed).
const vec3 WATER_BODY_GRAZING = vec3(0.004, 0.022, 0.022);
// Absorption coefficients of pure water (1/m) at about 650, 550 and 450 nm (Pope & Fry 1997):
// the tint of light that travelled through the water.
const vec3 PURE_WATER_ABSORPTION = vec3(0.35, 0.057, 0.015);
// Light through a crest: the path (m) it crosses, the share of the sun's light the crest
// sends on toward the eye (forward scattering), and the colour of sea water's scattering
// (∝ λ^-2 at 650, 550 and 450 nm, between pure water's λ^-4.3 and particles' λ^-1).
const float CREST_PATH = 1.5;
const float CREST_TRANSMITTANCE = 1.0;
const vec3 WATER_SCATTER_COLOUR = vec3(0.48, 0.67, 1.0);
// Diffuse albedo of foam (fresh foam is 0.5-0.8 over the visible).
const vec3 FOAM_ALBEDO = vec3(0.75, 0.78, 0.8);
// Screen-space filter: variance of the pixel footprint and the largest added alpha^2
// (Tokuyoshi & Kaplanyan 2019).
const float PIXEL_VARIANCE = 0.25;
const float MAX_KERNEL_ALPHA2 = 0.18;
// Sub-pixel positions of the supersampled shading (rotated grid, in pixels).
const vec2 SUBSAMPLES[4] = vec2[4](
    vec2(-0.125, -0.375), vec2(0.375, -0.125), vec2(0.125, 0.375), vec2(-0.375, 0.125));
// Mip level of the finest cascade above which a pixel is supersampled.
const float SUPERSAMPLE_FROM_LOD = 0.5;

// Texels per side of a whitecap level (`sim::whitecaps::WHITECAP_TEXELS`).
const float WHITECAP_TEXELS = 256.0;

// The foam pattern (`render::ocean::foam_pattern`): uniform over [0, 1] at every mip, drawn at
// two scales (m per tile): the large one shapes the patches, the small one, turned, breaks
// their edges. The weights of the two in the sum the coverage thresholds.
// One layer (the renderer's image views are arrays).
layout(set = 0, binding = 5) uniform sampler2DArray u_foam_pattern;
const float FOAM_TILE_LARGE = 6.0;
const float FOAM_TILE_SMALL = 2.1;
const float FOAM_WEIGHT_LARGE = 0.65;
const mat2 FOAM_TURN = mat2(0.8, 0.6, -0.6, 0.8);
// Half-width of the threshold's soft edge (pattern units): foam edges a few texels wide.
const float FOAM_EDGE = 0.03;
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

// The whitecap coverage at rest position `xz`: the fine level inside its window, fading to
// the coarse level toward its edge, and beyond both to the coarse level's mean. Sampled with
// the pixel's footprint (`dx`, `dy`), so the mips give the area's coverage far away.
float whitecap_coverage(vec2 xz, vec2 dx, vec2 dy) {
    float cover = g.whitecaps[1].w;
    for (int l = 1; l >= 0; --l) {
        vec4 level = g.whitecaps[l];
        float side = level.z * WHITECAP_TEXELS;
        vec2 uv = xz / side + 0.5 / WHITECAP_TEXELS;
        float c = textureGrad(u_whitecaps, vec3(uv, float(l)), dx / side, dy / side).r;
        vec2 d = abs(xz - level.xy) / (0.5 * side);
        cover = mix(cover, c, 1.0 - smoothstep(0.8, 0.95, max(d.x, d.y)));
    }
    return cover;
}

// The value t a share `c` of n = a·u₁ + b·u₂ exceeds, u₁, u₂ uniform on [0, 1] and
// independent, a = FOAM_WEIGHT_LARGE ≥ b: the inverse of the sum's (trapezoidal) distribution,
// so thresholding the two-scale pattern at t whitens a share c of the surface.
float share_threshold(float c) {
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
float drawn_foam(vec2 xz, vec2 dx, vec2 dy, float c) {
    vec2 large = xz / FOAM_TILE_LARGE;
    vec2 small = FOAM_TURN * xz / FOAM_TILE_SMALL + 0.37;
    float u1 = textureGrad(u_foam_pattern, vec3(large, 0.0), dx / FOAM_TILE_LARGE,
                           dy / FOAM_TILE_LARGE).r;
    float u2 = textureGrad(u_foam_pattern, vec3(small, 0.0), FOAM_TURN * dx / FOAM_TILE_SMALL,
                           FOAM_TURN * dy / FOAM_TILE_SMALL).r;
    float n = FOAM_WEIGHT_LARGE * u1 + (1.0 - FOAM_WEIGHT_LARGE) * u2;
    float t = share_threshold(clamp(c, 0.0, 1.0));
    float sharp = smoothstep(t - FOAM_EDGE, t + FOAM_EDGE, n) * smoothstep(0.0, 0.005, c);
    float texels = max(length(dx), length(dy)) * (256.0 / FOAM_TILE_LARGE);
    float far = smoothstep(FOAM_FADE_FROM_LOD, FOAM_FADE_TO_LOD, log2(max(texels, 1e-6)));
    return mix(sharp, c, far);
}

// Bubbles under the surface at `xz` seen along unit `v` through normal `n`: the pattern on a
// plane BUBBLE_DEPTH below, reached along the refracted ray (it slides against the foam as the
// head moves), thresholded by the wider bubble coverage. The share of that plane lit.
float bubbles_under(vec2 xz, vec3 v, vec3 n, vec2 dx, vec2 dy, float c) {
    vec3 t = refract(-v, n, 1.0 / 1.33);
    vec2 under = xz + t.xz / max(-t.y, 0.25) * BUBBLE_DEPTH;
    float u = textureGrad(u_foam_pattern, vec3(under / BUBBLE_TILE + 0.61, 0.0),
                          dx / BUBBLE_TILE, dy / BUBBLE_TILE).r;
    float share = min(BUBBLE_SPREAD * c, 1.0);
    return smoothstep(1.0 - share - 0.1, 1.0 - share + 0.1, u) * smoothstep(0.0, 0.005, c);
}

// The averaged normal's length a smoothness encodes: eq. 53 inverted.
float normal_length(float smoothness) {
    float r = (1.0 - smoothness) * (1.0 - smoothness);
    float t = (-0.85 + sqrt(0.7225 + 0.6 * (1.0 - r))) / 0.3;
    return (clamp(t, 0.0, 1.0) + 2.0) / 3.0;
}

// The water at one shading position.
struct Water {
    vec3 n;            // shading normal
    float foam;        // foam coverage
    float smoothness;  // roughest cascade's smoothness
    float filtered;    // slope variance filtered out of the normal maps (Toksvig)
};

// Sums the cascades' slopes (n.xz / n.y), combines foam as independent coverage, keeps the
// roughest smoothness. `dx`, `dy`: the footprint's extent in world xz (texture gradients);
// `implicit`: take the hardware's own derivatives (the single-sampled path, bit-for-bit the
// shading without anti-aliasing).
Water water_at(vec2 xz, vec2 dx, vec2 dy, bool implicit) {
    Water w;
    vec2 slope = vec2(0.0);
    float clear = 1.0;
    w.smoothness = 1.0;
    w.filtered = 0.0;
    int cascades = int(g.params.x);
    float half_texel = 0.5 / g.params.y;
    for (int c = 0; c < cascades; ++c) {
        vec2 uv = xz / g.patch_size[c] + half_texel;
        vec4 t = implicit
            ? texture(u_normal_foam, vec3(uv, float(c)))
            : textureGrad(u_normal_foam, vec3(uv, float(c)), dx / g.patch_size[c],
                          dy / g.patch_size[c]);
        vec2 nxz = t.rg * 2.0 - 1.0;
        float ny = sqrt(max(1.0 - dot(nxz, nxz), 0.05));
        slope += nxz / ny;
        clear *= 1.0 - t.b;
        w.smoothness = min(w.smoothness, t.a);
        float len = normal_length(t.a);
        w.filtered += max((1.0 - len) / len - g.specular_aa.z, 0.0);
    }
    w.n = normalize(vec3(slope.x, 1.0, slope.y));
    w.foam = 1.0 - clear;
    return w;
}

// The foam at one pixel, computed once and shared by its shading samples: the whitecap
// coverage (the area's share foamed), the share of the pixel drawn white, and the share of
// the bubble plane below that is lit.
struct Foam {
    float coverage;
    float drawn;
    float bubbles;
};

// Reflectance of water averaged over the slopes the normal does not show, a Gaussian of
// standard deviation σ_v along the view (Bruneton, Neyret & Holzschuch 2010, their fit): at
// grazing views the slopes turn facets toward the eye, so a rough sea reflects less of the sky
// than Schlick's flat-surface value. σ_v² = α²/2 for the isotropic lobe of GGX α² `a2`.
float mean_fresnel(float ndotv, float a2) {
    float sigma_v = sqrt(0.5 * a2);
    float f = pow(1.0 - ndotv, 5.0 * exp(-2.69 * sigma_v)) / (1.0 + 22.7 * pow(sigma_v, 1.5));
    return WATER_F0 + (1.0 - WATER_F0) * f;
}

// Radiance leaving the water toward the eye along `v` at height `height` (m above the mean
// sea); `unshown`: slope variance the normal does not show (specular anti-aliasing: the
// unresolved waves' and what filtering hid), < 0 for the plain shading (which still counts
// the unresolved waves').
vec3 shade(Water w, Foam f, vec3 v, float height, float unshown) {
    vec3 n = w.n;
    float ndotv = max(dot(n, v), 1e-3);
    vec3 l = g.sun.xyz;

    // GGX roughness; smoothness 1 is a mirror, clamped so the sun stays a few pixels wide.
    // The slopes no cascade shows (the observed total's remainder) roughen it in every path:
    // they are the sea's, not a filter's.
    float rough = max(1.0 - w.smoothness, MIN_ROUGHNESS);
    float a2 = rough * rough * rough * rough + g.specular_aa.x;
    if (unshown >= 0.0) {
        // The level-0 look, plus the slope variance this sample cannot show.
        a2 = min(g.specular_aa.w + unshown, 1.0);
    }
    // Broken water around the foam is rougher.
    a2 = min(a2 + FOAM_ROUGHNESS_A2 * f.coverage, 1.0);
    float alpha_rough = sqrt(sqrt(a2));
    float fresnel = mean_fresnel(ndotv, a2);
    // The sky reflected, from the map level prefiltered for this roughness, the ray kept
    // above the horizon.
    vec3 r = reflect(-v, n);
    r.y = abs(r.y);
    vec3 reflected = sky_env(r, alpha_rough);

    // The water body: light scattered back up by the water (greener at grazing views, which
    // see the light that crossed the thin upper layer), the bubbles below the foam, and the
    // sun through thin crests between the eye and the sun (strongest high on a wave whose
    // back faces the sun), each tinted by the absorption along its path.
    vec3 irradiance = horizontal_illuminance();
    float grazing = (1.0 - ndotv) * (1.0 - ndotv);
    vec3 body = mix(WATER_BODY_REFLECTANCE, WATER_BODY_GRAZING, grazing) * irradiance / PI;
    vec3 bubble_tint = exp(-PURE_WATER_ABSORPTION * 2.0 * BUBBLE_DEPTH);
    body += BUBBLE_REFLECTANCE * f.bubbles * bubble_tint * irradiance / PI;
    float crest = clamp(height / max(0.5 * g.sun.w, 0.05), 0.0, 1.0);
    float behind = pow(max(dot(-v, l), 0.0), 4.0);
    float back_lit = (0.5 - 0.5 * dot(l, n)) * (0.5 - 0.5 * dot(l, n));
    vec3 crest_tint = WATER_SCATTER_COLOUR * exp(-PURE_WATER_ABSORPTION * CREST_PATH);
    body += g.sun_illuminance.rgb * (CREST_TRANSMITTANCE / PI * crest * behind * back_lit)
            * crest_tint;
    vec3 colour = mix(body, reflected, fresnel);

    // The sun: GGX D, Schlick F at the half vector, height-correlated Smith visibility.
    vec3 hv = normalize(l + v);
    float ndoth = max(dot(n, hv), 0.0);
    float ndotl = max(dot(n, l), 0.0);
    float dd = ndoth * ndoth * (a2 - 1.0) + 1.0;
    float ggx = a2 / (PI * dd * dd);
    float vis = 0.5 / (ndotl * sqrt(ndotv * ndotv * (1.0 - a2) + a2)
                       + ndotv * sqrt(ndotl * ndotl * (1.0 - a2) + a2) + 1e-6);
    float f_sun = WATER_F0 + (1.0 - WATER_F0) * pow(1.0 - max(dot(v, hv), 0.0), 5.0);
    colour += g.sun_illuminance.rgb * (ggx * vis * f_sun * ndotl);

    // Foam: a diffuse white layer over the share of the pixel it covers.
    vec3 foam = FOAM_ALBEDO * irradiance / PI;
    return mix(colour, foam, f.drawn);
}

void main() {
    if (v_sky != 0u) {
        vec3 d = normalize(v_world);
        vec3 c = d.y >= 0.0 ? sky(d) : fog_colour(d);
        if (g.params.w > 1.5) {
            // `render::ocean::TONEMAP_RAMP_TOP` at the right edge.
            o_colour = vec4(tonemap(vec3(0.75 * (v_xz.x + 1.0))), 1.0);
        } else {
            o_colour = vec4(g.params.w > 0.5 ? vec3(1.0, 0.0, 1.0) : display(c), 1.0);
        }
        return;
    }
    vec3 view = v_eye - v_world;
    float dist = length(view);
    vec3 v = view / max(dist, 1e-4);
    vec2 dx = dFdx(v_xz);
    vec2 dy = dFdy(v_xz);

    // Everything that takes implicit derivatives happens here, in uniform control flow.
    Water w = water_at(v_xz, dx, dy, true);
    // Foam coverage: the whole surface's whitecaps, or each cascade's own foam (eq. 51) when
    // whitecaps are off.
    Foam f;
    f.coverage = g.whitecaps[1].w < 0.0 ? w.foam : whitecap_coverage(v_xz, dx, dy);
    f.drawn = drawn_foam(v_xz, dx, dy, f.coverage);
    f.bubbles = bubbles_under(v_xz, v, w.n, dx, dy, f.coverage);
    float height = v_world.y;
    vec3 dndx = dFdx(w.n);
    vec3 dndy = dFdy(w.n);
    int cascades = int(g.params.x);
    float half_texel = 0.5 / g.params.y;
    vec2 finest_uv = v_xz / g.patch_size[cascades - 1] + half_texel;
    float lod = textureQueryLod(u_normal_foam, finest_uv).x;

    vec3 colour;
    if (g.specular_aa.y < 0.5) {
        colour = shade(w, f, v, height, -1.0);
    } else {
        float kernel = min(2.0 * PIXEL_VARIANCE * (dot(dndx, dndx) + dot(dndy, dndy)),
                           MAX_KERNEL_ALPHA2);
        // The slopes no cascade shows (the observed total's remainder, `sim::spectrum::
        // unresolved_slope_variance`) roughen every sample, near or far.
        float tail = g.specular_aa.x;
        if (lod > SUPERSAMPLE_FROM_LOD) {
            // Four shading positions, each filtering a third of the pixel's extent (mips
            // log2(3) levels finer), their variance terms scaled to that footprint: the
            // normal's change across it is a ninth of that across the pixel.
            vec2 hx = dx / 3.0;
            vec2 hy = dy / 3.0;
            colour = vec3(0.0);
            for (int i = 0; i < 4; ++i) {
                vec2 xz = v_xz + SUBSAMPLES[i].x * dx + SUBSAMPLES[i].y * dy;
                Water s = water_at(xz, hx, hy, false);
                colour += shade(s, f, v, height, s.filtered + tail + kernel / 9.0);
            }
            colour *= 0.25;
        } else {
            colour = shade(w, f, v, height, w.filtered + tail + kernel);
        }
    }

    float fog = 1.0 - exp(-dist / g.params.z);
    colour = mix(colour, fog_colour(-v), fog);
    o_colour = vec4(display(colour), 1.0);
}
