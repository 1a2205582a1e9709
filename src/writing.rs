//! Writing a user's file without harming what is there: the one door every snapshot,
//! settings file, CSV, PNG, GIF and APNG goes out by.
//!
//! A path can name anything: a regular file, a symlink (to a file kept elsewhere, or to
//! one not made yet), a device (`/dev/null`), a FIFO, a socket or a directory. So the
//! chain of links is followed first, without opening anything, to the place the bytes
//! belong:
//!
//! - a regular file, or nothing yet: the bytes go to a temporary file beside it
//!   (`name.part`), created exclusively (never through a link, never over another
//!   write's) and locked while written, which is renamed over it when complete, so a
//!   stopped write leaves the old file; an existing file keeps its permissions (and,
//!   where allowed, its owner). A read-only file is refused. A `.part` file that no
//!   write holds is what a stopped one left, and is replaced;
//! - through a symlink: the file at the end of the chain is written so, and the links
//!   stay links;
//! - a device, FIFO, socket or directory, directly or through links: refused before
//!   anything is created, the node untouched.
//!
//! The browser has no files: there the OS calls below fail with a one-line reason, and
//! the page writes its local storage and downloads instead (`settings/medium.rs`,
//! `ui/page.rs`).

use std::fs::{File, Metadata};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::messages;
use crate::reading::not_a_file;

/// Most links followed from the path given to the file (Linux's own limit).
const MAX_LINKS: usize = 40;
/// Temporary names tried beside a file (`x.part`, `x.1.part`, ...) before giving up.
const MAX_TEMPORARY_NAMES: usize = 100;

/// Why a file could not be written, in words for a one-line message (the path is not in
/// it: the caller names the file its own way, as with [`crate::reading::ReadError`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum WriteError {
    /// A directory, a device, a FIFO or a socket (or a link to one): not a file to write.
    NotAFile(&'static str),
    /// The OS refused (permission, a full disk, a missing directory), in its words
    /// without the error number.
    Io(String),
}

impl std::fmt::Display for WriteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotAFile(kind) => write!(f, "it is {kind}, not a regular file"),
            Self::Io(reason) => write!(f, "{reason}"),
        }
    }
}

impl From<std::io::Error> for WriteError {
    fn from(error: std::io::Error) -> Self {
        Self::Io(messages::io_reason(&error))
    }
}

/// Where writing `path` puts the bytes: the end of its chain of symlinks, and what is
/// there now (none for a file not made yet, a dangling link's target included). Only
/// looks: nothing is opened or created.
fn resolve(path: &Path) -> Result<(PathBuf, Option<Metadata>), WriteError> {
    let mut current = path.to_path_buf();
    for _ in 0..=MAX_LINKS {
        match std::fs::symlink_metadata(&current) {
            Ok(metadata) if metadata.file_type().is_symlink() => {
                let next = std::fs::read_link(&current)?;
                // A relative target is read from the link's own directory.
                current = match current.parent() {
                    Some(directory) => directory.join(next),
                    None => next,
                };
            }
            Ok(metadata) => {
                return match not_a_file(&metadata) {
                    Some(kind) => Err(WriteError::NotAFile(kind)),
                    None => Ok((current, Some(metadata))),
                };
            }
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => return Ok((current, None)),
            Err(error) => return Err(error.into()),
        }
    }
    Err(WriteError::Io("its symbolic links go round in a loop".into()))
}

/// The file writing `path` would replace or create (the end of its chain of links),
/// or why it would be refused: a device, FIFO, socket or directory. Only looks.
pub fn target(path: &Path) -> Result<PathBuf, WriteError> {
    resolve(path).map(|(target, _)| target)
}

/// Writes `bytes` to `path`: to the regular file there (or at the end of its links),
/// replaced whole or not at all; a device, FIFO, socket or directory is refused.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(bytes)?;
    file.commit()
}

/// A file being written at a temporary name beside its place: [`Pending::commit`] renames
/// it into place; dropped before that, the temporary file is removed.
#[derive(Debug)]
pub struct Pending {
    /// The path as given, followed again before the rename.
    path: PathBuf,
    /// Where the bytes go: the end of `path`'s links.
    target: PathBuf,
    temporary: PathBuf,
    /// The temporary file held open and locked until it is renamed or removed, so no
    /// other write takes it for a stopped one's leftover.
    _lock: Option<File>,
    committed: bool,
}

