//! The grab-and-throw state machine driven by scripted controller input against a real world:
//! a hand out of reach does nothing, in reach it hovers, the grip grabs (a haptic event), the
//! held body follows the hand, the let-go throws it with the hand's linear velocity plus
//! ω × r and its angular velocity, and it then flies ballistically. The window's throw key
//! (`throw_from`) launches a crate along the view.

use std::time::Duration;

use glam::{Quat, Vec3};
use vr_ocean::physics::hands::GRAB_REACH;
use vr_ocean::physics::{
    BodySpec, BodyState, Floaters, Hand, HandCommand, HandEvent, HandInput, HandState,
    PhysicsConfig, Pose, PHYSICS_DT,
};
use vr_ocean::sim::{OceanConfig, Surfaces};

const FRAME: Duration = Duration::from_nanos(1_000_000_000 / 90);

struct Rig {
    world: Floaters,
    calm: Surfaces,
    hand: Hand,
}

impl Rig {
    /// One frame: the hand reports `input`, the app finds the body in reach, runs the machine,
    /// applies its command, then advances the physics. Returns the machine's event.
    fn frame(&mut self, input: HandInput) -> Option<HandEvent> {
        let near = self
            .world
            .nearest_body(input.pose.position, GRAB_REACH)
            .and_then(|id| Some((id, self.world.center_of_mass(id)?)));
        let step = self.hand.update(&input, near);
        if let Some(c) = step.command {
            self.world.apply(&c).unwrap();
        }
        self.world.advance(FRAME, &self.calm);
        step.event
    }
}

fn input(grip: f32, position: Vec3) -> HandInput {
    HandInput {
        grip,
        pose: Pose {
            position,
            rotation: Quat::from_rotation_y(0.3),
        },
        linvel: Vec3::ZERO,
        angvel: Vec3::ZERO,
    }
}

