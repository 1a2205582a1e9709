//! The narrow phase: planes (the ground, walls) and sphere pairs turned into the
//! paper resolver's contacts. (The soft solver makes its own, swept contacts from the
//! same generators: `solver/soft/collide.rs`.)

use glam::Vec3;

use super::broad_phase::{BroadPhase, Scratch};
use crate::physics::contact::Contact;
use crate::physics::error::{NON_NEGATIVE, PhysicsError, UNIT, check, non_negative};
use crate::physics::links::direction_or_zero;
use crate::physics::particles::Particles;

/// An infinite plane that particles rest on by their radius: the ground, or a wall.
/// Points `p` with `normal · p > offset` are on the free side.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plane {
    /// Unit normal, pointing to the free side.
    pub normal: Vec3,
    /// `normal · p` for any point `p` of the plane (m).
    pub offset: f32,
    /// Coefficient of restitution against the plane, in [0, 1].
    pub restitution: f32,
    /// Coulomb friction coefficient against the plane, >= 0.
    pub friction: f32,
    /// Rolling resistance coefficient against the plane, >= 0 (default 0): the
    /// largest torque opposing a rolling sphere's spin is this times its radius times
    /// the normal force (see [`SphereCollisions::rolling_resistance`]).
    #[serde(default)]
    pub rolling_resistance: f32,
    /// A finite wall's rectangle on the plane; `None`: the whole plane.
    #[serde(default)]
    pub extent: Option<Extent>,
}

/// A rectangle of a plane: a finite wall, or a ramp. A particle touches it while its
/// centre is on the free side and over the rectangle (its foot on the plane inside
/// the rectangle); past an edge or behind the wall, it passes.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Extent {
    /// The rectangle's centre, on the plane (m).
    pub center: Vec3,
    /// Unit direction of its first side, in the plane.
    pub along: Vec3,
    /// Half its length along `along` (m).
    pub half_along: f32,
    /// Half its width across, along `normal × along` (m).
    pub half_across: f32,
}

impl Plane {
    /// The plane through `point` with the free side towards `normal` (any length > 0).
    pub fn new(normal: Vec3, point: Vec3, restitution: f32, friction: f32) -> Result<Self, PhysicsError> {
        let unit = normal.try_normalize().ok_or_else(|| {
            PhysicsError::InvalidSetting(format!("plane normal must be finite and non-zero, got {normal}"))
        })?;
        if !point.is_finite() {
            return Err(PhysicsError::InvalidSetting(format!("plane point must be finite, got {point}")));
        }
        check_surface(restitution, friction, 0.0)?;
        Ok(Self {
            normal: unit,
            offset: unit.dot(point),
            restitution,
            friction,
            rolling_resistance: 0.0,
            extent: None,
        })
    }

    /// The same plane cut to a rectangle `length` by `width` (m) centred on `point`'s
    /// foot on the plane, its length along `along` (made to lie in the plane). The
    /// error says which value is unusable.
    pub fn with_extent(
        self,
        point: Vec3,
        along: Vec3,
        length: f32,
        width: f32,
    ) -> Result<Self, PhysicsError> {
        let sizes = length.is_finite() && width.is_finite() && length > 0.0 && width > 0.0;
        if !sizes {
            return Err(PhysicsError::InvalidSetting(format!(
                "a wall's size must be two lengths > 0 (m), got {length} by {width}"
            )));
        }
        if !point.is_finite() {
            return Err(PhysicsError::InvalidSetting(format!("wall centre must be finite, got {point}")));
        }
        let in_plane = along - self.normal * self.normal.dot(along);
        let along = in_plane.try_normalize().ok_or_else(|| {
            PhysicsError::InvalidSetting(format!(
                "a wall's direction along must be finite and not along its normal, got {along}"
            ))
        })?;
        let center = point - self.normal * self.distance(point);
        let extent = Extent { center, along, half_along: 0.5 * length, half_across: 0.5 * width };
        Ok(Self { extent: Some(extent), ..self })
    }

    /// Whether a particle centred at `p` is over the plane's part that exists: every
    /// point for an unbounded plane; for a rectangle, a centre on the free side whose
    /// foot on the plane falls inside it.
    #[inline]
    #[must_use]
    pub fn covers(&self, p: Vec3) -> bool {
        let Some(e) = &self.extent else { return true };
        let d = p - e.center;
        let across = self.normal.cross(e.along);
        self.distance(p) >= 0.0
            && d.dot(e.along).abs() <= e.half_along
            && d.dot(across).abs() <= e.half_across
    }

