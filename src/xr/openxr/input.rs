//! Controller input through OpenXR actions, with suggested bindings for the Touch controllers
//! (Quest 2's Touch; Quest 3/3S's Touch Plus and Quest Pro's Touch Pro, each when the runtime
//! has its extension) and the Khronos simple controller (any runtime):
//!
//! | action | Touch, Touch Plus, Touch Pro | simple controller |
//! |---|---|---|
//! | glide over the water | left thumbstick | — |
//! | snap turn | right thumbstick | — |
//! | next quality preset (haptic tick) | A | right menu |
//! | wind +1 m/s (repeats while held) | right trigger | right select |
//! | wind −1 m/s | left trigger | left select |
//! | recenter on the deck (hold 1 s, haptic tick) | B | left menu |
//! | grab a floating body (haptic tick), let go to throw | grip (squeeze), either hand | — |
//! | open or close the control panel | left menu (≡) | — |
//! | into the water, or back on the deck | Y | — |
//! | duck under (while held, in the water) | X | — |
//! | aim at the open panel, press on it (haptic tick) | aim ray and trigger, either hand | aim ray and select |
//!
//! While the panel is open the triggers press on it and leave the wind alone. The hands' grip
//! poses are located with their velocities (`xrLocateSpace` with `XrSpaceVelocity`) in the
//! session's space each frame, for grabbing and throwing; their aim poses, for the panel.

use glam::{Quat, Vec2, Vec3};
use openxr as xr;

/// Action paths of one interaction profile.
struct Profile {
    path: &'static str,
    /// Whether the instance may name this profile (its extension is enabled).
    usable: fn(&xr::InstanceExtensions) -> bool,
    glide: Option<&'static str>,
    turn: Option<&'static str>,
    preset: &'static str,
    wind_up: &'static str,
    wind_down: &'static str,
    recenter: &'static str,
    /// Each hand's squeeze (grab), where the controller has one.
    squeeze: Option<[&'static str; 2]>,
    /// The panel's menu button, where the controller has one to spare.
    menu: Option<&'static str>,
    /// Into the water or out, and duck under, where the controller has buttons to spare.
    water: Option<[&'static str; 2]>,
}

/// Grip poses of the left and right hand (every profile has them).
const GRIP_POSES: [&str; 2] = [
    "/user/hand/left/input/grip/pose",
    "/user/hand/right/input/grip/pose",
];

/// Aim poses of the left and right hand (every profile has them): the panel's rays.
const AIM_POSES: [&str; 2] = [
    "/user/hand/left/input/aim/pose",
    "/user/hand/right/input/aim/pose",
];

/// A profile of the Touch family: the same controls on every model.
const fn touch(path: &'static str, usable: fn(&xr::InstanceExtensions) -> bool) -> Profile {
    Profile {
        path,
        usable,
        glide: Some("/user/hand/left/input/thumbstick"),
        turn: Some("/user/hand/right/input/thumbstick"),
        preset: "/user/hand/right/input/a/click",
        wind_up: "/user/hand/right/input/trigger/value",
        wind_down: "/user/hand/left/input/trigger/value",
        recenter: "/user/hand/right/input/b/click",
        squeeze: Some([
            "/user/hand/left/input/squeeze/value",
            "/user/hand/right/input/squeeze/value",
        ]),
        menu: Some("/user/hand/left/input/menu/click"),
        water: Some([
            "/user/hand/left/input/y/click",
            "/user/hand/left/input/x/click",
        ]),
    }
}

/// Every profile we suggest bindings for. The Touch Plus and Touch Pro profiles extend Touch;
/// naming them without their extension would fail (`XR_ERROR_PATH_UNSUPPORTED`).
const PROFILES: [Profile; 4] = [
    touch("/interaction_profiles/oculus/touch_controller", |_| true),
    touch("/interaction_profiles/meta/touch_controller_plus", |e| {
        e.meta_touch_controller_plus.is_some()
    }),
    touch("/interaction_profiles/facebook/touch_controller_pro", |e| {
        e.fb_touch_controller_pro.is_some()
    }),
    Profile {
        path: "/interaction_profiles/khr/simple_controller",
        usable: |_| true,
        glide: None,
        turn: None,
        preset: "/user/hand/right/input/menu/click",
        wind_up: "/user/hand/right/input/select/click",
        wind_down: "/user/hand/left/input/select/click",
        recenter: "/user/hand/left/input/menu/click",
        squeeze: None,
        menu: None,
        water: None,
    },
];

/// A button held for [`LongPress::HOLD`] seconds: fires once per press.
#[derive(Clone, Copy, Debug, Default)]
pub struct LongPress {
    held: f32,
    fired: bool,
}

impl LongPress {
    /// Seconds the button must be held.
    pub const HOLD: f32 = 1.0;

    /// One frame: `down` the button state, `dt` s since the last frame. True when it fires.
    pub fn update(&mut self, down: bool, dt: f32) -> bool {
        if !down {
            *self = Self::default();
            return false;
        }
        self.held += dt.max(0.0);
        if !self.fired && self.held >= Self::HOLD {
            self.fired = true;
            return true;
        }
        false
    }
}

/// A trigger as a repeating button: fires when pressed past `PRESS`, then every `REPEAT`
/// seconds while held, and re-arms below `RELEASE`.
#[derive(Clone, Copy, Debug, Default)]
pub struct TriggerRepeat {
    held: bool,
    since: f32,
}

impl TriggerRepeat {
    /// Pressed past this value.
    pub const PRESS: f32 = 0.6;
    /// Released below this value.
    pub const RELEASE: f32 = 0.4;
    /// Seconds between repeats while held.
    pub const REPEAT: f32 = 0.35;

    /// One frame: trigger `value` in [0, 1], `dt` s since the last frame. True when it fires.
    pub fn update(&mut self, value: f32, dt: f32) -> bool {
        if !self.held {
            if value >= Self::PRESS {
                self.held = true;
                self.since = 0.0;
                return true;
            }
            return false;
        }
        if value < Self::RELEASE {
            self.held = false;
            return false;
        }
        self.since += dt.max(0.0);
        if self.since >= Self::REPEAT {
            self.since -= Self::REPEAT;
            return true;
        }
        false
    }
}

/// One frame of controller input.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InputFrame {
    /// Left stick (x right, y forward).
    pub glide: Vec2,
    /// Right stick's sideways deflection.
    pub turn_x: f32,
    /// The preset button went down this frame.
    pub next_preset: bool,
    /// Wind steps this frame (+1 up, −1 down, 0).
    pub wind_steps: i32,
    /// The recenter button was held long enough this frame.
    pub recenter: bool,
    /// The panel's menu button went down this frame.
    pub menu: bool,
    /// The left and right triggers, 0 to 1 (the panel's press).
    pub triggers: [f32; 2],
    /// The into-the-water button went down this frame (in or out).
    pub water: bool,
    /// The duck button is held.
    pub duck: bool,
}

/// One hand located this frame, in the session's space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandPose {
    /// Squeeze, 0 open to 1 closed.
    pub grip: f32,
    /// Grip pose position (m).
    pub position: Vec3,
    /// Grip pose orientation.
    pub orientation: Quat,
    /// Linear velocity (m/s); zero where the runtime does not know it.
    pub linvel: Vec3,
    /// Angular velocity (rad/s); zero where the runtime does not know it.
    pub angvel: Vec3,
}

