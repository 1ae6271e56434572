//! Kept settings (issue 31): a window run keeps what it ended with, the next starts from it
//! where no flag says otherwise, `--reset-settings` forgets it, a corrupt file is the defaults
//! and one warning (and kept aside), and a save killed midway leaves the old settings or the
//! new, never garbage.

use crate::common;

use std::path::Path;
use std::time::Duration;

use vr_ocean::ui::{Settings, SettingsFile};

fn saved(config: &Path) -> Settings {
    let text = std::fs::read_to_string(config.join("vr-ocean/settings.json")).unwrap();
    Settings::from_json(&text).unwrap()
}

#[test]
fn the_window_keeps_its_settings_between_runs() {
    if !common::need_xvfb_run("the_window_keeps_its_settings_between_runs") {
        return;
    }
    let config = common::scratch_path("settings-config");
    let _ = std::fs::remove_dir_all(&config);
    let run = |args: &[&str]| {
        let mut all = vec!["--frames", "3", "--audio", "off"];
        all.extend_from_slice(args);
        let out = common::xvfb_window(&config, &all);
        let (stdout, stderr) = (
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        );
        assert!(out.status.success(), "{args:?}\n{stdout}\n{stderr}");
        (stdout, stderr)
    };
    // First run: nothing kept yet (one warning), then its choices are kept.
    let (_, err) = run(&["--wind", "13", "--wind-dir", "40", "--sun-elevation", "8"]);
    assert_eq!(err.matches("no saved settings").count(), 1, "{err}");
    let s = saved(&config);
    assert_eq!((s.wind_speed, s.wind_direction_deg), (13.0, 40.0));
    assert_eq!((s.preset.as_str(), s.sun_elevation_deg), ("low", Some(8.0)));
    assert!(!s.audio);
    // Second run, no wind flags: it starts from them (and keeps them).
    let (_, err) = run(&["--volume", "0.5"]);
    assert!(
        err.contains("settings from") && err.contains("wind 13.0 m/s"),
        "{err}"
    );
    let s = saved(&config);
    assert_eq!(
        (s.wind_speed, s.sun_elevation_deg, s.volume),
        (13.0, Some(8.0), 0.5)
    );
    // A flag wins over what is kept.
    run(&["--wind", "6"]);
    assert_eq!(saved(&config).wind_speed, 6.0);
    // Forgotten: the defaults again.
    let (out, _) = run(&["--reset-settings"]);
    assert!(out.contains("settings forgotten"), "{out}");
    assert_eq!(saved(&config).wind_speed, Settings::default().wind_speed);
    // Corrupt: the defaults, one warning, the file kept aside, the run goes on.
    let file = config.join("vr-ocean/settings.json");
    std::fs::write(&file, "{\"wind_speed\": 9.0, \"preset\": ").unwrap();
    let (_, err) = run(&[]);
    assert_eq!(err.matches("unreadable").count(), 1, "{err}");
    assert!(config.join("vr-ocean/settings.json.bad").exists());
    assert_eq!(saved(&config).wind_speed, Settings::default().wind_speed);
    let _ = std::fs::remove_dir_all(&config);
}

/// The child's side of the kill test: saves settings in a loop until killed.
const SAVE_LOOP: &str = "VR_OCEAN_TEST_SAVE_LOOP";

#[test]
fn a_save_killed_midway_leaves_the_old_or_the_new_settings() {
    if let Some(path) = std::env::var_os(SAVE_LOOP) {
        let file = SettingsFile::at(path);
        for k in 0u64.. {
            let s = Settings {
                wind_speed: 1.0 + (k % 40) as f32,
                ..Settings::default()
            };
            file.save(&s).unwrap();
        }
    }
    let dir = common::scratch_path("settings-kill");
    let _ = std::fs::remove_dir_all(&dir);
    let file = SettingsFile::in_dir(&dir);
    file.save(&Settings::default()).unwrap();
    let exe = std::env::current_exe().unwrap();
    for round in 0..12u64 {
        let mut child = std::process::Command::new(&exe)
            .args(["a_save_killed_midway_leaves_the_old_or_the_new_settings"])
            .env(SAVE_LOOP, file.path())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(60 + 23 * round));
        child.kill().unwrap();
        child.wait().unwrap();
        let loaded = file.load();
        assert_eq!(loaded.warning, None, "round {round}: garbage was left");
        let w = loaded.settings.wind_speed;
        assert!(
            w == Settings::default().wind_speed || (1.0..=40.0).contains(&w),
            "round {round}: {w}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_window_killed_after_its_choice_was_kept_keeps_it() {
    // Issue 44: what the command line chose is this run's first word, kept at the start; a
    // SIGKILL (a Quest killing a stopped app) after that leaves it in the file.
    if !common::need_xvfb_run("a_window_killed_after_its_choice_was_kept_keeps_it") {
        return;
    }
    let config = common::scratch_path("settings-sigkill");
    let _ = std::fs::remove_dir_all(&config);
    let mut xvfb = std::process::Command::new("xvfb-run")
        .env("XDG_CONFIG_HOME", &config)
        .args(["-a", "-s", "-screen 0 1024x768x24"])
        .arg(env!("CARGO_BIN_EXE_vr-ocean"))
        .args([
            "window", "--size", "160x80", "--grid", "64", "--preset", "low",
        ])
        .args(["--threads", "1", "--frames", "100000", "--audio", "off"])
        .args(["--wind", "14", "--wind-dir", "35"])
        .env("RUST_BACKTRACE", "0")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("xvfb-run runs");
    let path = config.join("vr-ocean/settings.json");
    let deadline = std::time::Instant::now() + Duration::from_secs(120);
    while !path.exists() {
        assert!(
            std::time::Instant::now() < deadline,
            "nothing kept after 2 minutes"
        );
        assert!(xvfb.try_wait().unwrap().is_none(), "the window ended early");
        std::thread::sleep(Duration::from_millis(50));
    }
    // The window is still running: kill it as the system would, no chance to save.
    std::thread::sleep(Duration::from_millis(300));
    // This test's own window by its unique arguments (the parent is xvfb-run's shell).
    let status = std::process::Command::new("pkill")
        .args(["-KILL", "-f", "window --size 160x80 --grid 64 --preset low"])
        .status()
        .expect("pkill runs");
    assert!(status.success(), "the window was not running to be killed");
    xvfb.wait().unwrap();
    let s = saved(&config);
    assert_eq!((s.wind_speed, s.wind_direction_deg), (14.0, 35.0));
    let _ = std::fs::remove_dir_all(&config);
}
