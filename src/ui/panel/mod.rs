//! The control panel (issue 31): one panel and one model for both front ends, the headset's
//! quad layer and the window's overlay. Pure: egui lays it out and tessellates it into
//! triangles (`render::panel` paints them); the front ends feed [`PointerEvent`]s and apply
//! what the user changed.
//!
//! The UI runs only when something it shows changed (a pointer event, a value of the model,
//! the performance line's rounded text) or egui asked for another frame: an open panel nobody
//! touches costs nothing per frame, and its image is re-rendered only then.

pub mod model;
pub mod pointer;
pub mod view;

pub use model::{Comfort, PanelModel, PanelRequests, Perf};
pub use pointer::{PanelPointer, PointerEvent, UiEvent};

/// Where the panel's main widgets were last laid out (panel pixels), for scripted input in
/// tests and for tools that aim at them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Widgets {
    /// The Beaufort preset buttons 0-10: [min x, min y, max x, max y].
    pub beaufort: [[f32; 4]; 11],
    /// The wind slider's track.
    pub wind: [f32; 4],
    /// The sun height slider's track.
    pub sun: [f32; 4],
    /// The bodies' spawn button.
    pub spawn: [f32; 4],
    /// The reset button.
    pub reset: [f32; 4],
    /// The quit button.
    pub quit: [f32; 4],
    /// The into-the-water (back-on-the-deck) button.
    pub water: [f32; 4],
    /// The performance line.
    pub perf: [f32; 4],
}

/// What one [`Panel::update`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PanelUpdate {
    /// The UI ran: [`Panel::primitives`] and [`Panel::take_textures`] hold a new image.
    pub redrawn: bool,
    /// The model as the user left it, when they changed it.
    pub edited: Option<PanelModel>,
    /// The buttons pressed.
    pub requests: PanelRequests,
    /// A press landed on the panel: play a haptic tick.
    pub haptic: bool,
    /// The panel opened or closed.
    pub toggled: bool,
}

/// The panel: its pointer, egui's context, and the last image's triangles.
pub struct Panel {
    ctx: egui::Context,
    pointer: PanelPointer,
    pixels_per_point: f32,
    /// The model the last image shows (performance rounded as shown).
    drawn: Option<PanelModel>,
    /// When egui asked to run again (s), if it did.
    repaint_at: Option<f64>,
    primitives: Vec<egui::ClippedPrimitive>,
    textures: egui::TexturesDelta,
    widgets: Widgets,
    /// Images drawn so far ([`Panel::generation`]).
    generation: u64,
    /// Draw the pointer's cursor into the image (the headset's aim rays have no other).
    draw_cursor: bool,
}

impl Panel {
    /// A panel, open or closed, drawn at `pixels_per_point` image pixels per egui point.
    pub fn new(open: bool, pixels_per_point: f32) -> Self {
        let ctx = egui::Context::default();
        view::style(&ctx);
        Self {
            ctx,
            pointer: PanelPointer::new(open),
            pixels_per_point,
            drawn: None,
            repaint_at: None,
            primitives: Vec::new(),
            textures: egui::TexturesDelta::default(),
            widgets: Widgets::default(),
            generation: 0,
            draw_cursor: false,
        }
    }

    /// Draws a cursor where the pointer meets the panel, into the image (the headset: its
    /// aim rays have no cursor of their own; the window has the mouse's).
    pub fn set_draw_cursor(&mut self, on: bool) {
        self.draw_cursor = on;
    }

    /// How many images the UI has drawn: a painter repaints when this moved since its last
    /// paint (the panel changed), and only then.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The image's size in pixels.
    pub fn size_px(&self) -> [u32; 2] {
        view::PANEL_POINTS.map(|p| (p * self.pixels_per_point).round() as u32)
    }

    /// Image pixels per egui point.
    pub fn pixels_per_point(&self) -> f32 {
        self.pixels_per_point
    }

    /// Whether the panel is open.
    pub fn is_open(&self) -> bool {
        self.pointer.is_open()
    }

    /// Where the pointer meets the open panel (image pixels), for a cursor.
    pub fn cursor(&self) -> Option<[f32; 2]> {
        self.pointer.cursor()
    }

    /// Whether a press on the panel is held (the front end keeps the trigger for the panel).
    pub fn pressing(&self) -> bool {
        self.pointer.pressing()
    }

    /// Takes a pointer event (positions in image pixels).
    pub fn handle(&mut self, event: PointerEvent) {
        self.pointer.handle(event);
    }

    /// The model the last image shows (its performance line rounded as shown), if one was
    /// drawn since the panel last opened.
    pub fn shown(&self) -> Option<&PanelModel> {
        self.drawn.as_ref()
    }

    /// Where the main widgets were last laid out (image pixels).
    pub fn widgets(&self) -> &Widgets {
        &self.widgets
    }

