//! A link to an experiment: the web page's query string, read as the window's command
//! line. `?scene=bridge&set=load_x=1.5&set=g=5&solver=paper&integrator=rk4` is
//! `--scene=bridge --set=load_x=1.5 --set=g=5 --solver=paper --integrator=rk4`, so it is
//! checked by the same parser (`settings::Launch::from_args`), and refused with the same
//! one-line messages, as those flags typed. Besides the command line's keys a link has the page's own: `steps=N`
//! runs N physics steps at once and pauses there, a launcher's round fired at step 0
//! as `simulate` fires it (a link can show a moment, and a test can compare it with
//! `simulate --steps N`), `view=side|3d` and `camera=…` say how
//! it is looked at, `predictions=hidden` hides what the lab predicts (a class predicts
//! first), and `gpu=webgl2` leaves WebGPU out.
//! [`Link::of`] writes the link of what is on screen. A scene file that is not shipped
//! travels in the link itself (`#file=…`, see [`carried`](super::carried)), so a link to
//! a teacher's own experiment is never dead.

use super::model::Lab;

/// The keys a link may have: the window's flags, and the page's own.
const LINK_KEYS: &[&str] = &[
    "scene",
    "set",
    "solver",
    "integrator",
    "substeps",
    "fresh",
    "steps",
    "gpu",
    "file",
    "rate",
    "view",
    "camera",
    "predictions",
];

/// How the page names a scene file carried in a link, in its messages.
pub const CARRIED_NAME: &str = "the link's scene file";

/// What a link asked for, read from the page's query string.
#[derive(Debug, Default, PartialEq)]
pub struct Link {
    /// The window's flags, as a command line (the program's name first).
    pub args: Vec<String>,
    /// `steps=N`: steps to run at once, then pause.
    pub steps: Option<u64>,
    /// `gpu=webgl2`.
    pub webgl2_only: bool,
    /// `file=PACKED`: a scene file carried in the link (see [`carried`](super::carried)),
    /// opened instead of a named scene.
    pub scene_text: Option<String>,
    /// `rate=HZ`: the physics rate, where it is not the scene's own. A link opens at
    /// this rate or the scene's own, never at one saved in the settings, so that it
    /// shows the same experiment everywhere.
    pub rate: Option<f32>,
    /// `view=side|3d` and `camera=…`: how the experiment is looked at.
    pub view: LinkView,
}

/// How a link has the experiment looked at: the side view or 3D, and where the camera
/// is (`camera=x,y,z,distance,yaw,pitch`: the point looked at and the distance in
/// metres, the turn and elevation in degrees); without them, the scene's own framing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LinkView {
    /// `view=side` (true) or `view=3d` (false).
    pub side: Option<bool>,
    /// `camera=…`.
    pub camera: Option<[f32; 6]>,
    /// `predictions=hidden` (false) or `predictions=shown` (true).
    pub predictions: Option<bool>,
}

impl LinkView {
    /// Looks at `lab`'s experiment as the link says (after it was opened and framed).
    pub fn apply(&self, lab: &mut Lab) {
        if let Some(side) = self.side {
            lab.set_side_view(side);
        }
        if let Some(shown) = self.predictions {
            lab.view.predictions = shown;
        }
        if let Some([x, y, z, distance, yaw, pitch]) = self.camera {
            lab.camera.target = glam::Vec3::new(x, y, z);
            lab.camera.distance = distance;
            lab.camera.yaw = yaw.to_radians();
            lab.camera.pitch = pitch.to_radians();
            lab.camera_moved = true;
        }
    }

    /// Reads `camera=x,y,z,distance,yaw,pitch`.
    fn camera(value: &str) -> Result<[f32; 6], String> {
        let fail = || {
            format!(
                "invalid value '{}' for 'camera': six numbers x,y,z,distance,yaw,pitch (m, m, m, m > 0, degrees, \
                 degrees)",
                crate::messages::clip(value, 60)
            )
        };
        let numbers: Vec<f32> = value
            .split(',')
            .map(|n| n.trim().parse::<f32>())
            .collect::<Result<_, _>>()
            .map_err(|_| fail())?;
        let camera: [f32; 6] = numbers.try_into().map_err(|_| fail())?;
        let usable = camera.iter().all(|n| n.is_finite())
            && camera[3] > 0.0
            && camera[3] < 1e7
            && camera[5].abs() <= 90.0
            && camera[..3].iter().all(|n| n.abs() < 1e7);
        if usable { Ok(camera) } else { Err(fail()) }
    }
}

