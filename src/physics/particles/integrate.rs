//! The step's motion of the particles: the kick (velocities from accelerations and
//! forces, damped) and the drift (positions from velocities), the damping factors,
//! and the sums of their kinetic energy, in an order that gives the same bits on any
//! number of threads.

use glam::Vec3;

use super::desc::damping_factor;
use super::parts::{Disjoint, on_threads, tree_sum};
use super::sleep::{AWAKE, Sleep};
use super::store::Particles;

impl Particles {
    /// Recomputes `damping^dt` for every particle if `dt` changed since the last step.
    /// With a fixed time step this runs once, not once per step.
    pub(crate) fn prepare_damping(&mut self, dt: f32) {
        if dt != self.damping_dt {
            self.damping_dt = dt;
            for (factor, &damping) in self.damping_per_step.iter_mut().zip(&self.damping) {
                *factor = damping_factor(damping, dt);
            }
        }
    }

    /// Kinetic energy of the movable particles (J), in f64 and in index order: of
    /// their motion, `Σ ½ m v²`, plus of the rolling spheres' rotation (see
    /// [`Particles::rotational_energy`]).
    pub(crate) fn kinetic_energy(&self) -> f64 {
        let [moving, turning] = tree_sum(0..self.len(), &|range| self.kinetic_parts(range));
        0.5 * (moving + turning)
    }

    /// Twice the kinetic energy of motion and of spin of the particles `range` (J).
    pub(crate) fn kinetic_parts(&self, range: std::ops::Range<usize>) -> [f64; 2] {
        let bodies = self.velocity[range.clone()].iter().zip(&self.inverse_mass[range.clone()]);
        let moving = bodies
            .filter(|(_, w)| **w > 0.0)
            .map(|(v, &w)| f64::from(v.length_squared()) / f64::from(w))
            .sum();
        let spins = self.angular_velocity[range.clone()].iter().zip(&self.inverse_inertia[range]);
        let turning = spins
            .filter(|(_, i)| **i != 0.0)
            .map(|(w, &i)| f64::from(w.length_squared()) / f64::from(i))
            .sum();
        [moving, turning]
    }

    /// Kinetic energy of rotation (J), `Σ ½ I ω²` over the rolling spheres, in f64.
    pub(crate) fn rotational_energy(&self) -> f64 {
        let [_, turning] = tree_sum(0..self.len(), &|range| self.kinetic_parts(range));
        0.5 * turning
    }

    /// Adds to `dissipated` what damping took this step: each damped particle's end
    /// velocity is `d` times what it would have been, so it lost `½ m v² (1/d² - 1)`.
    pub(crate) fn count_damping_loss(&mut self) {
        let [lost] = tree_sum(0..self.len(), &|range: std::ops::Range<usize>| {
            let bodies = self.velocity[range.clone()].iter().zip(&self.inverse_mass[range.clone()]);
            let mut lost = 0.0;
            for ((v, &w), &d) in bodies.zip(&self.damping_per_step[range]) {
                if w > 0.0 && d < 1.0 && d > 0.0 {
                    let undamp = 1.0 / f64::from(d);
                    lost += 0.5 * f64::from(v.length_squared()) / f64::from(w) * (undamp * undamp - 1.0);
                }
            }
            [lost]
        });
        self.dissipated += lost;
    }

    /// Whether any movable particle is damped (damping below 1).
    pub(crate) fn any_damping(&self) -> bool {
        self.damping.iter().zip(&self.inverse_mass).any(|(&d, &w)| w > 0.0 && d < 1.0)
    }

    /// Zeroes every force accumulator.
    #[inline]
    pub fn clear_forces(&mut self) {
        self.force.fill(Vec3::ZERO);
    }

