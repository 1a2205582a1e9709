//! The scene file's writer: the text of a parsed [`Document`], as a person would write
//! it. Tables come in the order the reference lists them ([`ACCEPTED_KEYS`]), the keys
//! of each table in that order too, and only the keys the document gives. Numbers are
//! written in the fewest digits that read back to the same value (`0.1`, `12`,
//! `1e-5`), expressions as the quoted text they were.
//!
//! Writing is a function of the document alone, so a file read and written again is
//! the same bytes; comments of a hand-written file are not kept (the reader drops
//! them), and a short header says what the file is instead.

use std::fmt::Write as _;

use crate::scenes::ParamValues;

use super::format::{
    ACCEPTED_KEYS, BuoyancyTable, CameraTable, CollisionsTable, Document, DragTable, GridTable,
    LauncherTable, LinkTable, Num, ParamTable, ParticleTable, PlateTable, Ref, RowTable, SNum, SVec,
    SurfaceTable, WallTable,
};

/// The first lines of every written file.
pub const HEADER: &str = "# A particle-lab scene file (the format: docs/scene-format.md).\n\
# Open it with `particle-lab --scene-file FILE` or File → Open scene file.\n";

/// The text of `doc`. With `values`, each parameter's default is the value there where
/// it differs from the file's, and a parameter the scene has but the document does not
/// declare (the `g` every file scene gets) is declared, first, when its value is not
/// its default.
#[must_use]
pub fn write(doc: &Document, values: Option<&ParamValues>) -> String {
    let mut out = Writer { text: String::from(HEADER) };
    scene(&mut out, doc);
    let declared = |name: &str| doc.param.iter().any(|p| p.get_ref().name.get_ref() == name);
    for (p, value) in values.into_iter().flat_map(ParamValues::iter) {
        if declared(&p.name) || value == p.default {
            continue;
        }
        out.table("param", true);
        out.key("name", string(&p.name));
        if !p.unit.is_empty() {
            out.key("unit", string(&p.unit));
        }
        out.key("default", float32(value));
        out.key("min", float32(p.min));
        out.key("max", float32(p.max));
        if !p.help.is_empty() {
            out.key("help", string(&p.help));
        }
        out.flag("logarithmic", p.logarithmic);
        out.flag("integer", p.integer);
    }
    for p in &doc.param {
        let p = p.get_ref();
        let value = values.map(|v| v.get(p.name.get_ref()));
        param(&mut out, p, value);
    }
    for p in &doc.particle {
        particle(&mut out, p.get_ref());
    }
    for r in &doc.row {
        row(&mut out, r.get_ref());
    }
    for g in &doc.grid {
        grid(&mut out, g.get_ref());
    }
    for l in &doc.link {
        link(&mut out, l.get_ref());
    }
    for d in &doc.drag {
        drag(&mut out, d.get_ref());
    }
    for b in &doc.buoyancy {
        buoyancy(&mut out, b.get_ref());
    }
    if let Some(g) = &doc.ground {
        ground(&mut out, g);
    }
    for w in &doc.wall {
        wall(&mut out, w);
    }
    for p in &doc.plate {
        plate(&mut out, p);
    }
    if let Some(c) = &doc.collisions {
        collisions(&mut out, c);
    }
    if let Some(l) = &doc.launcher {
        launcher(&mut out, l);
    }
    if let Some(c) = &doc.camera {
        camera(&mut out, c);
    }
    out.text
}

/// The text being written.
struct Writer {
    text: String,
}

impl Writer {
    /// Starts a table (`[name]`, or `[[name]]` for one of an array), after a blank line.
    fn table(&mut self, name: &str, array: bool) {
        debug_assert!(ACCEPTED_KEYS.iter().any(|(t, _)| *t == name), "[{name}] is not a table of the format");
        let (open, close) = if array { ("[[", "]]") } else { ("[", "]") };
        let _ = write!(self.text, "\n{open}{name}{close}\n");
    }

    /// `key = value`.
    fn key(&mut self, key: &str, value: String) {
        let _ = writeln!(self.text, "{key} = {value}");
    }

    /// `key = value` where there is a value.
    fn some(&mut self, key: &str, value: Option<String>) {
        if let Some(value) = value {
            self.key(key, value);
        }
    }

    /// `key = true` where it is true (false is every flag's default).
    fn flag(&mut self, key: &str, on: bool) {
        if on {
            self.key(key, "true".into());
        }
    }
}

