#version 450
// The control panel (`render::panel`): egui's triangles in points, top-left origin.

layout(location = 0) in vec2 pos;
layout(location = 1) in vec2 uv;
// sRGB-encoded, premultiplied (egui's Color32).
layout(location = 2) in vec4 colour;

layout(push_constant) uniform Push {
    // The panel's size in points.
    vec2 size;
    // 1: the target stores linear light (an sRGB image encodes on write); 0: it stores the
    // sRGB-encoded values as they are.
    float linear_out;
} push;

layout(location = 0) out vec2 v_uv;
layout(location = 1) out vec4 v_colour;

void main() {
    v_uv = uv;
    v_colour = colour;
    gl_Position = vec4(2.0 * pos / push.size - 1.0, 0.0, 1.0);
}
