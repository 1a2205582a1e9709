//! Help → About this scene: a page for each compiled scene on the physics it shows,
//! the formulas behind its predictions, what they leave out, and something to try.
//! `particle-lab scenes --about NAME` prints the same page. Its numbers for the
//! scene's defaults are the scene's own predictions to 4 significant figures; a test
//! reads them off the scene's read-outs and finds them on the page.

/// A page: a title and its sections, each a heading and a paragraph.
#[derive(Clone, Copy, Debug)]
pub struct Page {
    /// The page's title.
    pub title: &'static str,
    /// Headings and paragraphs, in order.
    pub sections: &'static [(&'static str, &'static str)],
}

impl Page {
    /// The page as plain text: the title, then each heading and its paragraph.
    #[must_use]
    pub fn text(&self) -> String {
        let mut out = format!("{}\n", self.title);
        for (heading, body) in self.sections {
            out.push_str(&format!("\n{heading}\n{body}\n"));
        }
        out
    }
}

/// Shared by every page: how a step moves a particle.
const STEP: (&str, &str) = (
    "How the lab steps time",
    "Each step of dt, a particle's velocity takes the step's acceleration first (v becomes v + a dt), \
     and its position then moves with the new velocity (x becomes x + v dt): semi-implicit Euler, the paper's \
     integrator (the Run section offers three others). Contacts, rods and cables are solved after \
     the forces, so they act on the velocities the forces left. The energy section books where \
     every joule went: kinetic + potential + dissipated + constraint + removed − work put in stays \
     at the start's value to rounding, and what is left over is the integrator's error.",
);

static PROJECTILE: Page = Page {
    title: "projectile: rounds fired from a launcher",
    sections: &[
        (
            "What you see",
            "Each press of F fires a round: a particle with the launch speed, angle and mass set in \
             the panel, from a launcher 1.5 m above the ground by default. The dashed curve is the \
             next round's drag-free path, drawn before it is fired, and the faint ghost beside a \
             flying round is the exact path its own settings give. Each round that lands adds a row \
             to the table of runs.",
        ),
        (
            "The physics",
            "Without drag the only force is gravity, so the horizontal speed stays v₀ cos θ and the \
             vertical one falls by g each second: x = v₀ cos θ · t, y = h + v₀ sin θ · t − ½ g t². \
             The round is highest at y = h + (v₀ sin θ)² / (2g) and lands after \
             t = (v₀ sin θ + √((v₀ sin θ)² + 2 g h)) / g, at range v₀ cos θ · t. At the defaults \
             (25 m/s at 45°, h = 1.5 m, g = 9.81 m/s²) the peak is 17.43 m and the range to the \
             ground 65.18 m; from level ground (h = 0) it would be 63.71 m.",
        ),
        (
            "What the predictions leave out",
            "Drag (k1, k2) and damping, which the paper's presets switch on: with them the path is \
             no longer a parabola and the round falls short of the drag-free prediction. The step \
             itself: each step of semi-implicit Euler moves the round by its new velocity, not by \
             its average over the step, so the default round lands about 2 cm short of the \
             prediction at 240 Hz; the distance from the exact path shows the gap as it grows.",
        ),
        (
            "Try",
            "Fire at 30°, 45° and 60° and plot range against angle: on level ground 30° and 60° \
             land together and 45° goes furthest; from a height the best angle is a little under \
             45°. Or keep the angle and vary the speed, and plot range against speed squared: a \
             straight line whose slope is sin 2θ / g on level ground.",
        ),
        STEP,
    ],
};

static SPRING_FORCES: Page = Page {
    title: "springForces: springs, a bungee, buoyancy and a stiff spring",
    sections: &[
        (
            "What you see",
            "A bob hangs on a spring from a fixed anchor; beside it two particles joined by a free \
             spring, one on a bungee (a spring that only pulls), one floating in water, and one on \
             a stiff spring that the lab solves in closed form.",
        ),
        (
            "The physics",
            "A spring pulls with Hooke's law, F = −k (l − l₀) along its length, l₀ the rest length. \
             A mass on it oscillates about the point where the spring holds its weight, with period \
             T = 2π √(m/k): 1.405 s for the default 1 kg on 20 N/m, whatever g is (gravity moves \
             the centre of the swing, not its period). A bungee is the same force while stretched \
             and none while slack. Buoyancy follows the paper: the water pushes up with the weight \
             of the water displaced, in proportion to how deep the particle sits, up to its full \
             volume.",
        ),
        (
            "Why the stiff spring is solved exactly",
            "An explicit step follows a spring only while ω dt is small, ω = √(k/m) its angular \
             frequency: semi-implicit Euler stays bounded below ω dt = 2 and blows up above. The \
             default spring has ω dt = 0.01863 at 240 Hz; the 10,000 N/m stiff spring has \
             ω dt = 0.4167, and at a million N/m it would be over 2. The paper's answer is to \
             solve the spring's equation over the step in closed form, which is stable at any k.",
        ),
        (
            "What the predictions leave out",
            "The period 2π √(m/k) is for a spring without damping and a bob that moves only along \
             the spring; the default damping (0.99 of the velocity kept per second) slowly shrinks \
             the swing and lengthens the period by a very little.",
        ),
        (
            "Try",
            "Quadruple k and the period halves; quadruple the mass and it doubles (each start of \
             the bob is a row of the table of runs once its first period is timed). Change g with \
             the presets: the bob hangs higher on the Moon (its weight stretches the spring less) \
             and lower on Jupiter, and swings with the same period.",
        ),
        STEP,
    ],
};

