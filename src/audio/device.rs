//! Sound out of the machine: the default output device through cpal (ALSA or PulseAudio's
//! ALSA plug-in on the desktop, AAudio on the Quest) at 48 kHz with 10 ms buffers where the
//! device allows, or, when there is no device, a clock thread that runs the same callback on
//! the same schedule and drops the samples: the run goes on silent, and its timing (busy
//! time, late buffers) is still measured.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::engine::{SoundConfig, Soundscape};
use super::link::{link, CountersSnapshot, FrameSender};
use super::player::Player;
use super::AudioError;

/// Frames per buffer asked of the device: 10 ms at 48 kHz.
pub const BUFFER_FRAMES: u32 = 480;

/// Where the sound goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Sink {
    /// A device, by name.
    Device(String),
    /// No device: the clock renders on schedule and drops the samples.
    Clock,
}

/// A running output: keep it alive as long as the sound should play.
pub struct AudioOutput {
    sender: FrameSender,
    sink: Sink,
    buffer_frames: u32,
    started: Instant,
    _run: Running,
}

/// What keeps the sound going; dropping it stops it.
enum Running {
    #[cfg(feature = "audio-device")]
    Device {
        _stream: cpal::Stream,
    },
    Clock {
        _thread: ClockThread,
    },
}

impl AudioOutput {
    /// The default device, or (with one warning naming why) the silent clock.
    pub fn open(config: SoundConfig) -> Result<Self, AudioError> {
        config.validate()?;
        match Self::device(config) {
            Ok(out) => Ok(out),
            Err(e) => {
                log::warn!("{e}; running silent (the sound is still made and timed)");
                Self::clock(config, BUFFER_FRAMES)
            }
        }
    }

    /// The silent clock: the callback on a 10 ms schedule, samples dropped.
    pub fn clock(config: SoundConfig, buffer_frames: u32) -> Result<Self, AudioError> {
        let (sender, receiver) = link(config.volume);
        let player = Player::new(Soundscape::new(config)?, receiver);
        let period = Duration::from_secs_f64(buffer_frames as f64 / config.sample_rate as f64);
        let thread = ClockThread::start(player, buffer_frames as usize, period)?;
        Ok(Self {
            sender,
            sink: Sink::Clock,
            buffer_frames,
            started: Instant::now(),
            _run: Running::Clock { _thread: thread },
        })
    }

    #[cfg(not(feature = "audio-device"))]
    fn device(_config: SoundConfig) -> Result<Self, AudioError> {
        Err(AudioError::Device(
            "this build has no audio output (built without the `audio-device` feature)".into(),
        ))
    }

    #[cfg(feature = "audio-device")]
    fn device(config: SoundConfig) -> Result<Self, AudioError> {
        // ALSA reports a missing card on stderr itself, eight lines of it; the one warning
        // that matters is ours.
        quiet_alsa::while_opening(|| Self::open_device(config))
    }

    #[cfg(feature = "audio-device")]
    fn open_device(config: SoundConfig) -> Result<Self, AudioError> {
        use cpal::traits::{DeviceTrait, HostTrait, StreamTrait};

        let fail =
            |what: &str, e: &dyn std::fmt::Display| AudioError::Device(format!("{what}: {e}"));
        let host = cpal::default_host();
        let device = host
            .default_output_device()
            .ok_or_else(|| AudioError::Device("no audio output device".into()))?;
        let name = device
            .description()
            .map(|d| d.to_string())
            .unwrap_or_else(|_| "default".into());
        let default = device
            .default_output_config()
            .map_err(|e| fail("the device's output format", &e))?;
        let channels = default.channels();
        let stream_config = cpal::StreamConfig {
            channels,
            sample_rate: config.sample_rate,
            buffer_size: cpal::BufferSize::Fixed(BUFFER_FRAMES),
        };
        let (sender, receiver) = link(config.volume);
        let mut player = Player::new(Soundscape::new(config)?, receiver);
        let counters = sender.counters_arc();
        let errors = move |e: cpal::Error| {
            if e.kind() == cpal::ErrorKind::Xrun {
                counters.underruns.fetch_add(1, Ordering::Relaxed);
            } else {
                log::warn!("audio device: {e}");
            }
        };
        let ch = channels as usize;
        let stream = match default.sample_format() {
            cpal::SampleFormat::F32 => device.build_output_stream(
                stream_config,
                move |out: &mut [f32], _| player.fill(out, ch, |x| x),
                errors,
                None,
            ),
            cpal::SampleFormat::I16 => device.build_output_stream(
                stream_config,
                move |out: &mut [i16], _| {
                    player.fill(out, ch, |x| (x * i16::MAX as f32).round() as i16)
                },
                errors,
                None,
            ),
            other => {
                return Err(AudioError::Device(format!(
                    "the device wants {other} samples (f32 or i16 supported)"
                )))
            }
        }
        .map_err(|e| fail("opening the output stream", &e))?;
        stream.play().map_err(|e| fail("starting the output", &e))?;
        Ok(Self {
            sender,
            sink: Sink::Device(name),
            buffer_frames: BUFFER_FRAMES,
            started: Instant::now(),
            _run: Running::Device { _stream: stream },
        })
    }

