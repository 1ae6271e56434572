//! The export's scripted disturbances (`vr-ocean export --impulse X,Z --tow SPEED`): a 1 m
//! sphere dropped at t = 0, a 1 m float towed along +x from the origin, the layer following
//! the float (or centred on the drop). Reproducible: a pure function of the options and time.

use super::{InteractionConfig, InteractionLayer, WaveSource};

/// Density of the dropped sphere (kg/m³): a wooden ball, half under once afloat.
pub const DROPPED_DENSITY: f32 = 500.0;

/// The dropped sphere's speed as it meets the water (m/s): a fall of about half a metre.
pub const ENTRY_SPEED: f32 = 3.0;

/// Density of the towed float (kg/m³): a fender ball, a tenth under. A denser one makes waves
/// steep enough to break, and the breaking, not the dispersion, then shapes its wake.
pub const TOWED_DENSITY: f32 = 100.0;

/// Diameter of both spheres (m).
pub const SPHERE_DIAMETER: f32 = 1.0;

/// What to do to the layer.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Scenario {
    /// Drop a sphere here (world x, z, m) at t = 0; it then floats there.
    pub impulse: Option<[f32; 2]>,
    /// Tow a float along +x from the origin at this speed (m/s).
    pub tow: Option<f32>,
}

impl Scenario {
    /// The sources of step `step` (time step·dt), into `out` (cleared first).
    pub fn sources(&self, step: u64, dt: f32, out: &mut Vec<WaveSource>) {
        out.clear();
        if let Some([x, z]) = self.impulse {
            let mut s = WaveSource::floating_sphere(x, z, SPHERE_DIAMETER, DROPPED_DENSITY);
            if step == 0 {
                // The entry: the water under it pushed down at the entry speed over about its
                // radius (the potential of a sphere moving at w is w·R/2 at its surface).
                s.impulse = 0.5 * ENTRY_SPEED * s.radius;
                s.foam = 1.0;
            }
            out.push(s);
        }
        if let Some([x, z]) = self.towed_at(step as f64 * dt as f64) {
            out.push(WaveSource::floating_sphere(
                x,
                z,
                SPHERE_DIAMETER,
                TOWED_DENSITY,
            ));
        }
    }

    /// Where the towed float is at time `t` (s), if one is towed.
    pub fn towed_at(&self, t: f64) -> Option<[f32; 2]> {
        self.tow.map(|v| [(v as f64 * t) as f32, 0.0])
    }

    /// The point the layer is centred on at time `t`, and the source the export reports:
    /// the towed float, else the drop point.
    pub fn centre_at(&self, t: f64) -> [f32; 2] {
        self.towed_at(t).or(self.impulse).unwrap_or([0.0; 2])
    }
}

/// A layer driven by a [`Scenario`].
pub struct ScenarioRun {
    scenario: Scenario,
    layer: InteractionLayer,
    steps: u64,
    sources: Vec<WaveSource>,
}

impl ScenarioRun {
    /// A calm layer centred where the scenario starts.
    pub fn new(config: InteractionConfig, scenario: Scenario) -> Self {
        let [x, z] = scenario.centre_at(0.0);
        Self {
            scenario,
            layer: InteractionLayer::new(config, x, z),
            steps: 0,
            sources: Vec::with_capacity(2),
        }
    }

    /// Steps until the layer's time is the step nearest `t` (s); never backwards.
    pub fn advance_to(&mut self, t: f64) {
        let dt = self.layer.config().dt;
        let target = (t / dt as f64).round().max(0.0) as u64;
        while self.steps < target {
            let now = self.steps as f64 * dt as f64;
            let [x, z] = self.scenario.centre_at(now);
            self.layer.recentre(x, z);
            self.scenario.sources(self.steps, dt, &mut self.sources);
            self.layer.step(&self.sources);
            self.steps += 1;
        }
    }

    /// The layer.
    pub fn layer(&self) -> &InteractionLayer {
        &self.layer
    }

    /// The scenario.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }
}
