//! Helpers shared by the LOD tests: a deterministic generator, a Quest-like head and one
//! culled LOD frame.
#![allow(dead_code)]

use glam::Vec3;
use vr_ocean::base::Fov;
use vr_ocean::lod::{FrameInput, FrameStats, MaxDisplacement, OceanLod, StereoFrustum};

/// A small deterministic generator (64-bit LCG), uniform in [0, 1).
pub struct Lcg(pub u64);

impl Lcg {
    /// The next value in [0, 1).
    pub fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Both eyes of a head at `pos` (64 mm IPD, Quest-like FOVs), `yaw`/`pitch` in radians.
pub fn quest_eyes(pos: Vec3, yaw: f32, pitch: f32) -> StereoFrustum {
    StereoFrustum::from_head(pos, yaw, pitch, 0.064, Fov::QUEST_EYES).unwrap()
}

/// One LOD frame for `eyes`, culled against them, boxes padded by `pad`.
pub fn culled_frame(lod: &mut OceanLod, eyes: &StereoFrustum, pad: MaxDisplacement) -> FrameStats {
    lod.update(&FrameInput {
        viewer: eyes.centre(),
        culling: Some(eyes),
        max_displacement: pad,
    })
    .unwrap()
}