#[test]
fn grab_hold_and_throw_with_the_hands_velocity() {
    let mut rig = Rig {
        world: Floaters::new(PhysicsConfig::default()).unwrap(),
        calm: Surfaces::new(&OceanConfig::single(64, 100.0).unwrap()),
        hand: Hand::new(),
    };
    let deck = rig.world.deck().unwrap().height;
    let spec = BodySpec::crate_box(Vec3::splat(0.3), 400.0).unwrap();
    let id = rig
        .world
        .spawn(spec, Pose::at(Vec3::new(0.5, deck + 0.15, 0.0)))
        .unwrap();
    // It rests on the deck.
    for _ in 0..90 {
        rig.world.advance(FRAME, &rig.calm);
    }
    let rest = rig.world.pose(id).unwrap().position;
    assert!((rest.y - (deck + 0.15)).abs() < 0.01, "on the deck: {rest}");

    // Out of reach: idle. Within reach (5 cm from its side), open: hovering, no event.
    let far = rest + Vec3::new(0.0, 0.0, 0.4);
    assert_eq!(rig.frame(input(0.0, far)), None);
    assert_eq!(rig.hand.state(), HandState::Idle);
    let near = rest + Vec3::new(0.0, 0.0, 0.2);
    assert_eq!(rig.frame(input(0.0, near)), None);
    assert_eq!(rig.hand.state(), HandState::Hovering(id));

    // Grip: grabbed, the haptic event fires once.
    assert_eq!(rig.frame(input(0.9, near)), Some(HandEvent::Grabbed(id)));
    assert_eq!(rig.world.state(id), Some(BodyState::Held));
    let offset = rest - near;

    // Hold while the hand rises 0.6 m and moves 0.3 m sideways over half a second.
    let mut worst = 0.0f32;
    for i in 1..=45 {
        let s = i as f32 / 45.0;
        let hand_at = near + Vec3::new(0.3 * s, 0.6 * s, 0.0);
        assert_eq!(rig.frame(input(0.8, hand_at)), None);
        assert!(matches!(rig.hand.state(), HandState::Holding { .. }));
        let lag = (rig.world.pose(id).unwrap().position - (hand_at + offset)).length();
        worst = worst.max(lag);
    }
    // A hold sets the velocity that reaches the hand's target in one step, and the frame's
    // step runs after the hand moved: the body is where the hand holds it (within 5 mm; the
    // hand moves 15 mm a frame).
    let per_frame = Vec3::new(0.3, 0.6, 0.0).length() / 45.0;
    println!(
        "held body's largest distance from its place in the hand: {worst:.4} m (hand moves \
         {per_frame:.4} m a frame)"
    );
    assert!(worst < 0.005, "held body lags {worst} m");

    // Let go with the hand moving and turning: thrown with v + ω × r, ω.
    let hand_at = near + Vec3::new(0.3, 0.6, 0.0);
    let mut let_go = input(0.1, hand_at);
    let_go.linvel = Vec3::new(3.0, 2.0, -1.0);
    let_go.angvel = Vec3::new(0.0, 0.0, 4.0);
    let near_body = rig.world.center_of_mass(id).unwrap();
    let step = {
        let n = Some((id, near_body));
        rig.hand.update(&let_go, n)
    };
    assert_eq!(step.event, Some(HandEvent::Released(id)));
    let Some(HandCommand::Release { linvel, angvel, .. }) = step.command else {
        panic!("{step:?}")
    };
    // r is the body's centre from the hand as held at the grab (in the hand's frame, turned
    // by the hand's rotation now: the same rotation here).
    let expect_v = let_go.linvel + let_go.angvel.cross(offset);
    assert!(
        (linvel - expect_v).length() < 1e-4,
        "{linvel} vs {expect_v}"
    );
    assert_eq!(angvel, let_go.angvel);
    rig.world.apply(step.command.as_ref().unwrap()).unwrap();
    let (v0, w0) = rig.world.velocity(id).unwrap();
    assert!((v0 - expect_v).length() < 1e-5 && (w0 - angvel).length() < 1e-5);
    assert_eq!(rig.world.state(id), Some(BodyState::Floating));
    assert_eq!(rig.hand.state(), HandState::Idle);

    // Ballistic flight: after 0.3 s it is where v·t − ½g·t² puts it (it clears the deck).
    let p0 = rig.world.pose(id).unwrap().position;
    let steps = 27;
    for _ in 0..steps {
        rig.world.step(&rig.calm);
    }
    let t = steps as f32 * PHYSICS_DT;
    let g = rig.world.config().gravity;
    let expect = p0 + expect_v * t + Vec3::new(0.0, -0.5 * g * t * t, 0.0);
    let p = rig.world.pose(id).unwrap().position;
    let (_, w) = rig.world.velocity(id).unwrap();
    println!(
        "thrown at {expect_v} m/s spinning {angvel} rad/s: after {t:.2} s at {p}, ballistic \
         prediction {expect} ({:.4} m apart), spin {w}",
        (p - expect).length()
    );
    assert!((p - expect).length() < 0.02, "{p} vs {expect}");
    assert!((w - angvel).length() < 0.05, "spin kept in the air: {w}");
}

#[test]
fn the_throw_key_launches_a_crate_along_the_view() {
    let calm = Surfaces::new(&OceanConfig::single(64, 100.0).unwrap());
    let mut world = Floaters::new(PhysicsConfig::default()).unwrap();
    let eye = Vec3::new(0.0, 4.6, 0.0);
    let dir = Vec3::new(0.0, 0.2, -1.0);
    let id = world.throw_from(eye, dir, 8.0).unwrap();
    let (v, _) = world.velocity(id).unwrap();
    assert!((v - dir.normalize() * 8.0).length() < 1e-4, "{v}");
    // It lands in the water ahead, beyond the deck's edge, and floats.
    for _ in 0..(8.0 / PHYSICS_DT) as usize {
        world.step(&calm);
    }
    let p = world.pose(id).unwrap().position;
    assert!(p.z < -2.5 && p.y.abs() < 0.3, "floating ahead: {p}");
    // Bad throws are refused with what to change.
    let e = world.throw_from(eye, Vec3::ZERO, 8.0).unwrap_err();
    assert!(e.to_string().contains("throw direction"), "{e}");
    let e = world.throw_from(eye, dir, 100.0).unwrap_err();
    assert!(e.to_string().contains("0 to 30 m/s"), "{e}");
}
