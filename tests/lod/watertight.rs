//! Watertightness of what the renderer draws: for hundreds of viewers (positions, heights from
//! the water line through a standing user's 1.7 m to far above, every preset, several ocean
//! sizes) the world-space triangles of every patch instance (expanded through the index set of
//! its draw) plus the skirt form a closed, consistently oriented surface: every edge inside the
//! covered area is used by exactly two triangles, once in each direction; only the skirt's
//! outer rim is open. Also, with culling, every patch edge left open borders a culled patch, and
//! the geomorph moves every shared vertex identically in all patches that use it, also with
//! the collapse by the screen (`lod::ScreenCollapse`) walking vertices up the lattices.

use crate::common;

use common::lod::{culled_frame, quest_eyes, Lcg};

use glam::{Vec2, Vec3};

use vr_ocean::lod::morph::{patch_vertex_xz, skirt_vertex_xz};
use vr_ocean::lod::{
    FrameInput, LodSettings, MaxDisplacement, OceanLod, OceanSize, QualityPreset, ScreenCollapse,
    StitchFlags,
};

/// A headset's pixels per radian at the view's centre (a Quest 3 eye, 2064 px over 93°).
const PIXELS_PER_RADIAN: f32 = 1000.0;

/// Integer lattice key of a world xz position, in units of the finest vertex spacing.
struct Lattice {
    origin: Vec2,
    unit: f64,
}

impl Lattice {
    fn new(lod: &OceanLod) -> Self {
        let st = lod.settings();
        Self {
            origin: lod.grid_centre(),
            unit: st.vertex_spacing(st.max_level()) as f64,
        }
    }

    fn key(&self, p: Vec2) -> u64 {
        let f = |c: f32, o: f32| {
            let u = (c as f64 - o as f64) / self.unit;
            let r = u.round();
            assert!((u - r).abs() < 0.05, "vertex off the lattice: {u}");
            (r as i64 + (1 << 30)) as u64
        };
        (f(p.x, self.origin.x) << 32) | f(p.y, self.origin.y)
    }
}

/// Directed edges (a, b) of every drawn triangle, and each vertex's morphed position.
#[derive(Default)]
struct Surface {
    edges: Vec<(u64, u64)>,
    morphed: Vec<(u64, Vec2)>,
    upward: bool,
    /// Vertices the collapse by the screen moved further than the CDLOD morph alone.
    collapsed: usize,
}

fn gather(lod: &OceanLod, camera: Vec3, with_skirt: bool, collapse: &ScreenCollapse) -> Surface {
    let lat = Lattice::new(lod);
    let v = lod.settings().vertices();
    let mut s = Surface {
        upward: true,
        ..Default::default()
    };
    let pos = lod.mesh().positions();
    let mut keys = vec![0u64; pos.len()];
    let mut world = vec![Vec2::ZERO; pos.len()];
    for d in lod.draws() {
        let insts = &lod.instances()[d.first_instance as usize..][..d.instance_count as usize];
        for inst in insts {
            assert_eq!(inst.stitch, d.stitch.bits() as u32);
            for (k, p) in pos.iter().enumerate() {
                world[k] = Vec2::from(inst.centre) + inst.size * Vec2::new(p[0], p[2]);
                keys[k] = lat.key(world[k]);
                let ij = (k as u32 % (v + 1), k as u32 / (v + 1));
                let q = patch_vertex_xz(inst, v, ij, camera, collapse);
                let cdlod = patch_vertex_xz(inst, v, ij, camera, &ScreenCollapse::NONE);
                s.collapsed += usize::from(q.distance(cdlod) > 1e-3);
                s.morphed.push((keys[k], q));
            }
            add_triangles(&mut s, lod.mesh().indices(d.stitch), &keys, &world);
        }
    }
    if with_skirt {
        let sk = lod.skirt();
        let inst = lod.skirt_instance();
        let c = lod.grid_centre();
        let w: Vec<Vec2> = sk
            .positions()
            .iter()
            .map(|p| c + Vec2::new(p[0], p[2]))
            .collect();
        let k: Vec<u64> = w.iter().map(|&p| lat.key(p)).collect();
        for (n, p) in sk.positions().iter().enumerate() {
            let inner = (n as u32) < sk.inner_vertex_count();
            s.morphed
                .push((k[n], skirt_vertex_xz(&inst, *p, inner, camera, collapse)));
        }
        add_triangles(&mut s, sk.indices(), &k, &w);
    }
    s.edges.sort_unstable();
    s
}

fn add_triangles(s: &mut Surface, idx: &[u16], keys: &[u64], world: &[Vec2]) {
    for t in idx.chunks_exact(3) {
        let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
        let (u, w) = (world[b] - world[a], world[c] - world[a]);
        // y of (b − a) × (c − a) in (x, z): > 0 means the triangle faces up.
        if u.y * w.x - u.x * w.y <= 0.0 {
            s.upward = false;
        }
        for (p, q) in [(a, b), (b, c), (c, a)] {
            s.edges.push((keys[p], keys[q]));
        }
    }
}

fn has(edges: &[(u64, u64)], e: (u64, u64)) -> bool {
    edges.binary_search(&e).is_ok()
}

/// Every directed edge appears once; its reverse appears exactly when it is not on the rim.
fn assert_closed(s: &Surface, rim: impl Fn(u64) -> bool, what: &str) {
    assert!(s.upward, "{what}: a triangle faces down or is degenerate");
    for w in s.edges.windows(2) {
        assert_ne!(w[0], w[1], "{what}: edge used twice in one direction");
    }
    for &(a, b) in &s.edges {
        if !has(&s.edges, (b, a)) {
            assert!(
                rim(a) && rim(b),
                "{what}: open edge inside the surface (gap or T-junction)"
            );
        }
    }
}

