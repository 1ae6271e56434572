//! What a real-time output runs per buffer: take the newest frame and the queued splashes
//! from the link, render, count. Shared by the device's callback and the clock that stands in
//! for a missing device. No allocation, lock or I/O.

use std::sync::atomic::Ordering;
use std::time::Instant;

use super::engine::Soundscape;
use super::link::{FrameReceiver, Scheduling};

/// Frames converted at a time for devices that take integer samples.
pub const SCRATCH_FRAMES: usize = 1024;

/// Frames a pause fades out over, and a resume in (5 ms at 48 kHz: no click, no spike).
pub const FADE_FRAMES: f32 = 240.0;

/// The audio thread's side: the soundscape and the link's receiving end.
pub struct Player {
    engine: Soundscape,
    link: FrameReceiver,
    scratch: Box<[f32; 2 * SCRATCH_FRAMES]>,
    /// Whether the thread calling [`Player::fill`] has asked for real-time scheduling.
    promoted: bool,
    /// The pause's gain: 1 playing, 0 paused, between while fading.
    gain: f32,
}

impl Player {
    /// A player rendering `engine` from `link`.
    pub fn new(engine: Soundscape, link: FrameReceiver) -> Self {
        Self {
            engine,
            link,
            scratch: Box::new([0.0; 2 * SCRATCH_FRAMES]),
            promoted: false,
            gain: 1.0,
        }
    }

    /// Fills `out` (`channels` interleaved) with the next samples: stereo in the first two
    /// channels, silence in the rest (a mono device gets the mix).
    pub fn fill<T: Copy>(&mut self, out: &mut [T], channels: usize, convert: impl Fn(f32) -> T) {
        if !self.promoted {
            // Once, on the audio thread itself (cpal's or the clock's): a buffer must not wait
            // behind the renderer's threads for a core.
            self.promoted = true;
            let got = promote_this_thread();
            self.link
                .counters()
                .scheduling
                .store(got.as_u8(), Ordering::Relaxed);
        }
        let start = Instant::now();
        let channels = channels.max(1);
        let frames = out.len() / channels;
        let paused = self.link.paused();
        if paused {
            let c = self.link.counters();
            c.paused_frames.fetch_add(frames as u64, Ordering::Relaxed);
            if self.gain <= 0.0 {
                // Faded out: silence without the soundscape's work (its clock stands still).
                out.fill(convert(0.0));
                c.callbacks.fetch_add(1, Ordering::Relaxed);
                c.frames.fetch_add(frames as u64, Ordering::Relaxed);
                return;
            }
        }
        let target = if paused { 0.0 } else { 1.0 };
        let frame = *self.link.latest();
        self.engine.set_frame(&frame);
        self.engine.set_volume(self.link.volume());
        while let Some(mut s) = self.link.next_splash() {
            // In real time a splash sounds as soon as it arrives.
            s.time = self.engine.time();
            self.engine.splash(s);
        }
        let mut done = 0;
        while done < frames {
            let n = (frames - done).min(SCRATCH_FRAMES);
            let buf = &mut self.scratch[..2 * n];
            self.engine.render(buf);
            if self.gain != target || target < 1.0 {
                // Fading toward the pause's target, a step a frame.
                for s in buf.chunks_exact_mut(2) {
                    self.gain += (target - self.gain).clamp(-1.0 / FADE_FRAMES, 1.0 / FADE_FRAMES);
                    s[0] *= self.gain;
                    s[1] *= self.gain;
                }
            }
            let dst = &mut out[done * channels..(done + n) * channels];
            for (d, s) in dst.chunks_exact_mut(channels).zip(buf.chunks_exact(2)) {
                match d.len() {
                    1 => d[0] = convert(0.5 * (s[0] + s[1])),
                    _ => {
                        d[0] = convert(s[0]);
                        d[1] = convert(s[1]);
                        for x in &mut d[2..] {
                            *x = convert(0.0);
                        }
                    }
                }
            }
            done += n;
        }
        let c = self.link.counters();
        let ns = start.elapsed().as_nanos() as u64;
        c.callbacks.fetch_add(1, Ordering::Relaxed);
        c.frames.fetch_add(frames as u64, Ordering::Relaxed);
        c.busy_ns.fetch_add(ns, Ordering::Relaxed);
        c.worst_ns.fetch_max(ns, Ordering::Relaxed);
    }

    /// The counters (the clock adds its late buffers here).
    pub fn counters(&self) -> &super::link::Counters {
        self.link.counters()
    }

    /// The counters, to be held by the thread that runs this player.
    pub fn counters_arc(&self) -> std::sync::Arc<super::link::Counters> {
        self.link.counters_arc()
    }

