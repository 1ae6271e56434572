//! Per-frame LOD cost: traversal + balance + stitch flags + stereo culling + batching at Ultra,
//! S = 8192, single thread, for a standing user looking at the horizon and from 300 m up.

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;

use vr_ocean::base::Fov;
use vr_ocean::lod::{
    FrameInput, LodSettings, MaxDisplacement, OceanLod, OceanSize, QualityPreset, StereoFrustum,
};

fn frame(c: &mut Criterion) {
    let st = LodSettings::new(QualityPreset::Ultra, OceanSize::new(8192.0).unwrap());
    let pad = MaxDisplacement::new([1.0, 1.5, 1.0]).unwrap();
    for (name, height, pitch) in [("standing_horizon", 1.7, 0.0), ("aerial_300m", 300.0, -0.6)] {
        let mut lod = OceanLod::new(st);
        let mut n = 0u32;
        c.bench_function(&format!("lod_frame_ultra_8192/{name}"), |b| {
            b.iter(|| {
                n = n.wrapping_add(1);
                let t = (n % 1000) as f32 * 0.01;
                let pos = Vec3::new(t * 3.0, height, -t);
                let eyes =
                    StereoFrustum::from_head(pos, t * 0.3, pitch, 0.064, Fov::QUEST_EYES).unwrap();
                lod.update(&FrameInput {
                    viewer: eyes.centre(),
                    culling: Some(&eyes),
                    max_displacement: pad,
                })
                .unwrap()
            })
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = frame
}
criterion_main!(benches);
