//! How many simulation workers a device gets, their priority, and their thread ids (for the
//! runtime's thread settings on Android).
//!
//! Phone-class SoCs (the Quest's Snapdragon XR2) mix fast and slow cores; a Rayon pool as wide
//! as every core spends its fork-joins waiting for the slow ones. The workers go on the
//! performance cores only, one of which is left to the render thread (the frame loop: LOD,
//! recording, submission, the OpenXR calls). The cores' speeds come from Linux cpufreq
//! (`/sys/devices/system/cpu/cpuN/cpufreq/cpuinfo_max_freq`), which Android exposes too.

use std::path::Path;
use std::sync::atomic::{AtomicU32, AtomicUsize, Ordering};
use std::sync::Arc;

/// A core counts as a performance core when its maximum clock is at least this share of the
/// fastest core's (XR2 Gen 1: 2.84/2.42 GHz prime and gold cores, 1.8 GHz silver ones).
pub const PERFORMANCE_SHARE: f64 = 0.8;

/// Maximum clock (kHz) of each core that reports one, in core order.
pub fn core_max_khz(sys_cpu: &Path) -> Vec<u64> {
    let mut out = Vec::new();
    for i in 0..1024 {
        let dir = sys_cpu.join(format!("cpu{i}"));
        if !dir.exists() {
            break;
        }
        let file = dir.join("cpufreq/cpuinfo_max_freq");
        if let Some(khz) = std::fs::read_to_string(file)
            .ok()
            .and_then(|s| s.trim().parse::<u64>().ok())
        {
            out.push(khz);
        }
    }
    out
}

/// Performance cores among `max_khz` (see [`PERFORMANCE_SHARE`]); 0 for an empty list.
pub fn performance_cores(max_khz: &[u64]) -> usize {
    let Some(&fastest) = max_khz.iter().max() else {
        return 0;
    };
    let floor = fastest as f64 * PERFORMANCE_SHARE;
    max_khz.iter().filter(|&&f| f as f64 >= floor).count()
}

/// Simulation workers for a device with these core clocks: the performance cores but one (the
/// render thread's), between 1 and `cap`. Without cpufreq data, `fallback` (e.g. the available
/// parallelism) minus one, within the same bounds.
pub fn recommended_workers(max_khz: &[u64], fallback: usize, cap: usize) -> usize {
    let cores = match performance_cores(max_khz) {
        0 => fallback,
        n => n,
    };
    cores.saturating_sub(1).clamp(1, cap.max(1))
}

/// Nice value the workers ask for: slightly above normal, so the simulation step for the next
/// frame is not preempted by background work (Android's `THREAD_PRIORITY_DISPLAY` is −4).
pub const WORKER_NICE: i32 = -4;

/// Raises the calling thread's priority to `nice` (Linux and Android: `setpriority` with
/// `who = 0` applies to the calling thread). Returns whether it was allowed; desktop users
/// without `CAP_SYS_NICE` get `false` and keep the normal priority. The simulation's workers
/// call it on Android only.
pub fn raise_thread_priority(nice: i32) -> bool {
    #[cfg(any(target_os = "linux", target_os = "android"))]
    {
        use std::ffi::c_int;
        extern "C" {
            fn setpriority(which: c_int, who: c_int, prio: c_int) -> c_int;
        }
        const PRIO_PROCESS: c_int = 0;
        // SAFETY: a plain system call on the calling thread; no memory is passed.
        unsafe { setpriority(PRIO_PROCESS, 0, nice) == 0 }
    }
    #[cfg(not(any(target_os = "linux", target_os = "android")))]
    {
        let _ = nice;
        false
    }
}

/// Most simulation worker threads a [`WorkerThreads`] keeps.
pub const MAX_REGISTERED_WORKERS: usize = 16;

/// The kernel thread ids of one simulation's workers, in start order: what the XR backend
/// hands to the runtime's thread settings. One per [`crate::sim::Simulation`] (not
/// process-wide: on Android a second `android_main` in the same process starts a new
/// simulation, whose workers must be handed over, and the first one's dead threads not).
/// Cloning shares it. No allocation after creation.
#[derive(Clone, Debug, Default)]
pub struct WorkerThreads(Arc<Registry>);

#[derive(Debug, Default)]
struct Registry {
    /// Thread ids (0 = empty slot).
    tids: [AtomicU32; MAX_REGISTERED_WORKERS],
    count: AtomicUsize,
}

impl WorkerThreads {
    /// Records the calling thread as one of these workers (the pool's start handler calls
    /// this). Ids beyond [`MAX_REGISTERED_WORKERS`] are not kept.
    pub fn register_this_thread(&self) {
        let Some(tid) = current_thread_id() else {
            return;
        };
        let slot = self.0.count.fetch_add(1, Ordering::Relaxed);
        if let Some(s) = self.0.tids.get(slot) {
            s.store(tid, Ordering::Release);
        }
    }

