//! One cascade's private state and its stages 2-6 (thesis Table 1): the packed spectrum, the FFT
//! work buffers its derivative mode needs ([`Derivatives`]) and its persistent foam.
//! [`crate::sim::SimCore`] owns one per cascade and shares the FFT plan and scratch among them.

use std::time::{Duration, Instant};

use crate::sim::evolve::{self, LoopPhase, OutsideSupport};
use crate::sim::fft::{Fft2d, Output};
use crate::sim::grid::{AlignedBuf, GridSize, SplitField};
use crate::sim::params::{Derivatives, WaveParams};
use crate::sim::spectrum::{CascadeSpec, PackedSpectrum};
use crate::sim::surface::{self, CascadeSurface, SurfaceParams, Transformed};
use crate::sim::tuning::Tuning;

/// Wall time of each stage of the last step, summed over cascades (thesis Table 1).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Stage 2: time evolution and packing of the derivative spectra.
    pub evolve: Duration,
    /// Stages 3-4: the inverse 2D FFTs (four per cascade, two with
    /// [`Derivatives::Finite`](crate::sim::Derivatives::Finite)).
    pub fft: Duration,
    /// Stages 5-6+: displacement, normals, Jacobian, foam, packing and mips.
    pub surface: Duration,
    /// Whitecaps of the whole surface ([`crate::sim::whitecaps`]).
    pub whitecaps: Duration,
}

impl StageTimes {
    /// Sum of all stages.
    pub fn total(&self) -> Duration {
        self.evolve + self.fft + self.surface + self.whitecaps
    }
}

/// One cascade's FFT work buffers, as many as its derivative mode transforms.
enum Fields {
    Spectral(Box<[SplitField; 4]>),
    Finite(Box<[SplitField; 2]>),
}

impl Fields {
    fn new(mode: Derivatives, grid: GridSize) -> Fields {
        match mode {
            Derivatives::Spectral => {
                Fields::Spectral(Box::new(std::array::from_fn(|_| SplitField::zeros(grid))))
            }
            Derivatives::Finite => {
                Fields::Finite(Box::new(std::array::from_fn(|_| SplitField::zeros(grid))))
            }
        }
    }

    /// Every field, for the FFT, with what it makes of each: Z, the finite mode's second
    /// field, is real and comes as row pairs (about 0.7 of a transform).
    fn all(&mut self) -> (&mut [SplitField], &'static [Output]) {
        match self {
            Fields::Spectral(f) => (&mut f[..], &[Output::Complex; 4]),
            Fields::Finite(f) => (&mut f[..], &[Output::Complex, Output::RealRowPairs]),
        }
    }

    /// The transformed fields for the surface stage.
    fn transformed(&self) -> Transformed<'_> {
        match self {
            Fields::Spectral(f) => Transformed::Spectral(f),
            Fields::Finite(f) => Transformed::Finite(f),
        }
    }
}

/// What every cascade's stages 2-6 share in one step.
#[derive(Clone, Copy)]
pub(crate) struct StepAt {
    /// Simulation time (s).
    pub t: f64,
    /// Its loop phase (eq. 24).
    pub phase: LoopPhase,
    /// Choppiness, roughness, foam and the time since the last step.
    pub params: SurfaceParams,
}

/// One cascade's private state: its packed spectrum, FFT work buffers, persistent foam and
/// the buffers that change its sea state smoothly ([`crate::sim::retune`]).
pub(crate) struct CascadeSim {
    /// The grid, patch and band it runs.
    pub spec: CascadeSpec,
    /// The spectrum the evolution reads (during a sea-state change, the blend).
    pub spectrum: PackedSpectrum,
    fields: Fields,
    /// Persistent foam per texel.
    pub(crate) foam: AlignedBuf,
    /// Draws, powers and spare buffers for sea-state changes.
    pub(crate) tuning: Tuning,
    /// The patch whose waves it shows ([`CascadeSurface::fade_patch`]).
    pub(crate) fade_patch: f32,
}

