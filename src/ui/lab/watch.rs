//! Watching the open scene file for changes, for hot reload: the folder is watched
//! and a change counts once the file has stayed unchanged a moment.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, channel};
use std::time::Duration;

use web_time::Instant;

use notify::{RecursiveMode, Watcher};

/// How long the file must stay unchanged before it is read: editors save in several
/// writes (truncate, write, rename), and reading between them would see half a file.
const SETTLE: Duration = Duration::from_millis(150);

/// Watches the open scene file's folder for changes to it.
pub struct Watch {
    /// The file.
    pub(super) path: PathBuf,
    /// Kept alive: dropping it stops the watching.
    _watcher: notify::RecommendedWatcher,
    events: Receiver<notify::Result<notify::Event>>,
    /// When the file last changed, if it has since the last reload.
    changed: Option<Instant>,
}

impl Watch {
    /// Starts watching `path`. The folder is watched rather than the file, since an
    /// editor that saves by renaming a new file over the old one would end a watch on
    /// the file itself.
    pub fn new(path: &Path) -> Result<Self, String> {
        let (sender, events) = channel();
        let mut watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
            // The window may be gone; then nobody needs the event.
            let _ = sender.send(event);
        })
        .map_err(|e| format!("cannot watch {} for changes: {e}", path.display()))?;
        let folder = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
            _ => PathBuf::from("."),
        };
        watcher
            .watch(&folder, RecursiveMode::NonRecursive)
            .map_err(|e| format!("cannot watch {} for changes: {e}", path.display()))?;
        Ok(Self { path: path.to_path_buf(), _watcher: watcher, events, changed: None })
    }

    /// True once the file has changed and then stayed unchanged for [`SETTLE`].
    pub(super) fn settled_change(&mut self) -> bool {
        let name = self.path.file_name();
        while let Ok(event) = self.events.try_recv() {
            let Ok(event) = event else { continue };
            let touches = event.paths.iter().any(|p| p.file_name() == name);
            if touches && !event.kind.is_access() {
                self.changed = Some(Instant::now());
            }
        }
        match self.changed {
            Some(at) if at.elapsed() >= SETTLE => {
                self.changed = None;
                true
            }
            _ => false,
        }
    }
}
