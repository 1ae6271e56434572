//! The panel's layout in egui: the sea state (Beaufort presets 0-10 and a wind slider), the
//! wind's direction, the sun and clouds, the bodies, comfort, the performance line and quit.
//! Widgets edit a copy of the [`PanelModel`]; buttons set [`PanelRequests`].

use egui::{Color32, FontId, RichText, TextStyle};

use crate::ui::beaufort::MAX_PRESET;
use crate::ui::panel::model::{PanelModel, PanelRequests};
use crate::ui::panel::Widgets;
use crate::ui::Beaufort;

/// The panel's size in points (egui's logical pixels); the image is this times the pixels
/// per point.
pub const PANEL_POINTS: [f32; 2] = [440.0, 560.0];

/// Styles the context once: large type and targets for a panel read at arm's length and
/// aimed at with a hand-held ray.
pub fn style(ctx: &egui::Context) {
    ctx.style_mut(|s| {
        s.text_styles = [
            (TextStyle::Heading, FontId::proportional(20.0)),
            (TextStyle::Body, FontId::proportional(15.0)),
            (TextStyle::Button, FontId::proportional(15.0)),
            (TextStyle::Small, FontId::proportional(12.0)),
            (TextStyle::Monospace, FontId::monospace(14.0)),
        ]
        .into();
        s.spacing.item_spacing = egui::vec2(8.0, 7.0);
        s.spacing.button_padding = egui::vec2(8.0, 4.0);
        s.spacing.slider_width = 250.0;
        s.spacing.interact_size.y = 24.0;
        s.visuals = egui::Visuals::dark();
        s.visuals.panel_fill = Color32::from_rgb(18, 28, 38);
        // Near-white text on the dark fill: contrast for a panel seen through lenses.
        s.visuals.override_text_color = Some(Color32::from_gray(235));
        s.animation_time = 0.0;
    });
}

/// A slider that leaves a value it is shown alone: egui's default clamping rounds the value
/// to the displayed decimals every frame (a panel merely opened would change the sun).
fn slider<'a>(value: &'a mut f32, range: std::ops::RangeInclusive<f32>) -> egui::Slider<'a> {
    egui::Slider::new(value, range).clamping(egui::SliderClamping::Edits)
}

/// A widget's rectangle as [min x, min y, max x, max y] (points).
fn corners(r: egui::Rect) -> [f32; 4] {
    [r.min.x, r.min.y, r.max.x, r.max.y]
}

/// Lays the panel out for one frame, editing `m`, setting `requests` and noting where the main
/// widgets are in `widgets` (points).
pub fn show(
    ctx: &egui::Context,
    m: &mut PanelModel,
    requests: &mut PanelRequests,
    widgets: &mut Widgets,
) {
    egui::CentralPanel::default().show(ctx, |ui| {
        ui.horizontal(|ui| {
            ui.heading("vr-ocean");
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                let quit = ui.button("Quit");
                widgets.quit = corners(quit.rect);
                if quit.clicked() {
                    requests.quit = true;
                }
            });
        });
        ui.separator();
        sea(ui, m, widgets);
        ui.separator();
        sky(ui, m, widgets);
        ui.separator();
        bodies(ui, m, requests, widgets);
        ui.separator();
        comfort(ui, m, requests, widgets);
        ui.separator();
        perf(ui, m, widgets);
    });
}

