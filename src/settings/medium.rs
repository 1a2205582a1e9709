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
/// leaves the old one.
#[cfg(not(target_arch = "wasm32"))]
pub fn write(path: &Path, text: &str) -> Result<(), String> {
    let write = || -> std::io::Result<()> {
        if let Some(directory) = path.parent() {
            std::fs::create_dir_all(directory)?;
        }
        let mut name = path.file_name().unwrap_or_default().to_os_string();
        name.push(".tmp");
        let temporary = path.with_file_name(name);
        std::fs::write(&temporary, text)?;
        std::fs::rename(&temporary, path)
    };
    write().map_err(|e| crate::messages::io_reason(&e))
}

/// Moves what is at `path` to `aside`, replacing what was there.
#[cfg(not(target_arch = "wasm32"))]
pub fn set_aside(path: &Path, aside: &Path) -> Result<(), String> {
    std::fs::rename(path, aside).map_err(|e| crate::messages::io_reason(&e))
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