    /// Runs the UI when the open panel needs it: pointer events came, `live` (the app's state
    /// now, at `now` seconds) differs from what the image shows, or egui asked for a frame.
    pub fn update(&mut self, live: &PanelModel, now: f64) -> PanelUpdate {
        let toggled = self.pointer.take_toggled();
        let haptic = self.pointer.take_haptic();
        let mut update = PanelUpdate {
            toggled,
            haptic,
            ..PanelUpdate::default()
        };
        if !self.is_open() {
            // Nothing to show; forget events (the closing "gone" included) and redraw on open.
            self.pointer.take_ui_events().for_each(drop);
            self.drawn = None;
            return update;
        }
        let shown = PanelModel {
            perf: live.perf.shown(),
            ..*live
        };
        let ppp = self.pixels_per_point;
        let mut events = Vec::new();
        for e in self.pointer.take_ui_events() {
            let at = |p: [f32; 2]| egui::pos2(p[0] / ppp, p[1] / ppp);
            events.push(match e {
                UiEvent::Moved(p) => egui::Event::PointerMoved(at(p)),
                UiEvent::Button(p, pressed) => egui::Event::PointerButton {
                    pos: at(p),
                    button: egui::PointerButton::Primary,
                    pressed,
                    modifiers: egui::Modifiers::NONE,
                },
                UiEvent::Gone => egui::Event::PointerGone,
            });
        }
        let due = self.repaint_at.is_some_and(|t| now >= t);
        if events.is_empty() && !due && self.drawn == Some(shown) {
            return update;
        }
        log::debug!(
            "panel redrawn at {now:.3} s: {} events, repaint due {due}, model changed {}",
            events.len(),
            self.drawn != Some(shown)
        );
        let raw = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(view::PANEL_POINTS[0], view::PANEL_POINTS[1]),
            )),
            time: Some(now),
            events,
            focused: true,
            ..egui::RawInput::default()
        };
        self.ctx.set_pixels_per_point(ppp);
        if self.drawn.is_none() {
            // egui lays out a context's first frame before it knows the screen (right-aligned
            // widgets land far off): a first run with no input settles the layout.
            let (mut m, mut r, mut w) = (*live, PanelRequests::default(), Widgets::default());
            let settle = egui::RawInput {
                events: Vec::new(),
                ..raw.clone()
            };
            let out = self
                .ctx
                .run(settle, |ctx| view::show(ctx, &mut m, &mut r, &mut w));
            // Its textures (the font atlas) are the image's too.
            self.textures.append(out.textures_delta);
        }
        let mut edited = *live;
        let mut requests = PanelRequests::default();
        let mut widgets = Widgets::default();
        let out = self.ctx.run(raw, |ctx| {
            view::show(ctx, &mut edited, &mut requests, &mut widgets);
        });
        self.widgets = Widgets {
            beaufort: widgets.beaufort.map(|r| r.map(|v| v * ppp)),
            wind: widgets.wind.map(|v| v * ppp),
            sun: widgets.sun.map(|v| v * ppp),
            spawn: widgets.spawn.map(|v| v * ppp),
            reset: widgets.reset.map(|v| v * ppp),
            quit: widgets.quit.map(|v| v * ppp),
            water: widgets.water.map(|v| v * ppp),
            perf: widgets.perf.map(|v| v * ppp),
        };
        let mut shapes = out.shapes;
        if let Some(p) = self.pointer.cursor().filter(|_| self.draw_cursor) {
            let at = egui::pos2(p[0] / ppp, p[1] / ppp);
            for shape in [
                egui::Shape::circle_filled(at, 6.0, egui::Color32::from_black_alpha(140)),
                egui::Shape::circle_filled(at, 4.0, egui::Color32::WHITE),
            ] {
                shapes.push(egui::epaint::ClippedShape {
                    clip_rect: egui::Rect::EVERYTHING,
                    shape,
                });
            }
        }
        self.primitives = self.ctx.tessellate(shapes, out.pixels_per_point);
        self.textures.append(out.textures_delta);
        self.repaint_at = out
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .map(|v| v.repaint_delay)
            .filter(|d| *d < std::time::Duration::from_secs(3600))
            .map(|d| now + d.as_secs_f64());
        self.drawn = Some(PanelModel {
            perf: edited.perf.shown(),
            ..edited
        });
        self.generation += 1;
        update.redrawn = true;
        update.edited = (edited != *live).then_some(edited);
        update.requests = requests;
        update
    }

    /// The last image's triangles (panel pixels = points × [`Panel::pixels_per_point`]).
    pub fn primitives(&self) -> &[egui::ClippedPrimitive] {
        &self.primitives
    }

    /// Texture changes (the font atlas) since the last call, for the painter to upload.
    pub fn take_textures(&mut self) -> egui::TexturesDelta {
        std::mem::take(&mut self.textures)
    }
}

#[cfg(test)]
mod tests;
