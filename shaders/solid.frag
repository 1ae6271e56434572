#version 450
// Solid things lit by the sea's sun and sky (linear HDR, exposed and tonemapped like the
// water): diffuse sun (no shadows), the sky's light from the hemisphere the face looks at, the
// sea's light on faces looking down, the daylight fading under the water, and the same fog as
// the water (from the air) or the water between (from under it).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "water.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) flat in vec4 v_colour;
layout(location = 3) flat in vec3 v_eye;
layout(location = 0) out vec4 o_colour;

// Share of the horizontal illuminance the sea sends back up (its albedo, Fresnel and body).
const float SEA_ALBEDO = 0.06;
// A held body glows this much (share of the horizontal illuminance) so the hand knows what it
// has.
const float HELD_GLOW = 0.35;
// Deck planks: width (m) and the dark seam between them (m).
const float PLANK_WIDTH = 0.14;
const float PLANK_SEAM = 0.008;

// Planks along z on the deck's top: each a little lighter or darker, dark seams between.
vec3 planks(vec3 albedo, vec3 p, vec3 n) {
    if (n.y < 0.5) {
        return albedo;
    }
    float u = p.x / PLANK_WIDTH;
    float plank = floor(u);
    float shade = 0.85 + 0.3 * fract(sin(plank * 12.9898) * 43758.5453);
    float edge = min(fract(u), 1.0 - fract(u)) * PLANK_WIDTH;
    // Filtered by the pixel footprint so far seams fade instead of aliasing.
    float w = max(fwidth(p.x), 1e-4);
    float seam = 1.0 - smoothstep(PLANK_SEAM - w, PLANK_SEAM + w, edge);
    return albedo * shade * mix(1.0, 0.35, seam * clamp(PLANK_SEAM / w, 0.0, 1.0));
}

void main() {
    vec3 n = normalize(v_normal);
    vec3 view = v_eye - v_world;
    float dist = length(view);
    vec3 v = view / max(dist, 1e-4);
    if (dot(n, v) < 0.0) {
        n = -n;
    }
    vec3 l = g.sun.xyz;
    // Colour alpha: 0 plain, 1 held (glows), 2 deck planks.
    bool deck = v_colour.a > 1.5;
    vec3 albedo = deck ? planks(v_colour.rgb, v_world, n) : v_colour.rgb;
    // Illuminance on the face (klux): the sun, the sky dome as much of it as the face sees,
    // the sea below for faces turned down.
    vec3 e_h = horizontal_illuminance();
    vec3 e = g.sun_illuminance.rgb * max(dot(n, l), 0.0)
           + g.sky_illuminance.rgb * (0.5 + 0.5 * n.y)
           + SEA_ALBEDO * e_h * (0.5 - 0.5 * n.y);
    e += HELD_GLOW * e_h * (deck ? 0.0 : v_colour.a);
    // Under the water the daylight fades with depth (the mean sea's; the waves' own rise is
    // small beside the fade's metres).
    e *= exp(-DOWNWELLING_ATTENUATION * max(-v_world.y, 0.0));
    vec3 colour = albedo * e / PI;
    // Seen from under the water, the water between (issue 45); from the air, the fog.
    Waterline wl = waterline_at_near_plane(-v, v_eye);
    if (wl.below) {
        colour = through_water(colour, dist, -v, g.underwater.y);
    } else {
        float fog = 1.0 - exp(-dist * g.params.z);
        colour = mix(colour, fog_colour(-v), fog);
    }
    o_colour = vec4(with_meniscus(display(colour), wl), 1.0);
}