    /// [`Particles::integrate_velocities`], keeping copies on the way: each velocity
    /// before the kick into `before`, each spin into `spins` (when given) and each
    /// velocity after it into `after`. The same numbers as the copies and the kick made
    /// one after the other, in one sweep over the particles (on several threads when
    /// `parallel`) instead of four: on 2 threads, an 8,000-sphere pile's kicks took
    /// 0.066 ms a step this way against 0.076 ms, and 0.12 against 0.20 ms when the
    /// two cores were far apart.
    pub(crate) fn integrate_velocities_keeping(
        &mut self,
        h: f32,
        parallel: bool,
        before: &mut Vec<Vec3>,
        mut spins: Option<&mut Vec<Vec3>>,
        after: &mut Vec<Vec3>,
    ) {
        let n = self.len();
        for out in [Some(&mut *before), spins.as_deref_mut(), Some(&mut *after)].into_iter().flatten() {
            out.resize(n, Vec3::ZERO);
        }
        let (velocity, inputs, spin) = self.kick_parts();
        // The run of particles from `first`: their velocities and their parts of the copies.
        let sweep = |first: usize,
                     v: &mut [Vec3],
                     before: &mut [Vec3],
                     spins: Option<&mut [Vec3]>,
                     after: &mut [Vec3]| {
            before.copy_from_slice(v);
            if let Some(spins) = spins {
                spins.copy_from_slice(&spin[first..first + v.len()]);
            }
            inputs.kick(first, v, h);
            after.copy_from_slice(v);
        };
        if parallel {
            let (velocity, before, after) =
                (Disjoint::new(velocity), Disjoint::new(before), Disjoint::new(after));
            let spins = spins.map(|s| Disjoint::new(s));
            on_threads(n, |run| {
                // SAFETY: `on_threads` gives each run to one thread; the runs are disjoint.
                let (v, b, a) =
                    unsafe { (velocity.run(run.clone()), before.run(run.clone()), after.run(run.clone())) };
                // SAFETY: as above.
                let s = spins.as_ref().map(|s| unsafe { s.run(run.clone()) });
                sweep(run.start, v, b, s, a);
            });
        } else {
            sweep(0, velocity, before, spins.map(Vec::as_mut_slice), after);
        }
    }

    /// The velocity half of a semi-implicit Euler (sub)step: `v = (v + (a + F/m) h)
    /// damping^h` for every movable, awake particle ([`kicked`]).
    /// [`Particles::prepare_damping`] must have been called with `h`; the position half
    /// is [`Particles::integrate_positions`].
    pub(crate) fn integrate_velocities(&mut self, h: f32, parallel: bool) {
        let (velocity, inputs, _) = self.kick_parts();
        if parallel {
            let shared = Disjoint::new(velocity);
            on_threads(shared.len(), |run| {
                // SAFETY: `on_threads` gives each run to one thread; the runs are disjoint.
                inputs.kick(run.start, unsafe { shared.run(run.clone()) }, h);
            });
        } else {
            inputs.kick(0, velocity, h);
        }
    }

    /// Each particle's mass and moment of inertia in `f64`, `[1/w, 1/I]` from its
    /// inverses (0 for an immovable particle, `w <= 0`, and for a sphere that does not
    /// roll, `I⁻¹ = 0`), into `out`: so that the energy sums of every substep (two
    /// each) multiply by them instead of dividing by the inverses each time.
    pub(crate) fn masses_into(&self, out: &mut Vec<[f64; 2]>, parallel: bool) {
        out.resize(self.len(), [0.0; 2]);
        let (inverse_mass, inverse_inertia) = (&self.inverse_mass, &self.inverse_inertia);
        let fill = |first: usize, out: &mut [[f64; 2]]| {
            let inverses = inverse_mass[first..].iter().zip(&inverse_inertia[first..]);
            for (m, (&w, &i)) in out.iter_mut().zip(inverses) {
                let mass = if w > 0.0 { 1.0 / f64::from(w) } else { 0.0 };
                *m = [mass, if i != 0.0 { 1.0 / f64::from(i) } else { 0.0 }];
            }
        };
        if parallel {
            let shared = Disjoint::new(out);
            on_threads(shared.len(), |run| {
                // SAFETY: `on_threads` gives each run to one thread; the runs are disjoint.
                fill(run.start, unsafe { shared.run(run.clone()) });
            });
        } else {
            fill(0, out);
        }
    }

