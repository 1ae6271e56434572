//! A hand's grab-and-throw state machine: pure, driven by what a controller reports each
//! frame, so scripted inputs test it without a headset.
//!
//! ```text
//!            body in reach              grip pressed               grip let go
//!   Idle ───────────────────▶ Hovering ──────────────▶ Holding ─────────────────▶ Idle
//!        ◀─────────────────── (haptic tick, Grab)     (Grab every frame)   (Release: thrown)
//!           out of reach
//! ```
//!
//! The grip has hysteresis ([`GRIP_PRESS`], [`GRIP_LETGO`]) and grabs only on the press: a
//! closed fist swept through a body does not pick it up. On the let-go the body gets the
//! hand's velocity *at the body*: v + ω × r, with r from the hand to the body's centre as it
//! was held, and the hand's angular velocity.
//!
//! Each frame the app asks [`Floaters::nearest_body`](crate::physics::Floaters::nearest_body)
//! within [`GRAB_REACH`] of the hand, calls [`Hand::update`], applies the command with
//! [`Floaters::apply`](crate::physics::Floaters::apply) and plays a haptic tick on
//! [`HandEvent::Grabbed`].

use glam::Vec3;

use crate::physics::slot::BodyId;
use crate::physics::{Pose, PHYSICS_DT};

/// Grip value (0..1) at which the hand closes.
pub const GRIP_PRESS: f32 = 0.7;

/// Grip value below which a closed hand opens again.
pub const GRIP_LETGO: f32 = 0.35;

/// How far from a body's box a hand can grab it (m).
pub const GRAB_REACH: f32 = 0.12;

/// Fastest a held body is driven towards its hand (m/s).
pub const MAX_HOLD_SPEED: f32 = 20.0;

/// Fastest a held body is turned towards its hand's orientation (rad/s).
pub const MAX_HOLD_SPIN: f32 = 30.0;

/// Fastest throw (m/s): a pitcher's arm.
pub const MAX_THROW_SPEED: f32 = 30.0;

/// Fastest spin a throw gives (rad/s).
pub const MAX_THROW_SPIN: f32 = 40.0;

/// What a controller reports in one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandInput {
    /// Grip (squeeze) value, 0 open to 1 closed.
    pub grip: f32,
    /// The hand's (grip pose's) pose in the world.
    pub pose: Pose,
    /// Its linear velocity (m/s), from `xrLocateSpace`.
    pub linvel: Vec3,
    /// Its angular velocity (rad/s, world axes).
    pub angvel: Vec3,
}

/// Where a hand is in its grab cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HandState {
    /// Nothing in reach.
    Idle,
    /// A body is in reach (a renderer may highlight it).
    Hovering(BodyId),
    /// Holding a body.
    Holding {
        /// The body.
        body: BodyId,
        /// The body's centre relative to the hand, in the hand's frame (m).
        lever: Vec3,
    },
}

/// What the app should do to the bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HandCommand {
    /// Hold `body` to the hand at `hand` ([`Floaters::grab`](crate::physics::Floaters::grab)).
    Grab {
        /// The body.
        body: BodyId,
        /// The hand's pose.
        hand: Pose,
    },
    /// Let `body` go with these velocities
    /// ([`Floaters::release`](crate::physics::Floaters::release)).
    Release {
        /// The body.
        body: BodyId,
        /// Linear velocity at the body's centre (m/s).
        linvel: Vec3,
        /// Angular velocity (rad/s).
        angvel: Vec3,
    },
}

/// What happened, for feedback.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HandEvent {
    /// A body was grabbed: play a haptic tick.
    Grabbed(BodyId),
    /// A body was let go (thrown if the hand moved).
    Released(BodyId),
}

/// One update's outcome.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HandStep {
    /// What to apply to the bodies, if anything.
    pub command: Option<HandCommand>,
    /// What to tell the user, if anything.
    pub event: Option<HandEvent>,
}

/// One hand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hand {
    state: HandState,
    closed: bool,
}

impl Default for Hand {
    fn default() -> Self {
        Self::new()
    }
}

impl Hand {
    /// An open, idle hand.
    pub fn new() -> Self {
        Self {
            state: HandState::Idle,
            closed: false,
        }
    }

    /// The current state.
    pub fn state(&self) -> HandState {
        self.state
    }

