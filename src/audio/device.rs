//! Sound out of the machine: the default output device through cpal (ALSA or PulseAudio's
//! ALSA plug-in on the desktop, AAudio on the Quest) at 48 kHz with 10 ms buffers where the
//! device allows, or, when there is no device, a clock thread that runs the same callback on
//! the same schedule and drops the samples: the run goes on silent, and its timing (busy
//! time, late buffers) is still measured.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use super::clock::ClockOutlet;
use super::engine::{SoundConfig, Soundscape};
use super::link::{link, CountersSnapshot, FrameSender};
use super::player::Player;
use super::reopen::{Keeper, Outlet};
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
    /// The thread that owns the stream and reopens it when the device is lost; dropping it
    /// stops the sound.
    _keeper: Keeper,
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

    /// The silent clock: the callback on a device's schedule, samples dropped.
    pub fn clock(config: SoundConfig, buffer_frames: u32) -> Result<Self, AudioError> {
        let period = Duration::from_secs_f64(buffer_frames as f64 / config.sample_rate as f64);
        let outlet = ClockOutlet {
            frames: buffer_frames as usize,
            period,
        };
        let mut out = Self::on(config, outlet, buffer_frames)?;
        out.sink = Sink::Clock;
        Ok(out)
    }

    /// Sound through `outlet`'s streams, reopened on its thread whenever one is lost (the
    /// device's path; a test's outlet injects the loss).
    pub fn on<O: Outlet>(
        config: SoundConfig,
        outlet: O,
        buffer_frames: u32,
    ) -> Result<Self, AudioError> {
        let (sender, receiver) = link(config.volume);
        let player = Arc::new(Mutex::new(Player::new(Soundscape::new(config)?, receiver)));
        let (keeper, name) = Keeper::start(outlet, player, sender.counters_arc())?;
        Ok(Self {
            sender,
            sink: Sink::Device(name),
            buffer_frames,
            started: Instant::now(),
            _keeper: keeper,
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
        let outlet = cpal_outlet::DefaultDevice {
            sample_rate: config.sample_rate,
        };
        Self::on(config, outlet, BUFFER_FRAMES)
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

/// The machine's default output through cpal, opened again (the default may have changed:
/// headphones plugged in) after each loss.
#[cfg(feature = "audio-device")]
mod cpal_outlet {
    use std::sync::atomic::Ordering;

    use cpal::traits::{DeviceTrait, HostTrait, StreamTrait};

    use super::super::reopen::{fill_shared, LossReporter, Outlet, SharedPlayer};
    use super::super::AudioError;
    use super::{quiet_alsa, BUFFER_FRAMES};

    /// The default device at this rate.
    pub struct DefaultDevice {
        pub sample_rate: u32,
    }

    impl Outlet for DefaultDevice {
        type Stream = cpal::Stream;

        fn open(
            &mut self,
            player: &SharedPlayer,
            loss: LossReporter,
        ) -> Result<(cpal::Stream, String), AudioError> {
            // ALSA reports a missing card on stderr itself, eight lines of it; the one warning
            // that matters is ours.
            quiet_alsa::while_opening(|| self.open_default(player, loss))
        }
    }

    impl DefaultDevice {
        fn open_default(
            &self,
            player: &SharedPlayer,
            loss: LossReporter,
        ) -> Result<(cpal::Stream, String), AudioError> {
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
                sample_rate: self.sample_rate,
                buffer_size: cpal::BufferSize::Fixed(BUFFER_FRAMES),
            };
            let counters = player
                .lock()
                .map_err(|_| AudioError::Device("the sound's player failed earlier".into()))?
                .counters_arc();
            let errors = move |e: cpal::Error| match e.kind() {
                cpal::ErrorKind::Xrun => {
                    counters.underruns.fetch_add(1, Ordering::Relaxed);
                }
                // Gone (unplugged, the route closed): closed and reopened on the keeper's
                // thread, not here.
                cpal::ErrorKind::DeviceNotAvailable | cpal::ErrorKind::StreamInvalidated => {
                    loss.lost(e.to_string())
                }
                // Android without the low-latency path: the report says "platform's".
                cpal::ErrorKind::RealtimeDenied => {
                    log::info!("audio: the device did not grant its low-latency path ({e})")
                }
                _ => log::warn!("audio device: {e}"),
            };
            let ch = channels as usize;
            let p = player.clone();
            let stream = match default.sample_format() {
                cpal::SampleFormat::F32 => device.build_output_stream(
                    stream_config,
                    move |out: &mut [f32], _| fill_shared(&p, out, ch, |x| x),
                    errors,
                    None,
                ),
                cpal::SampleFormat::I16 => device.build_output_stream(
                    stream_config,
                    move |out: &mut [i16], _| {
                        fill_shared(&p, out, ch, |x| (x * i16::MAX as f32).round() as i16)
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
            Ok((stream, name))
        }
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
