#version 450
// Water shading in linear HDR (kcd/m², the sky's units), exposed and tonemapped here (Khronos
// PBR Neutral) into the sRGB target: normals and foam from the cascades' RGBA8 mip chains
// (eq. 50-53); Schlick Fresnel (IOR 1.33) between the sky reflected from the prefiltered
// environment map (mip by roughness) and the water body lit by the sun and the sky; a GGX sun
// highlight with height-correlated Smith masking-shadowing whose roughness comes from the
// mips' smoothness; foam lit like a diffuse surface; fog to the sky at the horizon.
//
// Specular anti-aliasing (g.specular_aa.y = 1). With no temporal filter in a headset, the far
// sea must not sparkle:
// - where the finest cascade is minified (its texels smaller than a pixel), the pixel is
//   shaded at four sub-pixel positions (a rotated grid) from mips chosen for a third of the
//   pixel's extent, and the colours averaged: supersampling only where shading aliases;
// - the slope variance a shading sample still cannot show widens the GGX lobe: filtered out of
//   the normal maps (Toksvig: an averaged normal is shorter; the variance (1 - |n|)/|n| beyond
//   the level-0, material shortening), below the finest cascade (Bruneton, Neyret & Holzschuch
//   2010: integrated from the spectrum on the CPU), and the normal's change across the
//   footprint (Tokuyoshi & Kaplanyan 2019, clamped).
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
// Size (m) of the foam pattern's cells: whitecap patches and streaks of a few metres.
const float FOAM_CELL = 0.9;

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

// Smooth value noise in [0, 1] over cells of unit size.
float hash(vec2 p) {
    p = fract(p * vec2(0.1031, 0.1030));
    p += dot(p, p.yx + 33.33);
    return fract((p.x + p.y) * p.x);
}
float value_noise(vec2 p) {
    vec2 i = floor(p);
    vec2 f = p - i;
    vec2 u = f * f * (3.0 - 2.0 * f);
    float a = hash(i), b = hash(i + vec2(1.0, 0.0));
    float c = hash(i + vec2(0.0, 1.0)), d = hash(i + vec2(1.0, 1.0));
    return mix(mix(a, b, u.x), mix(c, d, u.x), u.y);
}

// Foam seen at `xz`: coverage c thresholds a two-octave pattern (about a share c of the
// surface turns white: patches, not a grey veil); where the footprint outgrows the pattern's
// cells the pattern would alias, so the coverage itself (its area mean) is shown.
float whitecap_foam(vec2 xz, vec2 dx, vec2 dy) {
    float c = whitecap_coverage(xz, dx, dy);
    vec2 p = xz / FOAM_CELL;
    float n = 0.55 * value_noise(p) + 0.3 * value_noise(p * 2.3 + 17.0)
            + 0.15 * value_noise(p * 5.1 - 9.0);
    // The sum clusters around ½; stretched toward a uniform spread.
    n = clamp(0.5 + 2.2 * (n - 0.5), 0.0, 1.0);
    // About a share c of the surface turns white: the pattern's highest values, so patches
    // grow and merge where the coverage is high and thin to flecks where it is low (the
    // stretched pattern reaches 1 often: none at all where there is no coverage).
    float pattern = smoothstep(1.0 - c - 0.05, 1.0 - c + 0.05, n) * min(8.0 * c, 1.0);
    // Thicker toward a patch's heart, thin and broken at its edges.
    pattern *= 0.7 + 0.3 * value_noise(p * 7.3 + 3.0);
    float footprint = max(length(dx), length(dy)) / FOAM_CELL;
    return clamp(mix(pattern, c, clamp(2.0 * footprint - 0.5, 0.0, 1.0)), 0.0, 1.0);
}

// Adds whitecaps `caps` to a cascade foam coverage (independent coverages).
float with_caps(float foam, float caps) {
    return 1.0 - (1.0 - foam) * (1.0 - caps);
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

// Radiance leaving the water toward the eye along `v`; `unshown`: slope variance the normal
// does not show (specular anti-aliasing), < 0 for the plain shading.
vec3 shade(Water w, vec3 v, float unshown) {
    vec3 n = w.n;
    float ndotv = max(dot(n, v), 1e-3);
    float fresnel = WATER_F0 + (1.0 - WATER_F0) * pow(1.0 - ndotv, 5.0);
    vec3 l = g.sun.xyz;

    // GGX roughness; smoothness 1 is a mirror, clamped so the sun stays a few pixels wide.
    float rough = max(1.0 - w.smoothness, MIN_ROUGHNESS);
    float a2 = rough * rough * rough * rough;
    if (unshown >= 0.0) {
        // The level-0 look, plus the slope variance this sample cannot show.
        a2 = min(g.specular_aa.w + unshown, 1.0);
    }
    // The sky reflected, from the map level prefiltered for this roughness (α² = r⁴), the ray
    // kept above the horizon.
    vec3 r = reflect(-v, n);
    r.y = abs(r.y);
    vec3 reflected = sky_env(r, sqrt(sqrt(a2)));
    vec3 irradiance = horizontal_illuminance();
    vec3 body = WATER_BODY_REFLECTANCE * irradiance / PI;
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

    vec3 foam = FOAM_ALBEDO * irradiance / PI;
    return mix(colour, foam, w.foam * 0.9);
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
    float caps = g.whitecaps[1].w < 0.0 ? 0.0 : whitecap_foam(v_xz, dx, dy);
    w.foam = with_caps(w.foam, caps);
    vec3 dndx = dFdx(w.n);
    vec3 dndy = dFdy(w.n);
    int cascades = int(g.params.x);
    float half_texel = 0.5 / g.params.y;
    vec2 finest_uv = v_xz / g.patch_size[cascades - 1] + half_texel;
    float lod = textureQueryLod(u_normal_foam, finest_uv).x;

    vec3 colour;
    if (g.specular_aa.y < 0.5) {
        colour = shade(w, v, -1.0);
    } else {
        float kernel = min(2.0 * PIXEL_VARIANCE * (dot(dndx, dndx) + dot(dndy, dndy)),
                           MAX_KERNEL_ALPHA2);
        float tail = clamp(lod, 0.0, 1.0) * g.specular_aa.x;
        if (lod > SUPERSAMPLE_FROM_LOD) {
            // Four shading positions, each filtering a third of the pixel's extent (mips
            // log2(3) levels finer), their variance terms scaled to that footprint: the
            // normal's change across it is a ninth of that across the pixel, and the waves
            // below the finest cascade are unresolved once its texels are smaller than it.
            vec2 hx = dx / 3.0;
            vec2 hy = dy / 3.0;
            float sub_tail = clamp(lod - log2(3.0), 0.0, 1.0) * g.specular_aa.x;
            colour = vec3(0.0);
            for (int i = 0; i < 4; ++i) {
                vec2 xz = v_xz + SUBSAMPLES[i].x * dx + SUBSAMPLES[i].y * dy;
                Water s = water_at(xz, hx, hy, false);
                s.foam = with_caps(s.foam, caps);
                colour += shade(s, v, s.filtered + sub_tail + kernel / 9.0);
            }
            colour *= 0.25;
        } else {
            colour = shade(w, v, w.filtered + tail + kernel);
        }
    }

    float fog = 1.0 - exp(-dist / g.params.z);
    colour = mix(colour, fog_colour(-v), fog);
    o_colour = vec4(display(colour), 1.0);
}
