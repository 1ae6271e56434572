//! The ocean pass's GPU time on a calibrated device ([`predict`]): the model of the module's
//! documentation applied to a view's counts.

use super::DeviceRates;
use crate::render::budget::{PathCosts, PathCounts};

/// The prediction of one pass, with its terms (ms).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Prediction {
    /// The whole pass.
    pub ms: f64,
    /// Clear, resolve and store (the empty pass).
    pub pass_ms: f64,
    /// Rasterization, interpolation, tests and writes per fragment lane.
    pub fragments_ms: f64,
    /// The shaders' ALU work.
    pub alu_ms: f64,
    /// Their texture work.
    pub texture_ms: f64,
    /// What the overlap hides of the smaller of the two (negative where they slow each other).
    pub hidden_ms: f64,
    /// The vertex shader's work.
    pub vertex_ms: f64,
    /// Lanes shaded per tallied fragment (`w`: 1 for large triangles, more for small ones).
    pub lanes_per_fragment: f64,
}

/// The ocean pass's time on the device `rates` describe, for a frame that measured `counts`
/// with `costs` per invocation.
pub fn predict(rates: &DeviceRates, costs: &PathCosts, counts: &PathCounts) -> Prediction {
    let n = |x: u64| x as f64;
    let sized: f64 = counts.by_area.iter().map(|&k| n(k)).sum();
    let fragments_ns = if sized > 0.0 {
        counts
            .by_area
            .iter()
            .enumerate()
            .map(|(bin, &k)| n(k) * rates.fragment_at_area(PathCounts::area_of_bin(bin)))
            .sum()
    } else {
        n(counts.tallied()) * rates.fragment_ns
    };
    // Lanes per fragment in the device's blocks (1 where it wastes none, or nothing was
    // tallied).
    let q = counts.lanes_per_fragment(rates.block_px).unwrap_or(1.0);
    let paths = [
        (n(counts.sky), costs.sky),
        (n(counts.single), costs.single),
        (n(counts.supersampled), costs.supersampled),
        (n(counts.resamples), costs.resample),
        (n(counts.foam), costs.foam),
        (n(counts.plain), costs.plain),
        (n(counts.detail), costs.detail),
        (n(counts.knee), costs.knee),
        (n(counts.below), costs.below),
        (n(counts.depths), costs.depths),
    ];
    // Each fragment pays its own path's work, and on a device whose lanes run branches they
    // did not take (σ), the share σ of every path's (the union's).
    let sigma = rates.branch_share;
    let everything = n(counts.tallied());
    let alu_ns: f64 = q
        * ((1.0 - sigma) * paths.iter().map(|(k, c)| k * rates.alu_of(*c)).sum::<f64>()
            + sigma * everything * rates.alu_of(costs.union));
    let texture_ns: f64 = q
        * ((1.0 - sigma)
            * paths
                .iter()
                .map(|(k, c)| k * rates.texture_of(*c))
                .sum::<f64>()
            + sigma * everything * rates.texture_of(costs.union)
            + n(counts.aniso_taps) * rates.tap_ns.unwrap_or(0.0));
    // What the overlap hides (negative: what the interference adds).
    let hidden_ns = (1.0 - rates.overlap) * alu_ns.min(texture_ns);
    let vertex_ns = n(counts.vertex_invocations)
        * (rates.alu_of(costs.vertex) + rates.texture_of(costs.vertex));
    let to_ms = 1e-6;
    let p = Prediction {
        ms: 0.0,
        pass_ms: rates.pass_ms,
        fragments_ms: fragments_ns * to_ms,
        alu_ms: alu_ns * to_ms,
        texture_ms: texture_ns * to_ms,
        hidden_ms: hidden_ns * to_ms,
        vertex_ms: vertex_ns * to_ms,
        lanes_per_fragment: q,
    };
    Prediction {
        ms: p.pass_ms + p.fragments_ms + p.alu_ms + p.texture_ms - p.hidden_ms + p.vertex_ms,
        ..p
    }
}
