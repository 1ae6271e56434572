//! Moving a tracked user over the water: the world pose of the runtime's tracking space. The
//! left thumbstick glides head-relative over the sea, the right one snap-turns about the head;
//! tracked poses are mapped into the world by [`Locomotion::to_world`].

use glam::{Quat, Vec2, Vec3};

/// How the thumbsticks move the user.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocomotionSettings {
    /// Glide speed at full stick (m/s).
    pub speed: f32,
    /// One snap turn (rad).
    pub snap_angle: f32,
    /// Stick deflection below which it counts as centred.
    pub dead_zone: f32,
    /// Sideways deflection that triggers a snap turn.
    pub snap_threshold: f32,
    /// Deflection below which the next snap turn is armed again.
    pub snap_release: f32,
    /// Turn smoothly with the stick (at [`SMOOTH_TURN_SPEED`] at full deflection) instead of
    /// in snaps.
    pub smooth_turn: bool,
}

/// Turning speed of smooth turning at full stick (rad/s): 90°/s, slow enough for most users.
pub const SMOOTH_TURN_SPEED: f32 = std::f32::consts::FRAC_PI_2;

/// How much higher a seated user's floor is put (m): a standing eye height (1.7 m) less a
/// seated one (1.2 m), so they see the sea from the deck as if standing.
pub const SEATED_RAISE: f32 = 0.5;

impl Default for LocomotionSettings {
    fn default() -> Self {
        Self {
            speed: 4.0,
            snap_angle: 30f32.to_radians(),
            dead_zone: 0.15,
            snap_threshold: 0.7,
            snap_release: 0.3,
            smooth_turn: false,
        }
    }
}

/// Where the tracking space sits in the world, and the stick state that moves it.
#[derive(Clone, Copy, Debug)]
pub struct Locomotion {
    settings: LocomotionSettings,
    /// The origin the session started with: the deck.
    home: Vec3,
    origin: Vec3,
    yaw: f32,
    snap_armed: bool,
    /// The floor's raise above the deck for a seated user (m).
    raised: f32,
    /// The origin's height the session started with (m).
    start_height: f32,
}

impl Locomotion {
    /// Tracking space origin at `origin` in the world (its y is the height of the tracking
    /// floor, or of the LOCAL space's eye level, above the mean sea level).
    pub fn new(origin: Vec3, settings: LocomotionSettings) -> Self {
        Self {
            settings,
            home: origin,
            origin,
            yaw: 0.0,
            snap_armed: true,
            raised: 0.0,
            start_height: origin.y,
        }
    }

    /// One frame of input: `head` is the head pose in tracking space, `glide` the left stick
    /// (x right, y forward), `turn_x` the right stick's sideways deflection, `dt` the frame
    /// period (s). Returns whether a snap turn happened.
    pub fn update(
        &mut self,
        head_position: Vec3,
        head_orientation: Quat,
        glide: Vec2,
        turn_x: f32,
        dt: f32,
    ) -> bool {
        let s = self.settings;
        if glide.length() > s.dead_zone && dt.is_finite() && dt > 0.0 {
            let (_, world_head) = self.to_world(head_position, head_orientation);
            let forward = world_head * Vec3::NEG_Z;
            let flat_forward = Vec3::new(forward.x, 0.0, forward.z).normalize_or_zero();
            let right = Vec3::new(-flat_forward.z, 0.0, flat_forward.x);
            let stick = glide.clamp_length_max(1.0);
            self.origin += (flat_forward * stick.y + right * stick.x) * s.speed * dt;
        }
        let mut turned = false;
        if s.smooth_turn {
            if turn_x.abs() > s.dead_zone && dt.is_finite() && dt > 0.0 {
                self.turn_about_head(
                    head_position,
                    head_orientation,
                    -turn_x.clamp(-1.0, 1.0) * SMOOTH_TURN_SPEED * dt,
                );
            }
        } else if self.snap_armed && turn_x.abs() >= s.snap_threshold {
            self.turn_about_head(
                head_position,
                head_orientation,
                -turn_x.signum() * s.snap_angle,
            );
            self.snap_armed = false;
            turned = true;
        } else if turn_x.abs() < s.snap_release {
            self.snap_armed = true;
        }
        turned
    }

