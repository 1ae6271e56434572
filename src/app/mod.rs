//! The frame loop that ties the layers together: sim → lod → render, driven by any
//! [`FrameLoop`]. The simulation step for the next frame runs on its own Rayon pool while this
//! frame's LOD is updated and its commands are recorded and submitted.

pub mod chosen;
pub mod clock;
pub mod floating;
pub mod govern;
pub mod keep;
mod panel;
pub mod report;
pub mod scripted;
pub mod sound;
pub mod timing;
mod tweaks;

use std::time::Instant;

use crate::base::ParamError;
use crate::lod::{self, LodSettings, MaxDisplacement, OceanLod, StereoFrustum};
use crate::physics::PhysicsError;
use crate::render::readback::Readback;
use crate::render::{self, OceanRenderer, RenderError, RendererSettings};
use crate::sim::{OceanConfig, SimError, Simulation};
use crate::xr::{FrameLoop, FrameState, XrError};
pub use floating::{interaction_for, Afloat, DeckPlacement, FloatOptions};
pub use govern::{GovernorChange, GovernorOptions, GpuFault};
pub use report::RunReport;
pub use sound::{SoundOptions, SoundReport, SoundSink};
use timing::RunStats;
pub use timing::{FrameTimes, Percentiles, Timing};

/// Why a run stopped.
#[derive(Debug)]
pub enum AppError {
    /// The XR backend or the renderer failed.
    Xr(XrError),
    /// The simulation could not start.
    Sim(SimError),
    /// A parameter (pose, displacement) is out of range.
    Param(ParamError),
    /// A file could not be written.
    Io(String),
    /// The floating bodies could not be set up (too many, no room to place them).
    Physics(PhysicsError),
}

impl std::fmt::Display for AppError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AppError::Xr(e) => e.fmt(f),
            AppError::Sim(e) => e.fmt(f),
            AppError::Param(e) => e.fmt(f),
            AppError::Io(e) => f.write_str(e),
            AppError::Physics(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for AppError {}

impl From<XrError> for AppError {
    fn from(e: XrError) -> Self {
        AppError::Xr(e)
    }
}

impl From<RenderError> for AppError {
    fn from(e: RenderError) -> Self {
        AppError::Xr(XrError::Render(e))
    }
}

impl From<SimError> for AppError {
    fn from(e: SimError) -> Self {
        AppError::Sim(e)
    }
}

impl From<PhysicsError> for AppError {
    fn from(e: PhysicsError) -> Self {
        AppError::Physics(e)
    }
}

impl From<ParamError> for AppError {
    fn from(e: ParamError) -> Self {
        AppError::Param(e)
    }
}

/// What a run draws and how.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Simulation grid, cascades and waves.
    pub ocean: OceanConfig,
    /// Simulation threads.
    pub threads: usize,
    /// LOD preset and ocean size.
    pub lod: LodSettings,
    /// Renderer settings.
    pub renderer: RendererSettings,
    /// Frames whose images are handed to the capture callback (sorted or not).
    pub capture: Vec<u64>,
    /// Frames at the start left out of the timing statistics (pipeline warm-up).
    pub warmup: u64,
    /// Floating bodies and the deck; `None`: open water only (image and timing tests).
    pub floating: Option<FloatOptions>,
    /// The GPU-time governor (off by default: images and timings stay as configured).
    pub governor: GovernorOptions,
    /// The sound (off by default).
    pub audio: SoundOptions,
    /// Start with the control panel open (where the backend shows one).
    pub panel_open: bool,
    /// Comfort options to start with (the backend's turning and floor; the deck's height is
    /// the floating bodies' deck).
    pub comfort: crate::ui::panel::Comfort,
}

/// One captured frame: both eyes as tightly packed sRGB RGBA8 rows.
pub struct Capture<'a> {
    /// Frame number.
    pub frame: u64,
    /// The frame's state (poses, time).
    pub state: &'a FrameState,
    /// Per-eye width.
    pub width: u32,
    /// Per-eye height.
    pub height: u32,
    /// Left and right eye pixels.
    pub eyes: [&'a [u8]; 2],
    /// The simulation's surfaces the frame showed (tests ask them where the water was).
    pub surfaces: &'a crate::sim::Surfaces,
}

