//! Thread priorities on the headset. The simulation workers run above normal priority so the
//! next frame's step is not preempted; the thread that calls `xrWaitFrame` and submits must not
//! sit below them. Where the runtime offers `XR_KHR_android_thread_settings` it is told which
//! thread is which (this one RENDERER_MAIN, the workers APPLICATION_WORKER) and schedules them
//! itself; elsewhere on Android this thread is raised to the workers' priority. Desktops leave
//! priorities alone.

use openxr as xr;

use crate::sim::workers;

/// Which threads the runtime knows about.
#[derive(Debug, Default)]
pub(super) struct ThreadSettings {
    /// Whether the runtime takes thread hints.
    hints: bool,
    /// This run's simulation workers (none until the app hands them over).
    workers: Option<workers::WorkerThreads>,
    /// Of those, the ones already handed to the runtime.
    workers_done: usize,
}

impl ThreadSettings {
    /// Hands the calling (frame-loop) thread to the runtime as RENDERER_MAIN, or raises it.
    pub fn start(instance: &xr::Instance, session: &xr::Session<xr::Vulkan>) -> Self {
        let mut this = Self::default();
        if !cfg!(target_os = "android") {
            return this;
        }
        this.hints = has_hints(instance);
        let tid = workers::current_thread_id();
        match (this.hints, tid) {
            (true, Some(tid)) => {
                set(instance, session, tid, Role::RendererMain);
            }
            _ => {
                let raised = workers::raise_thread_priority(workers::WORKER_NICE);
                log::info!(
                    "no XR_KHR_android_thread_settings: render thread at nice {}: {}",
                    workers::WORKER_NICE,
                    if raised { "yes" } else { "not permitted" }
                );
            }
        }
        this
    }

    /// The run's simulation workers, handed to the runtime as they start ([`Self::poll`]).
    pub fn hand_workers(&mut self, workers: &workers::WorkerThreads) {
        self.workers = Some(workers.clone());
        self.workers_done = 0;
    }

    /// Hands simulation workers started since the last call to the runtime (no allocation).
    pub fn poll(&mut self, instance: &xr::Instance, session: &xr::Session<xr::Vulkan>) {
        let Some(w) = self.workers.as_ref().filter(|_| self.hints) else {
            return;
        };
        for tid in w.ids(self.workers_done) {
            set(instance, session, tid, Role::Worker);
            self.workers_done += 1;
        }
    }
}

/// The thread types we use.
#[derive(Clone, Copy, Debug)]
enum Role {
    /// The frame loop: time-critical graphics work.
    RendererMain,
    /// A simulation worker: background CPU work.
    Worker,
}

#[cfg(target_os = "android")]
fn has_hints(instance: &xr::Instance) -> bool {
    instance.exts().khr_android_thread_settings.is_some()
}

#[cfg(not(target_os = "android"))]
fn has_hints(_: &xr::Instance) -> bool {
    false
}

#[cfg(target_os = "android")]
fn set(instance: &xr::Instance, session: &xr::Session<xr::Vulkan>, tid: u32, role: Role) {
    let Some(ext) = instance.exts().khr_android_thread_settings.as_ref() else {
        return;
    };
    let ty = match role {
        Role::RendererMain => xr::sys::AndroidThreadTypeKHR::RENDERER_MAIN,
        Role::Worker => xr::sys::AndroidThreadTypeKHR::APPLICATION_WORKER,
    };
    // SAFETY: a valid session and a thread id of this process (gettid).
    let r = unsafe { (ext.set_android_application_thread)(session.as_raw(), ty, tid) };
    match super::error::check(r) {
        Ok(()) => log::info!("thread {tid}: {role:?} (XR_KHR_android_thread_settings)"),
        Err(e) => log::warn!("xrSetAndroidApplicationThreadKHR({tid}, {role:?}): {e:?} ({e})"),
    }
}

#[cfg(not(target_os = "android"))]
fn set(_: &xr::Instance, _: &xr::Session<xr::Vulkan>, _: u32, _: Role) {}
