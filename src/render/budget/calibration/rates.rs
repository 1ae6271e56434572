//! A device's costs, fitted to its calibration passes ([`DeviceRates::fit`]), and what a
//! fragment of a small triangle costs it ([`DeviceRates::fragment_at_area`]).

use super::grid::grid_lanes_per_fragment;
use super::{KernelKind, KernelMeasurement};
use crate::render::budget::spirv::InstructionCounts;

/// A device's costs, fitted from its calibration passes (nanoseconds per unit).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DeviceRates {
    /// The device.
    pub device: String,
    /// The empty pass (ms): clearing, resolving and storing the targets.
    pub pass_ms: f64,
    /// Per fragment lane: rasterization, interpolation, depth test and the samples written.
    pub fragment_ns: f64,
    /// Per FP32 ALU operation and lane.
    pub alu_ns: f64,
    /// Per relaxed-precision ALU operation and lane.
    pub relaxed_ns: f64,
    /// Per special-function operation and lane.
    pub special_ns: f64,
    /// Per trilinear sample (implicit derivatives) and lane.
    pub sample_ns: f64,
    /// Per sample at an explicit level of detail and lane.
    pub lod_sample_ns: f64,
    /// Per sample with explicit gradients and lane.
    pub grad_sample_ns: f64,
    /// Per level-of-detail query and lane.
    pub lod_query_ns: f64,
    /// Per anisotropic tap beyond a sample's first (`None`: not measured, the device in use
    /// draws without anisotropic filtering).
    pub tap_ns: Option<f64>,
    /// κ: the share of the smaller of ALU and texture time that the other does not hide (0:
    /// fully overlapped, a GPU's latency hiding at best; 1: one after the other; above 1: each
    /// slows the other, as on a CPU whose registers and caches they share), as measured, kept
    /// at or above 0.
    pub overlap: f64,
    /// κ as the mixed kernel measured it.
    pub overlap_measured: f64,
    /// σ: the share of a branch's work that lanes which do not take it still pay (0: a branch
    /// no lane of a wave takes is skipped; 1: both sides of every branch run for every
    /// lane), from the kernel whose samples no lane's branch reaches, kept in [0, 1].
    pub branch_share: f64,
    /// Per fragment of small triangles, by their area (from the grids; largest first).
    pub areas: Vec<AreaCost>,
    /// The side (pixels) of the squares the device shades a triangle's fragments in, of 2
    /// (quads: the least, derivatives need them), 4 and 8: the one whose lanes explain the
    /// grids' measured waste best.
    pub block_px: u32,
    /// Per grid (as `areas`): the waste `block_px` predicts over what was measured.
    pub block_fit: Vec<f64>,
    /// The costs whose passes measured less than nothing (noise, or work the device's
    /// compiler removed), kept at 0: named here so that a report says so.
    pub at_zero: Vec<String>,
}

/// What a fragment of a triangle of a given size costs the device (from one grid's passes).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AreaCost {
    /// The triangles' area (pixels).
    pub area_px: f64,
    /// The grid's cell (pixels a side).
    pub cell_px: u32,
    /// Per fragment: set-up, rasterization, tests and writes (ns), the base shader's.
    pub fragment_ns: f64,
    /// Lanes shaded per fragment, relative to a full-screen pass: the arithmetic shader's time
    /// per fragment beyond the base's, over the same on the full-screen passes.
    pub waste: f64,
}

/// Why the calibration could not be fitted.
#[derive(Clone, Debug, PartialEq)]
pub struct FitError(pub String);

impl std::fmt::Display for FitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "the calibration cannot be fitted: {}", self.0)
    }
}

impl std::error::Error for FitError {}

