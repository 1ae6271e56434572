//! Sea states that change smoothly (issue 31, item 3): Beaufort 3 to 8 while stepping. The
//! step's worst time during the change stays within 1.5x of the median before it, Hs rises
//! monotonically to the new state's, and the coarsest patch's growth (257 -> 514 m) changes
//! nothing the surface shows. Its timings want the CPU alone: `cargo xtask test` runs it in
//! the frame-time step, one test at a time, and skips it among the host's tests (which run
//! beside each other: there one CI run read 1.54x, alone 1.23x). Run with `--nocapture` for
//! the numbers in BENCHMARKS.md.

use std::time::{Duration, Instant};

use vr_ocean::sim::retune::BLEND_SECONDS;
use vr_ocean::sim::{OceanConfig, SeaState, SimCore, Surfaces, WaveParams};
use vr_ocean::ui::Beaufort;

/// Steps per second (a Quest 2's 72 Hz).
const RATE: f64 = 72.0;
/// Steps before the change.
const BEFORE: usize = 120;

fn sea(force: u8) -> OceanConfig {
    let mut cfg = OceanConfig::default_cascades(256).unwrap();
    cfg.waves.wind_speed = Beaufort::new(force).unwrap().wind_speed();
    cfg.fit_patches();
    cfg
}

/// What one run of the change records per step.
struct Run {
    /// Wall time of each step (the change's `set_waves` included in its step).
    times: Vec<Duration>,
    /// Expected significant height each step shows (m).
    hs: Vec<f32>,
    /// The step whose surfaces first carry the grown patch, and the height error there
    /// against the sea that never changed (m), at the grown grid's texels.
    switch: Option<(usize, f32)>,
}

/// Steps Beaufort 3 for [`BEFORE`] steps, changes to Beaufort 8 (`smooth` or at once) and
/// steps until the change is done plus a second. A second core that stays at Beaufort 3
/// runs beside it (untimed) to judge the step where the patch grows.
fn run(smooth: bool) -> Run {
    let calm = sea(3);
    let mut core = SimCore::new(calm.clone()).unwrap();
    let mut same = SimCore::new(calm.clone()).unwrap();
    let mut out = Surfaces::with_float_copies(&calm);
    let mut reference = Surfaces::with_float_copies(&calm);
    let gale: WaveParams = sea(8).waves;
    let mut rec = Run {
        times: Vec::new(),
        hs: Vec::new(),
        switch: None,
    };
    let total = BEFORE + ((BLEND_SECONDS + 2.0) * RATE) as usize;
    for i in 0..total {
        let t = i as f64 / RATE;
        let start = Instant::now();
        if i == BEFORE {
            if smooth {
                core.set_waves(SeaState::new(gale).unwrap()).unwrap();
            } else {
                core.set_waves_at_once(SeaState::new(gale).unwrap())
                    .unwrap();
            }
        }
        core.step(t, &mut out);
        rec.times.push(start.elapsed());
        rec.hs.push(out.significant_height);
        let grown = out.cascades[0].patch;
        if rec.switch.is_none() && grown != calm.patch_sizes[0] && smooth {
            same.step(t, &mut reference);
            // Texel (c, r) of the grown grid sits where texel (2c, 2r) of the old one does
            // (mod N): the same waves there, unless the switch popped.
            let n = out.cascades[0].grid.n();
            let mut worst = 0.0f32;
            for r in 0..n {
                for c in 0..n {
                    let g = out.cascades[0].displacement[r * n + c];
                    let o = reference.cascades[0].displacement[(2 * r % n) * n + 2 * c % n];
                    for k in 0..3 {
                        worst = worst.max((g[k] - o[k]).abs());
                    }
                }
            }
            rec.switch = Some((i, worst));
        }
        if i > BEFORE && smooth && !core.retuning() && i + (RATE as usize) < total {
            // Done: a second more, then stop.
            let rest = i + RATE as usize;
            for j in i + 1..=rest {
                let t = j as f64 / RATE;
                let start = Instant::now();
                core.step(t, &mut out);
                rec.times.push(start.elapsed());
                rec.hs.push(out.significant_height);
            }
            break;
        }
    }
    rec
}

