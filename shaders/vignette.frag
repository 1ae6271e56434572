#version 450
// The comfort vignette: black, blended over the frame by its ring's alpha (see vignette.vert).
layout(location = 0) in float v_alpha;
layout(location = 0) out vec4 o_colour;

void main() {
    o_colour = vec4(0.0, 0.0, 0.0, v_alpha);
}
