//! The per-frame half of the backend: events into the [`Lifecycle`], then while the session
//! runs `xrWaitFrame`, `xrBeginFrame`, `xrLocateViews` at the predicted display time (no
//! allocation), the controllers, and the [`FrameState`] the app renders.

use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use glam::{Quat, Vec3};
use openxr as xr;

use super::error::{check, Call, CallError};
use super::input::InputFrame;
use super::lifecycle::{self, Action, Event, ExitReason};
use super::session::LOCAL_EYE_HEIGHT;
use super::{FramePoll, OpenXr, Pending, EXIT_SIGNAL};
use crate::base::{EyeView, Fov};
use crate::physics::{HandInput, Pose};
use crate::ui::panel::PointerEvent;
use crate::xr::{FrameState, Tweak, XrError, MAX_POINTER_EVENTS, MAX_TWEAKS};

impl OpenXr {
    /// One step of [`crate::xr::FrameLoop::begin_frame`] that never waits for the session to
    /// run: polls the runtime's events, and while the session runs waits for, begins and
    /// returns the next frame. [`FramePoll::Idle`] when the session is not running (call again
    /// later: the desktop sleeps [`super::IDLE_POLL`], Android waits for its activity events
    /// instead); [`FramePoll::Done`] once the session is over.
    pub fn poll_frame(&mut self) -> Result<FramePoll, XrError> {
        loop {
            self.poll_events()?;
            if EXIT_SIGNAL.swap(false, Ordering::Relaxed) {
                log::info!("exit requested by signal");
                self.request_exit();
            }
            if let Some(reason) = self.stats.summary.exit {
                log::info!("leaving: {reason:?}");
                return if reason.is_clean() {
                    Ok(FramePoll::Done)
                } else {
                    Err(XrError::Lost(match reason {
                        ExitReason::SessionLost => {
                            "the OpenXR session was lost (LOSS_PENDING): the headset was \
                             disconnected or the runtime stopped it"
                        }
                        _ => "the OpenXR runtime went away (instance loss pending)",
                    }))
                };
            }
            if self.lifecycle.needs_exit_request() && !self.exit_sent {
                self.exit_sent = true;
                log::info!("requesting exit");
                if let Err(e) = self.session().session.request_exit() {
                    log::warn!("xrRequestExitSession: {e:?} ({e})");
                }
            }
            if !self.lifecycle.running() {
                return Ok(FramePoll::Idle);
            }
            let state = match self.session_mut().waiter.wait() {
                Ok(s) => s,
                // STOPPING raced the wait: handle the events first.
                Err(xr::sys::Result::ERROR_SESSION_NOT_RUNNING) => continue,
                Err(e) => return Err(CallError::new("xrWaitFrame", e).into()),
            };
            self.stats.waited();
            if let Some(s) = self.session.as_ref() {
                self.threads.poll(&self.instance, &s.session);
            }
            self.session_mut().stream.begin().call("xrBeginFrame")?;
            return self.begun(state).map(FramePoll::Frame);
        }
    }

    /// The frame just begun: views, input, and the state handed to the app.
    fn begun(&mut self, state: xr::FrameState) -> Result<FrameState, XrError> {
        let time = state.predicted_display_time;
        let display_time = self.stats.display_time(time);
        let period = (state.predicted_display_period.as_nanos() as f64 * 1e-9).max(1e-4);
        let located = if state.should_render {
            self.locate_views(time)?
        } else {
            None
        };
        let mut tweaks = [None; MAX_TWEAKS];
        let input = self.handle_input(located.as_ref(), period as f32, &mut tweaks)?;
        let (pointer, rays) = self.aim_at_panel(time, input.as_ref());
        let blank_view = xr::View {
            pose: xr::Posef::IDENTITY,
            fov: xr::Fovf {
                angle_left: -0.7,
                angle_right: 0.7,
                angle_up: 0.7,
                angle_down: -0.7,
            },
        };
        let raw_views = located.unwrap_or([blank_view; 2]);
        let views = raw_views.map(|v| {
            let (position, orientation) = self
                .locomotion
                .to_world(vec3(v.pose.position), quat(v.pose.orientation));
            EyeView {
                position,
                orientation,
                fov: fov(v.fov),
            }
        });
        let hands = self.locate_hands(time);
        let should_render = located.is_some();
        if should_render && self.locomotion.in_water() {
            let eyes = (views[0].position.y + views[1].position.y) * 0.5;
            self.stats.summary.afloat.observe(eyes, self.water_surface);
        }
        if !should_render {
            self.stats.summary.frames_not_rendered += 1;
        }
        self.pending = Some(Pending {
            time,
            views: raw_views,
            acquired: false,
            released: false,
            started: Instant::now(),
            waited: Duration::ZERO,
        });
        let frame = FrameState {
            index: self.index,
            predicted_display_time: display_time,
            period,
            views,
            should_render,
            paused: !self.lifecycle.focused(),
            tweaks,
            hands,
            pointer,
            rays,
            in_water: self.locomotion.in_water(),
            vignette: self.locomotion.vignette(),
        };
        self.index += 1;
        Ok(frame)
    }

