//! The window's mouse and Tab key as the control panel's pointer (issue 31): Tab opens and
//! closes the panel; while it is shown, the cursor aims at it (window pixels mapped through
//! where the last frame showed it) and a left press on it is the trigger. A press that starts
//! off the panel, and every other button, still turns the view. Pure and allocation-free.

use crate::ui::panel::PointerEvent;
use crate::xr::desktop::present::OverlayPlacement;
use crate::xr::MAX_POINTER_EVENTS;

/// The mouse's side of the panel between frames.
#[derive(Clone, Debug, Default)]
pub(super) struct PanelMouse {
    /// Where the panel was shown last frame; `None` while it is closed.
    placement: Option<OverlayPlacement>,
    /// A left press went to the panel and is held.
    pressed: bool,
    /// The aim last sent (panel pixels), `None` off the panel.
    aimed: Option<[f32; 2]>,
    /// The cursor in window pixels, `None` outside the window.
    cursor: Option<[f32; 2]>,
    queue: [Option<PointerEvent>; MAX_POINTER_EVENTS],
}

impl PanelMouse {
    /// The panel is shown at `placement` (or not, `None`) from this frame on; when it has just
    /// appeared under a still cursor, the panel hears where the cursor is.
    pub fn shown(&mut self, placement: Option<OverlayPlacement>) {
        let appeared = self.placement.is_none() && placement.is_some();
        self.placement = placement;
        if placement.is_none() {
            self.aimed = None;
            self.pressed = false;
        } else if appeared {
            self.aim();
        }
    }

    /// The Tab key: opens or closes the panel.
    pub fn menu(&mut self) {
        self.push(PointerEvent::Menu);
    }

    /// The cursor moved to `at` (window pixels), or left the window (`None`).
    pub fn moved(&mut self, at: Option<[f32; 2]>) {
        self.cursor = at;
        if self.placement.is_some() {
            self.aim();
        }
    }

    /// The left button went down or up. Returns whether the panel took it (the view does not
    /// turn): a press on the shown panel, and the release of such a press.
    pub fn left_button(&mut self, down: bool) -> bool {
        if down && self.aimed.is_some() {
            self.pressed = true;
            self.push(PointerEvent::Trigger(true));
            true
        } else if !down && self.pressed {
            self.pressed = false;
            self.push(PointerEvent::Trigger(false));
            true
        } else {
            false
        }
    }

    /// Moves this frame's events out, first to last.
    pub fn take(&mut self) -> [Option<PointerEvent>; MAX_POINTER_EVENTS] {
        std::mem::take(&mut self.queue)
    }

    /// Tells the panel where the cursor aims when that changed.
    fn aim(&mut self) {
        let at = self
            .cursor
            .zip(self.placement)
            .and_then(|(c, p)| p.panel_pixel(c));
        if at != self.aimed {
            self.aimed = at;
            self.push(PointerEvent::Aim(at));
        }
    }

    /// Queues `e`; an aim right after an aim replaces it (only the last position of a move
    /// matters). A full queue keeps the presses and drops the event, with a log line.
    fn push(&mut self, e: PointerEvent) {
        let len = self.queue.iter().take_while(|q| q.is_some()).count();
        if let (PointerEvent::Aim(_), Some(Some(PointerEvent::Aim(_)))) =
            (e, len.checked_sub(1).map(|i| self.queue[i]))
        {
            self.queue[len - 1] = Some(e);
        } else if len < MAX_POINTER_EVENTS {
            self.queue[len] = Some(e);
        } else {
            log::warn!("too much panel input in one frame; {e:?} ignored");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ash::vk;

    fn events(m: &mut PanelMouse) -> Vec<PointerEvent> {
        m.take().into_iter().flatten().collect()
    }

    #[test]
    fn tab_opens_the_cursor_aims_and_a_left_press_on_the_panel_is_the_trigger() {
        let mut m = PanelMouse::default();
        let at = OverlayPlacement::centred(
            vk::Extent2D {
                width: 1600,
                height: 800,
            },
            [440, 560],
        );
        // Closed: the mouse is the view's, Tab asks to open.
        m.moved(Some([700.0, 300.0]));
        assert!(!m.left_button(true));
        assert!(!m.left_button(false));
        m.menu();
        assert_eq!(events(&mut m), [PointerEvent::Menu]);
        // Shown under the still cursor: the panel hears where it is.
        m.shown(Some(at));
        assert_eq!(events(&mut m), [PointerEvent::Aim(Some([120.0, 180.0]))]);
        m.shown(Some(at));
        assert!(events(&mut m).is_empty());
        // Moves in a row merge; a press and release on the panel are the trigger.
        m.moved(Some([701.0, 300.0]));
        m.moved(Some([702.0, 301.0]));
        assert!(m.left_button(true));
        m.moved(Some([750.0, 301.0]));
        assert!(m.left_button(false));
        assert_eq!(
            events(&mut m),
            [
                PointerEvent::Aim(Some([122.0, 181.0])),
                PointerEvent::Trigger(true),
                PointerEvent::Aim(Some([170.0, 181.0])),
                PointerEvent::Trigger(false),
            ]
        );
        // A drag that slips off the panel keeps the press until release.
        assert!(m.left_button(true));
        m.moved(Some([100.0, 300.0]));
        assert!(m.left_button(false));
        assert_eq!(
            events(&mut m),
            [
                PointerEvent::Trigger(true),
                PointerEvent::Aim(None),
                PointerEvent::Trigger(false),
            ]
        );
        // Off the panel a press turns the view.
        assert!(!m.left_button(true));
        assert!(!m.left_button(false));
        // Closed again: nothing more reaches the panel.
        m.shown(None);
        m.moved(Some([700.0, 300.0]));
        assert!(!m.left_button(true));
        assert!(events(&mut m).is_empty());
    }

    #[test]
    fn a_flood_of_presses_keeps_the_first_and_merges_moves() {
        let mut m = PanelMouse::default();
        m.shown(Some(OverlayPlacement::centred(
            vk::Extent2D {
                width: 800,
                height: 800,
            },
            [440, 560],
        )));
        m.moved(Some([400.0, 400.0]));
        for _ in 0..MAX_POINTER_EVENTS {
            m.left_button(true);
            m.left_button(false);
        }
        let e = events(&mut m);
        assert_eq!(e.len(), MAX_POINTER_EVENTS);
        assert!(matches!(e[0], PointerEvent::Aim(Some(_))));
        assert_eq!(e[1], PointerEvent::Trigger(true));
    }
}
