//! A link to an experiment: the web page's query string, read as the window's command
//! line. `?scene=bridge&set=load_x=1.5&set=g=5&solver=paper&integrator=rk4` is
//! `--scene=bridge --set=load_x=1.5 --set=g=5 --solver=paper --integrator=rk4`, so it is
//! checked by the same parser (`settings::Launch::from_args`), and refused with the same
//! one-line messages, as those flags typed. Besides the command line's keys a link has the page's own: `steps=N`
//! runs N physics steps at once and pauses there (a link can show a moment, and a
//! test can compare it with `simulate --steps N`), and `gpu=webgl2` leaves WebGPU out.
//! [`Link::of`] writes the link of what is on screen.

use super::model::Lab;

/// The keys a link may have: the window's flags, and the page's own.
const LINK_KEYS: &[&str] = &["scene", "set", "solver", "integrator", "substeps", "fresh", "steps", "gpu"];

/// What a link asked for, read from the page's query string.
#[derive(Debug, Default, PartialEq)]
pub struct Link {
    /// The window's flags, as a command line (the program's name first).
    pub args: Vec<String>,
    /// `steps=N`: steps to run at once, then pause.
    pub steps: Option<u64>,
    /// `gpu=webgl2`.
    pub webgl2_only: bool,
}

impl Link {
    /// Reads `pairs` (the query string's keys and values, decoded). An unknown key or a
    /// bad `steps` or `gpu` is refused in one line, as a mistyped flag is.
    pub fn parse(pairs: &[(String, String)]) -> Result<Self, String> {
        let mut link = Self { args: vec!["particle-lab".into()], ..Self::default() };
        for (key, value) in pairs {
            match key.as_str() {
                "steps" => {
                    let steps = value.parse::<u64>().map_err(|_| {
                        format!("invalid value '{value}' for 'steps': a whole number of physics steps")
                    })?;
                    link.steps = Some(steps);
                }
                "gpu" => match value.as_str() {
                    "webgl2" => link.webgl2_only = true,
                    "webgpu" | "auto" => link.webgl2_only = false,
                    _ => return Err(format!("invalid value '{value}' for 'gpu': webgpu, webgl2 or auto")),
                },
                "fresh" => link.args.push("--fresh".into()),
                key if LINK_KEYS.contains(&key) => link.args.push(format!("--{key}={value}")),
                _ => {
                    return Err(format!(
                        "unknown key '{key}' in the link (it may have {})",
                        LINK_KEYS.join(", ")
                    ));
                }
            }
        }
        Ok(link)
    }
}

/// Percent-encodes `text` for a query string: letters, digits and `-._~` stay, `=` too
/// (a `set` value's own `=` reads better unescaped and decodes the same).
fn encode(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for byte in text.bytes() {
        if byte.is_ascii_alphanumeric() || b"-._~=".contains(&byte) {
            out.push(byte as char);
        } else {
            out.push_str(&format!("%{byte:02X}"));
        }
    }
    out
}

impl Link {
    /// `steps=N`: runs N physics steps at once, as `simulate --steps N` does, and
    /// pauses there. Without it, nothing.
    pub fn run_steps(&self, lab: &mut Lab) {
        if let Some(steps) = self.steps {
            lab.paused = false;
            lab.run_steps_recorded(steps);
            lab.paused = true;
        }
    }

    /// The query string (with its `?`) that opens `lab` as it is: its scene, every
    /// parameter, the solver, its substeps and the integrator; with `steps`, paused at
    /// the step it is at.
    #[must_use]
    pub fn of(lab: &Lab, with_steps: bool) -> String {
        let solver = lab.solver();
        let mut pairs = vec![("scene".to_string(), lab.entry.info.name.to_string())];
        // f32's Display is the shortest text that reads back as the same value.
        for (param, value) in lab.scene.params().iter() {
            pairs.push(("set".into(), format!("{}={value}", param.name)));
        }
        pairs.push(("solver".into(), solver.kind.name().into()));
        pairs.push(("substeps".into(), solver.substeps.to_string()));
        pairs.push(("integrator".into(), solver.integrator.name().into()));
        if with_steps {
            pairs.push(("steps".into(), lab.scene.world().steps().to_string()));
        }
        let query: Vec<String> = pairs.iter().map(|(k, v)| format!("{k}={}", encode(v))).collect();
        format!("?{}", query.join("&"))
    }
}