/// What a caller of [`run`] hears about while frames go by.
pub trait RunHooks {
    /// A frame listed in [`RunOptions::capture`] finished rendering.
    fn capture(&mut self, _capture: &Capture<'_>) -> Result<(), AppError> {
        Ok(())
    }

    /// A frame ended (after [`FrameLoop::end_frame`]). Tests count allocations here.
    fn frame_done(&mut self, _frame: &FrameState) {}

    /// The user's choices, to be kept (`keep::SettingsKeeper` saves them): at the run's start
    /// (what the command line chose); once they have stayed unchanged for [`KEEP_AFTER`]
    /// after a change; at once when the app pauses (the session leaves FOCUSED or the
    /// activity gets `onPause`, which come before STOPPING and `onStop`, when a Quest may kill
    /// the process); and at the end of the run however it ended (a lost runtime, a device
    /// error). A process killed at any moment loses at most the last [`KEEP_AFTER`] of
    /// changes.
    fn keep(&mut self, _chosen: &chosen::Chosen) {}

    /// The control panel drew a new image during this frame (egui ran: it allocates). Tests
    /// that count allocations tell these frames apart.
    fn panel_drawn(&mut self, _frame: &FrameState) {}
}

/// Hooks that do nothing.
pub struct NoHooks;

impl RunHooks for NoHooks {}

/// How long the user's choices stay unchanged after a change before they are kept
/// ([`RunHooks::keep`]): a slider dragged is kept once, when it stops.
pub const KEEP_AFTER: std::time::Duration = std::time::Duration::from_secs(1);

/// Runs the frame loop until the backend ends the session, telling `hooks` about captures
/// (frames in `opts.capture`, after their rendering finished) and every finished frame.
pub fn run(
    xr: &mut dyn FrameLoop,
    opts: &RunOptions,
    hooks: &mut dyn RunHooks,
) -> Result<RunReport, AppError> {
    let errors_before = xr.gpu().validation_errors();
    let mut frames = Frames::new(xr, opts, hooks)?;
    let result = loop {
        match frames.step() {
            Ok(true) => {}
            Ok(false) => break Ok(()),
            Err(e) => break Err(e),
        }
    };
    let (mut report, xr, audio) = frames.finish();
    result?;
    report.audio = audio?;
    report.validation_errors = xr.gpu().validation_errors() - errors_before;
    Ok(report)
}

/// The frame loop's state: the layers' objects for this run and what it measured so far.
struct Frames<'a> {
    xr: &'a mut dyn FrameLoop,
    opts: &'a RunOptions,
    hooks: &'a mut dyn RunHooks,
    lod: OceanLod,
    sim: Simulation,
    renderer: OceanRenderer,
    readback: Option<Readback>,
    afloat: Option<Afloat>,
    /// The GPU-time governor, when on.
    governed: Option<govern::Governed>,
    /// The sound, when on.
    ears: Option<sound::Ears>,
    /// The control panel, where the backend shows one.
    panel: Option<panel::PanelHost>,
    /// The user asked to quit (the panel): the session ends before the next frame.
    quit: bool,
    /// Whether a simulation step is in flight (started for the coming frame's world time).
    in_flight: bool,
    /// Display time to world time across the user's absences (`FrameState::paused`).
    clock: clock::WorldClock,
    /// The choices last given to [`RunHooks::keep`] (or the run's start).
    kept: Option<chosen::Chosen>,
    /// A change not kept yet, and since when it has stood.
    changed: Option<(chosen::Chosen, Instant)>,
    stats: RunStats,
}

/// What one frame measured on the way.
struct FrameCost {
    start: Instant,
    sim_wait: std::time::Duration,
    sim_step: std::time::Duration,
    lod: std::time::Duration,
}

