//! Where the settings text lives: a file on the desktop; in a browser, the page's
//! `localStorage`, under the same path as its key (`particle-lab/settings.json`). The
//! store reads, writes and sets aside through these three calls and nothing else, so
//! what it checks and says is the same in both.

use std::path::Path;

use crate::reading::ReadError;

/// The text at `path`, at most `limit` bytes of it.
#[cfg(not(target_arch = "wasm32"))]
pub fn read(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    crate::reading::read_limited(path, limit)
}

/// Writes `text` to `path`: beside it first and renamed into it, so a crash mid-write
/// leaves the old one. A settings file that is a link (to a dotfile kept elsewhere)
/// stays a link and the file it names is written; a device or FIFO is refused.
#[cfg(not(target_arch = "wasm32"))]
pub fn write(path: &Path, text: &str) -> Result<(), String> {
    if let Some(directory) = path.parent() {
        std::fs::create_dir_all(directory).map_err(|e| crate::messages::io_reason(&e))?;
    }
    crate::writing::write_atomic(path, text.as_bytes()).map_err(|e| e.to_string())
}

/// Moves what is at `path` to `aside`, replacing what was there. A link to a regular
/// file (a dotfile kept elsewhere) is not moved: the file's text is copied to `aside`
/// and the link left in place, so the next [`write`] goes through it to the same file
/// and nothing becomes a regular file where a link was. Anything else (a regular file,
/// a FIFO, a directory, a link to a device) is renamed, the node itself untouched.
#[cfg(not(target_arch = "wasm32"))]
pub fn set_aside(path: &Path, aside: &Path) -> Result<(), String> {
    let reason = |e: std::io::Error| crate::messages::io_reason(&e);
    let linked = std::fs::symlink_metadata(path).map_err(reason)?.file_type().is_symlink();
    let kept_file = match crate::writing::target(path) {
        Ok(target) if linked => std::fs::metadata(&target).is_ok_and(|m| m.is_file()).then_some(target),
        _ => None,
    };
    let Some(target) = kept_file else {
        return std::fs::rename(path, aside).map_err(reason);
    };
    let mut copy = crate::writing::AtomicFile::create(aside).map_err(|e| e.to_string())?;
    let mut source = std::fs::File::open(&target).map_err(reason)?;
    std::io::copy(&mut source, &mut copy).map_err(reason)?;
    copy.commit().map_err(|e| e.to_string())
}

#[cfg(target_arch = "wasm32")]
fn storage() -> Result<web_sys::Storage, String> {
    web_sys::window()
        .and_then(|w| w.local_storage().ok().flatten())
        .ok_or_else(|| "this browser keeps no local storage for the page".to_string())
}

#[cfg(target_arch = "wasm32")]
fn key(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

#[cfg(target_arch = "wasm32")]
pub fn read(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    let storage = storage().map_err(ReadError::Io)?;
    match storage.get_item(&key(path)) {
        Ok(Some(text)) if text.len() as u64 > limit => Err(ReadError::TooLarge { limit }),
        Ok(Some(text)) => Ok(text.into_bytes()),
        Ok(None) => Err(ReadError::Missing),
        Err(_) => Err(ReadError::Io("the browser refused to read local storage".into())),
    }
}

#[cfg(target_arch = "wasm32")]
pub fn write(path: &Path, text: &str) -> Result<(), String> {
    storage()?
        .set_item(&key(path), text)
        .map_err(|_| "the browser refused to write local storage (is it full?)".to_string())
}

#[cfg(target_arch = "wasm32")]
pub fn set_aside(path: &Path, aside: &Path) -> Result<(), String> {
    let storage = storage()?;
    let text = storage.get_item(&key(path)).ok().flatten().unwrap_or_default();
    storage
        .set_item(&key(aside), &text)
        .map_err(|_| "the browser refused to write local storage".to_string())?;
    storage.remove_item(&key(path)).map_err(|_| "the browser refused to write local storage".to_string())
}