    /// Polls every queued event into the lifecycle and carries out what it says.
    fn poll_events(&mut self) -> Result<(), XrError> {
        loop {
            let event = match self.instance.poll_event(&mut self.event_buffer) {
                Ok(Some(e)) => e,
                Ok(None) => return Ok(()),
                Err(e) => return Err(CallError::new("xrPollEvent", e).into()),
            };
            let ev = match event {
                xr::Event::SessionStateChanged(s) => {
                    log::info!("session state: {}", lifecycle::state_name(s.state()));
                    Event::State(s.state())
                }
                xr::Event::InstanceLossPending(_) => {
                    log::warn!("the OpenXR instance is about to be lost");
                    Event::InstanceLossPending
                }
                xr::Event::EventsLost(l) => {
                    log::warn!("{} OpenXR events were lost", l.lost_event_count());
                    continue;
                }
                xr::Event::InteractionProfileChanged(_) => {
                    log::info!("interaction profile changed");
                    continue;
                }
                xr::Event::ReferenceSpaceChangePending(_) => {
                    log::info!("reference space change pending (recentre)");
                    continue;
                }
                xr::Event::DisplayRefreshRateChangedFB(r) => {
                    log::info!(
                        "display refresh rate {} -> {} Hz",
                        r.from_display_refresh_rate(),
                        r.to_display_refresh_rate()
                    );
                    continue;
                }
                _ => continue,
            };
            let action = self.lifecycle.on_event(ev);
            self.apply(action)?;
        }
    }

    fn apply(&mut self, action: Action) -> Result<(), XrError> {
        match action {
            Action::None => {}
            Action::Begin => {
                self.session()
                    .session
                    .begin(xr::ViewConfigurationType::PRIMARY_STEREO)
                    .call("xrBeginSession")?;
                log::info!("session begun");
            }
            Action::End => {
                self.session().session.end().call("xrEndSession")?;
                log::info!("session ended");
            }
            Action::Exit(reason) => {
                self.stats.summary.exit = Some(reason);
            }
        }
        Ok(())
    }

    /// Locates both eyes in the tracking space at `time` without allocating. `None` when the
    /// runtime cannot orient the head (the frame is then not rendered). With a valid
    /// orientation but no valid position (tracking lost, e.g. the cameras covered) the eyes keep
    /// their last known positions, so the frame is still shown, turning with the head.
    fn locate_views(&mut self, time: xr::Time) -> Result<Option<[xr::View; 2]>, XrError> {
        let s = self.session();
        let info = xr::sys::ViewLocateInfo {
            ty: xr::sys::ViewLocateInfo::TYPE,
            next: std::ptr::null(),
            view_configuration_type: xr::ViewConfigurationType::PRIMARY_STEREO,
            display_time: time,
            space: s.space.as_raw(),
        };
        let mut state = xr::sys::ViewState {
            ty: xr::sys::ViewState::TYPE,
            next: std::ptr::null_mut(),
            view_state_flags: xr::ViewStateFlags::EMPTY,
        };
        let blank = xr::sys::View {
            ty: xr::sys::View::TYPE,
            next: std::ptr::null_mut(),
            pose: xr::Posef::IDENTITY,
            fov: xr::Fovf::default(),
        };
        let mut raw = [blank; 2];
        let mut count = 0;
        // SAFETY: valid session and space, and an output array of the stated capacity.
        let r = unsafe {
            (self.instance.fp().locate_views)(
                s.session.as_raw(),
                &info,
                &mut state,
                2,
                &mut count,
                raw.as_mut_ptr(),
            )
        };
        check(r).call("xrLocateViews")?;
        let flags = state.view_state_flags;
        if count != 2 || !flags.contains(xr::ViewStateFlags::ORIENTATION_VALID) {
            return Ok(None);
        }
        let mut views = raw.map(|v| xr::View {
            pose: v.pose,
            fov: v.fov,
        });
        if flags.contains(xr::ViewStateFlags::POSITION_VALID) {
            if self.tracking.position_lost {
                log::info!("head position tracked again");
                self.tracking.position_lost = false;
            }
            self.tracking.last_positions = Some(views.map(|v| v.pose.position));
        } else {
            if !self.tracking.position_lost {
                log::warn!(
                    "head position lost (orientation still tracked): rendering from the last \
                     known position"
                );
                self.tracking.position_lost = true;
            }
            let positions = self.tracking.last_positions.unwrap_or(STANDING_EYES);
            for (v, p) in views.iter_mut().zip(positions) {
                v.pose.position = p;
            }
        }
        Ok(Some(views))
    }

    /// Both hands at `time` in the world (after the frame's input was read and the user
    /// moved), for grabbing and throwing; none while the session is not focused.
    fn locate_hands(&self, time: xr::Time) -> [Option<HandInput>; 2] {
        if !self.lifecycle.focused() {
            return [None; 2];
        }
        let s = self.session();
        let turn = Quat::from_rotation_y(self.locomotion.yaw());
        s.input.hands(&s.session, &s.space, time).map(|h| {
            h.map(|h| {
                let (position, rotation) = self.locomotion.to_world(h.position, h.orientation);
                HandInput {
                    grip: h.grip,
                    pose: Pose { position, rotation },
                    linvel: turn * h.linvel,
                    angvel: turn * h.angvel,
                }
            })
        })
    }

