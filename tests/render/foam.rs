//! Foam on lavapipe, validation layer required (issue 14, item 4): the area the renderer draws
//! white is the whitecap coverage the simulation computed under it, and follows the wind.
//!
//! Looking straight down from 10 m, pixels map evenly onto the sea (~10 cm each), so the share
//! of pixels whitened must match the mean coverage of the sea they show, read from the same
//! simulation replayed step by step on the CPU.
//!
//! Issue 29, item 4: the foam's edges are soft, it is streaked along a strong wind, lit on the
//! wave's normal, and it moves with the water (the waves' orbits and the surface's drift) that
//! the replayed simulation predicts.

use crate::common;

use common::gpu::{self, Frame};
use glam::Vec3;
use vr_ocean::render::camera::project_to_pixel;
use vr_ocean::render::tonemap::srgb_decode;
use vr_ocean::render::StereoMode;
use vr_ocean::sim::{OceanConfig, SimCore, Surfaces};
use vr_ocean::xr::desktop::{PERIOD, SETTLE_DT};

/// Settling frames, `SETTLE_DT` apart, before the drawn ones: 12 s of simulated time (foam
/// settles in ~5 s: decay 0.6/s).
const SKIP: u64 = 120;
/// Drawn frames; the last is captured.
const FRAMES: u64 = 2;
/// Eye height (m) and image side (px).
const HEIGHT: f32 = 10.0;
const SIZE: u32 = 192;

/// The default sea at `wind`, each cascade's own foam (eq. 51) off so that only whitecaps
/// whiten the water.
fn sea(wind: f32) -> OceanConfig {
    let mut cfg = OceanConfig::default_cascades(256).unwrap();
    cfg.waves.wind_speed = wind;
    cfg.waves.foam.growth = 0.0;
    cfg.fit_patches();
    cfg
}

/// The surfaces the app showed on frame `captured` (settling frames included), replayed on the CPU: `app::run` steps
/// first at the first frame's time, then each frame starts the step for its time plus its
/// period, shown on the next frame.
fn shown_surfaces(cfg: &OceanConfig, captured: u64) -> Surfaces {
    let frame_end = |i: u64| {
        if i < SKIP {
            (i + 1) as f64 * SETTLE_DT
        } else {
            SKIP as f64 * SETTLE_DT + (i - SKIP + 1) as f64 * PERIOD
        }
    };
    let mut core = SimCore::new(cfg.clone()).unwrap();
    core.set_focus(0.0, 0.0);
    let mut out = Surfaces::new(cfg);
    core.step(0.0, &mut out);
    for i in 0..captured {
        core.step(frame_end(i), &mut out);
    }
    out
}

/// Mean coverage of the sea both eyes of `frame` show (rest positions on a 5 cm lattice,
/// kept where they project inside the image: straight down, evenly per pixel).
fn coverage_seen(frame: &Frame, surfaces: &Surfaces) -> f64 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for eye in 0..2 {
        let view = &frame.state.views[eye];
        for j in -400..=400 {
            for i in -400..=400 {
                let p = Vec3::new(i as f32 * 0.05, 0.0, j as f32 * 0.05);
                let Some((x, y)) = project_to_pixel(view, p, frame.width, frame.height) else {
                    continue;
                };
                if (0.0..frame.width as f32).contains(&x) && (0.0..frame.height as f32).contains(&y)
                {
                    sum += surfaces.whitecaps.coverage_at(p.x, p.z).unwrap() as f64;
                    n += 1;
                }
            }
        }
    }
    sum / n as f64
}

/// Per pixel of both eyes, how much brighter (sum of RGB codes) `with` is than `without`.
fn gains(with: &Frame, without: &Frame) -> Vec<i32> {
    let mut out = Vec::with_capacity(2 * (with.width * with.height) as usize);
    for eye in 0..2 {
        for y in 0..with.height {
            for x in 0..with.width {
                let sum = |f: &Frame| {
                    f.pixel(eye, x, y)[..3]
                        .iter()
                        .map(|&c| c as i32)
                        .sum::<i32>()
                };
                out.push(sum(with) - sum(without));
            }
        }
    }
    out
}

