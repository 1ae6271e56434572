//! Scripted input through the whole panel (pointer, egui, model), like the grab-and-throw
//! tests: aim, hover, press, slider drag, buttons, close, and the redraw-only-on-change rule.

use super::*;
use crate::ui::Beaufort;

fn live() -> PanelModel {
    PanelModel {
        wind_speed: Beaufort::new(3).unwrap().wind_speed(),
        wind_direction_deg: 30.0,
        sun_elevation_deg: 35.0,
        sun_azimuth_deg: 120.0,
        clouds: 0.2,
        bodies: 3,
        comfort: Comfort::default(),
        in_water: false,
        perf: Perf {
            frame_ms: 11.1,
            gpu_ms: Some(6.4),
            level: Some("full"),
        },
    }
}

fn centre(r: [f32; 4]) -> [f32; 2] {
    [(r[0] + r[2]) / 2.0, (r[1] + r[3]) / 2.0]
}

/// One frame: the events, then the update at `t`; the app applies what the user edited.
fn frame(
    panel: &mut Panel,
    model: &mut PanelModel,
    t: f64,
    events: &[PointerEvent],
) -> PanelUpdate {
    for &e in events {
        panel.handle(e);
    }
    let u = panel.update(model, t);
    if let Some(edited) = u.edited {
        *model = edited;
    }
    u
}

#[test]
fn an_open_panel_nobody_touches_is_drawn_once() {
    let mut panel = Panel::new(true, 2.0);
    let mut m = live();
    assert!(frame(&mut panel, &mut m, 0.0, &[]).redrawn);
    let mut redraws = 0;
    for i in 1..100 {
        redraws += frame(&mut panel, &mut m, i as f64 / 72.0, &[]).redrawn as u32;
    }
    // egui may ask for a frame or two after the first (its layout settling), never more.
    assert!(redraws <= 2, "{redraws} redraws of an untouched panel");
    // The performance line redraws only when its text (0.1 ms) changes.
    m.perf.frame_ms = 11.12;
    assert!(!frame(&mut panel, &mut m, 2.0, &[]).redrawn);
    m.perf.frame_ms = 11.3;
    assert!(frame(&mut panel, &mut m, 2.1, &[]).redrawn);
    assert!(!panel.primitives().is_empty());
    assert!(
        !panel.take_textures().set.is_empty(),
        "the font atlas to upload"
    );
}

#[test]
fn aim_and_click_a_beaufort_preset() {
    let mut panel = Panel::new(false, 2.0);
    let mut m = live();
    assert!(!frame(&mut panel, &mut m, 0.0, &[]).redrawn, "closed");
    let u = frame(&mut panel, &mut m, 0.1, &[PointerEvent::Menu]);
    assert!(u.toggled && u.redrawn);
    let eight = centre(panel.widgets().beaufort[8]);
    assert!(eight[0] > 0.0, "laid out: {:?}", panel.widgets());
    // Hover, press (a haptic tick), release: the sea state is force 8.
    frame(&mut panel, &mut m, 0.2, &[PointerEvent::Aim(Some(eight))]);
    let press = frame(&mut panel, &mut m, 0.3, &[PointerEvent::Trigger(true)]);
    assert!(press.haptic);
    frame(&mut panel, &mut m, 0.4, &[PointerEvent::Trigger(false)]);
    assert_eq!(m.wind_speed, Beaufort::new(8).unwrap().wind_speed());
    assert_eq!(m.beaufort(), Beaufort::new(8).ok());
    // A press that misses every widget changes nothing.
    let before = m;
    frame(
        &mut panel,
        &mut m,
        0.5,
        &[
            PointerEvent::Aim(Some([3.0, 3.0])),
            PointerEvent::Trigger(true),
            PointerEvent::Trigger(false),
        ],
    );
    assert_eq!(m, before);
    // Shown, never touched: a value the sliders cannot show exactly stays as it was.
    m.sun_elevation_deg = 35.37;
    m.wind_speed = 18.95;
    frame(&mut panel, &mut m, 0.6, &[]);
    assert_eq!((m.sun_elevation_deg, m.wind_speed), (35.37, 18.95));
}