/// The action set and its actions.
pub struct Input {
    set: xr::ActionSet,
    glide: xr::Action<xr::Vector2f>,
    turn: xr::Action<xr::Vector2f>,
    preset: xr::Action<bool>,
    wind_up: xr::Action<f32>,
    wind_down: xr::Action<f32>,
    recenter: xr::Action<bool>,
    haptic: xr::Action<xr::Haptic>,
    grip_pose: xr::Action<xr::Posef>,
    aim_pose: xr::Action<xr::Posef>,
    squeeze: xr::Action<f32>,
    menu: xr::Action<bool>,
    water: xr::Action<bool>,
    duck: xr::Action<bool>,
    /// The left and right hand's paths (subaction paths).
    hands: [xr::Path; 2],
    /// The grip poses' action spaces, made when the set is attached.
    grip_spaces: Option<[xr::Space; 2]>,
    /// The aim poses' action spaces, made when the set is attached.
    aim_spaces: Option<[xr::Space; 2]>,
    right: xr::Path,
    up: TriggerRepeat,
    down: TriggerRepeat,
    hold: LongPress,
}

impl Input {
    /// Creates the actions and suggests the bindings of every profile the runtime accepts
    /// (a rejected profile is logged, not fatal: the others still work).
    pub fn new(instance: &xr::Instance) -> Result<Self, String> {
        let err =
            |what: &str, e: xr::sys::Result| format!("OpenXR input set-up ({what}): {e:?} ({e})");
        let set = instance
            .create_action_set("ocean", "Ocean", 0)
            .map_err(|e| err("xrCreateActionSet", e))?;
        let right = instance
            .string_to_path("/user/hand/right")
            .map_err(|e| err("path", e))?;
        let left = instance
            .string_to_path("/user/hand/left")
            .map_err(|e| err("path", e))?;
        let glide = set
            .create_action::<xr::Vector2f>("glide", "Glide over the water", &[])
            .map_err(|e| err("glide", e))?;
        let turn = set
            .create_action::<xr::Vector2f>("snap_turn", "Snap turn", &[])
            .map_err(|e| err("snap_turn", e))?;
        let preset = set
            .create_action::<bool>("next_preset", "Next quality preset", &[])
            .map_err(|e| err("next_preset", e))?;
        let wind_up = set
            .create_action::<f32>("wind_up", "Raise the wind", &[])
            .map_err(|e| err("wind_up", e))?;
        let wind_down = set
            .create_action::<f32>("wind_down", "Lower the wind", &[])
            .map_err(|e| err("wind_down", e))?;
        let recenter = set
            .create_action::<bool>("recenter", "Recenter on the deck (hold)", &[])
            .map_err(|e| err("recenter", e))?;
        let haptic = set
            .create_action::<xr::Haptic>("tick", "Haptic tick", &[left, right])
            .map_err(|e| err("tick", e))?;
        let grip_pose = set
            .create_action::<xr::Posef>("hand_pose", "Hand pose", &[left, right])
            .map_err(|e| err("hand_pose", e))?;
        let squeeze = set
            .create_action::<f32>("grab", "Grab a floating body", &[left, right])
            .map_err(|e| err("grab", e))?;
        let aim_pose = set
            .create_action::<xr::Posef>("aim_pose", "Aim at the panel", &[left, right])
            .map_err(|e| err("aim_pose", e))?;
        let menu = set
            .create_action::<bool>("panel", "Open or close the panel", &[])
            .map_err(|e| err("panel", e))?;
        let water = set
            .create_action::<bool>("into_water", "Into the water, or back on the deck", &[])
            .map_err(|e| err("into_water", e))?;
        let duck = set
            .create_action::<bool>("duck", "Duck under the water (hold)", &[])
            .map_err(|e| err("duck", e))?;
        for p in PROFILES.iter().filter(|p| (p.usable)(instance.exts())) {
            let path = |s: &str| instance.string_to_path(s);
            let suggest = || -> Result<(), xr::sys::Result> {
                let profile = path(p.path)?;
                let mut b = vec![
                    xr::Binding::new(&preset, path(p.preset)?),
                    xr::Binding::new(&wind_up, path(p.wind_up)?),
                    xr::Binding::new(&wind_down, path(p.wind_down)?),
                    xr::Binding::new(&recenter, path(p.recenter)?),
                    xr::Binding::new(&haptic, path("/user/hand/left/output/haptic")?),
                    xr::Binding::new(&haptic, path("/user/hand/right/output/haptic")?),
                ];
                if let Some(g) = p.glide {
                    b.push(xr::Binding::new(&glide, path(g)?));
                }
                if let Some(t) = p.turn {
                    b.push(xr::Binding::new(&turn, path(t)?));
                }
                for g in GRIP_POSES {
                    b.push(xr::Binding::new(&grip_pose, path(g)?));
                }
                for a in AIM_POSES {
                    b.push(xr::Binding::new(&aim_pose, path(a)?));
                }
                if let Some(m) = p.menu {
                    b.push(xr::Binding::new(&menu, path(m)?));
                }
                if let Some([w, d]) = p.water {
                    b.push(xr::Binding::new(&water, path(w)?));
                    b.push(xr::Binding::new(&duck, path(d)?));
                }
                for s in p.squeeze.into_iter().flatten() {
                    b.push(xr::Binding::new(&squeeze, path(s)?));
                }
                instance.suggest_interaction_profile_bindings(profile, &b)
            };
            match suggest() {
                Ok(()) => log::info!("bindings suggested for {}", p.path),
                Err(e) => log::warn!("the runtime rejected bindings for {}: {e:?} ({e})", p.path),
            }
        }
        Ok(Self {
            set,
            glide,
            turn,
            preset,
            wind_up,
            wind_down,
            recenter,
            haptic,
            grip_pose,
            aim_pose,
            squeeze,
            menu,
            water,
            duck,
            hands: [left, right],
            grip_spaces: None,
            aim_spaces: None,
            right,
            up: TriggerRepeat::default(),
            down: TriggerRepeat::default(),
            hold: LongPress::default(),
        })
    }

