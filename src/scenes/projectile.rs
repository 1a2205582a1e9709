//! projectile: rounds fired from a launcher. It opens as the textbook's problem (Earth's
//! g = 9.81 m/s², no damping, no drag), so the drag-free predictions are the answer;
//! the paper's round (g exaggerated to 20 m/s², 200 kg, damping 0.99) and Cyclone's
//! ammo types are presets.
//!
//! Nothing is fired until the user fires: the window opens, and resets, with no round
//! in flight. A headless run (`simulate`, `render`, a link with `steps`) fires one round
//! at step 0, as pressing F at once would ([`super::fire_at_start`]).

use std::borrow::Cow;

use glam::Vec3;

use super::launcher::{Aim, Launcher, ROUND_RADIUS};
use super::{
    CameraHint, Marker, Param, ParamError, ParamTable, ParamValues, Preset, Scene, SceneAction, SceneEntry,
    SceneInfo,
};
use crate::physics::{ParticleId, PhysicsError, ResolveReport, SphereCollisions, World};

#[rustfmt::skip]
static PARAMS: &[Param] = &[
    Param { name: Cow::Borrowed("g"), unit: Cow::Borrowed("m/s²"), default: 9.81, min: -5.0, max: 50.0, help: Cow::Borrowed("Gravitational acceleration, downwards (negative floats up)"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("speed"), unit: Cow::Borrowed("m/s"), default: 25.0, min: 0.0, max: 200.0, help: Cow::Borrowed("Launch speed of the next round"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("angle"), unit: Cow::Borrowed("°"), default: 45.0, min: -90.0, max: 90.0, help: Cow::Borrowed("Launch elevation above the horizontal"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("mass"), unit: Cow::Borrowed("kg"), default: 200.0, min: 0.1, max: 1000.0, help: Cow::Borrowed("Mass of the next round (matters when rounds collide)"), logarithmic: true, integer: false },
    Param { name: Cow::Borrowed("damping"), unit: Cow::Borrowed(""), default: 1.0, min: 0.5, max: 1.0, help: Cow::Borrowed("Fraction of velocity a round keeps per second (1: no damping)"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("height"), unit: Cow::Borrowed("m"), default: 1.5, min: 0.0, max: 50.0, help: Cow::Borrowed("Height of the launcher above the ground"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("k1"), unit: Cow::Borrowed("N·s/m"), default: 0.0, min: 0.0, max: 100.0, help: Cow::Borrowed("Linear drag of the next round, F = -k1 v (the paper's drag)"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("k2"), unit: Cow::Borrowed("N·s²/m²"), default: 0.0, min: 0.0, max: 10.0, help: Cow::Borrowed("Quadratic drag of the next round, F = -k2 |v| v"), logarithmic: false, integer: false },
    Param { name: Cow::Borrowed("target"), unit: Cow::Borrowed("m"), default: 30.0, min: 1.0, max: 190.0, help: Cow::Borrowed("Distance of the target on the ground from the launcher"), logarithmic: false, integer: false },
];

#[rustfmt::skip]
static PRESETS: &[Preset] = &[
    Preset { name: "paper", help: "The paper's round: 200 kg at 25 m/s and 45° from 1.5 m, g = 20 m/s², damping 0.99, no drag", values: &[("g", 20.0), ("speed", 25.0), ("angle", 45.0), ("mass", 200.0), ("damping", 0.99), ("height", 1.5), ("k1", 0.0), ("k2", 0.0)] },
    Preset { name: "pistol", help: "2 kg at 35 m/s, weak gravity", values: &[("g", 1.0), ("speed", 35.0), ("angle", 0.0), ("mass", 2.0), ("damping", 0.99)] },
    Preset { name: "artillery", help: "200 kg at (40, 30) m/s, g = 20 m/s²", values: &[("g", 20.0), ("speed", 50.0), ("angle", 36.869_9), ("mass", 200.0), ("damping", 0.99)] },
    Preset { name: "fireball", help: "1 kg at 10 m/s that floats upwards", values: &[("g", -0.6), ("speed", 10.0), ("angle", 0.0), ("mass", 1.0), ("damping", 0.9)] },
    Preset { name: "laser", help: "0.1 kg at 100 m/s, no gravity", values: &[("g", 0.0), ("speed", 100.0), ("angle", 0.0), ("mass", 0.1), ("damping", 0.99)] },
    Preset { name: "Earth", help: "g = 9.81 m/s², the round unchanged", values: &[("g", 9.81)] },
    Preset { name: "Moon", help: "g = 1.62 m/s², the round unchanged", values: &[("g", 1.62)] },
    Preset { name: "Mars", help: "g = 3.71 m/s², the round unchanged", values: &[("g", 3.71)] },
    Preset { name: "Jupiter", help: "g = 24.79 m/s², the round unchanged", values: &[("g", 24.79)] },
];

static INFO: SceneInfo = SceneInfo {
    name: Cow::Borrowed("projectile"),
    summary: Cow::Borrowed(
        "Rounds fired from a launcher: Earth's g, no damping, no drag (the paper's round is a preset)",
    ),
    dt: 1.0 / 240.0,
    // 4 s: the default round (25 m/s at 45° from 1.5 m) lands after 3.69 s.
    default_steps: 960,
    params: ParamTable::Static(PARAMS),
    presets: PRESETS,
    actions: super::launcher::FIRE,
    trails: true,
    color_by_speed: false,
};

pub(super) const ENTRY: SceneEntry = SceneEntry::Compiled { info: &INFO, create };

fn create(params: ParamValues) -> Box<dyn Scene> {
    let mut world = World::new();
    world.add_contact_generator(SphereCollisions::elastic(0.8)).expect("a constant restitution in range");
    // No round yet: the window waits for Fire; a headless run fires one at step 0.
    let launcher = Launcher::new(aim(&params), true);
    Box::new(Projectile { world, params, launcher })
}

/// The launcher's aim the parameters set: `height` above the origin, towards +x.
fn aim(params: &ParamValues) -> Aim {
    Aim {
        position: Vec3::new(0.0, params.get("height"), 0.0),
        speed: params.get("speed"),
        angle: params.get("angle"),
        mass: params.get("mass"),
        radius: ROUND_RADIUS,
        damping: params.get("damping"),
        k1: params.get("k1"),
        k2: params.get("k2"),
        target: Some(params.get("target")),
        g: params.get("g"),
    }
}

struct Projectile {
    world: World,
    params: ParamValues,
    /// The launcher, its rounds and their flights.
    launcher: Launcher,
}

impl Scene for Projectile {
    scene_basics!();

    fn keeps_particle(&self, _id: ParticleId) -> bool {
        // Every particle is a round, removed when it lands: a later world need not
        // hold any. The rounds the state names are checked.
        false
    }

    fn save_state(&self) -> serde_json::Value {
        self.launcher.save_state()
    }

    fn restore_state(&mut self, state: &super::RawValue) -> Result<(), String> {
        self.launcher.restore_state(&self.world, state)
    }

    fn set_param(&mut self, name: &str, value: f32) -> Result<(), ParamError> {
        self.params.set(name, value)?;
        if name == "g" {
            let g = self.params.get("g");
            self.world.set_acceleration_all(Vec3::new(0.0, -g, 0.0)).expect("g is range-checked");
            // Rounds in flight now fall differently: their ghosts start again from here.
            self.launcher.set_gravity(&self.world, g);
        }
        // Launch settings apply to the next round fired.
        self.launcher.aim = aim(&self.params);
        Ok(())
    }

    fn step(&mut self, dt: f32) -> Result<ResolveReport, PhysicsError> {
        self.launcher.before_step(&self.world);
        let report = self.world.step(dt)?;
        self.launcher.after_step(&mut self.world);
        Ok(report)
    }

    fn act(&mut self, action: SceneAction) -> bool {
        match action {
            SceneAction::Fire => self.launcher.fire(&mut self.world).is_ok(),
            SceneAction::MoveLoad { .. } => false,
        }
    }

    fn labels<'a>(&'a self, out: &mut Vec<(Vec3, &'a str)>) {
        self.launcher.labels(&self.world, out);
    }

    fn outlines(&self, out: &mut Vec<(Vec3, Vec3)>) {
        self.launcher.outlines(out);
    }

    fn hover_points(&self, out: &mut Vec<(Vec3, String)>) {
        self.launcher.hover_points(out);
    }

    fn markers(&self, out: &mut Vec<Marker>) {
        self.launcher.markers(out);
    }

    fn predictions(&self, out: &mut Vec<Marker>) {
        self.launcher.predictions(&self.world, out);
    }

    fn framing_points(&self, out: &mut Vec<Vec3>) {
        self.launcher.framing_points(out);
    }

    fn camera(&self) -> CameraHint {
        CameraHint { target: Vec3::new(16.0, 5.0, 0.0), distance: 42.0, yaw: 0.0, pitch: 0.25 }
    }

    fn exact_error(&self) -> Option<f32> {
        self.launcher.exact_error(&self.world)
    }

    fn launcher(&self) -> Option<&Launcher> {
        Some(&self.launcher)
    }

    fn delete_runs(&mut self, which: Option<usize>) -> bool {
        self.launcher.delete_runs(which);
        true
    }

    fn readout_rows(&self, _dt: f32) -> Vec<super::Readout> {
        self.launcher.readout_rows(&self.world)
    }
}
