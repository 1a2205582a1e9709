//! Snapshots in the lab: save and load the running scene (File menu, F5 and F9,
//! `--from`).

use super::model::Lab;
use crate::render::OrbitCamera;
use crate::scenes::snapshot::Snapshot;
use crate::scenes::{self, Scene, SceneEntry};

impl Lab {
    /// A lab on the scene a snapshot holds, at the step it was saved, framed by the
    /// scene's camera hint.
    pub fn from_snapshot(snapshot: &Snapshot) -> Result<Self, String> {
        let (entry, scene) = snapshot.restore_with_entry()?;
        let mut lab = Self::from_entry(&entry, &[], snapshot.world.solver())?;
        lab.install(entry, scene, snapshot.dt);
        lab.camera = OrbitCamera::framing(lab.scene.as_ref());
        Ok(lab)
    }

    /// The running scene as a snapshot.
    pub fn snapshot(&self) -> Result<Snapshot, String> {
        Snapshot::of(self.scene.as_ref(), self.dt())
    }

    /// Replaces the running scene with a snapshot's, keeping the camera; on an error
    /// nothing changes. The plots and trails start again from the loaded state, and a
    /// Compare copy stops (it would have to run from the scene's start to catch up).
    pub fn load_snapshot(&mut self, snapshot: &Snapshot) -> Result<(), String> {
        let (entry, scene) = snapshot.restore_with_entry()?;
        self.install(entry, scene, snapshot.dt);
        Ok(())
    }

    /// Makes a restored scene the running one, at time step `dt`.
    pub(super) fn install(&mut self, entry: SceneEntry, scene: Box<dyn Scene>, dt: f32) {
        self.stop_compare();
        self.entry = entry;
        self.scene = scene;
        self.solver = *self.scene.world().solver();
        self.set_dt(dt);
        self.apply_scene_view();
        self.restart();
        self.follow_crowd();
    }

    /// Writes a snapshot to `path`; the status line says where, or why not.
    pub fn save_snapshot_to(&mut self, path: &std::path::Path) {
        self.status = match self.snapshot().and_then(|snapshot| snapshot.save(path)) {
            Ok(()) => {
                let world = self.scene.world();
                let hash = scenes::snapshot::hash_text(world.state_hash());
                log::info!("saved snapshot {} at step {}, state hash {hash}", path.display(), world.steps());
                format!("Saved {} (step {}, t = {:.3} s)", path.display(), world.steps(), world.time())
            }
            Err(error) => error,
        };
    }

    /// Loads a snapshot's text that came from elsewhere than a path (a browser's file
    /// input), named `name` in messages; a bad one changes nothing, as
    /// [`Self::load_snapshot_from`].
    pub fn load_snapshot_text(&mut self, name: &str, text: &str) {
        let name = crate::messages::one_line(name);
        let loaded = Snapshot::from_json(text).and_then(|snapshot| self.load_snapshot(&snapshot));
        self.status = match loaded {
            Ok(()) => {
                let world = self.scene.world();
                format!("Loaded {name} (step {}, t = {:.3} s)", world.steps(), world.time())
            }
            Err(error) => format!("{name}: {}", crate::messages::one_line(&error)),
        };
        log::info!("{}", self.status);
    }

    /// The snapshot of now as its file's name and text, for a browser to download.
    pub fn snapshot_download(&self) -> Result<(String, String), String> {
        let snapshot = self.snapshot()?;
        let world = self.scene.world();
        Ok((
            format!("particle-lab-{}-step{}.json", self.entry.info().name, world.steps()),
            snapshot.to_json(),
        ))
    }

    /// Loads the snapshot at `path`; a bad file leaves the running scene as it was
    /// and the status line says what is wrong.
    pub fn load_snapshot_from(&mut self, path: &std::path::Path) {
        let loaded = Snapshot::load(path).and_then(|snapshot| {
            self.load_snapshot(&snapshot).map_err(|e| format!("{}: {e}", path.display()))
        });
        match loaded {
            Ok(()) => {
                let world = self.scene.world();
                log::info!("loaded snapshot {} at step {}", path.display(), world.steps());
                self.status =
                    format!("Loaded {} (step {}, t = {:.3} s)", path.display(), world.steps(), world.time());
            }
            Err(error) => {
                log::warn!("{error}");
                self.status = error;
            }
        }
    }

    /// F5: keeps the current state to go back to with F9.
    pub fn quick_save(&mut self) {
        match self.snapshot() {
            Ok(snapshot) => {
                self.status =
                    format!("Quick save at t = {:.3} s: F9 goes back to it", self.scene.world().time());
                self.quick_save = Some(snapshot);
            }
            Err(error) => self.status = error,
        }
    }

    /// F9: goes back to the state F5 kept, keeping the camera.
    pub fn quick_load(&mut self) {
        let Some(snapshot) = self.quick_save.take() else {
            self.status = "Nothing quick-saved yet: F5 saves, F9 goes back".into();
            return;
        };
        let result = self.load_snapshot(&snapshot);
        self.status = match result {
            Ok(()) => format!("Back to the quick save at t = {:.3} s", self.scene.world().time()),
            Err(error) => error,
        };
        self.quick_save = Some(snapshot);
    }

    /// The state hash of the running world, as the panel shows it.
    #[must_use]
    pub fn state_hash(&self) -> String {
        scenes::snapshot::hash_text(self.scene.world().state_hash())
    }
}
