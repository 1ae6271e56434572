//! [`Floaters`]: the bodies, the deck and the rapier world they live in; the fixed step;
//! what a renderer draws.

use std::time::Duration;

use glam::{Mat4, Vec2, Vec3};
use rapier3d::prelude::{
    ColliderBuilder, MassProperties, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle,
};

use crate::physics::body::{BodySpec, Hull, FRICTION, MAX_COLUMNS};
use crate::physics::buoyancy::{self, Motion, Water, ADDED_MASS_COEFFICIENT};
use crate::physics::clock::{FixedClock, Ticks};
use crate::physics::convert::{from_rapier, pose_from_rapier, pose_to_rapier, to_rapier};
use crate::physics::error::PhysicsError;
use crate::physics::hands::{drive_to, HandInput};
use crate::physics::impacts::{Impact, Impacts};
use crate::physics::kind::BodyKind;
use crate::physics::slot::{BodyId, BodyState, Slot};
use crate::physics::wakes::Wakes;
use crate::physics::water::{key, WaterSamples};
use crate::physics::{DeckSpec, PhysicsConfig, Pose, MAX_BODIES, PHYSICS_DT};
use crate::sim::interaction::{InteractionConfig, InteractionLayer, WaveSource};
use crate::sim::Surfaces;

/// One body as a renderer draws it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyInstance {
    /// Which body.
    pub id: BodyId,
    /// Which unit mesh: a cube, a cylinder (diameter 1 along y) or the boat hull
    /// ([`crate::physics::body::boat_unit_hull`]), each spanning [-0.5, 0.5]³.
    pub kind: BodyKind,
    /// Full extents (m): the unit mesh's scale.
    pub size: Vec3,
    /// The interpolated pose of the body frame.
    pub pose: Pose,
    /// Model matrix of the unit mesh: translation · rotation · scale(size).
    pub model: Mat4,
    /// Whether a hand holds it (a renderer may highlight it).
    pub held: bool,
}

/// Mechanical energy of the live bodies (J), with their real masses (not the added mass).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy {
    /// Kinetic energy, translation and rotation.
    pub kinetic: f64,
    /// Gravitational potential energy relative to the mean sea level.
    pub potential: f64,
}

/// Floating bodies, the deck and the fixed-step clock. See the [module docs](crate::physics).
pub struct Floaters {
    pub(crate) world: PhysicsWorld,
    config: PhysicsConfig,
    pub(crate) slots: Vec<Slot>,
    pub(crate) water: WaterSamples,
    clock: FixedClock,
    alpha: f32,
    steps: u64,
    pub(crate) throws: u64,
    /// The interaction layer and its sources, when on ([`Floaters::set_interaction`]).
    pub(crate) wakes: Option<Wakes>,
    /// Bodies hitting the water since the last [`Floaters::clear_impacts`].
    pub(crate) impacts: Impacts,
}

