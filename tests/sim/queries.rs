//! Height queries land on the surface: they invert the choppy displacement, read the GPU's f16
//! copy within a centimetre, and find the rest position under several cascades.

use vr_ocean::sim::{OceanConfig, SimCore, Surfaces};

use crate::helpers::step;

#[test]
fn height_queries_invert_the_choppy_displacement() {
    let mut cfg = OceanConfig::single(128, 80.0).unwrap();
    cfg.waves.choppiness = 1.0;
    cfg.waves.wind_speed = 8.0;
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let s = step(&mut core, &cfg, 42.0);
    let c = &s.cascades[0];
    let n = 128;
    let texel = 80.0 / n as f32;
    let mut worst = 0.0f32;
    let mut checked = 0;
    for row in (0..n).step_by(3) {
        for col in (0..n).step_by(3) {
            let d = c.displacement[row * n + col];
            if d[3] < 0.2 {
                continue; // folded or nearly folded: the surface has several heights here
            }
            // The water at rest position p sits at p + D(p) with height h(p).
            let (x, z) = (col as f32 * texel + d[0], row as f32 * texel + d[2]);
            let h = s.height_at(x + 3.0 * 80.0, z - 80.0); // any patch repeat
            worst = worst.max((h - d[1]).abs());
            checked += 1;
        }
    }
    assert!(checked > 1000);
    assert!(worst < 0.01, "worst height error {worst} m");
    // Batch form equals the single form.
    let pts = [[1.0f32, 2.0], [-30.0, 17.5], [400.0, -900.0]];
    let batch: Vec<f32> = s.heights_at(&pts).collect();
    for (p, h) in pts.iter().zip(batch) {
        assert_eq!(h, s.height_at(p[0], p[1]));
    }
}

#[test]
fn height_queries_on_the_gpu_copy_are_within_a_centimetre() {
    // Without f32 copies (the renderer's configuration) queries read the RGBA16F displacement.
    let mut cfg = OceanConfig::single(128, 80.0).unwrap();
    cfg.waves.choppiness = 1.0;
    cfg.waves.wind_speed = 8.0;
    let mut core_full = SimCore::new(cfg.clone()).unwrap();
    let mut core_gpu = SimCore::new(cfg.clone()).unwrap();
    let mut full = Surfaces::with_float_copies(&cfg);
    let mut gpu = Surfaces::new(&cfg);
    core_full.step(42.0, &mut full);
    core_gpu.step(42.0, &mut gpu);
    assert!(gpu.cascades[0].displacement.is_empty());
    let mut worst = 0.0f32;
    for i in 0..2000 {
        let (x, z) = (i as f32 * 0.173 - 60.0, i as f32 * -0.0911 + 13.0);
        let (a, b) = (full.height_at(x, z), gpu.height_at(x, z));
        worst = worst.max((a - b).abs());
    }
    assert!(worst < 0.01, "f16 queries differ by up to {worst} m");
    assert_eq!(full.max_displacement(), gpu.max_displacement());
}

#[test]
fn multi_cascade_height_queries_land_on_the_surface() {
    let cfg = OceanConfig::default_cascades(64).unwrap();
    let mut core = SimCore::new(cfg.clone()).unwrap();
    let s = step(&mut core, &cfg, 5.0);
    for i in 0..200 {
        let (x, z) = (i as f32 * 3.7 - 300.0, i as f32 * -1.3 + 50.0);
        let (px, pz) = vr_ocean::sim::query::rest_position(&s.cascades, x, z);
        let d = vr_ocean::sim::query::displacement_at(&s.cascades, px, pz);
        let miss = ((px + d[0] - x).powi(2) + (pz + d[2] - z).powi(2)).sqrt();
        // Converged wherever the summed surface is not folded.
        assert!(
            miss < 0.01 || d[1].abs() > 0.0 && miss < 0.5,
            "({x}, {z}) missed by {miss} m"
        );
    }
}
