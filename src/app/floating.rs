//! The app's floating bodies: the physics world ([`Floaters`]) hosted in the frame loop, the
//! user's hands and throw key applied to it, and what the renderer draws of it (the bodies and
//! the deck as [`Solid`]s).
//!
//! Each frame, after the simulation's surfaces for the frame are in: the hands are applied,
//! then [`Floaters::advance`] runs the fixed steps the frame's period holds (reading those
//! surfaces), then the interpolated poses become this frame's solids. The world is made on the
//! first frame, where the deck can be put under the viewer and the bodies need a sea to float
//! at their draft; a body that drifts out of sight is brought back (see [`RESPAWN_DISTANCE`]).
//! Nothing here allocates per frame in steady state (rapier's own step aside: see
//! `tests/no_alloc/physics.rs`).

use std::time::Duration;

use glam::{Vec2, Vec3};

use crate::lod::QualityPreset;
use crate::physics::hands::GRAB_REACH;
use crate::physics::impacts::MAX_IMPACTS;
use crate::physics::{
    BodyCount, BodyKind, Floaters, Hand, HandEvent, HandInput, HandState, Impact, PhysicsConfig,
    PhysicsError, PHYSICS_DT,
};
use crate::render::ocean::{Solid, SolidKind, MAX_SOLIDS};
use crate::sim::interaction::InteractionConfig;
use crate::sim::Surfaces;
use crate::xr::FrameState;

/// Speed of a crate thrown with the window's throw key (m/s): an easy underarm throw.
pub const THROW_SPEED: f32 = 9.0;

/// Speed of a crate the panel's spawn button drops in front of the user (m/s): a gentle
/// toss that lands a few metres out.
pub const DROP_SPEED: f32 = 3.0;

/// A body farther than this from the viewer (horizontally, m) has drifted out of the scene
/// and is put back on the water near the viewer: the sea's drift and throws would otherwise
/// empty it over a long session.
pub const RESPAWN_DISTANCE: f32 = 150.0;

/// Height of a standing user's eyes above the floor (m): where a desktop view's deck goes.
pub const EYE_HEIGHT: f32 = 1.7;

/// The lowest deck (its top, m above the mean sea level) put under a desktop view: below it
/// the waves would wash over it, so a head lower than this plus [`EYE_HEIGHT`] (a path along
/// the shore) gets no deck.
pub const MIN_DECK_HEIGHT: f32 = 1.0;

/// The highest: a big ship's deck. A head higher than this plus [`EYE_HEIGHT`] (an aerial
/// path) is not standing on anything, so it gets no deck.
pub const MAX_DECK_HEIGHT: f32 = 8.0;

/// Where the deck goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DeckPlacement {
    /// Centred on the origin, its top at this height (m): the OpenXR tracking floor.
    At(f32),
    /// Under the first frame's head, [`EYE_HEIGHT`] below it (desktop views: the window's
    /// start, a camera path's first key); none when that is outside [`MIN_DECK_HEIGHT`] to
    /// [`MAX_DECK_HEIGHT`].
    UnderViewer,
}

/// What a run floats.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloatOptions {
    /// Bodies spawned around the viewer (0 = none; the deck is still drawn).
    pub bodies: BodyCount,
    /// Where the deck goes.
    pub deck: DeckPlacement,
    /// The interaction layer (splashes, rings, wakes), or `None` for off.
    pub interaction: Option<InteractionConfig>,
}

/// The interaction layer for a quality preset: 256² cells of 0.16 m (41 m) from `High` up,
/// 128² of 0.24 m (31 m) at `Medium` (the Quest's), 128² of 0.32 m (41 m) at `Low`. A 128²
/// step costs about a fifth of a 256² one (`benches/interaction.rs`).
pub fn interaction_for(preset: QualityPreset) -> InteractionConfig {
    let (cells, cell_m) = match preset {
        QualityPreset::Low => (128, 0.32),
        QualityPreset::Medium => (128, 0.24),
        QualityPreset::High | QualityPreset::Ultra => (256, 0.16),
    };
    InteractionConfig::new(cells, cell_m, PHYSICS_DT).expect("the presets' layers are valid")
}

/// The physics world of a run and what it draws.
pub struct Afloat {
    opts: FloatOptions,
    /// Made on the first frame.
    world: Option<Floaters>,
    hands: [Hand; 2],
    /// Whether each hand was in the water last frame (a haptic tick as it goes in).
    wet: [bool; 2],
    /// The floating user's head last frame (its velocity drives the body's wake).
    swimmer: Option<Vec3>,
    solids: Vec<Solid>,
    /// This frame's impacts (bodies and hands), timed on the frames' clock.
    impacts: Vec<Impact>,
}