fn median(v: &[Duration]) -> Duration {
    let mut v = v.to_vec();
    v.sort();
    v[v.len() / 2]
}

#[test]
fn beaufort_3_to_8_blends_without_a_spike_or_a_pop() {
    // Per step, the least of five runs: the host's noise (other processes, a preempted
    // thread) hits each run at different steps; what the change costs is there every time.
    // (With three, one suite run had a step slowed in all three, 1.56x; alone 1.23-1.30x.)
    let runs: Vec<Run> = (0..5).map(|_| run(true)).collect();
    let steps = runs.iter().map(|r| r.times.len()).min().unwrap();
    let least: Vec<Duration> = (0..steps)
        .map(|i| runs.iter().map(|r| r.times[i]).min().unwrap())
        .collect();
    let before = median(&least[20..BEFORE]);
    let (worst_at, worst) = least[BEFORE..]
        .iter()
        .enumerate()
        .max_by_key(|(_, d)| **d)
        .map(|(i, d)| (i + BEFORE, *d))
        .unwrap();
    let ratio = worst.as_secs_f64() / before.as_secs_f64();
    // The gale's own step, once the change is done (a larger spectrum, more foam).
    let after = median(&least[steps - RATE as usize / 2..]);
    let profile: Vec<String> = least[BEFORE - 2..BEFORE + 30]
        .iter()
        .map(|d| format!("{:.2}", d.as_secs_f64() * 1e3))
        .collect();
    println!("steps from 2 before the change (ms): {}", profile.join(" "));
    let mut order: Vec<usize> = (BEFORE..steps).collect();
    order.sort_by(|&a, &b| least[b].cmp(&least[a]));
    let top: Vec<String> = order[..5]
        .iter()
        .map(|&i| format!("{} ({:.2} ms)", i - BEFORE, least[i].as_secs_f64() * 1e3))
        .collect();
    println!("slowest steps of the change: {}", top.join(", "));
    println!(
        "step median before {:.2} ms, after {:.2} ms; worst during the change {:.2} ms (step {}), \
         ratio {ratio:.2}",
        before.as_secs_f64() * 1e3,
        after.as_secs_f64() * 1e3,
        worst.as_secs_f64() * 1e3,
        worst_at - BEFORE
    );

    // The same change at once, for scale: one step rebuilds every spectrum.
    let at_once = run(false);
    let spike =
        at_once.times[BEFORE].as_secs_f64() / median(&at_once.times[20..BEFORE]).as_secs_f64();
    println!("at once: the change's step is {spike:.1}x the median");
    assert!(
        spike > 1.5,
        "the at-once change must be what this test catches ({spike:.2}x)"
    );
    assert!(
        ratio <= 1.5,
        "worst step during the change {ratio:.2}x the median before it (limit 1.5x)"
    );

    // Hs: flat before, then rising monotonically to the gale's.
    let hs = &runs[0].hs;
    let gale = SimCore::new(sea(8)).unwrap();
    let target = 4.0 * gale.expected_variances().sum::<f64>().sqrt() as f32;
    let first = hs[BEFORE - 1];
    println!(
        "Hs {first:.3} m -> {:.3} m (the gale's {target:.3} m) over {:.1} s",
        hs.last().unwrap(),
        (hs.len() - BEFORE) as f64 / RATE
    );
    for (i, w) in hs[BEFORE - 1..].windows(2).enumerate() {
        assert!(
            w[1] >= w[0],
            "Hs fell at step {i} of the change: {} -> {}",
            w[0],
            w[1]
        );
    }
    assert!((hs.last().unwrap() / target - 1.0).abs() < 1e-3);
    assert!(hs[BEFORE + (BLEND_SECONDS * RATE / 2.0) as usize] > first);

    // The coarsest patch grew to the next octave without changing the surface.
    let (at, err) = runs[0]
        .switch
        .expect("the gale needs a larger coarsest patch");
    assert_eq!(sea(8).patch_sizes[0], 514.0);
    println!(
        "patch 257 -> 514 m at step {} of the change: surface moved {err:.2e} m",
        at - BEFORE
    );
    assert!(err < 1e-4, "the patch switch moved the surface by {err} m");
}