/// A number in the fewest digits that read back as the same `f64`; an exponent where
/// plain digits would run long. TOML reads `12` as an integer, which every number key
/// takes.
#[must_use]
pub fn float(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    let plain = format!("{x}");
    if x.abs() >= 1e15 {
        // Plain digits here would read as a TOML integer, which stops at 2^63.
        return format!("{x:e}");
    }
    if x != 0.0 && x.abs() < 1e-4 {
        let exponent = format!("{x:e}");
        if exponent.len() < plain.len() {
            return exponent;
        }
    }
    plain
}

/// An `f32` in the fewest digits that read back as the same `f32` (a slider's value
/// of 0.3 is written `0.3`, not the `f64` it widens to).
#[must_use]
pub fn float32(x: f32) -> String {
    let digits = float(f64::from(x));
    // The shortest f64 text of a widened f32 may carry digits the f32 does not need.
    let short = if x.is_finite() && x != 0.0 && !(1e-4..1e15).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    };
    if short.parse::<f64>().is_ok_and(|y| y as f32 == x) && short.len() < digits.len() {
        short
    } else {
        digits
    }
}

/// A TOML basic string: quotes, backslashes and control characters escaped.
#[must_use]
pub fn string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn num(n: &SNum) -> String {
    match n.get_ref() {
        Num::Value(x) => float(*x),
        Num::Text(t) => string(t),
    }
}

fn nums(values: &[SNum]) -> String {
    let items: Vec<String> = values.iter().map(num).collect();
    format!("[{}]", items.join(", "))
}

fn vector(v: &SVec) -> String {
    nums(v.get_ref())
}

fn reference(r: &Ref) -> String {
    match r {
        Ref::Index(i) => i.to_string(),
        Ref::Name(name) => string(name),
    }
}

fn scene(out: &mut Writer, doc: &Document) {
    let s = &doc.scene;
    out.table("scene", false);
    out.key("name", string(s.name.get_ref()));
    if !s.summary.is_empty() {
        out.key("summary", string(&s.summary));
    }
    out.some("dt", s.dt.as_ref().map(|dt| float(*dt.get_ref())));
    out.some("steps", s.steps.as_ref().map(|n| n.get_ref().to_string()));
    out.some("trails", s.trails.map(|b| b.to_string()));
    out.some("color_by_speed", s.color_by_speed.map(|b| b.to_string()));
    out.some("gravity", s.gravity.as_ref().map(num));
    out.some("solver", s.solver.as_ref().map(|name| string(name.get_ref())));
    out.some("substeps", s.substeps.as_ref().map(|n| n.get_ref().to_string()));
    out.some("integrator", s.integrator.as_ref().map(|name| string(name.get_ref())));
}

/// A `[[param]]`, its default `value` where one is given and differs from the file's as
/// the scene reads it (an `f32`); otherwise the file's digits.
fn param(out: &mut Writer, p: &ParamTable, value: Option<f32>) {
    out.table("param", true);
    let name = p.name.get_ref();
    out.key("name", string(name));
    if !p.unit.is_empty() {
        out.key("unit", string(&p.unit));
    }
    let written = *p.default.get_ref();
    let default = match value {
        Some(value) if value != written as f32 => float32(value),
        _ => float(written),
    };
    out.key("default", default);
    out.key("min", float(*p.min.get_ref()));
    out.key("max", float(*p.max.get_ref()));
    if !p.help.is_empty() {
        out.key("help", string(&p.help));
    }
    out.flag("logarithmic", p.logarithmic);
    out.flag("integer", p.integer);
}

/// The keys every table that makes particles shares, in the reference's order.
macro_rules! particle_keys {
    ($out:expr, $t:expr) => {{
        $out.some("velocity", $t.velocity.as_ref().map(vector));
        $out.some("mass", $t.mass.as_ref().map(num));
        $out.some("radius", $t.radius.as_ref().map(num));
        $out.some("damping", $t.damping.as_ref().map(num));
        $out.flag("fixed", $t.fixed);
        $out.flag("rolls", $t.rolls);
    }};
}

/// The keys every table that makes links shares, in the reference's order.
macro_rules! link_keys {
    ($out:expr, $t:expr) => {{
        $out.some("length", $t.length.as_ref().map(num));
        $out.some("k", $t.k.as_ref().map(num));
        $out.some("restitution", $t.restitution.as_ref().map(num));
        $out.some("damping_ratio", $t.damping_ratio.as_ref().map(num));
        $out.some("tear", $t.tear.as_ref().map(num));
    }};
}

