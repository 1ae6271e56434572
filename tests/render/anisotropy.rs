//! Anisotropic filtering of the normal maps (issue 29, item 5) on Mesa 25's lavapipe in the
//! Debian trixie root of the `openxr (Monado)` step (needs root, so `#[ignore]`d; that step
//! runs it). Bookworm's Mesa 22.3 lavapipe has `samplerAnisotropy` too, but filters a tap
//! about 50x slower than trilinearly (gpu_pass 9.3 s against 0.18 s at 256², Zen 5) and keeps
//! little of the pattern; Mesa 25.0's costs nothing measurable at 4 taps (101-138 ms against
//! 111-119 ms).
//!
//! Looking level at the horizon from the deck, the water just below it (a pixel's footprint
//! there is many times longer than wide) keeps more of its wave pattern with 4 taps than with
//! trilinear filtering, which takes the mip of the footprint's long side; and its mean light
//! stays, because the filtered normals still average the same footprint (the specular AA's
//! variance comes from their length). The run has the Khronos validation layer required.

use crate::common;

use std::path::{Path, PathBuf};
use std::time::Duration;

use common::monado;
use vr_ocean::render::tonemap::srgb_decode;

const EXE: &str = env!("CARGO_BIN_EXE_vr-ocean");
const SIZE: u32 = 320;

/// Renders the level view of the horizon in the root with `taps`; the left eye's image.
fn horizon(root: &Path, taps: u32) -> image::RgbaImage {
    let out = format!("/tmp/vr-ocean-aniso-{taps}-{}", std::process::id());
    let path = format!("{out}.path");
    // 4.5 m up, looking level across the wind (toward −x).
    std::fs::write(root.join(path.trim_start_matches('/')), "0 0 4.5 0 90 0\n").unwrap();
    let size = format!("{SIZE}x{SIZE}");
    let taps_arg = taps.to_string();
    let run = monado::client_without_service(
        root,
        &format!("aniso-{taps}"),
        Path::new(EXE),
        &[
            "headless",
            "--validation",
            "--anisotropy",
            &taps_arg,
            "--msaa",
            "1",
            "--bodies",
            "0",
            "--frames",
            "2",
            "--warmup",
            "0",
            "--size",
            &size,
            "--path",
            &path,
            "--out",
            &out,
        ],
        &[],
        Duration::from_secs(300),
    );
    assert!(run.success(), "{run}");
    assert!(
        !run.stderr.contains("anisotropic filtering:"),
        "the device did not give {taps} taps: {run}"
    );
    let file: PathBuf = root
        .join(out.trim_start_matches('/'))
        .join("frame_00001_left.png");
    let img = image::open(&file)
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
        .to_rgba8();
    let _ = std::fs::remove_dir_all(root.join(out.trim_start_matches('/')));
    let _ = std::fs::remove_file(root.join(path.trim_start_matches('/')));
    img
}

/// Over `rows`: the mean linear luminance, and the high-pass share (the standard deviation of
/// luminance less its 5-pixel horizontal box mean, over the mean): the detail across the view.
fn band(img: &image::RgbaImage, rows: std::ops::Range<u32>) -> (f64, f64) {
    let lum = |p: &image::Rgba<u8>| {
        (0.2126 * srgb_decode(p[0]) + 0.7152 * srgb_decode(p[1]) + 0.0722 * srgb_decode(p[2]))
            as f64
    };
    let (mut sum, mut n, mut hp) = (0.0f64, 0.0f64, 0.0f64);
    for y in rows {
        let row: Vec<f64> = (0..img.width()).map(|x| lum(img.get_pixel(x, y))).collect();
        for x in 2..row.len() - 2 {
            let local = row[x - 2..=x + 2].iter().sum::<f64>() / 5.0;
            sum += row[x];
            hp += (row[x] - local).powi(2);
            n += 1.0;
        }
    }
    let mean = sum / n;
    (mean, (hp / n).sqrt() / mean)
}

#[test]
#[ignore = "needs root and the trixie root (the `openxr (Monado)` step of cargo xtask test)"]
fn distant_water_keeps_its_pattern_with_anisotropic_filtering() {
    let root = monado::root_from_env();
    let off = horizon(&root, 1);
    let on = horizon(&root, 4);
    // Level view: the horizon is the middle row; the band is the next eighth of the image
    // (about 1-8° below it).
    let rows = SIZE / 2 + 2..SIZE / 2 + SIZE / 8;
    let (mean_off, hp_off) = band(&off, rows.clone());
    let (mean_on, hp_on) = band(&on, rows.clone());
    println!(
        "rows {rows:?} below the horizon: high-pass share trilinear {hp_off:.4}, 4 taps \
         {hp_on:.4} ({:.2}x); mean luminance {mean_off:.4} / {mean_on:.4}",
        hp_on / hp_off
    );
    assert!(
        hp_on >= 1.15 * hp_off,
        "anisotropic filtering kept no more of the pattern: {hp_on:.4} vs {hp_off:.4}"
    );
    assert!(
        (mean_on / mean_off - 1.0).abs() <= 0.03,
        "the distant water's light changed: {mean_on:.4} vs {mean_off:.4}"
    );
}
