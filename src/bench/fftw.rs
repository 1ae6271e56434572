//! Minimal FFI to the system FFTW (single precision), a benchmark baseline only. Enabled by the
//! `fftw` feature; links `libfftw3f` (Debian `libfftw3-dev`).

use std::os::raw::{c_int, c_uint, c_void};

#[repr(C)]
struct PlanOpaque {
    _private: [u8; 0],
}

#[link(name = "fftw3f")]
extern "C" {
    fn fftwf_plan_many_dft(
        rank: c_int,
        n: *const c_int,
        howmany: c_int,
        input: *mut [f32; 2],
        inembed: *const c_int,
        istride: c_int,
        idist: c_int,
        output: *mut [f32; 2],
        onembed: *const c_int,
        ostride: c_int,
        odist: c_int,
        sign: c_int,
        flags: c_uint,
    ) -> *mut PlanOpaque;
    fn fftwf_execute(plan: *const PlanOpaque);
    fn fftwf_destroy_plan(plan: *mut PlanOpaque);
    fn fftwf_malloc(n: usize) -> *mut c_void;
    fn fftwf_free(p: *mut c_void);
}

const FFTW_BACKWARD: c_int = 1;
const FFTW_PATIENT: c_uint = 1 << 5;

/// `howmany` in-place complex inverse 2D transforms of side `n`, planned with FFTW_PATIENT,
/// on FFTW-allocated (SIMD-aligned) interleaved data.
pub struct FftwBatch {
    plan: *mut PlanOpaque,
    data: *mut [f32; 2],
    len: usize,
}

impl FftwBatch {
    /// Plans the batch (FFTW_PATIENT measures many algorithms: seconds for large sizes).
    /// Returns None if FFTW cannot plan or allocate.
    pub fn new(n: usize, howmany: usize) -> Option<Self> {
        let len = n * n * howmany;
        // SAFETY: plain allocation; checked for null below.
        let data = unsafe { fftwf_malloc(len * 8) } as *mut [f32; 2];
        if data.is_null() {
            return None;
        }
        let dims = [n as c_int, n as c_int];
        // SAFETY: `data` holds `howmany` contiguous n×n complex arrays; null embeds mean dense.
        let plan = unsafe {
            fftwf_plan_many_dft(
                2,
                dims.as_ptr(),
                howmany as c_int,
                data,
                std::ptr::null(),
                1,
                (n * n) as c_int,
                data,
                std::ptr::null(),
                1,
                (n * n) as c_int,
                FFTW_BACKWARD,
                FFTW_PATIENT,
            )
        };
        if plan.is_null() {
            // SAFETY: allocated above by fftwf_malloc.
            unsafe { fftwf_free(data as *mut c_void) };
            return None;
        }
        let mut batch = Self { plan, data, len };
        // Planning scribbles over the array: refill with something finite.
        for (i, v) in batch.data_mut().iter_mut().enumerate() {
            *v = [
                ((i * 7919) % 1000) as f32 * 1e-3,
                ((i * 104_729) % 1000) as f32 * 1e-3,
            ];
        }
        Some(batch)
    }

    /// The interleaved complex data, transform after transform.
    pub fn data_mut(&mut self) -> &mut [[f32; 2]] {
        // SAFETY: `data` points to `len` elements owned by self.
        unsafe { std::slice::from_raw_parts_mut(self.data, self.len) }
    }

    /// Runs all transforms once.
    pub fn execute(&mut self) {
        // SAFETY: the plan was made for `data`, which lives as long as self.
        unsafe { fftwf_execute(self.plan) }
    }
}

impl Drop for FftwBatch {
    fn drop(&mut self) {
        // SAFETY: both were created in `new` and are released exactly once.
        unsafe {
            fftwf_destroy_plan(self.plan);
            fftwf_free(self.data as *mut c_void);
        }
    }
}