/// Share of pixels (both eyes) drawn white: at least 200 codes brighter (sum of RGB) with
/// whitecaps than without, a third of what a fully foamed pixel gains here (~600), well above
/// what the bubbles below the foam add (~100).
fn whitened_share(with: &Frame, without: &Frame) -> f64 {
    let g = gains(with, without);
    g.iter().filter(|&&d| d >= 200).count() as f64 / g.len() as f64
}

#[test]
fn the_white_area_is_the_simulated_coverage() {
    let path = gpu::standing(HEIGHT, 0.0, -89.0);
    let mut rows = Vec::new();
    for wind in [8.0f32, 18.0] {
        let mut shots = Vec::new();
        for whitecaps in [true, false] {
            let mut opts = gpu::small_options(StereoMode::TwoPass, vec![SKIP + FRAMES - 1]);
            opts.ocean = sea(wind);
            opts.renderer.whitecaps = whitecaps;
            let (_, mut f) = gpu::render_after(&opts, path.clone(), SKIP, FRAMES, SIZE, SIZE);
            let f = f.remove(0);
            if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
                eprintln!(
                    "saved {}",
                    f.save(&format!("foam-{wind}-{whitecaps}")).display()
                );
            }
            shots.push(f);
        }
        let drawn = whitened_share(&shots[0], &shots[1]);
        let simulated = coverage_seen(&shots[0], &shown_surfaces(&sea(wind), SKIP + FRAMES - 1));
        println!(
            "{wind} m/s: {:.2} % of the pixels drawn white, {:.2} % simulated coverage under them",
            100.0 * drawn,
            100.0 * simulated
        );
        rows.push((wind, drawn, simulated));
    }
    let (_, calm_drawn, calm_simulated) = rows[0];
    let (_, gale_drawn, gale_simulated) = rows[1];
    // A gale's white area is its coverage (the pattern whitens a share c of coverage c).
    assert!(
        gale_simulated > 0.01,
        "the replayed gale barely foams: {rows:?}"
    );
    assert!(
        (0.67..=1.5).contains(&(gale_drawn / gale_simulated)),
        "drawn white area vs coverage: {rows:?}"
    );
    // A breeze stays nearly clear, as its coverage says.
    assert!(
        calm_drawn <= calm_simulated + 0.005,
        "a breeze drawn whiter than its coverage: {rows:?}"
    );
}

/// The gale (20 m/s) straight down from `HEIGHT`, the settings changed by `set`: the captured
/// frame after settling.
fn gale_shot(set: impl Fn(&mut vr_ocean::render::RendererSettings)) -> Frame {
    let mut opts = gpu::small_options(StereoMode::TwoPass, vec![SKIP + FRAMES - 1]);
    opts.ocean = sea(20.0);
    set(&mut opts.renderer);
    let path = gpu::standing(HEIGHT, 0.0, -89.0);
    let (_, mut f) = gpu::render_after(&opts, path, SKIP, FRAMES, SIZE, SIZE);
    f.remove(0)
}

/// The gain (`gains`) of a fully foamed pixel: the 99th percentile of the visibly foamed ones'.
fn white_gain(gains: &[i32]) -> f64 {
    let mut sorted: Vec<i32> = gains.iter().copied().filter(|&g| g > 30).collect();
    sorted.sort_unstable();
    sorted[sorted.len() * 99 / 100] as f64
}

/// Of the pixels foam whitens visibly (at least 30 % of the way from the water without it to
/// fully foamed white, the 99th percentile of the gain: above what the bubbles alone add), the
/// share that is partial (30-70 % of the way): soft edges and thin foam, not paint chips.
fn partial_share(with: &Frame, without: &Frame) -> (f64, usize) {
    let gains = gains(with, without);
    let white = white_gain(&gains);
    let gains: Vec<f64> = gains.into_iter().map(|d| d.max(0) as f64).collect();
    let foamed = gains.iter().filter(|&&g| g >= 0.3 * white).count();
    let partial = gains
        .iter()
        .filter(|&&g| (0.3 * white..=0.7 * white).contains(&g))
        .count();
    (partial as f64 / foamed.max(1) as f64, foamed)
}

