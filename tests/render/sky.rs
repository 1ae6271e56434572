//! The sky away from a clear midday (issue 29), on lavapipe with the validation layer required:
//! an overcast gale is grey above and below the horizon (Preetham's hazy sky was tan and the
//! sea under it olive), and a low sun lays a bright path on the water (there was none at 1.5°).
//!
//! The path is measured as light (the rendered codes through the inverse tone curve: the knee
//! compresses a glitter) at a resolution that resolves it (a column under a 1.5° sun is under a
//! degree wide near the horizon): at 240 px per eye, in display values, it read 1.16-1.33x the
//! water 15° to its side; in radiance at 480 px it is over 2x (3.7-3.8x since the sun's glint
//! follows Cox & Munk, and brighter than the sky beside the sun).

use crate::common;

use common::gpu::{self, Frame};
use glam::Vec3;
use vr_ocean::app::RunOptions;
use vr_ocean::render::camera::project_to_pixel;
use vr_ocean::render::sky::SunSky;
use vr_ocean::render::tonemap::srgb_decode;
use vr_ocean::render::{Msaa, StereoMode};

/// The side (px) of `render`'s square eye images.
const W: u32 = 240;

fn linear_rgb(p: [u8; 4]) -> Vec3 {
    Vec3::new(srgb_decode(p[0]), srgb_decode(p[1]), srgb_decode(p[2]))
}

fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// HSV saturation of a colour.
fn saturation(c: Vec3) -> f32 {
    1.0 - c.min_element() / c.max_element().max(1e-6)
}

/// The small scene at MSAA 1 under `sun` with `wind` (m/s).
fn options(sun: SunSky, wind: f32) -> RunOptions {
    let mut opts = gpu::small_options(StereoMode::Multiview, vec![41]);
    opts.renderer.msaa = Msaa::X1;
    opts.ocean.waves.wind_speed = wind;
    opts.renderer.sun = sun;
    opts
}

/// One frame of `opts`, 4.5 m up looking along `yaw`/`pitch`, `side` px square per eye (saved
/// as `name` with VR_OCEAN_SAVE_FRAMES).
fn capture(opts: &RunOptions, yaw: f32, pitch: f32, side: u32, name: &str) -> Frame {
    let (_, mut frames) = gpu::render(opts, gpu::standing(4.5, yaw, pitch), 42, side, side);
    let f = frames.pop().expect("one capture");
    if std::env::var_os("VR_OCEAN_SAVE_FRAMES").is_some() {
        println!("saved {}", f.save(name).display());
    }
    f
}

fn render(sun: SunSky, wind: f32, yaw: f32, pitch: f32, name: &str) -> Frame {
    capture(&options(sun, wind), yaw, pitch, W, name)
}

/// The image point of the direction `elevation_deg` above the horizon at `azimuth_deg` (the
/// sun's convention: from +x toward +z), if in view.
fn pixel_of(f: &Frame, eye: usize, elevation_deg: f32, azimuth_deg: f32) -> Option<(f32, f32)> {
    let v = &f.state.views[eye];
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    let d = Vec3::new(ce * ca, se, ce * sa);
    project_to_pixel(v, v.position + d * 1.0e5, f.width, f.height)
}

/// Mean linear colour of the pixels of `eye` between the rows of elevations `from`..`to`
/// (degrees; negative below the horizon, where the sea's rows are taken at the same image
/// rows as the sky's mirror) straight ahead, over the middle 80 % of the columns.
fn band(f: &Frame, eye: usize, azimuth: f32, from: f32, to: f32) -> Vec3 {
    let row = |e: f32| pixel_of(f, eye, e, azimuth).expect("in view").1;
    let (r0, r1) = (row(from).min(row(to)), row(from).max(row(to)));
    let (mut sum, mut n) = (Vec3::ZERO, 0);
    for y in r0.ceil() as u32..=(r1.floor() as u32).min(f.height - 1) {
        for x in f.width / 10..f.width * 9 / 10 {
            sum += linear_rgb(f.pixel(eye, x, y));
            n += 1;
        }
    }
    assert!(n > 0, "no rows between {from}° and {to}°");
    sum / n as f32
}

#[test]
fn an_overcast_gale_is_grey_above_and_below_the_horizon() {
    // Looking along −z (azimuth −90°), the sun 35° high behind and to the side, the default
    // turbidity (clouds over haze, turbidity 10, are as grey, 1-2 % redder than blue: the haze
    // reddens the sunlight the deck diffuses).
    let gale = |clouds: f32| SunSky {
        elevation_deg: 35.0,
        azimuth_deg: 120.0,
        turbidity: 2.5,
        clouds,
    };
    let overcast = render(gale(1.0), 20.0, 0.0, 0.0, "overcast");
    let clear = render(gale(0.0), 20.0, 0.0, 0.0, "clear");
    for eye in 0..2 {
        let sky = band(&overcast, eye, -90.0, 2.0, 10.0);
        // The sea reflecting that band: the rows 2-10° below the horizon.
        let sea = band(&overcast, eye, -90.0, -2.0, -10.0);
        let blue_sky = band(&clear, eye, -90.0, 2.0, 10.0);
        println!(
            "eye {eye}: overcast sky 2-10° up {sky:.3} (saturation {:.3}), sea 2-10° down {sea:.3} \
             (saturation {:.3}); clear sky {blue_sky:.3} (saturation {:.3})",
            saturation(sky),
            saturation(sea),
            saturation(blue_sky)
        );
        assert!(
            saturation(sky) <= 0.15 && sky.z >= sky.x,
            "the overcast sky is not grey: {sky}"
        );
        assert!(
            saturation(sea) <= 0.15 && sea.z >= sea.x,
            "the sea under it is not grey: {sea}"
        );
        assert!(luminance(sea) < luminance(sky), "{sea} vs {sky}");
        // The same band under a clear sky is blue: the test tells them apart.
        assert!(
            saturation(blue_sky) > 0.2 && blue_sky.z > blue_sky.x,
            "{blue_sky}"
        );
    }
}

