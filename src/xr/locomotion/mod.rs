//! Moving a tracked user over the water: the world pose of the runtime's tracking space. The
//! left thumbstick glides head-relative over the sea (or swims, in the water), the right one
//! snap-turns about the head; tracked poses are mapped into the world by
//! [`Locomotion::to_world`]. In the water ([`float`]) the tracking space's height follows the
//! sea under the head, so the user floats; the comfort vignette's strength follows how fast
//! the view is moved for the user.

pub mod float;

use glam::{Quat, Vec2, Vec3};

use float::{Afloat, FloatSettings};

/// How far from the deck's centre a user entering the water comes up (m): off the default
/// deck's edge (half of 4 m) by a body length.
pub const WATER_ENTRY_DISTANCE: f32 = 3.5;

/// View speed at which the comfort vignette is at full strength (m/s); turning smoothly at
/// [`SMOOTH_TURN_SPEED`] counts as this much.
pub const VIGNETTE_FULL_SPEED: f32 = 2.0;

/// Time constant of the vignette's easing in and out (s).
pub const VIGNETTE_EASE_S: f32 = 0.15;

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
    /// In the water: the float state and the tracked head's height when the user went in
    /// (the reference the eyes' height is set from, so the user's own head motion still
    /// moves the view).
    water: Option<(Afloat, f32)>,
    /// Ride the waves in the water (false: a fixed height).
    ride: bool,
    /// Whether the comfort vignette is on.
    vignette_on: bool,
    /// The vignette's strength now, 0 (none) to 1.
    vignette: f32,
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
            water: None,
            ride: true,
            vignette_on: true,
            vignette: 0.0,
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
        let speed = match &self.water {
            Some((afloat, _)) => afloat.settings().swim_speed,
            None => s.speed,
        };
        // The speed the view is moved at, for the vignette: the ride's, the stick's, a turn's.
        let mut moved = self.water.map_or(0.0, |(a, _)| a.vertical_speed().abs());
        if glide.length() > s.dead_zone && dt.is_finite() && dt > 0.0 {
            let (_, world_head) = self.to_world(head_position, head_orientation);
            let forward = world_head * Vec3::NEG_Z;
            let flat_forward = Vec3::new(forward.x, 0.0, forward.z).normalize_or_zero();
            let right = Vec3::new(-flat_forward.z, 0.0, flat_forward.x);
            let stick = glide.clamp_length_max(1.0);
            self.origin += (flat_forward * stick.y + right * stick.x) * speed * dt;
            moved += stick.length() * speed;
        }
        let mut turned = false;
        if s.smooth_turn {
            if turn_x.abs() > s.dead_zone && dt.is_finite() && dt > 0.0 {
                let rate = turn_x.clamp(-1.0, 1.0) * SMOOTH_TURN_SPEED;
                self.turn_about_head(head_position, head_orientation, -rate * dt);
                moved += rate.abs() / SMOOTH_TURN_SPEED * VIGNETTE_FULL_SPEED;
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
        if dt.is_finite() && dt > 0.0 {
            let target = if self.vignette_on {
                (moved / VIGNETTE_FULL_SPEED).min(1.0)
            } else {
                0.0
            };
            let a = 1.0 - (-dt / VIGNETTE_EASE_S).exp();
            self.vignette += (target - self.vignette) * a;
        }
        turned
    }

    /// In the water, before [`Locomotion::update`] each frame: `surface` is the sea's height
    /// under the head (the mean over the body's footprint, m over the mean level; `None`
    /// when unknown), `duck` whether the duck button is held. The tracking space is lifted so
    /// the eyes float ([`float`]) when the tracked head is as high as it was at the entry
    /// (the user's own motion still moves the view). On the deck nothing happens.
    pub fn ride(&mut self, surface: Option<f32>, duck: bool, dt: f32) {
        let Some((afloat, reference)) = self.water.as_mut() else {
            return;
        };
        let eyes = afloat.step(surface, duck, dt);
        self.origin.y = eyes - *reference;
    }

    /// Goes into the water: the head comes up [`WATER_ENTRY_DISTANCE`] from the deck's centre
    /// the way it faces, floating, with the current comfort options. `surface` is the sea's
    /// height there, if known. Already in the water: nothing changes.
    pub fn enter_water(
        &mut self,
        head_position: Vec3,
        head_orientation: Quat,
        surface: Option<f32>,
    ) {
        if self.water.is_some() {
            return;
        }
        let (_, q) = self.to_world(head_position, head_orientation);
        let f = q * Vec3::NEG_Z;
        let flat = Vec3::new(f.x, 0.0, f.z).normalize_or(Vec3::NEG_Z);
        let target = self.home + flat * WATER_ENTRY_DISTANCE;
        let r = Quat::from_rotation_y(self.yaw);
        let head = r * head_position;
        self.origin.x = target.x - head.x;
        self.origin.z = target.z - head.z;
        let mut afloat = Afloat::new(FloatSettings::default(), self.ride);
        let eyes = afloat.step(surface, false, 0.0);
        self.water = Some((afloat, head_position.y));
        self.origin.y = eyes - head_position.y;
    }

    /// Climbs out: back on the deck, re-anchored over its centre ([`Locomotion::recenter`]).
    pub fn leave_water(&mut self, head_position: Vec3, head_orientation: Quat) {
        self.water = None;
        self.recenter(head_position, head_orientation);
    }

    /// Whether the user is in the water.
    pub fn in_water(&self) -> bool {
        self.water.is_some()
    }

    /// The comfort vignette's strength now: 0 (none) to 1 (the view narrowed most).
    pub fn vignette(&self) -> f32 {
        self.vignette
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
    /// In the water the floor's height is the float's, so only the deck's home moves.
    pub fn set_comfort(&mut self, snap_deg: f32, smooth: bool, seated: bool, deck_raise: f32) {
        if snap_deg.is_finite() && snap_deg > 0.0 {
            self.settings.snap_angle = snap_deg.to_radians();
        }
        self.settings.smooth_turn = smooth;
        self.raised = if seated { SEATED_RAISE } else { 0.0 };
        if deck_raise.is_finite() {
            self.home.y = self.start_height + deck_raise;
        }
        if self.water.is_none() {
            self.origin.y = self.home.y + self.raised;
        }
    }

    /// The water's comfort options: ride the waves (false: the eyes at a fixed height over
    /// the mean level) and the vignette while the view is moved.
    pub fn set_water_comfort(&mut self, ride: bool, vignette: bool) {
        self.ride = ride;
        self.vignette_on = vignette;
        if let Some((afloat, _)) = self.water.as_mut() {
            afloat.set_ride(ride);
        }
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

    #[test]
    fn into_the_water_the_head_floats_swims_ducks_and_climbs_back_out() {
        let home = Vec3::new(0.0, 2.9, 0.0);
        let mut l = Locomotion::new(home, LocomotionSettings::default());
        // Standing 1.7 m tall, facing +x (turned 90° right).
        let head = Vec3::new(0.2, 1.7, 0.1);
        let q = Quat::from_rotation_y(-90f32.to_radians());
        l.enter_water(head, q, Some(0.4));
        assert!(l.in_water());
        let (p, _) = l.to_world(head, q);
        assert!(close(p, Vec3::new(WATER_ENTRY_DISTANCE, 0.55, 0.0)), "{p}");
        // The head rides a slow swell: its height follows the water's, 15 cm over it.
        let dt = 1.0 / 72.0;
        for i in 0..720 {
            let h = (i as f32 * dt * 0.8).sin();
            l.ride(Some(h), false, dt);
            l.update(head, q, Vec2::ZERO, 0.0, dt);
            let y = l.to_world(head, q).0.y;
            if i > 72 {
                assert!(
                    (y - h - 0.15).abs() < 0.085,
                    "frame {i}: eyes {y} over water {h}"
                );
            }
        }
        // The user's own head motion still moves the view (crouching 30 cm).
        let low = head - Vec3::Y * 0.3;
        assert!((l.to_world(head, q).0.y - l.to_world(low, q).0.y - 0.3).abs() < 1e-5);
        // Swimming is slower than gliding: 1 s of full stick forward.
        let before = l.to_world(head, q).0;
        l.ride(Some(0.0), false, 1.0);
        l.update(head, q, Vec2::new(0.0, 1.0), 0.0, 1.0);
        let after = l.to_world(head, q).0;
        let swim = FloatSettings::default().swim_speed;
        assert!(
            (after.x - before.x - swim).abs() < 1e-4,
            "{before} -> {after}"
        );
        // Ducking takes the eyes under.
        for _ in 0..300 {
            l.ride(Some(0.0), true, dt);
            l.update(head, q, Vec2::ZERO, 0.0, dt);
        }
        assert!(
            l.to_world(head, q).0.y < -1.0,
            "{}",
            l.to_world(head, q).0.y
        );
        // Out: back over the deck, standing on it.
        l.leave_water(head, q);
        assert!(!l.in_water());
        let (p, _) = l.to_world(head, q);
        assert!(close(p, Vec3::new(0.0, 2.9 + 1.7, 0.0)), "{p}");
    }

    #[test]
    fn the_vignette_follows_the_moved_view_and_can_be_turned_off() {
        let mut l = Locomotion::new(Vec3::new(0.0, 2.9, 0.0), LocomotionSettings::default());
        let dt = 1.0 / 72.0;
        let step = |l: &mut Locomotion, stick: f32| {
            for _ in 0..72 {
                l.update(Vec3::Y, Quat::IDENTITY, Vec2::new(0.0, stick), 0.0, dt);
            }
            l.vignette()
        };
        assert_eq!(step(&mut l, 0.0), 0.0);
        // Gliding at 4 m/s: full; half a stick of it (2 m/s) too; standing still: gone.
        assert!(step(&mut l, 1.0) > 0.99);
        assert!(step(&mut l, 0.0) < 0.01);
        let swim = {
            l.enter_water(Vec3::Y, Quat::IDENTITY, Some(0.0));
            step(&mut l, 1.0)
        };
        // Swimming at 1.2 m/s: 60 %.
        assert!((swim - 0.6).abs() < 0.01, "{swim}");
        l.set_water_comfort(true, false);
        assert!(step(&mut l, 1.0) < 0.01);
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
