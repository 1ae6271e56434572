//! Bad input to the physics is a clear error that says what to change, never a panic.

use crate::common;

use glam::{Vec2, Vec3};
use vr_ocean::physics::{
    BodyCount, BodySpec, Floaters, PhysicsConfig, PhysicsError, Pose, MAX_BODIES,
};
use vr_ocean::sim::{OceanConfig, Surfaces};

fn calm() -> Surfaces {
    Surfaces::new(&OceanConfig::single(64, 100.0).unwrap())
}

#[test]
fn too_many_bodies_names_the_option_and_the_limit() {
    let e = BodyCount::new(MAX_BODIES + 1).unwrap_err();
    assert_eq!(
        e,
        PhysicsError::TooManyBodies {
            requested: 65,
            limit: 64
        }
    );
    assert_eq!(
        e.to_string(),
        "--bodies 65: at most 64 floating bodies (0 = none)"
    );
    // A full world refuses one more, by spawn and by spawn_around.
    let mut w = Floaters::new(PhysicsConfig::default()).unwrap();
    w.spawn_around(BodyCount::new(64).unwrap(), Vec2::ZERO, &calm())
        .unwrap();
    let spec = BodySpec::crate_box(Vec3::splat(0.3), 400.0).unwrap();
    let e = w
        .spawn(spec, Pose::at(Vec3::new(500.0, 0.0, 0.0)))
        .unwrap_err();
    assert!(
        matches!(e, PhysicsError::TooManyBodies { limit: 64, .. }),
        "{e}"
    );
    let e = w
        .spawn_around(BodyCount::new(1).unwrap(), Vec2::ZERO, &calm())
        .unwrap_err();
    assert!(e.to_string().contains("at most 64"), "{e}");
}

#[test]
fn a_body_that_cannot_be_placed_says_why_and_what_to_do() {
    let mut w = Floaters::new(PhysicsConfig::default()).unwrap();
    let deck = w.deck().unwrap();
    let spec = BodySpec::crate_box(Vec3::splat(0.5), 400.0).unwrap();
    // Inside the deck slab.
    let e = w
        .spawn(spec, Pose::at(Vec3::new(0.0, deck.height - 0.1, 0.0)))
        .unwrap_err();
    println!("{e}");
    assert!(matches!(e, PhysicsError::CannotPlace { .. }));
    assert!(e
        .to_string()
        .contains("overlap the deck: place it beside the deck or on top"));
    // Resting on top of it is fine.
    w.spawn(spec, Pose::at(Vec3::new(0.0, deck.height + 0.25, 0.0)))
        .unwrap();
    // On another body.
    let e = w
        .spawn(spec, Pose::at(Vec3::new(0.1, deck.height + 0.3, 0.0)))
        .unwrap_err();
    println!("{e}");
    assert!(e.to_string().contains("overlap another body"), "{e}");
    // Not a number.
    let e = w
        .spawn(spec, Pose::at(Vec3::new(f32::NAN, 0.0, 0.0)))
        .unwrap_err();
    println!("{e}");
    assert!(
        e.to_string().contains("not finite: give finite numbers"),
        "{e}"
    );
    let e = w
        .spawn_around(
            BodyCount::new(2).unwrap(),
            Vec2::new(f32::INFINITY, 0.0),
            &calm(),
        )
        .unwrap_err();
    assert_eq!(
        e,
        PhysicsError::NotFinite {
            what: "spawn centre"
        }
    );
    // Nothing of that was added.
    assert_eq!(w.live(), 1);
}

#[test]
fn out_of_range_bodies_and_worlds_name_the_valid_range() {
    let e = BodySpec::crate_box(Vec3::new(0.5, 20.0, 0.5), 400.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "body size y 20: must be finite and 0.05 to 10 m"
    );
    let e = BodySpec::buoy(0.5, 0.5, -3.0).unwrap_err();
    assert!(
        e.to_string()
            .contains("body density -3: must be 10 to 20000 kg/m³"),
        "{e}"
    );
    let bad = PhysicsConfig {
        floor_depth: 0.0,
        ..PhysicsConfig::default()
    };
    let e = Floaters::new(bad).err().unwrap();
    assert_eq!(e.to_string(), "floor depth 0: must be 1 to 10000 m");
    let e = PhysicsConfig::with_deck_height(f32::NAN)
        .validate()
        .unwrap_err();
    assert!(e.to_string().starts_with("deck height NaN"), "{e}");
}

#[test]
fn the_bodies_option_is_checked_before_anything_opens() {
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("physics_cli_rejected");
    let out_s = out.to_str().unwrap();
    for cmd in [vec!["headless", "--out", out_s], vec!["window"], vec!["xr"]] {
        let with = |extra: &[&'static str]| -> Vec<&str> {
            let mut v = cmd.clone();
            v.extend_from_slice(extra);
            v
        };
        common::assert_rejected(
            &with(&["--bodies", "65"]),
            &["--bodies 65: at most 64 floating bodies (0 = none)"],
        );
        common::assert_rejected(&with(&["--bodies=-1"]), &["--bodies"]);
    }
    assert!(!out.exists(), "nothing written for a rejected run");
}
