//! The tape measure: two clicks, on particles or the ground, and the distance
//! between them in the status line. Its ends are world points, drawn in the 3D
//! frame, so they are kept on the lab beside the world they measure.

use glam::Vec2;

use super::model::Lab;

impl Lab {
    /// Places an end of the tape where `pixel` points: the centre of the particle
    /// there, else where the ray meets the ground (y = 0), else the plane through the
    /// camera's target facing it. A third click starts a new tape.
    pub fn tape_click(&mut self, pixel: Vec2, viewport: Vec2) {
        let point = match self.pick(pixel, viewport) {
            Some(id) => {
                let particles = &self.scene.world().particles;
                particles.index(id).map(|i| particles.positions()[i])
            }
            None => {
                let (origin, direction) = self.camera.ray(pixel, viewport);
                let ground = (direction.y < -1e-4).then(|| origin + direction * (-origin.y / direction.y));
                ground.or_else(|| {
                    let normal = (self.camera.eye() - self.camera.target).normalize_or_zero();
                    let facing = direction.dot(normal);
                    (facing.abs() > 1e-4)
                        .then(|| origin + direction * ((self.camera.target - origin).dot(normal) / facing))
                })
            }
        };
        let Some(point) = point else { return };
        if self.tape_points.len() == 2 {
            self.tape_points.clear();
        }
        self.tape_points.push(point);
        if let [a, b] = self.tape_points[..] {
            let d = b - a;
            self.status = format!(
                "tape: {:.3} m (Δx {}, Δy {}, Δz {} m)",
                d.length(),
                crate::messages::fixed(d.x, 3),
                crate::messages::fixed(d.y, 3),
                crate::messages::fixed(d.z, 3)
            );
            log::info!("{}", self.status);
        }
    }
}

impl Lab {
    /// Turns the tape measure on or off; either way its ends are cleared.
    pub fn set_tape(&mut self, on: bool) {
        self.tape = on;
        self.tape_points.clear();
        log::info!("tape measure: {on}");
    }
}
