//! What one frame draws, as plain data: sphere and segment instances, the water. Built
//! from a scene on the CPU, uploaded by the renderer. No GPU types here.

use std::collections::{HashMap, VecDeque};
use std::sync::LazyLock;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::physics::{LinkKind, LinkState, ParticleId};
use crate::scenes::{Marker, Scene};

/// One sphere impostor.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SphereInstance {
    /// Centre (m).
    pub center: [f32; 3],
    /// Radius (m).
    pub radius: f32,
    /// Linear RGBA colour.
    pub color: [f32; 4],
    /// Orientation of a sphere that rolls (a unit quaternion, x, y, z, w), drawn as a
    /// dark band with a light dot that turn with it; [`UNMARKED`] for none.
    pub spin: [f32; 4],
}

/// [`SphereInstance::spin`] of a sphere drawn plain: a point mass, a marker, a ghost.
pub const UNMARKED: [f32; 4] = [0.0; 4];

/// One thick line segment, drawn as a screen-space quad.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SegmentInstance {
    /// Start (m).
    pub from: [f32; 3],
    /// Width in pixels.
    pub width: f32,
    /// End (m).
    pub to: [f32; 3],
    /// Unused; keeps the colour 16-byte aligned.
    pub pad: f32,
    /// Linear RGBA colour; alpha blends.
    pub color: [f32; 4],
}

/// A rectangle of water surface.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct WaterQuad {
    /// Centre x, surface height, centre z, unused (m).
    pub center: [f32; 4],
    /// Half extents in x and z, unused, unused (m).
    pub half_extent: [f32; 4],
}

/// Everything the renderer draws for one frame.
#[derive(Clone, Debug, Default)]
pub struct FrameData {
    /// Particles and markers.
    pub spheres: Vec<SphereInstance>,
    /// Links and the pool's edges.
    pub segments: Vec<SegmentInstance>,
    /// Fading trails, drawn translucent after everything else.
    pub trails: Vec<SegmentInstance>,
    /// A pool, if the scene has one.
    pub water: Option<WaterQuad>,
    /// Draw the ground's grid lines.
    pub grid: bool,
    /// Draw a soft shadow under each sphere.
    pub shadows: bool,
}

/// What the View menu toggles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ViewOptions {
    /// Fading trails behind moving particles.
    pub trails: bool,
    /// Colour links by tension instead of by kind.
    pub tension_colors: bool,
    /// Grid lines on the ground.
    pub grid: bool,
    /// The statistics block in the panel.
    pub stats: bool,
    /// 4x multisample anti-aliasing (costly on a software GPU).
    pub msaa: bool,
    /// Colour particles by speed ([`speed_color`]) instead of by id.
    pub color_by_speed: bool,
    /// Draw the path each fast particle swept in the last step (what continuous
    /// collision has to catch), from a ghost of where it started.
    pub swept: bool,
    /// Names of objects and links, and metre ticks along the x axis.
    pub labels: bool,
    /// Force arrows (a free-body diagram) on the selected particle.
    pub forces: bool,
    /// Velocity and force arrows on every particle, not only the selected one (up to
    /// [`VECTOR_PARTICLE_LIMIT`]).
    pub all_vectors: bool,
    /// Debug drawing like Box2D's: contact points, normals and overlaps, and the limits
    /// of links (a cable's full length, a spring's natural length).
    pub contacts: bool,
    /// What the scene predicts (the exact path's ghost, the next round's drag-free path)
    /// and the predicted read-outs; off so that a class predicts before it measures.
    pub predictions: bool,
}

/// Most particles that get arrows when [`ViewOptions::all_vectors`] is on.
pub const VECTOR_PARTICLE_LIMIT: usize = 200;

impl Default for ViewOptions {
    fn default() -> Self {
        Self {
            trails: true,
            tension_colors: false,
            grid: true,
            stats: true,
            msaa: true,
            color_by_speed: false,
            swept: false,
            labels: true,
            forces: true,
            all_vectors: false,
            contacts: false,
            predictions: true,
        }
    }
}

/// Above this many spheres no blob shadows are drawn: in a crowd they lie under other
/// spheres, and on a software GPU they cost as much as the spheres themselves.
pub const SHADOW_LIMIT: usize = 20_000;

/// The speed at the hot end of the colour-by-speed ramp (m/s); faster is as hot. A
/// fixed scale, so a colour means the same speed in every frame and every scene.
pub const SPEED_SCALE: f32 = 10.0;