impl<'a> Frames<'a> {
    /// The LOD, the simulation and the renderer for `opts` on `xr`'s device.
    fn new(
        xr: &'a mut dyn FrameLoop,
        opts: &'a RunOptions,
        hooks: &'a mut dyn RunHooks,
    ) -> Result<Self, AppError> {
        let lod = OceanLod::new(opts.lod);
        let sim = Simulation::new(opts.ocean.clone(), opts.threads)?;
        xr.hand_workers(sim.workers());
        let afloat = opts.floating.as_ref().map(Afloat::new).transpose()?;
        let ears = sound::Ears::new(&opts.audio)?;
        let mut comfort = opts.comfort;
        if let Some(h) = afloat.as_ref().and_then(|a| a.deck_height()) {
            comfort.deck_height_m = h;
        }
        xr.set_comfort(comfort);
        let panel = panel::PanelHost::new(&*xr, opts.panel_open, comfort);
        // The renderer draws the interaction layer the floating bodies will make.
        let mut settings = opts.renderer;
        settings.interaction = opts
            .floating
            .as_ref()
            .and_then(|f| f.interaction)
            .map(|c| c.cells);
        let mut renderer = OceanRenderer::new(xr.gpu(), &opts.ocean, &lod, xr.targets(), settings)?;
        // The part of the images the backend shows (a headset's default render scale).
        if let Err(e) = renderer.set_render_area(xr.render_rect()) {
            renderer.destroy(xr.gpu());
            return Err(e.into());
        }
        let readback = if opts.capture.is_empty() {
            None
        } else {
            match Readback::new(xr.gpu(), xr.targets().extent) {
                Ok(r) => Some(r),
                Err(e) => {
                    renderer.destroy(xr.gpu());
                    return Err(e.into());
                }
            }
        };
        let governed =
            govern::Governed::new(opts.governor, &*xr, opts.lod.preset(), &opts.renderer);
        if let Some(g) = governed.as_ref() {
            xr.report_governor(g.state());
        }
        Ok(Self {
            xr,
            opts,
            hooks,
            lod,
            sim,
            renderer,
            readback,
            afloat,
            governed,
            ears,
            panel,
            quit: false,
            in_flight: false,
            clock: clock::WorldClock::default(),
            kept: None,
            changed: None,
            stats: RunStats::new(),
        })
    }

    /// One frame: wait for it, hand over the simulation, apply tweaks, update the LOD, render
    /// and end it. False once the backend ended the session.
    fn step(&mut self) -> Result<bool, AppError> {
        let start = Instant::now();
        if self.quit {
            return Ok(false);
        }
        let Some(mut frame) = self.xr.begin_frame()? else {
            return Ok(false);
        };
        // From here on the frame's time is the world's: it stands still while the user is away.
        let display_time = frame.predicted_display_time;
        frame.predicted_display_time = self.clock.world_time(display_time, frame.paused);
        if let Some(ears) = self.ears.as_mut() {
            ears.set_paused(frame.paused, self.clock.away(display_time));
        }
        // Whitecaps follow the viewer (the eyes' midpoint).
        let viewer = (frame.views[0].position + frame.views[1].position) * 0.5;
        self.sim.set_focus(viewer.x, viewer.z);
        // The first frame has a sea even when it begins paused; after a pause the world goes
        // on from the time it stopped at.
        if !self.in_flight && (!frame.paused || self.stats.frames == 0) {
            self.sim.begin_step(frame.predicted_display_time);
            self.in_flight = true;
        }
        // The step for this frame's world time was started a frame ago.
        let wait = Instant::now();
        if self.in_flight {
            self.sim.end_step();
            self.in_flight = false;
        }
        let sim_wait = wait.elapsed();
        // The sea under the head, for a floating user's next frame (as a body feels it).
        let surface = self.sim.surfaces();
        let radius = crate::physics::wakes::SWIMMER_RADIUS;
        self.xr
            .report_water(surface.footprint_height_at(viewer.x, viewer.z, radius));
        let sim_step = self.sim.last_step_time();
        // Live changes (window keys, controllers) apply from the step started next.
        self.apply_tweaks(&frame)?;
        if !self.drive_panel(&frame)? && !self.xr.request_quit() {
            self.quit = true;
        }
        // The bodies ride the surfaces shown this frame; away, they hold still (no step, no
        // splash) and the sound is not fed.
        if !frame.paused {
            if let Some(afloat) = self.afloat.as_mut() {
                let ticks = afloat.advance(&frame, self.sim.surfaces())?;
                for (hand, _) in ticks.iter().enumerate().filter(|(_, &t)| t) {
                    self.xr.haptic_tick(hand);
                }
            }
            if let Some(ears) = self.ears.as_mut() {
                ears.hear(&frame, self.sim.surfaces(), self.afloat.as_ref())?;
            }
            self.sim
                .begin_step(frame.predicted_display_time + frame.period);
            self.in_flight = true;
        }
        let t_lod = Instant::now();
        self.update_lod(&frame)?;
        let cost = FrameCost {
            start,
            sim_wait,
            sim_step,
            lod: t_lod.elapsed(),
        };
        // A frame the runtime does not want shown is not drawn, nor are its images taken.
        let report = if frame.should_render {
            Some(self.render(&frame)?)
        } else {
            None
        };
        self.xr.end_frame(&frame)?;
        self.hooks.frame_done(&frame);
        self.stats.frames += 1;
        if let Some(r) = report {
            self.record(&frame, &r, &cost);
            self.govern(&frame, r.gpu_pass)?;
        }
        self.keep_settled_choices(frame.paused);
        if self.stats.shown_at.elapsed().as_secs_f64() >= 0.5 {
            self.stats.shown_at = Instant::now();
            self.stats.recent.summarise(
                &mut self.stats.text,
                self.lod.settings().preset(),
                &self.sim.config().waves,
                self.governed.as_ref().map(|g| g.level()),
            );
            self.xr.show_stats(&self.stats.text);
        }
        Ok(true)
    }

