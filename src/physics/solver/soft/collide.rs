//! Stage 1, collide: contacts from every generator once a step, with speculative
//! margins; sphere pairs are swept over the step so that a pair passing by is never
//! stopped by a ghost; rods and cables join the step as links.

use web_time::Instant;

use glam::Vec3;
use rayon::prelude::*;

use super::warm::key;
use super::{FreshContact, NONE, SoftLink, SoftStep, Surface, ms};
use crate::physics::collision::{BroadPhase, ContactGenerator, Plane, Plate, Scratch};
use crate::physics::ids::ContactGeneratorId;
use crate::physics::links::{Constraint, LinkEnd, direction_or_zero};
use crate::physics::particles::{AWAKE, Particles};
use crate::physics::solver::report::Profile;
use crate::physics::solver::settings::SolverSettings;

impl SoftStep {
    /// Stage 1: contacts from every generator, with speculative margins.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn collide(
        &mut self,
        settings: &SolverSettings,
        particles: &Particles,
        generators: &[(ContactGeneratorId, ContactGenerator)],
        broad_phase: &mut BroadPhase,
        scratch: &mut Scratch,
        dt: f32,
        profile: &mut Profile,
    ) {
        // How far each particle can move this step, plus the fixed margin; the lengths
        // of the accelerations are kept for the sphere pairs' slack.
        self.acceleration.clear();
        self.acceleration.extend(particles.acceleration.iter().map(|a| a.length()));
        self.margin.clear();
        self.margin.extend(
            particles
                .velocity
                .iter()
                .zip(&self.acceleration)
                .map(|(v, &a)| settings.speculative_distance + (v.length() + a * dt) * dt),
        );
        self.fresh.clear();
        self.fresh_keys.clear();
        self.fresh_groups.clear();
        self.links.clear();
        self.sleeping_links.clear();
        self.to_wake.clear();
        self.asleep.clear();
        self.asleep.extend(particles.sleep.iter().map(|s| s.island != AWAKE));
        let any_asleep = self.asleep.contains(&true);
        // With every sphere asleep there is nobody to query the grid: skip building it.
        let any_awake_sphere =
            particles.radius.iter().zip(&self.asleep).any(|(&r, &asleep)| r > 0.0 && !asleep);
        profile.broad_phase_ms = 0.0;
        scratch.pair_budget_hit = false;
        self.bouncy_contacts = false;
        self.surfaces.clear();
        self.surfaces.extend(generators.iter().map(|(_, generator)| surface(generator)));
        let started = Instant::now();
        for (source, (id, generator)) in generators.iter().enumerate() {
            let start = self.fresh.len();
            match generator {
                ContactGenerator::Plane(plane) => self.collide_plane(plane, particles, source as u32),
                ContactGenerator::Plate(plate) => self.collide_plate(plate, particles, source as u32),
                ContactGenerator::Spheres(_) if !any_awake_sphere => {}
                ContactGenerator::Spheres(_) => {
                    let broad = Instant::now();
                    scratch.reach.clear();
                    scratch.reach.extend(
                        particles.radius.iter().zip(&self.margin).map(
                            |(&r, &m)| {
                                if r > 0.0 { r + m } else { 0.0 }
                            },
                        ),
                    );
                    let asleep = any_asleep.then_some(self.asleep.as_slice());
                    broad_phase.find_pairs_awake(
                        &particles.position,
                        &scratch.reach,
                        asleep,
                        &mut scratch.pairs,
                    );
                    scratch.pair_budget_hit |= broad_phase.budget_hit();
                    profile.broad_phase_ms += ms(broad.elapsed());
                    let slack = 2.0 * settings.speculative_distance;
                    self.collide_spheres(source as u32, particles, &scratch.pairs, slack, dt);
                }
                ContactGenerator::Link(link) => self.add_link(link, particles, source as u32),
            }
            if self.fresh.len() > start {
                self.fresh_groups.push((*id, start..self.fresh.len()));
                // Every contact takes its generator's restitution.
                self.bouncy_contacts |= self.surfaces[source].restitution > 0.0;
            }
        }
        profile.narrow_phase_ms = ms(started.elapsed()) - profile.broad_phase_ms;
    }

    fn collide_plane(&mut self, plane: &Plane, particles: &Particles, source: u32) {
        let positions = particles.position.iter().zip(&particles.radius);
        let bodies = particles.inverse_mass.iter().zip(&self.margin);
        for (i, (((&p, &r), (&w, &margin)), &asleep)) in positions.zip(bodies).zip(&self.asleep).enumerate() {
            let separation = plane.distance(p) - r;
            if w > 0.0 && !asleep && separation < margin && plane.covers(p) {
                self.fresh_keys.push(key(i as u32, NONE));
                self.fresh.push(still_contact(i, plane.normal, separation, source));
            }
        }
    }

    /// A plate's contacts: against its nearest point (a face or the opening's rim),
    /// with the normal from that point, fixed for the step as a sphere pair's is.
    fn collide_plate(&mut self, plate: &Plate, particles: &Particles, source: u32) {
        let positions = particles.position.iter().zip(&particles.radius);
        let bodies = particles.inverse_mass.iter().zip(&self.margin);
        for (i, (((&p, &r), (&w, &margin)), &asleep)) in positions.zip(bodies).zip(&self.asleep).enumerate() {
            if w <= 0.0 || asleep {
                continue;
            }
            let (normal, distance) = plate.nearest(p);
            let separation = distance - r;
            if separation < margin {
                self.fresh_keys.push(key(i as u32, NONE));
                self.fresh.push(still_contact(i, normal, separation, source));
            }
        }
    }

    /// Contacts of the broad phase's pairs that can come within `slack` of touching in
    /// the step `dt` (see [`swept_contact`]: a pair that only passes by gets none).
    ///
    /// The pairs are taken in chunks on several threads when there are many and the
    /// pool has more than one; each chunk's contacts (and islands to wake) are then
    /// appended in chunk order, so the contacts come out in the pairs' order whatever
    /// the number of threads. On one thread they are made straight onto the lists.
    fn collide_spheres(
        &mut self,
        source: u32,
        particles: &Particles,
        pairs: &[(u32, u32)],
        slack: f32,
        dt: f32,
    ) {
        let (asleep, acceleration) = (&self.asleep, &self.acceleration);
        if pairs.len() < PARALLEL_PAIRS || rayon::current_num_threads() == 1 {
            // One task: straight onto the fresh lists (the order chunks would give),
            // without copying each contact a second time.
            let mut out = PairChunk {
                keys: std::mem::take(&mut self.fresh_keys),
                contacts: std::mem::take(&mut self.fresh),
                wake: std::mem::take(&mut self.to_wake),
            };
            collide_pairs(source, particles, (asleep, acceleration), pairs, slack, dt, &mut out);
            (self.fresh_keys, self.fresh, self.to_wake) = (out.keys, out.contacts, out.wake);
            return;
        }
        let chunks = pairs.len().div_ceil(PAIR_CHUNK);
        if self.pair_chunks.len() < chunks {
            self.pair_chunks.resize_with(chunks, PairChunk::default);
        }
        let collide = |(k, out): (usize, &mut PairChunk)| {
            out.clear();
            let pairs = &pairs[k * PAIR_CHUNK..((k + 1) * PAIR_CHUNK).min(pairs.len())];
            collide_pairs(source, particles, (asleep, acceleration), pairs, slack, dt, out);
        };
        self.pair_chunks[..chunks].par_iter_mut().enumerate().for_each(collide);
        let outputs = &self.pair_chunks[..chunks];
        append(&mut self.fresh_keys, outputs, |out| &out.keys);
        append(&mut self.fresh, outputs, |out| &out.contacts);
        for out in outputs {
            self.to_wake.extend_from_slice(&out.wake);
        }
    }

    fn add_link(&mut self, link: &Constraint, particles: &Particles, generator: u32) {
        let Some(a) = particles.index(link.a) else { return };
        let (b, anchor) = match link.b {
            LinkEnd::Particle(id) => match particles.index(id) {
                Some(b) if b != a => (b as u32, Vec3::ZERO),
                _ => return, // gone, or a link to itself, which constrains nothing
            },
            LinkEnd::Anchor(point) => (NONE, point),
        };
        let w = particles.inverse_mass[a] + if b == NONE { 0.0 } else { particles.inverse_mass[b as usize] };
        if w <= 0.0 {
            return;
        }
        let asleep_b = b != NONE && self.asleep[b as usize];
        match (self.asleep[a], asleep_b) {
            (true, true) => {
                self.sleeping_links.push(generator);
                return;
            }
            (true, false) if b != NONE && particles.inverse_mass[b as usize] > 0.0 => {
                self.to_wake.push(particles.sleep[a].island);
            }
            (false, true) if particles.inverse_mass[a] > 0.0 => {
                self.to_wake.push(particles.sleep[b as usize].island)
            }
            (true, false) => {
                // Asleep on an anchor or an immovable particle.
                self.sleeping_links.push(generator);
                return;
            }
            _ => {}
        }
        self.links.push(SoftLink {
            a: a as u32,
            b,
            anchor,
            length: link.length,
            rigid: link.rigid,
            restitution: link.restitution,
            mass: 1.0 / w,
            impulse: 0.0,
            generator,
        });
    }
}

