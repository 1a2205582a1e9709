//! How a particle's motion is advanced over one (sub)step: four integrators a student
//! can compare on the same scene.
//!
//! Every integrator here produces two velocities per particle for a step of `h`:
//! - the **moving velocity** `u`, with which positions advance (`p += u h`), and
//! - the **end velocity** the particle has after the step.
//!
//! Contacts and links act on the moving velocity (that is what carries a particle into
//! an overlap); whatever change they make to it is added to the end velocity too. For
//! semi-implicit Euler the two are the same velocity, which is why it needs no extra
//! memory and is the default.
//!
//! | integrator | moving velocity | end velocity | exact for |
//! |---|---|---|---|
//! | explicit Euler (Cyclone's order) | `v` | `v + a h` | nothing; gains energy on a spring |
//! | semi-implicit Euler (the paper's) | `v + a h` | `v + a h` | nothing; keeps a spring's energy on average |
//! | velocity Verlet | `v + a h/2` | `v + (a + a') h/2` | constant forces (a projectile) |
//! | RK4 (classic Runge-Kutta) | `Δx / h` from four force evaluations | `v + Δv` | error `O(h⁴)` in smooth force-only motion |
//!
//! `a` is `(constant acceleration + F/m)` from the force generators at the start of the
//! step, `a'` the same at the moved positions. Verlet evaluates the generators twice a
//! step and RK4 four times, at trial states; damping multiplies the end velocity by
//! `damping^h` in every case.
//!
//! **The energy ledger is booked once a step.** A generator that takes energy out
//! (drag) books, at each evaluation, the power at that state times `h`; the step books
//! the evaluations' bookings weighed as the integrator weighs their accelerations
//! (RK4 `1/6, 1/3, 1/3, 1/6`, Verlet `1/2, 1/2`): the integrator's own quadrature of
//! the lost power, so that its error in the budget is its error in the motion. Drag's
//! semi-implicit form (the force that lands that step on drag's exact solution, with
//! the loss that goes with it) is used only by semi-implicit Euler, which evaluates
//! once; the others get the force at the state they evaluate.
//!
//! **Closed-form generators** (the stiff spring) add no force at an evaluation: the
//! integrator takes their exact step for their particle instead, with the other
//! accelerations of the first evaluation held constant over the step.

use glam::Vec3;

use super::forces::{ClosedStep, Evaluation, ForceRegistry};
use super::particles::{AWAKE, Particles};

/// The integrators a world can use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Integrator {
    /// `p += v h; v += a h`: position first, with the old velocity (as Cyclone's code
    /// does). Gains energy on every oscillation.
    ExplicitEuler,
    /// `v += a h; p += v h`: the paper's integrator and the default. Symplectic: a
    /// spring's energy oscillates about the true value instead of drifting.
    #[default]
    SemiImplicitEuler,
    /// Velocity Verlet: half a kick, drift, forces again, half a kick. Exact for a
    /// constant force; second order.
    Verlet,
    /// Classic fourth-order Runge-Kutta on positions and velocities.
    Rk4,
}

impl Integrator {
    /// Every integrator, in menu order.
    pub const ALL: [Self; 4] = [Self::ExplicitEuler, Self::SemiImplicitEuler, Self::Verlet, Self::Rk4];

    /// The name on the command line and in the panel.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::ExplicitEuler => "explicit-euler",
            Self::SemiImplicitEuler => "semi-implicit-euler",
            Self::Verlet => "verlet",
            Self::Rk4 => "rk4",
        }
    }

    /// One line saying what it is.
    #[must_use]
    pub fn summary(self) -> &'static str {
        match self {
            Self::ExplicitEuler => "p += v h, then v += a h (Cyclone's order): gains energy",
            Self::SemiImplicitEuler => "v += a h, then p += v h (the paper's): energy oscillates, no drift",
            Self::Verlet => "velocity Verlet: exact for constant forces, second order",
            Self::Rk4 => "classic Runge-Kutta: fourth order for force-only motion",
        }
    }

    /// Looks an integrator up by name.
    pub fn parse(name: &str) -> Result<Self, String> {
        Self::ALL.into_iter().find(|i| i.name().eq_ignore_ascii_case(name.trim())).ok_or_else(|| {
            let names: Vec<_> = Self::ALL.iter().map(|i| i.name()).collect();
            format!(
                "unknown integrator '{}'; valid integrators: {}",
                crate::messages::quote(name),
                names.join(", ")
            )
        })
    }
}

