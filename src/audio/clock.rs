//! The silent clock: a thread that stands in for a missing device, running the player's
//! callback on a device's schedule and dropping the samples, so a run without sound hardware
//! still makes its sound and measures its timing (busy time, late buffers).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::reopen::{fill_shared, LossReporter, Outlet, SharedPlayer};
use super::AudioError;

/// Opens [`ClockThread`]s of `frames` per buffer, one every `period`.
pub struct ClockOutlet {
    /// Frames per buffer.
    pub frames: usize,
    /// A buffer's duration.
    pub period: Duration,
}

impl Outlet for ClockOutlet {
    type Stream = ClockThread;

    fn open(
        &mut self,
        player: &SharedPlayer,
        _loss: LossReporter,
    ) -> Result<(ClockThread, String), AudioError> {
        let thread = ClockThread::start(player.clone(), self.frames, self.period)?;
        Ok((thread, "no device: silent clock".into()))
    }
}

/// The thread that stands in for a device: renders each buffer one period ahead of when a
/// device would play it and counts the buffers finished after that time as under-runs (and,
/// of those, the ones whose rendering took under half a period as late wakes). Dropping it
/// stops it.
pub struct ClockThread {
    stop: Arc<AtomicBool>,
    handle: Option<JoinHandle<()>>,
}

impl ClockThread {
    /// Starts the clock on `player`.
    pub fn start(
        player: SharedPlayer,
        frames: usize,
        period: Duration,
    ) -> Result<Self, AudioError> {
        let stop = Arc::new(AtomicBool::new(false));
        let flag = stop.clone();
        let counters = player
            .lock()
            .map_err(|_| AudioError::Device("the sound's player failed earlier".into()))?
            .counters_arc();
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
                    fill_shared(&player, &mut buffer, 2, |x| x);
                    let now = Instant::now();
                    if now > start + period * k {
                        counters.underruns.fetch_add(1, Ordering::Relaxed);
                        if now.duration_since(woke) < period / 2 {
                            // The work fitted; the thread got its core too late.
                            counters.late_wakes.fetch_add(1, Ordering::Relaxed);
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
