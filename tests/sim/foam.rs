//! Foam grows where the waves break (the Jacobian falls below the threshold) and decays at
//! its rate once they stop.

use vr_ocean::sim::{FoamParams, OceanConfig, SeaState, SimCore, Surfaces};

#[test]
fn foam_accumulates_where_waves_break_and_decays() {
    let mut cfg = OceanConfig::single(64, 30.0).unwrap();
    cfg.waves.choppiness = 2.0;
    cfg.waves.wind_speed = 20.0;
    cfg.waves.foam = FoamParams {
        threshold: 0.5,
        growth: 5.0,
        decay: 0.5,
    };
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let mut out = Surfaces::with_float_copies(&cfg);
    let mut t = 0.0;
    let mut coverage = Vec::new();
    for _ in 0..60 {
        t += 1.0 / 30.0;
        core.step(t, &mut out);
        let c = &out.cascades[0];
        let breaking = c.displacement.iter().filter(|d| d[3] < 0.5).count();
        let foam: f32 = c.base_normals().unwrap().iter().map(|b| b[3]).sum();
        coverage.push((breaking, foam));
    }
    assert!(
        coverage.iter().any(|&(b, _)| b > 0),
        "this sea state must break somewhere"
    );
    assert!(
        coverage.last().unwrap().1 > coverage[0].1,
        "foam accumulates: {coverage:?}"
    );
    // Switch breaking off: foam only decays.
    let mut calm = cfg.waves;
    calm.foam.threshold = 0.0;
    calm.choppiness = 0.0;
    core.set_waves(SeaState::new(calm).unwrap()).unwrap();
    let foam_sum = |s: &Surfaces| -> f32 {
        s.cascades[0]
            .base_normals()
            .unwrap()
            .iter()
            .map(|b| b[3])
            .sum()
    };
    let before = foam_sum(&out);
    core.step(t + 1.0, &mut out);
    let after = foam_sum(&out);
    let expect = before * (-0.5f32).exp();
    assert!(
        (after - expect).abs() <= 1e-3 * before.max(1.0),
        "{after} vs {expect}"
    );
}