    /// The horizontal plane `y = height`, free side up.
    #[must_use]
    pub fn ground(height: f32, restitution: f32, friction: f32) -> Self {
        Self { normal: Vec3::Y, offset: height, restitution, friction, rolling_resistance: 0.0, extent: None }
    }

    /// The same plane with rolling resistance `coefficient` (checked when the plane
    /// joins a world).
    #[must_use]
    pub fn with_rolling_resistance(self, coefficient: f32) -> Self {
        Self { rolling_resistance: coefficient, ..self }
    }

    /// Signed distance of a point from the plane, positive on the free side (m).
    #[inline]
    #[must_use]
    pub fn distance(&self, p: Vec3) -> f32 {
        self.normal.dot(p) - self.offset
    }

    pub(super) fn generate(&self, particles: &Particles, out: &mut Vec<Contact>) {
        let positions = particles.position.iter().zip(&particles.radius);
        for (i, ((&p, &r), &inverse_mass)) in positions.zip(&particles.inverse_mass).enumerate() {
            let penetration = r - self.distance(p);
            if penetration > 0.0 && inverse_mass > 0.0 && self.covers(p) {
                out.push(
                    Contact::new(i, None, self.normal, penetration, self.restitution)
                        .with_friction(self.friction),
                );
            }
        }
    }
}

/// Rolling resistance coefficient the lab's granular scenes and scene files use unless
/// told otherwise: with friction 0.5 a poured heap of rolling spheres rests near 25°
/// (tests/granular.rs measures it), inside the 25–35° DEM codes report for μ_r of
/// 0.05–0.1 (Ai et al. 2011); at 0.05 it spreads to about 18°.
pub const DEFAULT_ROLLING_RESISTANCE: f32 = 0.1;

/// A thin plate with a round opening: an infinite two-sided plane through `center`
/// with the disc of `opening` radius around `center` cut out, the floor of a silo or
/// an hourglass. A sphere touches it by its radius on either face, or at the rim of
/// the opening (the circle of the cut), whichever point of the plate is closest.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plate {
    /// Unit normal of the plate.
    pub normal: Vec3,
    /// Centre of the opening, a point of the plate (m).
    pub center: Vec3,
    /// Radius of the opening (m), >= 0 (0: a plate with no opening).
    pub opening: f32,
    /// Coefficient of restitution against the plate, in [0, 1].
    pub restitution: f32,
    /// Coulomb friction coefficient against the plate, >= 0.
    pub friction: f32,
    /// Rolling resistance coefficient against the plate, >= 0.
    pub rolling_resistance: f32,
}

impl Plate {
    /// The plate through `center` with normal `normal` (any length > 0) and an opening
    /// of radius `opening` around `center`.
    pub fn new(
        normal: Vec3,
        center: Vec3,
        opening: f32,
        restitution: f32,
        friction: f32,
    ) -> Result<Self, PhysicsError> {
        let unit = normal.try_normalize().ok_or_else(|| {
            PhysicsError::InvalidSetting(format!("plate normal must be finite and non-zero, got {normal}"))
        })?;
        let plate = Self { normal: unit, center, opening, restitution, friction, rolling_resistance: 0.0 };
        plate.validate()?;
        Ok(plate)
    }

    /// The same plate with rolling resistance `coefficient` (checked when the plate
    /// joins a world).
    #[must_use]
    pub fn with_rolling_resistance(self, coefficient: f32) -> Self {
        Self { rolling_resistance: coefficient, ..self }
    }