/// A hand plunging into the water, as an impact: a hand and forearm's mass and size.
const HAND_MASS: f32 = 0.6;
const HAND_SIZE: f32 = 0.05;

impl Afloat {
    /// Checks `opts`; the world is made on the first frame.
    pub fn new(opts: &FloatOptions) -> Result<Self, PhysicsError> {
        if let DeckPlacement::At(h) = opts.deck {
            PhysicsConfig::with_deck_height(h).validate()?;
        }
        Ok(Self {
            opts: *opts,
            world: None,
            hands: [Hand::new(); 2],
            wet: [false; 2],
            swimmer: None,
            solids: Vec::with_capacity(MAX_SOLIDS),
            impacts: Vec::with_capacity(MAX_IMPACTS + 2),
        })
    }

    /// The physics world, once the first frame made it.
    pub fn world(&self) -> Option<&Floaters> {
        self.world.as_ref()
    }

    /// The physics world, mutably, once the first frame made it.
    pub fn world_mut(&mut self) -> Option<&mut Floaters> {
        self.world.as_mut()
    }

    /// The world for the first frame's head at `viewer`, with its bodies around it.
    fn make_world(&self, viewer: Vec3, surfaces: &Surfaces) -> Result<Floaters, PhysicsError> {
        let mut config = PhysicsConfig::default();
        match self.opts.deck {
            DeckPlacement::At(h) => config = PhysicsConfig::with_deck_height(h),
            DeckPlacement::UnderViewer => {
                let top = viewer.y - EYE_HEIGHT;
                config.deck = config
                    .deck
                    .filter(|_| (MIN_DECK_HEIGHT..=MAX_DECK_HEIGHT).contains(&top))
                    .map(|mut d| {
                        d.height = top;
                        d.centre = [viewer.x, viewer.z];
                        d
                    });
            }
        }
        let mut world = Floaters::new(config)?;
        world.set_interaction(self.opts.interaction, Vec2::new(viewer.x, viewer.z));
        world.spawn_around(self.opts.bodies, Vec2::new(viewer.x, viewer.z), surfaces)?;
        Ok(world)
    }

    /// One frame: spawn (first frame), hands, fixed steps for the frame's period on
    /// `surfaces`, respawn what drifted away, and this frame's solids. Returns the hands that
    /// grabbed something or went into the water this frame (a haptic tick each).
    pub fn advance(
        &mut self,
        frame: &FrameState,
        surfaces: &Surfaces,
    ) -> Result<[bool; 2], PhysicsError> {
        let viewer = (frame.views[0].position + frame.views[1].position) * 0.5;
        let world = match self.world.take() {
            Some(w) => w,
            None => self.make_world(viewer, surfaces)?,
        };
        let world = self.world.insert(world);
        let mut ticks = [false; 2];
        let mut hand_in = [None; 2];
        world.follow(Vec2::new(viewer.x, viewer.z));
        for (i, ((hand, input), tick)) in self
            .hands
            .iter_mut()
            .zip(&frame.hands)
            .zip(&mut ticks)
            .enumerate()
        {
            *tick = drive_hand(world, hand, input.as_ref());
            let wet = input.is_some_and(|input| world.dip(&input, surfaces));
            *tick |= wet && !self.wet[i];
            if let (true, false, Some(input)) = (wet, self.wet[i], input.as_ref()) {
                hand_in[i] = Some(Impact {
                    time: frame.predicted_display_time,
                    position: input.pose.position,
                    speed: (-input.linvel.y).max(0.0),
                    mass: HAND_MASS,
                    radius: HAND_SIZE,
                });
            }
            self.wet[i] = wet;
        }
        // A floating user's body makes waves too, and a wake as it swims.
        let last = std::mem::take(&mut self.swimmer);
        if frame.in_water {
            let dt = frame.period.max(1e-4) as f32;
            let velocity = last.map_or(Vec3::ZERO, |p| (viewer - p) / dt);
            world.wade(viewer, velocity, surfaces);
            self.swimmer = Some(viewer);
        }
        world.advance(Duration::from_secs_f64(frame.period.max(0.0)), surfaces);
        // The bodies' impacts, from the physics clock to the frames' (the step that ends
        // last is at most one step behind this frame's time).
        let offset = frame.predicted_display_time - world.time();
        self.impacts.clear();
        for hit in world.impacts() {
            self.impacts.push(Impact {
                time: hit.time + offset,
                ..*hit
            });
        }
        self.impacts.extend(hand_in.into_iter().flatten());
        world.clear_impacts();
        world.bring_back(Vec2::new(viewer.x, viewer.z), RESPAWN_DISTANCE, surfaces);
        self.solids.clear();
        if let Some(deck) = world.deck() {
            self.solids.push(Solid {
                kind: SolidKind::Deck,
                model: deck.model(),
                highlight: false,
            });
        }
        let hovered = |id| {
            self.hands
                .iter()
                .any(|h| matches!(h.state(), HandState::Hovering(b) if b == id))
        };
        // The aim rays to the control panel, where they meet it.
        let rays = frame.rays.iter().flatten();
        self.solids
            .extend(rays.filter_map(|[from, to]| Solid::ray(*from, *to)));
        for b in world.instances() {
            self.solids.push(Solid {
                kind: match b.kind {
                    BodyKind::Buoy => SolidKind::Buoy,
                    BodyKind::Crate => SolidKind::Crate,
                    BodyKind::Boat => SolidKind::Boat,
                },
                model: b.model,
                highlight: b.held || hovered(b.id),
            });
        }
        Ok(ticks)
    }