    /// The workers' thread ids recorded so far, from the `from`-th on (a caller keeps how many
    /// it has handled). No allocation.
    pub fn ids(&self, from: usize) -> impl Iterator<Item = u32> + '_ {
        let n = self
            .0
            .count
            .load(Ordering::Relaxed)
            .min(MAX_REGISTERED_WORKERS);
        self.0.tids[from.min(n)..n]
            .iter()
            .map(|t| t.load(Ordering::Acquire))
            .take_while(|&t| t != 0)
    }
}

/// The calling thread's kernel thread id (`gettid`), where the platform has one (Linux,
/// Android); what `XR_KHR_android_thread_settings` takes.
pub fn current_thread_id() -> Option<u32> {
    #[cfg(any(target_os = "linux", target_os = "android"))]
    {
        extern "C" {
            fn gettid() -> i32;
        }
        // SAFETY: a plain system call returning the caller's id; no memory is passed.
        let tid = unsafe { gettid() };
        u32::try_from(tid).ok().filter(|&t| t != 0)
    }
    #[cfg(not(any(target_os = "linux", target_os = "android")))]
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn worker_threads_are_recorded_by_kernel_id_per_registry() {
        let first = WorkerThreads::default();
        let w = first.clone();
        let tid = std::thread::spawn(move || {
            w.register_this_thread();
            current_thread_id()
        })
        .join()
        .unwrap();
        // A second simulation's registry starts empty: the first one's threads are not its.
        let second = WorkerThreads::default();
        if cfg!(any(target_os = "linux", target_os = "android")) {
            let tid = tid.expect("gettid");
            assert_ne!(Some(tid), current_thread_id(), "another thread's id");
            assert_eq!(first.ids(0).collect::<Vec<_>>(), [tid]);
            assert_eq!(first.ids(1).count(), 0);
            assert_eq!(second.ids(0).count(), 0);
        }
    }

    #[test]
    fn xr2_clusters_give_two_or_three_workers() {
        // XR2 Gen 1 (Quest 2, Snapdragon 865 class): 1 prime + 3 gold + 4 silver.
        let gen1 = [
            1_804_800, 1_804_800, 1_804_800, 1_804_800, 2_419_200, 2_419_200, 2_419_200, 2_841_600,
        ];
        assert_eq!(performance_cores(&gen1), 4);
        assert_eq!(recommended_workers(&gen1, 8, 3), 3);
        // A 2 fast + 4 slower cluster layout with close clocks: all count, capped at 3.
        let gen2 = [
            2_054_400, 2_054_400, 2_054_400, 2_054_400, 2_361_600, 2_361_600,
        ];
        assert_eq!(performance_cores(&gen2), 6);
        assert_eq!(recommended_workers(&gen2, 6, 3), 3);
        // With only the two fast cores available to apps: one worker, one render thread.
        assert_eq!(
            recommended_workers(&[2_361_600, 2_361_600, 1_200_000], 3, 3),
            1
        );
    }

    #[test]
    fn desktop_and_missing_data() {
        // 16 equal cores: capped.
        assert_eq!(recommended_workers(&[4_500_000; 16], 16, 3), 3);
        // No cpufreq (containers, CI): the fallback count minus the render thread.
        assert_eq!(recommended_workers(&[], 2, 3), 1);
        assert_eq!(recommended_workers(&[], 1, 3), 1);
        assert_eq!(performance_cores(&[]), 0);
    }

    #[test]
    fn priority_change_is_reported_not_fatal() {
        // Lowering one's own priority is always allowed; raising it may not be.
        std::thread::spawn(|| assert!(raise_thread_priority(5)))
            .join()
            .unwrap();
        let _ = std::thread::spawn(|| raise_thread_priority(WORKER_NICE))
            .join()
            .unwrap();
    }

    #[test]
    fn reads_cpufreq_from_a_sysfs_tree() {
        let dir = std::env::temp_dir().join(format!("vr-ocean-cpufreq-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        for (i, khz) in [1_800_000u64, 2_400_000, 2_800_000].iter().enumerate() {
            let f = dir.join(format!("cpu{i}/cpufreq"));
            std::fs::create_dir_all(&f).unwrap();
            std::fs::write(f.join("cpuinfo_max_freq"), format!("{khz}\n")).unwrap();
        }
        // A core without cpufreq (offline) is skipped, the list ends at the first gap.
        std::fs::create_dir_all(dir.join("cpu3")).unwrap();
        std::fs::create_dir_all(dir.join("cpu5/cpufreq")).unwrap();
        assert_eq!(core_max_khz(&dir), [1_800_000, 2_400_000, 2_800_000]);
        assert_eq!(core_max_khz(&dir.join("missing")), Vec::<u64>::new());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
