//! What the simulation's law tests share: a cascade's spec, one step, the RMS of a field.

use vr_ocean::sim::spectrum::CascadeSpec;
use vr_ocean::sim::{OceanConfig, SimCore, Surfaces};

/// The spec of `cfg`'s cascade `i`.
pub fn spec_of(cfg: &OceanConfig, i: usize) -> CascadeSpec {
    cfg.cascade_specs()[i]
}

/// One step of `core` at time `t`, with the f32 copies kept.
pub fn step(core: &mut SimCore, cfg: &OceanConfig, t: f64) -> Surfaces {
    let mut out = Surfaces::with_float_copies(cfg);
    core.step(t, &mut out);
    out
}

/// Root mean square of `v`.
pub fn rms(v: impl Iterator<Item = f32>) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for x in v {
        s += (x as f64).powi(2);
        n += 1;
    }
    (s / n as f64).sqrt()
}
