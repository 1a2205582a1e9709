//! bridge: Cyclone's rope bridge. Twelve particles joined by rods across the deck and
//! cables along it, hung from anchors by support cables, with a movable load whose mass
//! is shared bilinearly among the four nearest particles.

use std::borrow::Cow;

use glam::Vec3;

use super::{
    ActionInfo, CameraHint, LOAD_STEP, Marker, Param, ParamError, ParamTable, ParamValues, Scene,
    SceneAction, SceneEntry, SceneInfo,
};
use crate::physics::{
    Constraint, ContactGenerator, GroundPlane, ParticleDesc, ParticleId, PhysicsError, ResolveReport, World,
};

/// Mass of each deck particle without the load (kg).
pub const BASE_MASS: f32 = 1.0;
/// Maximum lengths of the support cables, particle by particle (m).
pub const SUPPORT_LENGTHS: [f32; 12] = [3.0, 3.0, 3.5, 3.5, 4.0, 4.0, 4.0, 4.0, 3.5, 3.5, 3.0, 3.0];

#[rustfmt::skip]
static PARAMS: &[Param] = &[
    Param { name: Cow::Borrowed("load_x"), unit: Cow::Borrowed(""), default: 0.0, min: 0.0, max: 5.0, help: Cow::Borrowed("Load position along the bridge, from deck pair 0 to deck pair 5"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("load_z"), unit: Cow::Borrowed(""), default: 0.5, min: 0.0, max: 1.0, help: Cow::Borrowed("Load position across the bridge, from one side (0) to the other (1)"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("load_mass"), unit: Cow::Borrowed("kg"), default: 10.0, min: 0.0, max: 50.0, help: Cow::Borrowed("Mass of the load, shared among the four nearest particles"), logarithmic: false, integer: false },
    super::GRAVITY,
];

#[rustfmt::skip]
static ACTIONS: &[ActionInfo] = &[
    ActionInfo { label: "Load left", key: "Left arrow or A", action: SceneAction::MoveLoad { dx: -LOAD_STEP, dz: 0.0 } },
    ActionInfo { label: "Load right", key: "Right arrow or D", action: SceneAction::MoveLoad { dx: LOAD_STEP, dz: 0.0 } },
    ActionInfo { label: "Load back", key: "Up arrow or W", action: SceneAction::MoveLoad { dx: 0.0, dz: -LOAD_STEP } },
    ActionInfo { label: "Load front", key: "Down arrow or S", action: SceneAction::MoveLoad { dx: 0.0, dz: LOAD_STEP } },
];

static INFO: SceneInfo = SceneInfo {
    name: Cow::Borrowed("bridge"),
    summary: Cow::Borrowed("A rope bridge of rods and cables carrying a movable load"),
    dt: 1.0 / 240.0,
    default_steps: 1200,
    params: ParamTable::Static(PARAMS),
    presets: &[],
    actions: ACTIONS,
    trails: false,
    color_by_speed: false,
};

pub(super) const ENTRY: SceneEntry = SceneEntry::Compiled { info: &INFO, create };

fn create(params: ParamValues) -> Box<dyn Scene> {
    let mut world = World::new();
    let g = params.get("g");
    let particles: Vec<ParticleId> = (0..12)
        .map(|i| {
            world
                .add_particle(ParticleDesc {
                    position: Vec3::new((i / 2) as f32 * 2.0 - 5.0, 4.0, (i % 2) as f32 * 2.0 - 1.0),
                    acceleration: Vec3::new(0.0, -g, 0.0),
                    mass: BASE_MASS,
                    damping: 0.9,
                    radius: 0.2,
                    ..ParticleDesc::default()
                })
                .expect("bridge particles are valid")
        })
        .collect();
    let mut add = |generator: ContactGenerator| {
        world
            .add_contact_generator(generator)
            .expect("the bridge's links and ground are constants, all valid");
    };
    for i in 0..6 {
        add(Constraint::rod(particles[2 * i], particles[2 * i + 1], 2.0).into());
    }
    for i in 0..10 {
        add(Constraint::cable(particles[i], particles[i + 2], 1.9, 0.3).into());
    }
    for (i, &max_length) in SUPPORT_LENGTHS.iter().enumerate() {
        let anchor = Vec3::new((i / 2) as f32 * 2.2 - 5.5, 6.0, (i % 2) as f32 * 1.6 - 0.8);
        add(Constraint::support_cable(particles[i], anchor, max_length, 0.5).into());
    }
    add(GroundPlane { height: 0.0, restitution: 0.2 }.into());
    let mut bridge = Bridge { world, params, particles };
    bridge.distribute_load();
    Box::new(bridge)
}

struct Bridge {
    world: World,
    params: ParamValues,
    particles: Vec<ParticleId>,
}

impl Bridge {
    /// The four particles nearest the load with their bilinear weights (summing to 1).
    fn load_shares(&self) -> [(usize, f32); 4] {
        let (x, z) = (self.params.get("load_x"), self.params.get("load_z"));
        let pair = (x.floor() as usize).min(4);
        let along = x - pair as f32;
        [
            (2 * pair, (1.0 - along) * (1.0 - z)),
            (2 * pair + 1, (1.0 - along) * z),
            (2 * pair + 2, along * (1.0 - z)),
            (2 * pair + 3, along * z),
        ]
    }

    fn distribute_load(&mut self) {
        let load = self.params.get("load_mass");
        for &id in &self.particles {
            self.world.particles.set_mass(id, BASE_MASS).expect("base mass is valid");
        }
        for (particle, share) in self.load_shares() {
            let mass = BASE_MASS + load * share;
            self.world.particles.set_mass(self.particles[particle], mass).expect("mass >= base mass");
        }
    }

    fn load_position(&self) -> Vec3 {
        let p = &self.world.particles;
        self.load_shares()
            .iter()
            .filter_map(|&(i, share)| p.index(self.particles[i]).map(|i| p.position[i] * share))
            .sum()
    }
}

impl Scene for Bridge {
    scene_basics!();

    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        if super::set_param_or_gravity(&mut self.params, &mut self.world, name, value)? {
            self.distribute_load();
        }
        Ok(())
    }

    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        self.world.step(dt)
    }

    fn act(&mut self, action: SceneAction) -> bool {
        let SceneAction::MoveLoad { dx, dz } = action else { return false };
        let x = (self.params.get("load_x") + dx).clamp(0.0, 5.0);
        let z = (self.params.get("load_z") + dz).clamp(0.0, 1.0);
        self.params.set("load_x", x).expect("clamped to range");
        self.params.set("load_z", z).expect("clamped to range");
        self.distribute_load();
        true
    }

    fn markers(&self, out: &mut Vec<Marker>) {
        let load = self.params.get("load_mass");
        if load > 0.0 {
            // A sphere whose volume grows with the load, resting on the deck.
            let radius = 0.2 * (load / BASE_MASS).cbrt().max(1.0);
            out.push(Marker {
                position: self.load_position() + Vec3::Y * radius,
                radius,
                color: [0.85, 0.25, 0.1],
            });
        }
    }

    fn labels<'a>(&'a self, out: &mut Vec<(Vec3, &'a str)>) {
        let radius = 0.2 * (self.params.get("load_mass") / BASE_MASS).cbrt().max(1.0);
        out.push((self.load_position() + Vec3::Y * (2.0 * radius + 0.3), "load"));
    }

    fn camera(&self) -> CameraHint {
        CameraHint { target: Vec3::new(0.0, 3.2, 0.0), distance: 14.0, yaw: 0.55, pitch: 0.32 }
    }

    fn readout_rows(&self, _dt: f32) -> Vec<super::Readout> {
        use super::Readout;
        let p = &self.world.particles;
        let lowest = p.position.iter().map(|v| v.y).fold(f32::INFINITY, f32::min);
        let fastest = p.velocity.iter().map(|v| v.length()).fold(0.0, f32::max);
        let penetration = self.world.last_report().max_penetration;
        vec![
            Readout::new("lowest deck point", super::readout::shown(lowest, "m"))
                .with("lowest_m", lowest)
                .help("Height of the lowest particle: how far the load makes the deck sag"),
            Readout::new("fastest particle", super::readout::shown(fastest, "m/s"))
                .with("fastest_m_s", fastest)
                .help("Speed of the fastest particle: near zero once the bridge has settled under its load"),
            Readout::new("max penetration left", super::readout::shown(penetration * 1000.0, "mm"))
                .with("max_penetration_m", penetration)
                .help(
                    "The largest overlap or rod-length error the solver left after its last step: its \
                     residual error, not physics",
                ),
        ]
    }
}
