#version 450
// Geometry of the calibration kernels (`render::calibration`): one triangle over the whole
// viewport, or a grid of small triangles tiling it (`grid.xy` square cells of `grid.z` pixels
// from the top-left corner, two triangles each, split along the cell's rising diagonal), made
// from gl_VertexIndex alone (no vertex buffer). At depth 0.5, under the
// ocean pass's reversed-Z `GREATER` test against a cleared 0: every fragment passes and writes.
#extension GL_GOOGLE_include_directive : require
#include "calibrate.glsl"

// The corners of a cell's two triangles (counter-clockwise), in cell units.
const vec2 CORNERS[6] = vec2[6](vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(0.0, 1.0),
                                 vec2(1.0, 0.0), vec2(1.0, 1.0), vec2(0.0, 1.0));

void main() {
    vec2 at;
    if (pc.grid.x == 0u) {
        // (0, 0), (2, 0), (0, 2): one triangle whose inside covers the viewport.
        at = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    } else {
        uint cell = uint(gl_VertexIndex) / 6u;
        uvec2 c = uvec2(cell % pc.grid.x, cell / pc.grid.x);
        at = (vec2(c) + CORNERS[uint(gl_VertexIndex) % 6u]) * float(pc.grid.z)
            / vec2(pc.viewport.xy);
    }
    gl_Position = vec4(at * 2.0 - 1.0, 0.5, 1.0);
}