fn sea(ui: &mut egui::Ui, m: &mut PanelModel, widgets: &mut Widgets) {
    let now = m.beaufort();
    let title = match now {
        Some(b) => format!("Sea state: Beaufort {} ({})", b.number(), b.force().name),
        None => "Sea state: beyond force 12".to_string(),
    };
    ui.label(RichText::new(title).strong());
    ui.horizontal(|ui| {
        ui.spacing_mut().item_spacing.x = 7.0;
        for n in 0..=MAX_PRESET {
            let Ok(force) = Beaufort::new(n) else {
                continue;
            };
            let on = now == Some(force);
            let button = ui
                .add_sized([30.0, 26.0], egui::Button::selectable(on, format!("{n}")))
                .on_hover_text(format!(
                    "Beaufort {n}: {}, {:.0} m/s",
                    force.force().name,
                    force.wind_speed()
                ));
            widgets.beaufort[n as usize] = corners(button.rect);
            if button.clicked() {
                m.wind_speed = force.wind_speed();
            }
        }
    });
    let wind = ui.add(
        slider(&mut m.wind_speed, 0.5..=30.0)
            .text("wind")
            .suffix(" m/s")
            .fixed_decimals(1),
    );
    widgets.wind = corners(wind.rect);
    ui.add(
        slider(&mut m.wind_direction_deg, 0.0..=359.0)
            .text("toward")
            .suffix("°")
            .fixed_decimals(0),
    );
}

fn sky(ui: &mut egui::Ui, m: &mut PanelModel, widgets: &mut Widgets) {
    ui.label(RichText::new("Sky").strong());
    let sun = ui.add(
        slider(&mut m.sun_elevation_deg, -10.0..=90.0)
            .text("sun height")
            .suffix("°")
            .fixed_decimals(0),
    );
    widgets.sun = corners(sun.rect);
    ui.add(
        slider(&mut m.sun_azimuth_deg, 0.0..=359.0)
            .text("sun bearing")
            .suffix("°")
            .fixed_decimals(0),
    );
    let mut cover = m.clouds * 100.0;
    if ui
        .add(
            slider(&mut cover, 0.0..=100.0)
                .text("clouds")
                .suffix(" %")
                .fixed_decimals(0),
        )
        .changed()
    {
        m.clouds = cover / 100.0;
    }
}

fn bodies(ui: &mut egui::Ui, m: &PanelModel, requests: &mut PanelRequests, widgets: &mut Widgets) {
    ui.horizontal(|ui| {
        ui.label(RichText::new(format!("Bodies: {}", m.bodies)).strong());
        let spawn = ui.button("Spawn in front");
        widgets.spawn = corners(spawn.rect);
        if spawn.clicked() {
            requests.spawn_body = true;
        }
        let reset = ui.button("Reset");
        widgets.reset = corners(reset.rect);
        if reset.clicked() {
            requests.reset_bodies = true;
        }
    });
}

fn comfort(
    ui: &mut egui::Ui,
    m: &mut PanelModel,
    requests: &mut PanelRequests,
    widgets: &mut Widgets,
) {
    ui.label(RichText::new("Comfort").strong());
    ui.horizontal(|ui| {
        let label = if m.in_water {
            "Back on the deck"
        } else {
            "Into the water"
        };
        let water = ui.button(label);
        widgets.water = corners(water.rect);
        if water.clicked() {
            requests.water = true;
        }
        ui.checkbox(&mut m.comfort.ride_waves, "ride the waves");
        ui.checkbox(&mut m.comfort.vignette, "vignette");
    });
    let c = &mut m.comfort;
    ui.horizontal(|ui| {
        ui.checkbox(&mut c.smooth_turn, "smooth turn");
        ui.checkbox(&mut c.seated, "seated");
    });
    ui.add_enabled(
        !c.smooth_turn,
        slider(&mut c.snap_turn_deg, 15.0..=90.0)
            .text("snap turn")
            .suffix("°")
            .step_by(15.0)
            .fixed_decimals(0),
    );
    ui.add(
        slider(&mut c.deck_height_m, 0.5..=10.0)
            .text("deck height")
            .suffix(" m")
            .fixed_decimals(1),
    );
}

fn perf(ui: &mut egui::Ui, m: &PanelModel, widgets: &mut Widgets) {
    let p = m.perf.shown();
    let gpu = p.gpu_ms.map_or("-".to_string(), |g| format!("{g:.1} ms"));
    let level = p
        .level
        .map_or(String::new(), |l| format!(" | governor: {l}"));
    let line = ui.label(
        RichText::new(format!("frame {:.1} ms | GPU {gpu}{level}", p.frame_ms))
            .monospace()
            .color(Color32::from_gray(190)),
    );
    widgets.perf = corners(line.rect);
}