/// The exposed radiance (scene-linear, before the tone curve) of a pixel: the curve's knee
/// compresses a glitter path, so ratios of light are read through its inverse. A white code
/// (255) reads as code 254's radiance: a lower bound (a glint counts for less, never more).
fn radiance(p: [u8; 4]) -> f32 {
    let c = linear_rgb([p[0].min(254), p[1].min(254), p[2].min(254), 255]);
    luminance(vr_ocean::render::tonemap::pbr_neutral_inverse(c).expect("below white"))
}

#[test]
fn a_low_sun_lays_a_glitter_column_on_the_water() {
    // At 480 px per eye (the Quest eyes' field: ~5 px a degree, 2 px at 240, where the column
    // is a pixel wide) with the headsets' shading: the lobe filtered, no supersampling.
    const SIDE: u32 = 480;
    for elevation in [4.0f32, 1.5] {
        // Facing the sun (azimuth −90° is straight ahead), looking 4° down, clear maritime air
        // (turbidity 2.5, the default).
        let sun = SunSky {
            elevation_deg: elevation,
            azimuth_deg: -90.0,
            turbidity: 2.5,
            clouds: 0.0,
        };
        let mut opts = options(sun, 6.0);
        opts.renderer.supersampling = false;
        let f = capture(&opts, 0.0, -4.0, SIDE, &format!("glitter-{elevation}"));
        for eye in 0..2 {
            // Mean radiance over rows `from`..`to` degrees of elevation, ±0.4° around `azimuth`.
            let patch = |azimuth: f32, from: f32, to: f32| {
                let row = |e: f32| pixel_of(&f, eye, e, azimuth).expect("in view").1;
                let (r0, r1) = (row(from).min(row(to)), row(from).max(row(to)));
                let (mut sum, mut n) = (0.0f32, 0);
                for y in r0.ceil() as u32..=r1.floor() as u32 {
                    let e = from + (to - from) * (y as f32 - row(from)) / (row(to) - row(from));
                    let left = pixel_of(&f, eye, e, azimuth - 0.4).expect("in view").0;
                    let right = pixel_of(&f, eye, e, azimuth + 0.4).expect("in view").0;
                    for x in left.round() as u32..=right.round() as u32 {
                        sum += radiance(f.pixel(eye, x, y));
                        n += 1;
                    }
                }
                assert!(n > 0, "no pixels at {azimuth}° from {from}° to {to}°");
                sum / n as f32
            };
            // The water from 0.5° to 5° below the horizon: under the sun, 15° to either side.
            let column = patch(-90.0, -0.5, -5.0);
            let sides = [patch(-105.0, -0.5, -5.0), patch(-75.0, -0.5, -5.0)];
            let brighter_side = sides[0].max(sides[1]);
            // The sky beside the sun (5° and 10° to either side, at its height).
            let beside =
                [-100.0, -95.0, -85.0, -80.0].map(|a| patch(a, elevation - 0.3, elevation + 0.3));
            let sky_beside = beside.iter().fold(0.0f32, |m, &v| m.max(v));
            println!(
                "sun {elevation}°, eye {eye}: column {column:.3}, water 15° aside {:.3} / {:.3} \
                 ({:.2}x), the sky beside the sun {sky_beside:.3} ({:.2}x)",
                sides[0],
                sides[1],
                column / brighter_side,
                column / sky_beside
            );
            assert!(
                column >= 1.5 * brighter_side,
                "no glitter column: {column} vs {sides:?} 15° to the sides"
            );
            // Cox & Munk's glint over a Gaussian sea (issue 43): 1.10-1.21x the sky 5-10°
            // beside the sun; 0.72x with GGX's masking at grazing.
            assert!(
                column > sky_beside,
                "the glitter column ({column}) is darker than the sky beside the sun \
                 ({sky_beside})"
            );
            // The sky brightest toward the sun at every height down to the horizon.
            for e in [0.3f32, 0.6, 1.0, 2.5, 3.0, 6.0] {
                if (e - elevation).abs() < 0.8 {
                    continue; // the sun's disc (0.27° in radius) would count toward it
                }
                let toward = patch(-90.0, e - 0.2, e + 0.2);
                for a in [-120.0, -105.0, -75.0, -60.0] {
                    let away = patch(a, e - 0.2, e + 0.2);
                    assert!(
                        toward > away,
                        "the sky {e}° up is brighter {}° from the sun ({away}) than toward it \
                         ({toward})",
                        a + 90.0
                    );
                }
            }
        }
    }
}
