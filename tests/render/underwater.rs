//! Under the surface on lavapipe, validation layer required (issue 45): the view from below
//! shows Snell's window and the water's own colour, the waterline is a sharp line in both eyes,
//! and in a storm every frame is drawn from the side of the surface the eye is on.

use crate::common;

use common::gpu::{self, Frame};
use glam::Vec3;
use vr_ocean::app::{self, Capture, RunHooks};
use vr_ocean::render::camera::project_to_pixel;
use vr_ocean::render::ocean::WATERLINE_MARGIN_M;
use vr_ocean::render::tonemap::srgb_decode;
use vr_ocean::render::StereoMode;
use vr_ocean::sim::query::depth_at;
use vr_ocean::sim::OceanConfig;
use vr_ocean::xr::desktop::PERIOD;

const SIZE: u32 = 128;
// Both eyes in two passes, as the app draws them on lavapipe: Mesa 22.3's multiview writes the
// second view's clipped triangles (the surface right over a swimmer's head) into the first's.

/// The default cascades on a 64² grid at `wind` m/s.
fn sea(wind: f32) -> OceanConfig {
    let mut cfg = OceanConfig::default_cascades(64).unwrap();
    cfg.waves.wind_speed = wind;
    cfg.fit_patches();
    cfg
}

/// One frame (the second) seen from `height` m looking up by `pitch` degrees over a `wind` sea.
fn shot(height: f32, pitch: f32, wind: f32, name: &str) -> Frame {
    let mut opts = gpu::small_options(StereoMode::TwoPass, vec![1]);
    opts.ocean = sea(wind);
    let (_, mut frames) = gpu::render(&opts, gpu::standing(height, 0.0, pitch), 2, SIZE, SIZE);
    let f = frames.pop().expect("the captured frame");
    println!("{name}: {}", f.save(name).display());
    f
}

/// Linear luminance (Rec. 709) of a pixel.
fn luminance(p: [u8; 4]) -> f64 {
    let [r, g, b] = [0, 1, 2].map(|i| f64::from(srgb_decode(p[i])));
    0.2126 * r + 0.7152 * g + 0.0722 * b
}

/// Mean linear RGB and luminance of `eye`'s pixels in [x0, x1) × [y0, y1).
fn mean(f: &Frame, eye: usize, x: (u32, u32), y: (u32, u32)) -> ([f64; 3], f64) {
    let (mut rgb, mut lum, mut n) = ([0.0; 3], 0.0, 0.0);
    for yy in y.0..y.1 {
        for xx in x.0..x.1 {
            let p = f.pixel(eye, xx, yy);
            for (c, s) in rgb.iter_mut().enumerate() {
                *s += f64::from(srgb_decode(p[c]));
            }
            lum += luminance(p);
            n += 1.0;
        }
    }
    (rgb.map(|c| c / n), lum / n)
}

/// The world direction of pixel (x, y)'s centre in `eye` of `f`.
fn ray_of(f: &Frame, eye: usize, x: u32, y: u32) -> Vec3 {
    let v = &f.state.views[eye];
    let u = (x as f32 + 0.5) / f.width as f32;
    let w = (y as f32 + 0.5) / f.height as f32;
    let tx = v.fov.angle_left.tan() + u * (v.fov.angle_right.tan() - v.fov.angle_left.tan());
    let ty = v.fov.angle_up.tan() + w * (v.fov.angle_down.tan() - v.fov.angle_up.tan());
    v.orientation * Vec3::new(tx, ty, -1.0).normalize()
}

/// Off the vertical (degrees), the corners counted as outside Snell's window: its edge on a flat
/// sea (48.6) and five degrees for the waves of a 2 m/s sea, which tilt the edge back and forth
/// (their slopes' deviation, 0.11, turns a ray near the critical angle by several degrees).
const OUTSIDE_WINDOW_DEG: f32 = 53.6;

