//! The impact stage of a substep: pairs that meet within the substep bounce, one pair at
//! a time, so a blow passes down a row of balls.

use glam::Vec3;

use super::collide::effective_mass;
use super::{Impact, NONE, SoftStep};
use crate::physics::particles::Particles;

/// Most passes of the impact stage over its pairs in one substep; a row of `n` touching
/// balls with `k` arriving needs about `k + 1`.
const MAX_IMPACT_SWEEPS: usize = 32;

impl SoftStep {
    /// The impact stage of a substep, between integrating velocities and the solve:
    /// every contact and cable with restitution that closes faster than `threshold` and
    /// would meet within the substep bounces, one pair at a time, in generation order,
    /// sweeping until none is left closing. One pair at a time is what passes a blow
    /// down a row of touching balls (Newton's cradle) instead of sharing it out.
    ///
    /// The bounce is exact for the integrator. Semi-implicit Euler in steps of `h`
    /// under a constant closing acceleration `a` keeps `a·gap + c²/2 - a·h·c/2` for the
    /// closing speed `c` it moved with: its "shadow" energy, conserved exactly where
    /// `a·gap + c²/2` drifts by `a²h²/2` every substep, and at the top of a flight
    /// (`c` = 0) simply `a` times the height. The bounce leaves with the speed whose
    /// shadow energy is `e²` times the one it came with, so a ball dropped on the
    /// ground returns to `e²` of its height at any step (tests/truth.rs).
    ///
    /// Returns what the bounces lost (J, >= 0): for each, the effective mass times the
    /// shadow energy it came with less the one it leaves with, `(1 - e²)` of it (see
    /// [`Impact::leaving_speed`]); 0 for `e = 1`. The change of each particle's velocity
    /// is kept in `bounced`, for the contacts' own bookkeeping after the solve.
    pub(super) fn impacts(&mut self, particles: &mut Particles, h: f32, threshold: f32) -> f64 {
        let (v, v0, w) = (&particles.velocity, &self.substep_velocity, &particles.inverse_mass);
        self.impacts.clear();
        // Generation order (by generator, then by pair), so the result is the same
        // however the contacts were coloured.
        for c in &self.fresh {
            let restitution = self.surfaces[c.source as usize].restitution;
            if restitution == 0.0 {
                continue;
            }
            let moved = if c.b == NONE {
                self.delta[c.a as usize]
            } else {
                self.delta[c.a as usize] - self.delta[c.b as usize]
            };
            let acceleration = (closing(c.a, c.b, c.normal, v) - closing(c.a, c.b, c.normal, v0)) / h;
            self.impacts.push(Impact {
                a: c.a,
                b: c.b,
                normal: c.normal,
                gap: c.separation + moved.dot(c.normal),
                restitution,
                mass: effective_mass(w, c.a, c.b),
                closing_acceleration: acceleration,
            });
        }
        for link in &self.links {
            if link.rigid || link.restitution == 0.0 {
                continue;
            }
            // A cable is a contact whose normal is -u and whose gap is the slack.
            let (u, length, _) = link.geometry(&particles.position, |i| v[i]);
            let acceleration = (closing(link.a, link.b, -u, v) - closing(link.a, link.b, -u, v0)) / h;
            self.impacts.push(Impact {
                a: link.a,
                b: link.b,
                normal: -u,
                gap: link.length - length,
                restitution: link.restitution,
                mass: link.mass,
                closing_acceleration: acceleration,
            });
        }
        if self.impacts.is_empty() {
            return 0.0;
        }
        let v = &mut particles.velocity;
        let mut lost = 0.0;
        for _ in 0..MAX_IMPACT_SWEEPS {
            let mut bounced = false;
            for impact in &self.impacts {
                let c = closing(impact.a, impact.b, impact.normal, v);
                if c <= threshold || impact.gap >= c * h {
                    continue;
                }
                let (leaving, shadow_lost) = impact.leaving_speed(c, h);
                let p = impact.normal * (impact.mass * (leaving + c));
                let change = p * w[impact.a as usize];
                v[impact.a as usize] += change;
                self.bounced.push((impact.a, change));
                if impact.b != NONE {
                    let change = p * w[impact.b as usize];
                    v[impact.b as usize] -= change;
                    self.bounced.push((impact.b, -change));
                }
                lost += f64::from(impact.mass) * f64::from(shadow_lost);
                bounced = true;
            }
            if !bounced {
                break;
            }
        }
        lost
    }

    /// What the cables without restitution lose this substep when they are jerked taut
    /// (J, >= 0): the solve stops them dead, which takes the shadow energy they came
    /// with, as a bounce with `e = 0` would (see [`impacts`](Self::impacts); the same
    /// threshold tells a jerk from a cable that stays taut). Nothing is moved here.
    pub(super) fn jerked_cables(&self, particles: &Particles, h: f32, threshold: f32) -> f64 {
        let (v, v0) = (&particles.velocity, &self.substep_velocity);
        let mut lost = 0.0;
        for link in self.links.iter().filter(|link| !link.rigid && link.restitution == 0.0) {
            let (u, length, _) = link.geometry(&particles.position, |i| v[i]);
            let c = closing(link.a, link.b, -u, v);
            let gap = link.length - length;
            if c <= threshold || gap >= c * h {
                continue;
            }
            let acceleration = (c - closing(link.a, link.b, -u, v0)) / h;
            let jerk = Impact {
                a: link.a,
                b: link.b,
                normal: -u,
                gap,
                restitution: 0.0,
                mass: link.mass,
                closing_acceleration: acceleration,
            };
            lost += f64::from(link.mass) * f64::from(jerk.leaving_speed(c, h).1);
        }
        lost
    }
}

/// How fast `a` and `b` (or `a` and a fixed plane, `b` = [`NONE`]) close along `n`, the
/// way `a` is pushed, with velocities `v` (m/s).
fn closing(a: u32, b: u32, n: Vec3, v: &[Vec3]) -> f32 {
    let vb = if b == NONE { Vec3::ZERO } else { v[b as usize] };
    -(v[a as usize] - vb).dot(n)
}

impl Impact {
    /// Separating speed after the bounce of a pair closing at `c` (m/s), and the shadow
    /// energy per unit effective mass the bounce takes (J/kg, >= 0); see
    /// [`SoftStep::impacts`]. The pair then moves off from `gap` this substep.
    ///
    /// The shadow energy is what semi-implicit Euler conserves; the bounce keeps `e²` of
    /// it, so `1 - e²` of it is lost, none at `e = 1`. It is the loss the budget books:
    /// the kinetic energy the bounce changes differs from it by the integrator's own
    /// `a h c` correction, which is not a loss (it is booked with the constraint's
    /// error), and at the top of the next flight the height shows exactly this loss.
    fn leaving_speed(&self, c: f32, h: f32) -> (f32, f32) {
        let (a, e, gap) = (self.closing_acceleration, self.restitution, self.gap.max(0.0));
        // Shadow energy per unit effective mass on the way in, measured from contact.
        let arriving = a * gap + 0.5 * c * c - 0.5 * a * h * c;
        // On the way out the pair starts at `gap` and moves with the new speed `u` this
        // substep: its shadow energy is a·gap + u²/2 + a·h·u/2.
        let kinetic = (e * e * arriving - a * gap).max(0.0);
        let half = 0.5 * a * h;
        let leaving = -half + (half * half + 2.0 * kinetic).sqrt();
        (leaving, (arriving - (a * gap + kinetic)).max(0.0))
    }
}