#[test]
fn foam_edges_are_soft() {
    let shots: Vec<Frame> = [true, false]
        .into_iter()
        .map(|whitecaps| gale_shot(|r| r.whitecaps = whitecaps))
        .collect();
    if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
        eprintln!("saved {}", shots[0].save("foam-soft").display());
    }
    let (share, foamed) = partial_share(&shots[0], &shots[1]);
    println!(
        "20 m/s: {:.1} % of {foamed} visibly foamed pixels are partial (30-70 % white)",
        100.0 * share
    );
    assert!(foamed > 500, "too little foam to judge: {foamed} pixels");
    assert!(
        share >= 0.4,
        "foam edges are hard: {:.1} % partial",
        100.0 * share
    );
}

/// Mean length (pixels) of the runs of `mask` along image rows (`along_rows`) or columns, both
/// eyes of a `w`×`h` image.
fn mean_run(mask: &[bool], w: u32, h: u32, along_rows: bool) -> f64 {
    let (mut total, mut runs) = (0usize, 0usize);
    let (outer, inner) = if along_rows { (h, w) } else { (w, h) };
    for eye in 0..2 {
        for o in 0..outer {
            let mut run = 0;
            for i in 0..=inner {
                let on = i < inner && {
                    let (x, y) = if along_rows { (i, o) } else { (o, i) };
                    mask[(eye * w * h + y * w + x) as usize]
                };
                if on {
                    run += 1;
                } else if run > 0 {
                    total += run;
                    runs += 1;
                    run = 0;
                }
            }
        }
    }
    total as f64 / runs.max(1) as f64
}

/// Issue 29, item 4: in a gale the foam is drawn out into streaks along the wind. Straight
/// down at 20 m/s blowing toward +x (along the image's rows): the foamed pixels' runs along the
/// wind over those across it, with the streaks against without (the same sea, the same
/// coverage); without, the pattern's cells are round and the ratio is the coverage's own.
#[test]
fn gale_foam_is_streaked_along_the_wind() {
    let bare = gale_shot(|r| r.whitecaps = false);
    let mut ratios = Vec::new();
    for streaks in [true, false] {
        let f = gale_shot(|r| r.foam_streaks = streaks);
        if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
            eprintln!(
                "saved {}",
                f.save(&format!("foam-streaks-{streaks}")).display()
            );
        }
        let gains: Vec<i32> = gains(&f, &bare);
        let white = white_gain(&gains);
        let mask: Vec<bool> = gains.iter().map(|&g| g as f64 >= 0.3 * white).collect();
        let along = mean_run(&mask, SIZE, SIZE, true);
        let across = mean_run(&mask, SIZE, SIZE, false);
        println!(
            "streaks {streaks}: foamed runs {along:.1} px along the wind, {across:.1} across \
             ({} foamed pixels)",
            mask.iter().filter(|&&m| m).count()
        );
        ratios.push(along / across);
    }
    let (on, off) = (ratios[0], ratios[1]);
    assert!(
        on > 1.5 * off,
        "along/across with streaks {on:.2}, without {off:.2}"
    );
}

