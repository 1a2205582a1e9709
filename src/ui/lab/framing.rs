//! Where the camera looks: framing the scene, the 2D side view, following a
//! particle, the view's shape, and the view options `render --view` names.

use glam::Vec3;

use super::limits::FRAMING_ASPECT;

/// Margin kept around the points a framing must show, as a share of the view's height.
pub const FRAMING_MARGIN: f32 = 0.06;
/// The side view's left margin, as a share of the view's height: its height scale
/// stands there (some 60 points wide), and a launcher at the view's edge hid behind it.
pub const SIDE_VIEW_LEFT_MARGIN: f32 = 0.15;
/// Most times the camera backs off (by 15% each) to fit them: 1.15^80 is 70,000x.
const FRAMING_STEPS: usize = 80;
use super::model::Lab;
use crate::render::OrbitCamera;

impl Lab {
    /// Points the camera where the scene asks, backing off in a view narrower than the
    /// one the scenes' camera hints were made for, so the whole scene stays in sight.
    pub fn frame_scene(&mut self) {
        self.camera = OrbitCamera::framing(self.scene.as_ref());
        if self.view_aspect > 0.0 && self.view_aspect < FRAMING_ASPECT {
            self.camera.distance *= FRAMING_ASPECT / self.view_aspect;
        }
        if self.side_view {
            self.look_from_the_side();
        }
        self.fit_framing_points();
        self.camera_moved = false;
        self.follow_particle();
    }

    /// Home: follow goes off and the scene is framed, whatever the camera did.
    pub fn home(&mut self) {
        if self.follow {
            self.follow = false;
            log::info!("follow: off (Home)");
        }
        self.frame_scene();
    }

    /// Backs the camera off (keeping its direction) until the points the scene asks
    /// to keep in view, a projectile's predicted path to its landing and its target,
    /// are inside the view with a margin; centred on them when they do not fit.
    fn fit_framing_points(&mut self) {
        let mut points = Vec::new();
        self.scene.framing_points(&mut points);
        points.retain(|p| p.is_finite());
        if points.is_empty() {
            return;
        }
        let view = glam::Vec2::new(1000.0 * self.view_aspect.max(0.1), 1000.0);
        let margin = FRAMING_MARGIN * view.y;
        let left = if self.side_view { SIDE_VIEW_LEFT_MARGIN * view.y } else { margin };
        let fits = |camera: &OrbitCamera| {
            points.iter().all(|&p| {
                camera.project(p, view).is_some_and(|s| {
                    s.x >= left && s.x <= view.x - margin && s.y >= margin && s.y <= view.y - margin
                })
            })
        };
        if fits(&self.camera) {
            return;
        }
        let (low, high) = points
            .iter()
            .fold((self.camera.target, self.camera.target), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let centre = (low + high) * 0.5;
        self.camera.target =
            Vec3::new(centre.x, centre.y.max(if self.side_view { self.side_lift() } else { 0.0 }), centre.z);
        for _ in 0..FRAMING_STEPS {
            if fits(&self.camera) {
                break;
            }
            self.camera.distance *= 1.15;
        }
    }

    /// Turns the 2D side view on or off: on, the camera looks along -z at the same
    /// point with a parallel projection; off, the scene is framed again in 3D.
    pub fn set_side_view(&mut self, on: bool) {
        log::info!("side view: {on}");
        self.side_view = on;
        if on {
            self.look_from_the_side();
        } else {
            self.frame_scene();
        }
    }

    /// How far above the ground the side view's target stays (m): half a metre, or a
    /// tenth of the camera's distance for a camera closer than 5 m (millimetre
    /// particles seen from centimetres stay in the view).
    fn side_lift(&self) -> f32 {
        (0.1 * self.camera.distance).min(0.5)
    }

    pub(super) fn look_from_the_side(&mut self) {
        self.camera.orthographic = true;
        self.camera.yaw = 0.0;
        self.camera.pitch = 0.0;
        // Level with the target, which must be above the ground for the eye to be.
        self.camera.target.y = self.camera.target.y.max(self.camera.ground + self.side_lift());
    }

    /// With follow on: puts the camera's target on the selected particle, or else the
    /// newest movable one (the highest id: the round just fired).
    pub fn follow_particle(&mut self) {
        if !self.follow {
            return;
        }
        let particles = &self.scene.world().particles;
        let chosen = self.selected.and_then(|id| particles.index(id)).or_else(|| {
            let movable =
                particles.ids().iter().enumerate().filter(|(i, _)| particles.inverse_masses()[*i] > 0.0);
            movable.max_by_key(|(_, id)| id.0).map(|(i, _)| i)
        });
        if let Some(i) = chosen {
            let p = particles.positions()[i];
            let ground = self.camera.ground;
            self.camera.target = if self.side_view {
                Vec3::new(p.x, p.y.max(ground + self.side_lift()), self.camera.target.z)
            } else {
                Vec3::new(p.x, p.y.max(ground), p.z)
            };
        }
    }

    /// Tells the lab the 3D view's shape; reframes the scene if it changed and the
    /// user has not moved the camera since it was last framed.
    pub fn set_view_aspect(&mut self, aspect: f32) {
        if aspect.is_finite() && aspect > 0.0 && (aspect - self.view_aspect).abs() > 0.01 {
            self.view_aspect = aspect;
            if !self.camera_moved {
                self.frame_scene();
            }
        }
    }

    /// Turns on a view option by the name `render --view` takes; an unknown name gets a
    /// one-line refusal that lists the known ones.
    pub fn set_view_option(&mut self, name: &str) -> Result<(), String> {
        match name.trim() {
            "forces" => self.view.forces = true,
            "no-forces" => self.view.forces = false,
            "all-vectors" => self.view.all_vectors = true,
            "contacts" => self.view.contacts = true,
            "tension" => self.view.tension_colors = true,
            "no-labels" => self.view.labels = false,
            "no-trails" => self.view.trails = false,
            "no-predictions" => self.view.predictions = false,
            "side" => self.set_side_view(true),
            "follow" => {
                self.follow = true;
                self.follow_particle();
            }
            other => {
                return Err(format!(
                    "--view {}: unknown view option; known: forces, no-forces, all-vectors, contacts, \
                     tension, side, follow, no-labels, no-trails, no-predictions",
                    crate::messages::quote(other)
                ));
            }
        }
        Ok(())
    }
}