    /// Called when a new stream (a new thread) takes the player over: that thread asks for
    /// its scheduling at its first buffer.
    pub fn rebind(&mut self) {
        self.promoted = false;
    }
}

/// Asks the scheduler to run the calling thread as a real-time one (SCHED_FIFO, priority 10,
/// as audio servers do), or failing that at nice −10; without the privilege it stays as it
/// is. Linux only (Android has its own below). Nothing is logged (this runs on the audio
/// thread); what it got goes to the report.
#[cfg(target_os = "linux")]
pub fn promote_this_thread() -> Scheduling {
    let param = libc::sched_param { sched_priority: 10 };
    // SAFETY: `param` is a valid sched_param for this call; pid 0 is the calling thread, whose
    // scheduling policy is all that changes.
    if unsafe { libc::sched_setscheduler(0, libc::SCHED_FIFO, &param) } == 0 {
        return Scheduling::RealTime;
    }
    // SAFETY: on Linux PRIO_PROCESS with who = 0 names the calling thread; only its nice
    // value changes (a refusal leaves it as it is).
    if unsafe { libc::setpriority(libc::PRIO_PROCESS, 0, -10) } == 0 {
        Scheduling::Raised
    } else {
        Scheduling::Platform
    }
}

/// On Android the platform schedules AAudio's callback thread: SCHED_FIFO when the stream got
/// the low-latency path (asked for through cpal's `realtime` feature), else an ordinary
/// thread. Reports which; an app may not change it.
#[cfg(target_os = "android")]
pub fn promote_this_thread() -> Scheduling {
    // SAFETY: pid 0 is the calling thread; the call only reads its policy.
    if unsafe { libc::sched_getscheduler(0) } == libc::SCHED_FIFO {
        Scheduling::RealTime
    } else {
        Scheduling::Platform
    }
}

/// Elsewhere the platform's audio thread keeps its own priority.
#[cfg(not(any(target_os = "linux", target_os = "android")))]
pub fn promote_this_thread() -> Scheduling {
    Scheduling::Platform
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::audio::engine::SoundConfig;
    use crate::audio::link::link;
    use crate::audio::scene::SoundFrame;

    /// The largest step between neighbouring samples of either channel, from `last` (the
    /// previous buffer's last frame) on.
    fn largest_step(last: [f32; 2], buf: &[f32]) -> f32 {
        let frames = || std::iter::once(&last[..]).chain(buf.chunks_exact(2));
        frames()
            .zip(frames().skip(1))
            .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
            .fold(0.0, f32::max)
    }

    fn last_frame(buf: &[f32]) -> [f32; 2] {
        [buf[buf.len() - 2], buf[buf.len() - 1]]
    }

    #[test]
    fn a_pause_fades_out_to_counted_silence_and_back_in_without_a_jump() {
        let (mut tx, rx) = link(1.0);
        let mut player = Player::new(Soundscape::new(SoundConfig::default()).unwrap(), rx);
        // A windy sea: something to hear.
        let frame = SoundFrame {
            wind_speed: 14.0,
            ..SoundFrame::default()
        };
        tx.publish(&frame);
        let mut buf = vec![0.0f32; 2 * 480];
        for _ in 0..20 {
            player.fill(&mut buf, 2, |x| x);
        }
        let playing = buf.iter().map(|x| x.abs()).fold(0.0, f32::max);
        assert!(playing > 1e-3, "the sea is silent: {playing}");
        let mut last = last_frame(&buf);
        player.fill(&mut buf, 2, |x| x);
        let steady = largest_step(last, &buf);
        last = last_frame(&buf);

        tx.set_paused(true);
        player.fill(&mut buf, 2, |x| x);
        // The first paused buffer fades: its last 240 frames silent, no step larger than
        // playing's.
        assert!(buf[2 * 240..].iter().all(|&x| x == 0.0));
        assert!(largest_step(last, &buf) <= steady * 1.5 + 1e-6);
        let before = player.counters().snapshot();
        player.fill(&mut buf, 2, |x| x);
        assert!(buf.iter().all(|&x| x == 0.0));
        let after = player.counters().snapshot();
        assert_eq!(after.paused_frames - before.paused_frames, 480);

        tx.set_paused(false);
        player.fill(&mut buf, 2, |x| x);
        // Back in from silence: the first samples near zero, rising over the fade.
        assert!(
            buf[0].abs() < 1e-3 && buf[1].abs() < 1e-3,
            "{:?}",
            &buf[..2]
        );
        assert!(largest_step([0.0; 2], &buf) <= steady * 1.5 + 1e-6);
        player.fill(&mut buf, 2, |x| x);
        assert!(buf.iter().map(|x| x.abs()).fold(0.0, f32::max) > 1e-3);
    }
}
