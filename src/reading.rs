//! Reading a user's file without trusting it: the one door every scene file, snapshot
//! and settings file comes in by.
//!
//! A path can name anything: `/dev/zero` (endless), a FIFO (blocks until a writer
//! comes), a directory, a symlink to either, or a regular file that grows while it is
//! read. So the kind is checked first, without opening it (opening a FIFO blocks), and
//! the read stops one byte past the limit whatever the file's reported size.

use std::io::Read;
use std::path::Path;

use crate::messages;

/// Why a file could not be read, in words for a one-line message (the path is not in
/// it: the caller names the file its own way).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ReadError {
    /// No file there.
    Missing,
    /// A directory, a device, a FIFO or a socket: not a file to read.
    NotAFile(&'static str),
    /// Longer than the limit (bytes).
    TooLarge { limit: u64 },
    /// The OS refused (permission, I/O error), in its words without the error number.
    Io(String),
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Missing => write!(f, "no such file"),
            Self::NotAFile(kind) => write!(f, "it is {kind}, not a regular file"),
            Self::TooLarge { limit } => write!(f, "it is larger than the limit of {}", bytes(*limit)),
            Self::Io(reason) => write!(f, "{reason}"),
        }
    }
}

/// `limit` in the unit a person reads (4 MB, 512 MB, 64 KB).
#[must_use]
pub fn bytes(limit: u64) -> String {
    const MB: u64 = 1 << 20;
    const KB: u64 = 1 << 10;
    if limit >= MB && limit.is_multiple_of(MB) {
        format!("{} MB", limit / MB)
    } else if limit >= KB && limit.is_multiple_of(KB) {
        format!("{} KB", limit / KB)
    } else {
        format!("{limit} bytes")
    }
}

/// What kind of thing `metadata` describes, if it is not a regular file (also what
/// [`crate::writing`] refuses to write over).
pub(crate) fn not_a_file(metadata: &std::fs::Metadata) -> Option<&'static str> {
    let kind = metadata.file_type();
    if kind.is_file() {
        return None;
    }
    if kind.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return Some("a FIFO (named pipe)");
        }
        if kind.is_char_device() || kind.is_block_device() {
            return Some("a device");
        }
        if kind.is_socket() {
            return Some("a socket");
        }
    }
    Some("not a regular file")
}

/// The bytes of the regular file at `path`, at most `limit` of them. A device, FIFO,
/// socket or directory is refused before it is opened; a file longer than `limit`
/// (by its metadata, or by what reading finds, for one that grows) is refused after
/// reading at most `limit + 1` bytes.
pub fn read_limited(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    let io = |error: std::io::Error| match error.kind() {
        std::io::ErrorKind::NotFound => ReadError::Missing,
        _ => ReadError::Io(messages::io_reason(&error)),
    };
    let metadata = std::fs::metadata(path).map_err(io)?;
    if let Some(kind) = not_a_file(&metadata) {
        return Err(ReadError::NotAFile(kind));
    }
    if metadata.len() > limit {
        return Err(ReadError::TooLarge { limit });
    }
    let file = std::fs::File::open(path).map_err(io)?;
    // The file may have been swapped since the check: look at what was opened.
    if let Some(kind) = file.metadata().ok().as_ref().and_then(not_a_file) {
        return Err(ReadError::NotAFile(kind));
    }
    let mut bytes = Vec::with_capacity(usize::try_from(metadata.len()).unwrap_or(0).min(1 << 20));
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(ReadError::TooLarge { limit });
    }
    Ok(bytes)
}

/// [`read_limited`] as UTF-8 text.
pub fn read_text_limited(path: &Path, limit: u64) -> Result<String, ReadError> {
    let bytes = read_limited(path, limit)?;
    String::from_utf8(bytes).map_err(|_| ReadError::Io("it is not UTF-8 text".into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_and_directories_are_refused_without_reading() {
        assert_eq!(read_limited(Path::new("/dev/zero"), 10), Err(ReadError::NotAFile("a device")));
        assert_eq!(read_limited(Path::new("/"), 10), Err(ReadError::NotAFile("a directory")));
        assert_eq!(read_limited(Path::new("/nonexistent/x"), 10), Err(ReadError::Missing));
    }

    #[test]
    fn the_limit_is_kept() {
        let dir = std::env::temp_dir().join(format!("particle-lab-reading-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("eleven");
        std::fs::write(&file, b"hello world").unwrap();
        assert_eq!(read_limited(&file, 11).unwrap(), b"hello world");
        assert_eq!(read_limited(&file, 10), Err(ReadError::TooLarge { limit: 10 }));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn sizes_read_as_a_person_says_them() {
        assert_eq!(bytes(4 << 20), "4 MB");
        assert_eq!(bytes(64 << 10), "64 KB");
        assert_eq!(bytes(1000), "1000 bytes");
    }
}