impl DeviceRates {
    /// Fits the costs to `passes` (one of each full-screen kind, the empty pass, and grids).
    pub fn fit(device: &str, passes: &[KernelMeasurement]) -> Result<Self, FitError> {
        let one = |kind: KernelKind| {
            passes
                .iter()
                .find(|p| p.kind == kind)
                .ok_or_else(|| FitError(format!("no {kind:?} pass")))
        };
        let empty = one(KernelKind::Empty)?;
        // Per fragment lane, beyond the empty pass (ns).
        let per_lane = |p: &KernelMeasurement| {
            if p.fragments > 0.0 {
                Ok((p.ms - empty.ms) * 1e6 / p.fragments)
            } else {
                Err(FitError(format!("{}: no fragments", p.name)))
            }
        };
        let base = one(KernelKind::Base)?;
        let alu = one(KernelKind::Alu)?;
        let relaxed = one(KernelKind::Relaxed)?;
        let special = one(KernelKind::Special)?;
        // Solve the full-screen kernels for the costs, one unknown at a time: each kernel adds
        // one kind of work to what the ones before it priced.
        let full = |c: InstructionCounts| f64::from(c.alu - c.relaxed.min(c.alu));
        let rel = |c: InstructionCounts| f64::from(c.relaxed.min(c.alu));
        let gain = |p: &KernelMeasurement, what: f64| -> Result<f64, FitError> {
            if what > 0.0 {
                Ok(1.0 / what)
            } else {
                Err(FitError(format!(
                    "{}: none of the work it measures",
                    p.name
                )))
            }
        };
        // base = fragment + alu·A_b (the base's few operations, priced at the ALU kernel's
        // rate: solved together, two equations).
        let (fb, fa) = (per_lane(base)?, per_lane(alu)?);
        let (ab, aa) = (full(base.counts), full(alu.counts));
        let alu_ns = (fa - fb) * gain(alu, aa - ab)?;
        let fragment_ns = fb - alu_ns * ab;
        let priced = |c: InstructionCounts| fragment_ns + alu_ns * full(c);
        let relaxed_ns =
            (per_lane(relaxed)? - priced(relaxed.counts)) * gain(relaxed, rel(relaxed.counts))?;
        let priced = |c: InstructionCounts| priced(c) + relaxed_ns * rel(c);
        let special_ns = (per_lane(special)? - priced(special.counts))
            * gain(special, f64::from(special.counts.special))?;
        let priced = |c: InstructionCounts| priced(c) + special_ns * f64::from(c.special);
        // The sample kernels' time is their samples' overlapped with their own arithmetic
        // (`combine`), by the κ the mixed kernel shows, itself priced with the samples' cost:
        // solved by iteration from κ = 1 (one after the other), which converges in a few
        // rounds since the kernels' arithmetic is small beside their samples.
        let mixed = one(KernelKind::Mixed)?;
        let lanes_of = |kind: KernelKind| one(kind).and_then(per_lane);
        let (m_tri, m_lod, m_grad, m_query, m_mixed) = (
            lanes_of(KernelKind::Trilinear)?,
            lanes_of(KernelKind::Lod)?,
            lanes_of(KernelKind::Grad)?,
            lanes_of(KernelKind::Query)?,
            per_lane(mixed)?,
        );
        let arithmetic = |c: InstructionCounts| priced(c) - fragment_ns;
        // The texture time X of a kernel that took `m` per lane with arithmetic `a`.
        let texture_of = |m: f64, a: f64, k: f64| {
            let x = m - fragment_ns - k * a;
            if x >= a {
                x
            } else {
                (m - fragment_ns - a) / k.max(1e-6)
            }
        };
        let mut overlap = 1.0;
        let mut overlap_measured = 1.0;
        let mut sample_ns = 0.0;
        let (mut lod_sample_ns, mut grad_sample_ns, mut lod_query_ns) = (0.0, 0.0, 0.0);
        for _ in 0..20 {
            let per = |p: KernelKind, m: f64, n: fn(InstructionCounts) -> u32| {
                let p = one(p)?;
                Ok::<f64, FitError>(
                    texture_of(m, arithmetic(p.counts), overlap) * gain(p, f64::from(n(p.counts)))?,
                )
            };
            sample_ns = per(KernelKind::Trilinear, m_tri, |c| c.samples)?;
            lod_sample_ns = per(KernelKind::Lod, m_lod, |c| c.lod_samples)?;
            grad_sample_ns = per(KernelKind::Grad, m_grad, |c| c.grad_samples)?;
            lod_query_ns = per(KernelKind::Query, m_query, |c| c.lod_queries)?;
            // The mixed kernel: its ALU and texture parts as priced alone, against its time.
            let a = arithmetic(mixed.counts);
            let x = sample_ns * f64::from(mixed.counts.samples);
            overlap_measured = if a.min(x) > 0.0 {
                (m_mixed - fragment_ns - a.max(x)) / a.min(x)
            } else {
                1.0
            };
            overlap = overlap_measured.max(0.0);
        }
        let priced = |c: InstructionCounts| {
            let explicit = c.lod_samples + c.grad_samples + c.lod_queries;
            let a = arithmetic(c);
            let x = f64::from(c.samples.saturating_sub(explicit)) * sample_ns
                + f64::from(c.lod_samples) * lod_sample_ns
                + f64::from(c.grad_samples) * grad_sample_ns
                + f64::from(c.lod_queries) * lod_query_ns;
            fragment_ns + a.max(x) + overlap * a.min(x)
        };
        let tap_ns = match passes.iter().find(|p| p.kind == KernelKind::Anisotropic) {
            Some(aniso) if aniso.taps > 1.0 && aniso.counts.samples > 0 => {
                let samples = f64::from(aniso.counts.samples);
                Some((per_lane(aniso)? - priced(aniso.counts)) / (samples * (aniso.taps - 1.0)))
            }
            _ => None,
        };
        // Small triangles: per grid, the base shader's cost per fragment and the heavy shader's
        // waste, against the full-screen passes.
        let heavy = one(KernelKind::Lod)?;
        let shading_full = per_lane(heavy)? - per_lane(base)?;
        let mut areas = Vec::new();
        for g in passes.iter().filter(|p| p.kind == KernelKind::GridBase) {
            let a = passes
                .iter()
                .find(|p| p.kind == KernelKind::GridShaded && p.cell == g.cell)
                .ok_or_else(|| FitError(format!("no shaded pass on {} px cells", g.cell)))?;
            let cell = f64::from(g.cell);
            areas.push(AreaCost {
                area_px: 0.5 * cell * cell,
                cell_px: g.cell,
                fragment_ns: per_lane(g)?,
                waste: (per_lane(a)? - per_lane(g)?) / shading_full,
            });
        }
        areas.sort_by(|x, y| y.area_px.total_cmp(&x.area_px));
        // The block side whose lanes explain the measured waste best (least squares in log).
        let misfit = |block: u32| -> f64 {
            areas
                .iter()
                .map(|c| {
                    let model = grid_lanes_per_fragment(c.cell_px, block);
                    (model / c.waste.max(1e-3)).ln().powi(2)
                })
                .sum()
        };
        // Every Vulkan device shades at least 2×2 quads (derivatives need them): no side of 1.
        let block_px = [2u32, 4, 8]
            .into_iter()
            .min_by(|&a, &b| misfit(a).total_cmp(&misfit(b)))
            .unwrap_or(2);
        let block_fit = areas
            .iter()
            .map(|c| grid_lanes_per_fragment(c.cell_px, block_px) / c.waste)
            .collect();
        // A cost measured below zero is noise (or work the compiler removed): kept at 0, named.
        let mut at_zero = Vec::new();
        let mut floor = |name: &str, v: f64| {
            if v < 0.0 {
                at_zero.push(name.to_string());
                0.0
            } else {
                v
            }
        };
        let relaxed_ns = floor("relaxed", relaxed_ns);
        let lod_sample_ns = floor("lod_sample", lod_sample_ns);
        let grad_sample_ns = floor("grad_sample", grad_sample_ns);
        let lod_query_ns = floor("lod_query", lod_query_ns);
        let tap_ns = tap_ns.map(|t| floor("tap", t));
        // σ: the branch kernel's time beyond the base's, over the explicit-level kernel's.
        let branch = one(KernelKind::Branch)?;
        let branch_share = ((per_lane(branch)? - per_lane(base)?) / shading_full).clamp(0.0, 1.0);
        // (The branch kernel holds the heavy kernel's samples: `shading_full` is its work.)
        let rates = Self {
            device: device.to_string(),
            pass_ms: empty.ms,
            fragment_ns,
            alu_ns,
            relaxed_ns,
            special_ns,
            sample_ns,
            lod_sample_ns,
            grad_sample_ns,
            lod_query_ns,
            tap_ns,
            overlap,
            overlap_measured,
            branch_share,
            areas,
            block_px,
            block_fit,
            at_zero,
        };
        for (name, v) in [
            ("alu", rates.alu_ns),
            ("special", rates.special_ns),
            ("sample", rates.sample_ns),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(FitError(format!(
                    "the {name} cost came out {v} ns: the passes' times do not grow with their \
                     work (a device too fast for these sizes, or timestamps that do not time)"
                )));
            }
        }
        Ok(rates)
    }

    /// The set-up, rasterization and writes of a fragment of a triangle of `area_px` pixels
    /// (ns): interpolated in log area between the grids, towards the full-screen pass's
    /// (a million pixels) beyond the largest, the smallest grid's below it.
    pub fn fragment_at_area(&self, area_px: f64) -> f64 {
        self.interpolate(
            area_px,
            |c| c.area_px,
            |c| c.fragment_ns,
            (20.0, self.fragment_ns),
        )
    }

    /// `value` of the grids at `at` along `key` (log-linear between grids; from the largest
    /// grid towards `full` = (log2 of a full-screen triangle's key, its value); the smallest
    /// grid's below).
    fn interpolate(
        &self,
        at: f64,
        key: impl Fn(&AreaCost) -> f64,
        value: impl Fn(&AreaCost) -> f64,
        (full_at, full): (f64, f64),
    ) -> f64 {
        let mut points: Vec<(f64, f64)> = self
            .areas
            .iter()
            .map(|c| (key(c).log2(), value(c)))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let Some(&(largest, at_largest)) = points.last() else {
            return full;
        };
        let x = at.max(1e-9).log2();
        if x >= largest {
            let t = ((x - largest) / (full_at - largest).max(1e-9)).clamp(0.0, 1.0);
            return at_largest + t * (full - at_largest);
        }
        if x <= points[0].0 {
            return points[0].1;
        }
        for pair in points.windows(2) {
            let ((x0, y0), (x1, y1)) = (pair[0], pair[1]);
            if x <= x1 {
                return y0 + (x - x0) / (x1 - x0) * (y1 - y0);
            }
        }
        at_largest
    }

    /// Lane-time (ns) of one invocation doing `c`'s ALU work.
    pub(super) fn alu_of(&self, c: InstructionCounts) -> f64 {
        let relaxed = f64::from(c.relaxed.min(c.alu));
        (f64::from(c.alu) - relaxed) * self.alu_ns
            + relaxed * self.relaxed_ns
            + f64::from(c.special) * self.special_ns
    }

    /// Lane-time (ns) of one invocation's samples of `c`, each kind at its cost.
    pub(super) fn texture_of(&self, c: InstructionCounts) -> f64 {
        let explicit = c.lod_samples + c.grad_samples + c.lod_queries;
        f64::from(c.samples.saturating_sub(explicit)) * self.sample_ns
            + f64::from(c.lod_samples) * self.lod_sample_ns
            + f64::from(c.grad_samples) * self.grad_sample_ns
            + f64::from(c.lod_queries) * self.lod_query_ns
    }
}