/// The surface a generator gives each of its contacts (a link makes none: no
/// restitution, friction or rolling resistance).
fn surface(generator: &ContactGenerator) -> Surface {
    let (restitution, friction, rolling_resistance) = match generator {
        ContactGenerator::Plane(plane) => (plane.restitution, plane.friction, plane.rolling_resistance),
        ContactGenerator::Plate(plate) => (plate.restitution, plate.friction, plate.rolling_resistance),
        ContactGenerator::Spheres(s) => (s.restitution, s.friction, s.rolling_resistance),
        ContactGenerator::Link(_) => (0.0, 0.0, 0.0),
    };
    Surface { restitution, friction, rolling_resistance }
}

/// Pairs per chunk of the sphere contacts (one task each). Under Miri this and the
/// two sizes below are a few pairs and bytes, so that its run of the tests reaches the
/// threads and [`append`]'s `set_len` at a size it can interpret; which path runs
/// changes no bit.
const PAIR_CHUNK: usize = if cfg!(miri) { 8 } else { 2048 };
/// Pairs from which the sphere contacts are made on several threads.
const PARALLEL_PAIRS: usize = if cfg!(miri) { 16 } else { 4096 };

/// Bytes from which [`append`] copies on several threads: an 8,000-sphere pile's
/// 29,000 contacts (2.4 MB) already copy faster on two (from 32,768 contacts down to
/// this, its narrow phase took 0.25 instead of 0.26 ms a step on 2 threads in the
/// cores' fast mode, 0.31–0.33 instead of 0.36–0.41 in their slow one); their keys
/// (230 KB) stay on one.
const PARALLEL_APPEND: usize = if cfg!(miri) { 256 } else { 512 * 1024 };