    /// The velocities, what the kick reads, and the spins, borrowed apart.
    fn kick_parts(&mut self) -> (&mut [Vec3], KickInputs<'_>, &[Vec3]) {
        let Self {
            velocity,
            acceleration,
            force,
            inverse_mass,
            damping_per_step,
            sleep,
            angular_velocity,
            ..
        } = self;
        let inputs = KickInputs { acceleration, force, inverse_mass, damping: damping_per_step, sleep };
        (velocity, inputs, angular_velocity)
    }

    /// The position half of a substep: `p += v h` for every movable particle, adding the
    /// move to `delta` too.
    pub(crate) fn integrate_positions(&mut self, h: f32, delta: &mut [Vec3], parallel: bool) {
        // Sleeping particles have zero velocity: moving them by it changes nothing.
        let drift = |((p, d), (&v, &inverse_mass)): ((&mut Vec3, &mut Vec3), (&Vec3, &f32))| {
            if inverse_mass > 0.0 {
                *p += v * h;
                *d += v * h;
            }
        };
        if parallel {
            let (velocity, inverse_mass) = (&self.velocity, &self.inverse_mass);
            let (position, delta) = (Disjoint::new(&mut self.position), Disjoint::new(delta));
            on_threads(velocity.len(), |run| {
                // SAFETY: `on_threads` gives each run to one thread; the runs are disjoint.
                let (p, d) = unsafe { (position.run(run.clone()), delta.run(run.clone())) };
                let inputs = velocity[run.clone()].iter().zip(&inverse_mass[run]);
                p.iter_mut().zip(d).zip(inputs).for_each(drift);
            });
        } else {
            self.position
                .iter_mut()
                .zip(delta)
                .zip(self.velocity.iter().zip(&self.inverse_mass))
                .for_each(drift);
        }
    }

    /// Acceleration the particle at `index` received this step: constant part plus
    /// accumulated force over mass (m/s²). Zero for immovable particles.
    #[inline]
    #[must_use]
    pub fn step_acceleration(&self, index: usize) -> Vec3 {
        let inverse_mass = self.inverse_mass[index];
        if inverse_mass > 0.0 {
            self.acceleration[index] + self.force[index] * inverse_mass
        } else {
            Vec3::ZERO
        }
    }
}

/// Semi-implicit Euler's kick, the one place it is written: the velocity `v` (m/s)
/// after `h` seconds of the acceleration `acceleration` (m/s², constant plus force over
/// mass), times the step's damping factor `damping^h`. Positions then move with it.
#[inline]
#[must_use]
pub(crate) fn kicked(v: Vec3, acceleration: Vec3, h: f32, damping_per_step: f32) -> Vec3 {
    (v + acceleration * h) * damping_per_step
}

/// What the velocity kick reads of every particle.
#[derive(Clone, Copy)]
struct KickInputs<'a> {
    acceleration: &'a [Vec3],
    force: &'a [Vec3],
    inverse_mass: &'a [f32],
    damping: &'a [f32],
    sleep: &'a [Sleep],
}

