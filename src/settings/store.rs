//! The settings file on disk: where it is, reading it (a bad one is set aside),
//! writing it when it changed.

use std::path::{Path, PathBuf};
use std::time::Duration;

use web_time::Instant;

use super::format::Settings;
use super::medium;

/// The settings file's name inside the config directory.
pub const FILE_NAME: &str = "settings.json";
/// Largest settings file read (bytes): a real one is about 1 KB.
pub const MAX_FILE_BYTES: u64 = 1 << 20;
/// How often the window checks whether the settings changed and writes them if so.
pub const AUTOSAVE_INTERVAL: Duration = Duration::from_secs(2);

/// What reading the settings file found.
#[derive(Clone, Debug, PartialEq)]
pub enum Loaded {
    /// No file (a first launch), or no config directory to look in.
    Missing,
    /// A valid file.
    Restored(Settings),
    /// A file that could not be used: set aside, with the one warning line to print.
    Unusable {
        /// `particle-lab: ...`, saying what was wrong and where the file went.
        warning: String,
    },
}

/// The settings file: where it is, and what was last written to it.
#[derive(Debug)]
pub struct Store {
    path: Option<PathBuf>,
    written: Option<Settings>,
    checked: Instant,
    save_failed: bool,
}

impl Store {
    /// The file in the platform's config directory (on Linux `$XDG_CONFIG_HOME`, else
    /// `~/.config`, then `particle-lab/settings.json`); none if there is no home.
    /// In a browser: the page's local storage, under `particle-lab/settings.json`.
    #[must_use]
    pub fn from_platform() -> Self {
        #[cfg(target_arch = "wasm32")]
        return Self::with_path(Some(Path::new("particle-lab").join(FILE_NAME)));
        #[cfg(not(target_arch = "wasm32"))]
        {
            let dirs = directories::ProjectDirs::from("", "", "particle-lab");
            Self::with_path(dirs.map(|dirs| dirs.config_dir().join(FILE_NAME)))
        }
    }

    /// The file `FILE_NAME` in `directory` (for tests).
    #[must_use]
    pub fn in_dir(directory: &Path) -> Self {
        Self::with_path(Some(directory.join(FILE_NAME)))
    }

    fn with_path(path: Option<PathBuf>) -> Self {
        Self { path, written: None, checked: Instant::now(), save_failed: false }
    }

    /// Where the settings live, if anywhere.
    #[must_use]
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// Where an unusable file is moved: `settings.json.bad` beside it.
    #[must_use]
    pub fn aside_path(path: &Path) -> PathBuf {
        let mut name = path.file_name().unwrap_or_default().to_os_string();
        name.push(".bad");
        path.with_file_name(name)
    }

    /// Reads the file, at most [`MAX_FILE_BYTES`] of it, refusing a directory, device
    /// or FIFO without opening it (so nothing blocks or reads on forever). One that
    /// cannot be used is moved aside (replacing an older one there; a link is moved, not
    /// what it points to) and the warning says so; nothing here panics or exits.
    pub fn load(&mut self) -> Loaded {
        use crate::reading::ReadError;
        let Some(path) = &self.path else { return Loaded::Missing };
        let shown = crate::messages::path(path);
        let parsed = match medium::read(path, MAX_FILE_BYTES) {
            Ok(bytes) => std::str::from_utf8(&bytes)
                .map_err(|e| format!("not UTF-8 text: {e}"))
                .and_then(Settings::parse),
            Err(ReadError::Missing) => return Loaded::Missing,
            // The OS refused (permission): the file may be fine; it is left where it is.
            Err(ReadError::Io(reason)) => {
                return Loaded::Unusable {
                    warning: format!(
                        "particle-lab: cannot read the settings file {shown}: {reason}; starting from the defaults"
                    ),
                };
            }
            Err(error @ (ReadError::NotAFile(_) | ReadError::TooLarge { .. })) => Err(error.to_string()),
        };
        match parsed {
            Ok(settings) => {
                self.written = Some(settings.clone());
                Loaded::Restored(settings)
            }
            Err(reason) => {
                let aside = Self::aside_path(path);
                let whereto = match medium::set_aside(path, &aside) {
                    Ok(()) => format!("moved it to {}", crate::messages::path(&aside)),
                    Err(reason) => format!("could not move it aside ({reason})"),
                };
                let reason = crate::messages::one_line(&reason);
                Loaded::Unusable {
                    warning: format!(
                        "particle-lab: the settings file {shown} is unusable ({reason}); {whereto} and started from \
                         the defaults"
                    ),
                }
            }
        }
    }

    /// Writes `settings` unless the file already holds them; true if it wrote. The file
    /// is written beside its place and renamed into it, so a crash mid-write leaves the
    /// old one.
    pub fn save(&mut self, settings: &Settings) -> Result<bool, String> {
        let Some(path) = &self.path else { return Ok(false) };
        if self.written.as_ref() == Some(settings) {
            return Ok(false);
        }
        medium::write(path, &settings.to_text()).map_err(|reason| {
            format!("cannot save the settings to {}: {reason}", crate::messages::path(path))
        })?;
        self.written = Some(settings.clone());
        Ok(true)
    }

    /// Saves what `current` gives if [`AUTOSAVE_INTERVAL`] has passed since the last
    /// check and it changed. A failure is reported once, on stderr, then only logged.
    pub fn autosave(&mut self, current: impl FnOnce() -> Settings) {
        if self.path.is_none() || self.checked.elapsed() < AUTOSAVE_INTERVAL {
            return;
        }
        self.checked = Instant::now();
        self.save_reporting(&current());
    }

    /// Saves now (on exit), reporting a failure as [`Self::autosave`] does; true if
    /// the file holds `settings` afterwards.
    pub fn save_reporting(&mut self, settings: &Settings) -> bool {
        match self.save(settings) {
            Ok(wrote) => {
                if wrote {
                    log::debug!("settings saved");
                }
                self.path.is_some()
            }
            Err(message) => {
                if std::mem::replace(&mut self.save_failed, true) {
                    log::debug!("{message}");
                } else {
                    eprintln!("particle-lab: {message}");
                }
                false
            }
        }
    }
}
