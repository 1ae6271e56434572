//! Keeping what the user chose in their settings file ([`RunHooks::keep`]): the run's first
//! word (what the command line chose), a change once it has settled or the app pauses, and the
//! run's last word however the run ended, each saved atomically
//! (`ui::store::SettingsFile::save`) and only when it differs from what the file holds.

use super::chosen::Chosen;
use super::RunHooks;
use crate::ui::store::SettingsFile;
use crate::ui::Settings;

/// Hooks that save the user's choices to `file`, with the sound as the run had it.
pub struct SettingsKeeper<'a> {
    file: Option<&'a SettingsFile>,
    volume: f32,
    audio: bool,
    saves: u32,
    /// What the file holds (read at the start, then what was saved); `None` when it could not
    /// be read: the next word is written whatever it is.
    on_disk: Option<Settings>,
}

impl<'a> SettingsKeeper<'a> {
    /// Saves to `file` (`None`: keeps nothing, for `--no-settings`), with the master `volume`
    /// and whether the run had sound (`audio`).
    pub fn new(file: Option<&'a SettingsFile>, volume: f32, audio: bool) -> Self {
        let on_disk = file
            .map(|f| f.load())
            .filter(|l| l.warning.is_none())
            .map(|l| l.settings);
        Self {
            file,
            volume,
            audio,
            saves: 0,
            on_disk,
        }
    }

    /// Saves made so far (words equal to what the file held were not written).
    pub fn saves(&self) -> u32 {
        self.saves
    }
}

impl RunHooks for SettingsKeeper<'_> {
    fn keep(&mut self, chosen: &Chosen) {
        let Some(file) = self.file else {
            return;
        };
        let settings = chosen.settings(self.volume, self.audio);
        if self.on_disk.as_ref() == Some(&settings) {
            return;
        }
        // Rare (the start, a settled change, a pause, the run's end), so the file's work is
        // no frame's.
        match file.save(&settings) {
            Ok(()) => {
                self.saves += 1;
                self.on_disk = Some(settings);
                log::info!("settings saved to {}", file.path().display());
            }
            Err(e) => log::warn!("{e}"),
        }
    }
}