/// Issue 29, item 4: foam catches the light. A gale (20 m/s) straight down under a low sun
/// (20° high), foam lit on the waves' normals against lit as level foam, the same sea: on the
/// pixels fully foamed in both, the ratio of their linear luminances (under the tone map's
/// knee, so linear in the light) is 1 everywhere for level foam and follows the faces' turn to
/// the sun when lit on its normal (n·l swings by about ±0.2 around the level 0.34 here).
#[test]
fn foam_is_lit_on_the_waves_faces() {
    let shot = |whitecaps: bool, lit: bool| {
        gale_shot(|r| {
            r.whitecaps = whitecaps;
            r.foam_lit = lit;
            r.sun.elevation_deg = 20.0;
        })
    };
    let bare = shot(false, true);
    let lit = shot(true, true);
    let level = shot(true, false);
    if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
        eprintln!("saved {}", lit.save("foam-lit").display());
        eprintln!("saved {}", level.save("foam-level").display());
    }
    let full = |f: &Frame| {
        let g = gains(f, &bare);
        let white = white_gain(&g);
        g.iter()
            .map(|&v| v as f64 >= 0.8 * white)
            .collect::<Vec<bool>>()
    };
    let (full_lit, full_level) = (full(&lit), full(&level));
    let lum = |f: &Frame, eye: usize, x: u32, y: u32| {
        let p = f.pixel(eye, x, y);
        0.2126 * srgb_decode(p[0]) + 0.7152 * srgb_decode(p[1]) + 0.0722 * srgb_decode(p[2])
    };
    let mut ratios = Vec::new();
    let mut i = 0;
    for eye in 0..2 {
        for y in 0..SIZE {
            for x in 0..SIZE {
                if full_lit[i] && full_level[i] {
                    ratios.push((lum(&lit, eye, x, y) / lum(&level, eye, x, y)) as f64);
                }
                i += 1;
            }
        }
    }
    assert!(ratios.len() > 500, "{} fully foamed pixels", ratios.len());
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let sd = (ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / ratios.len() as f64).sqrt();
    println!(
        "{} fully foamed pixels: foam lit on its normal / as level foam {mean:.3} ± {sd:.3}",
        ratios.len()
    );
    assert!(
        sd >= 0.05,
        "foam lit on its normal is level foam everywhere: ratio {mean:.3} ± {sd:.3}"
    );
}

/// Where the image shows the water at `rest` (a rest position) on frame `frame`: its displaced
/// position projected into `frame`'s left eye.
fn pixel_of(frame: &Frame, surfaces: &Surfaces, rest: [f32; 2]) -> Option<[f32; 2]> {
    let d = vr_ocean::sim::query::displacement_at(&surfaces.cascades, rest[0], rest[1]);
    let p = Vec3::new(rest[0] + d[0], d[1], rest[1] + d[2]);
    project_to_pixel(&frame.state.views[0], p, frame.width, frame.height).map(|(x, y)| [x, y])
}

/// The brightness above the water's of pixel (x, y) of `f`'s left eye: foam (the sky's
/// reflection stays under the threshold).
fn foam_weight(f: &Frame, x: i32, y: i32) -> f64 {
    let p = f.pixel(0, x as u32, y as u32);
    (p[..3].iter().map(|&c| c as i32).sum::<i32>() - 450).max(0) as f64
}

/// How far (px) the water under the foam of the centre half of `frames[0]`'s left eye has
/// moved in `frames[1]`, from the simulations `shown` for each: the mean over rest positions
/// (a 5 cm lattice), weighted by the foam they show in the first frame. With `drift`, a rest
/// position has moved by the drift between the two frames.
fn water_shift(frames: &[Frame], shown: &[Surfaces; 2], drift: bool) -> [f32; 2] {
    let side = frames[0].width as f32;
    let (lo, hi) = (side / 4.0, 3.0 * side / 4.0);
    let [d0, d1] = [&shown[0], &shown[1]].map(|s| s.whitecaps.drift);
    let moved = if drift {
        [d1[0] - d0[0], d1[1] - d0[1]]
    } else {
        [0.0; 2]
    };
    let (mut sum, mut weight) = ([0.0f64; 2], 0.0f64);
    for j in -200..=200 {
        for i in -200..=200 {
            let rest = [i as f32 * 0.05, j as f32 * 0.05];
            let Some(a) = pixel_of(&frames[0], &shown[0], rest) else {
                continue;
            };
            if !(lo..hi).contains(&a[0]) || !(lo..hi).contains(&a[1]) {
                continue;
            }
            let w = foam_weight(&frames[0], a[0] as i32, a[1] as i32);
            let later = [rest[0] + moved[0], rest[1] + moved[1]];
            let Some(b) = pixel_of(&frames[1], &shown[1], later).filter(|_| w > 0.0) else {
                continue;
            };
            for k in 0..2 {
                sum[k] += w * (b[k] - a[k]) as f64;
            }
            weight += w;
        }
    }
    sum.map(|s| (s / weight.max(1e-9)) as f32)
}

