#version 450
// Full-screen triangle at the far plane (depth 0 with reversed Z); drawn after the ocean with
// depth test >=, so it only fills pixels the ocean left empty.
#ifdef MULTIVIEW
#extension GL_EXT_multiview : require
#endif
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

#ifndef MULTIVIEW
layout(push_constant) uniform Push { uint eye; } pc;
#endif

layout(location = 0) out vec3 v_dir;

void main() {
#ifdef MULTIVIEW
    uint eye = gl_ViewIndex;
#else
    uint eye = pc.eye;
#endif
    vec2 ndc = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2)) * 2.0 - 1.0;
    vec4 w = g.sky_from_clip[eye] * vec4(ndc, 1.0, 1.0);
    v_dir = w.xyz / w.w;
    gl_Position = vec4(ndc, 0.0, 1.0);
}