/// The colour-by-speed ramp from rest to [`SPEED_SCALE`], evenly spaced stops in sRGB:
/// blue, sky blue, green, yellow, red.
pub const SPEED_RAMP: [[u8; 3]; 5] =
    [[40, 70, 165], [35, 150, 215], [70, 195, 110], [240, 200, 50], [225, 55, 35]];

/// Where `speed` (m/s) falls on the ramp, 0 to 1: the square root of its share of
/// [`SPEED_SCALE`], so that slow creep (0.1 m/s is 10% up the ramp) stands out from rest.
#[inline]
#[must_use]
pub fn speed_fraction(speed: f32) -> f32 {
    (speed / SPEED_SCALE).clamp(0.0, 1.0).sqrt()
}

/// The speed (m/s) at `fraction` (0 to 1) of the ramp: the inverse of [`speed_fraction`].
#[inline]
#[must_use]
pub fn speed_at_fraction(fraction: f32) -> f32 {
    fraction.clamp(0.0, 1.0).powi(2) * SPEED_SCALE
}

/// The ramp's sRGB colour at `fraction` (0 to 1), interpolated between its stops.
#[must_use]
pub fn ramp_srgb(fraction: f32) -> [u8; 3] {
    let x = fraction.clamp(0.0, 1.0) * (SPEED_RAMP.len() - 1) as f32;
    let below = (x.floor() as usize).min(SPEED_RAMP.len() - 2);
    let t = x - below as f32;
    let (a, b) = (SPEED_RAMP[below], SPEED_RAMP[below + 1]);
    std::array::from_fn(|c| (f32::from(a[c]) + (f32::from(b[c]) - f32::from(a[c])) * t).round() as u8)
}

/// The ramp in linear RGB at 256 evenly spaced fractions: a lookup per particle
/// instead of three `powf` calls.
static SPEED_TABLE: LazyLock<[[f32; 3]; 256]> = LazyLock::new(|| {
    let linear = |c: u8| {
        let c = f32::from(c) / 255.0;
        if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
    };
    std::array::from_fn(|i| ramp_srgb(i as f32 / 255.0).map(linear))
});

/// Colour of a particle moving at `speed` (m/s), linear RGB: see [`SPEED_RAMP`].
#[inline]
#[must_use]
pub fn speed_color(speed: f32) -> [f32; 3] {
    ramp_lookup(&SPEED_TABLE, speed)
}

#[inline]
fn ramp_lookup(table: &[[f32; 3]; 256], speed: f32) -> [f32; 3] {
    table[((speed_fraction(speed) * 255.0 + 0.5) as usize).min(255)]
}

/// Colour of a link of each kind (linear RGB): rods blue, cables green, supports grey,
/// springs orange, bungees purple, stiff springs red.
#[must_use]
pub fn link_color(kind: LinkKind) -> [f32; 3] {
    match kind {
        LinkKind::Rod => [0.10, 0.30, 0.95],
        LinkKind::Cable => [0.10, 0.75, 0.20],
        LinkKind::SupportRod | LinkKind::SupportCable => [0.55, 0.55, 0.58],
        LinkKind::Spring => [0.95, 0.45, 0.05],
        LinkKind::Bungee => [0.60, 0.20, 0.85],
        LinkKind::StiffSpring => [0.90, 0.10, 0.10],
    }
}

/// Blue (no load) to red (`tension >= reference`); compression towards cyan. The
/// square root spreads the colours when one link carries far more than the rest.
#[must_use]
pub fn tension_color(tension: f32, reference: f32) -> [f32; 3] {
    let x = (tension / reference.max(1e-6)).clamp(-1.0, 1.0);
    let x = x.signum() * x.abs().sqrt();
    if x >= 0.0 {
        let (cold, hot) = (Vec3::new(0.15, 0.25, 0.9), Vec3::new(1.0, 0.1, 0.05));
        cold.lerp(hot, x).to_array()
    } else {
        Vec3::new(0.15, 0.25, 0.9).lerp(Vec3::new(0.1, 0.9, 0.9), -x).to_array()
    }
}

/// Colour of a particle: a few distinct hues by id; immovable ones grey.
#[must_use]
pub fn particle_color(id: ParticleId, immovable: bool) -> [f32; 3] {
    const PALETTE: [[f32; 3]; 6] = [
        [0.90, 0.55, 0.10],
        [0.85, 0.85, 0.80],
        [0.20, 0.60, 0.90],
        [0.85, 0.25, 0.45],
        [0.35, 0.80, 0.45],
        [0.75, 0.65, 0.20],
    ];
    if immovable { [0.4, 0.4, 0.4] } else { PALETTE[id.0 as usize % PALETTE.len()] }
}

