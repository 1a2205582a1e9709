//! The energy bars (PhET's bar chart) and the energy history as CSV: whose energy
//! the bars show and where gravitational energy is measured from.

use super::model::Lab;
use super::records::EnergyBars;
use crate::physics::ParticleId;

impl Lab {
    /// The height gravitational energy is measured from in the bars and the plot (m),
    /// and its name: the scene's own reference, or the ground.
    #[must_use]
    pub fn gravity_from(&self) -> (f32, String) {
        match self.scene.gravity_reference() {
            // The height to 4 significant figures, as the panel shows a measurement
            // (-5.155 m, not -5.1552753); the bars are computed from the full value.
            Some((height, name)) => {
                let mut shown =
                    crate::scenes::runs::significant(f64::from(height), crate::scenes::runs::FIGURES);
                if shown.contains('.') && !shown.contains('e') {
                    // A height is a place, not a measurement: 0.5 m, not 0.5000 m.
                    shown = shown.trim_end_matches('0').trim_end_matches('.').to_string();
                }
                (height, format!("{name} (y = {shown} m)"))
            }
            None => (0.0, "the ground (y = 0)".into()),
        }
    }

    /// The particle the bars show, if they show one: the selected particle, else the
    /// scene's focus (springForces' bob), unless the user asked for the whole scene.
    #[must_use]
    pub fn bars_particle(&self) -> Option<(ParticleId, String)> {
        if !self.bars_for_selected {
            return None;
        }
        match self.selected {
            Some(id) => Some((id, format!("particle {}", id.0))),
            None => self.scene.energy_focus().map(|(id, name)| (id, name.to_string())),
        }
        .filter(|(id, _)| self.scene.world().particle_energy(*id).is_some())
    }

    /// The energy bars now ([`EnergyBars`]), gravitational energy from
    /// [`Self::gravity_from`].
    #[must_use]
    pub fn energy_bars(&self) -> EnergyBars {
        let world = self.scene.world();
        let (height, reference) = self.gravity_from();
        let particle =
            self.bars_particle().and_then(|(id, name)| Some((world.particle_energy(id)?, id, name)));
        let bars = match &particle {
            Some(((kinetic, gravitational, stored), id, _)) => {
                let i = world.particles.index(*id).expect("it has an energy");
                let shift = world.particles.accelerations()[i].y * world.particles.mass(i) * height;
                let gravitational = gravitational + shift + 0.0;
                vec![
                    ("kinetic", *kinetic),
                    ("gravity", gravitational),
                    ("elastic", *stored),
                    ("total", kinetic + gravitational + stored),
                ]
            }
            None => {
                let e = world.energy();
                let shift = world.gravity_reference_shift(height);
                vec![
                    ("kinetic", e.kinetic),
                    ("gravity", e.gravitational + shift),
                    ("elastic", e.potential - e.gravitational),
                    ("dissipated", e.dissipated),
                    ("constraint", e.constraint),
                    ("removed", e.removed),
                    (
                        "budget",
                        e.kinetic + e.potential + shift + e.dissipated + e.constraint + e.removed - e.work,
                    ),
                ]
            }
        };
        let subject = particle.map_or_else(|| "the scene".to_string(), |(_, _, name)| name);
        EnergyBars { subject, reference, bars }
    }

    /// The energy history (every sample kept, not only the plotted window) as CSV:
    /// `t,kinetic,potential,total,dissipated,constraint,work,removed,error`, in J.
    #[must_use]
    pub fn energy_csv(&self) -> String {
        use std::fmt::Write;
        let mut out = String::from("t,kinetic,potential,total,dissipated,constraint,work,removed,error\n");
        for sample in &self.energy {
            let e = &sample.energy;
            let total = e.kinetic + e.potential;
            let _ = writeln!(
                out,
                "{},{},{},{total},{},{},{},{},{}",
                sample.t, e.kinetic, e.potential, e.dissipated, e.constraint, e.work, e.removed, e.error
            );
        }
        out
    }

    /// Writes [`Self::energy_csv`] to `path`, whole or not at all (through a link to the
    /// file it names; a device or FIFO is refused).
    pub fn export_energy_csv(&self, path: &std::path::Path) -> Result<(), crate::writing::WriteError> {
        crate::writing::write_atomic(path, self.energy_csv().as_bytes())
    }
}
