//! Keeps the Rayon pool's other threads awake through a step.
//!
//! A step is a dozen short fork-joins (evolution, two passes per transform, surface rows,
//! mips), some only 20-50 µs long. A Rayon worker that finds no work for a few microseconds goes
//! to sleep on a futex, and the next fork-join has to wake it: 10-20 µs under KVM (measured:
//! a 2×20 µs join costs 41 µs after a 50 µs gap, 21 µs back to back), so the second thread
//! joined most regions late and the finite step at N = 256 ran only 1.3-1.6x faster on two
//! threads than on one. [`with_pool_awake`] parks one "keeper" job on each other thread for the
//! length of the step: it runs whatever work the step forks (through [`rayon::yield_now`]) and
//! spins in between, so no fork-join waits for a wake-up. Which thread runs which task does not
//! change any result: the stages compute every element the same way on any thread.
//!
//! The keepers are `rayon::join` halves, stack jobs, so a step still allocates nothing.
//!
//! # Why a keeper cannot hang the step
//! A keeper spins until the step is done, so it must never spin on top of a job the step waits
//! for: a thread that took one of the step's jobs and then, waiting inside that job's own join,
//! a keeper, would never get back to the job. (Rayon's thieves take the oldest job first and the
//! keepers are older than any of the step's, so this should not happen; the rule below does not
//! depend on it.) The step waits (at most 100 µs, about one wake-up) for its keepers
//! to start before it begins, and a keeper that starts after the step did returns at once: a
//! keeper spins only if no job of the step existed when it was taken.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Idle rounds of a keeper between two `sched_yield`s: often enough that a keeper on an
/// oversubscribed host (tests, CI) hands its core to a runnable thread, rarely enough that it
/// stays on the CPU (and awake) on a free one.
const SPINS_PER_OS_YIELD: u32 = 64;

/// How long the step waits for its keepers to start (each a sleeping worker's wake-up, 10-20 µs
/// under KVM) before it starts without the late ones. Unit tests wait longer, so that a loaded
/// test host cannot make a keeper late and a test that checks where work ran flaky.
#[cfg(not(test))]
const KEEPER_WAIT: Duration = Duration::from_micros(100);
#[cfg(test)]
const KEEPER_WAIT: Duration = Duration::from_secs(2);

/// What the step and its keepers share.
struct Keepers {
    /// The step's thread.
    owner: usize,
    /// Keepers spinning (or done spinning).
    started: AtomicUsize,
    /// The step has started: keepers taken from now on may sit on top of its jobs.
    step_started: AtomicBool,
    /// The step is over: keepers return.
    done: AtomicBool,
}

#[cfg(test)]
thread_local! {
    /// Keepers running on this thread (tests check where forked work ran).
    static KEEPING: std::cell::Cell<u32> = const { std::cell::Cell::new(0) };
}

/// Runs `f` on this thread with every other thread of the current Rayon pool kept awake until
/// it returns (see the module doc). Outside a pool, or on a pool of one thread, just `f()`.
pub fn with_pool_awake<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    let Some(owner) = rayon::current_thread_index() else {
        return f();
    };
    let others = rayon::current_num_threads() - 1;
    if others == 0 {
        return f();
    }
    let k = Keepers {
        owner,
        started: AtomicUsize::new(0),
        step_started: AtomicBool::new(false),
        done: AtomicBool::new(false),
    };
    let run = || {
        // Set even if `f` panics: `join` waits for the keepers before it unwinds.
        let _done = SetOnDrop(&k.done);
        let since = Instant::now();
        while k.started.load(Ordering::SeqCst) < others && since.elapsed() < KEEPER_WAIT {
            std::hint::spin_loop();
        }
        k.step_started.store(true, Ordering::SeqCst);
        f()
    };
    with_keepers(others, &k, run)
}

/// `f` beside `count` keepers: one `join` per keeper, `f` innermost (run first, on this thread).
fn with_keepers<R: Send>(count: usize, k: &Keepers, f: impl FnOnce() -> R + Send) -> R {
    if count == 0 {
        return f();
    }
    rayon::join(|| with_keepers(count - 1, k, f), || keep(k)).0
}

