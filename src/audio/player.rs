//! What a real-time output runs per buffer: take the newest frame and the queued splashes
//! from the link, render, count. Shared by the device's callback and the clock that stands in
//! for a missing device. No allocation, lock or I/O.

use std::sync::atomic::Ordering;
use std::time::Instant;

use super::engine::Soundscape;
use super::link::FrameReceiver;

/// Frames converted at a time for devices that take integer samples.
pub const SCRATCH_FRAMES: usize = 1024;

/// The audio thread's side: the soundscape and the link's receiving end.
pub struct Player {
    engine: Soundscape,
    link: FrameReceiver,
    scratch: Box<[f32; 2 * SCRATCH_FRAMES]>,
}

impl Player {
    /// A player rendering `engine` from `link`.
    pub fn new(engine: Soundscape, link: FrameReceiver) -> Self {
        Self {
            engine,
            link,
            scratch: Box::new([0.0; 2 * SCRATCH_FRAMES]),
        }
    }

    /// Fills `out` (`channels` interleaved) with the next samples: stereo in the first two
    /// channels, silence in the rest (a mono device gets the mix).
    pub fn fill<T: Copy>(&mut self, out: &mut [T], channels: usize, convert: impl Fn(f32) -> T) {
        let start = Instant::now();
        let frame = *self.link.latest();
        self.engine.set_frame(&frame);
        self.engine.set_volume(self.link.volume());
        while let Some(mut s) = self.link.next_splash() {
            // In real time a splash sounds as soon as it arrives.
            s.time = self.engine.time();
            self.engine.splash(s);
        }
        let channels = channels.max(1);
        let frames = out.len() / channels;
        let mut done = 0;
        while done < frames {
            let n = (frames - done).min(SCRATCH_FRAMES);
            let buf = &mut self.scratch[..2 * n];
            self.engine.render(buf);
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
}
