//! The steady state of the physics: 64 bodies in the default sea, frames advanced with
//! `Floaters::advance` (reading the latest surfaces), drawn through `Floaters::instances`, one
//! held by a hand, under a counting global allocator.
//!
//! Our side allocates nothing: the height queries, the water forces, the hand and the
//! instances. rapier 0.36's step does allocate small buffers every step, whatever the caller
//! does: its modified-bodies list is `mem::take`n and dropped each step (any
//! `RigidBodySet::get_mut`, which applying a force needs, refills it), its island solver
//! builds a `StageSync` (a Vec of cursors) per solve, and parry's EPA and polygonal contact
//! manifolds (cylinders, the boat hull) build small Vecs per contact. Attributed by a
//! backtrace-taking allocator over 20 steps of this scene: 100 in `ModifiedObjects`, 20 in
//! `StageSync::new`, ~110 in parry's contact code and rapier's pair/BVH updates, none
//! elsewhere (11.5 a step). The test pins that: everything outside
//! `Floaters::advance` allocates nothing, and `advance` at most [`RAPIER_ALLOCATIONS_PER_STEP`]
//! per fixed step, so any allocation of ours (or a growing one of rapier's) fails it.

use crate::common;

use std::time::Duration;

use glam::Vec3;
use vr_ocean::physics::{Floaters, Hand, HandInput, Pose};
use vr_ocean::sim::{OceanConfig, Simulation};

/// Ceiling on rapier 0.36's allocations per step in this scene (measured 9.8 to 12.1 over 375
/// steps; see the module docs).
const RAPIER_ALLOCATIONS_PER_STEP: usize = 20;

fn steady_state_frames_do_not_allocate() {
    let cfg = OceanConfig::default_cascades(64).unwrap();
    let mut sim = Simulation::new(cfg, 1).unwrap();
    let mut t = 0.0;
    sim.step_blocking(t);
    let (mut world, ids) = common::physics::full_world(sim.surfaces());
    let held = ids[0];
    let mut hand = Hand::new();
    let frame = Duration::from_secs_f64(1.0 / 72.0);
    // One frame; returns the physics steps it ran, the allocations inside `advance` and a
    // checksum of what was drawn. Counting is on for the whole frame (caller, simulation
    // worker) and the span of `advance` is counted apart.
    let mut frame_of = |world: &mut Floaters, sim: &mut Simulation, t: &mut f64, i: usize| {
        *t += frame.as_secs_f64();
        let surfaces = sim.step_blocking(*t);
        let before = common::allocations();
        let ticks = world.advance(frame, surfaces);
        let in_advance = common::allocations() - before;
        // A hand closes on body 0 at frame 10 and keeps it.
        let centre = world.pose(held).map(|p| p.position).unwrap_or(Vec3::ZERO);
        let input = HandInput {
            grip: if i >= 10 { 1.0 } else { 0.0 },
            pose: Pose::at(centre + Vec3::new(0.05, 0.0, 0.0)),
            linvel: Vec3::ZERO,
            angvel: Vec3::ZERO,
        };
        let step = hand.update(&input, Some((held, centre)));
        if let Some(c) = step.command {
            world.apply(&c).unwrap();
        }
        let mut sum = Vec3::ZERO;
        for inst in world.instances() {
            sum += inst.model.w_axis.truncate();
        }
        (ticks.steps, in_advance, sum)
    };
    // Warm-up: rapier sizes its contact and island buffers over the first frames.
    for i in 0..300 {
        frame_of(&mut world, &mut sim, &mut t, i);
    }
    let ((steps, in_advance, sum), n) = common::count_allocations(|| {
        let (mut steps, mut in_advance, mut sum) = (0u32, 0usize, Vec3::ZERO);
        for i in 300..600 {
            let (s, a, v) = frame_of(&mut world, &mut sim, &mut t, i);
            steps += s;
            in_advance += a;
            sum += v;
        }
        (steps, in_advance, sum)
    });
    assert!(sum.is_finite() && steps > 300, "{steps} physics steps ran");
    println!(
        "{steps} physics steps in 300 frames with 64 bodies (one held): {in_advance} \
         allocations inside Floaters::advance ({:.2} a step, all rapier's), {} outside",
        in_advance as f64 / steps as f64,
        n - in_advance
    );
    assert_eq!(
        n - in_advance,
        0,
        "{} heap allocations outside the physics step (simulation, hand, instances)",
        n - in_advance
    );
    assert!(
        in_advance <= RAPIER_ALLOCATIONS_PER_STEP * steps as usize,
        "{in_advance} allocations in {steps} physics steps: more than rapier's own"
    );
}

/// Runs this suite (`main.rs` calls it).
pub fn main() {
    crate::run(
        "steady_state_frames_do_not_allocate",
        steady_state_frames_do_not_allocate,
    );
}
