#version 450
// The calibration kernels of `vr-ocean gpu-budget --calibrate` (`render::calibration`): each
// full-screen fragment shader does a known amount of one kind of work, so that the time of its
// pass, less the base kernel's, gives the device's cost of that kind of work per fragment.
// Built (`shaders/shader_table.rs` CALIBRATION_SHADERS) with KERNEL and COUNT defined and
// optimized by spirv-opt like the ocean's cost variants, so that `render::budget::spirv`
// counts them in the same units as the ocean's paths:
//   0 base: nothing but the fragment's own write;
//   1 FP32 arithmetic: COUNT rounds of (fma, min, add) on a vec4, none of which the compiler
//     can fold into the next (12 scalar ALU operations a round);
//   2 the same in relaxed precision (`mediump`);
//   3 special functions: COUNT rounds of (add, inversesqrt, exp2) on a vec4 (8 special and 4
//     ALU operations a round);
//   4 trilinear samples: COUNT samples of an RGBA8 array with mips, as the ocean's normal maps
//     are (256 texels a side), with a minified footprint (2.83 texels a pixel: mip 1.5);
//   5 anisotropic samples: the same through the anisotropic sampler with a 4:1 footprint;
//   6 mixed: COUNT rounds of one trilinear sample and 48 FP32 operations, as the water mixes
//     them: whether this device overlaps texture and ALU work;
//   7 samples at an explicit level of detail that differs from lane to lane (the sky's map
//     read at the lobe's roughness, the sub-samples' mips);
//   8 samples with explicit gradients (the foam pattern's, the whitecaps');
//   9 level-of-detail queries (the finest cascade's);
//   10 kernel 7's samples behind a branch that no lane takes (its condition is each lane's
//     own, which the compiler cannot know): a GPU skips it where a whole wave agrees, a CPU
//     device that masks lanes may run it anyway.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "calibrate.glsl"

layout(set = 0, binding = 0) uniform mediump sampler2DArray u_trilinear;
layout(set = 0, binding = 1) uniform mediump sampler2DArray u_anisotropic;
layout(location = 0) out vec4 o_colour;

// Another place and scale of the texture for each sample, so that no two samples are the
// same and each has a footprint of its own (as the water's cascades have): a compiler cannot
// share one sample's level of detail with the next.
vec3 sample_at(vec2 uv, int i) {
    return vec3(uv * (1.0 + 0.13 * float(i)) + float(i) * vec2(0.37, 0.21), 0.0);
}

void main() {
    vec2 p = gl_FragCoord.xy;
    vec4 v = vec4(p, p.yx) * pc.k.x;
    // 2.83 texels a pixel: mip 1.5, between two levels, as the water's minified normal maps
    // mostly are (at a whole level a sampler may read one level only).
    vec2 uv = p * (1.0 / 90.5);
#if KERNEL == 1
    [[unroll]] for (int i = 0; i < COUNT; ++i) {
        v = min(fma(v, pc.k.yyyy, pc.k.zzzz), pc.k.wwww) + pc.k.zzzz;
    }
#elif KERNEL == 2
    // The operands read once, before the loop: every unrolled copy uses these relaxed values.
    mediump vec4 h = vec4(p, p.yx) * pc.kh.x;
    mediump vec4 a = pc.kh.yyyy;
    mediump vec4 b = pc.kh.zzzz;
    mediump vec4 c = pc.kh.wwww;
    [[unroll]] for (int i = 0; i < COUNT; ++i) {
        h = min(fma(h, a, b), c) + b;
    }
    v = h;
#elif KERNEL == 3
    [[unroll]] for (int i = 0; i < COUNT; ++i) {
        v = exp2(-inversesqrt(v + pc.k.wwww));
    }
#elif KERNEL == 4
    [[unroll]] for (int i = 0; i < COUNT; ++i) {
        v += texture(u_trilinear, sample_at(uv, i));
    }
#elif KERNEL == 5
    // Four times as many texels along y as across x: 4 taps where the device filters up to 4x.
    vec2 stretched = vec2(uv.x * 0.5, uv.y * 2.0);
    [[unroll]] for (int i = 0; i < COUNT; ++i) {
        v += texture(u_anisotropic, sample_at(stretched, i));
    }
#elif KERNEL == 6
    [[unroll]] for (int i = 0; i < COUNT; ++i) {
        v += texture(u_trilinear, sample_at(uv, i));
        [[unroll]] for (int j = 0; j < 4; ++j) {
            v = min(fma(v, pc.k.yyyy, pc.k.zzzz), pc.k.wwww) + pc.k.zzzz;
        }
    }
#elif KERNEL == 7
    // Levels 0.5 to 2.5, changing across the screen within each quad, and from sample to
    // sample.
    float level = 0.5 + 2.0 * fract(dot(p, vec2(0.37, 0.61)));
    [[unroll]] for (int i = 0; i < COUNT; ++i) {
        v += textureLod(u_trilinear, sample_at(uv, i), level + 0.07 * float(i));
    }
#elif KERNEL == 8
    // The footprint of mip 1 along x and of mip 0.5 along y, given explicitly.
    vec2 gx = dFdx(uv);
    vec2 gy = 0.7 * dFdy(uv);
    [[unroll]] for (int i = 0; i < COUNT; ++i) {
        float scale = 1.0 + 0.13 * float(i);
        v += textureGrad(u_trilinear, sample_at(uv, i), gx * scale, gy * scale);
    }
#elif KERNEL == 9
    [[unroll]] for (int i = 0; i < COUNT; ++i) {
        v.xy += textureQueryLod(u_trilinear, sample_at(uv, i).xy);
    }
#elif KERNEL == 10
    if (p.x < -1.0) {
        float level = 0.5 + 2.0 * fract(dot(p, vec2(0.37, 0.61)));
        [[unroll]] for (int i = 0; i < COUNT; ++i) {
            v += textureLod(u_trilinear, sample_at(uv, i), level + 0.07 * float(i));
        }
    }
#endif
    o_colour = v;
}