    /// The control panel's pointer events of this frame (the menu button, the aim rays and
    /// triggers of `input`), at `time`, and the rays that meet it in the world.
    #[allow(clippy::type_complexity)]
    fn aim_at_panel(
        &mut self,
        time: xr::Time,
        input: Option<&InputFrame>,
    ) -> (
        [Option<PointerEvent>; MAX_POINTER_EVENTS],
        [Option<[Vec3; 2]>; 2],
    ) {
        let Some(input) = input else {
            return ([None; MAX_POINTER_EVENTS], [None; 2]);
        };
        let s = self.session();
        let aims = if self.panel.is_open() {
            s.input.aims(&s.space, time)
        } else {
            [None; 2]
        };
        let aimed = self.panel.aim(input.menu, aims, input.triggers);
        let world = |p: Vec3| self.locomotion.to_world(p, Quat::IDENTITY).0;
        let rays = aimed.rays.map(|r| r.map(|(a, b)| [world(a), world(b)]));
        (aimed.events, rays)
    }

    /// Reads the controllers, moves the user and collects the tweaks of this frame; returns
    /// what was read (`None` while not focused).
    fn handle_input(
        &mut self,
        views: Option<&[xr::View; 2]>,
        dt: f32,
        tweaks: &mut [Option<Tweak>; MAX_TWEAKS],
    ) -> Result<Option<InputFrame>, XrError> {
        if !self.lifecycle.focused() {
            return Ok(None);
        }
        let s = self.session_mut();
        let frame = match s.input.read(&s.session, dt) {
            Ok(f) => f,
            Err(xr::sys::Result::SESSION_NOT_FOCUSED) => return Ok(None),
            Err(e) => return Err(CallError::new("xrSyncActions", e).into()),
        };
        if let Some(v) = views {
            let (p, q) = head_pose(v);
            self.panel.head = Some((p, q));
            let in_water = self.locomotion.in_water();
            let toggled = frame.water.then_some(!in_water);
            match self.want_water.take().or(toggled) {
                Some(true) if !in_water => {
                    self.locomotion.enter_water(p, q, self.water_surface);
                    log::info!("into the water");
                    let s = self.session();
                    s.input.tick(&s.session);
                }
                Some(false) if in_water => {
                    self.locomotion.leave_water(p, q);
                    log::info!("back on the deck");
                    let s = self.session();
                    s.input.tick(&s.session);
                }
                _ => {}
            }
            self.locomotion.ride(self.water_surface, frame.duck, dt);
            if self.locomotion.update(p, q, frame.glide, frame.turn_x, dt) {
                log::debug!("snap turn: yaw {:.0}°", self.locomotion.yaw().to_degrees());
            }
            if frame.recenter {
                // Recentring always brings the user back onto the deck.
                self.locomotion.leave_water(p, q);
                log::info!("recentred on the deck");
                let s = self.session();
                s.input.tick(&s.session);
            }
        }
        let mut n = 0;
        if frame.next_preset {
            // The app cycles from the user's current preset (kept, panel or governor aside).
            tweaks[n] = Some(Tweak::NextPreset);
            n += 1;
            let s = self.session();
            s.input.tick(&s.session);
        }
        // While the panel is open the triggers press on it.
        if frame.wind_steps != 0 && !self.panel.is_open() {
            tweaks[n] = Some(Tweak::WindSpeed(frame.wind_steps as f32));
        }
        Ok(Some(frame))
    }
}

/// Eye positions assumed when the position was never tracked: standing, 63 mm apart, at the
/// space's origin.
const STANDING_EYES: [xr::Vector3f; 2] = [
    xr::Vector3f {
        x: -0.0315,
        y: LOCAL_EYE_HEIGHT,
        z: 0.0,
    },
    xr::Vector3f {
        x: 0.0315,
        y: LOCAL_EYE_HEIGHT,
        z: 0.0,
    },
];

/// What is known of the head's tracking between frames.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Tracking {
    /// Both eyes' positions when the position was last valid.
    pub last_positions: Option<[xr::Vector3f; 2]>,
    /// Whether the position is lost now (logged once per loss).
    pub position_lost: bool,
}

/// The head pose: midway between the eyes, with the left eye's orientation.
fn head_pose(v: &[xr::View; 2]) -> (Vec3, Quat) {
    let p = (vec3(v[0].pose.position) + vec3(v[1].pose.position)) * 0.5;
    (p, quat(v[0].pose.orientation))
}

fn vec3(v: xr::Vector3f) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

fn quat(q: xr::Quaternionf) -> Quat {
    Quat::from_xyzw(q.x, q.y, q.z, q.w).normalize()
}

fn fov(f: xr::Fovf) -> Fov {
    Fov {
        angle_left: f.angle_left,
        angle_right: f.angle_right,
        angle_up: f.angle_up,
        angle_down: f.angle_down,
    }
}