impl CascadeSim {
    /// Runs stage 1 for `spec` and allocates the buffers of derivative mode `mode`; with
    /// `changes_patch`, also those for moving to another octave of patch.
    pub fn new(
        spec: CascadeSpec,
        waves: &crate::sim::WaveParams,
        mode: Derivatives,
        changes_patch: bool,
    ) -> CascadeSim {
        let tuning = Tuning::new(&spec, waves, changes_patch);
        CascadeSim {
            spectrum: PackedSpectrum::from_powers(
                &tuning.lattice,
                tuning.powers(),
                tuning.moments(),
                tuning.support().clone(),
            ),
            fields: Fields::new(mode, spec.grid),
            foam: AlignedBuf::zeros(spec.grid.texels()),
            tuning,
            fade_patch: spec.patch,
            spec,
        }
    }

    /// Stages 2-6 at `at` into `out`, adding their wall times to `times`. `scratch` holds 1 or
    /// more FFT scratch fields (see `Fft2d::inverse_batch`).
    pub fn step(
        &mut self,
        fft: &Fft2d,
        scratch: &mut [SplitField],
        at: StepAt,
        out: &mut CascadeSurface,
        times: &mut StageTimes,
    ) {
        let StepAt { t, phase, params } = at;
        out.patch = self.spec.patch;
        out.fade_patch = self.fade_patch;
        let t0 = Instant::now();
        // The FFT neither reads nor needs the rows outside the spectrum's support: the
        // evolution writes no zeros there.
        let (spectrum, patch) = (&self.spectrum, self.spec.patch);
        let outside = OutsideSupport::Unwritten;
        match &mut self.fields {
            Fields::Spectral(f) => evolve::evolve(spectrum, patch, phase, f, outside),
            Fields::Finite(f) => evolve::evolve_finite(spectrum, patch, phase, f, outside),
        }
        let t1 = Instant::now();
        let (fields, outputs) = self.fields.all();
        // The finite mode's two transforms differ in cost (Z, as row pairs, is about 0.7 of
        // h + i·X): side by side one thread waits for the other, so from N = 256 they go one
        // after another, each split among all threads (2 threads, N = 256: FFT stage
        // 0.200 -> 0.166 ms sse2, 0.116-0.122 -> 0.105 avx2; at N = 128 the extra fork-joins
        // cost more, 0.025-0.027 -> 0.030 avx2).
        let groups = if outputs.contains(&Output::RealRowPairs) && self.spec.grid.n() > 128 {
            1
        } else {
            scratch.len().min(fields.len())
        };
        let support = &self.spectrum.support;
        fft.inverse_batch_support_as(fields, outputs, &mut scratch[..groups], support);
        let t2 = Instant::now();
        surface::finalize(self.fields.transformed(), &mut self.foam, params, t, out);
        let t3 = Instant::now();
        times.evolve += t1 - t0;
        times.fft += t2 - t1;
        times.surface += t3 - t2;
    }
}

impl CascadeSim {
    /// Changes this cascade to `spec` and `waves` at once (a change that cannot blend): stage 1
    /// in full into the buffers held, the persistent foam kept.
    pub fn retune_at_once(&mut self, spec: CascadeSpec, waves: &WaveParams) {
        self.tuning.rebuild(&spec, waves);
        self.spectrum
            .harmonic
            .copy_from_slice(&self.tuning.lattice.harmonic);
        self.spec = spec;
        self.show_current();
    }

    /// Packs the blend at weight `w` into the spectrum the evolution reads.
    pub(crate) fn show_blend(&mut self, w: f32) {
        self.fade_patch = self.tuning.show_blend(w, &mut self.spectrum);
    }

    /// Packs the current state's powers into the spectrum the evolution reads.
    pub(crate) fn show_current(&mut self) {
        self.fade_patch = self.tuning.show_current(&mut self.spectrum);
    }

    /// Moves this cascade to the grid of `spec` (see [`Tuning::switch_grid`]).
    pub(crate) fn switch_grid(&mut self, spec: CascadeSpec) {
        if self.tuning.switch_grid(
            &self.spec,
            &spec,
            &mut self.foam,
            &mut self.spectrum.harmonic,
        ) {
            self.spec = spec;
        }
    }
}
