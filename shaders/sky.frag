#version 450
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) in vec3 v_dir;
layout(location = 0) out vec4 o_colour;

void main() {
    vec3 d = normalize(v_dir);
    vec3 c = d.y >= 0.0 ? sky(d) : fog_colour(d);
    if (g.params.w > 0.5) {
        c = vec3(1.0, 0.0, 1.0);
    }
    o_colour = vec4(c, 1.0);
}
