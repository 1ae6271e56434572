//! The panel's pointer as a state machine: a controller's aim ray (or the desktop mouse)
//! reduced to where it meets the panel, the trigger (or mouse button) and the menu button
//! (or key), turned into what the panel's UI reads (pointer moves, presses, releases, the
//! pointer leaving) and what the hand feels (a haptic tick on each press that lands).
//!
//! Pure and allocation-free: the front ends feed [`PointerEvent`]s, the panel reads
//! [`PanelPointer::take_ui_events`] before it runs its UI.

/// What a front end reports of the pointer, in order, during a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PointerEvent {
    /// Where the aim meets the panel, in panel pixels from its top-left corner; `None` when it
    /// misses (or the mouse left the overlay).
    Aim(Option<[f32; 2]>),
    /// The trigger (or primary button) went down (`true`) or up.
    Trigger(bool),
    /// The menu button (or the overlay's key): opens or closes the panel.
    Menu,
    /// Close the panel (the UI's own close button, a lost session).
    Close,
}

/// What the panel's UI is told, in order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum UiEvent {
    /// The pointer is over the panel at this pixel.
    Moved([f32; 2]),
    /// The primary button went down (`true`) or up at this pixel.
    Button([f32; 2], bool),
    /// The pointer left the panel.
    Gone,
}

/// Most UI events one frame keeps (a frame sees a handful; more are merged: see
/// [`PanelPointer::handle`]).
pub const MAX_UI_EVENTS: usize = 16;

/// The pointer's state between frames.
#[derive(Clone, Debug)]
pub struct PanelPointer {
    open: bool,
    /// Where the aim meets the panel, if it does.
    at: Option<[f32; 2]>,
    /// Whether the trigger is down.
    trigger: bool,
    /// Whether a press began on the panel and has not been released (a slider drag keeps
    /// going when the aim slips off the panel's edge).
    pressing: bool,
    /// The last pixel the UI was told of.
    last_seen: Option<[f32; 2]>,
    events: [UiEvent; MAX_UI_EVENTS],
    len: usize,
    haptic: bool,
    toggled: bool,
}

impl PanelPointer {
    /// A closed panel, nothing aimed at it.
    pub fn new(open: bool) -> Self {
        Self {
            open,
            at: None,
            trigger: false,
            pressing: false,
            last_seen: None,
            events: [UiEvent::Gone; MAX_UI_EVENTS],
            len: 0,
            haptic: false,
            toggled: false,
        }
    }

    /// Whether the panel is open.
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// Where the aim meets the open panel (for the cursor), if it does.
    pub fn cursor(&self) -> Option<[f32; 2]> {
        self.at.filter(|_| self.open)
    }

    /// Whether a press is being held on the panel (a drag).
    pub fn pressing(&self) -> bool {
        self.pressing
    }

    /// Takes one event. A closed panel ignores everything but the menu button; its trigger
    /// belongs to the scene (throwing, grabbing).
    pub fn handle(&mut self, event: PointerEvent) {
        match event {
            PointerEvent::Menu => {
                if self.open {
                    self.close();
                } else {
                    self.open = true;
                    self.toggled = true;
                    if let Some(p) = self.at {
                        self.push(UiEvent::Moved(p));
                    }
                }
            }
            PointerEvent::Close => {
                if self.open {
                    self.close();
                }
            }
            PointerEvent::Aim(at) => {
                let was = self.at;
                self.at = at;
                if !self.open {
                    return;
                }
                match (was, at) {
                    (_, Some(p)) if Some(p) != was => self.push(UiEvent::Moved(p)),
                    (Some(_), None) if !self.pressing => self.push(UiEvent::Gone),
                    _ => {}
                }
            }
            PointerEvent::Trigger(down) => {
                let was = self.trigger;
                self.trigger = down;
                if !self.open || was == down {
                    return;
                }
                match (down, self.at) {
                    (true, Some(p)) => {
                        self.pressing = true;
                        self.haptic = true;
                        self.push(UiEvent::Button(p, true));
                    }
                    (false, _) if self.pressing => {
                        self.pressing = false;
                        // Released off the panel: at the last point egui saw, then gone.
                        let p = self.at.unwrap_or_else(|| self.last_point());
                        self.push(UiEvent::Button(p, false));
                        if self.at.is_none() {
                            self.push(UiEvent::Gone);
                        }
                    }
                    _ => {}
                }
            }
        }
    }

    fn close(&mut self) {
        if self.pressing {
            let p = self.at.unwrap_or_else(|| self.last_point());
            self.push(UiEvent::Button(p, false));
        }
        self.pressing = false;
        self.push(UiEvent::Gone);
        self.open = false;
        self.toggled = true;
    }

    /// The last point the UI was told of.
    fn last_point(&self) -> [f32; 2] {
        self.last_seen.unwrap_or([0.0, 0.0])
    }

    fn push(&mut self, e: UiEvent) {
        if let UiEvent::Moved(p) | UiEvent::Button(p, _) = e {
            self.last_seen = Some(p);
        }
        // Consecutive moves merge (only the last position matters).
        if let (UiEvent::Moved(_), Some(UiEvent::Moved(_))) = (e, self.events[..self.len].last()) {
            self.events[self.len - 1] = e;
            return;
        }
        if self.len == MAX_UI_EVENTS {
            // Full: drop the oldest move, else the oldest event (a frame never gets here).
            let drop = self.events[..self.len]
                .iter()
                .position(|e| matches!(e, UiEvent::Moved(_)))
                .unwrap_or(0);
            self.events.copy_within(drop + 1..self.len, drop);
            self.len -= 1;
        }
        self.events[self.len] = e;
        self.len += 1;
    }

