//! The command line: bad input gives a clear error and a non-zero exit, never a panic; export
//! writes files other tools can read.

use crate::common;

use std::path::PathBuf;

use common::{assert_rejected, vr_ocean};

fn scratch_dir(name: &str) -> PathBuf {
    let d = common::scratch_path(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn bad_parameters_are_named_with_their_valid_range() {
    let dir = scratch_dir("bad");
    let out = dir.to_str().unwrap();
    let base = ["export", "--time", "0", "--out", out];
    let with = |extra: &[&'static str]| -> Vec<&str> {
        let mut v: Vec<&str> = base.to_vec();
        v.extend_from_slice(extra);
        v
    };
    assert_rejected(&with(&["--grid", "100"]), &["grid", "power of two"]);
    assert_rejected(&with(&["--grid", "2048"]), &["grid", "1024"]);
    assert_rejected(&with(&["--wind", "0"]), &["wind", "> 0"]);
    assert_rejected(&with(&["--wind", "NaN"]), &["wind", "NaN"]);
    assert_rejected(&with(&["--depth", "-2"]), &["depth", "> 0"]);
    assert_rejected(&with(&["--depth", "0"]), &["depth"]);
    assert_rejected(&with(&["--choppiness=-0.5"]), &["choppiness", "[0, 2]"]);
    assert_rejected(&with(&["--patch=-10"]), &["patch", "> 0"]);
    assert_rejected(&with(&["--patch", "10,20"]), &["patch", "decreasing"]);
    assert_rejected(&with(&["--alignment", "inf"]), &["alignment"]);
    assert_rejected(
        &with(&["--derivatives", "sideways"]),
        &["derivatives", "spectral", "finite"],
    );
    assert_rejected(&["bench", "--derivatives", "exact"], &["derivatives"]);
    assert_rejected(&with(&["--impulse", "3"]), &["impulse", "X,Z"]);
    assert_rejected(&with(&["--impulse", "3,nan"]), &["impulse", "X,Z"]);
    assert_rejected(&with(&["--tow", "0"]), &["tow", "> 0"]);
    assert_rejected(&with(&["--tow", "40"]), &["tow", "10"]);
    assert_rejected(
        &["export", "--time", "-1", "--tow", "1", "--out", out],
        &["time", ">= 0"],
    );
    assert_rejected(
        &with(&["--spectrum", "jonswap", "--fetch", "nan"]),
        &["fetch"],
    );
    assert_rejected(&["export", "--time", "nan", "--out", out], &["time"]);
    assert_rejected(&["simulate", "--seconds", "-1"], &["seconds"]);
    assert_rejected(
        &["simulate", "--threads", "0", "--seconds", "0.1"],
        &["threads"],
    );
    assert_rejected(&["bench", "--sizes", "48"], &["grid", "power of two"]);
    // Nothing was written for rejected runs.
    assert!(!dir.exists());
}

#[test]
fn unwritable_output_is_a_clear_error() {
    let file = scratch_dir("blocker");
    std::fs::write(&file, b"a file, not a directory").unwrap();
    let under_file = file.join("out");
    assert_rejected(
        &[
            "export",
            "--grid",
            "16",
            "--time",
            "0",
            "--out",
            under_file.to_str().unwrap(),
        ],
        &["cannot write", "out"],
    );
    std::fs::remove_file(&file).unwrap();
}

#[test]
fn simulate_runs_and_reports() {
    let out = run_ok(&[
        "simulate",
        "--grid",
        "32",
        "--seconds",
        "0.2",
        "--threads",
        "2",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Hs"), "{text}");
}

/// `simulate` reports the whitecap coverage the renderer draws (issue 29: it printed the
/// per-cascade foam, 0.0 % in a gale whose whitecaps cover several percent of the sea).
#[test]
fn simulate_reports_the_whitecaps_the_renderer_draws() {
    let out = run_ok(&[
        "simulate",
        "--grid",
        "64",
        "--wind",
        "20",
        "--seconds",
        "3",
        "--threads",
        "2",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    let last = text.lines().last().unwrap_or_default();
    let pct: f64 = last
        .split("whitecaps")
        .nth(1)
        .and_then(|r| r.trim().split('%').next())
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or_else(|| panic!("no whitecap coverage in {last:?}"));
    assert!(
        pct > 1.0 && pct < 30.0,
        "20 m/s after 3 s: {pct} % ({last})"
    );
    // And how far the surface's drift carried the foam: 2-4.5 % of the wind for 3 s.
    let drifted: f64 = last
        .split("foam drifted")
        .nth(1)
        .and_then(|r| r.trim().split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no drift in {last:?}"));
    assert!(
        (0.02 * 20.0 * 3.0..=0.045 * 20.0 * 3.0).contains(&drifted),
        "20 m/s for 3 s: drifted {drifted} m ({last})"
    );
}

#[test]
fn the_derivative_mode_is_chosen_on_the_command_line() {
    // The same sea exported with spectral derivatives and with central differences: the same
    // heights, normals a little apart (the flag took effect, and did nothing wild).
    let export = |mode: &str| {
        let dir = scratch_dir(&format!("derivatives-{mode}"));
        run_ok(&[
            "export",
            "--grid",
            "32",
            "--patch",
            "50",
            "--time",
            "2",
            "--derivatives",
            mode,
            "--out",
            dir.to_str().unwrap(),
        ]);
        (
            read_npy(&dir.join("t2.000_height.npy")).1,
            read_npy(&dir.join("t2.000_normals.npy")).1,
        )
    };
    let (h_s, n_s) = export("spectral");
    let (h_f, n_f) = export("finite");
    let dh = h_s
        .iter()
        .zip(&h_f)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(dh < 1e-5, "heights differ by {dh} m");
    let worst = n_s
        .chunks(3)
        .zip(n_f.chunks(3))
        .map(|(a, b)| {
            (a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
                .min(1.0)
                .acos()
                .to_degrees()
        })
        .fold(0.0f32, f32::max);
    assert!(
        worst > 0.01 && worst < 20.0,
        "normals {worst} deg apart at most"
    );
}

/// Runs `vr-ocean` with `args` and asserts it succeeded (its stderr as the message).
fn run_ok(args: &[&str]) -> std::process::Output {
    let out = vr_ocean(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn read_npy(path: &std::path::Path) -> (Vec<u64>, Vec<f32>) {
    let bytes = std::fs::read(path).unwrap();
    let npy = npyz::NpyFile::new(&bytes[..]).unwrap();
    let shape = npy.shape().to_vec();
    (shape, npy.into_vec::<f32>().unwrap())
}

#[test]
fn export_writes_npy_and_exr_that_read_back() {
    let dir = scratch_dir("export");
    run_ok(&[
        "export",
        "--grid",
        "32",
        "--patch",
        "50",
        "--wind",
        "8",
        "--time",
        "0,1.5",
        "--out",
        dir.to_str().unwrap(),
    ]);
    for t in ["t0.000", "t1.500"] {
        let (shape, h) = read_npy(&dir.join(format!("{t}_height.npy")));
        assert_eq!(shape, vec![32, 32]);
        assert!(h.iter().all(|v| v.is_finite()));
        assert!(h.iter().any(|&v| v != 0.0));
        let (nshape, normals) = read_npy(&dir.join(format!("{t}_normals.npy")));
        assert_eq!(nshape, vec![32, 32, 3]);
        for n in normals.chunks(3) {
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((l - 1.0).abs() < 1e-4 && n[1] > 0.0);
        }
        for f in ["dx", "dz", "jacobian", "foam"] {
            assert_eq!(read_npy(&dir.join(format!("{t}_{f}.npy"))).0, vec![32, 32]);
        }
        // The EXR holds the same height values, bit for bit.
        let img =
            exr::prelude::read_all_flat_layers_from_file(dir.join(format!("{t}.exr"))).unwrap();
        let layer = &img.layer_data[0];
        let ch = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == "height")
            .expect("height channel");
        let values: Vec<f32> = ch.sample_data.values_as_f32().collect();
        assert_eq!(values, h);
        let names: Vec<String> = layer
            .channel_data
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        for want in ["dx", "dz", "jacobian", "normal.x", "normal.y", "normal.z"] {
            assert!(names.iter().any(|n| n == want), "{names:?}");
        }
    }
    // Different times differ; no temporary files are left behind.
    assert_ne!(
        read_npy(&dir.join("t0.000_height.npy")).1,
        read_npy(&dir.join("t1.500_height.npy")).1
    );
    for e in std::fs::read_dir(&dir).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        assert!(!name.ends_with(".partial"), "{name}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn export_writes_the_whitecaps_the_renderer_draws() {
    let dir = scratch_dir("export-whitecaps");
    run_ok(&[
        "export",
        "--grid",
        "64",
        "--wind",
        "20",
        "--time",
        "0,2,4,6",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("t6.000_whitecaps.json")).unwrap()).unwrap();
    let levels = json["levels"].as_array().expect("levels");
    assert_eq!(levels.len(), 2);
    for (l, level) in levels.iter().enumerate() {
        let (shape, cover) = read_npy(&dir.join(format!("t6.000_whitecaps_l{l}.npy")));
        let texels = level["texels"].as_u64().unwrap();
        assert_eq!(shape, vec![texels, texels]);
        assert!(cover.iter().all(|c| (0.0..=1.0).contains(c)));
        let mean = cover.iter().sum::<f32>() / cover.len() as f32;
        let published = level["mean"].as_f64().unwrap() as f32;
        println!("level {l}: mean coverage {mean:.4} (published {published:.4})");
        assert!((mean - published).abs() < 0.01, "{mean} vs {published}");
        assert!(level["spacing"].as_f64().unwrap() > 0.0);
        assert!(level["origin_x"].is_number() && level["origin_z"].is_number());
    }
    // A gale foams (Monahan: ~10 % at 20 m/s), where the cascades' own foam export is eq. 51's.
    let fine = read_npy(&dir.join("t6.000_whitecaps_l0.npy")).1;
    let share = fine.iter().sum::<f32>() / fine.len() as f32;
    assert!(share > 0.01, "a 20 m/s sea without whitecaps: {share}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Reads an exported interaction layer at time `t` as a field to measure, with its source.
fn read_interaction(dir: &std::path::Path, t: &str) -> (Vec<f32>, usize, f32, [f32; 2], [f32; 2]) {
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join(format!("t{t}_interaction.json"))).unwrap())
            .unwrap();
    let f = |k: &str| json[k].as_f64().unwrap_or_else(|| panic!("{k} in {json}")) as f32;
    let cells = json["cells"].as_u64().unwrap() as usize;
    let (shape, heights) = read_npy(&dir.join(format!("t{t}_interaction_height.npy")));
    assert_eq!(shape, vec![cells as u64, cells as u64]);
    (
        heights,
        cells,
        f("cell_m"),
        [f("origin_x"), f("origin_z")],
        [f("source_x"), f("source_z")],
    )
}

/// `export --impulse` writes rings that keep deep water's dispersion (Cauchy-Poisson's
/// wavelength within 15 %) and `--tow` a Kelvin wake (19.5° ± 3°), both measured from the
/// exported files with `sim::interaction::measure`.
#[test]
fn export_writes_the_interaction_layer() {
    use vr_ocean::sim::interaction::measure::{ring_half_waves, wake_half_angle, FieldView};
    let dir = scratch_dir("export-interaction");
    let out = dir.to_str().unwrap();
    run_ok(&[
        "export",
        "--grid",
        "32",
        "--time",
        "5,6",
        "--impulse",
        "2,-3",
        "--out",
        out,
    ]);
    for t in ["5.000", "6.000"] {
        let (heights, cells, cell_m, origin, source) = read_interaction(&dir, t);
        assert_eq!(source, [2.0, -3.0]);
        let view = FieldView {
            heights: &heights,
            cells,
            cell_m,
            origin,
        };
        let time: f32 = t.parse().unwrap();
        let waves = ring_half_waves(&view, 2.0, -3.0, time, 9.81, 0.68, 14.0);
        assert!(waves.len() >= 4, "{waves:?}");
        for w in &waves {
            println!(
                "t {t}: r {:.2} m, λ {:.3} vs {:.3} m",
                w.inner, w.measured, w.predicted
            );
            assert!((w.measured / w.predicted - 1.0).abs() < 0.15, "{w:?}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
    run_ok(&[
        "export", "--grid", "32", "--time", "20", "--tow", "1.2", "--out", out,
    ]);
    let (heights, cells, cell_m, origin, source) = read_interaction(&dir, "20.000");
    assert!(
        (source[0] - 24.0).abs() < 0.02 && source[1] == 0.0,
        "{source:?}"
    );
    let view = FieldView {
        heights: &heights,
        cells,
        cell_m,
        origin,
    };
    let angle = wake_half_angle(&view, source[0], source[1]).unwrap();
    println!(
        "wake half-angle {angle:.1}° at Fr {:.2}",
        1.2 / 9.81f32.sqrt()
    );
    assert!((angle - 19.47).abs() <= 3.0, "{angle}");
    std::fs::remove_dir_all(&dir).unwrap();
}
