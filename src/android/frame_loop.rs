//! [`ActivityFrameLoop`]: the OpenXR backend driven from android-activity's event loop.

use android_activity::{AndroidApp, MainEvent, PollEvent};

use super::activity::{ActivityEvent, ActivityState};
use crate::render::{GpuContext, TargetImages};
use crate::ui::panel::{Comfort, Panel};
use crate::xr::gpu_governor::{GovernorCaps, GovernorState};
use crate::xr::openxr::{FramePoll, OpenXr};
use crate::xr::{Acquired, FrameLoop, FrameState, XrError};

/// A [`FrameLoop`] over [`OpenXr`] that polls the activity's events before every frame:
/// without waiting while the session runs, waiting up to [`ActivityState::poll_timeout`]
/// while it does not (instead of the desktop's sleep). Destroy asks the session to end
/// ([`OpenXr::request_exit`]); the frame loop then ends once the runtime reaches EXITING.
pub struct ActivityFrameLoop {
    // Dropped before `app`: the backend uses the VM and Activity `app` keeps alive.
    xr: OpenXr,
    app: AndroidApp,
    activity: ActivityState,
}

impl ActivityFrameLoop {
    /// Wraps the backend; `app` is the handle `android_main` was given.
    pub fn new(xr: OpenXr, app: AndroidApp) -> Self {
        Self {
            xr,
            app,
            activity: ActivityState::new(),
        }
    }

    /// The backend, e.g. for its summary.
    pub fn xr(&self) -> &OpenXr {
        &self.xr
    }

    /// Polls android-activity once, waiting at most as long as the activity's state allows.
    fn pump(&mut self) {
        let timeout = self.activity.poll_timeout(self.xr.session_running());
        let activity = &mut self.activity;
        self.app.poll_events(Some(timeout), |event| {
            if let PollEvent::Main(main) = event {
                if let Some(e) = activity_event(&main) {
                    log::info!("activity: {e:?}");
                    activity.on_event(e);
                }
            }
        });
    }
}

/// The lifecycle events the frame loop cares about; the rest are ignored.
fn activity_event(event: &MainEvent<'_>) -> Option<ActivityEvent> {
    Some(match event {
        MainEvent::Start => ActivityEvent::Start,
        MainEvent::Resume { .. } => ActivityEvent::Resume,
        MainEvent::Pause => ActivityEvent::Pause,
        MainEvent::Stop => ActivityEvent::Stop,
        MainEvent::Destroy => ActivityEvent::Destroy,
        MainEvent::InitWindow { .. } => ActivityEvent::WindowCreated,
        MainEvent::TerminateWindow { .. } => ActivityEvent::WindowDestroyed,
        _ => return None,
    })
}

impl FrameLoop for ActivityFrameLoop {
    fn gpu(&self) -> &GpuContext {
        self.xr.gpu()
    }

    fn targets(&self) -> TargetImages<'_> {
        self.xr.targets()
    }

    fn begin_frame(&mut self) -> Result<Option<FrameState>, XrError> {
        loop {
            self.pump();
            if self.activity.take_exit_request() {
                log::info!("activity destroyed: ending the OpenXR session");
                self.xr.request_exit();
            }
            match self.xr.poll_frame()? {
                FramePoll::Frame(mut frame) => {
                    // Out of the foreground (`onPause`), the user is away too.
                    frame.paused |= !self.activity.resumed();
                    return Ok(Some(frame));
                }
                FramePoll::Done => return Ok(None),
                // The next pump waits for activity events instead of sleeping.
                FramePoll::Idle => {}
            }
        }
    }

    fn acquire_image(&mut self) -> Result<Acquired, XrError> {
        self.xr.acquire_image()
    }

    fn release_image(&mut self) -> Result<(), XrError> {
        self.xr.release_image()
    }

    fn end_frame(&mut self, frame: &FrameState) -> Result<(), XrError> {
        self.xr.end_frame(frame)
    }

    fn show_stats(&mut self, text: &str) {
        self.xr.show_stats(text);
    }

    fn report_gpu_time(&mut self, gpu: std::time::Duration) {
        self.xr.report_gpu_time(gpu);
    }

    fn report_cpu_wait(&mut self, waited: std::time::Duration) {
        self.xr.report_cpu_wait(waited);
    }

    fn hand_workers(&mut self, workers: &crate::sim::workers::WorkerThreads) {
        self.xr.hand_workers(workers);
    }

    fn governor_caps(&self) -> GovernorCaps {
        self.xr.governor_caps()
    }

    fn set_foveation_boost(&mut self, boost: bool) -> bool {
        self.xr.set_foveation_boost(boost)
    }

    fn set_render_rect(&mut self, rect: ash::vk::Rect2D) -> bool {
        self.xr.set_render_rect(rect)
    }

    fn render_rect(&self) -> ash::vk::Rect2D {
        self.xr.render_rect()
    }

    fn report_governor(&mut self, state: GovernorState) {
        self.xr.report_governor(state);
    }

    fn haptic_tick(&mut self, hand: usize) {
        self.xr.haptic_tick(hand);
    }

    fn panel_pixels_per_point(&self) -> Option<f32> {
        self.xr.panel_pixels_per_point()
    }

    fn panel_draws_cursor(&self) -> bool {
        self.xr.panel_draws_cursor()
    }

    fn show_panel(&mut self, panel: &mut Panel) -> Result<(), XrError> {
        self.xr.show_panel(panel)
    }

    fn panel_haptic(&mut self) {
        self.xr.panel_haptic();
    }

    fn set_comfort(&mut self, comfort: Comfort) {
        self.xr.set_comfort(comfort);
    }

    fn request_quit(&mut self) -> bool {
        self.xr.request_quit()
    }
}
