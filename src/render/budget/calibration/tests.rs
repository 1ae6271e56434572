//! The fit and the prediction on a synthetic device that follows the model exactly.

use super::*;
use crate::render::budget::{PathCosts, PathCounts};

fn counts(alu: u32, relaxed: u32, special: u32, samples: u32) -> InstructionCounts {
    InstructionCounts {
        alu,
        relaxed,
        special,
        samples,
        ..Default::default()
    }
}

const ALU_KERNEL: InstructionCounts = InstructionCounts {
    alu: 1156,
    relaxed: 0,
    special: 0,
    samples: 0,
    lod_samples: 0,
    grad_samples: 0,
    lod_queries: 0,
    branches: 0,
};
const BASE_KERNEL: InstructionCounts = InstructionCounts {
    alu: 4,
    ..ALU_KERNEL
};

/// Passes a device of known costs would measure: the fit must find the costs again.
fn synthetic(truth: &DeviceRates, overlap: f64) -> Vec<KernelMeasurement> {
    let f = 1e6;
    let shading = |c: InstructionCounts, taps: f64| {
        let a = truth.alu_of(c);
        let x =
            truth.texture_of(c) + f64::from(c.samples) * (taps - 1.0) * truth.tap_ns.unwrap_or(0.0);
        a.max(x) + overlap * a.min(x)
    };
    let pass = |name: &str, kind, c: InstructionCounts, taps: f64| {
        let lanes = if kind == KernelKind::Empty { 0.0 } else { f };
        let ms = truth.pass_ms + lanes * (truth.fragment_ns + shading(c, taps)) * 1e-6;
        KernelMeasurement {
            name: name.into(),
            kind,
            ms,
            runs_ms: vec![ms],
            fragments: f,
            triangles: 2.0,
            cell: 0,
            taps,
            counts: c,
        }
    };
    let mut out = vec![
        pass("empty", KernelKind::Empty, counts(0, 0, 0, 0), 1.0),
        pass("base", KernelKind::Base, BASE_KERNEL, 1.0),
        pass("alu", KernelKind::Alu, ALU_KERNEL, 1.0),
        pass(
            "relaxed",
            KernelKind::Relaxed,
            counts(1156, 1152, 0, 0),
            1.0,
        ),
        pass("special", KernelKind::Special, counts(100, 0, 192, 0), 1.0),
        pass(
            "trilinear",
            KernelKind::Trilinear,
            counts(60, 0, 0, 12),
            1.0,
        ),
        pass(
            "anisotropic",
            KernelKind::Anisotropic,
            counts(60, 0, 0, 12),
            4.0,
        ),
        pass("mixed", KernelKind::Mixed, counts(400, 0, 0, 8), 1.0),
        pass(
            "lod",
            KernelKind::Lod,
            InstructionCounts {
                lod_samples: 12,
                ..counts(70, 0, 0, 12)
            },
            1.0,
        ),
        pass(
            "grad",
            KernelKind::Grad,
            InstructionCounts {
                grad_samples: 12,
                ..counts(80, 0, 0, 12)
            },
            1.0,
        ),
        pass(
            "query",
            KernelKind::Query,
            InstructionCounts {
                lod_queries: 12,
                ..counts(60, 0, 0, 12)
            },
            1.0,
        ),
    ];
    // The branch kernel: the base's work, and σ of the explicit-level kernel's beyond it.
    let lod = InstructionCounts {
        lod_samples: 12,
        ..counts(70, 0, 0, 12)
    };
    let mut branch = pass("branch", KernelKind::Branch, lod, 1.0);
    let base = pass("base", KernelKind::Base, BASE_KERNEL, 1.0);
    branch.ms = base.ms + truth.branch_share * (branch.ms - base.ms);
    out.push(branch);
    for area in &truth.areas {
        let cell = (2.0 * area.area_px).sqrt().round() as u32;
        for (kind, c) in [
            (KernelKind::GridBase, BASE_KERNEL),
            (KernelKind::GridShaded, lod),
        ] {
            // The base shader's own few operations are wasted alike.
            let shade = area.waste * (shading(c, 1.0) - shading(BASE_KERNEL, 1.0));
            let ms = truth.pass_ms + f * (area.fragment_ns + shade) * 1e-6;
            out.push(KernelMeasurement {
                name: format!("{kind:?} {cell}"),
                kind,
                ms,
                runs_ms: vec![ms],
                fragments: f,
                triangles: f / area.area_px,
                cell,
                taps: 1.0,
                counts: c,
            });
        }
    }
    out
}

fn truth() -> DeviceRates {
    // A device that shades 4×4 blocks: its grids waste what the blocks make them.
    let area = |cell: u32, fragment_ns| AreaCost {
        area_px: 0.5 * f64::from(cell * cell),
        cell_px: cell,
        fragment_ns,
        waste: grid_lanes_per_fragment(cell, 4),
    };
    DeviceRates {
        device: "synthetic".into(),
        pass_ms: 0.5,
        fragment_ns: 2.0,
        alu_ns: 0.05,
        relaxed_ns: 0.03,
        special_ns: 0.2,
        sample_ns: 1.5,
        lod_sample_ns: 2.5,
        grad_sample_ns: 4.0,
        lod_query_ns: 0.9,
        tap_ns: Some(0.7),
        overlap: 0.25,
        overlap_measured: 0.25,
        branch_share: 0.0,
        at_zero: Vec::new(),
        areas: vec![area(16, 2.2), area(4, 4.0), area(1, 30.0)],
        block_px: 4,
        block_fit: Vec::new(),
    }
}

