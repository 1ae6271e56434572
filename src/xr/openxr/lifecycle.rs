//! The OpenXR session lifecycle as a pure state machine: which runtime events lead to
//! `xrBeginSession`, `xrEndSession`, `xrRequestExitSession` and the end of the program. The
//! backend feeds it every event it polls; tests feed it scripted event streams.
//!
//! The rules (OpenXR 1.1 §10.3): READY → begin; SYNCHRONIZED/VISIBLE/FOCUSED only change what
//! is shown and whether input counts; STOPPING → end; EXITING or LOSS_PENDING → destroy the
//! session and leave; an instance-loss-pending event ends everything too.

use openxr::SessionState;

/// What the runtime told us.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    /// `XrEventDataSessionStateChanged`.
    State(SessionState),
    /// `XrEventDataInstanceLossPending`: the runtime is going away (update, crash).
    InstanceLossPending,
}

/// What the backend must do next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Nothing.
    None,
    /// Call `xrBeginSession` (the frame loop starts).
    Begin,
    /// Call `xrEndSession` (the frame loop stops).
    End,
    /// Destroy the session and leave, for this reason.
    Exit(ExitReason),
}

/// Why the session ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExitReason {
    /// EXITING: the user or the app asked to quit. A clean end.
    Exiting,
    /// LOSS_PENDING: the session is lost (e.g. the headset was disconnected).
    SessionLost,
    /// The instance is about to be lost (runtime update or crash).
    InstanceLost,
}

impl ExitReason {
    /// Whether the program ends successfully.
    pub fn is_clean(self) -> bool {
        self == ExitReason::Exiting
    }
}

/// Most state changes kept for the log; later ones are counted only.
pub const MAX_HISTORY: usize = 64;

/// The session's state and what has happened to it.
#[derive(Debug)]
pub struct Lifecycle {
    state: SessionState,
    running: bool,
    exit_requested: bool,
    history: Vec<SessionState>,
    dropped: usize,
}

impl Default for Lifecycle {
    fn default() -> Self {
        Self::new()
    }
}

impl Lifecycle {
    /// A session just created (state UNKNOWN until the runtime says IDLE).
    pub fn new() -> Self {
        Self {
            state: SessionState::UNKNOWN,
            running: false,
            exit_requested: false,
            history: Vec::with_capacity(MAX_HISTORY),
            dropped: 0,
        }
    }

    /// Takes one event; returns what to do.
    pub fn on_event(&mut self, event: Event) -> Action {
        let state = match event {
            Event::InstanceLossPending => return Action::Exit(ExitReason::InstanceLost),
            Event::State(s) => s,
        };
        self.state = state;
        if self.history.len() < MAX_HISTORY {
            self.history.push(state);
        } else {
            self.dropped += 1;
        }
        match state {
            SessionState::READY if !self.running => {
                self.running = true;
                Action::Begin
            }
            SessionState::STOPPING if self.running => {
                self.running = false;
                Action::End
            }
            SessionState::EXITING => Action::Exit(ExitReason::Exiting),
            SessionState::LOSS_PENDING => Action::Exit(ExitReason::SessionLost),
            _ => Action::None,
        }
    }

    /// The app wants to quit (frame count reached, Ctrl-C, back button). Returns whether to
    /// call `xrRequestExitSession` (only valid while the session runs); when it is not
    /// running, returns [`Action::Exit`] directly.
    pub fn request_exit(&mut self) -> Action {
        if self.exit_requested {
            return Action::None;
        }
        self.exit_requested = true;
        if self.running {
            Action::None
        } else {
            Action::Exit(ExitReason::Exiting)
        }
    }

    /// Whether the app asked to quit.
    pub fn exit_requested(&self) -> bool {
        self.exit_requested
    }

    /// Whether `xrRequestExitSession` must be called now: asked for and the session runs.
    pub fn needs_exit_request(&self) -> bool {
        self.exit_requested && self.running
    }

    /// Between `xrBeginSession` and `xrEndSession`: frames must be waited, begun and ended.
    pub fn running(&self) -> bool {
        self.running
    }

    /// FOCUSED: input is ours.
    pub fn focused(&self) -> bool {
        self.state == SessionState::FOCUSED
    }

    /// The current state.
    pub fn state(&self) -> SessionState {
        self.state
    }

    /// Every state reached, in order (the first [`MAX_HISTORY`]).
    pub fn history(&self) -> &[SessionState] {
        &self.history
    }

    /// Writes the history as `IDLE>READY>...` into `out`.
    pub fn history_text(&self, out: &mut String) {
        for (i, s) in self.history.iter().enumerate() {
            if i > 0 {
                out.push('>');
            }
            out.push_str(state_name(*s));
        }
        if self.dropped > 0 {
            out.push_str(&format!(">(+{})", self.dropped));
        }
    }
}