    /// The UI events since the last call (empty when nothing happened), then forgotten.
    pub fn take_ui_events(&mut self) -> impl Iterator<Item = UiEvent> + '_ {
        let len = std::mem::take(&mut self.len);
        self.events[..len].iter().copied()
    }

    /// Whether a press landed on the panel since the last call (the front end plays a short
    /// haptic tick on the pressing hand).
    pub fn take_haptic(&mut self) -> bool {
        std::mem::take(&mut self.haptic)
    }

    /// Whether the panel opened or closed since the last call.
    pub fn take_toggled(&mut self) -> bool {
        std::mem::take(&mut self.toggled)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn events(p: &mut PanelPointer) -> Vec<UiEvent> {
        p.take_ui_events().collect()
    }

    #[test]
    fn a_closed_panel_leaves_the_trigger_to_the_scene() {
        let mut p = PanelPointer::new(false);
        p.handle(PointerEvent::Aim(Some([10.0, 10.0])));
        p.handle(PointerEvent::Trigger(true));
        assert!(events(&mut p).is_empty());
        assert!(!p.take_haptic());
        assert!(!p.pressing());
        assert_eq!(p.cursor(), None);
    }

    #[test]
    fn aim_hover_press_release_and_close() {
        let mut p = PanelPointer::new(false);
        p.handle(PointerEvent::Menu);
        assert!(p.is_open() && p.take_toggled());
        // Aim: the moves of a frame merge into the last.
        p.handle(PointerEvent::Aim(Some([10.0, 20.0])));
        p.handle(PointerEvent::Aim(Some([12.0, 21.0])));
        assert_eq!(events(&mut p), [UiEvent::Moved([12.0, 21.0])]);
        assert_eq!(p.cursor(), Some([12.0, 21.0]));
        // Holding still tells the UI nothing.
        p.handle(PointerEvent::Aim(Some([12.0, 21.0])));
        assert!(events(&mut p).is_empty());
        // Press: a button event and a haptic tick.
        p.handle(PointerEvent::Trigger(true));
        assert_eq!(events(&mut p), [UiEvent::Button([12.0, 21.0], true)]);
        assert!(p.take_haptic() && !p.take_haptic());
        p.handle(PointerEvent::Trigger(false));
        assert_eq!(events(&mut p), [UiEvent::Button([12.0, 21.0], false)]);
        // Aiming away: the pointer is gone.
        p.handle(PointerEvent::Aim(None));
        assert_eq!(events(&mut p), [UiEvent::Gone]);
        p.handle(PointerEvent::Menu);
        assert!(!p.is_open() && p.take_toggled());
        assert_eq!(events(&mut p), [UiEvent::Gone]);
    }

    #[test]
    fn a_drag_that_slips_off_the_edge_keeps_going_until_release() {
        let mut p = PanelPointer::new(true);
        p.handle(PointerEvent::Aim(Some([100.0, 50.0])));
        p.handle(PointerEvent::Trigger(true));
        p.handle(PointerEvent::Aim(Some([300.0, 52.0])));
        assert_eq!(
            events(&mut p),
            [
                UiEvent::Moved([100.0, 50.0]),
                UiEvent::Button([100.0, 50.0], true),
                UiEvent::Moved([300.0, 52.0]),
            ]
        );
        // Off the edge mid-drag: no "gone" yet, the press holds.
        p.handle(PointerEvent::Aim(None));
        assert!(events(&mut p).is_empty());
        assert!(p.pressing());
        // Released off the panel: at the last point, then gone.
        p.handle(PointerEvent::Trigger(false));
        assert_eq!(
            events(&mut p),
            [UiEvent::Button([300.0, 52.0], false), UiEvent::Gone]
        );
        assert!(!p.pressing());
    }

    #[test]
    fn closing_mid_press_releases_first() {
        let mut p = PanelPointer::new(true);
        p.handle(PointerEvent::Aim(Some([5.0, 5.0])));
        p.handle(PointerEvent::Trigger(true));
        let _ = events(&mut p);
        p.handle(PointerEvent::Close);
        assert_eq!(
            events(&mut p),
            [UiEvent::Button([5.0, 5.0], false), UiEvent::Gone]
        );
        assert!(!p.is_open() && !p.pressing());
        // A press that began before the panel opened is not the panel's.
        let mut p = PanelPointer::new(false);
        p.handle(PointerEvent::Trigger(true));
        p.handle(PointerEvent::Menu);
        p.handle(PointerEvent::Aim(Some([1.0, 1.0])));
        p.handle(PointerEvent::Trigger(false));
        assert_eq!(events(&mut p), [UiEvent::Moved([1.0, 1.0])]);
    }

    #[test]
    fn a_flood_of_events_keeps_the_presses() {
        let mut p = PanelPointer::new(true);
        for i in 0..40 {
            p.handle(PointerEvent::Aim(Some([i as f32, 0.0])));
            p.handle(PointerEvent::Trigger(i % 2 == 0));
        }
        let e = events(&mut p);
        assert_eq!(e.len(), MAX_UI_EVENTS);
        assert_eq!(*e.last().unwrap(), UiEvent::Button([39.0, 0.0], false));
    }
}
