//! The plain data the lab keeps and hands out: timing figures, energy samples and
//! bars, the drag in progress, the window's requests. A leaf: no lab methods here.

use glam::Vec3;

use crate::physics::{Energy, LinkEnd, LinkState, ParticleId, World};
use crate::scenes::Scene;

/// Timing figures for the stats block.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    /// Frames per second, smoothed.
    pub fps: f32,
    /// Time between frames (ms), smoothed.
    pub frame_ms: f32,
    /// Wall time per physics step (ms), smoothed.
    pub step_ms: f32,
    /// Physics steps run in the last frame.
    pub steps_last_frame: u32,
    /// Steps dropped so far because a frame took too long or the physics used up its
    /// budget ([`PHYSICS_BUDGET`]).
    pub dropped_steps: u64,
    /// Simulated seconds per real second over recent frames, smoothed: the time scale
    /// when the physics keeps up, less when steps are dropped.
    pub sim_speed: f32,
}

/// A sample of the energy plot.
#[derive(Clone, Copy, Debug)]
pub struct EnergySample {
    /// Simulated time (s).
    pub t: f64,
    /// The world's energy budget then (J), its gravitational energy measured from the
    /// scene's reference height (see [`Scene::gravity_reference`]).
    pub energy: Energy,
    /// Distance from the scene's exact answer (m), NaN where it has none.
    pub exact_error: f32,
}

impl EnergySample {
    /// The sample of a scene's current state.
    #[must_use]
    pub fn of(scene: &dyn Scene) -> Self {
        let world = scene.world();
        let energy = world.energy();
        // Gravitational energy from the scene's reference height (see `gravity_from`).
        let shift =
            scene.gravity_reference().map_or(0.0, |(height, _)| world.gravity_reference_shift(height));
        Self {
            t: world.time(),
            energy: Energy {
                potential: energy.potential + shift,
                gravitational: energy.gravitational + shift,
                ..energy
            },
            exact_error: scene.exact_error().unwrap_or(f32::NAN),
        }
    }
}

/// The energy bars: whose energy they show, the height gravitational energy is
/// measured from, and each bar's name and value (J).
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyBars {
    /// "the scene", or the particle shown ("the bob", "particle 3").
    pub subject: String,
    /// Where gravitational energy is zero ("the ground (y = 0)").
    pub reference: String,
    /// Kinetic, gravitational, elastic and, for the scene, dissipated, the constraint
    /// term, removed and the budget; for a particle, its total.
    pub bars: Vec<(&'static str, f32)>,
}

impl EnergyBars {
    /// Each bar's height (signed, up positive) when `span` pixels stand for the range
    /// the bars cover (from the lowest value or 0 to the highest or 0). 0 J is no bar.
    #[must_use]
    pub fn heights(&self, span: f32) -> Vec<f32> {
        let low = self.bars.iter().map(|b| b.1).fold(0.0, f32::min);
        let high = self.bars.iter().map(|b| b.1).fold(0.0, f32::max);
        let range = high - low;
        self.bars
            .iter()
            .map(|&(_, value)| if range > 0.0 && value != 0.0 { value / range * span } else { 0.0 })
            .collect()
    }
}

/// A particle held by the mouse: it follows the pointer in the plane through its
/// grab point facing the camera.
#[derive(Clone, Copy, Debug)]
pub struct Grab {
    /// The particle.
    pub id: ParticleId,
    /// A point of the drag plane (m).
    pub plane_point: Vec3,
    /// The drag plane's normal.
    pub plane_normal: Vec3,
    /// Where the pointer puts it (m).
    pub target: Vec3,
    /// The mass the drag pulls along (kg): the particle's and that of every movable
    /// particle joined to it by links.
    pub pulled_mass: f32,
}

/// Things the panel asks the window to do.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Requests {
    /// Save a screenshot after this frame.
    pub screenshot: bool,
    /// Close the window.
    pub quit: bool,
    /// Ask for a file (Ctrl+O, Ctrl+S): the File menu's dialog, or the path field
    /// standing in for it.
    pub file: Option<Purpose>,
}

/// What a file dialog, or the path field standing in for it, is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Purpose {
    /// File → Open scene file…
    OpenScene,
    /// File → Open snapshot…
    OpenSnapshot,
    /// File → Save snapshot as…
    SaveSnapshot,
    /// File → Save scene as…
    SaveScene,
}

impl Purpose {
    /// The window's title, as the menu item says it.
    #[must_use]
    pub fn title(self) -> &'static str {
        match self {
            Self::OpenScene => "Open scene file",
            Self::OpenSnapshot => "Open snapshot",
            Self::SaveSnapshot => "Save snapshot as",
            Self::SaveScene => "Save scene as",
        }
    }

    /// The files it takes, by extension (without the dot).
    #[must_use]
    pub fn extension(self) -> &'static str {
        match self {
            Self::OpenScene | Self::SaveScene => "toml",
            Self::OpenSnapshot | Self::SaveSnapshot => "json",
        }
    }

    /// What it opens or saves, in words.
    #[must_use]
    pub fn kind(self) -> &'static str {
        match self {
            Self::OpenScene | Self::SaveScene => "scene file",
            Self::OpenSnapshot | Self::SaveSnapshot => "snapshot",
        }
    }

    /// The button's word.
    #[must_use]
    pub fn action(self) -> &'static str {
        match self {
            Self::OpenScene | Self::OpenSnapshot => "Open",
            Self::SaveSnapshot | Self::SaveScene => "Save",
        }
    }

    /// Whether it writes a file (rather than opening one).
    #[must_use]
    pub fn saves(self) -> bool {
        matches!(self, Self::SaveSnapshot | Self::SaveScene)
    }
}

/// Reused buffers for finding the mass joined to the dragged particle, so that a
/// drag allocates nothing once it has started.
#[derive(Debug, Default)]
pub struct Joined {
    links: Vec<LinkState>,
    parent: Vec<u32>,
}

impl Joined {
    /// The total mass of the movable particles joined to particle `i` through any
    /// chain of links (kg), itself included; pinned particles add nothing.
    pub fn mass(&mut self, world: &World, i: usize) -> f32 {
        let particles = &world.particles;
        world.links_into(&mut self.links);
        self.parent.clear();
        self.parent.extend(0..particles.len() as u32);
        fn root(parent: &mut [u32], mut k: u32) -> u32 {
            while parent[k as usize] != k {
                let up = parent[parent[k as usize] as usize];
                parent[k as usize] = up;
                k = up;
            }
            k
        }
        for link in &self.links {
            let (Some(a), LinkEnd::Particle(b)) = (particles.index(link.spec.a), link.spec.b) else {
                continue;
            };
            let Some(b) = particles.index(b) else { continue };
            // Through a pinned particle nothing is pulled along: it holds.
            if particles.inverse_masses()[a] == 0.0 || particles.inverse_masses()[b] == 0.0 {
                continue;
            }
            let (ra, rb) = (root(&mut self.parent, a as u32), root(&mut self.parent, b as u32));
            self.parent[ra as usize] = rb;
        }
        let mine = root(&mut self.parent, i as u32);
        (0..particles.len())
            .filter(|&k| particles.inverse_masses()[k] > 0.0 && root(&mut self.parent, k as u32) == mine)
            .map(|k| particles.mass(k))
            .sum()
    }
}