static BRIDGE: Page = Page {
    title: "bridge: a rope bridge of rods and cables",
    sections: &[
        (
            "What you see",
            "Cyclone's rope bridge: twelve particles joined by rods (links of fixed length) across \
             the deck and by cables (links that can slacken but not stretch) along it, hung from \
             anchors by support cables, carrying a load you move along and across it with the \
             sliders.",
        ),
        (
            "The physics",
            "Rods and cables are solved like contacts: when a rod's length is wrong, or a cable is \
             taut and stretching, the solver applies the impulse that stops the change and moves \
             the ends back. The load is a mass shared among the four nearest deck particles, so the \
             deck sags most under it. With no springs, all the give is the geometry of the cables.",
        ),
        (
            "What the read-outs mean",
            "The lowest deck point is how far the load pulls the deck down. The penetration left \
             is the largest rod-length error or overlap the solver left after its last step: its \
             residual error, not physics. The constraint term in the energy section is the energy \
             those corrections put in or took out.",
        ),
        ("Try", "Move the load to the middle and to an end and watch the sag; double its mass."),
        STEP,
    ],
};

static PENDULUM: Page = Page {
    title: "pendulum: a chain of 1 to 5 rods from a pivot",
    sections: &[
        (
            "What you see",
            "A bob on a rod swings from a pivot; with more rods the chain becomes a double or \
             triple pendulum, whose motion is chaotic: two releases a hair apart soon part ways \
             (Compare shows it).",
        ),
        (
            "The physics",
            "For small swings a pendulum of length L swings with period T₀ = 2π √(L/g), 2.006 s \
             for 1 m on Earth, whatever the bob's mass. For a release at θ₀ the swing is slower: \
             the exact period is T = 4 √(L/g) K(sin(θ₀/2)), with K the complete elliptic integral \
             of the first kind. At the default 90° that is 2.368 s, 1.180 times the small-swing \
             period. The lab measures the period from whole swings of the bob.",
        ),
        (
            "Energy",
            "With no damping and no drag nothing takes energy out, so kinetic + potential stays at \
             its start. A rod does no work on its bob; what the solver's corrections of the rod's \
             length add or remove is booked under constraint, the solver's error, and dissipated \
             stays 0.",
        ),
        (
            "Try",
            "Release at 10°, 45° and 90°: each release is a row of the table of runs once its \
             first swing is timed, beside both predictions. At 10° they agree to 0.2%; at 90° the \
             exact period is 18% longer. Plot period against angle to see the small-swing formula \
             fail.",
        ),
        STEP,
    ],
};

static CRADLE: Page = Page {
    title: "cradle: Newton's cradle",
    sections: &[
        (
            "What you see",
            "Five balls hang side by side on cables. Lift one or more and let go: as many balls \
             leave the far end as came in.",
        ),
        (
            "The physics",
            "When equal balls collide elastically, momentum and kinetic energy are both kept, and \
             the only way to keep both is for the moving ball to stop and its neighbour to leave \
             with its speed; the impulse passes down the row. The lifted balls reach the bottom at \
             v = √(2 g L (1 − cos θ)): 1.621 m/s for 1 m cables lifted 30°.",
        ),
        (
            "What the prediction leaves out",
            "The cables' stretch and any damping. With restitution below 1 each collision keeps \
             only part of the closing speed, and the whole row soon swings together.",
        ),
        (
            "Try",
            "Lift two balls, then three; set restitution to 0.8 and watch the swing spread. Each \
             release is a row of the table of runs: how many balls swung out and how high, beside \
             the elastic prediction.",
        ),
        STEP,
    ],
};