#[test]
fn looking_up_from_four_metres_shows_snells_window() {
    // A calm sea: the window's edge sharp, 48.6 degrees off the vertical. Its centre, the
    // pixel straight up, against the image's corners outside it (the corners' rays 52-61
    // degrees off the vertical in the headset's asymmetric fields of view; the one at 52, on
    // the window's wavy edge, is left out and printed).
    let f = shot(-4.0, 89.9, 2.0, "underwater-up");
    let side = SIZE / 10;
    let around = |c: f32| {
        let c = (c.round() as u32).clamp(side / 2, SIZE - side / 2);
        (c - side / 2, c + side / 2)
    };
    for eye in 0..2 {
        let v = &f.state.views[eye];
        let (zx, zy) = project_to_pixel(v, v.position + Vec3::Y * 100.0, SIZE, SIZE)
            .expect("the zenith is ahead");
        let (_, centre) = mean(&f, eye, around(zx), around(zy));
        let mut outside = Vec::new();
        for (x, y) in [(0, 0), (SIZE - 1, 0), (0, SIZE - 1), (SIZE - 1, SIZE - 1)] {
            let off = ray_of(&f, eye, x, y).y.acos().to_degrees();
            let (_, l) = mean(&f, eye, around(x as f32), around(y as f32));
            println!("eye {eye}: corner ({x}, {y}) {off:.1} degrees off the vertical: {l:.4}");
            if off > OUTSIDE_WINDOW_DEG {
                outside.push(l);
            }
        }
        assert!(
            outside.len() >= 3,
            "eye {eye}: the field of view's corners moved into the window"
        );
        let corner = outside.iter().sum::<f64>() / outside.len() as f64;
        let ratio = centre / corner;
        println!("eye {eye}: window centre ({zx:.0}, {zy:.0}) {centre:.4}, corners {corner:.4}: {ratio:.2}x");
        assert!(
            ratio >= 3.0,
            "eye {eye}: the window's centre is only {ratio:.2}x the corners (linear luminance)"
        );
    }
}

#[test]
fn looking_level_from_four_metres_the_lower_half_is_the_water() {
    let f = shot(-4.0, 0.0, 2.0, "underwater-level");
    let half = SIZE / 2;
    for eye in 0..2 {
        let (lower, lower_lum) = mean(&f, eye, (0, SIZE), (half, SIZE));
        let (_, upper_lum) = mean(&f, eye, (0, SIZE), (0, half));
        println!("eye {eye}: lower rgb {lower:.4?} lum {lower_lum:.4}, upper lum {upper_lum:.4}");
        let [r, g, b] = lower;
        assert!(
            g > r && b > r,
            "eye {eye}: the lower half is not water-coloured: linear rgb {lower:?}"
        );
        assert!(
            lower_lum < upper_lum,
            "eye {eye}: the depths ({lower_lum:.4}) are not darker than the view up ({upper_lum:.4})"
        );
    }
}

#[test]
fn at_the_mean_level_the_waterline_is_a_sharp_line_in_both_eyes() {
    // The eye at the mean level of a glassy sea looking level: the sky above the horizon, the
    // water below it, the two meeting across a couple of pixels.
    let f = shot(0.0, 0.0, 0.5, "underwater-line");
    let mut rows = [0.0; 2];
    for (eye, row) in rows.iter_mut().enumerate() {
        let (sky, sky_lum) = mean(&f, eye, (0, SIZE), (0, SIZE / 4));
        let (water, water_lum) = mean(&f, eye, (0, SIZE), (3 * SIZE / 4, SIZE));
        println!("eye {eye}: sky {sky:.4?} lum {sky_lum:.4}; water {water:.4?} lum {water_lum:.4}");
        assert!(
            water[1] > water[0] && water[2] > water[0] && water_lum < 0.5 * sky_lum,
            "eye {eye}: the lower quarter is not the water seen from inside it"
        );
        // Per column, the line: the largest fall of luminance over three rows (where the
        // sky meets the water); sharp: those three rows hold at least 80 % of the fall over
        // eight rows around them.
        let mut line = 0.0;
        let mut softest = f64::MAX;
        for x in 0..SIZE {
            let lum: Vec<f64> = (0..SIZE).map(|y| luminance(f.pixel(eye, x, y))).collect();
            let fall =
                |y: usize, n: usize| lum[y.saturating_sub(n)] - lum[(y + n).min(lum.len() - 1)];
            let (at, steep) = (1..SIZE as usize - 1)
                .map(|y| (y, lum[y - 1] - lum[y + 1]))
                .max_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            let wide = fall(at, 4).max(steep);
            softest = softest.min(steep / wide);
            line += at as f64;
        }
        *row = line / f64::from(SIZE);
        let horizon = f.horizon_row(eye);
        println!(
            "eye {eye}: line at row {row:.1} (horizon {horizon:.1}); the softest column's three \
             rows hold {:.0} % of its fall",
            100.0 * softest
        );
        assert!(
            softest >= 0.8,
            "eye {eye}: the waterline is soft: {:.0} % of a column's fall in three rows",
            100.0 * softest
        );
        assert!(
            (*row - f64::from(horizon)).abs() < 3.0,
            "eye {eye}: the line (row {row:.1}) is not at the horizon ({horizon:.1})"
        );
    }
    assert!(
        (rows[0] - rows[1]).abs() < 1.0,
        "the eyes disagree on the line: rows {rows:?}"
    );
}