impl KickInputs<'_> {
    /// Kicks the velocities `v` of the particles from `first` on: [`kicked`] for every
    /// movable, awake one.
    fn kick(&self, first: usize, v: &mut [Vec3], h: f32) {
        let run = first..first + v.len();
        let bodies = self.inverse_mass[run.clone()]
            .iter()
            .zip(&self.damping[run.clone()])
            .zip(&self.sleep[run.clone()]);
        let inputs = self.acceleration[run.clone()].iter().zip(&self.force[run]).zip(bodies);
        for (v, ((&a, &f), ((&inverse_mass, &damp), sleep))) in v.iter_mut().zip(inputs) {
            if inverse_mass > 0.0 && sleep.island == AWAKE {
                *v = kicked(*v, a + f * inverse_mass, h, damp);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::particles::desc::ParticleDesc;

    /// The kick that keeps copies gives, bit for bit, the velocities of the plain kick
    /// and copies of the velocities before and after it and of the spins, on one thread
    /// and on several, for a mix of movable, immovable, damped and sleeping particles
    /// with forces on them, in more particles than one task takes.
    #[test]
    #[cfg_attr(miri, ignore = "5,000 particles: too slow to interpret (`parts.rs` tests its threads)")]
    fn the_kick_that_keeps_copies_is_the_kick_and_the_copies() {
        let mut particles = Particles::new();
        for i in 0..5000 {
            let f = i as f32;
            let desc = ParticleDesc {
                velocity: Vec3::new((f * 0.37).sin(), (f * 0.11).cos(), -f * 1e-3),
                acceleration: Vec3::new(0.0, -9.81, 0.1 * (f * 0.7).sin()),
                mass: 1.0 + (i % 7) as f32,
                immovable: i % 17 == 3,
                damping: if i % 5 == 0 { 0.9 } else { 1.0 },
                radius: 0.5,
                ..ParticleDesc::default()
            };
            particles.add(desc).expect("a valid particle");
            particles.force[i] = Vec3::new(f.cos(), 0.5, f * 1e-2);
            particles.angular_velocity[i] = Vec3::new(f * 1e-3, -1.0, (f * 0.3).cos());
        }
        particles.sleep[11].island = 0;
        let h = 1.0 / 240.0;
        particles.prepare_damping(h);
        let mut expected = particles.clone();
        let start = expected.velocity.clone();
        expected.integrate_velocities(h, false);
        let bits = |v: &[Vec3]| v.iter().flat_map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<_>>();
        for parallel in [false, true] {
            for with_spins in [false, true] {
                let mut p = particles.clone();
                let (mut before, mut spins, mut after) =
                    (Vec::new(), vec![Vec3::NAN; 3], vec![Vec3::NAN; 9000]);
                let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool");
                pool.install(|| {
                    p.integrate_velocities_keeping(
                        h,
                        parallel,
                        &mut before,
                        with_spins.then_some(&mut spins),
                        &mut after,
                    )
                });
                assert_eq!(bits(&p.velocity), bits(&expected.velocity), "parallel {parallel}");
                assert_eq!(bits(&before), bits(&start));
                assert_eq!(bits(&after), bits(&expected.velocity));
                if with_spins {
                    assert_eq!(bits(&spins), bits(&particles.angular_velocity));
                }
            }
        }
        assert_ne!(bits(&expected.velocity), bits(&start), "the kick changed the velocities");
    }

    /// Each particle's noted mass and moment of inertia are `m` and `2/5 m r²` as the
    /// particle was made (to f32's rounding of their inverses), 0 for an immovable
    /// particle and for a point mass's inertia; the same bits on one thread and on two.
    #[test]
    #[cfg_attr(miri, ignore = "5,000 particles: too slow to interpret (`parts.rs` tests its threads)")]
    fn the_masses_are_the_particles_masses_and_moments_of_inertia() {
        let mut particles = Particles::new();
        let mut made = Vec::new();
        for i in 0..5000 {
            let (mass, radius, immovable) =
                (1.0 + (i % 7) as f32 * 0.5, 0.1 + (i % 3) as f32 * 0.2, i % 13 == 5);
            particles
                .add(ParticleDesc { mass, radius, immovable, ..ParticleDesc::default() })
                .expect("valid");
            made.push((f64::from(mass), f64::from(radius), immovable));
        }
        // Half of them spheres that roll.
        for i in (0..5000).step_by(2) {
            let (mass, radius, _) = made[i];
            particles.inverse_inertia[i] = (1.0 / (0.4 * mass * radius * radius)) as f32;
        }
        let mut alone = Vec::new();
        particles.masses_into(&mut alone, false);
        assert_eq!(alone.len(), 5000);
        for (i, (&[m, inertia], &(mass, radius, immovable))) in alone.iter().zip(&made).enumerate() {
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * b;
            assert!(if immovable { m == 0.0 } else { close(m, mass) }, "particle {i}: mass {m}, made {mass}");
            let expected = if i % 2 == 0 { 0.4 * mass * radius * radius } else { 0.0 };
            assert!(close(inertia, expected), "particle {i}: inertia {inertia}, expected {expected}");
        }
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool");
        let mut shared = vec![[f64::NAN; 2]; 7];
        pool.install(|| particles.masses_into(&mut shared, true));
        let bits = |m: &[[f64; 2]]| m.iter().flat_map(|x| x.map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&shared), bits(&alone));
    }
}