    /// Attaches the action set to `session` (once, before the first sync) and makes the
    /// hands' grip spaces (a runtime that refuses them leaves the session without hands,
    /// logged: the sea is still there to look at).
    pub fn attach(&mut self, session: &xr::Session<xr::Vulkan>) -> Result<(), String> {
        session
            .attach_action_sets(&[&self.set])
            .map_err(|e| format!("xrAttachSessionActionSets: {e:?} ({e})"))?;
        let space = |hand| {
            self.grip_pose
                .create_space(session, hand, xr::Posef::IDENTITY)
        };
        match space(self.hands[0]).and_then(|l| Ok([l, space(self.hands[1])?])) {
            Ok(spaces) => self.grip_spaces = Some(spaces),
            Err(e) => log::warn!("xrCreateActionSpace (grip pose): {e:?} ({e}): no hands"),
        }
        let aim = |hand| {
            self.aim_pose
                .create_space(session, hand, xr::Posef::IDENTITY)
        };
        match aim(self.hands[0]).and_then(|l| Ok([l, aim(self.hands[1])?])) {
            Ok(spaces) => self.aim_spaces = Some(spaces),
            Err(e) => log::warn!("xrCreateActionSpace (aim pose): {e:?} ({e}): no panel rays"),
        }
        Ok(())
    }

