#version 450
// The control panel: vertex colour times texture (the font atlas and egui's images), both
// premultiplied and sRGB-encoded; blended premultiplied.

// Views are 2D arrays (`render::memory::Image`): layer 0.
layout(set = 0, binding = 0) uniform sampler2DArray tex;

layout(push_constant) uniform Push {
    vec2 size;
    float linear_out;
} push;

layout(location = 0) in vec2 v_uv;
layout(location = 1) in vec4 v_colour;

layout(location = 0) out vec4 out_colour;

vec3 srgb_decode(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(0.04045, c));
}

void main() {
    vec4 c = v_colour * texture(tex, vec3(v_uv, 0.0));
    if (push.linear_out > 0.5 && c.a > 0.0) {
        // Un-premultiply, decode, premultiply again: the blend then runs in linear light.
        c.rgb = srgb_decode(c.rgb / c.a) * c.a;
    }
    out_colour = c;
}
