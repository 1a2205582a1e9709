//! Snapshots: a running scene saved to a file and loaded again, to step on with the
//! same bits.
//!
//! A snapshot is one JSON object (described for users in docs/cli.md, "Snapshots"):
//!
//! - `format` (`"particle-lab snapshot"`) and `version` ([`VERSION`]): read first, so a
//!   file from a newer particle-lab is refused with that said, not with a field error;
//! - `scene` (its name), `params` (every parameter's value) and `dt` (the physics step,
//!   s): what rebuilds the scene's own objects (its ids, its rules);
//! - `world` ([`WorldState`]): every particle, force and contact generator, the
//!   solver and integrator settings, the warm-start impulses, time and step count;
//! - `scene_state`: what the scene keeps beside its world (rounds in flight, ghosts of
//!   the exact answer), or `null`;
//! - `hash`: [`World::state_hash`] of the saved world, as 16 hex digits, and
//!   `checksum`: a hash of every other field as written (scene, its file, parameters,
//!   `dt`, world, scene state: everything that changes the run). Loading checks both, so
//!   a damaged file cannot pass for a good one; delete them to load a file edited by
//!   hand, which is then checked field by field. A version 1 file's checksum covers its
//!   world only, and is checked as such.
//!
//! Numbers are written in the shortest form that reads back to the same f32 or f64, so
//! a saved world and the loaded one are the same bits.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::{ParamValues, RawValue, Scene, SceneEntry};
use crate::messages;
use crate::physics::{World, WorldState};
use crate::reading;

/// The `format` field of every snapshot.
pub const FORMAT: &str = "particle-lab snapshot";

/// The snapshot format this build writes and reads. Raise it when a change makes old
/// files mean something else. Version 2: the checksum covers every field, not only
/// the world.
pub const VERSION: u32 = 2;

/// The oldest version this build still reads (its checksum covers the world only).
pub const OLDEST_VERSION: u32 = 1;

/// Largest snapshot file read (bytes), 512 MB: a 100,000-particle pile is about 60 MB.
/// The read stops there whatever the file's reported size.
pub const MAX_FILE_BYTES: u64 = 512 * 1024 * 1024;

/// A saved scene: see the module comment for each field.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Snapshot {
    /// Always [`FORMAT`].
    pub format: String,
    /// The format version, [`VERSION`] when written by this build.
    pub version: u32,
    /// The scene's name.
    pub scene: String,
    /// For a scene built from a file: the file's text (and where it was read from), so
    /// the snapshot rebuilds the same scene wherever it is opened.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene_file: Option<SceneSource>,
    /// Every parameter's value, in the scene's table order.
    pub params: Vec<(String, f32)>,
    /// The physics time step the lab ran at (s).
    pub dt: f32,
    /// [`World::state_hash`] of `world`, as 16 hex digits (what `simulate` prints);
    /// optional when reading.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hash: Option<String>,
    /// A hash of every other field as written (the scene, its file, parameters, `dt`,
    /// world and scene state), as 16 hex digits: it covers what the state hash leaves
    /// out (forces, settings, totals, the rate); optional when reading.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checksum: Option<String>,
    /// The world.
    pub world: WorldState,
    /// What the scene keeps beside its world ([`Scene::save_state`]), as its JSON
    /// text: read into the scene's own types only when it is restored, so a huge
    /// value is never first built as a tree of JSON values.
    #[serde(default = "null_state")]
    pub scene_state: Box<RawValue>,
}

/// A scene state of `null`, for a file that has none.
fn null_state() -> Box<RawValue> {
    RawValue::from_string("null".into()).expect("null is JSON")
}

/// `json` without the whitespace between its tokens: the compact form, byte for byte,
/// of a value written by serde_json, pretty or not, whose object keys are in the order
/// it writes them (as every file this program writes), found without parsing it.
fn compact(json: &str) -> String {
    let (mut out, mut in_string, mut escaped) = (String::with_capacity(json.len()), false, false);
    for c in json.chars() {
        if in_string {
            (in_string, escaped) = (escaped || c != '"', !escaped && c == '\\');
        } else if c == '"' {
            in_string = true;
        } else if c.is_ascii_whitespace() {
            continue;
        }
        out.push(c);
    }
    out
}

