//! Fly-around head control for the window: WASD moves in the horizontal plane, Q/E lowers and
//! raises the head (Q takes it under the water, to [`DEEPEST_M`]), the mouse (while a button
//! is held) turns it. Pure state, no window types, so it is tested without a display.

use glam::{Quat, Vec3};

use super::path::head_orientation;

/// The deepest the head goes under the mean sea (m): the daylight there is a few percent of
/// the surface's in the blue, and nothing below is drawn (no sea floor).
pub const DEEPEST_M: f32 = 50.0;

/// The movement keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MoveKey {
    /// W.
    Forward,
    /// S.
    Back,
    /// A.
    Left,
    /// D.
    Right,
    /// E.
    Up,
    /// Q.
    Down,
    /// Shift: 5× speed.
    Fast,
}

/// Keyboard-and-mouse head pose.
#[derive(Clone, Debug)]
pub struct FlyControls {
    /// Head position (m).
    pub position: Vec3,
    /// Yaw (degrees, positive left).
    pub yaw: f32,
    /// Pitch (degrees, positive up), kept in [−89, 89].
    pub pitch: f32,
    /// Walking speed (m/s).
    pub speed: f32,
    /// Degrees per pixel of mouse motion.
    pub sensitivity: f32,
    held: [bool; 7],
}

impl FlyControls {
    /// Starts standing at `position` looking along `yaw`/`pitch`.
    pub fn new(position: Vec3, yaw: f32, pitch: f32) -> Self {
        Self {
            position,
            yaw,
            pitch: pitch.clamp(-89.0, 89.0),
            speed: 4.0,
            sensitivity: 0.15,
            held: [false; 7],
        }
    }

    /// A key went down (`true`) or up.
    pub fn key(&mut self, key: MoveKey, down: bool) {
        self.held[key as usize] = down;
    }

    /// Whether `key` is held.
    pub fn held(&self, key: MoveKey) -> bool {
        self.held[key as usize]
    }

    /// Lets go of every key (the window lost focus, so key releases would be missed).
    pub fn release_all(&mut self) {
        self.held = [false; 7];
    }

    /// The mouse moved by (dx, dy) pixels while turning.
    pub fn look(&mut self, dx: f64, dy: f64) {
        self.yaw -= dx as f32 * self.sensitivity;
        self.yaw = self.yaw.rem_euclid(360.0);
        self.pitch = (self.pitch - dy as f32 * self.sensitivity).clamp(-89.0, 89.0);
    }

    /// Advances `dt` seconds of movement.
    pub fn update(&mut self, dt: f32) {
        let h = |k: MoveKey| if self.held[k as usize] { 1.0 } else { 0.0 };
        let yaw = Quat::from_rotation_y(self.yaw.to_radians());
        let forward = yaw * Vec3::NEG_Z;
        let right = yaw * Vec3::X;
        let dir = forward * (h(MoveKey::Forward) - h(MoveKey::Back))
            + right * (h(MoveKey::Right) - h(MoveKey::Left))
            + Vec3::Y * (h(MoveKey::Up) - h(MoveKey::Down));
        let speed = self.speed
            * if self.held[MoveKey::Fast as usize] {
                5.0
            } else {
                1.0
            };
        self.position += dir * speed * dt;
        // Keep the head within the water's lit depths and the LOD's coordinate range.
        self.position.y = self.position.y.clamp(-DEEPEST_M, 5000.0);
        let lim = 1.0e6;
        self.position.x = self.position.x.clamp(-lim, lim);
        self.position.z = self.position.z.clamp(-lim, lim);
    }

    /// The head pose.
    pub fn pose(&self) -> (Vec3, Quat) {
        (self.position, head_orientation(self.yaw, self.pitch))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walks_where_it_looks_and_clamps_pitch() {
        let mut c = FlyControls::new(Vec3::new(0.0, 1.7, 0.0), 90.0, 0.0);
        c.key(MoveKey::Forward, true);
        c.update(1.0);
        assert!(
            (c.position - Vec3::new(-4.0, 1.7, 0.0)).length() < 1e-4,
            "{}",
            c.position
        );
        c.key(MoveKey::Forward, false);
        c.key(MoveKey::Down, true);
        c.update(1.0);
        assert!(
            (c.position.y + 2.3).abs() < 1e-4,
            "Q goes under the water: {}",
            c.position
        );
        c.update(100.0);
        assert_eq!(c.position.y, -DEEPEST_M);
        c.look(0.0, -10_000.0);
        assert_eq!(c.pitch, 89.0);
    }
}
