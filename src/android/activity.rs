//! The Android activity's lifecycle as a pure state machine, for the frame loop.
//!
//! NativeActivity tells the app thread about start/resume/pause/stop/destroy and its window.
//! The OpenXR session's own lifecycle (READY → `xrBeginSession`, STOPPING → `xrEndSession`)
//! is the backend's ([`crate::xr::openxr::lifecycle`]); on Quest the runtime makes the session
//! READY after the activity resumes and STOPPING after it pauses. What the activity decides
//! here:
//!
//! * how long the frame loop may block waiting for activity events: not at all while the
//!   session runs (frames are paced by `xrWaitFrame`), [`RESUMED_IDLE_WAIT`] while resumed
//!   and waiting for READY, [`PAUSED_WAIT`] while paused with the session stopped (the app
//!   sleeps, waking a few times a second to poll OpenXR events);
//! * when to ask the session to end: once, after Destroy.
//!
//! The window (`InitWindow`/`TerminateWindow`) is tracked and logged only: OpenXR composes
//! to the headset's display itself, so no swapchain depends on the activity's window.

use std::time::Duration;

/// Longest wait for activity events while resumed and the session is not running yet.
pub const RESUMED_IDLE_WAIT: Duration = Duration::from_millis(10);

/// Longest wait for activity events while paused and the session is stopped.
pub const PAUSED_WAIT: Duration = Duration::from_millis(250);

/// An activity lifecycle event (android-activity's `MainEvent`s the frame loop cares about).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ActivityEvent {
    /// `onStart`.
    Start,
    /// `onResume`: in the foreground.
    Resume,
    /// `onPause`: leaving the foreground.
    Pause,
    /// `onStop`: no longer visible.
    Stop,
    /// `onDestroy`: the app thread must end.
    Destroy,
    /// The native window exists.
    WindowCreated,
    /// The native window is going away.
    WindowDestroyed,
}

/// Where the activity is.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ActivityState {
    started: bool,
    resumed: bool,
    window: bool,
    destroyed: bool,
    exit_taken: bool,
}

impl ActivityState {
    /// A created activity, not yet started.
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes one event.
    pub fn on_event(&mut self, event: ActivityEvent) {
        match event {
            ActivityEvent::Start => self.started = true,
            ActivityEvent::Resume => {
                self.started = true;
                self.resumed = true;
            }
            ActivityEvent::Pause => self.resumed = false,
            ActivityEvent::Stop => {
                self.resumed = false;
                self.started = false;
            }
            ActivityEvent::Destroy => {
                self.resumed = false;
                self.started = false;
                self.destroyed = true;
            }
            ActivityEvent::WindowCreated => self.window = true,
            ActivityEvent::WindowDestroyed => self.window = false,
        }
    }

    /// In the foreground (between `onResume` and `onPause`).
    pub fn resumed(&self) -> bool {
        self.resumed
    }

    /// Whether the native window exists.
    pub fn has_window(&self) -> bool {
        self.window
    }

    /// Whether `onDestroy` came.
    pub fn destroyed(&self) -> bool {
        self.destroyed
    }

    /// How long the next poll of activity events may block, given whether the OpenXR session
    /// runs: zero while it runs or once destroyed (the session must be ended promptly),
    /// [`RESUMED_IDLE_WAIT`] while resumed, [`PAUSED_WAIT`] while paused.
    pub fn poll_timeout(&self, session_running: bool) -> Duration {
        if session_running || self.destroyed {
            Duration::ZERO
        } else if self.resumed {
            RESUMED_IDLE_WAIT
        } else {
            PAUSED_WAIT
        }
    }

    /// True exactly once after Destroy: ask the OpenXR session to end.
    pub fn take_exit_request(&mut self) -> bool {
        if self.destroyed && !self.exit_taken {
            self.exit_taken = true;
            true
        } else {
            false
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ActivityEvent as E;

    fn after(events: &[ActivityEvent]) -> ActivityState {
        let mut s = ActivityState::new();
        for &e in events {
            s.on_event(e);
        }
        s
    }

    #[test]
    fn waits_follow_the_lifecycle() {
        let created = ActivityState::new();
        assert_eq!(created.poll_timeout(false), PAUSED_WAIT);
        let resumed = after(&[E::Start, E::Resume, E::WindowCreated]);
        assert!(resumed.resumed() && resumed.has_window());
        assert_eq!(resumed.poll_timeout(false), RESUMED_IDLE_WAIT);
        assert_eq!(resumed.poll_timeout(true), Duration::ZERO);
        let paused = after(&[E::Start, E::Resume, E::Pause]);
        assert!(!paused.resumed());
        assert_eq!(paused.poll_timeout(false), PAUSED_WAIT);
        // Paused while the runtime has not stopped the session yet: frames go on.
        assert_eq!(paused.poll_timeout(true), Duration::ZERO);
        let stopped = after(&[E::Start, E::Resume, E::Pause, E::Stop, E::WindowCreated]);
        assert_eq!(stopped.poll_timeout(false), PAUSED_WAIT);
        let again = after(&[E::Resume, E::Pause, E::Stop, E::Start, E::Resume]);
        assert_eq!(again.poll_timeout(false), RESUMED_IDLE_WAIT);
        assert!(!after(&[E::WindowCreated, E::WindowDestroyed]).has_window());
    }

    #[test]
    fn destroy_asks_for_exit_once_and_never_blocks() {
        let mut s = after(&[E::Start, E::Resume]);
        assert!(!s.take_exit_request());
        s.on_event(E::Destroy);
        assert!(s.destroyed() && !s.resumed());
        assert_eq!(s.poll_timeout(false), Duration::ZERO);
        assert!(s.take_exit_request());
        assert!(!s.take_exit_request());
        // Later events do not bring it back.
        s.on_event(E::Resume);
        assert!(!s.take_exit_request());
        assert_eq!(s.poll_timeout(false), Duration::ZERO);
    }
}