/// Appends `part` of every chunk to `to`, chunk after chunk: on several threads for
/// many (a falling pile of 100,000 spheres makes 33 MB of contacts a step, too much
/// to copy on one).
fn append<T: Copy + Send + Sync>(to: &mut Vec<T>, chunks: &[PairChunk], part: fn(&PairChunk) -> &[T]) {
    let total: usize = chunks.iter().map(|chunk| part(chunk).len()).sum();
    if total * std::mem::size_of::<T>() < PARALLEL_APPEND {
        chunks.iter().for_each(|chunk| to.extend_from_slice(part(chunk)));
        return;
    }
    let start = to.len();
    to.reserve(total);
    copy_parts(&mut to.spare_capacity_mut()[..total], chunks, part);
    // SAFETY: `copy_parts` wrote all `total` elements after the first `start` (each
    // chunk's part to its own run, the runs one after another, summing to `total`).
    unsafe { to.set_len(start + total) };
}

/// Writes `part` of each chunk into `out`, one after another, which they fill exactly:
/// halves of the chunks on two tasks at a time.
fn copy_parts<T: Copy + Send + Sync>(
    out: &mut [std::mem::MaybeUninit<T>],
    chunks: &[PairChunk],
    part: fn(&PairChunk) -> &[T],
) {
    if chunks.len() <= 4 {
        let mut at = 0;
        for chunk in chunks {
            let values = part(chunk);
            for (slot, &value) in out[at..at + values.len()].iter_mut().zip(values) {
                slot.write(value);
            }
            at += values.len();
        }
        assert_eq!(at, out.len(), "the parts fill their run");
        return;
    }
    let middle = chunks.len() / 2;
    let left: usize = chunks[..middle].iter().map(|chunk| part(chunk).len()).sum();
    let (low, high) = out.split_at_mut(left);
    rayon::join(|| copy_parts(low, &chunks[..middle], part), || copy_parts(high, &chunks[middle..], part));
}

/// One chunk's sphere contacts, their keys and the sleeping islands its pairs reached.
#[derive(Clone, Debug, Default)]
pub(super) struct PairChunk {
    keys: Vec<u64>,
    contacts: Vec<FreshContact>,
    wake: Vec<u32>,
}

impl PairChunk {
    fn clear(&mut self) {
        self.keys.clear();
        self.contacts.clear();
        self.wake.clear();
    }
}

