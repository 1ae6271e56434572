//! Where the settings are kept: `$XDG_CONFIG_HOME/vr-ocean/settings.json` (else
//! `~/.config/vr-ocean/settings.json`) on the desktop, the app's internal files directory on the
//! Quest. Saving writes a temporary file in the same directory, flushes it to the disk and
//! renames it over the old one, so a run killed mid-save leaves the old settings or the new,
//! never a mixture. Loading never fails: a missing, partial or corrupt file gives the defaults
//! and one warning, and a corrupt file is kept aside (`settings.json.bad`) rather than
//! overwritten unseen.

use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use super::settings::Settings;
use super::UiError;

/// The file's name.
pub const FILE_NAME: &str = "settings.json";

/// The settings file of one front end.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SettingsFile {
    path: PathBuf,
}

/// What loading found.
#[derive(Clone, Debug, PartialEq)]
pub struct Loaded {
    /// The settings to use.
    pub settings: Settings,
    /// Why they are the defaults, when they are: to be shown once.
    pub warning: Option<String>,
}

impl SettingsFile {
    /// The file at `path`.
    pub fn at(path: impl Into<PathBuf>) -> Self {
        Self { path: path.into() }
    }

    /// The desktop's: under `$XDG_CONFIG_HOME` (or `$HOME/.config`); `None` when neither is
    /// set.
    pub fn desktop() -> Option<Self> {
        let base = std::env::var_os("XDG_CONFIG_HOME")
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
            .or_else(|| {
                std::env::var_os("HOME")
                    .filter(|v| !v.is_empty())
                    .map(|h| PathBuf::from(h).join(".config"))
            })?;
        Some(Self::at(base.join("vr-ocean").join(FILE_NAME)))
    }

    /// In the directory `dir` (the Quest app's internal files directory).
    pub fn in_dir(dir: &Path) -> Self {
        Self::at(dir.join(FILE_NAME))
    }

    /// Where it is.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The kept settings, or the defaults and why.
    pub fn load(&self) -> Loaded {
        let text = match fs::read_to_string(&self.path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Loaded {
                    settings: Settings::default(),
                    warning: Some(format!(
                        "no saved settings at {} yet: using the defaults",
                        self.path.display()
                    )),
                };
            }
            Err(e) => {
                return Loaded {
                    settings: Settings::default(),
                    warning: Some(format!(
                        "cannot read {}: {e}; using the defaults",
                        self.path.display()
                    )),
                };
            }
        };
        match Settings::from_json(&text) {
            Ok(settings) => Loaded {
                settings,
                warning: None,
            },
            Err(why) => {
                let aside = self.path.with_extension("json.bad");
                let kept = match fs::rename(&self.path, &aside) {
                    Ok(()) => format!(" (kept as {})", aside.display()),
                    Err(_) => String::new(),
                };
                Loaded {
                    settings: Settings::default(),
                    warning: Some(format!(
                        "the saved settings in {} are unreadable: {why}; using the defaults{kept}",
                        self.path.display()
                    )),
                }
            }
        }
    }

    /// Saves `settings` atomically (temporary file, flushed, renamed over the old one).
    pub fn save(&self, settings: &Settings) -> Result<(), UiError> {
        let fail = |what: &str, p: &Path, e: std::io::Error| {
            UiError::Io(format!("cannot {what} {}: {e}", p.display()))
        };
        if let Some(dir) = self.path.parent().filter(|d| !d.as_os_str().is_empty()) {
            fs::create_dir_all(dir).map_err(|e| fail("create", dir, e))?;
        }
        let tmp = self
            .path
            .with_extension(format!("json.tmp-{}", std::process::id()));
        let write = || -> std::io::Result<()> {
            let mut f = fs::File::create(&tmp)?;
            f.write_all(settings.to_json().as_bytes())?;
            f.write_all(b"\n")?;
            f.sync_all()
        };
        if let Err(e) = write() {
            let _ = fs::remove_file(&tmp);
            return Err(fail("write", &tmp, e));
        }
        fs::rename(&tmp, &self.path).map_err(|e| {
            let _ = fs::remove_file(&tmp);
            fail("replace", &self.path, e)
        })?;
        // The rename is the directory's change: synced too, or a power cut may undo it.
        sync_dir(self.path.parent().filter(|d| !d.as_os_str().is_empty()))
            .map_err(|(dir, e)| fail("sync", &dir, e))
    }

    /// Forgets the kept settings (`--reset-settings`); nothing kept is not an error.
    pub fn reset(&self) -> Result<(), UiError> {
        match fs::remove_file(&self.path) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
            Err(e) => Err(UiError::Io(format!(
                "cannot remove {}: {e}",
                self.path.display()
            ))),
        }
    }
}

/// Syncs directory `dir` (the current one for `None`) where the platform allows it (Unix);
/// elsewhere a directory is not opened as a file and this does nothing.
fn sync_dir(dir: Option<&Path>) -> Result<(), (std::path::PathBuf, std::io::Error)> {
    #[cfg(unix)]
    {
        let dir = dir.unwrap_or(Path::new("."));
        fs::File::open(dir)
            .and_then(|d| d.sync_all())
            .map_err(|e| (dir.to_path_buf(), e))
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("vr-ocean-ui-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn saved_settings_come_back_and_reset_forgets_them() {
        let dir = scratch("roundtrip");
        let file = SettingsFile::in_dir(&dir.join("nested"));
        let first = file.load();
        assert_eq!(first.settings, Settings::default());
        assert!(first.warning.unwrap().contains("no saved settings"));
        let s = Settings {
            wind_speed: 21.0,
            ..Settings::default()
        };
        file.save(&s).unwrap();
        assert_eq!(
            file.load(),
            Loaded {
                settings: s,
                warning: None
            }
        );
        file.reset().unwrap();
        file.reset().unwrap();
        assert_eq!(file.load().settings, Settings::default());
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_truncated_file_is_the_defaults_one_warning_and_kept_aside() {
        let dir = scratch("truncated");
        let file = SettingsFile::in_dir(&dir);
        let s = Settings {
            choppiness: 1.5,
            ..Settings::default()
        };
        file.save(&s).unwrap();
        let text = fs::read_to_string(file.path()).unwrap();
        fs::write(file.path(), &text[..text.len() / 2]).unwrap();
        let loaded = file.load();
        assert_eq!(loaded.settings, Settings::default());
        let w = loaded.warning.unwrap();
        assert!(w.contains("unreadable") && w.contains(".bad"), "{w}");
        assert!(dir.join("settings.json.bad").exists());
        // The next save is clean.
        file.save(&s).unwrap();
        assert_eq!(file.load().settings, s);
        let _ = fs::remove_dir_all(&dir);
    }
}
