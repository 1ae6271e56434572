// Shared by every shader: the per-frame globals (std140, `render::frame::Globals` on the CPU
// side, keep both in sync) and the procedural sky.

layout(set = 0, binding = 0, std140) uniform Globals {
    // Per eye: projection (reversed-Z, infinite far) × view.
    mat4 view_proj[2];
    // Per eye: inverse of projection × view rotation (no translation): clip → world direction.
    mat4 sky_from_clip[2];
    // Per eye: world position of the eye (xyz).
    vec4 eye_pos[2];
    // xyz: the viewer the LOD measured morph distances from; w: simulation time (s).
    vec4 lod_viewer;
    // xyz: unit direction towards the sun; w: sun intensity.
    vec4 sun;
    // Patch size L (m) of cascades 0..3.
    vec4 patch_size;
    // Distance (m) at which each cascade's displacement starts fading out of the mesh.
    vec4 fade_start;
    // Distance (m) at which it is gone (its waves would alias on the coarser mesh there).
    vec4 fade_end;
    // x: cascade count, y: FFT grid side N, z: fog distance (m), w: 1 = paint the sky magenta
    // (tests: any magenta below the horizon is a crack).
    vec4 params;
    // Specular anti-aliasing. x: slope variance of the waves too short for any cascade;
    // y: 1 = on; z: Toksvig variance of level-0 normals (the material's); w: GGX alpha^2 of
    // level-0 smoothness.
    vec4 specular_aa;
    // Per whitecap level (`sim::whitecaps`): the window's centre x, z (m), the lattice spacing
    // (m) and the level's mean coverage (negative: whitecaps off).
    vec4 whitecaps[2];
} g;

const float PI = 3.14159265;

// Radiance of the sky along unit direction `d` (linear RGB): a zenith-to-horizon gradient, a
// sun glow and disc. Below the horizon it keeps the horizon colour, the colour fog fades to.
vec3 sky(vec3 d) {
    vec3 zenith = vec3(0.10, 0.28, 0.62);
    vec3 horizon = vec3(0.62, 0.74, 0.86);
    float up = clamp(d.y, 0.0, 1.0);
    vec3 c = mix(horizon, zenith, pow(up, 0.45));
    float s = max(dot(d, g.sun.xyz), 0.0);
    c += vec3(1.0, 0.85, 0.6) * (0.25 * pow(s, 8.0) + 0.6 * pow(s, 256.0));
    c += vec3(1.0, 0.95, 0.85) * g.sun.w * smoothstep(0.99985, 0.99995, s);
    return c;
}

// Sky light without the sun's disc and glow: what a diffuse face facing `d` is lit by.
vec3 sky_diffuse(vec3 d) {
    vec3 zenith = vec3(0.10, 0.28, 0.62);
    vec3 horizon = vec3(0.62, 0.74, 0.86);
    return mix(horizon, zenith, pow(clamp(d.y, 0.0, 1.0), 0.45));
}

// The colour distant water fades to along horizontal direction `d`: the sky just above the
// horizon there, so the ocean meets the sky without a seam.
vec3 fog_colour(vec3 d) {
    vec2 h = d.xz;
    float l = length(h);
    return sky(l > 1e-6 ? vec3(h.x / l, 0.0, h.y / l) : vec3(1.0, 0.0, 0.0));
}
