//! The steady state of the simulation allocates nothing: a counting global allocator watches
//! every thread (caller, worker and Rayon pool) while steps run.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use vr_ocean::sim::{OceanConfig, Simulation};

struct Counting;

static COUNTING: AtomicBool = AtomicBool::new(false);
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: same contract as ours.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as ours.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: same contract as ours.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The tests share the counter, so they take turns.
static SERIAL: Mutex<()> = Mutex::new(());

#[test]
fn steady_state_steps_do_not_allocate() {
    let _turn = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    for threads in [1, 2] {
        let cfg = OceanConfig::default_cascades(64).unwrap();
        let mut sim = Simulation::new(cfg, threads).unwrap();
        let mut t = 0.0;
        // Warm-up: first steps may size lazily created thread-local state.
        for _ in 0..10 {
            t += 1.0 / 72.0;
            sim.step_blocking(t);
        }
        ALLOCATIONS.store(0, Ordering::SeqCst);
        COUNTING.store(true, Ordering::SeqCst);
        let mut checksum = 0.0f32;
        for _ in 0..200 {
            t += 1.0 / 72.0;
            sim.begin_step(t);
            // The caller reads the previous step while the next one runs.
            checksum += sim.surfaces().cascades[0].displacement_f16[5][1].to_f32();
            let s = sim.end_step();
            checksum += s.height_at(1.0, 2.0);
        }
        COUNTING.store(false, Ordering::SeqCst);
        let n = ALLOCATIONS.load(Ordering::SeqCst);
        assert!(checksum.is_finite());
        assert_eq!(
            n, 0,
            "{n} heap allocations in 200 steady-state steps on {threads} thread(s)"
        );
    }
}

#[test]
fn the_counter_sees_allocations() {
    // Guards the test above against passing vacuously.
    let _turn = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    ALLOCATIONS.store(0, Ordering::SeqCst);
    COUNTING.store(true, Ordering::SeqCst);
    let v: Vec<u64> = std::hint::black_box((0..100).collect());
    COUNTING.store(false, Ordering::SeqCst);
    assert_eq!(v.len(), 100);
    assert!(ALLOCATIONS.load(Ordering::SeqCst) >= 1);
}