/// Recent positions of moving particles, for trails that fade with age.
#[derive(Debug, Default)]
pub struct Trails {
    points: HashMap<ParticleId, VecDeque<(Vec3, f64)>>,
    spare: Vec<VecDeque<(Vec3, f64)>>,
}

impl Trails {
    /// How long a trail point lasts (s).
    pub const LIFETIME: f64 = 4.0;
    /// Smallest distance between recorded points (m).
    const SPACING: f32 = 0.05;
    /// Scenes with more particles than this get no trails: a trail behind every
    /// sphere of a pile is clutter, and recording costs a map look-up per particle.
    pub const PARTICLE_LIMIT: usize = 5_000;

    /// Records where every particle is at simulated time `now`, and forgets points
    /// older than the lifetime (also of particles that are gone). Above
    /// [`Self::PARTICLE_LIMIT`] particles it records nothing and forgets everything.
    pub fn record(&mut self, scene: &dyn Scene, now: f64) {
        let particles = &scene.world().particles;
        if particles.len() > Self::PARTICLE_LIMIT {
            self.clear();
            return;
        }
        for (i, &id) in particles.ids().iter().enumerate() {
            let p = particles.position[i];
            let spare = &mut self.spare;
            let trail = self.points.entry(id).or_insert_with(|| spare.pop().unwrap_or_default());
            if trail.back().is_none_or(|&(last, _)| last.distance(p) >= Self::SPACING) {
                trail.push_back((p, now));
            }
        }
        for trail in self.points.values_mut() {
            while trail.front().is_some_and(|&(_, t)| now - t > Self::LIFETIME || t > now) {
                trail.pop_front();
            }
        }
        // Emptied trails go to the spare list, so a steady scene allocates nothing.
        let spare = &mut self.spare;
        self.points.retain(|_, trail| {
            if trail.is_empty() {
                spare.push(std::mem::take(trail));
            }
            !trail.is_empty()
        });
    }

    /// Forgets every trail.
    pub fn clear(&mut self) {
        self.spare.extend(self.points.drain().map(|(_, mut trail)| {
            trail.clear();
            trail
        }));
    }
}

/// Builds [`FrameData`] from a scene, reusing its storage from frame to frame.
#[derive(Debug)]
pub struct FrameBuilder {
    links: Vec<LinkState>,
    contact_points: Vec<crate::physics::ContactPoint>,
    markers: Vec<Marker>,
    outlines: Vec<(Vec3, Vec3)>,
    /// The frame built last.
    pub frame: FrameData,
    /// How large the drawing's own marks are (the least radius a particle is drawn
    /// with, an anchor's sphere), as a share of their size seen from afar: 1 for a
    /// camera [`DECORATION_DISTANCE`] or more away, less for one closer, so that a
    /// millimetre particle seen from centimetres is drawn at its own size, not as a
    /// 5 cm ball. See [`decoration_scale`].
    pub decoration_scale: f32,
}

impl Default for FrameBuilder {
    fn default() -> Self {
        Self {
            links: Vec::new(),
            contact_points: Vec::new(),
            markers: Vec::new(),
            outlines: Vec::new(),
            frame: FrameData::default(),
            decoration_scale: 1.0,
        }
    }
}

/// The least radius a particle is drawn with, seen from [`DECORATION_DISTANCE`] or
/// further (m): a point particle stays visible.
pub const MIN_DRAWN_RADIUS: f32 = 0.05;
/// Radius of the sphere drawn at a link's fixed end, seen from afar (m).
pub const ANCHOR_RADIUS: f32 = 0.08;
/// Camera distance (m) from which the drawing's own marks have their full size (every
/// built-in scene is seen from further); a closer camera shrinks them in proportion, so
/// a point particle stays a dot about 5% of the distance across, and a millimetre
/// particle framed from centimetres is drawn at its own size.
pub const DECORATION_DISTANCE: f32 = 1.0;

/// [`FrameBuilder::decoration_scale`] for a camera `distance` (m) from its target.
#[must_use]
pub fn decoration_scale(distance: f32) -> f32 {
    if distance.is_finite() && distance > 0.0 { (distance / DECORATION_DISTANCE).min(1.0) } else { 1.0 }
}