/// The contacts of `pairs` into `out` (see [`SoftStep::collide_spheres`]), given which
/// particles sleep and the length of each one's acceleration (m/s²).
fn collide_pairs(
    source: u32,
    particles: &Particles,
    (asleep, acceleration): (&[bool], &[f32]),
    pairs: &[(u32, u32)],
    slack: f32,
    dt: f32,
    out: &mut PairChunk,
) {
    let (p, w, r, v) = (&particles.position, &particles.inverse_mass, &particles.radius, &particles.velocity);
    for &(a, b) in pairs {
        let (i, j) = (a as usize, b as usize);
        let total = w[i] + w[j];
        if total <= 0.0 {
            continue;
        }
        if asleep[j] {
            // An awake particle reached a sleeping one: wake its island.
            if w[j] > 0.0 {
                out.wake.push(particles.sleep[j].island);
            }
            continue;
        }
        // Gravity moves both alike; any difference in constant acceleration may close
        // the gap by up to |a_i - a_j| dt² / 2 (counted twice, as the margins do).
        let slack = slack + (acceleration[i] + acceleration[j]) * dt * dt;
        let swept = swept_contact(p[i] - p[j], v[i] - v[j], r[i] + r[j], dt, slack);
        let Some((normal, separation)) = swept else { continue };
        out.keys.push(key(a, b));
        out.contacts.push(FreshContact { a, b, normal, separation, source });
    }
}

/// The contact of particle `i` with something that does not move (a plane, a plate,
/// generator `source`): its normal and separation (m).
#[inline]
fn still_contact(i: usize, normal: Vec3, separation: f32, source: u32) -> FreshContact {
    FreshContact { a: i as u32, b: NONE, normal, separation, source }
}

/// What a contact's solve needs of its particles `a` and `b` ([`NONE`] for a plane)
/// beyond its normal: see [`terms`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Terms {
    /// Effective mass along any direction, `1 / (1/m_a + 1/m_b)` (kg).
    pub(super) mass: f32,
    /// Effective mass of the contact point along a tangent (kg): `1 / (1/m_a + 1/m_b
    /// + r_a²/I_a + r_b²/I_b)`, which is `mass` when nothing rolls.
    pub(super) tangent_mass: f32,
    /// Lever of `a`'s contact point (m): its radius if it rolls (the contact point is
    /// `-lever_a · normal` from its centre), else 0.
    pub(super) lever_a: f32,
    /// Lever of `b`'s contact point (m): its radius if it rolls (at `+lever_b ·
    /// normal` from its centre), else 0.
    pub(super) lever_b: f32,
    /// Largest rolling-resistance torque per newton of normal force (m): the
    /// coefficient times the rolling radius; 0 for none.
    pub(super) rolling: f32,
    /// Effective inertia against relative spin (kg·m²), `1 / (1/I_a + 1/I_b)`; 0 when
    /// neither rolls.
    pub(super) rolling_mass: f32,
}

/// The effective mass of a contact of `a` and `b` ([`NONE`] for a plane), `1 / (w_a +
/// w_b)` from the particles' inverse masses `w`.
#[inline]
pub(super) fn effective_mass(w: &[f32], a: u32, b: u32) -> f32 {
    1.0 / (w[a as usize] + if b == NONE { 0.0 } else { w[b as usize] })
}

/// A contact's [`Terms`], with rolling resistance `coefficient`: the levers of its
/// contact point for spheres that roll, the tangential effective mass with their
/// turning, and the coefficient times the rolling radius (`r_a r_b / (r_a + r_b)` for
/// two spheres that roll, else the radius of the one that does). A contact of point
/// masses has no levers, and its tangential mass is its mass.
#[inline]
pub(super) fn terms(particles: &Particles, a: u32, b: u32, coefficient: f32) -> Terms {
    let mass = effective_mass(&particles.inverse_mass, a, b);
    let none = Terms { mass, tangent_mass: mass, ..Terms::default() };
    let inertia = &particles.inverse_inertia;
    let (ia, ib) = (inertia[a as usize], if b == NONE { 0.0 } else { inertia[b as usize] });
    if ia == 0.0 && ib == 0.0 {
        return none;
    }
    let radius = &particles.radius;
    let lever_a = if ia > 0.0 { radius[a as usize] } else { 0.0 };
    let lever_b = if ib > 0.0 { radius[b as usize] } else { 0.0 };
    let tangent_mass = 1.0 / (1.0 / mass + ia * lever_a * lever_a + ib * lever_b * lever_b);
    let rolling_radius = if lever_a > 0.0 && lever_b > 0.0 {
        lever_a * lever_b / (lever_a + lever_b)
    } else {
        lever_a.max(lever_b)
    };
    Terms {
        mass,
        tangent_mass,
        lever_a,
        lever_b,
        rolling: coefficient * rolling_radius,
        rolling_mass: 1.0 / (ia + ib),
    }
}