    /// The frame thread's end of the link: publish frames and splashes here.
    pub fn sender(&mut self) -> &mut FrameSender {
        &mut self.sender
    }

    /// Where the sound goes.
    pub fn sink(&self) -> &Sink {
        &self.sink
    }

    /// Frames per buffer.
    pub fn buffer_frames(&self) -> u32 {
        self.buffer_frames
    }

    /// The callback's counts so far, and the seconds since the output opened.
    pub fn counters(&self) -> (CountersSnapshot, f64) {
        (
            self.sender.counters().snapshot(),
            self.started.elapsed().as_secs_f64(),
        )
    }
}

/// ALSA's own error messages silenced on this thread while the device is opened (ALSA 1.1.6's
/// per-thread handler, `snd_lib_error_set_local`); elsewhere, nothing to silence.
#[cfg(feature = "audio-device")]
mod quiet_alsa {
    #[cfg(target_os = "linux")]
    pub fn while_opening<R>(f: impl FnOnce() -> R) -> R {
        use std::ffi::{c_char, c_int, c_void};

        /// ALSA's `snd_local_error_handler_t`: the message's format and its `va_list` (a
        /// pointer in the x86-64 and AArch64 calling conventions), ignored.
        type Handler = unsafe extern "C" fn(
            *const c_char,
            c_int,
            *const c_char,
            c_int,
            *const c_char,
            *mut c_void,
        );

        unsafe extern "C" fn ignore(
            _file: *const c_char,
            _line: c_int,
            _func: *const c_char,
            _err: c_int,
            _fmt: *const c_char,
            _args: *mut c_void,
        ) {
        }

        // libasound is linked by cpal's ALSA backend (alsa-sys).
        extern "C" {
            fn snd_lib_error_set_local(handler: Option<Handler>) -> Option<Handler>;
        }

        // SAFETY: the handler has ALSA's signature and touches nothing; the previous
        // handler (this thread's) is put back below.
        let previous = unsafe { snd_lib_error_set_local(Some(ignore)) };
        let result = f();
        // SAFETY: restores what ALSA returned above.
        unsafe { snd_lib_error_set_local(previous) };
        result
    }

    #[cfg(not(target_os = "linux"))]
    pub fn while_opening<R>(f: impl FnOnce() -> R) -> R {
        f()
    }
}

/// The thread that stands in for a device: renders each buffer one period ahead of when a
/// device would play it and counts the buffers finished after that time as under-runs (and,
/// of those, the ones whose rendering took under half a period as late wakes).
struct ClockThread {
    stop: Arc<AtomicBool>,
    handle: Option<JoinHandle<()>>,
}

impl ClockThread {
    fn start(mut player: Player, frames: usize, period: Duration) -> Result<Self, AudioError> {
        let stop = Arc::new(AtomicBool::new(false));
        let flag = stop.clone();
        let handle = std::thread::Builder::new()
            .name("vr-ocean-audio".into())
            .spawn(move || {
                let mut buffer = vec![0.0f32; 2 * frames];
                let start = Instant::now();
                let mut k: u32 = 1;
                while !flag.load(Ordering::Relaxed) {
                    // Buffer k plays at start + k·period; it is asked for a period before.
                    let asked = start + period * (k - 1);
                    if let Some(wait) = asked.checked_duration_since(Instant::now()) {
                        std::thread::sleep(wait);
                    }
                    let woke = Instant::now();
                    player.fill(&mut buffer, 2, |x| x);
                    let now = Instant::now();
                    if now > start + period * k {
                        let c = player.counters();
                        c.underruns.fetch_add(1, Ordering::Relaxed);
                        if now.duration_since(woke) < period / 2 {
                            // The work fitted; the thread got its core too late.
                            c.late_wakes.fetch_add(1, Ordering::Relaxed);
                        }
                        // A device that ran dry starts again from now, as this does.
                        let behind = now.duration_since(start).as_secs_f64();
                        k = k.max((behind / period.as_secs_f64()).ceil() as u32);
                    }
                    k += 1;
                }
            })
            .map_err(|e| AudioError::Device(format!("cannot start the audio thread: {e}")))?;
        Ok(Self {
            stop,
            handle: Some(handle),
        })
    }
}

impl Drop for ClockThread {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}