fn particle(out: &mut Writer, p: &ParticleTable) {
    out.table("particle", true);
    out.some("name", p.name.as_ref().map(|n| string(n.get_ref())));
    out.key("position", vector(&p.position));
    particle_keys!(out, p);
    out.some("color", p.color.as_ref().map(|c| string(c.get_ref())));
}

fn row(out: &mut Writer, r: &RowTable) {
    out.table("row", true);
    out.some("name", r.name.as_ref().map(|n| string(n.get_ref())));
    out.key("count", num(&r.count));
    out.some("start", r.start.as_ref().map(vector));
    out.some("step", r.step.as_ref().map(vector));
    out.some("position", r.position.as_ref().map(vector));
    particle_keys!(out, r);
    if !r.pin.is_empty() {
        out.key("pin", nums(&r.pin));
    }
    out.some("link", r.link.as_ref().map(|l| string(l.get_ref())));
    out.flag("closed", r.closed);
    link_keys!(out, r);
}

fn grid(out: &mut Writer, g: &GridTable) {
    out.table("grid", true);
    out.some("name", g.name.as_ref().map(|n| string(n.get_ref())));
    out.key("rows", num(&g.rows));
    out.key("cols", num(&g.cols));
    out.some("origin", g.origin.as_ref().map(vector));
    out.some("step_col", g.step_col.as_ref().map(vector));
    out.some("step_row", g.step_row.as_ref().map(vector));
    out.some("position", g.position.as_ref().map(vector));
    particle_keys!(out, g);
    if !g.pin.is_empty() {
        let pairs: Vec<String> = g.pin.iter().map(|pair| nums(pair.get_ref())).collect();
        out.key("pin", format!("[{}]", pairs.join(", ")));
    }
    out.some("link", g.link.as_ref().map(|l| string(l.get_ref())));
    out.flag("shear", g.shear);
    link_keys!(out, g);
}

fn link(out: &mut Writer, l: &LinkTable) {
    out.table("link", true);
    out.key("kind", string(l.kind.get_ref()));
    out.key("a", reference(l.a.get_ref()));
    out.some("b", l.b.as_ref().map(|b| reference(b.get_ref())));
    out.some("anchor", l.anchor.as_ref().map(vector));
    link_keys!(out, l);
}

fn drag(out: &mut Writer, d: &DragTable) {
    out.table("drag", true);
    out.some("k1", d.k1.as_ref().map(num));
    out.some("k2", d.k2.as_ref().map(num));
    if let Some(targets) = &d.targets {
        let items: Vec<String> = targets.iter().map(|t| reference(t.get_ref())).collect();
        out.key("targets", format!("[{}]", items.join(", ")));
    }
}

fn buoyancy(out: &mut Writer, b: &BuoyancyTable) {
    out.table("buoyancy", true);
    out.key("particle", reference(b.particle.get_ref()));
    out.key("surface", num(&b.surface));
    out.key("half_height", num(&b.half_height));
    out.key("volume", num(&b.volume));
    out.some("density", b.density.as_ref().map(num));
}

/// The keys of a surface (ground, wall), in the reference's order.
macro_rules! surface_keys {
    ($out:expr, $t:expr) => {{
        $out.some("restitution", $t.restitution.as_ref().map(num));
        $out.some("friction", $t.friction.as_ref().map(num));
        $out.some("rolling_resistance", $t.rolling_resistance.as_ref().map(num));
    }};
}

fn ground(out: &mut Writer, g: &SurfaceTable) {
    out.table("ground", false);
    out.some("height", g.height.as_ref().map(num));
    surface_keys!(out, g);
}

fn wall(out: &mut Writer, w: &WallTable) {
    out.table("wall", true);
    out.key("normal", vector(&w.normal));
    out.key("point", vector(&w.point));
    out.some("size", w.size.as_ref().map(|size| nums(size.get_ref())));
    out.some("along", w.along.as_ref().map(vector));
    surface_keys!(out, w);
}

fn plate(out: &mut Writer, p: &PlateTable) {
    out.table("plate", true);
    out.key("normal", vector(&p.normal));
    out.key("point", vector(&p.point));
    out.key("opening", num(&p.opening));
    surface_keys!(out, p);
}

