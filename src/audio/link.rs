//! The lock-free hand-over from the frame thread to the audio callback: the latest
//! [`SoundFrame`] through a triple buffer (the writer never waits, the reader always gets a
//! whole frame, the newest), splashes through a single-producer single-consumer ring, and the
//! volume and the callback's counters as atomics. Nothing here allocates after [`link`], locks
//! or blocks.

use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, AtomicU8, AtomicUsize, Ordering};
use std::sync::Arc;

use super::scene::{SoundFrame, Splash};

/// Splashes the ring holds between two callbacks (more are dropped and counted).
pub const SPLASH_RING: usize = 32;

/// Set in the shared index when the writer has published since the reader last looked.
const FRESH: u8 = 4;

/// What the callback counts, read by the app for its report.
#[derive(Debug, Default)]
pub struct Counters {
    /// Callbacks run.
    pub callbacks: AtomicU64,
    /// Frames rendered.
    pub frames: AtomicU64,
    /// Buffers the device reported as under-run (or the clock saw late).
    pub underruns: AtomicU64,
    /// Nanoseconds spent rendering in callbacks.
    pub busy_ns: AtomicU64,
    /// The longest callback (ns).
    pub worst_ns: AtomicU64,
    /// Splashes dropped because the ring was full.
    pub dropped: AtomicU64,
    /// Late buffers the clock saw whose rendering took under half a period: the thread
    /// was woken too late (held off its core), not slowed by its work.
    pub late_wakes: AtomicU64,
    /// The scheduling the audio thread obtained ([`Scheduling`] as a number, 0 before the
    /// first callback).
    pub scheduling: AtomicU8,
    /// Frames the callback gave as silence because the app was paused (the user away).
    pub paused_frames: AtomicU64,
    /// Streams opened again after the device was lost (headphones plugged in or out).
    pub reopened: AtomicU64,
}

/// The scheduling the audio thread asked for and got (see `player::promote_this_thread`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Scheduling {
    /// Not known yet (no callback has run).
    #[default]
    Unknown,
    /// Real-time (SCHED_FIFO): nothing of the app's own can hold it off a core.
    RealTime,
    /// A raised nice value: favoured, but it can wait behind other threads.
    Raised,
    /// As the platform started it (on Android: an AAudio thread without the low-latency path).
    Platform,
}

impl Scheduling {
    fn from_u8(v: u8) -> Self {
        match v {
            1 => Self::RealTime,
            2 => Self::Raised,
            3 => Self::Platform,
            _ => Self::Unknown,
        }
    }

    /// The number [`Counters::scheduling`] holds.
    pub fn as_u8(self) -> u8 {
        match self {
            Self::Unknown => 0,
            Self::RealTime => 1,
            Self::Raised => 2,
            Self::Platform => 3,
        }
    }
}

impl std::fmt::Display for Scheduling {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Unknown => "unknown",
            Self::RealTime => "real-time",
            Self::Raised => "raised priority",
            Self::Platform => "platform's",
        })
    }
}

/// A snapshot of [`Counters`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CountersSnapshot {
    /// Callbacks run.
    pub callbacks: u64,
    /// Frames rendered.
    pub frames: u64,
    /// Under-runs.
    pub underruns: u64,
    /// Rendering time (ns).
    pub busy_ns: u64,
    /// Longest callback (ns).
    pub worst_ns: u64,
    /// Splashes dropped.
    pub dropped: u64,
    /// Late buffers whose thread woke too late (the clock only).
    pub late_wakes: u64,
    /// The audio thread's scheduling.
    pub scheduling: Scheduling,
    /// Frames given as silence while paused.
    pub paused_frames: u64,
    /// Streams reopened after a lost device.
    pub reopened: u64,
}

