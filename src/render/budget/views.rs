//! The standard views every headset is priced in (`vr-ocean gpu-budget`) and the calibration
//! times: where the eyes are and where they look.

/// A standard view: where the eyes are and where they look.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StandardView {
    /// Short name (the JSON's `view`).
    pub name: &'static str,
    /// Eye height above the mean sea (m).
    pub height: f32,
    /// Yaw (degrees; 0 looks along −z, the default sun is at −28).
    pub yaw: f32,
    /// Pitch (degrees, negative looks down).
    pub pitch: f32,
}

/// The views every headset is measured in and the calibration runs: standing on the deck
/// facing the horizon, into the sun's glitter, looking down at the water, and 25 m up (a
/// stress view: no eye the app allows is that high).
pub const VIEWS: [StandardView; 4] = [
    StandardView {
        name: "horizon",
        height: 1.7,
        yaw: 0.0,
        pitch: 0.0,
    },
    StandardView {
        name: "glitter",
        height: 1.7,
        yaw: -28.0,
        pitch: -5.0,
    },
    StandardView {
        name: "down",
        height: 1.7,
        yaw: 60.0,
        pitch: -60.0,
    },
    StandardView {
        name: "high",
        height: 25.0,
        yaw: 0.0,
        pitch: -15.0,
    },
];

/// The highest eye the app allows: a standing eye (1.7 m) on the tallest deck
/// (`app::floating::MAX_DECK_HEIGHT`, 8 m; `tests/gpu_budget.rs` holds the two in step), looking
/// out as "high" does. The budget's gate takes it in place of the 25 m stress view (issue 43).
pub const TOP_DECK: StandardView = StandardView {
    name: "top-deck",
    height: 9.7,
    yaw: 0.0,
    pitch: -15.0,
};

/// Under the water (issue 45): a swimmer's head 2 m down looking 15 degrees up, Snell's window
/// in the upper half, the surface's underside and the depths below it.
pub const UNDER: StandardView = StandardView {
    name: "under",
    height: -2.0,
    yaw: 0.0,
    pitch: 15.0,
};

/// At the waterline: the eyes at the mean level looking level, the near plane across the
/// surface (each pixel decides its side), the sky above and the water below.
pub const WATERLINE: StandardView = StandardView {
    name: "waterline",
    height: 0.0,
    yaw: 0.0,
    pitch: 0.0,
};

/// The views `vr-ocean gpu-budget` prices: [`VIEWS`], [`TOP_DECK`], [`UNDER`] and
/// [`WATERLINE`].
pub fn budget_views() -> [&'static StandardView; 7] {
    [
        &VIEWS[0], &VIEWS[1], &VIEWS[2], &VIEWS[3], &TOP_DECK, &UNDER, &WATERLINE,
    ]
}

/// The stress view the gate leaves out: reported, not gated (no user's eye is that high).
pub const STRESS_VIEW: &str = "high";