impl FrameBuilder {
    /// Fills `self.frame` for the scene's current state. `highlight` is drawn brighter
    /// and larger (the particle under the mouse or being dragged).
    pub fn build(
        &mut self,
        scene: &dyn Scene,
        trails: Option<&Trails>,
        now: f64,
        options: ViewOptions,
        highlight: Option<ParticleId>,
    ) -> &FrameData {
        let frame = &mut self.frame;
        frame.spheres.clear();
        frame.segments.clear();
        frame.trails.clear();
        frame.grid = options.grid;
        let world = scene.world();
        let particles = &world.particles;
        frame.shadows = particles.len() <= SHADOW_LIMIT;
        let speed_table = &*SPEED_TABLE;
        let colors = scene.particle_colors();
        let each = particles.ids().iter().zip(&particles.position).zip(&particles.radius);
        let turning = particles.orientations().iter().zip(particles.inverse_inertias());
        for ((((&id, position), &radius), (&inverse_mass, velocity)), (orientation, &inverse_inertia)) in
            each.zip(particles.inverse_mass.iter().zip(&particles.velocity)).zip(turning)
        {
            let immovable = inverse_mass == 0.0;
            let mut color = if options.color_by_speed && !immovable {
                ramp_lookup(speed_table, velocity.length())
            } else {
                match colors.binary_search_by_key(&id, |&(id, _)| id) {
                    Ok(k) => colors[k].1,
                    Err(_) => particle_color(id, immovable),
                }
            };
            let mut radius = radius.max(MIN_DRAWN_RADIUS * self.decoration_scale);
            let mut spin = if inverse_inertia != 0.0 { orientation.to_array() } else { UNMARKED };
            if highlight == Some(id) {
                // Plain yellow, a little larger: the one picked stands out.
                color = [1.0, 0.95, 0.3];
                radius *= 1.15;
                spin = UNMARKED;
            }
            frame.spheres.push(SphereInstance {
                center: position.to_array(),
                radius,
                color: [color[0], color[1], color[2], 1.0],
                spin,
            });
        }
        self.markers.clear();
        scene.markers(&mut self.markers);
        if options.predictions {
            scene.predictions(&mut self.markers);
        }
        for marker in &self.markers {
            let [r, g, b] = marker.color;
            frame.spheres.push(SphereInstance {
                center: marker.position.to_array(),
                radius: marker.radius,
                color: [r, g, b, 1.0],
                spin: UNMARKED,
            });
        }

        world.links_into(&mut self.links);
        let reference = tension_reference(&self.links);
        let springs = self.links.iter().filter(|l| coiled(l.spec.kind)).count();
        for link in &self.links {
            let [r, g, b] = if options.tension_colors {
                tension_color(link.tension, reference)
            } else {
                link_color(link.spec.kind)
            };
            let color = [r, g, b, 1.0];
            let width = match link.spec.kind {
                LinkKind::Rod | LinkKind::SupportRod => 5.0,
                LinkKind::Spring | LinkKind::Bungee | LinkKind::StiffSpring => 4.0,
                LinkKind::Cable | LinkKind::SupportCable => 3.0,
            };
            if coiled(link.spec.kind) && springs <= COIL_LIMIT {
                coil(link.from, link.to, color, &mut frame.segments);
            } else {
                frame.segments.push(SegmentInstance {
                    from: link.from.to_array(),
                    width,
                    to: link.to.to_array(),
                    pad: 0.0,
                    color,
                });
            }
            // Anchors: a small grey sphere where a link is fixed in space.
            if let crate::physics::LinkEnd::Anchor(anchor) = link.spec.b {
                frame.spheres.push(SphereInstance {
                    center: anchor.to_array(),
                    radius: ANCHOR_RADIUS * self.decoration_scale,
                    color: [0.35, 0.35, 0.38, 1.0],
                    spin: UNMARKED,
                });
            }
            if options.contacts {
                link_limit(link, &mut frame.trails, &mut frame.segments);
            }
        }
        if options.contacts {
            world.contact_points_into(&mut self.contact_points);
            for contact in self.contact_points.iter().take(CONTACT_DRAW_LIMIT) {
                contact_marker(contact, &mut frame.segments);
            }
        }

        self.outlines.clear();
        scene.outlines(&mut self.outlines);
        for &(from, to) in &self.outlines {
            frame.segments.push(SegmentInstance {
                from: from.to_array(),
                width: 2.0,
                to: to.to_array(),
                pad: 0.0,
                color: [0.55, 0.6, 0.68, 1.0],
            });
        }

        if let Some(water) = scene.water() {
            frame.water = Some(WaterQuad {
                center: [water.center.x, water.height, water.center.y, 0.0],
                half_extent: [water.half_extent.x, water.half_extent.y, 0.0, 0.0],
            });
            // The pool's rim and floor edges, so its depth reads.
            let (c, h) = (water.center, water.half_extent);
            let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
            for k in 0..4 {
                let (ax, az) = corners[k];
                let (bx, bz) = corners[(k + 1) % 4];
                for y in [0.0, water.height] {
                    frame.segments.push(SegmentInstance {
                        from: [c.x + ax * h.x, y, c.y + az * h.y],
                        width: 2.0,
                        to: [c.x + bx * h.x, y, c.y + bz * h.y],
                        pad: 0.0,
                        color: [0.3, 0.5, 0.7, 1.0],
                    });
                }
            }
        } else {
            frame.water = None;
        }

        if options.swept {
            swept_paths(
                world,
                MIN_DRAWN_RADIUS * self.decoration_scale,
                &mut frame.trails,
                &mut frame.spheres,
            );
        }

        if let (true, Some(trails)) = (options.trails, trails) {
            for trail in trails.points.values() {
                for ((a, _), (b, tb)) in trail.iter().zip(trail.iter().skip(1)) {
                    let fade = (1.0 - (now - tb) / Trails::LIFETIME).clamp(0.0, 1.0) as f32;
                    frame.trails.push(SegmentInstance {
                        from: a.to_array(),
                        width: 2.5,
                        to: b.to_array(),
                        pad: 0.0,
                        color: [1.0, 0.8, 0.35, 0.8 * fade],
                    });
                }
            }
        }
        &self.frame
    }
}

