#version 450
// Solid things in the sea's pass: the floating bodies and the deck (`render::ocean::solids`).
// Unit meshes with flat normals, instanced with a model matrix and a colour; one draw per mesh.
#ifdef MULTIVIEW
#extension GL_EXT_multiview : require
#endif
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

// The pipelines share one push-constant block (`render::pipeline::Push`); solids read `eye`.
layout(push_constant) uniform Push {
    uint eye;
    uint mode;
    uint inner_count;
    uint grid_v;
} pc;

// Unit mesh: position in [-0.5, 0.5]^3 and its face normal.
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
// `render::ocean::SolidInstance`: model matrix (columns) and colour (rgb; a: 0 plain, 1 held,
// 2 deck planks).
layout(location = 2) in vec4 i_model0;
layout(location = 3) in vec4 i_model1;
layout(location = 4) in vec4 i_model2;
layout(location = 5) in vec4 i_model3;
layout(location = 6) in vec4 i_colour;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
layout(location = 2) flat out vec4 v_colour;
layout(location = 3) flat out vec3 v_eye;

void main() {
#ifdef MULTIVIEW
    uint eye = gl_ViewIndex;
#else
    uint eye = pc.eye;
#endif
    mat4 model = mat4(i_model0, i_model1, i_model2, i_model3);
    vec4 world = model * vec4(a_pos, 1.0);
    // Normals under a non-uniform scale: the inverse transpose.
    v_normal = transpose(inverse(mat3(model))) * a_normal;
    v_world = world.xyz;
    v_colour = i_colour;
    v_eye = g.eye_pos[eye].xyz;
    gl_Position = g.view_proj[eye] * world;
}