    /// Advances the machine by one frame. `nearest` is the body within reach of the hand and
    /// its centre (m), if any (ignored while holding). A NaN grip counts as open; non-finite
    /// hand velocities throw with none.
    pub fn update(&mut self, input: &HandInput, nearest: Option<(BodyId, Vec3)>) -> HandStep {
        let grip = if input.grip.is_nan() { 0.0 } else { input.grip };
        let pressed = !self.closed && grip >= GRIP_PRESS;
        let let_go = self.closed && grip <= GRIP_LETGO;
        if pressed {
            self.closed = true;
        } else if let_go {
            self.closed = false;
        }
        let mut step = HandStep::default();
        self.state = match self.state {
            HandState::Holding { body, lever } if let_go => {
                let r = input.pose.rotation * lever;
                let (v, w) = if input.linvel.is_finite() && input.angvel.is_finite() {
                    (input.linvel + input.angvel.cross(r), input.angvel)
                } else {
                    (Vec3::ZERO, Vec3::ZERO)
                };
                step.command = Some(HandCommand::Release {
                    body,
                    linvel: v,
                    angvel: w,
                });
                step.event = Some(HandEvent::Released(body));
                HandState::Idle
            }
            held @ HandState::Holding { body, .. } => {
                step.command = Some(HandCommand::Grab {
                    body,
                    hand: input.pose,
                });
                held
            }
            HandState::Idle | HandState::Hovering(_) => match nearest {
                Some((body, centre)) if pressed && input.pose.is_finite() => {
                    let lever = input.pose.rotation.conjugate() * (centre - input.pose.position);
                    step.command = Some(HandCommand::Grab {
                        body,
                        hand: input.pose,
                    });
                    step.event = Some(HandEvent::Grabbed(body));
                    HandState::Holding { body, lever }
                }
                Some((body, _)) => HandState::Hovering(body),
                None => HandState::Idle,
            },
        };
        step
    }

    /// Forgets a held body without a command (the app could not grab it, or it sank).
    pub fn cancel(&mut self) {
        self.state = HandState::Idle;
    }
}

/// Velocities that carry `from` to `to` in one step, capped at
/// [`MAX_HOLD_SPEED`] and
/// [`MAX_HOLD_SPIN`].
pub(crate) fn drive_to(from: &Pose, to: &Pose) -> (Vec3, Vec3) {
    let v = ((to.position - from.position) / PHYSICS_DT).clamp_length_max(MAX_HOLD_SPEED);
    let mut turn = to.rotation * from.rotation.conjugate();
    if turn.w < 0.0 {
        turn = -turn;
    }
    let (axis, angle) = turn.to_axis_angle();
    let w = if angle.is_finite() && axis.is_finite() {
        (axis * angle / PHYSICS_DT).clamp_length_max(MAX_HOLD_SPIN)
    } else {
        Vec3::ZERO
    };
    (v, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(grip: f32, x: f32) -> HandInput {
        HandInput {
            grip,
            pose: Pose::at(Vec3::new(x, 3.0, 0.0)),
            linvel: Vec3::new(2.0, 1.0, 0.0),
            angvel: Vec3::new(0.0, 0.0, 1.0),
        }
    }

    #[test]
    fn hover_grab_hold_throw() {
        let b = BodyId(3);
        let near = Some((b, Vec3::new(0.0, 3.1, 0.0)));
        let mut hand = Hand::new();
        assert_eq!(hand.update(&input(0.0, 0.0), None), HandStep::default());
        assert_eq!(hand.state(), HandState::Idle);
        hand.update(&input(0.0, 0.0), near);
        assert_eq!(hand.state(), HandState::Hovering(b));
        let s = hand.update(&input(0.9, 0.0), near);
        assert_eq!(s.event, Some(HandEvent::Grabbed(b)));
        assert!(matches!(s.command, Some(HandCommand::Grab { body, .. }) if body == b));
        // Held while the grip stays above the let-go value, whatever is near.
        let s = hand.update(&input(0.5, 0.2), None);
        assert!(
            matches!(s.command, Some(HandCommand::Grab { hand, .. }) if hand.position.x == 0.2)
        );
        assert_eq!(s.event, None);
        let s = hand.update(&input(0.1, 0.2), None);
        let Some(HandCommand::Release { linvel, angvel, .. }) = s.command else {
            panic!("{s:?}")
        };
        // v + ω × r with r = (0, 0.1, 0): (2, 1, 0) + (0, 0, 1) × (0, 0.1, 0) = (1.9, 1, 0).
        assert!(
            (linvel - Vec3::new(1.9, 1.0, 0.0)).length() < 1e-5,
            "{linvel}"
        );
        assert_eq!(angvel, Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(s.event, Some(HandEvent::Released(b)));
        assert_eq!(hand.state(), HandState::Idle);
    }

    #[test]
    fn a_closed_fist_does_not_pick_things_up() {
        let near = Some((BodyId(0), Vec3::ZERO));
        let mut hand = Hand::new();
        hand.update(&input(1.0, 0.0), None);
        let s = hand.update(&input(1.0, 0.0), near);
        assert_eq!(s.command, None);
        assert_eq!(hand.state(), HandState::Hovering(BodyId(0)));
        // NaN grip opens the hand; the next press grabs.
        hand.update(&input(f32::NAN, 0.0), near);
        let s = hand.update(&input(0.8, 0.0), near);
        assert_eq!(s.event, Some(HandEvent::Grabbed(BodyId(0))));
    }
}