    /// What the user has chosen now: the waves, the preset (the user's, not the governor's
    /// step), the sky and the comfort options; a change the panel has not applied yet is the
    /// user's last word too.
    fn chosen(&self) -> chosen::Chosen {
        let (waves, sun) = self.panel.as_ref().map_or((None, None), |p| p.pending());
        chosen::Chosen {
            waves: waves.map_or(self.sim.config().waves, |s| *s.waves()),
            preset: self
                .governed
                .as_ref()
                .map_or(self.lod.settings().preset(), |g| g.preset),
            sun: sun.unwrap_or(self.renderer.settings().sun),
            comfort: self
                .panel
                .as_ref()
                .map_or(self.opts.comfort, |p| p.comfort()),
        }
    }

    /// Gives the hooks the user's choices once a change has stood for [`KEEP_AFTER`], or at
    /// once when the app pauses (`paused`: the session left FOCUSED, the activity paused): a
    /// Quest may stop and kill a paused app, and nothing changes while paused anyway.
    fn keep_settled_choices(&mut self, paused: bool) {
        let now = self.chosen();
        let Some(kept) = self.kept else {
            // The run's start: what the command line chose is this run's first word, kept
            // before any frame can be the last.
            self.hooks.keep(&now);
            self.kept = Some(now);
            return;
        };
        if now == kept {
            self.changed = None;
            return;
        }
        let settled = match self.changed {
            Some((pending, since)) if pending == now => since.elapsed() >= KEEP_AFTER,
            _ => {
                self.changed = Some((now, Instant::now()));
                false
            }
        };
        if settled || paused {
            self.hooks.keep(&now);
            self.kept = Some(now);
            self.changed = None;
        }
    }

    /// The LOD for both eyes of `frame`, padded by the shown surfaces' displacement.
    fn update_lod(&mut self, frame: &FrameState) -> Result<(), AppError> {
        let stereo = StereoFrustum::new(frame.views[0], frame.views[1])?;
        let surfaces = self.sim.surfaces();
        let stats = self.lod.update(&lod::FrameInput {
            viewer: stereo.centre(),
            culling: Some(&stereo),
            max_displacement: MaxDisplacement::new(surfaces.max_displacement())?,
        })?;
        if frame.should_render && frame.index >= self.opts.warmup {
            self.stats.triangles += u64::from(stats.triangles);
            self.stats.triangle_frames += 1;
        }
        Ok(())
    }