/// Buffers of the integrators other than semi-implicit Euler, kept between steps so
/// that a step allocates nothing.
#[derive(Clone, Debug, Default)]
pub(crate) struct Integration {
    /// Which particles the integrator moves: movable and awake.
    moves: Vec<bool>,
    start_position: Vec<Vec3>,
    start_velocity: Vec<Vec3>,
    /// Moving velocity of each particle this step.
    moving: Vec<Vec3>,
    /// End velocity of each particle this step, before constraints.
    end: Vec<Vec3>,
    /// Accelerations of the force evaluations (RK4 uses all four).
    a1: Vec<Vec3>,
    a2: Vec<Vec3>,
    a3: Vec<Vec3>,
    a4: Vec<Vec3>,
    /// This step's closed-form steps.
    closed: Vec<ClosedStep>,
}

impl Integration {
    /// Computes this step's moving and end velocities with `integrator` and leaves
    /// every particle at its start position with its moving velocity, ready for the
    /// constraint solve. Sleeping and immovable particles are left alone.
    /// `prepare_damping(h)` must have been called.
    pub(crate) fn predict(
        &mut self,
        integrator: Integrator,
        particles: &mut Particles,
        forces: &mut ForceRegistry,
        h: f32,
    ) {
        self.moves.clear();
        self.moves.extend(
            particles.inverse_mass.iter().zip(&particles.sleep).map(|(&w, s)| w > 0.0 && s.island == AWAKE),
        );
        self.start_position.clone_from(&particles.position);
        self.start_velocity.clone_from(&particles.velocity);
        self.moving.clone_from(&particles.velocity);
        self.end.clone_from(&particles.velocity);
        let n = particles.len();
        for buffer in [&mut self.a1, &mut self.a2, &mut self.a3, &mut self.a4] {
            buffer.resize(n, Vec3::ZERO);
        }
        let (moves, x, v) = (&self.moves, &self.start_position, &self.start_velocity);
        let evaluation = match integrator {
            Integrator::SemiImplicitEuler => Evaluation::Step,
            _ => Evaluation::Instantaneous,
        };
        // What the evaluations book as dissipated, each on its own, weighed below.
        let booked_before = particles.dissipated;
        let mut booked = [0.0_f64; 4];
        booked[0] = evaluate(particles, forces, h, evaluation, &mut self.a1);
        forces.closed_steps(particles, &self.a1, h, &mut self.closed);
        let a1 = &self.a1;
        let weights: &[f64] = match integrator {
            Integrator::SemiImplicitEuler | Integrator::ExplicitEuler => {
                for i in (0..n).filter(|&i| moves[i]) {
                    self.end[i] = v[i] + a1[i] * h;
                    let explicit = integrator == Integrator::ExplicitEuler;
                    self.moving[i] = if explicit { v[i] } else { self.end[i] };
                }
                &[1.0]
            }
            Integrator::Verlet => {
                for i in (0..n).filter(|&i| moves[i]) {
                    self.moving[i] = v[i] + a1[i] * (0.5 * h);
                }
                // Forces again where the half-kicked velocity carries the particles.
                let moving = &self.moving;
                set_state(particles, moves, |i| (x[i] + moving[i] * h, moving[i]));
                booked[1] = evaluate(particles, forces, h, evaluation, &mut self.a2);
                for i in (0..n).filter(|&i| moves[i]) {
                    self.end[i] = self.moving[i] + self.a2[i] * (0.5 * h);
                }
                &[0.5, 0.5]
            }
            Integrator::Rk4 => {
                // k1 = (v, a1) at the start; k2 at the midpoint along k1; k3 at the
                // midpoint along k2; k4 at the end along k3.
                let half = 0.5 * h;
                set_state(particles, moves, |i| (x[i] + v[i] * half, v[i] + a1[i] * half));
                booked[1] = evaluate(particles, forces, h, evaluation, &mut self.a2);
                let a2 = &self.a2;
                set_state(particles, moves, |i| (x[i] + (v[i] + a1[i] * half) * half, v[i] + a2[i] * half));
                booked[2] = evaluate(particles, forces, h, evaluation, &mut self.a3);
                let a3 = &self.a3;
                set_state(particles, moves, |i| (x[i] + (v[i] + a2[i] * half) * h, v[i] + a3[i] * h));
                booked[3] = evaluate(particles, forces, h, evaluation, &mut self.a4);
                let a4 = &self.a4;
                for i in (0..n).filter(|&i| moves[i]) {
                    let (k2, k3, k4) = (v[i] + a1[i] * half, v[i] + a2[i] * half, v[i] + a3[i] * h);
                    self.moving[i] = (v[i] + 2.0 * k2 + 2.0 * k3 + k4) / 6.0;
                    self.end[i] = v[i] + (a1[i] + 2.0 * a2[i] + 2.0 * a3[i] + a4[i]) * (h / 6.0);
                }
                &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0]
            }
        };
        particles.dissipated = booked_before + weights.iter().zip(&booked).map(|(w, d)| w * d).sum::<f64>();
        // The closed-form steps replace whatever the integrator made of their particles.
        for step in self.closed.iter().filter(|s| self.moves[s.index]) {
            self.moving[step.index] = step.moving;
            self.end[step.index] = step.end;
            particles.dissipated += step.dissipated;
        }
        for i in (0..n).filter(|&i| moves[i]) {
            let (d, undamped) = (particles.damping_per_step(i), self.end[i]);
            self.end[i] *= d;
            // What damping took, for the energy budget.
            let mass = 1.0 / f64::from(particles.inverse_mass[i]);
            particles.dissipated +=
                0.5 * mass * f64::from(undamped.length_squared()) * f64::from(1.0 - d * d);
        }
        let moving = &self.moving;
        set_state(particles, moves, |i| (x[i], moving[i]));
    }

    /// Each particle's velocity without this step's kick, while the particles hold their
    /// moving velocities (between [`predict`](Self::predict) and [`finish`](Self::finish)):
    /// the moving velocity less what the integrator adds to the velocity over the step
    /// (`end - start`), into `out` by dense index. It is the velocity the constraints
    /// would see if no force had acted this step, in the frame they work in: for
    /// semi-implicit Euler the start velocity, for the others the moving velocity less a
    /// whole kick. A resting contact stops the kick's share of its closing speed every
    /// step; measured from this velocity it stops nothing (see `solver/soft/losses.rs`).
    pub(crate) fn kick_free_velocities(&self, particles: &Particles, out: &mut Vec<Vec3>) {
        out.clear();
        out.extend_from_slice(&particles.velocity);
        let kicks = self.end.iter().zip(&self.start_velocity);
        for ((v, (&end, &start)), _) in
            out.iter_mut().zip(kicks).zip(&self.moves).filter(|(_, moves)| **moves)
        {
            *v -= end - start;
        }
    }

    /// After the constraints have changed the moving velocities (and positions have
    /// moved by them): gives each particle its end velocity plus the same change.
    pub(crate) fn finish(&self, particles: &mut Particles) {
        for (i, _) in self.moves.iter().enumerate().filter(|(_, moves)| **moves) {
            particles.velocity[i] = self.end[i] + (particles.velocity[i] - self.moving[i]);
        }
    }
}

