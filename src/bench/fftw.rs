//! Minimal FFI to the system FFTW (single precision), a benchmark baseline only: behind the
//! `fftw` feature, linking `libfftw3f` (Debian `libfftw3-dev`). Used by `vr-ocean bench` and
//! `benches/fft.rs`. Plans are made with the caller's flags (FFTW_PATIENT for the baselines)
//! outside any timing.
use std::ffi::{c_int, c_uint, c_void};

/// `FFTW_BACKWARD`: the sign of the exponent, +1, i.e. the unnormalized inverse transform.
pub const FFTW_BACKWARD: c_int = 1;
/// `FFTW_PATIENT` planner flag.
pub const FFTW_PATIENT: c_uint = 1 << 5;

/// `fftwf_complex`: interleaved re, im.
pub type Complex = [f32; 2];

#[link(name = "fftw3f")]
extern "C" {
    fn fftwf_plan_dft_2d(
        n0: c_int,
        n1: c_int,
        input: *mut Complex,
        output: *mut Complex,
        sign: c_int,
        flags: c_uint,
    ) -> *mut c_void;
    #[allow(clippy::too_many_arguments)]
    fn fftwf_plan_many_dft(
        rank: c_int,
        n: *const c_int,
        howmany: c_int,
        input: *mut Complex,
        inembed: *const c_int,
        istride: c_int,
        idist: c_int,
        output: *mut Complex,
        onembed: *const c_int,
        ostride: c_int,
        odist: c_int,
        sign: c_int,
        flags: c_uint,
    ) -> *mut c_void;
    fn fftwf_execute(plan: *mut c_void);
    fn fftwf_destroy_plan(plan: *mut c_void);
    fn fftwf_malloc(n: usize) -> *mut c_void;
    fn fftwf_free(p: *mut c_void);
}

/// A zeroed, FFTW-aligned array of complex values.
pub struct Buffer {
    ptr: *mut Complex,
    len: usize,
}

impl Buffer {
    /// `len` zeros, allocated with `fftwf_malloc` (SIMD-aligned).
    pub fn zeros(len: usize) -> Option<Buffer> {
        // SAFETY: plain allocation call; checked for null below.
        let ptr = unsafe { fftwf_malloc(len * std::mem::size_of::<Complex>()) } as *mut Complex;
        if ptr.is_null() {
            return None;
        }
        // SAFETY: `ptr` points to `len` freshly allocated, suitably aligned Complex slots.
        unsafe { std::ptr::write_bytes(ptr, 0, len) };
        Some(Buffer { ptr, len })
    }

    /// The values.
    pub fn as_slice(&self) -> &[Complex] {
        // SAFETY: `ptr` holds `len` initialised values owned by `self`.
        unsafe { std::slice::from_raw_parts(self.ptr, self.len) }
    }

    /// The values, mutably.
    pub fn as_mut_slice(&mut self) -> &mut [Complex] {
        // SAFETY: as above, and `&mut self` gives exclusive access.
        unsafe { std::slice::from_raw_parts_mut(self.ptr, self.len) }
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: allocated by `fftwf_malloc` and freed only here.
        unsafe { fftwf_free(self.ptr as *mut c_void) }
    }
}

/// How a [`Plan`] lays out its transforms.
#[derive(Clone, Copy, Debug)]
pub enum Layout {
    /// One `fftwf_plan_many_dft` over `howmany` contiguous N×N arrays.
    Many,
    /// One `fftwf_plan_dft_2d`, executed on each of the `howmany` arrays in turn (new-array
    /// execution is not bound here, so each array gets its own plan with the same wisdom).
    Single,
}

/// A planned batch of `howmany` inverse N×N complex transforms that owns its arrays (so they
/// outlive the plan). In place when `out` is `None`.
pub struct Plan {
    plans: Vec<*mut c_void>,
    input: Buffer,
    output: Option<Buffer>,
}

// SAFETY: a plan and its arrays are owned by one `Plan` and used through `&mut self` only;
// FFTW allows executing a plan from any thread (planning is not involved after `new`).
unsafe impl Send for Plan {}

impl Plan {
    /// Plans with `flags` (planning may overwrite the arrays; fill them afterwards).
    pub fn new(
        n: usize,
        howmany: usize,
        layout: Layout,
        in_place: bool,
        flags: c_uint,
    ) -> Option<Plan> {
        let len = n * n * howmany;
        let mut input = Buffer::zeros(len)?;
        let mut output = match in_place {
            true => None,
            false => Some(Buffer::zeros(len)?),
        };
        let ip = input.as_mut_slice().as_mut_ptr();
        let op = output
            .as_mut()
            .map_or(ip, |b| b.as_mut_slice().as_mut_ptr());
        let ni = n as c_int;
        let plans = match layout {
            Layout::Many => {
                let dims = [ni, ni];
                let dist = ni * ni;
                // SAFETY: `ip`/`op` hold `howmany` contiguous n×n arrays owned by the returned
                // Plan; null embeds mean "same as dims".
                vec![unsafe {
                    fftwf_plan_many_dft(
                        2,
                        dims.as_ptr(),
                        howmany as c_int,
                        ip,
                        std::ptr::null(),
                        1,
                        dist,
                        op,
                        std::ptr::null(),
                        1,
                        dist,
                        FFTW_BACKWARD,
                        flags,
                    )
                }]
            }
            Layout::Single => (0..howmany)
                .map(|i| {
                    let off = i * n * n;
                    // SAFETY: array i of `ip`/`op`, n×n values, owned by the returned Plan.
                    unsafe {
                        fftwf_plan_dft_2d(ni, ni, ip.add(off), op.add(off), FFTW_BACKWARD, flags)
                    }
                })
                .collect(),
        };
        let plan = Plan {
            plans,
            input,
            output,
        };
        // Drop (which skips null plans) releases everything if any plan failed.
        plan.plans.iter().all(|p| !p.is_null()).then_some(plan)
    }

    /// The input arrays, to fill before [`Plan::execute`].
    pub fn input_mut(&mut self) -> &mut [Complex] {
        self.input.as_mut_slice()
    }

    /// The result arrays (the input arrays when in place).
    pub fn output(&self) -> &[Complex] {
        self.output.as_ref().unwrap_or(&self.input).as_slice()
    }

    /// Runs the transforms.
    pub fn execute(&mut self) {
        for &p in &self.plans {
            // SAFETY: `p` is a live plan whose arrays `self` owns.
            unsafe { fftwf_execute(p) }
        }
    }
}

impl Drop for Plan {
    fn drop(&mut self) {
        for &p in self.plans.iter().filter(|p| !p.is_null()) {
            // SAFETY: created by the planner above, destroyed once.
            unsafe { fftwf_destroy_plan(p) }
        }
    }
}