/// The scene file a snapshot's scene was built from.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SceneSource {
    /// Where it was read from, if from disk (shown in messages; not read again).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<String>,
    /// The TOML text.
    pub text: String,
}

/// What the checksum covers: every field of a snapshot but its format, version and
/// the two seals.
#[derive(Serialize)]
struct Sealed<'a> {
    scene: &'a str,
    scene_file: &'a Option<SceneSource>,
    params: &'a [(String, f32)],
    dt: f32,
    world: &'a WorldState,
    scene_state: &'a RawValue,
}

/// The checksum of a snapshot's fields: a hash of their compact JSON, byte by byte.
/// For a version 1 file, of its world alone (what that version sealed).
fn checksum(snapshot: &Snapshot) -> String {
    // A pretty file's scene state is sealed as the compact text it was sealed as.
    let scene_state = RawValue::from_string(compact(snapshot.scene_state.get()));
    let scene_state = scene_state.unwrap_or_else(|_| snapshot.scene_state.clone());
    let bytes = if snapshot.version == 1 {
        serde_json::to_vec(&snapshot.world)
    } else {
        serde_json::to_vec(&Sealed {
            scene: &snapshot.scene,
            scene_file: &snapshot.scene_file,
            params: &snapshot.params,
            dt: snapshot.dt,
            world: &snapshot.world,
            scene_state: &scene_state,
        })
    };
    let bytes = bytes.expect("a snapshot is plain data with string keys");
    let mut hasher = crate::physics::StateHasher::default();
    for chunk in bytes.chunks(8) {
        let mut word = [0u8; 8];
        word[..chunk.len()].copy_from_slice(chunk);
        hasher.u64(u64::from_le_bytes(word));
    }
    hasher.u64(bytes.len() as u64);
    hash_text(hasher.finish())
}

/// A hash as snapshots and `simulate` print it.
#[must_use]
pub fn hash_text(hash: u64) -> String {
    format!("{hash:016x}")
}

impl Snapshot {
    /// The state of `scene`, running at time step `dt`. Refused for a world holding a
    /// force generator of a kind the format does not know.
    pub fn of(scene: &dyn Scene, dt: f32) -> Result<Self, String> {
        let world = scene.world();
        // A figure that is not finite is written as `null`, which no reader takes back:
        // refused here, at save time, rather than when the file is opened again.
        if let Some(what) = world.first_non_finite(&mut Vec::new()) {
            return Err(format!("cannot save this scene: {what} is not a finite number"));
        }
        let state = world.state().map_err(|e| format!("cannot save this scene: {e}"))?;
        let mut snapshot = Self {
            format: FORMAT.into(),
            version: VERSION,
            scene: scene.info().name.to_string(),
            scene_file: scene.source().map(|(text, path)| SceneSource {
                path: path.map(|p| p.display().to_string()),
                text: text.to_string(),
            }),
            params: scene.params().iter().map(|(param, value)| (param.name.to_string(), value)).collect(),
            dt,
            hash: Some(hash_text(world.state_hash())),
            checksum: None,
            world: state,
            scene_state: serde_json::value::to_raw_value(&scene.save_state())
                .map_err(|e| format!("cannot save this scene's state: {e}"))?,
        };
        snapshot.checksum = Some(checksum(&snapshot));
        Ok(snapshot)
    }