/// The spec's name of a session state, without the prefix.
pub fn state_name(s: SessionState) -> &'static str {
    match s {
        SessionState::IDLE => "IDLE",
        SessionState::READY => "READY",
        SessionState::SYNCHRONIZED => "SYNCHRONIZED",
        SessionState::VISIBLE => "VISIBLE",
        SessionState::FOCUSED => "FOCUSED",
        SessionState::STOPPING => "STOPPING",
        SessionState::LOSS_PENDING => "LOSS_PENDING",
        SessionState::EXITING => "EXITING",
        _ => "UNKNOWN",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use SessionState as S;

    /// Feeds `events`, calling `request_exit` before the event at index `exit_at`; returns the
    /// actions in order (without `None`s).
    fn script(events: &[Event], exit_at: Option<usize>) -> (Lifecycle, Vec<Action>) {
        let mut l = Lifecycle::new();
        let mut out = Vec::new();
        for (i, &e) in events.iter().enumerate() {
            if exit_at == Some(i) {
                match l.request_exit() {
                    Action::None => {}
                    a => out.push(a),
                }
            }
            match l.on_event(e) {
                Action::None => {}
                a => out.push(a),
            }
        }
        (l, out)
    }

    fn states(s: &[SessionState]) -> Vec<Event> {
        s.iter().map(|&s| Event::State(s)).collect()
    }

    #[test]
    fn normal_session_begins_runs_and_ends_on_request() {
        let ev = states(&[
            S::IDLE,
            S::READY,
            S::SYNCHRONIZED,
            S::VISIBLE,
            S::FOCUSED,
            S::VISIBLE,
            S::SYNCHRONIZED,
            S::STOPPING,
            S::IDLE,
            S::EXITING,
        ]);
        let mut l = Lifecycle::new();
        let mut actions = Vec::new();
        for (i, &e) in ev.iter().enumerate() {
            let a = l.on_event(e);
            actions.push(a);
            match i {
                1..=6 => assert!(l.running(), "running after {:?}", e),
                _ => assert!(!l.running() || i == 0, "not running after {:?}", e),
            }
            assert_eq!(l.focused(), i == 4);
            if i == 4 {
                // The app asks to quit while focused: it must call xrRequestExitSession.
                assert_eq!(l.request_exit(), Action::None);
                assert!(l.needs_exit_request());
            }
        }
        assert_eq!(actions[1], Action::Begin);
        assert_eq!(actions[7], Action::End);
        assert_eq!(actions[9], Action::Exit(ExitReason::Exiting));
        assert_eq!(
            actions.iter().filter(|a| **a != Action::None).count(),
            3,
            "{actions:?}"
        );
        let mut text = String::new();
        l.history_text(&mut text);
        assert_eq!(
            text,
            "IDLE>READY>SYNCHRONIZED>VISIBLE>FOCUSED>VISIBLE>SYNCHRONIZED>STOPPING>IDLE>EXITING"
        );
    }

    #[test]
    fn focus_lost_and_regained_keeps_the_session_running() {
        let ev = states(&[
            S::IDLE,
            S::READY,
            S::SYNCHRONIZED,
            S::VISIBLE,
            S::FOCUSED,
            // System menu opened: focus lost, still visible.
            S::VISIBLE,
            S::FOCUSED,
            // Headset taken off: hidden, then back.
            S::VISIBLE,
            S::SYNCHRONIZED,
            S::VISIBLE,
            S::FOCUSED,
        ]);
        let mut l = Lifecycle::new();
        let mut focus = Vec::new();
        for &e in &ev {
            let a = l.on_event(e);
            assert!(matches!(a, Action::None | Action::Begin), "{a:?}");
            focus.push(l.focused());
        }
        assert!(l.running());
        assert_eq!(
            focus,
            [false, false, false, false, true, false, true, false, false, false, true]
        );
    }

    #[test]
    fn loss_pending_exits_with_a_lost_session() {
        let (l, actions) = script(
            &states(&[S::IDLE, S::READY, S::SYNCHRONIZED, S::LOSS_PENDING]),
            None,
        );
        assert_eq!(
            actions,
            [Action::Begin, Action::Exit(ExitReason::SessionLost)]
        );
        assert!(!ExitReason::SessionLost.is_clean());
        assert_eq!(l.state(), S::LOSS_PENDING);
    }

    #[test]
    fn instance_loss_exits_at_once() {
        let mut ev = states(&[S::IDLE, S::READY, S::SYNCHRONIZED, S::VISIBLE, S::FOCUSED]);
        ev.push(Event::InstanceLossPending);
        let (_, actions) = script(&ev, None);
        assert_eq!(
            actions,
            [Action::Begin, Action::Exit(ExitReason::InstanceLost)]
        );
    }

    #[test]
    fn exit_before_ready_needs_no_runtime_round_trip() {
        let (l, actions) = script(&states(&[S::IDLE, S::IDLE]), Some(1));
        assert_eq!(actions, [Action::Exit(ExitReason::Exiting)]);
        assert!(!l.needs_exit_request());
    }

    #[test]
    fn exit_requested_twice_asks_once() {
        let mut l = Lifecycle::new();
        l.on_event(Event::State(S::IDLE));
        l.on_event(Event::State(S::READY));
        assert_eq!(l.request_exit(), Action::None);
        assert!(l.needs_exit_request());
        assert_eq!(l.request_exit(), Action::None);
        assert_eq!(l.on_event(Event::State(S::STOPPING)), Action::End);
        assert!(!l.needs_exit_request(), "not running any more");
    }

    #[test]
    fn runtime_stopping_without_request_then_ready_again_restarts() {
        // The runtime may stop a session (e.g. headset idle) and make it READY again.
        let (l, actions) = script(
            &states(&[
                S::IDLE,
                S::READY,
                S::SYNCHRONIZED,
                S::STOPPING,
                S::IDLE,
                S::READY,
                S::SYNCHRONIZED,
            ]),
            None,
        );
        assert_eq!(actions, [Action::Begin, Action::End, Action::Begin]);
        assert!(l.running());
    }

    #[test]
    fn history_is_bounded() {
        let mut l = Lifecycle::new();
        for i in 0..MAX_HISTORY + 10 {
            let s = if i % 2 == 0 { S::VISIBLE } else { S::FOCUSED };
            l.on_event(Event::State(s));
        }
        assert_eq!(l.history().len(), MAX_HISTORY);
        let mut text = String::new();
        l.history_text(&mut text);
        assert!(text.ends_with(">(+10)"), "{text}");
    }
}