/// The shift (dx, dy) in pixels, within ±`reach`, that best lines up the bright (foam) parts
/// of `b`'s left eye with the centre half of `a`'s (normalized cross-correlation), and its
/// correlation.
fn foam_shift(a: &Frame, b: &Frame, reach: i32) -> ([i32; 2], f64) {
    let side = a.width as i32;
    let foam = foam_weight;
    let (lo, hi) = (side / 4, 3 * side / 4);
    let window: Vec<f64> = (lo..hi)
        .flat_map(|y| (lo..hi).map(move |x| (x, y)))
        .map(|(x, y)| foam(a, x, y))
        .collect();
    let mean = window.iter().sum::<f64>() / window.len() as f64;
    let centred: Vec<f64> = window.iter().map(|v| v - mean).collect();
    let norm_a = centred.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut best = ([0, 0], f64::MIN);
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            let inside = |v: i32| (0..side).contains(&v);
            if !(inside(lo + dx) && inside(hi - 1 + dx) && inside(lo + dy) && inside(hi - 1 + dy)) {
                continue;
            }
            let other: Vec<f64> = (lo..hi)
                .flat_map(|y| (lo..hi).map(move |x| (x, y)))
                .map(|(x, y)| foam(b, x + dx, y + dy))
                .collect();
            let m = other.iter().sum::<f64>() / other.len() as f64;
            let (mut dot, mut norm_b) = (0.0, 0.0);
            for (u, v) in centred.iter().zip(&other) {
                dot += u * (v - m);
                norm_b += (v - m) * (v - m);
            }
            let r = dot / (norm_a * norm_b.sqrt()).max(1e-9);
            if r > best.1 {
                best = ([dx, dy], r);
            }
        }
    }
    best
}

#[test]
fn foam_moves_with_the_water() {
    // Two frames 2 s apart, straight down on a gale: the foam in the image moves as the water
    // under it does: the waves' orbital motion plus the surface's drift (`sim::drift`), which
    // the replayed simulation predicts. Foam fixed in the world, or carried by the orbits but
    // not the drift, would land elsewhere.
    const LAG: u64 = 144;
    let mut cfg = sea(20.0);
    // Foam that lasts (it halves in 4.6 s instead of 1.2 s), so that most of the first
    // frame's is still there in the second.
    cfg.waves.foam.decay = 0.15;
    let captured = [SKIP, SKIP + LAG];
    let mut opts = gpu::small_options(StereoMode::TwoPass, captured.to_vec());
    opts.ocean = cfg.clone();
    let path = gpu::standing(HEIGHT, 0.0, -89.0);
    let (_, frames) = gpu::render_after(&opts, path, SKIP, LAG + 1, SIZE, SIZE);
    if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
        for (f, c) in frames.iter().zip(captured) {
            eprintln!("saved {}", f.save(&format!("foam-drift-{c}")).display());
        }
    }
    let shown = captured.map(|c| shown_surfaces(&cfg, c));
    let carried = water_shift(&frames, &shown, true);
    let orbits_only = water_shift(&frames, &shown, false);
    let (shift, r) = foam_shift(&frames[0], &frames[1], 40);
    let [d0, d1] = [&shown[0], &shown[1]].map(|s| s.whitecaps.drift);
    println!(
        "foam moved {shift:?} px (correlation {r:.2}); the water {carried:.1?} px, \
         without the drift {orbits_only:.1?} px (drift {:.2} m)",
        (d1[0] - d0[0]).hypot(d1[1] - d0[1])
    );
    let miss = |e: [f32; 2]| (shift[0] as f32 - e[0]).hypot(shift[1] as f32 - e[1]);
    assert!(r > 0.3, "the foam of the two frames barely matches: {r:.2}");
    assert!(
        miss(carried) <= 3.0,
        "foam {shift:?} px, the water {carried:?} px"
    );
    assert!(
        miss(orbits_only) > 6.0,
        "the drift is too small to tell: {orbits_only:?} px"
    );
}
