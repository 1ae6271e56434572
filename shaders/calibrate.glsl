// Shared by the calibration kernels (`render::calibration`, `shaders/calibrate.*`): their push
// constants (`render::calibration::KernelPush` on the CPU side; keep both in sync).
layout(push_constant) uniform Push {
    // The kernels' operands, never known to the compiler: x scales the fragment's position into
    // the first value, y, z, w are the operands of the arithmetic.
    vec4 k;
    // The same in relaxed precision, for the relaxed kernel (a `mediump` member: its loads stay
    // relaxed through the optimizer's unrolling, so every copy of the arithmetic is counted so).
    mediump vec4 kh;
    // x, y: the grid's cells across and down (0: one triangle over the viewport); z: a cell's
    // side (pixels); w: unused.
    uvec4 grid;
    // x, y: the viewport's size (pixels); z, w: unused.
    uvec4 viewport;
} pc;