#[test]
fn the_fit_finds_the_costs_of_a_device_that_follows_the_model() {
    let t = truth();
    let fitted = DeviceRates::fit("synthetic", &synthetic(&t, 0.25)).unwrap();
    for (got, want) in [
        (fitted.pass_ms, t.pass_ms),
        (fitted.fragment_ns, t.fragment_ns),
        (fitted.alu_ns, t.alu_ns),
        (fitted.relaxed_ns, t.relaxed_ns),
        (fitted.special_ns, t.special_ns),
        (fitted.sample_ns, t.sample_ns),
        (fitted.lod_sample_ns, t.lod_sample_ns),
        (fitted.grad_sample_ns, t.grad_sample_ns),
        (fitted.lod_query_ns, t.lod_query_ns),
        (fitted.tap_ns.unwrap(), t.tap_ns.unwrap()),
        (fitted.overlap, t.overlap),
        (fitted.branch_share, t.branch_share),
    ] {
        assert!((got - want).abs() < 1e-6 * want.max(1.0), "{got} vs {want}");
    }
    assert_eq!(fitted.areas.len(), 3);
    for (got, want) in fitted.areas.iter().zip(&t.areas) {
        assert!((got.area_px - want.area_px).abs() < 1e-9);
        assert!((got.waste - want.waste).abs() < 1e-6, "{got:?} vs {want:?}");
        // The base shader's own operations, wasted too, are in its per-fragment cost.
        assert!(
            (got.fragment_ns - want.fragment_ns).abs() < 0.05,
            "{got:?} vs {want:?}"
        );
    }
    // Between two grids, in log area; beyond the smallest, the smallest.
    // The grids' waste is a 4×4 block device's, to the digit.
    assert_eq!(fitted.block_px, 4);
    assert!(fitted.block_fit.iter().all(|r| (r - 1.0).abs() < 1e-6));
    // Set-up per fragment: between two grids in log area; a full-screen triangle's far
    // beyond the largest.
    assert!((fitted.fragment_at_area(1e7) - t.fragment_ns).abs() < 1e-9);
    assert!((fitted.fragment_at_area(8.0) - 4.0).abs() < 0.05);
}

#[test]
fn a_cpu_adds_texture_and_alu_time_and_small_triangles_cost_more() {
    let t = truth();
    let fitted = DeviceRates::fit("cpu", &synthetic(&t, 1.0)).unwrap();
    assert!((fitted.overlap - 1.0).abs() < 1e-9);
    let cost = |alu, samples| counts(alu, 0, 0, samples);
    let costs = PathCosts {
        sky: cost(50, 1),
        single: cost(400, 8),
        supersampled: cost(700, 14),
        resample: cost(20, 1),
        foam: cost(100, 3),
        plain: cost(350, 7),
        detail: cost(50, 2),
        vertex: cost(200, 3),
        union: cost(1500, 30),
        knee: cost(40, 0),
        below: cost(500, 4),
        depths: cost(60, 1),
    };
    let mut c = PathCounts {
        sky: 1000,
        single: 3000,
        ..Default::default()
    };
    // Every fragment of a large triangle: the full-screen costs.
    c.by_area[PathCounts::AREA_BINS - 1] = 4000;
    c.quarter_lanes = [16000; 3];
    let big = predict(&fitted, &costs, &c);
    assert!((big.lanes_per_fragment - 1.0).abs() < 0.01);
    let by_hand = t.pass_ms
        + 4000.0 * t.fragment_ns * 1e-6
        + (1000.0 * (50.0 * t.alu_ns + t.sample_ns)
            + 3000.0 * (400.0 * t.alu_ns + 8.0 * t.sample_ns))
            * 1e-6;
    assert!(
        (big.ms - by_hand).abs() < 0.01 * by_hand,
        "{} vs {by_hand}",
        big.ms
    );
    // The same fragments from quarter-pixel triangles: eight lanes each in 4×4 blocks, and
    // dearer set-up.
    c.by_area = [0; PathCounts::AREA_BINS];
    c.by_area[0] = 4000;
    c.quarter_lanes = [4 * 2 * 4000, 4 * 8 * 4000, 4 * 32 * 4000];
    let small = predict(&fitted, &costs, &c);
    assert!((small.lanes_per_fragment - 8.0).abs() < 1e-9);
    assert!((small.alu_ms - 8.0 * big.alu_ms).abs() < 0.01 * small.alu_ms);
    assert!(small.fragments_ms > 10.0 * big.fragments_ms);
    // A device that runs every branch for every lane pays the union for each fragment.
    let mut masking = fitted.clone();
    masking.branch_share = 1.0;
    let all = predict(&masking, &costs, &c);
    let union_alu = 4000.0 * 8.0 * 1500.0 * t.alu_ns * 1e-6;
    assert!(
        (all.alu_ms - union_alu).abs() < 0.01 * union_alu,
        "{} vs {union_alu}",
        all.alu_ms
    );
}

#[test]
fn passes_that_do_not_grow_with_their_work_are_refused() {
    let mut passes = synthetic(&truth(), 0.25);
    for p in &mut passes {
        p.ms = 1.0;
    }
    assert!(DeviceRates::fit("flat", &passes).is_err());
    assert!(DeviceRates::fit("none", &[]).is_err());
}