impl Pending {
    /// Puts the complete temporary file in place of its target. The path is followed
    /// again first: if it now leads elsewhere, or to a FIFO or a device, nothing is
    /// replaced.
    pub fn commit(mut self) -> Result<(), WriteError> {
        let (target, _) = resolve(&self.path)?;
        if target != self.target {
            return Err(WriteError::Io("its links were changed while it was written".into()));
        }
        std::fs::rename(&self.temporary, &self.target)?;
        self.committed = true;
        Ok(())
    }

    /// The temporary file's path (for tests: it lies beside the target).
    #[must_use]
    pub fn temporary(&self) -> &Path {
        &self.temporary
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.temporary);
        }
    }
}

/// A buffered writer over a temporary file beside `path`'s target, for outputs written
/// piece by piece (PNGs, recordings): [`AtomicFile::commit`] puts it in place; dropped
/// before that, nothing is left and what was there is untouched.
#[derive(Debug)]
pub struct AtomicFile {
    writer: BufWriter<File>,
    pending: Pending,
}

impl AtomicFile {
    /// Checks `path` (following its links) and creates the temporary file beside its
    /// target; a device, FIFO, socket or directory is refused before anything is made.
    pub fn create(path: &Path) -> Result<Self, WriteError> {
        let (target, existing) = resolve(path)?;
        if existing.as_ref().is_some_and(|m| m.permissions().readonly()) {
            return Err(WriteError::Io("it is read-only".into()));
        }
        let (temporary, file) = create_temporary(&target, existing.as_ref())?;
        let lock = file.try_clone().ok();
        let pending = Pending { path: path.to_path_buf(), target, temporary, _lock: lock, committed: false };
        Ok(Self { writer: BufWriter::new(file), pending })
    }

    /// Writes out what is buffered and puts the file in place.
    pub fn commit(self) -> Result<(), WriteError> {
        let Self { writer, pending } = self;
        writer.into_inner().map_err(|e| WriteError::from(e.into_error()))?;
        pending.commit()
    }

    /// The writer and the rename apart, for an encoder that keeps its writer to the end
    /// (a PNG's `finish` flushes and drops it): commit the [`Pending`] once the encoder
    /// has flushed.
    #[must_use]
    pub fn split(self) -> (BufWriter<File>, Pending) {
        (self.writer, self.pending)
    }

    /// The temporary file's path.
    #[must_use]
    pub fn temporary(&self) -> &Path {
        self.pending.temporary()
    }
}

impl Write for AtomicFile {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.writer.write(bytes)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.writer.flush()
    }
}

/// A new file beside `target` (`name.part`, or `name.1.part`, ... if that is taken),
/// created exclusively and locked while it is written, with the permissions and owner
/// of `existing` if it is given. A `.part` file there that no write holds locked is
/// what a stopped one left (Ctrl-C, a crash): it is removed and its name taken.
fn create_temporary(target: &Path, existing: Option<&Metadata>) -> Result<(PathBuf, File), WriteError> {
    let Some(name) = target.file_name() else {
        return Err(WriteError::Io("the path names no file".into()));
    };
    let mut attempt = 0;
    let mut cleared = false;
    while attempt < MAX_TEMPORARY_NAMES {
        let mut temporary = name.to_os_string();
        if attempt > 0 {
            temporary.push(format!(".{attempt}"));
        }
        temporary.push(".part");
        let temporary = target.with_file_name(temporary);
        let mut options = std::fs::OpenOptions::new();
        options.write(true).create_new(true);
        #[cfg(unix)]
        if let Some(metadata) = existing {
            use std::os::unix::fs::{OpenOptionsExt, PermissionsExt};
            options.mode(metadata.permissions().mode() & 0o777);
        }
        match options.open(&temporary) {
            Ok(file) => {
                let _ = file.try_lock();
                keep_owner_and_mode(&file, existing);
                return Ok((temporary, file));
            }
            // Taken: by a leftover (cleared, and the name tried once more) or by a
            // write under way, or something else (the next name).
            Err(error) if error.kind() == std::io::ErrorKind::AlreadyExists => {
                if !cleared && clear_left_over(&temporary) {
                    cleared = true;
                } else {
                    attempt += 1;
                    cleared = false;
                }
            }
            // A missing directory says "no such file", as reading and the OS do.
            Err(error) => return Err(error.into()),
        }
    }
    Err(WriteError::Io(format!("{MAX_TEMPORARY_NAMES} temporary names beside it are all taken")))
}

