//! The window's input: winit's event handler, the keys ([`KEYS_HELP`]) mapped to moves and
//! tweaks, the mouse look, and the queue of tweaks waiting for a frame.

use winit::application::ApplicationHandler;
use winit::event::{ElementState, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use super::panel::PanelMouse;
use crate::lod::QualityPreset;
use crate::xr::desktop::controls::{FlyControls, MoveKey};
use crate::xr::{Tweak, MAX_TWEAKS};

/// The controls, as printed at start-up and in the README.
pub const KEYS_HELP: &str = concat!(
    "  W/A/S/D  move                  Q/E    down/up           Shift  5x faster\n",
    "  mouse    look around while a mouse button is held\n",
    "  1/2      wind speed -/+ 1 m/s  3/4    wind direction -/+ 15 deg\n",
    "  5/6      choppiness -/+ 0.1    F1-F4  quality low/medium/high/ultra\n",
    "  7/8      sun lower/higher 5 deg  9/0  sun azimuth -/+ 15 deg\n",
    "  [/]      sea state: Beaufort force -/+ 1 (0 calm to 10 storm)\n",
    "  Space    throw a crate along the view\n",
    "  Tab      control panel (the mouse drives it)\n",
    "  Esc      quit (or close the window)",
);

/// Tweaks waiting for a frame (key presses faster than frames queue here).
pub(super) const PENDING_TWEAKS: usize = 16;

/// The movement key a physical key drives, if any.
pub fn move_key(code: KeyCode) -> Option<MoveKey> {
    Some(match code {
        KeyCode::KeyW => MoveKey::Forward,
        KeyCode::KeyS => MoveKey::Back,
        KeyCode::KeyA => MoveKey::Left,
        KeyCode::KeyD => MoveKey::Right,
        KeyCode::KeyE => MoveKey::Up,
        KeyCode::KeyQ => MoveKey::Down,
        KeyCode::ShiftLeft | KeyCode::ShiftRight => MoveKey::Fast,
        _ => return None,
    })
}

/// The live tweak a physical key asks for, if any (see [`KEYS_HELP`]).
pub fn tweak_for_key(code: KeyCode) -> Option<Tweak> {
    Some(match code {
        KeyCode::Digit1 => Tweak::WindSpeed(-1.0),
        KeyCode::Digit2 => Tweak::WindSpeed(1.0),
        KeyCode::Digit3 => Tweak::WindDirection(-15.0),
        KeyCode::Digit4 => Tweak::WindDirection(15.0),
        KeyCode::Digit5 => Tweak::Choppiness(-0.1),
        KeyCode::Digit6 => Tweak::Choppiness(0.1),
        KeyCode::BracketLeft => Tweak::SeaState(-1),
        KeyCode::BracketRight => Tweak::SeaState(1),
        KeyCode::F1 => Tweak::Preset(QualityPreset::Low),
        KeyCode::F2 => Tweak::Preset(QualityPreset::Medium),
        KeyCode::F3 => Tweak::Preset(QualityPreset::High),
        KeyCode::F4 => Tweak::Preset(QualityPreset::Ultra),
        KeyCode::Space => Tweak::Throw,
        KeyCode::Digit7 => Tweak::Sun {
            elevation: -5.0,
            azimuth: 0.0,
        },
        KeyCode::Digit8 => Tweak::Sun {
            elevation: 5.0,
            azimuth: 0.0,
        },
        KeyCode::Digit9 => Tweak::Sun {
            elevation: 0.0,
            azimuth: -15.0,
        },
        KeyCode::Digit0 => Tweak::Sun {
            elevation: 0.0,
            azimuth: 15.0,
        },
        _ => return None,
    })
}

/// winit's side: the window and what its events asked for since the last frame.
pub(super) struct Input {
    pub attributes: winit::window::WindowAttributes,
    pub window: Option<Window>,
    pub error: Option<String>,
    pub controls: FlyControls,
    pub pending: [Option<Tweak>; PENDING_TWEAKS],
    pub quit: bool,
    pub resized: bool,
    pub turning: bool,
    pub cursor: Option<(f64, f64)>,
    /// The mouse and Tab as the control panel's pointer.
    pub panel: PanelMouse,
}

impl Input {
    pub fn push_tweak(&mut self, t: Tweak) {
        match self.pending.iter_mut().find(|p| p.is_none()) {
            Some(slot) => *slot = Some(t),
            None => log::warn!("too many key presses at once; {t:?} ignored"),
        }
    }

    /// Moves up to [`MAX_TWEAKS`] queued tweaks out, oldest first.
    pub fn take_tweaks(&mut self) -> [Option<Tweak>; MAX_TWEAKS] {
        let mut out = [None; MAX_TWEAKS];
        let n = self.pending.iter().take_while(|p| p.is_some()).count();
        let k = n.min(MAX_TWEAKS);
        out[..k].copy_from_slice(&self.pending[..k]);
        self.pending.copy_within(k.., 0);
        for p in &mut self.pending[PENDING_TWEAKS - k..] {
            *p = None;
        }
        out
    }
}

impl ApplicationHandler for Input {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none() && self.error.is_none() {
            match event_loop.create_window(self.attributes.clone()) {
                Ok(w) => self.window = Some(w),
                Err(e) => self.error = Some(format!("cannot create the window: {e}")),
            }
        }
    }

    fn window_event(&mut self, _: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => self.quit = true,
            WindowEvent::Resized(_) | WindowEvent::ScaleFactorChanged { .. } => self.resized = true,
            WindowEvent::Focused(false) => {
                self.controls.release_all();
                self.turning = false;
            }
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return;
                };
                let down = event.state == ElementState::Pressed;
                if let Some(k) = move_key(code) {
                    self.controls.key(k, down);
                }
                if !down {
                    return;
                }
                if code == KeyCode::Escape {
                    self.quit = true;
                } else if code == KeyCode::Tab {
                    if !event.repeat {
                        self.panel.menu();
                    }
                } else if let Some(t) = tweak_for_key(code) {
                    // Holding a wave key repeats it; a preset switch or a throw happens once.
                    if !(event.repeat
                        && matches!(
                            t,
                            Tweak::Preset(_)
                                | Tweak::Throw
                                | Tweak::Sun { .. }
                                | Tweak::SeaState(_)
                        ))
                    {
                        self.push_tweak(t);
                    }
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let down = state == ElementState::Pressed;
                let panel =
                    button == winit::event::MouseButton::Left && self.panel.left_button(down);
                if !panel {
                    self.turning = down;
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (true, Some(prev)) = (self.turning, self.cursor) {
                    self.controls.look(now.0 - prev.0, now.1 - prev.1);
                }
                self.cursor = Some(now);
                self.panel.moved(Some([now.0 as f32, now.1 as f32]));
            }
            WindowEvent::CursorLeft { .. } => {
                self.cursor = None;
                self.panel.moved(None);
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_map_to_moves_and_tweaks() {
        assert_eq!(move_key(KeyCode::KeyW), Some(MoveKey::Forward));
        assert_eq!(move_key(KeyCode::ShiftRight), Some(MoveKey::Fast));
        assert_eq!(move_key(KeyCode::Digit1), None);
        assert_eq!(tweak_for_key(KeyCode::Digit2), Some(Tweak::WindSpeed(1.0)));
        assert_eq!(
            tweak_for_key(KeyCode::F4),
            Some(Tweak::Preset(QualityPreset::Ultra))
        );
        assert_eq!(tweak_for_key(KeyCode::KeyW), None);
    }

    #[test]
    fn queued_tweaks_leave_in_order_a_few_per_frame() {
        let mut input = Input {
            attributes: Window::default_attributes(),
            window: None,
            error: None,
            controls: FlyControls::new(glam::Vec3::Y, 0.0, 0.0),
            pending: [None; PENDING_TWEAKS],
            quit: false,
            resized: false,
            turning: false,
            cursor: None,
            panel: PanelMouse::default(),
        };
        for i in 0..(PENDING_TWEAKS + 2) {
            input.push_tweak(Tweak::WindSpeed(i as f32));
        }
        let mut seen = Vec::new();
        loop {
            let t = input.take_tweaks();
            if t[0].is_none() {
                break;
            }
            seen.extend(t.into_iter().flatten());
        }
        let want: Vec<Tweak> = (0..PENDING_TWEAKS)
            .map(|i| Tweak::WindSpeed(i as f32))
            .collect();
        assert_eq!(seen, want);
    }
}