    /// Renders `frame` into the backend's next image and hands captured frames to the hooks.
    fn render(&mut self, frame: &FrameState) -> Result<render::FrameReport, AppError> {
        let image = self.xr.acquire_image()?;
        let report = self.renderer.render(
            self.xr.gpu(),
            &render::FrameInput {
                image: image.colour,
                depth: image.depth,
                eyes: &frame.views,
                lod: &self.lod,
                surfaces: self.sim.surfaces(),
                solids: self.afloat.as_ref().map_or(&[], |a| a.solids()),
                interaction: self
                    .afloat
                    .as_ref()
                    .and_then(|a| a.world())
                    .and_then(|w| w.interaction()),
                vignette: frame.vignette,
            },
        )?;
        self.xr.report_cpu_wait(report.wait);
        self.xr.release_image()?;
        if let Some(rb) = self.readback.as_mut() {
            if self.opts.capture.contains(&frame.index) {
                let extent = self.xr.targets().extent;
                let image_handle = self.xr.targets().images[image.colour as usize];
                let eyes = rb.read(self.xr.gpu(), image_handle)?;
                self.hooks.capture(&Capture {
                    frame: frame.index,
                    state: frame,
                    width: extent.width,
                    height: extent.height,
                    eyes,
                    surfaces: self.sim.surfaces(),
                })?;
            }
        }
        Ok(report)
    }

    /// Files a rendered frame's timings (after the warm-up) and its GPU time.
    fn record(&mut self, frame: &FrameState, r: &render::FrameReport, cost: &FrameCost) {
        if let Some(g) = r.gpu_pass {
            self.xr.report_gpu_time(g);
        }
        let s = &mut self.stats;
        s.max_draws = s.max_draws.max(r.draws);
        let total = cost.start.elapsed();
        if frame.index >= self.opts.warmup {
            s.times.push(Timing::FrameTotal, total);
            s.times.push(Timing::SimStep, cost.sim_step);
            s.times.push(Timing::SimWait, cost.sim_wait);
            s.times.push(Timing::Lod, cost.lod);
            s.times.push(Timing::Record, r.record);
            s.times.push(Timing::Submit, r.submit);
            if let Some(g) = r.gpu_pass {
                s.times.push(Timing::GpuPass, g);
            }
        }
        s.recent.push(total, cost.sim_step, r.gpu_pass, r.draws);
    }

    /// Waits for the GPU, frees the renderer's objects and returns the report (validation
    /// errors not yet counted), the backend and what the sound did (its file finished).
    #[allow(clippy::type_complexity)]
    fn finish(
        mut self,
    ) -> (
        RunReport,
        &'a mut dyn FrameLoop,
        Result<Option<SoundReport>, AppError>,
    ) {
        let chosen = self.chosen();
        // The last chance to keep what the user chose, whether the run ended well or not.
        self.hooks.keep(&chosen);
        let gpu = self.xr.gpu();
        gpu.wait_idle();
        let attachment_bytes = self.renderer.attachment_bytes();
        let paths = self.renderer.path_counts(gpu).unwrap_or_else(|e| {
            log::warn!("the pass's counts could not be read: {e}");
            None
        });
        self.renderer.destroy(gpu);
        if let Some(r) = self.readback.as_mut() {
            r.destroy(gpu);
        }
        let report = RunReport {
            frames: self.stats.frames,
            times: self.stats.times,
            max_draws: self.stats.max_draws,
            mean_triangles: self.stats.triangles as f64 / self.stats.triangle_frames.max(1) as f64,
            attachment_bytes,
            validation_errors: 0,
            device: gpu.device_name.clone(),
            governor: self.governed.map_or(Vec::new(), |g| g.history),
            paths,
            audio: None,
            chosen,
        };
        let audio = self.ears.as_mut().map(|e| e.finish()).transpose();
        (report, self.xr, audio)
    }

    /// Feeds the governor this frame's GPU time and applies a new level. The LOD step
    /// rebuilds the renderer through [`Frames::switch_preset`], which waits for the GPU: a
    /// rare step, not the steady state.
    fn govern(
        &mut self,
        frame: &FrameState,
        gpu: Option<std::time::Duration>,
    ) -> Result<(), AppError> {
        let Some(g) = self.governed.as_mut() else {
            return Ok(());
        };
        let Some(level) = g.observe(frame, gpu) else {
            return Ok(());
        };
        let preset = g.preset_for(level);
        if preset != self.lod.settings().preset() {
            // Re-applies the level after the rebuild.
            return self.switch_preset(preset);
        }
        let g = self.governed.as_ref().expect("checked above");
        g.apply(level, &mut self.renderer, &mut *self.xr)?;
        Ok(())
    }
}