impl Link {
    /// Reads `pairs` (the query string's keys and values, decoded). An unknown key or a
    /// bad `steps` or `gpu` is refused in one line, as a mistyped flag is.
    pub fn parse(pairs: &[(String, String)]) -> Result<Self, String> {
        let mut link = Self { args: vec!["particle-lab".into()], ..Self::default() };
        for (key, value) in pairs {
            match key.as_str() {
                "steps" => {
                    let most = super::limits::MAX_STEPS;
                    let steps = value.parse::<u64>().ok().filter(|&steps| steps <= most).ok_or_else(|| {
                        format!("invalid value '{value}' for 'steps': a whole number of physics steps, 0 to {most}")
                    })?;
                    link.steps = Some(steps);
                }
                "gpu" => match value.as_str() {
                    "webgl2" => link.webgl2_only = true,
                    "webgpu" | "auto" => link.webgl2_only = false,
                    _ => return Err(format!("invalid value '{value}' for 'gpu': webgpu, webgl2 or auto")),
                },
                "fresh" => link.args.push("--fresh".into()),
                "file" => link.scene_text = Some(super::carried::unpack(value)?),
                "rate" => {
                    let range = super::limits::PHYSICS_RATE_RANGE;
                    let rate =
                        value.parse::<f32>().ok().filter(|rate| range.contains(rate)).ok_or_else(|| {
                            format!(
                                "invalid value '{value}' for 'rate': physics steps a second, {} to {}",
                                range.start(),
                                range.end()
                            )
                        })?;
                    link.rate = Some(rate);
                }
                "view" => {
                    link.view.side = Some(match value.as_str() {
                        "side" => true,
                        "3d" => false,
                        _ => return Err(format!("invalid value '{value}' for 'view': side or 3d")),
                    });
                }
                "camera" => link.view.camera = Some(LinkView::camera(value)?),
                "predictions" => {
                    link.view.predictions = Some(match value.as_str() {
                        "shown" => true,
                        "hidden" => false,
                        _ => {
                            return Err(format!(
                                "invalid value '{value}' for 'predictions': shown or hidden"
                            ));
                        }
                    });
                }
                key if LINK_KEYS.contains(&key) => link.args.push(format!("--{key}={value}")),
                _ => {
                    return Err(format!(
                        "unknown key '{key}' in the link (it may have {})",
                        LINK_KEYS.join(", ")
                    ));
                }
            }
        }
        if link.scene_text.is_some() && link.args.iter().any(|arg| arg.starts_with("--scene=")) {
            return Err("a link names a scene or carries a scene file, not both".into());
        }
        Ok(link)
    }

    /// Whether the link names an experiment (a scene, or a scene file it carries), as
    /// opposed to only page keys (`?gpu=webgl2`): such a link opens at its own physics
    /// rate (or the scene's), not a saved one.
    #[must_use]
    pub fn names_experiment(&self) -> bool {
        self.scene_text.is_some() || self.args.iter().any(|arg| arg.starts_with("--scene="))
    }

    /// Reads a whole link as typed or pasted: `https://…/?scene=…`, `?…`, `#file=…` or
    /// `…?query#fragment`; the keys and values of its query and its fragment, decoded.
    pub fn parse_text(text: &str) -> Result<Self, String> {
        let text = text.trim();
        let (before, fragment) = text.split_once('#').unwrap_or((text, ""));
        // As a page reads its fragment: any further '#' at its start is dropped.
        let fragment = fragment.trim_start_matches('#');
        let query = before.split_once('?').map_or("", |(_, query)| query);
        if query.is_empty() && fragment.is_empty() {
            return Err(format!(
                "'{}' is not a link to an experiment: it has neither '?' nor '#' (copy it with File > Copy \
                 link, or make it with `particle-lab link`)",
                crate::messages::clip(text, 60)
            ));
        }
        let mut pairs = Vec::new();
        for part in query.split('&').chain(fragment.split('&')).filter(|part| !part.is_empty()) {
            let (key, value) = part.split_once('=').unwrap_or((part, ""));
            pairs.push((decode(key)?, decode(value)?));
        }
        Self::parse(&pairs)
    }
}