    /// Turns by `angle` (rad, positive to the left) about the head, so its world position
    /// stays where it is.
    fn turn_about_head(&mut self, head_position: Vec3, head_orientation: Quat, angle: f32) {
        let (head_before, _) = self.to_world(head_position, head_orientation);
        self.yaw += angle;
        let (head_after, _) = self.to_world(head_position, head_orientation);
        self.origin += head_before - head_after;
    }

    /// Takes the user's comfort options: the snap-turn angle (degrees), smooth turning,
    /// seated (the floor raised by [`SEATED_RAISE`]) and the deck moved `deck_raise` metres
    /// above where the session started it (the floor moves with it).
    pub fn set_comfort(&mut self, snap_deg: f32, smooth: bool, seated: bool, deck_raise: f32) {
        if snap_deg.is_finite() && snap_deg > 0.0 {
            self.settings.snap_angle = snap_deg.to_radians();
        }
        self.settings.smooth_turn = smooth;
        self.raised = if seated { SEATED_RAISE } else { 0.0 };
        if deck_raise.is_finite() {
            self.home.y = self.start_height + deck_raise;
        }
        self.origin.y = self.home.y + self.raised;
    }

    /// Re-anchors the user on the deck: the head (tracking-space pose `head_position`,
    /// `head_orientation`) goes back over the deck's centre, facing the world's −z (the view the
    /// session started with), at the deck's height. For a user who glided away or stands
    /// turned in the room.
    pub fn recenter(&mut self, head_position: Vec3, head_orientation: Quat) {
        let forward = head_orientation * Vec3::NEG_Z;
        // The head's heading in tracking space (0 looks along −z, positive turns left).
        let heading = (-forward.x).atan2(-forward.z);
        if forward.x.abs() + forward.z.abs() > 1e-4 {
            self.yaw = -heading;
        }
        let r = Quat::from_rotation_y(self.yaw);
        let head = r * head_position;
        self.origin = Vec3::new(
            self.home.x - head.x,
            self.home.y + self.raised,
            self.home.z - head.z,
        );
    }

    /// A tracking-space pose in the world.
    pub fn to_world(&self, position: Vec3, orientation: Quat) -> (Vec3, Quat) {
        let r = Quat::from_rotation_y(self.yaw);
        (self.origin + r * position, r * orientation)
    }