impl Counters {
    /// The counts now.
    pub fn snapshot(&self) -> CountersSnapshot {
        CountersSnapshot {
            callbacks: self.callbacks.load(Ordering::Relaxed),
            frames: self.frames.load(Ordering::Relaxed),
            underruns: self.underruns.load(Ordering::Relaxed),
            busy_ns: self.busy_ns.load(Ordering::Relaxed),
            worst_ns: self.worst_ns.load(Ordering::Relaxed),
            dropped: self.dropped.load(Ordering::Relaxed),
            late_wakes: self.late_wakes.load(Ordering::Relaxed),
            scheduling: Scheduling::from_u8(self.scheduling.load(Ordering::Relaxed)),
            paused_frames: self.paused_frames.load(Ordering::Relaxed),
            reopened: self.reopened.load(Ordering::Relaxed),
        }
    }
}

struct Shared {
    frames: [UnsafeCell<SoundFrame>; 3],
    /// The middle slot's index, with [`FRESH`] when it holds an unread frame.
    middle: AtomicU8,
    ring: [UnsafeCell<Splash>; SPLASH_RING],
    head: AtomicUsize,
    tail: AtomicUsize,
    volume: AtomicU32,
    /// The app is paused (the user away): the callback fades out and gives silence.
    paused: AtomicBool,
    counters: Arc<Counters>,
}

// SAFETY: the slots are reached only through the protocol below: the writer owns the slot
// index it holds, the reader owns its own, and the middle one changes hands only through the
// atomic swap (AcqRel), so no slot is ever accessed by two threads at once; ring entries
// between `tail` and `head` belong to the reader, the rest to the writer, and each side
// publishes its index with Release after touching an entry and reads the other's with
// Acquire.
unsafe impl Sync for Shared {}

/// The frame thread's end.
pub struct FrameSender {
    shared: Arc<Shared>,
    write: u8,
}

/// The audio callback's end.
pub struct FrameReceiver {
    shared: Arc<Shared>,
    read: u8,
}

/// A new link at `volume` (0 to 1).
pub fn link(volume: f32) -> (FrameSender, FrameReceiver) {
    let splash = Splash {
        time: 0.0,
        position: glam::Vec3::ZERO,
        speed: 0.0,
        mass: 1.0,
        radius: 1.0,
    };
    let shared = Arc::new(Shared {
        frames: std::array::from_fn(|_| UnsafeCell::new(SoundFrame::default())),
        middle: AtomicU8::new(1),
        ring: std::array::from_fn(|_| UnsafeCell::new(splash)),
        head: AtomicUsize::new(0),
        tail: AtomicUsize::new(0),
        volume: AtomicU32::new(volume.to_bits()),
        paused: AtomicBool::new(false),
        counters: Arc::new(Counters::default()),
    });
    (
        FrameSender {
            shared: shared.clone(),
            write: 0,
        },
        FrameReceiver { shared, read: 2 },
    )
}

impl FrameSender {
    /// Publishes `frame` as the newest (replacing an unread one).
    pub fn publish(&mut self, frame: &SoundFrame) {
        // SAFETY: `write` is the writer's own slot (see `Shared`'s Sync note).
        unsafe { *self.shared.frames[self.write as usize].get() = *frame };
        let old = self
            .shared
            .middle
            .swap(self.write | FRESH, Ordering::AcqRel);
        self.write = old & !FRESH;
    }

    /// Queues a splash; false (and counted) when the ring is full.
    pub fn splash(&mut self, splash: Splash) -> bool {
        let s = &self.shared;
        let head = s.head.load(Ordering::Relaxed);
        let tail = s.tail.load(Ordering::Acquire);
        if head.wrapping_sub(tail) >= SPLASH_RING {
            s.counters.dropped.fetch_add(1, Ordering::Relaxed);
            return false;
        }
        // SAFETY: entries from `head` on belong to the writer until `head` moves past them.
        unsafe { *s.ring[head % SPLASH_RING].get() = splash };
        s.head.store(head.wrapping_add(1), Ordering::Release);
        true
    }

    /// Sets the volume (0 to 1; callers validate).
    pub fn set_volume(&self, volume: f32) {
        self.shared
            .volume
            .store(volume.clamp(0.0, 1.0).to_bits(), Ordering::Relaxed);
    }