/// The tension that [`tension_color`] paints hottest in a frame: the largest pull or
/// push of any link (N), so the colours use their whole range in every scene.
#[must_use]
pub fn tension_reference(links: &[LinkState]) -> f32 {
    links.iter().map(|l| l.tension.abs()).fold(0.0, f32::max)
}

/// Links of these kinds are drawn as coils.
fn coiled(kind: LinkKind) -> bool {
    matches!(kind, LinkKind::Spring | LinkKind::StiffSpring)
}

/// Above this many springs they are drawn straight: coils of hundreds would be clutter.
pub const COIL_LIMIT: usize = 64;
/// Turns of a drawn coil.
const COIL_TURNS: usize = 10;
/// Segments per turn.
const COIL_SEGMENTS: usize = 8;
/// Radius of a drawn coil (m).
const COIL_RADIUS: f32 = 0.09;

/// A spring from `from` to `to` as a helix of [`COIL_TURNS`] turns with short straight
/// leads at both ends, so it stretches and squeezes as the spring does.
fn coil(from: Vec3, to: Vec3, color: [f32; 4], out: &mut Vec<SegmentInstance>) {
    let axis = to - from;
    let length = axis.length();
    let mut push = |a: Vec3, b: Vec3| {
        out.push(SegmentInstance { from: a.to_array(), width: 2.5, to: b.to_array(), pad: 0.0, color });
    };
    if length < 1e-4 {
        return;
    }
    let along = axis / length;
    let (u, w) = along.any_orthonormal_pair();
    let (start, end) = (from + axis * 0.1, from + axis * 0.9);
    push(from, start);
    let steps = COIL_TURNS * COIL_SEGMENTS;
    let mut last = start;
    for k in 0..=steps {
        let t = k as f32 / steps as f32;
        let angle = std::f32::consts::TAU * COIL_TURNS as f32 * t;
        let point = start.lerp(end, t) + (u * angle.sin() + w * angle.cos()) * COIL_RADIUS;
        push(last, point);
        last = point;
    }
    push(last, end);
    last = end;
    push(last, to);
}

/// Most contacts drawn in one frame (a pile has tens of thousands).
pub const CONTACT_DRAW_LIMIT: usize = 20_000;

/// A contact as Box2D's debug drawing shows it: a short line along the normal standing
/// on a small cross in the contact plane (a pin, never a ball that could pass for a
/// particle); red where the surfaces overlap by more than 1 mm, yellow where they touch,
/// grey for a gap the soft solver keeps in case they meet.
fn contact_marker(contact: &crate::physics::ContactPoint, segments: &mut Vec<SegmentInstance>) {
    let color = if contact.depth > 1e-3 {
        [1.0, 0.15, 0.1, 1.0]
    } else if contact.depth > -1e-3 {
        [1.0, 0.85, 0.1, 1.0]
    } else {
        [0.6, 0.6, 0.65, 1.0]
    };
    let mut push = |from: Vec3, to: Vec3| {
        segments.push(SegmentInstance {
            from: from.to_array(),
            width: 2.0,
            to: to.to_array(),
            pad: 0.0,
            color,
        });
    };
    push(contact.point, contact.point + contact.normal * CONTACT_NORMAL_LENGTH);
    let (u, w) = contact.normal.any_orthonormal_pair();
    for across in [u, w] {
        push(contact.point - across * CONTACT_CROSS_HALF, contact.point + across * CONTACT_CROSS_HALF);
    }
}