static HOURGLASS: Page = Page {
    title: "hourglass: grains draining through an opening",
    sections: &[
        (
            "What you see",
            "Grains fill a bin over a floor with a round opening and drain through it. The read-outs \
             count the grains through and measure the flow.",
        ),
        (
            "The physics",
            "A granular flow through an opening does not depend on how deep the bed is, unlike a \
             liquid's: the grains above an opening lean on the walls and on each other. Beverloo's \
             law gives the mass flow, W = C ρ_b √g (D − k d)^(5/2), for an opening of diameter D, \
             grains of diameter d and a bed of bulk density ρ_b (the grains' density times the \
             packing), with C ≈ 0.58 and k ≈ 1.5. Below about 5 grain diameters arches form over \
             the opening and jam it.",
        ),
        (
            "The steady flow",
            "The flow is fitted over the steady part of the drain: from 10% to 45% of the grains \
             through, while the bed is still deeper than the opening. As the bed empties the last \
             grains slide down the floor to the opening and the flow falls: that drop is not part \
             of the ratio to Beverloo's law.",
        ),
        (
            "Try",
            "Make the opening 4, 5, 7 and 10 grains wide: 4 jams, 5 flows, and the steady flow \
             follows (D − 1.5 d)^(5/2). Each drain's steady flow is a row of the table of runs \
             beside Beverloo's prediction.",
        ),
        STEP,
    ],
};

static PILE: Page = Page {
    title: "pile: spheres dropped into a box",
    sections: &[
        (
            "What you see",
            "Thousands of spheres fall into an open box, pile up and come to rest; resting islands \
             fall asleep and stop costing time.",
        ),
        (
            "The physics",
            "The spheres roll: each has a moment of inertia 2/5 m r², and friction acts at the \
             contact point, so it both slows a sliding sphere and turns it. Coulomb friction holds \
             while the tangential force is at most μ times the normal force; rolling resistance \
             opposes a roll with a torque of at most μ_r r N. Contacts are soft: a stiff damped \
             spring (100 Hz, damping ratio 5) that resolves overlaps smoothly instead of all at \
             once, so a resting pile overlaps by a small fraction of a radius.",
        ),
        (
            "What the read-outs mean",
            "The median speed is near zero once the pile has settled; a solver that leaves it \
             boiling shows here first. The deepest overlap is the sum of radii less the distance of \
             centres over every touching pair and wall.",
        ),
        (
            "Try",
            "Set rolling resistance to 0 and the spheres roll out into a flatter pile; set friction \
             to 0 as well and they spread flatter still.",
        ),
        STEP,
    ],
};

static HEAP: Page = Page {
    title: "heap: grains poured onto open ground",
    sections: &[
        (
            "What you see",
            "Grains drain from a hopper through a round opening and pile up on open ground under \
             it. Once the heap has settled the lab measures how steep its flank stands and adds \
             a row to the table of runs.",
        ),
        (
            "The physics",
            "A grain on a slope stays put while friction can hold it: on a slope of angle θ it \
             slides once tan θ exceeds μ. A heap of round grains is flatter than that, because a \
             sphere can also roll: what keeps it from rolling down the flank is rolling resistance \
             (a torque of at most μ_r r N) and the grains it leans on. The steepest slope the heap \
             keeps is its angle of repose; glass beads rest at about 22° to 26°, sand at 30° to 35°.",
        ),
        (
            "How the angle is measured",
            "On the settled heap: the highest grain top in rings two radii wide around the heap's \
             axis, fitted by a straight line over the flank (from a fifth to four fifths of the \
             heap's reach), so that the rounded top and grains rolled far out do not count.",
        ),
        (
            "Try",
            "Run the heap at rolling resistance 0.05, 0.1 and 0.2 and plot the angle against it; \
             then set it to 0 and watch the grains roll apart into a layer with no heap at all. \
             Raise the outlet (drop) and the grains land harder and spread the heap flatter.",
        ),
        STEP,
    ],
};

/// A scene loaded from a file: its own summary is shown above this.
pub static FILE_PAGE: Page = Page {
    title: "A scene from a file",
    sections: &[
        (
            "What it is",
            "This scene was built from a scene file: its particles, springs, rods, cables and walls \
             as the file lists them (File > Save scene as… writes one, and the builder makes one by \
             hand). The format's reference is docs/scene-format.md.",
        ),
        STEP,
    ],
};

