//! Where the headset's control panel floats and what the controllers do to it (issue 31),
//! pure: the quad placed at arm's length in front of the head when it opens ([`PanelQuad`]),
//! the aim rays intersected with it in panel pixels, and the hands' aims, triggers and the
//! menu button turned into the panel's [`PointerEvent`]s ([`AimPointer`]). Everything is in
//! the session's tracking space, so the panel travels with the user when they glide or turn.

use glam::{Quat, Vec3};

use crate::ui::panel::PointerEvent;
use crate::xr::MAX_POINTER_EVENTS;

/// The panel's width (m): 0.5 m at [`PANEL_DISTANCE`] spans 42° of view, so its 1100 pixels
/// (440 points at 2.5 pixels per point) are about 26 per degree, the Quest 3's display density.
pub const PANEL_WIDTH: f32 = 0.5;

/// How far in front of the eyes the panel opens (m): arm's length.
pub const PANEL_DISTANCE: f32 = 0.65;

/// How far below the eyes its centre sits (m): a comfortable downward glance.
pub const PANEL_DROP: f32 = 0.12;

/// The quad: its pose in tracking space and its size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PanelQuad {
    /// Centre of the quad.
    pub centre: Vec3,
    /// Orientation: the quad lies in its local XY plane, its front facing +Z.
    pub orientation: Quat,
    /// Width and height (m).
    pub size: [f32; 2],
    /// The image's size (pixels).
    pub pixels: [u32; 2],
}

impl PanelQuad {
    /// The quad for an image of `pixels`, [`PANEL_DISTANCE`] in front of a head at `head`
    /// looking along `view`, level (turned only about the vertical), facing the head.
    pub fn in_front_of(head: Vec3, view: Quat, pixels: [u32; 2]) -> Self {
        let forward = view * Vec3::NEG_Z;
        let flat = Vec3::new(forward.x, 0.0, forward.z)
            .try_normalize()
            .unwrap_or(Vec3::NEG_Z);
        let yaw = (-flat.x).atan2(-flat.z);
        let aspect = pixels[1].max(1) as f32 / pixels[0].max(1) as f32;
        Self {
            centre: head + flat * PANEL_DISTANCE - Vec3::Y * PANEL_DROP,
            orientation: Quat::from_rotation_y(yaw),
            size: [PANEL_WIDTH, PANEL_WIDTH * aspect],
            pixels,
        }
    }

    /// The image pixel a ray from `origin` along `direction` meets on the quad's front, and
    /// the distance to it; `None` when it misses or comes from behind.
    pub fn hit(&self, origin: Vec3, direction: Vec3) -> Option<([f32; 2], f32)> {
        let inv = self.orientation.inverse();
        let o = inv * (origin - self.centre);
        let d = inv * direction.try_normalize()?;
        if o.z <= 0.0 || d.z >= -1e-6 {
            return None;
        }
        let t = -o.z / d.z;
        let p = o + d * t;
        let [w, h] = self.size;
        if p.x.abs() > w / 2.0 || p.y.abs() > h / 2.0 {
            return None;
        }
        let u = (p.x / w + 0.5) * self.pixels[0] as f32;
        let v = (0.5 - p.y / h) * self.pixels[1] as f32;
        let clamp = |x: f32, n: u32| x.clamp(0.0, n as f32 - 0.5);
        Some(([clamp(u, self.pixels[0]), clamp(v, self.pixels[1])], t))
    }
}

/// A trigger pressed past this value presses on the panel.
pub const TRIGGER_PRESS: f32 = 0.6;
/// A trigger let go below this value releases.
pub const TRIGGER_RELEASE: f32 = 0.4;

/// One hand's aim this frame: its ray in tracking space and its trigger.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandAim {
    /// The aim pose's position.
    pub origin: Vec3,
    /// The aim pose's forward (−Z) direction.
    pub direction: Vec3,
    /// Trigger, 0 to 1.
    pub trigger: f32,
}

/// The hands' pointer on the panel between frames: which hand aims, whether its trigger is
/// down, what the panel was last told.
#[derive(Clone, Copy, Debug, Default)]
pub struct AimPointer {
    /// The hand that drives the panel (0 left, 1 right).
    hand: usize,
    /// Its trigger is down on the panel (with hysteresis).
    down: bool,
    /// Per hand: its trigger was let go since the panel opened or it last pressed (a trigger
    /// held while the panel opens does not press on it).
    armed: [bool; 2],
    /// The aim last sent.
    aimed: Option<[f32; 2]>,
}

