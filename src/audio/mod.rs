//! Sound made from the simulated sea (issue 32): wind, the swell's rumble, the wash against
//! the deck, whitecaps crackling round the listener and splashes, synthesized (no recordings)
//! and placed round the head.
//!
//! Data flows one way, like the rest of the app: the frame thread reads the sea
//! ([`listen::SeaProbe`], from `sim`'s surfaces) and the physics' impacts (handed over by the
//! app as [`Splash`]es) into a plain [`SoundFrame`]; the [`Soundscape`] turns frames and
//! splashes into samples; an output takes them: [`AudioOutput`] (a device through cpal, fed
//! lock-free by [`link`](mod@link), or a silent clock when there is none) or [`WavRecorder`]
//! (`--audio-out`, in step with the frames, deterministic).
//!
//! | file | job |
//! |---|---|
//! | `scene.rs` | the plain inputs: [`SoundFrame`], [`Splash`] |
//! | `listen.rs` | the sea read from `sim` into a frame |
//! | `dsp.rs` | noise, filters, the head shadow, smoothing |
//! | `voices/` | one sound per file |
//! | `spatial.rs` | the head model: ITD, ILD, distance |
//! | `submerged.rs` | the ears under the water: the air's sound cut, the mix low and close |
//! | `engine.rs` | voices placed and mixed, the limiter |
//! | `link.rs` | frame thread → audio thread, lock-free |
//! | `player.rs` | the callback's work |
//! | `device.rs` | the output: cpal's default device, or the silent clock |
//! | `reopen.rs` | the thread that owns the stream and reopens it after a lost device |
//! | `clock.rs` | the silent clock that stands in for a missing device |
//! | `wav.rs` | `--audio-out` |
//! | `measure.rs` | power, centroid, onsets of rendered sound (tests, benchmark) |
//!
//! Invariants: the audio callback never allocates, blocks or does I/O
//! (`tests/no_alloc/audio.rs`; its one lock is a `try_lock` that no one else holds while a
//! stream plays); a stream is opened and closed on the keeper's thread, never in a callback;
//! the same seed, frames and splashes render the same samples; no sample leaves louder than [`engine::CEILING`]; a missing device is one warning and a
//! silent run. `audio` reads `sim` and `base` only (`tests/tidy.rs`).

pub mod clock;
pub mod device;
pub mod dsp;
pub mod engine;
pub mod link;
pub mod listen;
pub mod measure;
pub mod player;
pub mod reopen;
pub mod scene;
pub mod spatial;
pub mod submerged;
pub mod voices;
pub mod wav;

#[cfg(test)]
mod reopen_tests;
#[cfg(test)]
mod tests;

pub use device::{AudioOutput, Sink};
pub use engine::{SoundConfig, SoundStats, Soundscape};
pub use link::link;
pub use scene::{BreakingSector, Listener, SoundFrame, Splash, WashPoint};
pub use wav::WavRecorder;

/// The sample rate the soundscape renders at (Hz): the Quest's native rate and the desktop
/// norm.
pub const SAMPLE_RATE: u32 = 48_000;

/// Why sound could not be made.
#[derive(Debug, Clone, PartialEq)]
pub enum AudioError {
    /// A setting is out of range.
    Param(String),
    /// No output device could be opened (the run goes on silent).
    Device(String),
    /// A file could not be written.
    Io(String),
}

impl std::fmt::Display for AudioError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AudioError::Param(e) => write!(f, "audio: {e}"),
            AudioError::Device(e) => write!(f, "audio output: {e}"),
            AudioError::Io(e) => write!(f, "audio file: {e}"),
        }
    }
}

impl std::error::Error for AudioError {}