/// Undoes percent-encoding (and `+` for a space, as a query string may write it).
fn decode(text: &str) -> Result<String, String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut k = 0;
    while k < bytes.len() {
        match bytes[k] {
            b'%' => {
                let hex = bytes.get(k + 1..k + 3).filter(|h| h.iter().all(u8::is_ascii_hexdigit));
                let hex = hex.and_then(|h| std::str::from_utf8(h).ok());
                let byte = hex.and_then(|h| u8::from_str_radix(h, 16).ok()).ok_or_else(|| {
                    format!("the link has a broken escape near '{}'", crate::messages::clip(&text[k..], 12))
                })?;
                out.push(byte);
                k += 3;
            }
            b'+' => {
                out.push(b' ');
                k += 1;
            }
            byte => {
                out.push(byte);
                k += 1;
            }
        }
    }
    String::from_utf8(out).map_err(|_| "the link's text is not UTF-8".to_string())
}

/// Percent-encodes `text` for a query string: letters, digits and `-._~` stay, `=` and
/// `,` too (a `set` value's own `=` and the camera's commas read better unescaped and
/// decode the same).
fn encode(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for byte in text.bytes() {
        if byte.is_ascii_alphanumeric() || b"-._~=,".contains(&byte) {
            out.push(byte as char);
        } else {
            out.push_str(&format!("%{byte:02X}"));
        }
    }
    out
}

impl Link {
    /// `steps=N`: runs N physics steps at once, as `simulate --steps N` does, and
    /// pauses there: a launcher fires its round at step 0 first, as `simulate`'s does,
    /// so the page reaches `simulate`'s state hash. Without it, nothing (and nothing
    /// fires until the user does).
    pub fn run_steps(&self, lab: &mut Lab) {
        if let Some(steps) = self.steps {
            lab.fire_at_start();
            lab.paused = false;
            lab.run_steps_recorded(steps);
            lab.paused = true;
        }
    }

    /// The link (what follows the page's address) that opens `lab` as it is: its
    /// scene, every parameter, the solver, its substeps and the integrator; with
    /// `steps`, paused at the step it is at. A built-in or shipped scene is named
    /// (`?scene=bridge&…`); any other scene file is carried whole, packed, in the
    /// fragment (`#file=…&…`), which a browser never sends to a server. A link longer
    /// than [`MAX_LINK`](super::carried::MAX_LINK) is refused in one line.
    pub fn of(lab: &Lab, with_steps: bool) -> Result<String, String> {
        let solver = lab.solver();
        let name = &*lab.entry.info().name;
        let carried = lab.scene.source().map(|(text, _)| text).filter(|&text| {
            // Named when the name finds this very text (a built-in has no text).
            let shipped = crate::scenes::find(name).ok().and_then(crate::scenes::file::definition);
            shipped.is_none_or(|definition| definition.source() != text)
        });
        let mut pairs = match carried {
            Some(text) => vec![("file".to_string(), super::carried::pack(text))],
            None => vec![("scene".to_string(), name.to_string())],
        };
        // f32's Display is the shortest text that reads back as the same value.
        for (param, value) in lab.scene.params().iter() {
            pairs.push(("set".into(), format!("{}={value}", param.name)));
        }
        pairs.push(("solver".into(), solver.kind.name().into()));
        pairs.push(("substeps".into(), solver.substeps.to_string()));
        pairs.push(("integrator".into(), solver.integrator.name().into()));
        if lab.dt().to_bits() != lab.entry.info().dt.to_bits() {
            pairs.push(("rate".into(), lab.physics_rate.to_string()));
        }
        if with_steps {
            pairs.push(("steps".into(), lab.scene.world().steps().to_string()));
        }
        pairs.push(("view".into(), if lab.side_view { "side" } else { "3d" }.into()));
        if !lab.view.predictions {
            pairs.push(("predictions".into(), "hidden".into()));
        }
        if lab.camera_moved {
            let c = lab.camera;
            let numbers =
                [c.target.x, c.target.y, c.target.z, c.distance, c.yaw.to_degrees(), c.pitch.to_degrees()];
            let text: Vec<String> = numbers.iter().map(f32::to_string).collect();
            pairs.push(("camera".into(), text.join(",")));
        }
        let query: Vec<String> = pairs.iter().map(|(k, v)| format!("{k}={}", encode(v))).collect();
        let link = format!("{}{}", if carried.is_some() { "#" } else { "?" }, query.join("&"));
        let most = super::carried::MAX_LINK;
        if link.len() > most {
            return Err(format!(
                "This scene file makes a link of {:.1} KB, more than the {} KB a link can carry: save the scene \
                 file and share the file instead",
                link.len() as f64 / 1024.0,
                most / 1024
            ));
        }
        Ok(link)
    }
}