    /// Pauses the sound (the user away: faded out within a few milliseconds, then silence
    /// without the soundscape's work) or resumes it (faded in from where it stopped).
    pub fn set_paused(&self, paused: bool) {
        self.shared.paused.store(paused, Ordering::Relaxed);
    }

    /// The callback's counters.
    pub fn counters(&self) -> &Counters {
        &self.shared.counters
    }

    /// The counters, to be held elsewhere (a device's error callback).
    pub fn counters_arc(&self) -> Arc<Counters> {
        self.shared.counters.clone()
    }
}

impl FrameReceiver {
    /// The newest frame (the default one before any was published).
    pub fn latest(&mut self) -> &SoundFrame {
        let s = &self.shared;
        if s.middle.load(Ordering::Acquire) & FRESH != 0 {
            let old = s.middle.swap(self.read, Ordering::AcqRel);
            self.read = old & !FRESH;
        }
        // SAFETY: `read` is the reader's own slot.
        unsafe { &*s.frames[self.read as usize].get() }
    }

    /// The next queued splash.
    pub fn next_splash(&mut self) -> Option<Splash> {
        let s = &self.shared;
        let tail = s.tail.load(Ordering::Relaxed);
        if tail == s.head.load(Ordering::Acquire) {
            return None;
        }
        // SAFETY: entries before `head` (Acquire above) and from `tail` belong to the reader.
        let splash = unsafe { *s.ring[tail % SPLASH_RING].get() };
        s.tail.store(tail.wrapping_add(1), Ordering::Release);
        Some(splash)
    }

    /// Whether the frame thread paused the sound.
    pub fn paused(&self) -> bool {
        self.shared.paused.load(Ordering::Relaxed)
    }

    /// The volume set by the frame thread.
    pub fn volume(&self) -> f32 {
        f32::from_bits(self.shared.volume.load(Ordering::Relaxed))
    }

    /// The counters this end updates.
    pub fn counters(&self) -> &Counters {
        &self.shared.counters
    }

    /// The counters, to be held elsewhere (the clock's thread, the reopening thread).
    pub fn counters_arc(&self) -> Arc<Counters> {
        self.shared.counters.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reader_gets_the_newest_whole_frame() {
        let (mut tx, mut rx) = link(1.0);
        assert_eq!(rx.latest().time, 0.0);
        for t in 1..=5 {
            let f = SoundFrame {
                time: t as f64,
                wind_speed: t as f32,
                ..SoundFrame::default()
            };
            tx.publish(&f);
        }
        let f = *rx.latest();
        assert_eq!((f.time, f.wind_speed), (5.0, 5.0));
        assert_eq!(rx.latest().time, 5.0, "no new frame: the same one");
    }

    #[test]
    fn frames_cross_threads_whole() {
        let (mut tx, mut rx) = link(1.0);
        let reader = std::thread::spawn(move || {
            let mut last = 0.0;
            for _ in 0..200_000 {
                let f = rx.latest();
                // Every field written together: a torn frame would mix two.
                assert_eq!(f.time as f32, f.wind_speed);
                assert!(f.time >= last);
                last = f.time;
            }
        });
        for t in 0..200_000 {
            tx.publish(&SoundFrame {
                time: t as f64,
                wind_speed: t as f32,
                ..SoundFrame::default()
            });
        }
        reader.join().unwrap();
    }

    #[test]
    fn splashes_queue_in_order_and_overflow_is_counted() {
        let (mut tx, mut rx) = link(1.0);
        let s = |t: f64| Splash {
            time: t,
            position: glam::Vec3::ZERO,
            speed: 1.0,
            mass: 1.0,
            radius: 0.1,
        };
        for k in 0..SPLASH_RING + 3 {
            tx.splash(s(k as f64));
        }
        assert_eq!(tx.counters().snapshot().dropped, 3);
        let times: Vec<f64> = std::iter::from_fn(|| rx.next_splash().map(|s| s.time)).collect();
        assert_eq!(
            times,
            (0..SPLASH_RING).map(|k| k as f64).collect::<Vec<_>>()
        );
    }
}