#[test]
fn dragging_the_wind_slider_moves_the_wind_with_the_hand() {
    let mut panel = Panel::new(true, 2.0);
    let mut m = live();
    frame(&mut panel, &mut m, 0.0, &[]);
    let track = panel.widgets().wind;
    let y = (track[1] + track[3]) / 2.0;
    // The track is the slider's first part (its width in points, times pixels per point).
    let width = 250.0 * panel.pixels_per_point();
    let at = |f: f32| Some([track[0] + f * width, y]);
    frame(&mut panel, &mut m, 0.1, &[PointerEvent::Aim(at(0.1))]);
    frame(&mut panel, &mut m, 0.2, &[PointerEvent::Trigger(true)]);
    let start = m.wind_speed;
    let mut seen = vec![start];
    for (i, f) in [0.3, 0.5, 0.7, 0.9].into_iter().enumerate() {
        frame(
            &mut panel,
            &mut m,
            0.3 + i as f64 * 0.1,
            &[PointerEvent::Aim(at(f))],
        );
        seen.push(m.wind_speed);
    }
    frame(&mut panel, &mut m, 1.0, &[PointerEvent::Trigger(false)]);
    assert!(
        seen.windows(2).all(|w| w[1] > w[0]),
        "the wind follows the drag: {seen:?}"
    );
    assert!(m.wind_speed > 20.0, "{seen:?}");
    // After release, moving the aim changes nothing.
    let held = m.wind_speed;
    frame(&mut panel, &mut m, 1.1, &[PointerEvent::Aim(at(0.2))]);
    assert_eq!(m.wind_speed, held);
}

#[test]
fn the_water_button_asks_in_and_reads_back_on_the_deck_once_in() {
    let mut panel = Panel::new(true, 2.0);
    let mut m = live();
    frame(&mut panel, &mut m, 0.0, &[]);
    let water = centre(panel.widgets().water);
    frame(&mut panel, &mut m, 0.1, &[PointerEvent::Aim(Some(water))]);
    frame(&mut panel, &mut m, 0.2, &[PointerEvent::Trigger(true)]);
    let u = frame(&mut panel, &mut m, 0.3, &[PointerEvent::Trigger(false)]);
    assert!(u.requests.water && u.requests.any());
    // In the water the same button takes the user out: the panel redraws with it.
    m.in_water = true;
    assert!(frame(&mut panel, &mut m, 0.4, &[]).redrawn);
    frame(&mut panel, &mut m, 0.5, &[PointerEvent::Trigger(true)]);
    let u = frame(&mut panel, &mut m, 0.6, &[PointerEvent::Trigger(false)]);
    assert!(u.requests.water);
}

#[test]
fn quit_and_close() {
    let mut panel = Panel::new(true, 2.0);
    let mut m = live();
    frame(&mut panel, &mut m, 0.0, &[]);
    let quit = centre(panel.widgets().quit);
    frame(&mut panel, &mut m, 0.1, &[PointerEvent::Aim(Some(quit))]);
    frame(&mut panel, &mut m, 0.2, &[PointerEvent::Trigger(true)]);
    let u = frame(&mut panel, &mut m, 0.3, &[PointerEvent::Trigger(false)]);
    assert!(u.requests.quit);
    let u = frame(&mut panel, &mut m, 0.4, &[PointerEvent::Menu]);
    assert!(u.toggled && !u.redrawn && !panel.is_open());
    // Closed: the trigger is the scene's again, nothing redraws.
    let u = frame(
        &mut panel,
        &mut m,
        0.5,
        &[PointerEvent::Trigger(true), PointerEvent::Trigger(false)],
    );
    assert!(!u.redrawn && !u.haptic && !u.requests.any());
}
