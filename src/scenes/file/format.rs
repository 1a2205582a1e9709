//! The tables of a scene file as serde reads them, with the span of every value a later
//! check may have to point at. Unknown keys are refused (`deny_unknown_fields`), so a
//! misspelt key is reported where it is instead of being silently ignored.

use std::fmt;

use serde::Deserialize;
use serde::de::{self, Deserializer, Visitor};
use toml::Spanned;

/// A number, or an expression of the parameters in quotes.
#[derive(Clone, Debug, PartialEq)]
pub enum Num {
    /// A literal number.
    Value(f64),
    /// An expression, e.g. `"mass * g"`.
    Text(String),
}

/// A particle: its number in the file's order, or a name (`"ball"`, a whole array
/// `"chain"`, a member `"chain.3"`, `"chain.-1"` for the last, `"cloth.0.-1"`).
#[derive(Clone, Debug, PartialEq)]
pub enum Ref {
    /// Number in the file's order.
    Index(i64),
    /// A name.
    Name(String),
}

/// A value with its place in the file.
pub type SNum = Spanned<Num>;
/// Three values `[x, y, z]`, each a number or an expression.
pub type SVec = Spanned<Vec<SNum>>;

impl<'de> Deserialize<'de> for Num {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct NumVisitor;
        impl Visitor<'_> for NumVisitor {
            type Value = Num;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number or an expression in quotes (e.g. 2.5 or \"mass * g\")")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Num, E> {
                Ok(Num::Value(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Num, E> {
                Ok(Num::Value(v as f64))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Num, E> {
                Ok(Num::Value(v))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Num, E> {
                Ok(Num::Text(v.to_string()))
            }
        }
        deserializer.deserialize_any(NumVisitor)
    }
}

impl<'de> Deserialize<'de> for Ref {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct RefVisitor;
        impl Visitor<'_> for RefVisitor {
            type Value = Ref;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a particle: its number, or its name in quotes (e.g. 0 or \"chain.-1\")")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Ref, E> {
                Ok(Ref::Index(v))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Ref, E> {
                Ok(Ref::Index(i64::try_from(v).unwrap_or(i64::MAX)))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Ref, E> {
                Ok(Ref::Name(v.to_string()))
            }
        }
        deserializer.deserialize_any(RefVisitor)
    }
}

/// Declares a table of the file: serde reads it, refusing unknown keys. Its fields are
/// its own, with the fields of a group written in the place of the group's name: the
/// particles' (`particle_fields;`: of each particle the table makes), the links'
/// (`link_fields;`, which [`LinkProps`] borrows) and a plane's surface
/// (`surface_fields;`). serde's `flatten` would share them too, but it loses the values'
/// spans and refuses no unknown key.
macro_rules! table {
    ($(#[$meta:meta])* pub struct $name:ident { $($body:tt)* }) => {
        table!(@fields [$(#[$meta])*] $name [] $($body)*);
    };
    (@fields $meta:tt $name:ident [$($done:tt)*] particle_fields; $($rest:tt)*) => {
        table!(@fields $meta $name [$($done)*
            /// Velocity (m/s), default 0.
            pub velocity: Option<SVec>,
            /// Mass (kg) of each, default 1.
            pub mass: Option<SNum>,
            /// Radius (m) of each, default 0.1.
            pub radius: Option<SNum>,
            /// Fraction of velocity each keeps per second, default 1.
            pub damping: Option<SNum>,
            /// Immovable, every one.
            #[serde(default)]
            pub fixed: bool,
            /// Each a solid sphere that rolls (friction turns it; needs a radius),
            /// default false: the paper's point mass.
            #[serde(default)]
            pub rolls: bool,
        ] $($rest)*);
    };
    (@fields $meta:tt $name:ident [$($done:tt)*] link_fields; $($rest:tt)*) => {
        table!(@fields $meta $name [$($done)*
            /// Rest length, rod length or cable maximum (m); default the distance at the start.
            pub length: Option<SNum>,
            /// Spring constant (N/m).
            pub k: Option<SNum>,
            /// Restitution of a cable snapping taut.
            pub restitution: Option<SNum>,
            /// Damping ratio of a stiff spring.
            pub damping_ratio: Option<SNum>,
            /// Tension above which the link breaks (N).
            pub tear: Option<SNum>,
        ] $($rest)*);
    };
    (@fields $meta:tt $name:ident [$($done:tt)*] surface_fields; $($rest:tt)*) => {
        table!(@fields $meta $name [$($done)*
            /// Restitution, default 0.3.
            pub restitution: Option<SNum>,
            /// Friction, default 0.5.
            pub friction: Option<SNum>,
            /// Rolling resistance against spheres that roll, default 0.1.
            pub rolling_resistance: Option<SNum>,
        ] $($rest)*);
    };
    (@fields $meta:tt $name:ident [$($done:tt)*] $(#[$field_meta:meta])* pub $field:ident: $ty:ty, $($rest:tt)*) => {
        table!(@fields $meta $name [$($done)* $(#[$field_meta])* pub $field: $ty,] $($rest)*);
    };
    (@fields [$($meta:tt)*] $name:ident [$($done:tt)*]) => {
        $($meta)*
        #[derive(Debug, Deserialize, PartialEq)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            $($done)*
        }
    };
}

/// Every table a scene file may have and the keys each accepts, in the order the
/// reference (`docs/scene-format.md`) lists them. The parser refuses any other table or
/// key; a test below checks this list against the one serde reports for each table.
pub const ACCEPTED_KEYS: &[(&str, &[&str])] = &[
    (
        "scene",
        &[
            "name",
            "summary",
            "dt",
            "steps",
            "trails",
            "color_by_speed",
            "gravity",
            "solver",
            "substeps",
            "integrator",
        ],
    ),
    ("param", &["name", "unit", "default", "min", "max", "help", "logarithmic", "integer"]),
    ("particle", &["name", "position", "velocity", "mass", "radius", "damping", "fixed", "rolls", "color"]),
    (
        "row",
        &[
            "name",
            "count",
            "start",
            "step",
            "position",
            "velocity",
            "mass",
            "radius",
            "damping",
            "fixed",
            "rolls",
            "pin",
            "link",
            "closed",
            "length",
            "k",
            "restitution",
            "damping_ratio",
            "tear",
        ],
    ),
    (
        "grid",
        &[
            "name",
            "rows",
            "cols",
            "origin",
            "step_col",
            "step_row",
            "position",
            "velocity",
            "mass",
            "radius",
            "damping",
            "fixed",
            "rolls",
            "pin",
            "link",
            "shear",
            "length",
            "k",
            "restitution",
            "damping_ratio",
            "tear",
        ],
    ),
    ("link", &["kind", "a", "b", "anchor", "length", "k", "restitution", "damping_ratio", "tear"]),
    ("drag", &["k1", "k2", "targets"]),
    ("buoyancy", &["particle", "surface", "half_height", "volume", "density"]),
    ("ground", &["height", "restitution", "friction", "rolling_resistance"]),
    ("wall", &["normal", "point", "size", "along", "restitution", "friction", "rolling_resistance"]),
    ("plate", &["normal", "point", "opening", "restitution", "friction", "rolling_resistance"]),
    ("collisions", &["restitution", "friction", "rolling_resistance"]),
    (
        "launcher",
        &["position", "speed", "angle", "mass", "radius", "damping", "k1", "k2", "target", "fire_at_start"],
    ),
    ("camera", &["target", "distance", "yaw", "pitch"]),
];

/// The tables a scene file may have and the keys each accepts ([`ACCEPTED_KEYS`]).
#[must_use]
pub fn accepted_keys() -> &'static [(&'static str, &'static [&'static str])] {
    ACCEPTED_KEYS
}

/// The whole file.
#[derive(Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Document {
    /// `[scene]`: name, summary, time step.
    pub scene: SceneTable,
    /// `[[param]]`: the parameter table.
    #[serde(default)]
    pub param: Vec<Spanned<ParamTable>>,
    /// `[[particle]]`: single particles.
    #[serde(default)]
    pub particle: Vec<Spanned<ParticleTable>>,
    /// `[[row]]`: rows of particles, optionally linked in a chain or a ring.
    #[serde(default)]
    pub row: Vec<Spanned<RowTable>>,
    /// `[[grid]]`: grids of particles, optionally linked to their neighbours.
    #[serde(default)]
    pub grid: Vec<Spanned<GridTable>>,
    /// `[[link]]`: links between particles or to anchors.
    #[serde(default)]
    pub link: Vec<Spanned<LinkTable>>,
    /// `[[drag]]`: drag force generators.
    #[serde(default)]
    pub drag: Vec<Spanned<DragTable>>,
    /// `[[buoyancy]]`: buoyancy force generators.
    #[serde(default)]
    pub buoyancy: Vec<Spanned<BuoyancyTable>>,
    /// `[ground]`: the plane y = height.
    pub ground: Option<SurfaceTable>,
    /// `[[wall]]`: other planes.
    #[serde(default)]
    pub wall: Vec<WallTable>,
    /// `[[plate]]`: planes with a round opening.
    #[serde(default)]
    pub plate: Vec<PlateTable>,
    /// `[collisions]`: sphere-sphere collisions between every particle with a radius.
    pub collisions: Option<CollisionsTable>,
    /// `[camera]`: where the camera starts.
    pub camera: Option<CameraTable>,
    /// `[launcher]`: rounds fired at an aim, as in the projectile scene.
    pub launcher: Option<LauncherTable>,
}

table! {
    /// `[scene]`.
    pub struct SceneTable {
        /// Name in the Scene menu.
        pub name: Spanned<String>,
        /// One line saying what it shows.
        #[serde(default)]
        pub summary: String,
        /// Physics time step (s), default 1/240.
        pub dt: Option<Spanned<f64>>,
        /// Steps `simulate` runs by default.
        pub steps: Option<Spanned<i64>>,
        /// Whether trails start on (default true).
        pub trails: Option<bool>,
        /// Whether particles start coloured by speed (default false).
        pub color_by_speed: Option<bool>,
        /// Downward acceleration of every particle (m/s²), default `"g"`.
        pub gravity: Option<SNum>,
        /// The scene's own constraint solver, `"soft"` or `"paper"`; default: the
        /// lab's (soft).
        pub solver: Option<Spanned<String>>,
        /// The scene's own substeps per step (soft solver), 1 to 64; default: the lab's (4).
        pub substeps: Option<Spanned<i64>>,
        /// The scene's own integrator; default: the lab's (semi-implicit Euler).
        pub integrator: Option<Spanned<String>>,
    }
}

table! {
    /// `[[param]]`.
    pub struct ParamTable {
        /// Key for `--set` and the slider.
        pub name: Spanned<String>,
        /// Unit shown beside the value.
        #[serde(default)]
        pub unit: String,
        /// Starting value.
        pub default: Spanned<f64>,
        /// Smallest value.
        pub min: Spanned<f64>,
        /// Largest value.
        pub max: Spanned<f64>,
        /// One line of meaning.
        #[serde(default)]
        pub help: String,
        /// Slider on a logarithmic scale.
        #[serde(default)]
        pub logarithmic: bool,
        /// A count: the slider moves in whole numbers.
        #[serde(default)]
        pub integer: bool,
    }
}

table! {
    /// `[[particle]]`.
    pub struct ParticleTable {
        /// Name, for links and labels.
        pub name: Option<Spanned<String>>,
        /// Position (m).
        pub position: SVec,
        particle_fields;
        /// Colour in the view, `"#rrggbb"`; default the lab's palette.
        pub color: Option<Spanned<String>>,
    }
}

table! {
    /// `[[row]]`.
    pub struct RowTable {
        /// Name, for links and labels.
        pub name: Option<Spanned<String>>,
        /// Number of particles.
        pub count: SNum,
        /// Position of particle 0 (m).
        pub start: Option<SVec>,
        /// Offset from each particle to the next (m).
        pub step: Option<SVec>,
        /// Position of particle `i` (m), instead of start and step.
        pub position: Option<SVec>,
        particle_fields;
        /// Indices made immovable (negative counts from the end).
        #[serde(default)]
        pub pin: Vec<SNum>,
        /// Kind of link between neighbours, if any.
        pub link: Option<Spanned<String>>,
        /// Also link the last to the first (a ring).
        #[serde(default)]
        pub closed: bool,
        link_fields;
    }
}

table! {
    /// `[[grid]]`.
    pub struct GridTable {
        /// Name, for links and labels.
        pub name: Option<Spanned<String>>,
        /// Number of rows (index `i`).
        pub rows: SNum,
        /// Number of columns (index `j`).
        pub cols: SNum,
        /// Position of particle (0, 0) (m).
        pub origin: Option<SVec>,
        /// Offset from one column to the next (m).
        pub step_col: Option<SVec>,
        /// Offset from one row to the next (m).
        pub step_row: Option<SVec>,
        /// Position of particle (i, j) (m), instead of origin and steps.
        pub position: Option<SVec>,
        particle_fields;
        /// `[row, col]` pairs made immovable (negative counts from the end).
        #[serde(default)]
        pub pin: Vec<Spanned<Vec<SNum>>>,
        /// Kind of link between neighbours along rows and columns, if any.
        pub link: Option<Spanned<String>>,
        /// Also link diagonal neighbours.
        #[serde(default)]
        pub shear: bool,
        link_fields;
    }
}

/// What every link of a group shares, borrowed from the table that declares them
/// (serde's `flatten` would lose the values' spans, so each table lists the fields).
#[derive(Clone, Copy, Debug)]
pub struct LinkProps<'a> {
    /// Rest length, rod length or cable maximum (m); default the distance at the start.
    pub length: Option<&'a SNum>,
    /// Spring constant (N/m).
    pub k: Option<&'a SNum>,
    /// Restitution of a cable snapping taut.
    pub restitution: Option<&'a SNum>,
    /// Damping ratio of a stiff spring.
    pub damping_ratio: Option<&'a SNum>,
    /// Tension above which the link breaks (N).
    pub tear: Option<&'a SNum>,
}

macro_rules! link_props {
    ($($table:ty),*) => {$(
        impl $table {
            /// The link properties this table declares.
            #[must_use]
            pub fn props(&self) -> LinkProps<'_> {
                LinkProps {
                    length: self.length.as_ref(),
                    k: self.k.as_ref(),
                    restitution: self.restitution.as_ref(),
                    damping_ratio: self.damping_ratio.as_ref(),
                    tear: self.tear.as_ref(),
                }
            }
        }
    )*};
}

link_props!(RowTable, GridTable, LinkTable);

table! {
    /// `[[link]]`.
    pub struct LinkTable {
        /// rod, cable, spring, bungee or stiff_spring.
        pub kind: Spanned<String>,
        /// First end: one particle or a whole array.
        pub a: Spanned<Ref>,
        /// Second end, a particle or an array.
        pub b: Option<Spanned<Ref>>,
        /// Second end, a fixed point (m).
        pub anchor: Option<SVec>,
        link_fields;
    }
}

table! {
    /// `[[drag]]`.
    pub struct DragTable {
        /// Linear coefficient (N·s/m).
        pub k1: Option<SNum>,
        /// Quadratic coefficient (N·s²/m²).
        pub k2: Option<SNum>,
        /// Particles it acts on; default every movable particle.
        pub targets: Option<Vec<Spanned<Ref>>>,
    }
}

table! {
    /// `[[buoyancy]]`.
    pub struct BuoyancyTable {
        /// The floating particle, or an array of them.
        pub particle: Spanned<Ref>,
        /// Height of the liquid surface (m).
        pub surface: SNum,
        /// Half the body's height (m).
        pub half_height: SNum,
        /// Body volume (m³).
        pub volume: SNum,
        /// Liquid density (kg/m³), default 1000.
        pub density: Option<SNum>,
    }
}

table! {
    /// `[ground]`.
    pub struct SurfaceTable {
        /// Height (m), default 0.
        pub height: Option<SNum>,
        surface_fields;
    }
}

table! {
    /// `[[wall]]`.
    pub struct WallTable {
        /// Normal, towards the free side.
        pub normal: SVec,
        /// A point of the plane (m); a finite wall's centre.
        pub point: SVec,
        /// A finite wall's length and width `[l, w]` (m); without it the wall is the
        /// whole plane.
        pub size: Option<Spanned<Vec<SNum>>>,
        /// The direction of a finite wall's length (made to lie in the plane); default
        /// down its slope, or along x for an upright wall.
        pub along: Option<SVec>,
        surface_fields;
    }
}

table! {
    /// `[[plate]]`.
    pub struct PlateTable {
        /// Normal of the plate.
        pub normal: SVec,
        /// Centre of the opening, a point of the plate (m).
        pub point: SVec,
        /// Diameter of the opening (m).
        pub opening: SNum,
        surface_fields;
    }
}

table! {
    /// `[collisions]`: restitution 0.5, friction 0.3 and rolling resistance 0.1 by
    /// default between particles.
    pub struct CollisionsTable {
        surface_fields;
    }
}

table! {
    /// `[launcher]`.
    pub struct LauncherTable {
        /// Where rounds leave from (m), default `[0, 1.5, 0]`.
        pub position: Option<SVec>,
        /// Launch speed (m/s), default 25.
        pub speed: Option<SNum>,
        /// Elevation above the horizontal towards +x (degrees), default 45.
        pub angle: Option<SNum>,
        /// A round's mass (kg), default 1.
        pub mass: Option<SNum>,
        /// A round's radius (m), default 0.3.
        pub radius: Option<SNum>,
        /// Fraction of velocity a round keeps per second, default 1.
        pub damping: Option<SNum>,
        /// Linear drag of a round (N·s/m), default 0.
        pub k1: Option<SNum>,
        /// Quadratic drag of a round (N·s²/m²), default 0.
        pub k2: Option<SNum>,
        /// Distance of a target on the ground from the launcher, along x (m); default none.
        pub target: Option<SNum>,
        /// Whether a headless run (`simulate`, `render`, a link with `steps`) fires a
        /// round at step 0, default true; the window waits for Fire.
        pub fire_at_start: Option<bool>,
    }
}

table! {
    /// `[camera]`.
    pub struct CameraTable {
        /// Point looked at (m).
        pub target: Option<SVec>,
        /// Distance from it (m).
        pub distance: Option<SNum>,
        /// Turn about the vertical (degrees); 0 looks along -z.
        pub yaw: Option<SNum>,
        /// Elevation (degrees), positive looks down.
        pub pitch: Option<SNum>,
    }
}

#[cfg(test)]
mod tests {
    use super::{ACCEPTED_KEYS, Document};

    /// The names serde lists after "expected one of" in an unknown-field error.
    fn expected_names(message: &str) -> Vec<String> {
        let (_, list) = message.split_once("expected").unwrap_or_else(|| panic!("no list in: {message}"));
        list.split('`').skip(1).step_by(2).map(str::to_string).collect()
    }

    /// The parser's message for `text`, which must be refused.
    fn refusal(text: &str) -> String {
        match toml::from_str::<Document>(text) {
            Ok(_) => panic!("accepted, but should not have:\n{text}"),
            Err(error) => error.message().to_string(),
        }
    }

    /// A file whose table `table` holds `line` and nothing else (with the `[scene]`
    /// every file needs).
    fn file_with(table: &str, line: &str) -> String {
        let array = !matches!(table, "scene" | "ground" | "collisions" | "launcher" | "camera");
        let header = if array { format!("[[{table}]]") } else { format!("[{table}]") };
        if table == "scene" {
            format!("{header}\n{line}\n")
        } else {
            format!("[scene]\nname = \"keys\"\n{header}\n{line}\n")
        }
    }

    #[test]
    fn the_accepted_keys_are_exactly_the_ones_the_parser_accepts() {
        // The tables: an unknown one is refused with the list of the known ones.
        let message = refusal("[scene]\nname = \"keys\"\n[no_such_table]\nx = 1\n");
        assert!(message.contains("unknown field `no_such_table`"), "{message}");
        let mut tables = expected_names(&message);
        let mut listed: Vec<String> = ACCEPTED_KEYS.iter().map(|(t, _)| (*t).to_string()).collect();
        tables.sort();
        listed.sort();
        assert_eq!(tables, listed, "the tables a file may have");
        for (table, keys) in ACCEPTED_KEYS {
            // An unknown key is refused, and the refusal lists what the table accepts.
            let message = refusal(&file_with(table, "no_such_key = 1"));
            assert!(message.contains("unknown field `no_such_key`"), "[{table}]: {message}");
            let mut accepted = expected_names(&message);
            let mut listed: Vec<String> = keys.iter().map(|k| (*k).to_string()).collect();
            accepted.sort();
            listed.sort();
            assert_eq!(accepted, listed, "the keys of [{table}]");
            // Every listed key is taken as a key of the table (its value may still be
            // refused for its type, or another key be missing, but not the key itself).
            for key in *keys {
                if let Err(error) = toml::from_str::<Document>(&file_with(table, &format!("{key} = 1"))) {
                    let message = error.message();
                    assert!(!message.contains("unknown field"), "[{table}] {key}: {message}");
                }
            }
        }
    }
}