    /// Both hands' aim rays at `time` in `base` (origin, forward): `None` for a hand not
    /// located. Allocates nothing.
    pub fn aims(&self, base: &xr::Space, time: xr::Time) -> [Option<(Vec3, Vec3)>; 2] {
        let Some(spaces) = self.aim_spaces.as_ref() else {
            return [None; 2];
        };
        spaces.each_ref().map(|space| {
            let location = space.locate(base, time).ok()?;
            let need =
                xr::SpaceLocationFlags::POSITION_VALID | xr::SpaceLocationFlags::ORIENTATION_VALID;
            if !location.location_flags.contains(need) {
                return None;
            }
            let (p, q) = (location.pose.position, location.pose.orientation);
            let rotation = Quat::from_xyzw(q.x, q.y, q.z, q.w).normalize();
            Some((Vec3::new(p.x, p.y, p.z), rotation * Vec3::NEG_Z))
        })
    }

    /// Both hands at `time` in `base` (after [`Input::read`] synced the actions this frame):
    /// `None` for a hand whose controller is off, untracked or has no squeeze. Allocates
    /// nothing.
    pub fn hands(
        &self,
        session: &xr::Session<xr::Vulkan>,
        base: &xr::Space,
        time: xr::Time,
    ) -> [Option<HandPose>; 2] {
        let Some(spaces) = self.grip_spaces.as_ref() else {
            return [None; 2];
        };
        let mut out = [None; 2];
        for ((o, space), &hand) in out.iter_mut().zip(spaces).zip(&self.hands) {
            *o = self.hand(session, space, hand, base, time);
        }
        out
    }

    fn hand(
        &self,
        session: &xr::Session<xr::Vulkan>,
        space: &xr::Space,
        hand: xr::Path,
        base: &xr::Space,
        time: xr::Time,
    ) -> Option<HandPose> {
        let squeeze = self.squeeze.state(session, hand).ok()?;
        if !squeeze.is_active {
            return None;
        }
        let (location, velocity) = match space.relate(base, time) {
            Ok(r) => r,
            Err(e) => {
                log::warn!("xrLocateSpace (hand): {e:?} ({e})");
                return None;
            }
        };
        let need =
            xr::SpaceLocationFlags::POSITION_VALID | xr::SpaceLocationFlags::ORIENTATION_VALID;
        if !location.location_flags.contains(need) {
            return None;
        }
        let v3 = |v: xr::Vector3f| Vec3::new(v.x, v.y, v.z);
        let flags = velocity.velocity_flags;
        let q = location.pose.orientation;
        Some(HandPose {
            grip: squeeze.current_state,
            position: v3(location.pose.position),
            orientation: Quat::from_xyzw(q.x, q.y, q.z, q.w).normalize(),
            linvel: if flags.contains(xr::SpaceVelocityFlags::LINEAR_VALID) {
                v3(velocity.linear_velocity)
            } else {
                Vec3::ZERO
            },
            angvel: if flags.contains(xr::SpaceVelocityFlags::ANGULAR_VALID) {
                v3(velocity.angular_velocity)
            } else {
                Vec3::ZERO
            },
        })
    }