/// A keeper: runs the pool's pending work, or spins, until the step is done. It returns at once
/// on the step's own thread (which pops its own keeper while it waits inside one of the step's
/// joins: spinning there would wait for the step, which waits below it on the same stack) and
/// when the step has already started (see the module doc).
fn keep(k: &Keepers) {
    if rayon::current_thread_index() == Some(k.owner) || k.step_started.load(Ordering::SeqCst) {
        return;
    }
    k.started.fetch_add(1, Ordering::SeqCst);
    let done = &k.done;
    #[cfg(test)]
    KEEPING.with(|k| k.set(k.get() + 1));
    #[cfg(test)]
    let _count = Counted;
    let mut idle = 0u32;
    while !done.load(Ordering::Acquire) {
        if rayon::yield_now() == Some(rayon::Yield::Executed) {
            idle = 0;
            continue;
        }
        idle = idle.wrapping_add(1);
        if idle.is_multiple_of(SPINS_PER_OS_YIELD) {
            std::thread::yield_now();
        } else {
            std::hint::spin_loop();
        }
    }
}

/// Sets the flag when dropped (the end of `f`, returned or unwound).
struct SetOnDrop<'a>(&'a AtomicBool);

impl Drop for SetOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

/// Counts a keeper out of [`KEEPING`] when it ends (returned or unwound).
#[cfg(test)]
struct Counted;

#[cfg(test)]
impl Drop for Counted {
    fn drop(&mut self) {
        KEEPING.with(|k| k.set(k.get() - 1));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;
    use std::sync::atomic::AtomicUsize;
    use std::time::{Duration, Instant};

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    #[test]
    fn returns_f_and_runs_its_forks_on_every_pool_size() {
        assert_eq!(with_pool_awake(|| 7), 7, "outside a pool");
        for threads in 1..=4 {
            let sum = pool(threads).install(|| {
                with_pool_awake(|| (0..10_000u64).into_par_iter().map(|x| x * x).sum::<u64>())
            });
            assert_eq!(sum, (0..10_000u64).map(|x| x * x).sum::<u64>());
        }
    }

    #[test]
    fn forked_work_runs_inside_a_keeper_and_the_pool_is_free_after() {
        // The owner spins in the first half of a join, so only the other thread can run the
        // second: it must find it from inside its keeper (a sleeping worker woken by the join
        // would run it with no keeper on its stack). Afterwards no keeper is left running.
        let p = pool(2);
        for _ in 0..20 {
            let keepers_seen = p.install(|| {
                with_pool_awake(|| {
                    let deadline = Instant::now() + Duration::from_secs(10);
                    let seen = AtomicUsize::new(usize::MAX);
                    rayon::join(
                        || {
                            while seen.load(Ordering::Acquire) == usize::MAX
                                && Instant::now() < deadline
                            {
                                std::hint::spin_loop();
                            }
                        },
                        || seen.store(KEEPING.with(|k| k.get()) as usize, Ordering::Release),
                    );
                    seen.load(Ordering::Acquire)
                })
            });
            assert_eq!(keepers_seen, 1, "the forked half ran outside a keeper");
            let after = p.broadcast(|_| KEEPING.with(|k| k.get()));
            assert_eq!(after, vec![0, 0], "a keeper outlived its step");
        }
    }

    /// Nested fork-joins of uneven length, as a step's stages make, on pools of 2-4 threads:
    /// a keeper that started spinning on top of a job the step waits for would hang this (the
    /// watchdog turns a hang into a failure).
    #[test]
    fn uneven_nested_forks_never_hang() {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for threads in [2, 3, 4] {
                let p = pool(threads);
                for round in 0..300u64 {
                    let sum = p.install(|| {
                        with_pool_awake(|| {
                            (0..64u64)
                                .into_par_iter()
                                .map(|i| {
                                    let spin = (i * 7 + round) % 13;
                                    let t = Instant::now();
                                    while t.elapsed() < Duration::from_micros(spin) {}
                                    (0..i).into_par_iter().map(|j| j ^ round).sum::<u64>()
                                })
                                .sum::<u64>()
                        })
                    });
                    let want: u64 = (0..64u64)
                        .map(|i| (0..i).map(|j| j ^ round).sum::<u64>())
                        .sum();
                    assert_eq!(sum, want);
                }
            }
            tx.send(()).unwrap();
        });
        rx.recv_timeout(Duration::from_secs(120))
            .expect("with_pool_awake hung (or panicked) under nested forks");
    }

    #[test]
    fn nested_calls_and_a_panic_in_f_end() {
        let p = pool(2);
        let n = p.install(|| with_pool_awake(|| with_pool_awake(|| 3) + 1));
        assert_eq!(n, 4);
        let caught =
            p.install(|| std::panic::catch_unwind(|| with_pool_awake(|| panic!("a step failed"))));
        assert!(caught.is_err());
        assert_eq!(p.install(|| with_pool_awake(|| 5)), 5);
    }
}
