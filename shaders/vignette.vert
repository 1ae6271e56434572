#version 450
// The comfort vignette (`render::ocean::vignette`): a ring of directions around each eye's
// view axis, drawn last over the frame while the view is moved for the user (swimming,
// gliding, turning smoothly, riding the waves). Its vertices come from `gl_VertexIndex`
// (`ring * SEGMENTS + segment`): ring 0 at the clear field's edge (transparent), ring 1 a
// feather further out (opaque), ring 2 at 85 degrees (beyond every headset's field of view).
// The rings are directions, at infinity in both eyes, so the vignette shows no parallax.
#ifdef MULTIVIEW
#extension GL_EXT_multiview : require
#endif
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(push_constant) uniform Push {
    uint eye;
    uint mode;
    uint inner_count;
    uint grid_v;
} pc;

layout(location = 0) out float v_alpha;

// Mirrored in `render::ocean::vignette`.
const uint SEGMENTS = 48u;
// The clear field's half-angle at the weakest and at full strength (degrees), and the feather.
const float CLEAR_WEAK_DEG = 55.0;
const float CLEAR_FULL_DEG = 30.0;
const float FEATHER_DEG = 12.0;
const float OUTER_DEG = 85.0;

void main() {
#ifdef MULTIVIEW
    uint eye = gl_ViewIndex;
#else
    uint eye = pc.eye;
#endif
    float strength = clamp(g.vignette.x, 0.0, 1.0);
    uint ring = uint(gl_VertexIndex) / SEGMENTS;
    uint segment = uint(gl_VertexIndex) % SEGMENTS;
    float clear = radians(mix(CLEAR_WEAK_DEG, CLEAR_FULL_DEG, strength));
    float theta = ring == 0u ? clear : (ring == 1u ? clear + radians(FEATHER_DEG) : radians(OUTER_DEG));
    vec3 f = g.waterline[eye].xyz;
    vec3 other = abs(f.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 r = normalize(cross(f, other));
    vec3 u = cross(r, f);
    float phi = float(segment) * (6.28318531 / float(SEGMENTS));
    vec3 d = cos(theta) * f + sin(theta) * (cos(phi) * r + sin(phi) * u);
    vec4 clip = g.view_proj[eye] * vec4(d, 0.0);
    // Depth is neither tested nor written; keep it inside the clip volume.
    gl_Position = vec4(clip.xy, 0.5 * clip.w, clip.w);
    // Fades in over the first third of the strength.
    v_alpha = ring == 0u ? 0.0 : min(1.0, 3.0 * strength);
}
