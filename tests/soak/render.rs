//! 10 000 headless frames at a small size: resident memory does not grow, and no Vulkan object
//! leaks (the validation layer reports leaked objects as errors when the device is destroyed,
//! which fails the run).

use crate::common;

use common::gpu;
use vr_ocean::app::RunHooks;
use vr_ocean::lod::{LodSettings, OceanSize, QualityPreset};
use vr_ocean::render::StereoMode;
use vr_ocean::sim::OceanConfig;
use vr_ocean::xr::desktop::CameraPath;
use vr_ocean::xr::FrameState;

/// Resident set size (bytes) from /proc/self/statm.
fn resident_bytes() -> u64 {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap();
    let pages: u64 = statm.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * 4096
}

struct Rss {
    samples: Vec<(u64, u64)>,
}

impl RunHooks for Rss {
    fn frame_done(&mut self, frame: &FrameState) {
        if frame.index % 1000 == 999 {
            self.samples.push((frame.index + 1, resident_bytes()));
        }
    }
}

#[test]
fn ten_thousand_frames_without_growth() {
    const FRAMES: u64 = 10_000;
    // Walk a loop so the LOD, the culling and the instance count keep changing.
    let path = CameraPath::parse(
        "0   0   1.7  0    0   -5
         40  60  2.0  -60  180 -15
         80  0   1.7  -120 360 -5
         139 0   1.7  0    540 -5",
    )
    .unwrap();
    let mut opts = gpu::small_options(StereoMode::Multiview, Vec::new());
    opts.ocean = OceanConfig::default_cascades(16).unwrap();
    opts.lod = LodSettings::new(QualityPreset::Low, OceanSize::new(256.0).unwrap());
    let mut rss = Rss {
        samples: Vec::with_capacity(16),
    };
    let report = gpu::render_with(&opts, path, FRAMES, 16, 16, &mut rss);
    assert_eq!(report.frames, FRAMES);
    for (frame, bytes) in &rss.samples {
        println!(
            "frame {frame:>6}: resident {:.1} MiB",
            *bytes as f64 / 1048576.0
        );
    }
    // From the first sample (after 1000 frames: warm) to the last.
    let first = rss.samples[0].1;
    let last = rss.samples.last().unwrap().1;
    let growth = last.saturating_sub(first);
    assert!(
        growth < 4 << 20,
        "resident memory grew by {:.1} MiB over {} frames",
        growth as f64 / 1048576.0,
        FRAMES - 1000
    );
}
