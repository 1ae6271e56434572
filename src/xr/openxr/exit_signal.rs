//! A clean exit on Ctrl-C (SIGINT) and SIGTERM: the handler only raises [`EXIT_SIGNAL`]; the
//! frame loop sees it, calls `xrRequestExitSession` and leaves after STOPPING and EXITING
//! instead of the process dying mid-frame with the runtime's objects alive.

use std::sync::atomic::{AtomicBool, Ordering};

/// Set (from the signal handler, or by anyone) to ask for a clean end of the session.
pub static EXIT_SIGNAL: AtomicBool = AtomicBool::new(false);

/// Routes SIGINT and SIGTERM to [`EXIT_SIGNAL`] (Unix; elsewhere nothing).
pub fn install_exit_signal_handler() {
    #[cfg(unix)]
    {
        use std::ffi::c_int;
        extern "C" fn on_signal(_: c_int) {
            EXIT_SIGNAL.store(true, Ordering::Relaxed);
        }
        extern "C" {
            fn signal(signum: c_int, handler: extern "C" fn(c_int)) -> usize;
        }
        const SIGINT: c_int = 2;
        const SIGTERM: c_int = 15;
        // SAFETY: `signal` is libc's; the handler only stores to an atomic, which is
        // async-signal-safe.
        unsafe {
            signal(SIGINT, on_signal);
            signal(SIGTERM, on_signal);
        }
    }
    #[cfg(not(unix))]
    let _ = Ordering::Relaxed;
}