    /// The snapshot as pretty-printed JSON.
    #[must_use]
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a snapshot is plain data with string keys")
    }

    /// Reads a snapshot from JSON text; the error is one line: where the text stops
    /// making sense, or which field is wrong.
    pub fn from_json(text: &str) -> Result<Self, String> {
        Self::parse(text).map_err(|e| messages::one_line(&e))
    }

    fn parse(text: &str) -> Result<Self, String> {
        // Format and version first, from a small struct that skips every other field:
        // a newer file's unknown fields are not its problem.
        #[derive(Deserialize)]
        struct Header {
            format: Option<String>,
            version: Option<u64>,
        }
        let header: Header = serde_json::from_str(text).map_err(|e| {
            if e.is_eof() {
                format!("the file ends too early (cut short?): {e}")
            } else {
                format!("not a snapshot (not valid JSON): {e}")
            }
        })?;
        if header.format.as_deref() != Some(FORMAT) {
            return Err(format!("not a snapshot: its \"format\" field is not \"{FORMAT}\""));
        }
        match header.version {
            Some(v) if (u64::from(OLDEST_VERSION)..=u64::from(VERSION)).contains(&v) => {}
            Some(v) if v > u64::from(VERSION) => {
                return Err(format!(
                    "made by a newer particle-lab (snapshot version {v}; this one reads version {VERSION})"
                ));
            }
            Some(v) => {
                return Err(format!(
                    "snapshot version {v} is not supported (this one reads versions {OLDEST_VERSION} to \
                     {VERSION})"
                ));
            }
            None => return Err("not a snapshot: it has no \"version\" number".into()),
        }
        // Straight from the text: each number is read once into its own type (through a
        // JSON value an f32 would be rounded twice, and could come back one bit off).
        let snapshot: Self = serde_json::from_str(text).map_err(|e| format!("damaged snapshot: {e}"))?;
        if let Some(saved) = &snapshot.checksum {
            let sum = checksum(&snapshot);
            if *saved != sum {
                let what = if snapshot.version == 1 { "the world" } else { "the snapshot" };
                return Err(format!(
                    "{what} does not match its checksum ({} saved, {sum} read): the file was changed \
                     or damaged (delete the \"checksum\" and \"hash\" fields to load a file edited by hand)",
                    messages::quote(saved)
                ));
            }
        }
        Ok(snapshot)
    }

    /// Writes the snapshot to `path`, through a temporary file beside it, so a failed
    /// write leaves what was there.
    pub fn save(&self, path: &Path) -> Result<(), String> {
        // Through a link to the file it names; a device or FIFO is refused untouched.
        crate::writing::write_atomic(path, self.to_json().as_bytes())
            .map_err(|e| format!("cannot write {}: {e}", messages::path(path)))
    }

    /// Reads a snapshot file, at most [`MAX_FILE_BYTES`] of it; a device, FIFO or
    /// directory is refused without being opened. The error names the file.
    pub fn load(path: &Path) -> Result<Self, String> {
        let shown = messages::path(path);
        let text = reading::read_text_limited(path, MAX_FILE_BYTES).map_err(|e| match e {
            reading::ReadError::TooLarge { .. } => format!("{shown}: {e} for a snapshot"),
            _ => format!("cannot read {shown}: {e}"),
        })?;
        Self::from_json(&text).map_err(|e| format!("{shown}: {e}"))
    }

    /// The scene this snapshot holds, ready to step on: rebuilt from its name and
    /// parameters, then given the saved world and the scene's own state. Nothing is
    /// changed if any part is refused.
    pub fn restore(&self) -> Result<Box<dyn Scene>, String> {
        self.restore_with_entry().map(|(_, scene)| scene)
    }

    /// [`Snapshot::restore`], with the registry entry of the scene (for a scene file,
    /// the entry its embedded text made).
    pub fn restore_with_entry(&self) -> Result<(SceneEntry, Box<dyn Scene>), String> {
        // The parts' errors can quote the file's text (a name, a kind): one line.
        self.restore_checked().map_err(|e| messages::one_line(&e))
    }

    fn restore_checked(&self) -> Result<(SceneEntry, Box<dyn Scene>), String> {
        let entry = match &self.scene_file {
            Some(file) => {
                let shown = file.path.as_deref().map_or_else(
                    || format!("{} (in the snapshot)", messages::quote(&self.scene)),
                    |path| messages::path(Path::new(path)),
                );
                let entry = super::file::load_text(
                    &file.text,
                    &shown,
                    file.path.as_ref().map(std::path::PathBuf::from),
                )
                .map_err(|e| format!("scene_file: {e}"))?;
                if entry.info().name != self.scene {
                    return Err(format!(
                        "scene: the snapshot names scene '{}' but its scene file makes '{}'",
                        messages::quote(&self.scene),
                        messages::quote(&entry.info().name)
                    ));
                }
                entry
            }
            None => super::find(&self.scene)?.clone(),
        };
        let mut values = ParamValues::defaults(&entry.info().params);
        for (name, value) in &self.params {
            values.set(name, *value).map_err(|e| format!("params: {e}"))?;
        }
        if !crate::physics::error::time_step_in_range(self.dt) {
            return Err(format!(
                "dt = {} s is out of range; valid range: {:e} to {} s",
                crate::physics::error::Shown::shown(&self.dt),
                crate::physics::error::MIN_TIME_STEP,
                crate::physics::error::MAX_TIME_STEP
            ));
        }
        let world = World::from_state(self.world.clone()).map_err(|e| format!("world: {e}"))?;
        if let Some(what) = world.first_non_finite(&mut Vec::new()) {
            return Err(format!("world: {what} is not a finite number"));
        }
        if let Some(saved) = &self.hash {
            let hash = hash_text(world.state_hash());
            if *saved != hash {
                return Err(format!(
                    "the world does not match its hash ({} saved, {hash} read): the file was changed \
                     or damaged (delete the \"hash\" field to load a file edited by hand)",
                    messages::quote(saved)
                ));
            }
        }
        let mut scene = super::create_entry(&entry, values).map_err(|e| format!("scene_file: {e}"))?;
        // The scene's own objects (the bob, the bridge's deck) must be the world's: the
        // scene's rules act on them by id.
        let built = &scene.world().particles;
        for (i, id) in built.ids().iter().enumerate() {
            if !scene.keeps_particle(*id) {
                continue;
            }
            let movable = built.inverse_masses()[i] > 0.0;
            let loaded = world.particles.index(*id).map(|j| world.particles.inverse_masses()[j] > 0.0);
            if loaded != Some(movable) {
                let what = if movable { "movable" } else { "fixed" };
                return Err(format!("world: the scene's particle {} ({what}) is missing or changed", id.0));
            }
        }
        *scene.world_mut() = world;
        scene.restore_state(&self.scene_state).map_err(|e| format!("scene_state: {e}"))?;
        Ok((entry, scene))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file from before version 2 sealed its world only: it still loads, its
    /// checksum checked as it was written.
    #[test]
    fn a_version_1_file_is_read_with_its_world_only_checksum() {
        let scene = super::super::build("pendulum", &[]).unwrap();
        let mut old = Snapshot::of(scene.as_ref(), 1.0 / 240.0).unwrap();
        old.version = 1;
        old.checksum = Some(checksum(&old));
        assert_ne!(old.checksum, Snapshot::of(scene.as_ref(), 1.0 / 240.0).unwrap().checksum);
        let read = Snapshot::from_json(&old.to_json()).unwrap();
        assert_eq!((read.version, read.checksum.as_ref()), (1, old.checksum.as_ref()));
        assert!(read.restore().is_ok());
        let mut moved = old.clone();
        moved.world.time += 1.0;
        let error = Snapshot::from_json(&moved.to_json()).unwrap_err();
        assert!(error.starts_with("the world does not match its checksum"), "{error}");
        let too_old = old.to_json().replacen("\"version\": 1", "\"version\": 0", 1);
        let error = Snapshot::from_json(&too_old).unwrap_err();
        assert_eq!(error, "snapshot version 0 is not supported (this one reads versions 1 to 2)");
    }
}