/// Removes `temporary` if a stopped write left it: a regular file (not a link, not a
/// FIFO) that no write under way holds locked. True if it was removed.
fn clear_left_over(temporary: &Path) -> bool {
    let is_file = |m: &Metadata| m.file_type().is_file();
    let Ok(before) = std::fs::symlink_metadata(temporary) else { return false };
    if !is_file(&before) {
        return false;
    }
    let Ok(file) = File::open(temporary) else { return false };
    if file.try_lock().is_err() {
        return false;
    }
    // Still the file that was looked at and locked, not one made since.
    #[cfg(unix)]
    let same = |m: &Metadata| {
        use std::os::unix::fs::MetadataExt;
        m.dev() == before.dev() && m.ino() == before.ino()
    };
    #[cfg(not(unix))]
    let same = is_file;
    let unchanged = file.metadata().is_ok_and(|m| same(&m))
        && std::fs::symlink_metadata(temporary).is_ok_and(|m| same(&m));
    unchanged && std::fs::remove_file(temporary).is_ok()
}

/// Gives the new file the owner and permissions of the one it will replace, where the
/// OS allows (another user's owner only for root; a failure leaves ours).
fn keep_owner_and_mode(file: &File, existing: Option<&Metadata>) {
    let Some(metadata) = existing else { return };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let _ = std::os::unix::fs::fchown(file, Some(metadata.uid()), Some(metadata.gid()));
    }
    let _ = file.set_permissions(metadata.permissions());
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("particle-lab-writing-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn devices_and_directories_are_refused_by_looking_only() {
        assert_eq!(target(Path::new("/dev/null")), Err(WriteError::NotAFile("a device")));
        assert_eq!(target(Path::new("/")), Err(WriteError::NotAFile("a directory")));
        // Refused before a temporary file is made beside it.
        let error = AtomicFile::create(Path::new("/dev/null")).unwrap_err();
        assert_eq!(error.to_string(), "it is a device, not a regular file");
        assert!(!Path::new("/dev/null.part").exists());
    }

    #[cfg(unix)]
    #[test]
    fn links_are_followed_from_their_own_directory_and_loops_are_refused() {
        let dir = scratch("links");
        std::fs::create_dir(dir.join("kept")).unwrap();
        std::os::unix::fs::symlink("kept/file", dir.join("first")).unwrap();
        std::os::unix::fs::symlink("../first", dir.join("kept/second")).unwrap();
        // kept/second -> kept/../first -> (from kept/..) kept/file
        assert_eq!(target(&dir.join("kept/second")).unwrap(), dir.join("kept/../kept/file"));
        std::os::unix::fs::symlink("round", dir.join("round")).unwrap();
        let error = target(&dir.join("round")).unwrap_err();
        assert_eq!(error.to_string(), "its symbolic links go round in a loop");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_temporary_file_never_replaces_one_being_written_but_clears_a_left_over() {
        let dir = scratch("exclusive");
        let out = dir.join("run.gif");
        std::fs::write(dir.join("run.gif.part"), "someone else's").unwrap();
        // Held by a write under way.
        let other = File::open(dir.join("run.gif.part")).unwrap();
        other.try_lock().unwrap();
        let mut file = AtomicFile::create(&out).unwrap();
        assert_eq!(file.temporary(), dir.join("run.gif.1.part"));
        file.write_all(b"whole").unwrap();
        file.commit().unwrap();
        assert_eq!(std::fs::read(dir.join("run.gif.part")).unwrap(), b"someone else's");
        assert_eq!(std::fs::read(&out).unwrap(), b"whole");
        assert!(!dir.join("run.gif.1.part").exists());
        // Unlocked, it is what a stopped write left: its name is taken and it is gone.
        drop(other);
        let mut file = AtomicFile::create(&out).unwrap();
        assert_eq!(file.temporary(), dir.join("run.gif.part"));
        file.write_all(b"again").unwrap();
        file.commit().unwrap();
        assert!(!dir.join("run.gif.part").exists());
        assert_eq!(std::fs::read(&out).unwrap(), b"again");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_uncommitted_file_leaves_nothing_and_the_old_one_whole() {
        let dir = scratch("dropped");
        let out = dir.join("snapshot.json");
        std::fs::write(&out, "old").unwrap();
        let (mut writer, pending) = AtomicFile::create(&out).unwrap().split();
        writer.write_all(b"half of a new one").unwrap();
        writer.flush().unwrap();
        assert!(pending.temporary().exists());
        drop(pending);
        assert!(!dir.join("snapshot.json.part").exists());
        assert_eq!(std::fs::read(&out).unwrap(), b"old");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_file_in_a_missing_directory_says_so() {
        let error = write_atomic(Path::new("/nonexistent/particle-lab/x.csv"), b"t\n").unwrap_err();
        assert_eq!(error.to_string(), "no such file");
        assert_eq!(write_atomic(Path::new(""), b"").unwrap_err().to_string(), "the path names no file");
    }
}
