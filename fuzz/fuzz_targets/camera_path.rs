//! Camera paths: any text is a path or a clear error, never a panic; an accepted path gives a
//! finite pose at any time, and its throws and boats are countable.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vr_ocean::xr::desktop::CameraPath;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(path) = CameraPath::parse(text) else {
        return;
    };
    let end = path.duration();
    for t in [0.0, 0.37, 0.5 * end, end, end + 1.0, -1.0] {
        let (p, q) = path.pose(t);
        assert!(p.is_finite() && q.is_finite(), "pose at {t}: {p} {q}");
    }
    let _ = path.throws_in(0.0, end + 1.0);
    let _ = path.boats_in(0.0, end + 1.0).count();
});