/// Per frame of the storm: the eyes' depth under the surface the frame showed (m, by the
/// height query) and the upper half's mean linear red; and the darkest frame's mean luminance.
struct Storm(Vec<(f32, f64)>, f64);

impl RunHooks for Storm {
    fn capture(&mut self, c: &Capture<'_>) -> Result<(), app::AppError> {
        let mid = (c.state.views[0].position + c.state.views[1].position) * 0.5;
        let depth = depth_at(&c.surfaces.cascades, mid.to_array());
        let (mut sum, mut lum, mut n) = (0.0, 0.0, 0.0);
        for eye in c.eyes {
            for y in 0..c.height {
                for x in 0..c.width {
                    let i = 4 * (y * c.width + x) as usize;
                    if y < c.height / 2 {
                        sum += f64::from(srgb_decode(eye[i]));
                        n += 1.0;
                    }
                    lum += luminance(eye[i..i + 4].try_into().unwrap());
                }
            }
        }
        self.0.push((depth, sum / n));
        self.1 = self.1.min(lum / (2.0 * n));
        Ok(())
    }
}

#[test]
fn in_a_storm_every_frame_is_drawn_from_the_side_the_eye_is_on() {
    // The eye fixed half a metre above the mean level of a 15 m/s sea for 30 s, looking level:
    // from the air the upper half is the sky and the waves reflecting it; from under the water
    // it is the water and the surface's underside reflecting the depths (Snell's window starts
    // 41 degrees up), whose light crossed metres of water: no red left.
    const SECONDS: f64 = 30.0;
    let frames = (SECONDS / PERIOD).round() as u64;
    let size = 48;
    let mut opts = gpu::small_options(StereoMode::TwoPass, (0..frames).collect());
    opts.ocean = sea(15.0);
    let mut hooks = Storm(Vec::new(), f64::MAX);
    gpu::render_with(
        &opts,
        gpu::standing(0.5, 0.0, 0.0),
        frames,
        size,
        size,
        &mut hooks,
    );
    let (shots, darkest) = (hooks.0, hooks.1);
    // No blank frame going under or coming back: the water's own light (0.016 looking level
    // from 4 m) is the darkest there is.
    println!("darkest frame: mean luminance {darkest:.4}");
    assert!(
        darkest > 0.005,
        "a frame is all but blank: mean luminance {darkest:.4}"
    );
    assert_eq!(shots.len() as u64, frames);
    // The frames away from the line on either side.
    let clear = |below: bool| {
        shots
            .iter()
            .filter(move |(d, _)| {
                (*d > WATERLINE_MARGIN_M) == below && d.abs() > WATERLINE_MARGIN_M
            })
            .map(|&(_, l)| l)
    };
    let above = clear(false).count();
    let below = clear(true).count();
    let least_above = clear(false).fold(f64::MAX, f64::min);
    let most_below = clear(true).fold(0.0, f64::max);
    println!(
        "{frames} frames: {above} above, {below} below, {} within {WATERLINE_MARGIN_M} m of the \
         surface; the upper half's linear red: at least {least_above:.4} above, at most \
         {most_below:.4} below",
        shots.len() - above - below
    );
    assert!(
        above > frames as usize / 10 && below > frames as usize / 10,
        "the eye should spend time on both sides: {above} above, {below} below"
    );
    // A frame away from the line whose upper half is on the wrong side of this red is a
    // mismatch: the air's upper half is over half white's red (0.55 at the least measured),
    // the water's under a quarter of it (0.12 at the most, a crest's window tilted into view
    // half a metre under it).
    let threshold = 0.25;
    let mismatches = shots
        .iter()
        .filter(|(d, _)| d.abs() > WATERLINE_MARGIN_M)
        .filter(|&&(d, l)| (d > 0.0) != (l < threshold))
        .count();
    println!("threshold {threshold:.4}: {mismatches} mismatches");
    for (i, (d, l)) in shots.iter().enumerate() {
        if d.abs() > WATERLINE_MARGIN_M && (*d > 0.0) != (*l < threshold) {
            println!("frame {i}: depth {d:.3} m, red {l:.4}");
        }
    }
    assert_eq!(mismatches, 0);
}