/// Moves every particle in `moves` to a trial state `(position, velocity)`.
fn set_state(particles: &mut Particles, moves: &[bool], state: impl Fn(usize) -> (Vec3, Vec3)) {
    for (i, _) in moves.iter().enumerate().filter(|(_, moves)| **moves) {
        let (p, v) = state(i);
        particles.position[i] = p;
        particles.velocity[i] = v;
    }
}

/// Applies the force generators to the particles' current state in the form
/// `evaluation` asks for and writes each particle's acceleration `a + F/m` (zero for
/// immovable ones); returns what the generators booked as dissipated, which it takes
/// back out of the particles' tally for the caller to weigh.
fn evaluate(
    particles: &mut Particles,
    forces: &mut ForceRegistry,
    h: f32,
    evaluation: Evaluation,
    out: &mut [Vec3],
) -> f64 {
    let before = particles.dissipated;
    particles.clear_forces();
    forces.apply_for(particles, h, evaluation);
    let booked = particles.dissipated - before;
    particles.dissipated = before;
    let inputs = particles.acceleration.iter().zip(&particles.force).zip(&particles.inverse_mass);
    for (slot, ((&a, &f), &w)) in out.iter_mut().zip(inputs) {
        *slot = if w > 0.0 { a + f * w } else { Vec3::ZERO };
    }
    booked
}