/// The page of the compiled scene `name`, if it has one.
#[must_use]
pub fn page(name: &str) -> Option<&'static Page> {
    Some(match name {
        "projectile" => &PROJECTILE,
        "springForces" => &SPRING_FORCES,
        "bridge" => &BRIDGE,
        "pendulum" => &PENDULUM,
        "cradle" => &CRADLE,
        "hourglass" => &HOURGLASS,
        "pile" => &PILE,
        "heap" => &HEAP,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::{self, SCENES};

    /// The read-outs of scene `name` at its defaults after `steps` steps, by key.
    fn readouts(name: &str, steps: usize) -> Vec<(&'static str, f64)> {
        let mut scene = scenes::build(name, &[]).expect("a compiled scene");
        let dt = scene.info().dt;
        scenes::fire_at_start(scene.as_mut());
        for _ in 0..steps {
            scene.step(dt).expect("a step");
        }
        scene.readout_rows(dt).into_iter().flat_map(|row| row.values).collect()
    }

    /// `value` to 4 significant figures, as the page writes it.
    fn shown(value: f64) -> String {
        crate::scenes::runs::significant(value, crate::scenes::runs::FIGURES)
    }

    #[test]
    fn every_compiled_scene_has_a_page() {
        for entry in SCENES {
            let name = &entry.info().name;
            let page = page(name).unwrap_or_else(|| panic!("{name} has no page"));
            assert!(page.title.starts_with(&**name), "{name}'s page is titled {}", page.title);
            assert!(page.sections.len() >= 3, "{name}'s page is short");
            assert!(page.text().contains("The physics") || page.text().contains("What it is"));
        }
        assert!(page("no such scene").is_none());
    }

    /// The numbers the pages give for the defaults are the scenes' own predictions.
    #[test]
    fn the_pages_numbers_are_the_scenes_predictions() {
        let cases: [(&str, usize, &[&str]); 4] = [
            ("projectile", 1, &["peak_predicted_m", "range_predicted_m", "range_level_predicted_m"]),
            ("springForces", 0, &["period_predicted_s", "omega_dt", "stiff_omega_dt"]),
            ("pendulum", 0, &["period_predicted_s", "period_exact_s"]),
            ("cradle", 0, &["speed_at_bottom_predicted_m_s"]),
        ];
        for (name, steps, keys) in cases {
            let values = readouts(name, steps);
            let text = page(name).expect("a page").text();
            for key in keys {
                let value = values.iter().find(|(k, _)| k == key).map(|&(_, v)| v);
                let value = value.unwrap_or_else(|| panic!("{name} has no read-out {key}"));
                assert!(text.contains(&shown(value)), "{name}'s page lacks {key} = {}", shown(value));
            }
        }
        // The pendulum's ratio, by arithmetic on the two periods.
        let values = readouts("pendulum", 0);
        let get = |key| values.iter().find(|(k, _)| *k == key).expect("a read-out").1;
        let ratio = get("period_exact_s") / get("period_predicted_s");
        assert!(PENDULUM.text().contains(&format!("{ratio:.3} times")), "ratio {ratio}");
    }

    /// What the pendulum's page says of 10° and 90°: the two periods within 0.2% at 10°,
    /// the exact one 18% longer at 90°, from the scene's own periods.
    #[test]
    fn the_pendulum_pages_comparisons_hold() {
        for (angle, low, high) in [(10.0, 0.0, 0.002), (90.0, 0.175, 0.185)] {
            let scene = scenes::build("pendulum", &[format!("angle={angle}")]).expect("a pendulum");
            let values: Vec<_> =
                scene.readout_rows(scene.info().dt).into_iter().flat_map(|r| r.values).collect();
            let get = |key| values.iter().find(|(k, _)| *k == key).expect("a read-out").1;
            let longer = get("period_exact_s") / get("period_predicted_s") - 1.0;
            assert!((low..high).contains(&longer), "{angle}°: the exact period is {longer:.4} longer");
        }
    }

    /// The projectile page's claim on slopes: range against speed² from level ground
    /// has slope sin 2θ / g, checked on the scene's own predictions at two speeds.
    #[test]
    fn the_projectile_pages_slope_holds() {
        let range = |speed: f64| {
            let scene = scenes::build("projectile", &[format!("speed={speed}"), "height=0".into()])
                .expect("a projectile");
            let values: Vec<_> =
                scene.readout_rows(scene.info().dt).into_iter().flat_map(|r| r.values).collect();
            values.iter().find(|(k, _)| *k == "range_predicted_m").expect("a range").1
        };
        let slope = (range(30.0) - range(20.0)) / (30.0_f64.powi(2) - 20.0_f64.powi(2));
        let expected = (2.0 * 45.0_f64.to_radians()).sin() / 9.81;
        assert!((slope / expected - 1.0).abs() < 1e-3, "slope {slope} against {expected}");
    }
}
