//! Sound that survives its device: the stream is opened, and after a disconnect closed and
//! opened again, on a thread of its own ("vr-ocean-audio-device"), never in the stream's
//! callbacks (Android's AAudio guidance: a disconnected stream is closed and a new one opened
//! from another thread). Headphones plugged in or pulled out on a Quest disconnect the stream;
//! the new one plays the same [`Player`], so the soundscape's clock, voices and link carry on
//! where they stopped.
//!
//! An [`Outlet`] is what opens streams: cpal's default device, the silent clock, or a test's
//! stream that fails on purpose (the injectable device error).

use std::sync::atomic::Ordering;
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use super::link::Counters;
use super::player::Player;
use super::AudioError;

/// The player, shared by the stream that plays it now and the thread that hands it to the
/// next stream. Only one stream exists at a time, so the callback's `try_lock` never finds it
/// taken: it never waits.
pub type SharedPlayer = Arc<Mutex<Player>>;

/// Fills `out` from the shared player, or with silence in the instant a reopen holds it (or
/// when an earlier callback panicked in it).
pub fn fill_shared<T: Copy>(
    player: &SharedPlayer,
    out: &mut [T],
    channels: usize,
    convert: impl Fn(f32) -> T,
) {
    match player.try_lock() {
        Ok(mut p) => p.fill(out, channels, convert),
        Err(_) => out.fill(convert(0.0)),
    }
}

/// How long a failed reopen waits before the next try.
pub const RETRY: Duration = Duration::from_millis(500);

/// What the opening thread hears.
enum Event {
    /// The stream of this generation is gone (why).
    Lost(u64, String),
    /// The output is being dropped.
    Stop,
}

/// A stream's way to say it is gone: call [`LossReporter::lost`] from its error callback.
/// Reports of a stream that was already replaced are ignored.
#[derive(Clone)]
pub struct LossReporter {
    tx: Sender<Event>,
    generation: u64,
}

impl LossReporter {
    /// The stream is gone (a disconnected device); it will be closed and replaced.
    pub fn lost(&self, why: String) {
        // The thread may be gone already (the output dropped): nothing left to tell.
        let _ = self.tx.send(Event::Lost(self.generation, why));
    }
}

/// Opens streams that play a shared player. Runs on the opening thread, which also drops the
/// streams it returns (a cpal stream need not move between threads).
pub trait Outlet: Send + 'static {
    /// What keeps a stream playing; dropping it stops and closes the stream.
    type Stream;
    /// Opens a stream playing `player`; it calls `loss` when it is gone. Returns the stream
    /// and the device's name.
    fn open(
        &mut self,
        player: &SharedPlayer,
        loss: LossReporter,
    ) -> Result<(Self::Stream, String), AudioError>;
}

/// The opening thread: owns the stream; dropping it stops the stream and joins the thread.
pub struct Keeper {
    tx: Sender<Event>,
    handle: Option<JoinHandle<()>>,
}

impl Keeper {
    /// Opens the first stream on a new thread and returns once it plays (with the device's
    /// name), or with the error that kept it from opening (the thread is then gone).
    pub fn start<O: Outlet>(
        outlet: O,
        player: SharedPlayer,
        counters: Arc<Counters>,
    ) -> Result<(Self, String), AudioError> {
        let (tx, rx) = mpsc::channel();
        let (first_tx, first_rx) = mpsc::sync_channel(1);
        let loss_tx = tx.clone();
        let handle = std::thread::Builder::new()
            .name("vr-ocean-audio-device".into())
            .spawn(move || {
                let mut run = Run {
                    outlet,
                    player,
                    counters,
                    tx: loss_tx,
                    rx,
                    generation: 0,
                };
                match run.open() {
                    Ok((stream, name)) => {
                        let _ = first_tx.send(Ok(name));
                        run.keep(stream);
                    }
                    Err(e) => {
                        let _ = first_tx.send(Err(e));
                    }
                }
            })
            .map_err(|e| AudioError::Device(format!("cannot start the audio thread: {e}")))?;
        let mut keeper = Self {
            tx,
            handle: Some(handle),
        };
        let first = first_rx.recv().unwrap_or_else(|_| {
            Err(AudioError::Device(
                "the audio thread ended before opening the output".into(),
            ))
        });
        match first {
            Ok(name) => Ok((keeper, name)),
            Err(e) => {
                keeper.stop();
                Err(e)
            }
        }
    }

    fn stop(&mut self) {
        let _ = self.tx.send(Event::Stop);
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

impl Drop for Keeper {
    fn drop(&mut self) {
        self.stop();
    }
}

/// The opening thread's state.
struct Run<O: Outlet> {
    outlet: O,
    player: SharedPlayer,
    counters: Arc<Counters>,
    tx: Sender<Event>,
    rx: Receiver<Event>,
    /// The current stream's number: losses of older ones are stale.
    generation: u64,
}

impl<O: Outlet> Run<O> {
    fn open(&mut self) -> Result<(O::Stream, String), AudioError> {
        self.generation += 1;
        let loss = LossReporter {
            tx: self.tx.clone(),
            generation: self.generation,
        };
        self.outlet.open(&self.player, loss)
    }

    /// Keeps a stream until the output is dropped, replacing it whenever it is lost.
    fn keep(&mut self, mut stream: O::Stream) {
        loop {
            match self.rx.recv() {
                Ok(Event::Lost(g, why)) if g == self.generation => {
                    // Closed here, on this thread, before the next one opens.
                    drop(stream);
                    log::warn!("audio output lost ({why}); reopening");
                    match self.reopen() {
                        Some(s) => stream = s,
                        None => return,
                    }
                }
                Ok(Event::Lost(..)) => {}
                Ok(Event::Stop) | Err(_) => return,
            }
        }
    }

    /// Opens a new stream, retrying every [`RETRY`] until one opens or the output is dropped.
    fn reopen(&mut self) -> Option<O::Stream> {
        let mut logged = false;
        loop {
            // A new thread will call the player: it asks for its scheduling again.
            if let Ok(mut p) = self.player.lock() {
                p.rebind();
            }
            match self.open() {
                Ok((stream, name)) => {
                    self.counters.reopened.fetch_add(1, Ordering::Relaxed);
                    log::info!("audio output reopened on {name}");
                    return Some(stream);
                }
                Err(e) if !logged => {
                    logged = true;
                    log::warn!("{e}; trying again every {} ms", RETRY.as_millis());
                }
                Err(_) => {}
            }
            // Wait for the retry, leaving at once when the output is dropped.
            loop {
                match self.rx.recv_timeout(RETRY) {
                    Ok(Event::Stop) | Err(RecvTimeoutError::Disconnected) => return None,
                    Ok(Event::Lost(..)) => {}
                    Err(RecvTimeoutError::Timeout) => break,
                }
            }
        }
    }
}