fn collisions(out: &mut Writer, c: &CollisionsTable) {
    out.table("collisions", false);
    surface_keys!(out, c);
}

fn launcher(out: &mut Writer, l: &LauncherTable) {
    out.table("launcher", false);
    out.some("position", l.position.as_ref().map(vector));
    out.some("speed", l.speed.as_ref().map(num));
    out.some("angle", l.angle.as_ref().map(num));
    out.some("mass", l.mass.as_ref().map(num));
    out.some("radius", l.radius.as_ref().map(num));
    out.some("damping", l.damping.as_ref().map(num));
    out.some("k1", l.k1.as_ref().map(num));
    out.some("k2", l.k2.as_ref().map(num));
    out.some("target", l.target.as_ref().map(num));
    out.some("fire_at_start", l.fire_at_start.map(|b| b.to_string()));
}

fn camera(out: &mut Writer, c: &CameraTable) {
    out.table("camera", false);
    out.some("target", c.target.as_ref().map(vector));
    out.some("distance", c.distance.as_ref().map(num));
    out.some("yaw", c.yaw.as_ref().map(num));
    out.some("pitch", c.pitch.as_ref().map(num));
}

#[cfg(test)]
mod tests {
    use super::super::format::{ACCEPTED_KEYS, Document};
    use super::{float, float32, string, write};

    fn parse(text: &str) -> Document {
        toml::from_str(text).unwrap_or_else(|e| panic!("{e}\n{text}"))
    }

    /// Reads `text`, writes it, reads and writes that: the documents are equal and the
    /// two writings are the same bytes.
    fn round_trip(text: &str) -> String {
        let doc = parse(text);
        let once = write(&doc, None);
        let again = parse(&once);
        assert_eq!(doc, again, "the written file reads back as another document:\n{once}");
        let twice = write(&again, None);
        assert_eq!(once, twice, "a second writing differs");
        once
    }

    #[test]
    fn shipped_scene_files_round_trip_to_the_same_bytes() {
        // Read from disk, not through the registry (`file.rs`), which uses this writer.
        let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
        for entry in std::fs::read_dir(folder).expect("assets/scenes") {
            let path = entry.expect("a folder entry").path();
            let name = path.display();
            let text = std::fs::read_to_string(&path).expect("a scene file");
            let written = round_trip(&text);
            assert!(written.starts_with(super::HEADER), "{name}");
        }
    }

    /// A file with every table and every key the format accepts, every one in the first
    /// entry of its table (read, not built: some would not build together).
    const EVERY_KEY: &str = r##"
[camera]
pitch = 12.5
yaw = -30
distance = 9
target = [0, "1 + h", 0]

[scene]
name = "every \"key\"\nhere"
summary = "tab\there, a backslash \\ and ünïcode"
dt = 0.002
steps = 1200
trails = false
color_by_speed = true
gravity = "g * 2"
solver = "paper"
substeps = 8
integrator = "rk4"

[[param]]
name = "h"
unit = "m"
default = 1.5
min = 0.1
max = 10
help = "height"
logarithmic = true
integer = true

[[param]]
name = "n"
default = 4
min = 2
max = 9
integer = true

[[particle]]
name = "ball"
position = [0, "h", 1e-7]
velocity = [1, 0, -2.5]
mass = 2
radius = 0.25
damping = 0.99
fixed = true
rolls = true
color = "#10a0ff"

[[row]]
name = "chain"
count = "n"
start = [0, 3, 0]
step = [0.5, 0, 0]
position = ["i", 3, 0]
velocity = [0, 0, 0]
mass = 0.1
radius = 0.05
damping = 1
fixed = true
rolls = true
pin = [0, -1]
link = "spring"
closed = true
length = 0.5
k = 40
restitution = 0.2
damping_ratio = 0.1
tear = 1e4

[[row]]
count = 3
position = ["i", 6, 0]

[[grid]]
name = "cloth"
rows = 3
cols = "n"
origin = [0, 5, 0]
step_col = [0.2, 0, 0]
step_row = [0, 0, 0.2]
position = ["i", "j", 5]
velocity = [0, 1, 0]
mass = 0.05
radius = 0.02
damping = 0.9
fixed = true
rolls = true
pin = [[0, 0], [0, -1]]
link = "rod"
shear = true
length = 0.2
k = 1
restitution = 0
damping_ratio = 0
tear = 500

[[grid]]
rows = 2
cols = 2
position = ["i", "j", 8]

[[link]]
kind = "cable"
a = "ball"
b = "chain.-1"
anchor = [0, 9, 0]
length = 2
k = 1
restitution = 0.5
damping_ratio = 0.3
tear = 100

[[link]]
kind = "rod"
a = 0
anchor = [0, 9, 0]

[[drag]]
k1 = 0.1
k2 = 0.01
targets = ["ball", 3]

[[buoyancy]]
particle = "ball"
surface = 0.5
half_height = 0.25
volume = 0.03
density = 1025

[ground]
height = -1
restitution = 0.4
friction = 0.6
rolling_resistance = 0.05

[[wall]]
normal = [1, 0, 0]
point = [-5, 0, 0]
size = [4, "h"]
along = [0, 1, 0]
restitution = 0.2
friction = 0.3
rolling_resistance = 0.1

[[plate]]
normal = [0, 1, 0]
point = [0, "h", 0]
opening = 0.6
restitution = 0
friction = 0.4
rolling_resistance = 0.2

[collisions]
restitution = 0.5
friction = 0.3
rolling_resistance = 0.1

[launcher]
position = [0, "h", 0]
speed = 20
angle = 30
mass = 2
radius = 0.2
damping = 0.99
k1 = 0.1
k2 = 0.01
target = 25
fire_at_start = false
"##;