/// The contact of two spheres `offset = p_a - p_b` apart, closing with relative velocity
/// `velocity = v_a - v_b`, whose radii sum to `reach`: its unit normal (pointing the way
/// `a` is pushed) and its gap along that normal at the start of the step, or `None` when
/// the swept spheres come no closer than `slack` to touching within `dt`.
///
/// The relative path `d(t) = offset + velocity·t` is a straight line over the step.
/// The solver keeps a contact's gap along a fixed normal, `d(t)·n - reach`, from going
/// negative, so the normal decides what the contact does:
/// - overlapping at the start: the line of centres now (the overlap is pushed out);
/// - meeting within the step: the line of centres at the time of impact, the smallest
///   `t` in `[0, dt]` with `|d(t)| = reach` (the quadratic of PHYSICS.md). Along it the
///   gap is positive before `t` and zero at `t`, so the pair is stopped where it
///   touches and pushed the way it really touches (a glancing hit goes sideways);
/// - only passing near: the line of centres at the closest approach `t*`. As `t*`
///   minimises `|d|` over `[0, dt]`, `d(t*)·velocity·(t - t*) >= 0` for every `t` in the
///   step, so `d(t)·n >= |d(t*)| > reach`: the contact cannot act on the motion it was
///   made for. It is there for pushes from other contacts within the step (a pile).
///
/// A normal from the start separation alone would stop two spheres passing at a clear
/// gap as soon as their start-of-step line of centres closed: a ghost collision.
#[inline]
fn swept_contact(offset: Vec3, velocity: Vec3, reach: f32, dt: f32, slack: f32) -> Option<(Vec3, f32)> {
    let unit_or_up = |d: Vec3| {
        // Coincident centres have no direction: separate them vertically.
        let (n, length) = direction_or_zero(d);
        (if n == Vec3::ZERO { Vec3::Y } else { n }, length)
    };
    let squared = offset.length_squared();
    if squared <= reach * reach {
        let (normal, distance) = unit_or_up(offset);
        return Some((normal, distance - reach));
    }
    let closing = offset.dot(velocity);
    let speed_squared = velocity.length_squared();
    let closest_time = if speed_squared > 0.0 { (-closing / speed_squared).clamp(0.0, dt) } else { 0.0 };
    let closest = offset + velocity * closest_time;
    let closest_distance = closest.length();
    if closest_distance - reach >= slack {
        return None;
    }
    let at = if closest_distance < reach {
        // |offset + velocity t|² = reach²: the earlier root (the pair closes, so the
        // discriminant is positive and `closing` negative).
        let c = squared - reach * reach;
        let root = (closing * closing - speed_squared * c).max(0.0).sqrt();
        offset + velocity * (c / (-closing + root))
    } else {
        closest
    };
    let (normal, _) = unit_or_up(at);
    Some((normal, offset.dot(normal) - reach))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Appending chunks of uneven sizes (some empty) on several threads gives the list
    /// appending them one after another gives, after what the list held.
    #[test]
    fn appending_on_several_threads_is_appending_in_order() {
        // 300 chunks of up to 1,300 keys; under Miri, whose sizes are smaller, 20 of up to 16.
        let (chunks, spread, least) = if cfg!(miri) { (20, 12, 4) } else { (300, 1200, 100) };
        let sizes =
            (0..chunks).map(|k: usize| (k * 7919) % spread + if k.is_multiple_of(13) { 0 } else { least });
        let chunks: Vec<PairChunk> = sizes
            .enumerate()
            .map(|(k, size)| PairChunk {
                keys: (0..size).map(|i| (k as u64) << 32 | i as u64).collect(),
                ..PairChunk::default()
            })
            .collect();
        let total: usize = chunks.iter().map(|c| c.keys.len()).sum();
        assert!(total * size_of::<u64>() >= 2 * PARALLEL_APPEND, "{total} keys: the parallel path");
        let mut expected = vec![7, 8, 9];
        chunks.iter().for_each(|c| expected.extend_from_slice(&c.keys));
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let mut appended = vec![7, 8, 9];
        pool.install(|| append(&mut appended, &chunks, |c| &c.keys));
        assert_eq!(appended, expected);
        // A few, on one thread.
        let mut few = Vec::new();
        append(&mut few, &chunks[..3], |c| &c.keys);
        assert_eq!(few, expected[3..3 + few.len()]);
    }
}
