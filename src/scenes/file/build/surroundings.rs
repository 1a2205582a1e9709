//! What surrounds the particles: force fields (drag, buoyancy), the ground and walls,
//! and the camera.

use glam::Vec3;

use super::{ANY, Bounds, Builder, Located, NON_NEGATIVE, POSITIVE, UNIT, spend};
use crate::physics::{Buoyancy, DEFAULT_ROLLING_RESISTANCE, Drag, ForceId, Plane, Plate, SphereCollisions};
use crate::scenes::CameraHint;
use crate::scenes::file::format::{Document, SNum};
use crate::scenes::launcher::{Aim, ROUND_RADIUS};

impl Builder<'_> {
    pub(super) fn forces(&mut self, doc: &Document, g: f32) -> Result<Vec<(ForceId, Buoyancy)>, Located> {
        let mut applications = 0;
        for table in &doc.drag {
            let span = table.span();
            let t = table.get_ref();
            let k1 = self.compile_or(t.k1.as_ref(), 0.0, &[])?;
            let k2 = self.compile_or(t.k2.as_ref(), 0.0, &[])?;
            let targets = match &t.targets {
                Some(list) => {
                    let mut out = Vec::new();
                    for field in list {
                        let members = self.resolve(field)?;
                        spend(&mut applications, members.len(), "[[drag]]", &span)?;
                        out.extend(members.into_iter().map(|k| self.ids[k]));
                    }
                    out
                }
                None => {
                    spend(&mut applications, self.ids.len(), "[[drag]]", &span)?;
                    self.ids.clone()
                }
            };
            let drag = Drag {
                k1: self.eval(&k1, &[], "k1", NON_NEGATIVE)?,
                k2: self.eval(&k2, &[], "k2", NON_NEGATIVE)?,
                targets,
            };
            self.world.add_force(drag).map_err(|e| Located::at(&span, e.to_string()))?;
        }
        let mut floats = Vec::new();
        for table in &doc.buoyancy {
            let span = table.span();
            let t = table.get_ref();
            let targets = self.resolve(&t.particle)?;
            spend(&mut applications, targets.len(), "[[buoyancy]]", &span)?;
            let surface = self.compile(&t.surface, &[])?;
            let half_height = self.compile(&t.half_height, &[])?;
            let volume = self.compile(&t.volume, &[])?;
            let density = self.compile_or(t.density.as_ref(), 1000.0, &[])?;
            let (surface, half_height, volume, density) = (
                self.eval(&surface, &[], "surface", ANY)?,
                self.eval(&half_height, &[], "half_height", NON_NEGATIVE)?,
                self.eval(&volume, &[], "volume", NON_NEGATIVE)?,
                self.eval(&density, &[], "density", NON_NEGATIVE)?,
            );
            for k in targets {
                let float =
                    Buoyancy { target: self.ids[k], surface, half_height, volume, density, g: g.max(0.0) };
                let id =
                    self.world.add_force(float.clone()).map_err(|e| Located::at(&span, e.to_string()))?;
                floats.push((id, float));
            }
        }
        Ok(floats)
    }
    pub(super) fn surfaces(&mut self, doc: &Document) -> Result<(), Located> {
        if let Some(ground) = &doc.ground {
            let height = self.compile_or(ground.height.as_ref(), 0.0, &[])?;
            let restitution = self.compile_or(ground.restitution.as_ref(), 0.3, &[])?;
            let friction = self.compile_or(ground.friction.as_ref(), 0.5, &[])?;
            let rolling =
                self.compile_or(ground.rolling_resistance.as_ref(), DEFAULT_ROLLING_RESISTANCE.into(), &[])?;
            let plane = Plane::ground(
                self.eval(&height, &[], "height", ANY)?,
                self.eval(&restitution, &[], "restitution", UNIT)?,
                self.eval(&friction, &[], "friction", NON_NEGATIVE)?,
            )
            .with_rolling_resistance(self.eval(
                &rolling,
                &[],
                "rolling_resistance",
                NON_NEGATIVE,
            )?);
            self.world.add_contact_generator(plane).map_err(|e| Located::at(&height.span, e.to_string()))?;
        }
        for wall in &doc.wall {
            let normal = self.compile_vec(&wall.normal, &[])?;
            let point = self.compile_vec(&wall.point, &[])?;
            let [restitution, friction, rolling] =
                self.surface([&wall.restitution, &wall.friction, &wall.rolling_resistance], [0.3, 0.5])?;
            let plane = Plane::new(
                self.eval_vec(&normal, &[], "normal")?,
                self.eval_vec(&point, &[], "point")?,
                restitution,
                friction,
            )
            .map_err(|e| Located::at(&wall.normal.span(), e.to_string()))?
            .with_rolling_resistance(rolling);
            let plane = match &wall.size {
                None => plane,
                Some(size) => {
                    let items = size.get_ref();
                    if items.len() != 2 {
                        return Err(Located::at(
                            &size.span(),
                            format!("expected two lengths [length, width] (m), found {}", items.len()),
                        ));
                    }
                    let (length, width) = (self.compile(&items[0], &[])?, self.compile(&items[1], &[])?);
                    let length = self.eval(&length, &[], "the wall's length", POSITIVE)?;
                    let width = self.eval(&width, &[], "the wall's width", POSITIVE)?;
                    let along = match &wall.along {
                        Some(along) => {
                            let along = self.compile_vec(along, &[])?;
                            self.eval_vec(&along, &[], "along")?
                        }
                        None => crate::scenes::walls::slope_direction(plane.normal),
                    };
                    let point = self.eval_vec(&point, &[], "point")?;
                    let at = wall.along.as_ref().map_or(size.span(), |a| a.span());
                    plane
                        .with_extent(point, along, length, width)
                        .map_err(|e| Located::at(&at, e.to_string()))?
                }
            };
            self.world
                .add_contact_generator(plane)
                .map_err(|e| Located::at(&wall.normal.span(), e.to_string()))?;
        }
        for plate in &doc.plate {
            let normal = self.compile_vec(&plate.normal, &[])?;
            let point = self.compile_vec(&plate.point, &[])?;
            let opening = self.compile(&plate.opening, &[])?;
            let [restitution, friction, rolling] =
                self.surface([&plate.restitution, &plate.friction, &plate.rolling_resistance], [0.3, 0.5])?;
            let made = Plate::new(
                self.eval_vec(&normal, &[], "normal")?,
                self.eval_vec(&point, &[], "point")?,
                self.eval(&opening, &[], "opening", NON_NEGATIVE)? / 2.0,
                restitution,
                friction,
            )
            .map_err(|e| Located::at(&plate.normal.span(), e.to_string()))?
            .with_rolling_resistance(rolling);
            self.world.add_contact_generator(made).map_err(|e| Located::at(&opening.span, e.to_string()))?;
        }
        if let Some(collisions) = &doc.collisions {
            let fields = [&collisions.restitution, &collisions.friction, &collisions.rolling_resistance];
            let [restitution, friction, rolling_resistance] = self.surface(fields, [0.5, 0.3])?;
            let spheres = SphereCollisions { restitution, friction, rolling_resistance };
            self.world.add_contact_generator(spheres).map_err(|e| {
                Located::at(&collisions.restitution.as_ref().map_or(0..0, |r| r.span()), e.to_string())
            })?;
        }
        Ok(())
    }

    /// A surface's restitution, friction and rolling resistance from its three keys,
    /// with the table's own defaults for the first two (rolling resistance: 0.1).
    fn surface(&mut self, fields: [&Option<SNum>; 3], [e, mu]: [f64; 2]) -> Result<[f32; 3], Located> {
        let restitution = self.compile_or(fields[0].as_ref(), e, &[])?;
        let friction = self.compile_or(fields[1].as_ref(), mu, &[])?;
        let rolling = self.compile_or(fields[2].as_ref(), DEFAULT_ROLLING_RESISTANCE.into(), &[])?;
        Ok([
            self.eval(&restitution, &[], "restitution", UNIT)?,
            self.eval(&friction, &[], "friction", NON_NEGATIVE)?,
            self.eval(&rolling, &[], "rolling_resistance", NON_NEGATIVE)?,
        ])
    }

    /// The `[launcher]` table: the aim it fires with under gravity `g`, and whether a
    /// headless run fires a round at step 0.
    pub(super) fn launcher(&mut self, doc: &Document, g: f32) -> Result<Option<(Aim, bool)>, Located> {
        let Some(l) = &doc.launcher else { return Ok(None) };
        let position = self.compile_vec_or(l.position.as_ref(), Vec3::new(0.0, 1.5, 0.0), &[])?;
        let speed = self.compile_or(l.speed.as_ref(), 25.0, &[])?;
        let angle = self.compile_or(l.angle.as_ref(), 45.0, &[])?;
        let mass = self.compile_or(l.mass.as_ref(), 1.0, &[])?;
        let radius = self.compile_or(l.radius.as_ref(), f64::from(ROUND_RADIUS), &[])?;
        let damping = self.compile_or(l.damping.as_ref(), 1.0, &[])?;
        let k1 = self.compile_or(l.k1.as_ref(), 0.0, &[])?;
        let k2 = self.compile_or(l.k2.as_ref(), 0.0, &[])?;
        let target = l.target.as_ref().map(|t| self.compile(t, &[])).transpose()?;
        let aim = Aim {
            position: self.eval_vec(&position, &[], "position")?,
            speed: self.eval(&speed, &[], "speed", Bounds { min: 0.0, max: 1e8, text: "0 to 1e8 m/s" })?,
            angle: self.eval(
                &angle,
                &[],
                "angle",
                Bounds { min: -90.0, max: 90.0, text: "-90 to 90 degrees" },
            )?,
            mass: self.eval(&mass, &[], "mass", super::MASS)?,
            radius: self.eval(&radius, &[], "radius", NON_NEGATIVE)?,
            damping: self.eval(&damping, &[], "damping", UNIT)?,
            k1: self.eval(&k1, &[], "k1", NON_NEGATIVE)?,
            k2: self.eval(&k2, &[], "k2", NON_NEGATIVE)?,
            target: match &target {
                Some(t) => Some(self.eval(t, &[], "target", ANY)?),
                None => None,
            },
            g,
        };
        Ok(Some((aim, l.fire_at_start.unwrap_or(true))))
    }

    /// The `[camera]` table, with what it leaves out framing every particle.
    pub(super) fn camera(&mut self, doc: &Document) -> Result<CameraHint, Located> {
        let p = &self.world.particles;
        let (lo, hi) = p
            .positions()
            .iter()
            .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        let (centre, size) =
            if p.is_empty() { (Vec3::ZERO, 1.0) } else { ((lo + hi) * 0.5, (hi - lo).max_element()) };
        // What the particles fill with their radii.
        let whole = size + 2.0 * p.radii().iter().fold(0.0_f32, |a, &r| a.max(r));
        // From afar for a scene of a quarter metre or more; in proportion for a smaller
        // one (a millimetre particle seen from centimetres), the two meeting at 0.25 m.
        let distance = if whole >= 0.25 { 1.8 * size.max(0.5) + 1.0 } else { 7.6 * whole.max(1e-4) };
        let framing = CameraHint { target: centre, distance, yaw: 0.0, pitch: 0.2 };
        let Some(camera) = &doc.camera else { return Ok(framing) };
        let target = match &camera.target {
            Some(field) => {
                let value = self.compile_vec(field, &[])?;
                self.eval_vec(&value, &[], "target")?
            }
            None => framing.target,
        };
        let distance = self.compile_or(camera.distance.as_ref(), f64::from(framing.distance), &[])?;
        let yaw = self.compile_or(camera.yaw.as_ref(), 0.0, &[])?;
        let pitch = self.compile_or(camera.pitch.as_ref(), f64::from(framing.pitch.to_degrees()), &[])?;
        Ok(CameraHint {
            target,
            distance: self.eval(&distance, &[], "distance", POSITIVE)?,
            yaw: self.eval(&yaw, &[], "yaw", ANY)?.to_radians(),
            pitch: self
                .eval(&pitch, &[], "pitch", Bounds { min: -89.0, max: 89.0, text: "-89 to 89 degrees" })?
                .to_radians(),
        })
    }
}
