#version 450
// Water shading: normals and foam from the cascades' RGBA8 mip chains (eq. 50-53), Schlick
// Fresnel (IOR 1.33) between the reflected sky and the water body, a GGX sun highlight whose
// roughness comes from the mips' smoothness, persistent foam, and fog to the horizon colour.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(set = 0, binding = 2) uniform sampler2DArray u_normal_foam;

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec2 v_xz;
layout(location = 2) flat in vec3 v_eye;
layout(location = 3) flat in uint v_sky;
layout(location = 0) out vec4 o_colour;

void main() {
    if (v_sky != 0u) {
        vec3 d = normalize(v_world);
        vec3 c = d.y >= 0.0 ? sky(d) : fog_colour(d);
        o_colour = vec4(g.params.w > 0.5 ? vec3(1.0, 0.0, 1.0) : c, 1.0);
        return;
    }
    vec3 view = v_eye - v_world;
    float dist = length(view);
    vec3 v = view / max(dist, 1e-4);

    // Sum the cascades' slopes (n.xz / n.y), combine foam as independent coverage, keep the
    // roughest smoothness.
    vec2 slope = vec2(0.0);
    float clear = 1.0;
    float smoothness = 1.0;
    int cascades = int(g.params.x);
    float half_texel = 0.5 / g.params.y;
    for (int c = 0; c < cascades; ++c) {
        vec4 t = texture(u_normal_foam, vec3(v_xz / g.patch_size[c] + half_texel, float(c)));
        vec2 nxz = t.rg * 2.0 - 1.0;
        float ny = sqrt(max(1.0 - dot(nxz, nxz), 0.05));
        slope += nxz / ny;
        clear *= 1.0 - t.b;
        smoothness = min(smoothness, t.a);
    }
    vec3 n = normalize(vec3(slope.x, 1.0, slope.y));
    float foam = 1.0 - clear;

    float ndotv = max(dot(n, v), 1e-3);
    const float f0 = 0.02; // ((1 - 1.33) / (1 + 1.33))^2
    float fresnel = f0 + (1.0 - f0) * pow(1.0 - ndotv, 5.0);
    vec3 r = reflect(-v, n);
    r.y = abs(r.y);
    vec3 reflected = sky(r);
    vec3 l = g.sun.xyz;
    vec3 body = vec3(0.004, 0.025, 0.045) + vec3(0.0, 0.06, 0.07) * max(l.y, 0.0);
    vec3 colour = mix(body, reflected, fresnel);

    // GGX highlight; smoothness 1 is a mirror, clamped so the sun stays a few pixels wide.
    float rough = max(1.0 - smoothness, 0.06);
    float a2 = rough * rough * rough * rough;
    vec3 hv = normalize(l + v);
    float ndoth = max(dot(n, hv), 0.0);
    float ndotl = max(dot(n, l), 0.0);
    float dd = ndoth * ndoth * (a2 - 1.0) + 1.0;
    float ggx = a2 / (PI * dd * dd);
    colour += vec3(1.0, 0.9, 0.75) * g.sun.w * ggx * fresnel * ndotl * 0.25;

    colour = mix(colour, vec3(0.85, 0.9, 0.92) * (0.4 + 0.6 * max(l.y, 0.0)), foam * 0.9);

    float fog = 1.0 - exp(-dist / g.params.z);
    colour = mix(colour, fog_colour(-v), fog);
    o_colour = vec4(colour, 1.0);
}