    /// Syncs the actions and reads this frame's input (`dt` s since the last frame).
    pub fn read(
        &mut self,
        session: &xr::Session<xr::Vulkan>,
        dt: f32,
    ) -> Result<InputFrame, xr::sys::Result> {
        session.sync_actions(&[xr::ActiveActionSet::new(&self.set)])?;
        let any = xr::Path::NULL;
        let v2 = |s: xr::ActionState<xr::Vector2f>| {
            if s.is_active {
                Vec2::new(s.current_state.x, s.current_state.y)
            } else {
                Vec2::ZERO
            }
        };
        let glide = v2(self.glide.state(session, any)?);
        let turn = v2(self.turn.state(session, any)?);
        let p = self.preset.state(session, any)?;
        let up = self.wind_up.state(session, any)?;
        let down = self.wind_down.state(session, any)?;
        let up_value = if up.is_active { up.current_state } else { 0.0 };
        let down_value = if down.is_active {
            down.current_state
        } else {
            0.0
        };
        let wind_steps =
            self.up.update(up_value, dt) as i32 - self.down.update(down_value, dt) as i32;
        let r = self.recenter.state(session, any)?;
        let recenter = self.hold.update(r.is_active && r.current_state, dt);
        let m = self.menu.state(session, any)?;
        let w = self.water.state(session, any)?;
        let dk = self.duck.state(session, any)?;
        Ok(InputFrame {
            glide,
            turn_x: turn.x,
            next_preset: p.is_active && p.changed_since_last_sync && p.current_state,
            wind_steps,
            recenter,
            menu: m.is_active && m.changed_since_last_sync && m.current_state,
            triggers: [down_value, up_value],
            water: w.is_active && w.changed_since_last_sync && w.current_state,
            duck: dk.is_active && dk.current_state,
        })
    }

    /// A short tick on the right controller (preset changed, recentred).
    pub fn tick(&self, session: &xr::Session<xr::Vulkan>) {
        self.tick_path(session, self.right);
    }

    /// A short tick on hand `hand` (0 left, 1 right): it grabbed a body.
    pub fn tick_hand(&self, session: &xr::Session<xr::Vulkan>, hand: usize) {
        if let Some(&path) = self.hands.get(hand) {
            self.tick_path(session, path);
        }
    }

    fn tick_path(&self, session: &xr::Session<xr::Vulkan>, path: xr::Path) {
        let vibration = xr::HapticVibration::new()
            .amplitude(0.6)
            .frequency(xr::FREQUENCY_UNSPECIFIED)
            .duration(xr::Duration::from_nanos(30_000_000));
        if let Err(e) = self.haptic.apply_feedback(session, path, &vibration) {
            log::warn!("haptic feedback: {e:?} ({e})");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_press_fires_once_after_a_second() {
        let mut b = LongPress::default();
        let dt = 1.0 / 72.0;
        let mut fired = Vec::new();
        for i in 0..200 {
            if b.update(true, dt) {
                fired.push(i);
            }
        }
        // Once, after 72 frames (1 s) of holding, not again while held.
        assert_eq!(fired, [71]);
        // A short press does nothing; a new long press fires again.
        for _ in 0..30 {
            assert!(!b.update(false, dt));
            assert!(!b.update(true, dt));
        }
        assert!(!b.update(false, dt));
        assert!((0..80).any(|_| b.update(true, dt)));
    }

    #[test]
    fn the_touch_plus_and_pro_profiles_need_their_extensions() {
        let names: Vec<&str> = PROFILES.iter().map(|p| p.path).collect();
        assert!(names.contains(&"/interaction_profiles/meta/touch_controller_plus"));
        assert!(names.contains(&"/interaction_profiles/facebook/touch_controller_pro"));
        // Every profile binds every action the user has.
        for p in &PROFILES {
            assert!(p.recenter.starts_with("/user/hand/"), "{}", p.path);
        }
    }

    #[test]
    fn trigger_fires_on_press_then_repeats_while_held() {
        let mut t = TriggerRepeat::default();
        let dt = 1.0 / 72.0;
        let mut fired = 0;
        // Half pressed: nothing.
        for _ in 0..50 {
            fired += t.update(0.5, dt) as u32;
        }
        assert_eq!(fired, 0);
        // Held fully for 1 s: once at the press, then every 0.35 s → 1 + 2.
        for _ in 0..72 {
            fired += t.update(1.0, dt) as u32;
        }
        assert_eq!(fired, 3);
        // Wobbling between the thresholds does not re-fire; a release and press does.
        fired += t.update(0.45, dt) as u32 + t.update(0.65, dt) as u32;
        assert_eq!(fired, 3);
        t.update(0.1, dt);
        fired += t.update(0.9, dt) as u32;
        assert_eq!(fired, 4);
    }
}