fn assert_morph_consistent(s: &mut Surface, what: &str) {
    s.morphed.sort_unstable_by_key(|m| m.0);
    for w in s.morphed.windows(2) {
        if w[0].0 == w[1].0 {
            let d = w[0].1.distance(w[1].1);
            assert!(d < 1e-2, "{what}: a shared vertex morphs apart by {d} m");
        }
    }
}

/// Checks `cameras` viewers; returns how many, and how many vertices the collapse by the
/// screen moved (every other viewer's frame is drawn with it).
fn run(preset: QualityPreset, size: f32, cameras: usize, seed: u64) -> (usize, usize) {
    let st = LodSettings::new(preset, OceanSize::new(size).unwrap());
    let mut lod = OceanLod::new(st);
    let mut rng = Lcg(seed);
    let heights = [0.0, 0.3, 1.7, 1.7, 1.7, 4.0, 25.0, 120.0, 900.0, 6000.0];
    let pad = MaxDisplacement::new([1.5, 2.0, 1.5]).unwrap();
    let (mut checked, mut collapsed) = (0, 0);
    for n in 0..cameras {
        let x = (rng.next() - 0.5) * 40_000.0;
        let z = (rng.next() - 0.5) * 40_000.0;
        let y = heights[n % heights.len()] + rng.next() * 0.1;
        let camera = Vec3::new(x, y, z);
        let what = format!("{preset:?} S={size} camera {camera}");
        lod.update(&FrameInput {
            viewer: camera,
            culling: None,
            max_displacement: pad,
        })
        .unwrap();
        assert!(lod.draws().len() <= 16);
        let extent = st.skirt_extent() as f64;
        let lat = Lattice::new(&lod);
        let rim_units = (extent / lat.unit).round() as i64;
        let rim = |k: u64| {
            let x = (k >> 32) as i64 - (1 << 30);
            let z = (k & 0xffff_ffff) as i64 - (1 << 30);
            x.abs() == rim_units || z.abs() == rim_units
        };
        let collapse = if n % 2 == 0 {
            ScreenCollapse::new(&st, camera.y, PIXELS_PER_RADIAN)
        } else {
            ScreenCollapse::NONE
        };
        let mut full = gather(&lod, camera, true, &collapse);
        collapsed += full.collapsed;
        assert_closed(&full, rim, &what);
        assert_morph_consistent(&mut full, &what);

        // The same frame culled for a grazing or random view: open edges only where a
        // neighbour was culled (its triangles close them in the full surface).
        let yaw = rng.next() * std::f32::consts::TAU;
        let pitch = if n % 2 == 0 {
            -0.05
        } else {
            (rng.next() - 0.7) * 2.0
        };
        let eyes = quest_eyes(camera, yaw, pitch);
        culled_frame(&mut lod, &eyes, pad);
        assert!(lod.draws().len() <= 16);
        let seen = gather(&lod, camera, false, &collapse);
        for w in seen.edges.windows(2) {
            assert_ne!(w[0], w[1], "{what}: culled surface reuses an edge");
        }
        for &(a, b) in &seen.edges {
            if !has(&seen.edges, (b, a)) {
                assert!(
                    has(&full.edges, (b, a)),
                    "{what}: visible edge has no partner"
                );
            }
        }
        checked += 1;
    }
    (checked, collapsed)
}

#[test]
fn low_and_medium_are_watertight_for_hundreds_of_viewers() {
    let (mut n, mut collapsed) = (0, 0);
    for size in [256.0, 1000.0, 8192.0] {
        for (preset, cameras, seed) in [(QualityPreset::Low, 60, 1), (QualityPreset::Medium, 40, 2)]
        {
            let (c, m) = run(preset, size, cameras, seed);
            n += c;
            collapsed += m;
        }
    }
    assert!(n >= 300);
    assert!(
        collapsed > 10_000,
        "the screen's collapse moved only {collapsed} vertices"
    );
}

#[test]
fn high_and_ultra_are_watertight() {
    let (mut n, mut collapsed) = (0, 0);
    for size in [256.0, 3000.0, 8192.0] {
        for (preset, seed) in [(QualityPreset::High, 3), (QualityPreset::Ultra, 4)] {
            let (c, m) = run(preset, size, 12, seed);
            n += c;
            collapsed += m;
        }
    }
    assert!(n >= 72);
    assert!(
        collapsed > 10_000,
        "the screen's collapse moved only {collapsed} vertices"
    );
}

#[test]
fn stitch_flags_point_at_coarser_neighbours_only() {
    let st = LodSettings::new(QualityPreset::Ultra, OceanSize::new(8192.0).unwrap());
    let mut lod = OceanLod::new(st);
    lod.update(&FrameInput {
        viewer: Vec3::new(10.0, 1.7, -3.0),
        culling: None,
        max_displacement: MaxDisplacement::default(),
    })
    .unwrap();
    let l_max = st.max_level() as u8;
    for leaf in lod.leaves() {
        let d = 1i32 << (l_max - leaf.level);
        let (gx, gy) = (leaf.x as i32 * d, leaf.y as i32 * d);
        for (e, nx, ny) in [
            (StitchFlags::EAST, gx + d, gy),
            (StitchFlags::NORTH, gx, gy + d),
            (StitchFlags::WEST, gx - 1, gy),
            (StitchFlags::SOUTH, gx, gy - 1),
        ] {
            match lod.tree().level_at(nx, ny) {
                Some(n) => {
                    assert!(n.abs_diff(leaf.level) <= 1, "2:1 violated at {leaf:?}");
                    assert_eq!(leaf.stitch.contains(e), n < leaf.level);
                }
                None => assert!(leaf.stitch.contains(e), "ring edge must meet the skirt"),
            }
        }
    }
}
