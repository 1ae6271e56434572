//! Every valid parameter at its extreme (grid, patch, wind, choppiness, depth, spreading,
//! fetch) gives a finite surface.

use vr_ocean::sim::{OceanConfig, SimCore, SpectrumKind, Surfaces};

fn assert_finite(s: &Surfaces, what: &str) {
    for c in &s.cascades {
        assert!(
            c.displacement.iter().flatten().all(|v| v.is_finite()),
            "{what}"
        );
        assert!(
            (1..c.grid.mip_levels())
                .flat_map(|l| c.mip_floats(l).into_iter().flatten())
                .chain(c.base_normals().into_iter().flatten().flatten())
                .all(|v| v.is_finite()),
            "{what}"
        );
        assert!(
            c.displacement_f16.iter().flatten().all(|v| v.is_finite()),
            "{what}"
        );
    }
}

#[test]
fn extreme_valid_parameters_stay_finite() {
    let mut cases: Vec<(String, OceanConfig)> = Vec::new();
    for n in [16u32, 512] {
        for patch in [0.5f32, 100_000.0] {
            for wind in [0.1f32, 60.0] {
                for chop in [0.0f32, 2.0] {
                    for depth in [None, Some(0.01f32)] {
                        for (align, supp) in [(0.0f32, 0.0f32), (1.0, 1.0)] {
                            let mut c = OceanConfig::single(n, patch).unwrap();
                            c.waves.wind_speed = wind;
                            c.waves.choppiness = chop;
                            c.waves.depth = depth;
                            c.waves.alignment = align;
                            c.waves.small_wave_suppression = supp;
                            c.waves.roughness = align;
                            if supp > 0.5 {
                                c.waves.spectrum = SpectrumKind::Jonswap {
                                    gamma: 10.0,
                                    fetch_km: 10_000.0,
                                };
                            }
                            cases.push((format!("{n} {patch} {wind} {chop} {depth:?} {align}"), c));
                        }
                    }
                }
            }
        }
    }
    let mut tiny_fetch = OceanConfig::default_cascades(32).unwrap();
    tiny_fetch.waves.spectrum = SpectrumKind::Jonswap {
        gamma: 1.0,
        fetch_km: 1e-6,
    };
    cases.push(("tiny fetch".into(), tiny_fetch));
    for (what, cfg) in cases {
        cfg.validate().unwrap();
        let mut core = SimCore::new(cfg.clone()).unwrap();
        let mut out = Surfaces::with_float_copies(&cfg);
        core.step(0.0, &mut out);
        core.step(1234.5, &mut out);
        assert_finite(&out, &what);
    }
}