    /// Checks every field; the error names the first that is off.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        let unit = self.normal.is_finite() && (self.normal.length() - 1.0).abs() < 1e-4;
        check(unit, "plate normal", self.normal, "a unit vector")?;
        check(self.center.is_finite(), "plate centre", self.center, "a finite point (m)")?;
        check(non_negative(self.opening), "plate opening", self.opening, "a finite radius >= 0 (m)")?;
        check_surface(self.restitution, self.friction, self.rolling_resistance)
    }

    /// The unit normal pointing from the plate's nearest point towards `p`, and the
    /// distance from that point to `p` (m).
    #[inline]
    #[must_use]
    pub fn nearest(&self, p: Vec3) -> (Vec3, f32) {
        let offset = p - self.center;
        let height = offset.dot(self.normal);
        let across = offset - self.normal * height;
        let radial = across.length();
        if radial >= self.opening {
            // Over the plate itself: straight to its face, on whichever side.
            let side = if height < 0.0 { -self.normal } else { self.normal };
            return (side, height.abs());
        }
        // Over the opening: to the nearest point of its rim.
        let outward = if radial > 0.0 { across / radial } else { self.normal.any_orthonormal_vector() };
        let (direction, distance) = direction_or_zero(p - (self.center + outward * self.opening));
        (if direction == Vec3::ZERO { self.normal } else { direction }, distance)
    }

    pub(super) fn generate(&self, particles: &Particles, out: &mut Vec<Contact>) {
        let positions = particles.position.iter().zip(&particles.radius);
        for (i, ((&p, &r), &inverse_mass)) in positions.zip(&particles.inverse_mass).enumerate() {
            let (normal, distance) = self.nearest(p);
            let penetration = r - distance;
            if penetration > 0.0 && inverse_mass > 0.0 {
                out.push(
                    Contact::new(i, None, normal, penetration, self.restitution).with_friction(self.friction),
                );
            }
        }
    }
}

/// Checks a surface's restitution, friction and rolling resistance.
pub(crate) fn check_surface(restitution: f32, friction: f32, rolling: f32) -> Result<(), PhysicsError> {
    check((0.0..=1.0).contains(&restitution), "restitution", restitution, UNIT)?;
    check(non_negative(friction), "friction", friction, NON_NEGATIVE)?;
    check(non_negative(rolling), "rolling resistance", rolling, NON_NEGATIVE)
}

/// The horizontal plane `y = height` with no friction: the paper's ground.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GroundPlane {
    /// Height of the plane (m).
    pub height: f32,
    /// Coefficient of restitution against the ground.
    pub restitution: f32,
}

/// Collisions between every pair of particles with a radius, found through the
/// broad phase's grid.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SphereCollisions {
    /// Coefficient of restitution between particles, in [0, 1].
    pub restitution: f32,
    /// Coulomb friction coefficient between particles, >= 0.
    pub friction: f32,
    /// Rolling resistance coefficient between spheres that roll, >= 0 (default 0, the
    /// soft solver only). The contact resists the two spheres' relative rolling (their
    /// relative spin about axes in the contact plane; twist about the normal is only
    /// damped, never held, as DEM codes leave it out of the rolling torque) with a
    /// torque of at most this times the contact's rolling radius (`r_a r_b / (r_a +
    /// r_b)`, or the sphere's radius against a plane) times the normal force: the
    /// constant-torque ("type A") model of DEM codes, solved as a clamped constraint as
    /// Box2D v3 does, so a sphere can also rest on a gentle slope (while `tan θ` is at
    /// most the coefficient). A rolling sphere on flat ground then slows at `5/7 μ_r g`.
    /// Without it rolling spheres roll forever and heaps spread flat.
    #[serde(default)]
    pub rolling_resistance: f32,
}

impl SphereCollisions {
    /// Frictionless collisions with the given restitution (the paper's).
    #[must_use]
    pub fn elastic(restitution: f32) -> Self {
        Self { restitution, friction: 0.0, rolling_resistance: 0.0 }
    }

    /// Collisions with restitution and friction and no rolling resistance.
    #[must_use]
    pub fn new(restitution: f32, friction: f32) -> Self {
        Self { restitution, friction, rolling_resistance: 0.0 }
    }

    pub(super) fn generate(
        &self,
        particles: &Particles,
        broad_phase: &mut BroadPhase,
        scratch: &mut Scratch,
        out: &mut Vec<Contact>,
    ) {
        scratch.reach.clear();
        scratch.reach.extend_from_slice(&particles.radius);
        broad_phase.find_pairs(&particles.position, &scratch.reach, &mut scratch.pairs);
        scratch.pair_budget_hit |= broad_phase.budget_hit();
        for &(a, b) in &scratch.pairs {
            let (a, b) = (a as usize, b as usize);
            if particles.inverse_mass[a] + particles.inverse_mass[b] <= 0.0 {
                continue;
            }
            let reach = particles.radius[a] + particles.radius[b];
            let (normal, distance) = direction_or_zero(particles.position[a] - particles.position[b]);
            // Coincident centres have no direction: separate them vertically.
            let normal = if normal == Vec3::ZERO { Vec3::Y } else { normal };
            out.push(
                Contact::new(a, Some(b), normal, reach - distance, self.restitution)
                    .with_friction(self.friction),
            );
        }
    }
}