    /// The tracking space's rotation about +y (rad).
    pub fn yaw(&self) -> f32 {
        self.yaw
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recentring_puts_the_head_back_over_the_deck_facing_forward() {
        let home = Vec3::new(0.0, 2.9, 0.0);
        let mut l = Locomotion::new(home, LocomotionSettings::default());
        // Glide away and snap-turn twice, while standing 1 m off the room's centre, turned.
        let head = Vec3::new(1.0, 1.7, -0.5);
        let turned = Quat::from_rotation_y(0.7) * Quat::from_rotation_x(-0.2);
        for _ in 0..200 {
            l.update(head, turned, Vec2::new(0.3, 1.0), 0.0, 1.0 / 72.0);
        }
        l.update(head, turned, Vec2::ZERO, 1.0, 1.0 / 72.0);
        l.update(head, turned, Vec2::ZERO, 0.0, 1.0 / 72.0);
        l.update(head, turned, Vec2::ZERO, 1.0, 1.0 / 72.0);
        let (away, _) = l.to_world(head, turned);
        assert!(Vec2::new(away.x, away.z).length() > 5.0, "{away}");
        l.recenter(head, turned);
        let (p, q) = l.to_world(head, turned);
        assert!(close(Vec3::new(p.x, 0.0, p.z), Vec3::ZERO), "head at {p}");
        assert!((p.y - (home.y + head.y)).abs() < 1e-4, "height {}", p.y);
        let f = q * Vec3::NEG_Z;
        let flat = Vec3::new(f.x, 0.0, f.z).normalize();
        assert!(close(flat, Vec3::NEG_Z), "facing {flat}");
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-4
    }

    #[test]
    fn glide_follows_the_head_not_the_tracking_axes() {
        let mut l = Locomotion::new(Vec3::new(0.0, 3.0, 0.0), LocomotionSettings::default());
        // Head turned 90° left (looking along −x), stick fully forward for 1 s.
        let head = Quat::from_rotation_y(90f32.to_radians());
        l.update(Vec3::ZERO, head, Vec2::new(0.0, 1.0), 0.0, 1.0);
        let (p, _) = l.to_world(Vec3::ZERO, head);
        assert!(close(p, Vec3::new(-4.0, 3.0, 0.0)), "{p}");
        // Looking down steeply still glides level.
        let down = Quat::from_rotation_x(-80f32.to_radians());
        l.update(Vec3::ZERO, down, Vec2::new(0.0, 0.5), 0.0, 1.0);
        let (p2, _) = l.to_world(Vec3::ZERO, down);
        assert!((p2.y - 3.0).abs() < 1e-5 && (p2 - p).length() > 1.9, "{p2}");
    }

    #[test]
    fn stick_inside_the_dead_zone_does_not_drift() {
        let mut l = Locomotion::new(Vec3::ZERO, LocomotionSettings::default());
        for _ in 0..1000 {
            l.update(Vec3::ZERO, Quat::IDENTITY, Vec2::new(0.1, -0.1), 0.0, 0.014);
        }
        assert_eq!(l.to_world(Vec3::ZERO, Quat::IDENTITY).0, Vec3::ZERO);
    }

    #[test]
    fn comfort_turns_smoothly_raises_a_seated_floor_and_moves_with_the_deck() {
        let mut l = Locomotion::new(Vec3::new(0.0, 2.0, 0.0), LocomotionSettings::default());
        let head = Vec3::new(0.3, 1.2, 0.1);
        l.set_comfort(45.0, true, true, 1.0);
        assert!(
            (l.to_world(head, Quat::IDENTITY).0.y - (1.2 + 2.0 + 1.0 + SEATED_RAISE)).abs() < 1e-6
        );
        // Smooth: a full stick for half a second turns 45° about the head, no snap.
        let before = l.to_world(head, Quat::IDENTITY).0;
        for _ in 0..50 {
            assert!(!l.update(head, Quat::IDENTITY, Vec2::ZERO, 1.0, 0.01));
        }
        assert!(
            (l.yaw() + SMOOTH_TURN_SPEED * 0.5).abs() < 1e-4,
            "{}",
            l.yaw()
        );
        assert!((l.to_world(head, Quat::IDENTITY).0 - before).length() < 1e-4);
        // Inside the dead zone nothing turns.
        let yaw = l.yaw();
        l.update(head, Quat::IDENTITY, Vec2::ZERO, 0.1, 0.5);
        assert_eq!(l.yaw(), yaw);
        // Snapping again, by the new angle; standing, the deck back where it was.
        l.set_comfort(45.0, false, false, 0.0);
        assert!(l.update(head, Quat::IDENTITY, Vec2::ZERO, 1.0, 0.01));
        assert!((l.yaw() - yaw + 45f32.to_radians()).abs() < 1e-5);
        assert!((l.to_world(head, Quat::IDENTITY).0.y - 3.2).abs() < 1e-6);
    }

    #[test]
    fn snap_turn_is_once_per_flick_and_keeps_the_head_in_place() {
        let mut l = Locomotion::new(Vec3::new(5.0, 2.0, -1.0), LocomotionSettings::default());
        let head = Vec3::new(0.4, 1.6, 0.3);
        let (before, _) = l.to_world(head, Quat::IDENTITY);
        let mut turns = 0;
        // Held right for 30 frames: one turn.
        for _ in 0..30 {
            turns += l.update(head, Quat::IDENTITY, Vec2::ZERO, 0.9, 0.014) as u32;
        }
        assert_eq!(turns, 1);
        assert!(
            (l.yaw() + 30f32.to_radians()).abs() < 1e-6,
            "right turns clockwise"
        );
        let (after, q) = l.to_world(head, Quat::IDENTITY);
        assert!(close(before, after), "{before} vs {after}");
        // Facing turned right: forward is now rotated −30° about y.
        let f = q * Vec3::NEG_Z;
        assert!(f.x > 0.49 && f.x < 0.51, "{f}");
        // Between the thresholds nothing re-arms; released, the next flick turns again.
        turns += l.update(head, Quat::IDENTITY, Vec2::ZERO, 0.5, 0.014) as u32;
        turns += l.update(head, Quat::IDENTITY, Vec2::ZERO, 0.9, 0.014) as u32;
        assert_eq!(turns, 1);
        l.update(head, Quat::IDENTITY, Vec2::ZERO, 0.0, 0.014);
        turns += l.update(head, Quat::IDENTITY, Vec2::ZERO, -0.8, 0.014) as u32;
        assert_eq!(turns, 2);
        assert!(l.yaw().abs() < 1e-6);
    }
}
