//! The reopening keeper against a device that fails on purpose: streams unplugged mid-play,
//! opens refused until a device comes back; the clock and the real device's outlet as the
//! streams behind it. Beside `reopen.rs`, as it drives the outlets that build on it.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

use super::reopen::*;
use crate::audio::clock::ClockThread;
use crate::audio::AudioError;
use crate::audio::{AudioOutput, SoundConfig, SoundFrame};

/// The injectable device error: silent-clock streams, the first of which is unplugged
/// after `lose_after`; the next `refusals` opens fail (no device yet), then one opens.
struct Unplugged {
    opens: Arc<AtomicU32>,
    lose_after: Duration,
    refusals: u32,
}

impl Outlet for Unplugged {
    type Stream = (ClockThread, Option<JoinHandle<()>>);

    fn open(
        &mut self,
        player: &SharedPlayer,
        loss: LossReporter,
    ) -> Result<(Self::Stream, String), AudioError> {
        let n = self.opens.fetch_add(1, Ordering::Relaxed);
        if n > 0 && self.refusals > 0 {
            self.refusals -= 1;
            return Err(AudioError::Device("no output device".into()));
        }
        let clock = ClockThread::start(player.clone(), 480, Duration::from_millis(10))?;
        let after = self.lose_after;
        let unplug = (n == 0).then(|| {
            std::thread::spawn(move || {
                std::thread::sleep(after);
                loss.lost("headphones unplugged".into());
            })
        });
        Ok(((clock, unplug), format!("test device {n}")))
    }
}

#[test]
fn a_lost_device_is_reopened_and_the_same_sound_plays_on() {
    let opens = Arc::new(AtomicU32::new(0));
    let outlet = Unplugged {
        opens: opens.clone(),
        lose_after: Duration::from_millis(150),
        refusals: 1,
    };
    let mut out = AudioOutput::on(SoundConfig::default(), outlet, 480).unwrap();
    out.sender().publish(&SoundFrame {
        wind_speed: 14.0,
        ..SoundFrame::default()
    });
    // Lost at 150 ms; the first reopen is refused, the second (500 ms later) opens.
    let deadline = std::time::Instant::now() + Duration::from_secs(5);
    while out.counters().0.reopened == 0 {
        assert!(std::time::Instant::now() < deadline, "never reopened");
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(opens.load(Ordering::Relaxed), 3, "open, refused, reopened");
    // The new stream plays the same player: its counts carry on from the first stream's.
    let before = out.counters().0;
    std::thread::sleep(Duration::from_millis(300));
    let after = out.counters().0;
    assert!(
        before.callbacks >= 10,
        "the first stream played: {before:?}"
    );
    assert!(
        after.callbacks >= before.callbacks + 10,
        "the reopened stream plays: {before:?} → {after:?}"
    );
    assert_eq!(after.frames, after.callbacks * 480);
    assert_eq!(after.reopened, 1);
    // Dropping the output stops the stream and its thread.
    drop(out);
}

#[test]
fn a_device_that_never_comes_back_is_retried_until_the_output_is_dropped() {
    let opens = Arc::new(AtomicU32::new(0));
    let outlet = Unplugged {
        opens: opens.clone(),
        lose_after: Duration::from_millis(20),
        refusals: u32::MAX,
    };
    let out = AudioOutput::on(SoundConfig::default(), outlet, 480).unwrap();
    std::thread::sleep(Duration::from_millis(1200));
    // Opened once, then refused at 20 ms, 520 ms and 1020 ms.
    let n = opens.load(Ordering::Relaxed);
    assert!((3..=4).contains(&n), "{n} opens");
    let started = std::time::Instant::now();
    drop(out);
    assert!(
        started.elapsed() < Duration::from_millis(200),
        "dropping waited for a retry"
    );
}
