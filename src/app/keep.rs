//! Keeping what the user chose in their settings file ([`RunHooks::keep`]): a change once it
//! has settled and the run's last word however the run ended, each saved atomically
//! (`ui::store::SettingsFile::save`).

use super::live::Chosen;
use super::RunHooks;
use crate::ui::store::SettingsFile;

/// Hooks that save the user's choices to `file`, with the sound as the run had it.
pub struct SettingsKeeper<'a> {
    file: Option<&'a SettingsFile>,
    volume: f32,
    audio: bool,
    saves: u32,
}

impl<'a> SettingsKeeper<'a> {
    /// Saves to `file` (`None`: keeps nothing, for `--no-settings`), with the master `volume`
    /// and whether the run had sound (`audio`).
    pub fn new(file: Option<&'a SettingsFile>, volume: f32, audio: bool) -> Self {
        Self {
            file,
            volume,
            audio,
            saves: 0,
        }
    }

    /// Saves made so far.
    pub fn saves(&self) -> u32 {
        self.saves
    }
}

impl RunHooks for SettingsKeeper<'_> {
    fn keep(&mut self, chosen: &Chosen) {
        let Some(file) = self.file else {
            return;
        };
        // Rare (a settled change, the run's end), so the file's work is no frame's.
        match file.save(&chosen.settings(self.volume, self.audio)) {
            Ok(()) => {
                self.saves += 1;
                log::info!("settings saved to {}", file.path().display());
            }
            Err(e) => log::warn!("{e}"),
        }
    }
}
