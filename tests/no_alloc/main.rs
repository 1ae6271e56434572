//! No heap allocation per frame in the steady state of the simulation, the LOD, the physics,
//! the sound and the renderer. Each suite counts allocations with the counting global
//! allocator, which sees every thread of the process: so this target runs without libtest's
//! harness, and each suite in a process of its own (the binary runs itself once per suite),
//! where no thread another suite left behind can allocate while it counts.

#[path = "../common/mod.rs"]
mod common;

mod audio;
mod lod;
mod physics;
mod render;
mod sim;

#[global_allocator]
static GLOBAL: common::Counting = common::Counting;

/// Runs one test of a suite: its name, then `ok` (a failure panics, and the process fails).
pub fn run(name: &str, test: fn()) {
    print!("test {name} ... ");
    test();
    println!("ok");
}

/// The counter counts: a collect allocates, and is seen.
fn the_counter_sees_allocations() {
    let (v, n) = common::count_allocations(|| std::hint::black_box((0..100).collect::<Vec<u64>>()));
    assert_eq!(v.len(), 100);
    assert!(n >= 1);
}

/// The environment variable naming the suite a child process runs.
const SUITE_ENV: &str = "VR_OCEAN_NO_ALLOC_SUITE";

/// The suites, by name.
const SUITES: [(&str, fn()); 5] = [
    ("sim", sim::main),
    ("lod", lod::main),
    ("physics", physics::main),
    ("audio", audio::main),
    ("render", render::main),
];

fn main() {
    if let Ok(name) = std::env::var(SUITE_ENV) {
        let (_, suite) = SUITES
            .iter()
            .find(|(n, _)| *n == name)
            .unwrap_or_else(|| panic!("no suite {name}"));
        suite();
        // Guards the suite's zeros against passing vacuously.
        run("the_counter_sees_allocations", the_counter_sees_allocations);
        return;
    }
    let exe = std::env::current_exe().expect("the test binary's path");
    let mut failed = Vec::new();
    for (name, _) in SUITES {
        let status = std::process::Command::new(&exe)
            .env(SUITE_ENV, name)
            .status()
            .expect("the test binary runs");
        if !status.success() {
            failed.push(name);
        }
    }
    if !failed.is_empty() {
        eprintln!("no_alloc: suites failed: {failed:?}");
        std::process::exit(1);
    }
}