    /// Throws a crate from the head of `frame` along its view (the window's throw key).
    /// Before the first frame there is no world to throw into: nothing happens.
    pub fn throw(&mut self, frame: &FrameState) -> Result<(), PhysicsError> {
        let Some(world) = self.world.as_mut() else {
            return Ok(());
        };
        let head = (frame.views[0].position + frame.views[1].position) * 0.5;
        let forward = frame.views[0].orientation * Vec3::NEG_Z;
        world.throw_from(head, forward, THROW_SPEED).map(|_| ())
    }

    /// Drops a crate in front of the head of `frame`, tossed gently along the level view (the
    /// panel's spawn button). Before the first frame nothing happens.
    pub fn drop_in_front(&mut self, frame: &FrameState) -> Result<(), PhysicsError> {
        let Some(world) = self.world.as_mut() else {
            return Ok(());
        };
        let head = (frame.views[0].position + frame.views[1].position) * 0.5;
        let view = frame.views[0].orientation * Vec3::NEG_Z;
        let level = Vec3::new(view.x, 0.0, view.z)
            .try_normalize()
            .unwrap_or(Vec3::NEG_Z);
        world.throw_from(head, level, DROP_SPEED).map(|_| ())
    }

    /// Puts the bodies back as the run started them: the world is made again around the
    /// viewer on the next frame (the panel's reset button; allocates, a user's action).
    pub fn reset(&mut self) {
        self.world = None;
        self.hands = [Hand::new(); 2];
        self.wet = [false; 2];
    }

    /// Moves the deck to `height` m above the mean sea level (the panel's comfort): the world
    /// is made again on the next frame with the deck there. Only a deck at a fixed height (the
    /// headset's) moves; the window's follows the viewer.
    pub fn move_deck(&mut self, height: f32) -> Result<(), PhysicsError> {
        if let DeckPlacement::At(_) = self.opts.deck {
            PhysicsConfig::with_deck_height(height).validate()?;
            self.opts.deck = DeckPlacement::At(height);
            self.reset();
        }
        Ok(())
    }

    /// The deck's height above the mean sea level, when it is fixed (the headset's).
    pub fn deck_height(&self) -> Option<f32> {
        match self.opts.deck {
            DeckPlacement::At(h) => Some(h),
            DeckPlacement::UnderViewer => None,
        }
    }

    /// What hit the water during this frame's steps (bodies, then hands going in), with
    /// times on the frames' clock.
    pub fn impacts(&self) -> &[Impact] {
        &self.impacts
    }

    /// This frame's solids: the deck, the aim rays to the panel, then every live body.
    pub fn solids(&self) -> &[Solid] {
        &self.solids
    }
}

/// One hand's frame: its state machine, the command it gives, and whether it grabbed (haptic).
/// A hand without input this frame (not tracked) lets go of nothing and grabs nothing.
fn drive_hand(world: &mut Floaters, hand: &mut Hand, input: Option<&HandInput>) -> bool {
    let Some(input) = input else {
        return false;
    };
    let nearest = world
        .nearest_body(input.pose.position, GRAB_REACH)
        .and_then(|id| world.pose(id).map(|p| (id, p.position)));
    let step = hand.update(input, nearest);
    if let Some(command) = step.command {
        if let Err(e) = world.apply(&command) {
            // The body sank or was replaced under the hand: let go of it.
            log::warn!("hand: {e}");
            hand.cancel();
            return false;
        }
    }
    matches!(step.event, Some(HandEvent::Grabbed(_)))
}