/// The float mode's comfort vignette (issue 45): at full strength, the view within 30° of each
/// eye's axis is untouched, and beyond the feather (42°) the frame is black, in both eyes;
/// the same frame without it is bright there.
#[test]
fn the_comfort_vignette_narrows_the_view_around_each_eyes_axis() {
    let mut opts = gpu::small_options(StereoMode::TwoPass, vec![1]);
    opts.ocean = sea(8.0);
    let path = || gpu::standing(4.6, 0.0, -10.0);
    let plain = {
        let (_, mut frames) = gpu::render(&opts, path(), 2, SIZE, SIZE);
        frames.pop().expect("the captured frame")
    };
    let mut hooks = gpu::Collect(Vec::new());
    gpu::render_set_up(&opts, path(), 2, SIZE, SIZE, &mut hooks, |xr| {
        xr.show_vignette(1.0)
    });
    let narrowed = hooks.0.pop().expect("the captured frame");
    println!("vignette: {}", narrowed.save("vignette").display());
    for eye in 0..2 {
        let forward = narrowed.state.views[eye].orientation * Vec3::NEG_Z;
        let (mut inside, mut outside, mut outside_plain) = ((0.0, 0.0), 0.0, 0.0);
        let mut n_out = 0.0;
        for y in 0..SIZE {
            for x in 0..SIZE {
                let angle = ray_of(&narrowed, eye, x, y)
                    .angle_between(forward)
                    .to_degrees();
                let (a, b) = (narrowed.pixel(eye, x, y), plain.pixel(eye, x, y));
                if angle < 28.0 {
                    let d: i32 = (0..3)
                        .map(|c| (a[c] as i32 - b[c] as i32).abs())
                        .max()
                        .unwrap();
                    inside.0 += d as f64;
                    inside.1 += 1.0;
                } else if angle > 44.0 {
                    outside += luminance(a);
                    outside_plain += luminance(b);
                    n_out += 1.0;
                }
            }
        }
        let inside_diff = inside.0 / inside.1;
        println!(
            "eye {eye}: inside 28° mean |Δ| {inside_diff:.3} ({} px); beyond 44° luminance \
             {:.4} vs {:.4} without ({n_out} px)",
            inside.1,
            outside / n_out,
            outside_plain / n_out
        );
        assert!(
            inside.1 > 1000.0 && n_out > 500.0,
            "too few pixels to judge"
        );
        assert!(inside_diff < 0.01, "the clear field changed: {inside_diff}");
        assert!(outside / n_out < 1e-3, "the periphery is not dark");
        assert!(
            outside_plain / n_out > 0.05,
            "the plain frame is dark there too"
        );
    }
}
