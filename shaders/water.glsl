// The water's optical constants, shared by the surface seen from above (`ocean.frag`), the
// water seen from inside it (`underwater.glsl`) and the things in it (`solid.frag`), so the
// colours agree on both sides of the surface; the water volume's light; and the waterline's
// test: which side of the displaced surface a pixel's point on the near plane is (issue 45).

// Water's reflectance at normal incidence: ((1 - 1.33) / (1 + 1.33))^2.
const float WATER_F0 = 0.02;
// Water's refractive index over air's.
const float WATER_IOR = 1.33;
// Irradiance reflectance of the water body (the light scattered back up out of deep ocean
// water, per channel): about 1-2 % in the blue-green, almost none in the red.
const vec3 WATER_BODY_REFLECTANCE = vec3(0.002, 0.014, 0.022);
// Absorption coefficients of pure water (1/m) at about 650, 550 and 450 nm (Pope & Fry 1997):
// the tint of light that travelled through the water.
const vec3 PURE_WATER_ABSORPTION = vec3(0.35, 0.057, 0.015);
// The colour of sea water's scattering (∝ λ^-2 at 650, 550 and 450 nm, between pure water's
// λ^-4.3 and particles' λ^-1).
const vec3 WATER_SCATTER_COLOUR = vec3(0.48, 0.67, 1.0);
// Scattering coefficient of clear ocean water (1/m; 0.01-0.05 at 450 nm, Morel 1974), in that
// colour: with the absorption, how fast a ray's light is replaced by the water's own.
const vec3 WATER_SCATTERING = 0.033 * WATER_SCATTER_COLOUR;
const vec3 WATER_ATTENUATION = PURE_WATER_ABSORPTION + WATER_SCATTERING;
// Diffuse attenuation of the daylight going down (1/m): absorption and back-scattering over
// the mean cosine of its path (about 0.8 under a clear sky): the light fades with depth.
const vec3 DOWNWELLING_ATTENUATION = (PURE_WATER_ABSORPTION + 0.2 * WATER_SCATTERING) * 1.25;
// The upwelling radiance just under the surface over what leaves it (the body reflectance's
// radiance above): the surface passes t = 0.98 of it and spreads it by n² (0.98 / 1.77).
const float UNDER_SURFACE_GAIN = 1.81;
// The underwater light field's shape over the radiance looking straight down (1 there): in
// clear ocean water the horizontal radiance is about twice the nadir's and the radiance from
// above outside Snell's window three times (Tyler 1960's measurements, shallow and clear).
const float DEPTHS_LEVEL = 2.2;
const float DEPTHS_UP = 1.2;
// The glow toward the sun's refracted direction (forward scattering): its peak over the
// field's level where the sun is high, and its width (a power of the cosine).
const float SUN_GLOW = 6.0;
const float SUN_GLOW_POWER = 8.0;

// The radiance of the water itself (kcd/m²) seen along unit `d` from `depth` m under the
// surface: the light the water scatters toward the eye where nothing else is in view (the
// depths below, the water's distance sideways), from the same body reflectance the sea shows
// from above, faded with depth, with a glow toward the sun.
mediump vec3 depths_radiance(vec3 d, float depth) {
    mediump vec3 fade = exp(-DOWNWELLING_ATTENUATION * max(depth, 0.0));
    // The sun's direction in the water (Snell), toward where its light comes from.
    vec3 l = g.sun.xyz;
    float horizontal = (1.0 / WATER_IOR) * length(l.xz);
    vec3 toward = vec3(l.x / WATER_IOR, sqrt(max(1.0 - horizontal * horizontal, 0.0)),
                       l.z / WATER_IOR);
    // The sun's share of the daylight (0 when it is down).
    float sun_share = clamp(g.sun_illuminance.g * max(l.y, 0.0)
        / max(PI * g.diffuse.g, 1e-6), 0.0, 1.0);
    float glow = SUN_GLOW * sun_share * pow(max(dot(d, toward), 0.0), SUN_GLOW_POWER);
    float shape = DEPTHS_LEVEL + DEPTHS_UP * d.y + glow;
    return WATER_BODY_REFLECTANCE * UNDER_SURFACE_GAIN * g.diffuse.rgb * fade * shape;
}

// What is seen through `dist` m of water along unit `d` from `depth` m under the surface: the
// light from behind, absorbed and scattered away, and the water's own in its place.
mediump vec3 through_water(vec3 behind, float dist, vec3 d, float depth) {
    mediump vec3 kept = exp(-WATER_ATTENUATION * dist);
    return behind * kept + depths_radiance(d, depth) * (1.0 - kept);
}

// The cascades' displacement (Dx, h, Dz) at rest position `p`, at full resolution (near the
// eye every cascade is drawn unfaded).
layout(set = 0, binding = 1) uniform sampler2DArray u_displacement;
vec3 surface_displacement(vec2 p) {
    vec3 d = vec3(0.0);
    int cascades = int(g.params.x);
    float half_texel = g.derived.z;
    for (int c = 0; c < 4; ++c) {
        if (c < cascades) {
            vec2 uv = p * g.inv_patch_size[c] + half_texel;
            d += textureLod(u_displacement, vec3(uv, float(c)), 0.0).xyz;
        }
    }
    return d;
}

// The displaced surface's height (m) at world `xz`: the water there came from rest position
// p with p + D(p) = xz, found by two fixed-point steps (`sim::query::rest_position`: within
// millimetres where the surface is not folded), plus the interaction layer's rings.
float surface_height_at(vec2 xz) {
    vec2 p = xz;
    for (int i = 0; i < 2; ++i) {
        p = xz - surface_displacement(p).xz;
    }
    return surface_displacement(p).y + interaction_at(p).x;
}

// How far (m) above the surface the point of this pixel's ray `ray` (unit, from the eye at
// `eye`) on its eye's near plane is; negative below. The eye is told by its position (the two
// eyes' `g.eye_pos` differ wherever a stereo view does).
float over_surface(vec3 ray, vec3 eye) {
    uint i = distance(eye, g.eye_pos[0].xyz) <= distance(eye, g.eye_pos[1].xyz) ? 0u : 1u;
    vec4 plane = g.waterline[i];
    vec3 q = eye + ray * (plane.w / max(dot(ray, plane.xyz), 0.1));
    return q.y - surface_height_at(q.xz);
}

// The side of the surface a pixel is drawn from and its meniscus: `below` in the water;
// `line` (0..1) on the waterline.
struct Waterline {
    bool below;
    mediump float line;
};

// The frame's side (`g.underwater.x` 0 or 1) into `w`, no line; false where each pixel decides
// (2): the caller's test then fills `w`.
bool frame_side(out Waterline w) {
    w.below = g.underwater.x > 0.5;
    w.line = 0.0;
    return g.underwater.x < 1.5;
}

// For a solid's pixel along `ray` from `eye`: the side of its point on the near plane (the
// ocean's own pixels follow the mesh instead, `underwater.glsl`). Call in uniform control flow
// (the line's width takes screen derivatives).
Waterline waterline_at_near_plane(vec3 ray, vec3 eye) {
    Waterline w;
    if (!frame_side(w)) {
        float over = over_surface(ray, eye);
        w.below = over < 0.0;
        float width = 1.5 * fwidth(over) + 1e-4;
        w.line = 1.0 - smoothstep(0.0, width, abs(over));
    }
    return w;
}

// How dark the meniscus draws the line at its middle.
const float MENISCUS_DARKENING = 0.55;
vec3 with_meniscus(vec3 shown, Waterline w) {
    return shown * (1.0 - MENISCUS_DARKENING * w.line);
}