impl Floaters {
    /// An empty world (the deck only) after checking `config`.
    pub fn new(config: PhysicsConfig) -> Result<Self, PhysicsError> {
        config.validate()?;
        let mut world = PhysicsWorld::new();
        world.gravity = to_rapier(Vec3::new(0.0, -config.gravity, 0.0));
        world.integration_parameters.dt = PHYSICS_DT;
        if let Some(deck) = &config.deck {
            world.insert(
                RigidBodyBuilder::fixed().translation(to_rapier(deck.slab_centre())),
                ColliderBuilder::cuboid(
                    0.5 * deck.size[0],
                    0.5 * deck.thickness,
                    0.5 * deck.size[1],
                )
                .friction(FRICTION),
            );
        }
        Ok(Self {
            world,
            config,
            slots: Vec::with_capacity(MAX_BODIES),
            water: WaterSamples::new(),
            clock: FixedClock::new(PHYSICS_DT as f64),
            alpha: 0.0,
            steps: 0,
            throws: 0,
            wakes: None,
            impacts: Impacts::new(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &PhysicsConfig {
        &self.config
    }

    /// The deck, if any: a renderer draws a unit cube with [`DeckSpec::model`].
    pub fn deck(&self) -> Option<DeckSpec> {
        self.config.deck
    }

    /// Adds a body at `pose` (at rest). Refused when the world is full, the pose is not
    /// finite, or the body would overlap the deck or another body.
    pub fn spawn(&mut self, spec: BodySpec, pose: Pose) -> Result<BodyId, PhysicsError> {
        let slot = match self.slots.iter().position(|s| s.state == BodyState::Sunk) {
            Some(i) => i,
            None if self.slots.len() < MAX_BODIES => self.slots.len(),
            None => {
                return Err(PhysicsError::TooManyBodies {
                    requested: self.slots.len() + 1,
                    limit: MAX_BODIES,
                })
            }
        };
        self.check_placement(&spec, &pose, None)?;
        self.place(slot, spec, pose);
        Ok(BodyId(slot))
    }

    /// Whether `spec` at `pose` is finite and clear of the deck (boxes) and of the live bodies
    /// other than `ignore` (bounding spheres).
    pub(crate) fn check_placement(
        &self,
        spec: &BodySpec,
        pose: &Pose,
        ignore: Option<usize>,
    ) -> Result<(), PhysicsError> {
        let p = pose.position;
        let fail = |reason| PhysicsError::CannotPlace {
            kind: spec.kind(),
            position: p.to_array(),
            reason,
        };
        if !pose.is_finite() {
            return Err(fail(
                "the position or rotation is not finite: give finite numbers and a unit rotation",
            ));
        }
        if p.abs().max_element() > 1.0e5 {
            return Err(fail(
                "farther than 100 km from the origin: place it within 100 km",
            ));
        }
        let r = spec.bounding_radius();
        if let Some(deck) = &self.config.deck {
            // The body's box, turned, against the deck's: overlapping on every axis (by more
            // than a millimetre: resting on the deck is fine).
            let m = glam::Mat3::from_quat(pose.rotation);
            let h = 0.5 * spec.size();
            let reach = m.x_axis.abs() * h.x + m.y_axis.abs() * h.y + m.z_axis.abs() * h.z;
            let half = Vec3::new(deck.size[0], deck.thickness, deck.size[1]) * 0.5;
            let gap = (p - deck.slab_centre()).abs() - half - reach;
            if gap.max_element() < -1e-3 {
                return Err(fail(
                    "it would overlap the deck: place it beside the deck or on top of it",
                ));
            }
        }
        let hit = self.slots.iter().enumerate().any(|(i, s)| {
            Some(i) != ignore
                && s.state != BodyState::Sunk
                && s.curr.position.distance(p) < r + s.spec.bounding_radius()
        });
        if hit {
            return Err(fail(
                "it would overlap another body: leave their bounding spheres apart, or use \
                 spawn_around to find free water",
            ));
        }
        Ok(())
    }

    /// Puts a new rapier body for `spec` at `pose` into `slot` (replacing what was there).
    pub(crate) fn place(&mut self, slot: usize, spec: BodySpec, pose: Pose) {
        let collider = spec.collider().build();
        let solid = collider.mass_properties();
        let mass = solid.mass();
        // Added mass: C_a times the water the body displaces afloat (see `buoyancy`).
        let displaced = mass.min(self.config.water_density * spec.volume());
        let added = ADDED_MASS_COEFFICIENT * displaced;
        let body = RigidBodyBuilder::dynamic()
            .pose(pose_to_rapier(&pose))
            .can_sleep(false)
            .additional_mass_properties(MassProperties::new(
                solid.local_com,
                added,
                rapier3d::math::Vector::ZERO,
            ))
            .gravity_scale(mass / (mass + added));
        let (handle, _) = self.world.insert(body, collider);
        let fresh = Slot {
            spec,
            hull: Hull::of(&spec),
            handle,
            state: BodyState::Floating,
            prev: pose,
            curr: pose,
            flow: Vec2::ZERO,
            mass,
            added,
            inv_inertia: solid.inv_principal_inertia.max_element(),
            hold: None,
            submerged: 0.0,
            first_sample: 0,
            thrown: 0,
            motor: None,
        };
        if slot < self.slots.len() {
            let old = std::mem::replace(&mut self.slots[slot], fresh);
            self.remove_rapier_body(old.handle);
        } else {
            self.slots.push(fresh);
        }
        self.water.forget(slot);
    }

    fn remove_rapier_body(&mut self, handle: RigidBodyHandle) {
        self.world.remove_body(handle);
    }

    /// Runs the fixed steps a frame of `frame_dt` owes (0..=
    /// [`MAX_CATCH_UP_STEPS`](crate::physics::clock::MAX_CATCH_UP_STEPS)), all reading
    /// `surfaces`, and sets the interpolation fraction for [`Floaters::instances`].
    pub fn advance(&mut self, frame_dt: Duration, surfaces: &Surfaces) -> Ticks {
        let ticks = self.clock.advance(frame_dt);
        for _ in 0..ticks.steps {
            self.step(surfaces);
        }
        self.alpha = ticks.alpha;
        ticks
    }

    /// One fixed step of [`PHYSICS_DT`]: the water's forces from `surfaces`, held bodies
    /// driven to their hands, rapier's step, sinking. [`Floaters::advance`] calls it; tests
    /// and benches may call it directly.
    pub fn step(&mut self, surfaces: &Surfaces) {
        self.steps += 1;
        // 1. Every floating body's sample points, one query.
        self.water.begin();
        for (i, s) in self.slots.iter_mut().enumerate() {
            s.prev = s.curr;
            if s.state == BodyState::Floating {
                s.first_sample = self.water.len();
                for (j, c) in s.hull.columns().iter().enumerate() {
                    let [x, z] = buoyancy::sample_point(&s.curr, c);
                    self.water.push(key(i, j), x, z);
                }
            }
        }
        self.water.query(surfaces);
        // The interaction layer's waves (not the body's own hollow: `wakes`).
        if let Some(w) = &self.wakes {
            for (i, s) in self.slots.iter().enumerate() {
                if s.state == BodyState::Floating {
                    // Their mean over the hull lifts and lowers it; their tilt is not applied
                    // (the hollow's own asymmetry as the body moves pushed a buoy 4 m in 20 s).
                    let n = s.hull.columns().len();
                    let range = s.first_sample..s.first_sample + n;
                    let mean = range
                        .clone()
                        .map(|k| w.height_for(i, self.water.point(k)))
                        .sum::<f32>()
                        / n.max(1) as f32;
                    for k in range {
                        self.water.add_height(k, mean);
                    }
                }
            }
        }

        // 2. Forces.
        let water = Water {
            density: self.config.water_density,
            gravity: self.config.gravity,
            dt: PHYSICS_DT,
        };
        let (mut heights, mut rates) = ([0.0f32; MAX_COLUMNS], [0.0f32; MAX_COLUMNS]);
        // Launched boats in the water: their velocity, for their motors below.
        let mut motors: [Option<Vec3>; MAX_BODIES] = [None; MAX_BODIES];
        for (i, s) in self.slots.iter_mut().enumerate() {
            let Some(rb) = self.world.bodies.get_mut(s.handle) else {
                continue;
            };
            rb.reset_forces(false);
            rb.reset_torques(false);
            match s.state {
                BodyState::Sunk => {}
                BodyState::Held => {
                    self.impacts.lift(i);
                    if let Some(hold) = &s.hold {
                        let (v, w) = drive_to(&s.curr, &hold.target);
                        rb.set_linvel(to_rapier(v), true);
                        rb.set_angvel(to_rapier(w), true);
                    }
                }
                BodyState::Floating => {
                    let n = s.hull.columns().len();
                    for c in 0..n {
                        let h = self.water.height(s.first_sample + c);
                        heights[c] = h;
                        rates[c] = self.water.rate(key(i, c));
                    }
                    let motion = Motion {
                        pose: s.curr,
                        com: from_rapier(rb.center_of_mass()),
                        linvel: from_rapier(rb.linvel()),
                        angvel: from_rapier(rb.angvel()),
                        mass: s.mass + s.added,
                        inv_inertia: s.inv_inertia,
                    };
                    let f = buoyancy::water_forces(
                        &s.hull,
                        &motion,
                        &heights[..n],
                        &rates[..n],
                        s.flow,
                        &water,
                    );
                    s.flow = f.flow;
                    s.submerged = f.submerged;
                    // The added mass's weight where the body is out of the water (see
                    // `buoyancy`): it falls at g in the air.
                    let wet =
                        (f.submerged / (s.hull.area() * buoyancy::WET_LENGTH)).clamp(0.0, 1.0);
                    let dry_weight = s.added * water.gravity * (1.0 - wet);
                    rb.add_force(to_rapier(f.force - Vec3::Y * dry_weight), true);
                    let size = s.spec.size();
                    let impact = Impact {
                        time: self.steps as f64 * PHYSICS_DT as f64,
                        position: s.curr.position,
                        speed: -rb.linvel().y,
                        mass: s.mass,
                        radius: 0.25 * (size.x + size.z),
                    };
                    self.impacts.observe(i, wet, impact);
                    if s.motor.is_some() && wet > 0.0 {
                        motors[i] = Some(from_rapier(rb.linvel()));
                    }
                    rb.add_torque(to_rapier(f.torque), true);
                }
            }
        }

        for (i, v) in motors.iter().enumerate() {
            if let Some(v) = v {
                let force = self.motor_force(i, *v);
                if let Some(rb) = self.world.bodies.get_mut(self.slots[i].handle) {
                    rb.add_force(to_rapier(force), true);
                }
            }
        }

        // 3. Integrate and collide.
        self.world.step();

        // 4. New poses; sinking.
        let floor = -self.config.floor_depth;
        for i in 0..self.slots.len() {
            let s = &mut self.slots[i];
            if s.state == BodyState::Sunk {
                continue;
            }
            let Some(rb) = self.world.bodies.get_mut(s.handle) else {
                continue;
            };
            s.curr = pose_from_rapier(rb.position());
            let lost = !s.curr.is_finite() || !rb.is_enabled();
            if lost || rb.center_of_mass().y < floor {
                rb.set_enabled(false);
                s.state = BodyState::Sunk;
                s.hold = None;
                self.water.forget(i);
            }
        }

        // 5. The interaction layer: the bodies' new poses press and splash it.
        if let Some(w) = &mut self.wakes {
            let bodies = &self.world.bodies;
            w.step(&self.slots, |s| {
                bodies
                    .get(s.handle)
                    .map_or(Vec3::ZERO, |rb| from_rapier(rb.linvel()))
            });
        }
    }

    /// Water sample points of the last step and the fixed-point iterations their height
    /// queries took (see [`crate::physics::water`]).
    pub fn last_query_cost(&self) -> (usize, usize) {
        (self.water.len(), self.water.iterations())
    }

    /// Fixed steps run so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Simulated time (s): steps × [`PHYSICS_DT`].
    pub fn time(&self) -> f64 {
        self.steps as f64 * PHYSICS_DT as f64
    }

    /// The interpolation fraction of the last [`Floaters::advance`].
    pub fn alpha(&self) -> f32 {
        self.alpha
    }

    /// Slots in use (live and sunk).
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// Whether no body was ever added.
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// Every body's id (live and sunk), in slot order.
    pub fn ids(&self) -> impl Iterator<Item = BodyId> + '_ {
        (0..self.slots.len()).map(BodyId)
    }

    /// Bodies not sunk.
    pub fn live(&self) -> usize {
        self.slots
            .iter()
            .filter(|s| s.state != BodyState::Sunk)
            .count()
    }

    pub(crate) fn slot(&self, id: BodyId) -> Result<&Slot, PhysicsError> {
        self.slots
            .get(id.0)
            .filter(|s| s.state != BodyState::Sunk)
            .ok_or(PhysicsError::NoSuchBody { id: id.0 })
    }

    /// A body's spec (also for sunk ones).
    pub fn spec(&self, id: BodyId) -> Option<BodySpec> {
        self.slots.get(id.0).map(|s| s.spec)
    }

    /// A body's state.
    pub fn state(&self, id: BodyId) -> Option<BodyState> {
        self.slots.get(id.0).map(|s| s.state)
    }

    /// A body's pose after the last step.
    pub fn pose(&self, id: BodyId) -> Option<Pose> {
        self.slot(id).ok().map(|s| s.curr)
    }

    /// A body's pose between the last two steps by the last [`Floaters::advance`]'s fraction:
    /// where to draw it.
    pub fn interpolated_pose(&self, id: BodyId) -> Option<Pose> {
        self.slot(id).ok().map(|s| s.prev.lerp(&s.curr, self.alpha))
    }

    /// A body's linear (m/s) and angular (rad/s) velocity.
    pub fn velocity(&self, id: BodyId) -> Option<(Vec3, Vec3)> {
        let s = self.slot(id).ok()?;
        let rb = self.world.bodies.get(s.handle)?;
        Some((from_rapier(rb.linvel()), from_rapier(rb.angvel())))
    }

    /// A body's centre of mass (m).
    pub fn center_of_mass(&self, id: BodyId) -> Option<Vec3> {
        let s = self.slot(id).ok()?;
        Some(from_rapier(
            self.world.bodies.get(s.handle)?.center_of_mass(),
        ))
    }

    /// A body's submerged volume at the last step, as the water forces saw it (m³).
    pub fn submerged_volume(&self, id: BodyId) -> Option<f32> {
        self.slot(id).ok().map(|s| s.submerged)
    }

    /// What to draw: every live body, interpolated. Allocates nothing.
    pub fn instances(&self) -> impl Iterator<Item = BodyInstance> + '_ {
        self.slots
            .iter()
            .enumerate()
            .filter(|(_, s)| s.state != BodyState::Sunk)
            .map(|(i, s)| {
                let pose = s.prev.lerp(&s.curr, self.alpha);
                let size = s.spec.size();
                BodyInstance {
                    id: BodyId(i),
                    kind: s.spec.kind(),
                    size,
                    pose,
                    model: pose.matrix() * Mat4::from_scale(size),
                    held: s.state == BodyState::Held,
                }
            })
    }

    /// Mechanical energy of the live bodies, real masses only.
    pub fn energy(&self) -> Energy {
        let mut e = Energy::default();
        for s in self.slots.iter().filter(|s| s.state != BodyState::Sunk) {
            let Some(rb) = self.world.bodies.get(s.handle) else {
                continue;
            };
            let v2 = rb.linvel().length_squared();
            // rapier's energy counts the added mass in the translation: take it out.
            let rotation = rb.kinetic_energy() - 0.5 * (s.mass + s.added) * v2;
            e.kinetic += (0.5 * s.mass * v2 + rotation.max(0.0)) as f64;
            e.potential += (s.mass * self.config.gravity * rb.center_of_mass().y) as f64;
        }
        e
    }

    /// Bodies that hit the water since the last [`Floaters::clear_impacts`] (at most
    /// [`MAX_IMPACTS`](crate::physics::impacts::MAX_IMPACTS)), in step order.
    pub fn impacts(&self) -> &[Impact] {
        self.impacts.events()
    }

    /// Forgets the impacts read.
    pub fn clear_impacts(&mut self) {
        self.impacts.clear();
    }

    /// Turns the interaction layer on (`Some`: bodies and hands make waves, and feel them) or
    /// off, centred on `centre` (world x, z).
    pub fn set_interaction(&mut self, config: Option<InteractionConfig>, centre: Vec2) {
        self.wakes = config.map(|c| Wakes::new(c, centre));
    }

    /// The interaction layer, when on.
    pub fn interaction(&self) -> Option<&InteractionLayer> {
        self.wakes.as_ref().map(|w| &w.layer)
    }

    /// Where the layer should be centred from the next step on (the viewer, world x, z).
    pub fn follow(&mut self, centre: Vec2) {
        if let Some(w) = &mut self.wakes {
            w.follow(centre);
        }
    }

    /// Adds a disturbance to the next step (dropped beyond
    /// [`MAX_HAND_SOURCES`](crate::physics::wakes::MAX_HAND_SOURCES) a step, or when the
    /// layer is off).
    pub fn disturb(&mut self, source: WaveSource) {
        if let Some(w) = &mut self.wakes {
            w.disturb(source);
        }
    }

    /// A floating user whose head is at `head`, moving at `velocity` (m/s): the body under the
    /// head (its shoulders 0.25 m under the eyes) presses on the water with its volume and,
    /// swimming, with its dynamic pressure ρv²/2 over its frontal area, so it makes waves and
    /// a wake as the hands do. Returns whether the body is in the water (its disturbance then
    /// goes into the next step). Its own hollow in the layer is not read (as for the bodies:
    /// reading it, it would sink into it).
    pub fn wade(&mut self, head: Vec3, velocity: Vec3, surfaces: &Surfaces) -> bool {
        let g = self.config.gravity;
        self.wakes
            .as_mut()
            .is_some_and(|w| w.wade(head, velocity, surfaces, g))
    }

    /// A hand (controller) at `input` in the water of `surfaces`: when it is below the surface
    /// (the sea's and the layer's height), its disturbance goes into the next step and this
    /// returns true. The hand presses with its volume and, moving, with its dynamic pressure
    /// ρv²/2 over its cross-section; plunging in, it pushes the water down.
    pub fn dip(&mut self, input: &HandInput, surfaces: &Surfaces) -> bool {
        let g = self.config.gravity;
        self.wakes
            .as_mut()
            .is_some_and(|w| w.dip(input, surfaces, g))
    }
}