/// What one frame of aiming found: the events for the panel, and each hand's ray to draw
/// (from the aim to where it meets the panel) with the hand that drives it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AimFrame {
    /// Events for the panel, first to last.
    pub events: [Option<PointerEvent>; MAX_POINTER_EVENTS],
    /// Per hand: the ray's start and end in tracking space, when it meets the panel.
    pub rays: [Option<(Vec3, Vec3)>; 2],
    /// The hand whose trigger drives the panel.
    pub hand: usize,
}

impl AimPointer {
    /// One frame: `menu` the menu button went down, `hands` each hand's aim (`None`: not
    /// tracked), `quad` the open panel (`None`: closed). While a trigger is held on the
    /// panel its hand keeps it; otherwise the hand that meets the panel drives it (the right
    /// one when both do).
    pub fn update(
        &mut self,
        menu: bool,
        hands: [Option<HandAim>; 2],
        quad: Option<&PanelQuad>,
    ) -> AimFrame {
        let mut out = AimFrame::default();
        let mut n = 0;
        let mut push = |e: PointerEvent, out: &mut AimFrame| {
            if n < MAX_POINTER_EVENTS {
                out.events[n] = Some(e);
                n += 1;
            }
        };
        if menu {
            push(PointerEvent::Menu, &mut out);
        }
        let trigger = |i: usize| hands[i].map_or(0.0, |h| h.trigger);
        let Some(quad) = quad else {
            // Closed: the next open starts fresh.
            *self = Self {
                armed: [0, 1].map(|i| trigger(i) < TRIGGER_RELEASE),
                hand: self.hand,
                ..Self::default()
            };
            out.hand = self.hand;
            return out;
        };
        for (i, armed) in self.armed.iter_mut().enumerate() {
            *armed |= trigger(i) < TRIGGER_RELEASE;
        }
        let hits = hands.map(|h| h.and_then(|h| quad.hit(h.origin, h.direction).map(|x| (h, x))));
        for (ray, hit) in out.rays.iter_mut().zip(&hits) {
            *ray = hit.map(|(h, (_, t))| (h.origin, h.origin + h.direction.normalize() * t));
        }
        if !self.down {
            if hits[1].is_some() {
                self.hand = 1;
            } else if hits[0].is_some() {
                self.hand = 0;
            }
        }
        let aim = hits[self.hand].map(|(_, (px, _))| px);
        if aim != self.aimed {
            self.aimed = aim;
            push(PointerEvent::Aim(aim), &mut out);
        }
        let trigger = trigger(self.hand);
        if !self.down && self.armed[self.hand] && trigger >= TRIGGER_PRESS {
            self.down = true;
            self.armed[self.hand] = false;
            push(PointerEvent::Trigger(true), &mut out);
        } else if self.down && trigger < TRIGGER_RELEASE {
            self.down = false;
            push(PointerEvent::Trigger(false), &mut out);
        }
        out.hand = self.hand;
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const PIXELS: [u32; 2] = [1100, 1400];

    fn quad() -> PanelQuad {
        PanelQuad::in_front_of(Vec3::new(0.0, 1.6, 0.0), Quat::IDENTITY, PIXELS)
    }

    #[test]
    fn the_panel_opens_level_in_front_and_rays_map_to_its_pixels() {
        let q = quad();
        assert!((q.centre - Vec3::new(0.0, 1.48, -0.65)).length() < 1e-5);
        assert!((q.size[1] - 0.5 * 1400.0 / 1100.0).abs() < 1e-6);
        // Straight at the centre: the middle pixel, 0.65 m away.
        let eye = Vec3::new(0.0, 1.48, 0.0);
        let (px, t) = q.hit(eye, Vec3::NEG_Z).unwrap();
        assert!(
            (px[0] - 550.0).abs() < 0.01 && (px[1] - 700.0).abs() < 0.01,
            "{px:?}"
        );
        assert!((t - 0.65).abs() < 1e-5);
        // Up and left: the top-left quarter.
        let (px, _) = q.hit(eye, Vec3::new(-0.1, 0.1, -0.65)).unwrap();
        assert!(px[0] < 550.0 && px[1] < 700.0, "{px:?}");
        // Missing to the side, pointing away, from behind.
        assert!(q.hit(eye, Vec3::new(-1.0, 0.0, -0.65)).is_none());
        assert!(q.hit(eye, Vec3::Z).is_none());
        assert!(q.hit(Vec3::new(0.0, 1.48, -1.0), Vec3::Z).is_none());
        // Opened while looking down and to the left: level, turned to face the head.
        let view = Quat::from_rotation_y(0.5) * Quat::from_rotation_x(-0.6);
        let q = PanelQuad::in_front_of(Vec3::new(1.0, 1.6, 2.0), view, PIXELS);
        assert!((q.centre.y - 1.48).abs() < 1e-5);
        let back = q.orientation * Vec3::Z;
        let to_head = (Vec3::new(1.0, 1.48, 2.0) - q.centre).normalize();
        assert!(back.dot(to_head) > 0.9999, "{back} vs {to_head}");
        let (px, _) = q.hit(Vec3::new(1.0, 1.48, 2.0), -to_head).unwrap();
        assert!((px[0] - 550.0).abs() < 0.1 && (px[1] - 700.0).abs() < 0.1);
    }

    fn aim_at(q: &PanelQuad, px: [f32; 2], trigger: f32) -> HandAim {
        let local = Vec3::new(
            (px[0] / q.pixels[0] as f32 - 0.5) * q.size[0],
            (0.5 - px[1] / q.pixels[1] as f32) * q.size[1],
            0.0,
        );
        let target = q.centre + q.orientation * local;
        let origin = q.centre + q.orientation * Vec3::new(0.2, -0.3, 0.5);
        HandAim {
            origin,
            direction: target - origin,
            trigger,
        }
    }

    fn events(f: &AimFrame) -> Vec<PointerEvent> {
        f.events.iter().flatten().copied().collect()
    }

    fn near(e: &PointerEvent, px: [f32; 2]) -> bool {
        matches!(e, PointerEvent::Aim(Some(p)) if (p[0] - px[0]).abs() < 0.5 && (p[1] - px[1]).abs() < 0.5)
    }

    #[test]
    fn aim_press_drag_and_release_come_from_one_hand() {
        let q = quad();
        let mut p = AimPointer::default();
        // Closed: only the menu button reaches the panel.
        let f = p.update(true, [None, Some(aim_at(&q, [100.0, 100.0], 1.0))], None);
        assert_eq!(events(&f), [PointerEvent::Menu]);
        // Open, the right trigger still held from before: no press until it is let go.
        let f = p.update(
            false,
            [None, Some(aim_at(&q, [100.0, 100.0], 1.0))],
            Some(&q),
        );
        let e = events(&f);
        assert_eq!(e.len(), 1);
        assert!(near(&e[0], [100.0, 100.0]), "{e:?}");
        assert!(f.rays[1].is_some() && f.rays[0].is_none());
        let f = p.update(
            false,
            [None, Some(aim_at(&q, [100.0, 100.0], 0.0))],
            Some(&q),
        );
        assert!(events(&f).is_empty());
        // Left aims too, right presses: the right hand drives.
        let both = |l: [f32; 2], r: [f32; 2], lt: f32, rt: f32| {
            [Some(aim_at(&q, l, lt)), Some(aim_at(&q, r, rt))]
        };
        let f = p.update(
            false,
            both([500.0, 500.0], [200.0, 300.0], 0.0, 0.7),
            Some(&q),
        );
        let e = events(&f);
        assert!(
            near(&e[0], [200.0, 300.0]) && e[1] == PointerEvent::Trigger(true),
            "{e:?}"
        );
        assert_eq!(f.hand, 1);
        // Dragging: the right hand keeps the panel while its trigger is held (hysteresis: 0.5
        // is still down), even off the panel's edge.
        let f = p.update(
            false,
            both([500.0, 500.0], [400.0, 300.0], 0.9, 0.5),
            Some(&q),
        );
        assert!(near(&events(&f)[0], [400.0, 300.0]));
        let mut off = both([500.0, 500.0], [400.0, 300.0], 0.9, 0.5);
        off[1] = Some(HandAim {
            direction: Vec3::X,
            ..off[1].unwrap()
        });
        let f = p.update(false, off, Some(&q));
        assert_eq!(events(&f), [PointerEvent::Aim(None)]);
        let f = p.update(
            false,
            both([500.0, 500.0], [400.0, 300.0], 0.9, 0.1),
            Some(&q),
        );
        let e = events(&f);
        assert!(
            near(&e[0], [400.0, 300.0]) && e[1] == PointerEvent::Trigger(false),
            "{e:?}"
        );
        // Released: the right hand leaves, the left (trigger held) takes over and presses.
        let left_only = [Some(aim_at(&q, [500.0, 500.0], 0.9)), None];
        let f = p.update(false, left_only, Some(&q));
        let e = events(&f);
        assert!(
            near(&e[0], [500.0, 500.0]) && e[1] == PointerEvent::Trigger(true),
            "{e:?}"
        );
        assert_eq!(f.hand, 0);
        // Closing mid-press: the pointer resets.
        let f = p.update(true, left_only, None);
        assert_eq!(events(&f), [PointerEvent::Menu]);
    }
}
