//! One typed error for every failed OpenXR call: the call's name and its result code. Losing
//! the runtime (a crash, an update, the service killed) can surface in any call; it is
//! recognised and worded here, in one place.

use openxr as xr;

use crate::xr::XrError;

/// A failed OpenXR call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CallError {
    /// The call (`xrWaitFrame`, or what it did: "acquiring the colour swapchain image").
    pub call: &'static str,
    /// Its result code.
    pub result: xr::sys::Result,
}

impl CallError {
    /// `call` failed with `result`.
    pub fn new(call: &'static str, result: xr::sys::Result) -> Self {
        Self { call, result }
    }

    /// Whether the runtime went away (`XR_ERROR_INSTANCE_LOST`): nothing more can be done
    /// with this instance.
    pub fn runtime_lost(&self) -> bool {
        self.result == xr::sys::Result::ERROR_INSTANCE_LOST
    }

    /// Whether the session was lost (`XR_ERROR_SESSION_LOST`): the instance may make another.
    pub fn session_lost(&self) -> bool {
        self.result == xr::sys::Result::ERROR_SESSION_LOST
    }
}

impl std::fmt::Display for CallError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (call, e) = (self.call, self.result);
        match e {
            xr::sys::Result::ERROR_INSTANCE_LOST => write!(
                f,
                "the OpenXR runtime went away ({call}: XR_ERROR_INSTANCE_LOST)"
            ),
            xr::sys::Result::ERROR_SESSION_LOST => write!(
                f,
                "the OpenXR session was lost ({call}: XR_ERROR_SESSION_LOST)"
            ),
            e => write!(f, "{call}: {e:?} ({e})"),
        }
    }
}

impl std::error::Error for CallError {}

/// Names a failed call: `instance.properties().call("xrGetInstanceProperties")?`.
pub trait Call<T> {
    /// The result with its error typed as a [`CallError`] of `call`.
    fn call(self, call: &'static str) -> Result<T, CallError>;
}

impl<T> Call<T> for Result<T, xr::sys::Result> {
    fn call(self, call: &'static str) -> Result<T, CallError> {
        self.map_err(|result| CallError { call, result })
    }
}

/// A raw function-table call's result as a `Result` (negative codes are errors).
pub fn check(result: xr::sys::Result) -> Result<(), xr::sys::Result> {
    if result.into_raw() < 0 {
        Err(result)
    } else {
        Ok(())
    }
}

/// Why the backend could not start or stopped: a message that says what to install or check.
pub(super) fn backend(msg: impl Into<String>) -> XrError {
    XrError::Backend(msg.into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn losing_the_runtime_is_worded_once_for_every_call() {
        let lost: Result<(), _> = Err(xr::sys::Result::ERROR_INSTANCE_LOST);
        let e = lost.call("xrWaitFrame").unwrap_err();
        assert!(e.runtime_lost());
        assert_eq!(
            e.to_string(),
            "the OpenXR runtime went away (xrWaitFrame: XR_ERROR_INSTANCE_LOST)"
        );
        let other: Result<(), _> = Err(xr::sys::Result::ERROR_RUNTIME_FAILURE);
        let e = other.call("xrEndFrame").unwrap_err();
        assert!(!e.runtime_lost());
        assert!(
            e.to_string()
                .starts_with("xrEndFrame: ERROR_RUNTIME_FAILURE"),
            "{e}"
        );
        assert!(check(xr::sys::Result::SESSION_LOSS_PENDING).is_ok());
        assert!(check(xr::sys::Result::ERROR_VALIDATION_FAILURE).is_err());
    }
}
