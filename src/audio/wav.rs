//! `--audio-out`: the soundscape rendered in step with the frames into a 16-bit stereo WAV
//! (hound writes the header and the samples). The file is written as `NAME.partial` and
//! renamed when finished, so an interrupted run never leaves a truncated file under the
//! asked-for name; a run that fails still finishes what it had rendered.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use super::engine::{SoundConfig, Soundscape, BLOCK};
use super::scene::{SoundFrame, Splash};
use super::AudioError;

/// The soundscape writing into a file.
pub struct WavRecorder {
    engine: Soundscape,
    writer: Option<hound::WavWriter<BufWriter<File>>>,
    path: PathBuf,
    partial: PathBuf,
    buffer: [f32; 2 * BLOCK],
    /// Samples written, and where the next frame's end falls (in samples from the start).
    written: u64,
    start: Option<f64>,
}

impl WavRecorder {
    /// A recorder into `path` (created or replaced), rendering with `config`.
    pub fn create(path: &Path, config: SoundConfig) -> Result<Self, AudioError> {
        let engine = Soundscape::new(config)?;
        let spec = hound::WavSpec {
            channels: 2,
            sample_rate: config.sample_rate,
            bits_per_sample: 16,
            sample_format: hound::SampleFormat::Int,
        };
        let mut partial = path.as_os_str().to_owned();
        partial.push(".partial");
        let partial = PathBuf::from(partial);
        let writer = hound::WavWriter::create(&partial, spec)
            .map_err(|e| AudioError::Io(format!("cannot write {}: {e}", partial.display())))?;
        Ok(Self {
            engine,
            writer: Some(writer),
            path: path.to_path_buf(),
            partial,
            buffer: [0.0; 2 * BLOCK],
            written: 0,
            start: None,
        })
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The soundscape (its statistics).
    pub fn soundscape(&self) -> &Soundscape {
        &self.engine
    }

    /// Renders the sound up to `frame.time` with `frame`'s sea and `splashes` (events since
    /// the last frame, at their own times). The file starts at the first frame's time.
    pub fn frame(&mut self, frame: &SoundFrame, splashes: &[Splash]) -> Result<(), AudioError> {
        let rate = self.engine.sample_rate() as f64;
        let start = *self.start.get_or_insert_with(|| {
            self.engine.set_time(frame.time);
            frame.time
        });
        self.engine.set_frame(frame);
        for s in splashes {
            self.engine.splash(*s);
        }
        // Whole samples up to the frame's time, counted from the start (no drift).
        let end = ((frame.time - start) * rate).round().max(0.0) as u64;
        let writer = self
            .writer
            .as_mut()
            .ok_or_else(|| AudioError::Io("the WAV file was already finished".into()))?;
        while self.written < end {
            let n = ((end - self.written) as usize).min(BLOCK);
            let buf = &mut self.buffer[..2 * n];
            self.engine.render(buf);
            for &x in buf.iter() {
                writer
                    .write_sample((x * i16::MAX as f32).round() as i16)
                    .map_err(|e| AudioError::Io(format!("{}: {e}", self.path.display())))?;
            }
            self.written += n as u64;
        }
        Ok(())
    }

    /// Finishes the file (its header's lengths) and gives it its name; also done, logging any
    /// failure, on drop.
    pub fn finish(&mut self) -> Result<(), AudioError> {
        let Some(w) = self.writer.take() else {
            return Ok(());
        };
        let fail =
            |e: &dyn std::fmt::Display| AudioError::Io(format!("{}: {e}", self.path.display()));
        w.finalize().map_err(|e| fail(&e))?;
        std::fs::rename(&self.partial, &self.path).map_err(|e| fail(&e))
    }
}

impl Drop for WavRecorder {
    fn drop(&mut self) {
        if let Err(e) = self.finish() {
            log::warn!("{e}");
        }
    }
}