/// Half the width of the cross a contact's normal stands on (m).
pub const CONTACT_CROSS_HALF: f32 = 0.05;

/// Length of a drawn contact normal (m).
pub const CONTACT_NORMAL_LENGTH: f32 = 0.25;

/// A link's limit: a white collar (a ring around the link, not a ball, so it is never
/// taken for a particle) at the length it may not exceed (a cable) or rests at (a
/// spring or bungee), measured from its second end (the anchor, for a link to a fixed
/// point) along the link, and a translucent band from there to the first end: a
/// spring's stretch or squeeze, a cable's slack. A taut cable's collar sits on its
/// particle.
fn link_limit(link: &LinkState, bands: &mut Vec<SegmentInstance>, segments: &mut Vec<SegmentInstance>) {
    let limit = match link.spec.kind {
        LinkKind::Cable | LinkKind::SupportCable | LinkKind::Spring | LinkKind::Bungee => link.spec.rest,
        LinkKind::Rod | LinkKind::SupportRod | LinkKind::StiffSpring => return,
    };
    let Some(direction) = (link.from - link.to).try_normalize() else { return };
    let end = link.to + direction * limit;
    bands.push(SegmentInstance {
        from: end.to_array(),
        width: 6.0,
        to: link.from.to_array(),
        pad: 0.0,
        color: [0.95, 0.95, 0.95, 0.35],
    });
    ring(end, direction, LIMIT_COLLAR_RADIUS, [0.95, 0.95, 0.95, 1.0], segments);
}

/// Radius of the collar marking a link's limit (m): wider than a drawn coil.
pub const LIMIT_COLLAR_RADIUS: f32 = 0.16;
/// Sides of a drawn ring.
const RING_SIDES: usize = 12;

/// A ring of `radius` (m) around `center` in the plane across `axis` (unit): edge-on
/// a bar across the axis, from an angle an ellipse; never a ball.
fn ring(center: Vec3, axis: Vec3, radius: f32, color: [f32; 4], out: &mut Vec<SegmentInstance>) {
    let (u, w) = axis.any_orthonormal_pair();
    let at = |k: usize| {
        let angle = std::f32::consts::TAU * k as f32 / RING_SIDES as f32;
        center + (u * angle.cos() + w * angle.sin()) * radius
    };
    for k in 0..RING_SIDES {
        out.push(SegmentInstance {
            from: at(k).to_array(),
            width: 2.5,
            to: at(k + 1).to_array(),
            pad: 0.0,
            color,
        });
    }
}

/// Most swept paths drawn in one frame: enough for any scene a student fires rounds
/// in, and a bound on the cost in a pile where everything falls at once.
pub const SWEPT_LIMIT: usize = 512;

/// For each particle that moved more than its radius in the last step (at most
/// [`SWEPT_LIMIT`] of them): a translucent band from where it started to where it is,
/// and a translucent ghost where it started. A sphere that moves more than its own size
/// in one step would pass through a thin obstacle unless collision is continuous.
fn swept_paths(
    world: &crate::physics::World,
    least: f32,
    bands: &mut Vec<SegmentInstance>,
    ghosts: &mut Vec<SphereInstance>,
) {
    let particles = &world.particles;
    let motion = world.last_motion();
    let bodies = particles.positions().iter().zip(particles.radii()).zip(motion);
    for ((&position, &radius), &moved) in
        bodies.filter(|((_, r), m)| m.length() > r.max(least)).take(SWEPT_LIMIT)
    {
        let start = position - moved;
        bands.push(SegmentInstance {
            from: start.to_array(),
            width: 6.0,
            to: position.to_array(),
            pad: 0.0,
            color: [0.35, 0.85, 1.0, 0.6],
        });
        ghosts.push(SphereInstance {
            center: start.to_array(),
            radius: radius.max(least),
            color: [0.35, 0.85, 1.0, 0.35],
            spin: UNMARKED,
        });
    }
}