    #[test]
    fn every_key_of_the_format_is_written_in_the_references_order() {
        let written = round_trip(EVERY_KEY);
        // Tables in the reference's order, each key of each in its order.
        let mut position = 0;
        let mut table_order = Vec::new();
        for (table, keys) in ACCEPTED_KEYS {
            let headers = [format!("\n[{table}]\n"), format!("\n[[{table}]]\n")];
            let first = headers.iter().filter_map(|h| written.find(h.as_str())).min();
            let first = first.unwrap_or_else(|| panic!("[{table}] is not written:\n{written}"));
            assert!(first >= position, "[{table}] is written before the table above it:\n{written}");
            position = first;
            table_order.push(*table);
            // The first of this table's entries holds every key (the file gives them all
            // there), in the order listed.
            let body_start = first + 1;
            let body_end = written[body_start..].find("\n[").map_or(written.len(), |k| body_start + k);
            let body = &written[body_start..body_end];
            let mut last = 0;
            for key in *keys {
                let at = body
                    .find(&format!("\n{key} = "))
                    .unwrap_or_else(|| panic!("[{table}] {key} missing:\n{body}"));
                assert!(at >= last, "[{table}] {key} out of order:\n{body}");
                last = at;
            }
        }
        assert_eq!(table_order.len(), ACCEPTED_KEYS.len());
    }

    #[test]
    fn numbers_are_written_in_the_fewest_digits_that_read_back_the_same() {
        assert_eq!(float(12.0), "12");
        assert_eq!(float(0.1), "0.1");
        assert_eq!(float(-2.5), "-2.5");
        assert_eq!(float(1e-7), "1e-7");
        assert_eq!(float(1.0 / 240.0), "0.004166666666666667");
        assert_eq!(float(6.02e23), "6.02e23");
        assert_eq!(float32(0.3), "0.3");
        assert_eq!(float32(1.0 / 3.0), "0.33333334");
        // A spread of values: the text reads back as the same number, through TOML.
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let wide = f64::from_bits(x);
            if wide.is_finite() {
                let text = float(wide);
                let back: toml::Value = toml::from_str(&format!("v = {text}")).expect(&text);
                let back = back["v"].as_float().or_else(|| back["v"].as_integer().map(|i| i as f64));
                assert_eq!(back, Some(wide), "{text}");
            }
            let narrow = f32::from_bits(x as u32);
            if narrow.is_finite() {
                let text = float32(narrow);
                assert_eq!(text.parse::<f64>().map(|y| y as f32), Ok(narrow), "{text}");
            }
        }
    }

    #[test]
    fn strings_are_escaped_so_they_read_back_the_same() {
        for s in ["plain", "say \"hi\"", "back\\slash", "two\nlines", "tab\t", "bell\u{7}", "ünï ☃"] {
            let text = format!("v = {}", string(s));
            let back: toml::Value = toml::from_str(&text).expect(&text);
            assert_eq!(back["v"].as_str(), Some(s), "{text}");
        }
    }
}
