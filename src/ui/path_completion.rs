//! Completing a typed path, for the File menu's path fields (the way to open and save
//! where no file dialog can open): the entries of the typed folder that start with
//! what is typed after its last `/` (its folders, and its files of the wanted kinds:
//! `.toml` scene files, `.json` snapshots), sorted, and the longest text they all
//! start with, which Tab writes. Plain code over the file system, no egui: the view
//! draws the entries and sends the keys.

use std::path::{Path, PathBuf};

/// At most this many entries of a folder are looked at: a huge folder (`/usr/lib`)
/// must not stall a frame. The rest are not offered.
pub const MAX_READ: usize = 5_000;

/// One entry of the typed folder that matches what is typed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// Its name in the folder.
    pub name: String,
    /// A folder (completed with a `/` after it, to go on into it), else a file.
    pub folder: bool,
}

impl Entry {
    /// The name as a completion writes it: a folder's with its `/`.
    #[must_use]
    pub fn written(&self) -> String {
        if self.folder { format!("{}/", self.name) } else { self.name.clone() }
    }
}

/// What a typed path can complete to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Completion {
    /// The typed text up to and with its last `/`: the folder, as typed (empty for
    /// the current folder).
    pub folder: String,
    /// What is typed after it: the start of a name.
    pub start: String,
    /// The entries whose names begin with `start`: folders first, then files, each in
    /// name order (ignoring case, then exactly).
    pub entries: Vec<Entry>,
}

impl Completion {
    /// The text Tab gives: the one entry whole (a folder with its `/`), else as much
    /// as every entry begins with; with no entry the typed text, unchanged.
    #[must_use]
    pub fn completed(&self) -> String {
        match self.entries.as_slice() {
            [] => format!("{}{}", self.folder, self.start),
            [only] => self.with(only),
            entries => format!("{}{}", self.folder, common_start(entries.iter().map(|e| e.name.as_str()))),
        }
    }

    /// The text choosing `entry` (a click on it) gives.
    #[must_use]
    pub fn with(&self, entry: &Entry) -> String {
        format!("{}{}", self.folder, entry.written())
    }
}

/// Lists what `typed` can complete to: the entries of its folder (the text up to its
/// last `/`, the current folder if none; `~` is the home folder) whose names begin
/// with the rest, keeping folders and files whose extension is one of `extensions`
/// (without the dot, in any case). Names beginning with `.` are hidden unless the
/// typed start does too. An error is one line naming the folder: missing, not a
/// folder, permission denied.
pub fn complete(typed: &str, extensions: &[&str]) -> Result<Completion, String> {
    let (folder, start) = match typed.rfind('/') {
        Some(slash) => typed.split_at(slash + 1),
        None => ("", typed),
    };
    let listed = if folder.is_empty() { PathBuf::from(".") } else { expand_home(folder) };
    let cannot = |reason: String| format!("cannot list {}: {reason}", crate::messages::path(&listed));
    let read = std::fs::read_dir(&listed).map_err(|e| cannot(folder_reason(&e)))?;
    let mut entries = Vec::new();
    for item in read.take(MAX_READ) {
        let item = item.map_err(|e| cannot(folder_reason(&e)))?;
        // A name that is not UTF-8 cannot be typed in the field, nor offered.
        let Ok(name) = item.file_name().into_string() else { continue };
        if !name.starts_with(start) || (name.starts_with('.') && !start.starts_with('.')) {
            continue;
        }
        // Followed through links: a link to a folder is a folder. A broken link is a file.
        let folder = std::fs::metadata(item.path()).is_ok_and(|m| m.is_dir());
        if folder || has_extension(&name, extensions) {
            entries.push(Entry { name, folder });
        }
    }
    entries.sort_by(|a, b| {
        (!a.folder, a.name.to_lowercase(), &a.name).cmp(&(!b.folder, b.name.to_lowercase(), &b.name))
    });
    Ok(Completion { folder: folder.to_string(), start: start.to_string(), entries })
}

/// The path a typed text names: `~` or `~/…` in the home folder (`$HOME`), anything
/// else as typed.
#[must_use]
pub fn expand_home(typed: &str) -> PathBuf {
    let home = std::env::var_os("HOME").filter(|home| !home.is_empty());
    match (typed.strip_prefix('~'), home) {
        (Some(""), Some(home)) => PathBuf::from(home),
        (Some(rest), Some(home)) if rest.starts_with('/') => Path::new(&home).join(&rest[1..]),
        _ => PathBuf::from(typed),
    }
}

/// The longest text every name begins with (whole characters).
fn common_start<'a>(mut names: impl Iterator<Item = &'a str>) -> String {
    let Some(first) = names.next() else { return String::new() };
    let mut end = first.len();
    for name in names {
        end = first[..end]
            .char_indices()
            .zip(name.chars())
            .find(|((_, a), b)| a != b)
            .map_or_else(|| end.min(name.len()), |((at, _), _)| at);
    }
    first[..end].to_string()
}

fn has_extension(name: &str, extensions: &[&str]) -> bool {
    Path::new(name)
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| extensions.iter().any(|wanted| wanted.eq_ignore_ascii_case(e)))
}

/// Why a folder could not be listed, in words.
fn folder_reason(error: &std::io::Error) -> String {
    use std::io::ErrorKind;
    match error.kind() {
        ErrorKind::NotFound => "no such folder".into(),
        ErrorKind::NotADirectory => "it is not a folder".into(),
        _ => crate::messages::io_reason(error),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh folder holding `files` (a name ending in `/` is a folder).
    fn folder(tag: &str, files: &[&str]) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("particle-lab-completion-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        for name in files {
            match name.strip_suffix('/') {
                Some(sub) => std::fs::create_dir_all(dir.join(sub)).unwrap(),
                None => std::fs::write(dir.join(name), "").unwrap(),
            }
        }
        dir
    }

    fn names(completion: &Completion) -> Vec<String> {
        completion.entries.iter().map(Entry::written).collect()
    }

    #[test]
    fn lists_folders_then_files_of_the_wanted_kinds_sorted() {
        let dir = folder(
            "kinds",
            &["b.toml", "A.TOML", "c.json", "notes.txt", "zoo/", "Apes/", ".hidden.toml", ".git/", "toml"],
        );
        let typed = format!("{}/", dir.display());
        let scenes = complete(&typed, &["toml"]).unwrap();
        assert_eq!(names(&scenes), ["Apes/", "zoo/", "A.TOML", "b.toml"]);
        assert_eq!(scenes.folder, typed);
        assert_eq!(scenes.start, "");
        let snapshots = complete(&typed, &["json"]).unwrap();
        assert_eq!(names(&snapshots), ["Apes/", "zoo/", "c.json"]);
        let hidden = complete(&format!("{typed}."), &["toml"]).unwrap();
        assert_eq!(names(&hidden), [".git/", ".hidden.toml"], "a typed dot shows the hidden ones");
    }

    #[test]
    fn tab_writes_the_one_match_whole_or_what_all_matches_begin_with() {
        let dir =
            folder("tab", &["chain.toml", "chains/", "cloth.toml", "cradle.toml", "élan.toml", "éclat.toml"]);
        let typed = |rest: &str| format!("{}/{rest}", dir.display());
        let complete = |rest: &str| complete(&typed(rest), &["toml"]).unwrap();
        assert_eq!(complete("cl").completed(), typed("cloth.toml"), "one file: whole");
        assert_eq!(complete("chains").completed(), typed("chains/"), "one folder: with its slash");
        assert_eq!(complete("ch").completed(), typed("chain"), "chain.toml and chains/ begin with chain");
        assert_eq!(complete("c").completed(), typed("c"), "nothing more in common");
        assert_eq!(complete("cr").completed(), typed("cradle.toml"));
        assert_eq!(complete("é").completed(), typed("é"), "whole characters, not bytes");
        assert_eq!(complete("x").completed(), typed("x"), "no match: as typed");
        assert!(complete("x").entries.is_empty());
        let chain = complete("ch");
        assert_eq!(names(&chain), ["chains/", "chain.toml"]);
        assert_eq!(chain.with(&chain.entries[1]), typed("chain.toml"), "a click writes that entry");
    }

    #[test]
    fn a_relative_path_lists_from_the_current_folder() {
        // Tests run in the package's folder.
        let shipped = complete("assets/scenes/ch", &["toml"]).unwrap();
        assert_eq!(shipped.completed(), "assets/scenes/chain.toml");
        let top = complete("asse", &["toml"]).unwrap();
        assert_eq!(top.completed(), "assets/");
        assert_eq!(top.folder, "");
    }

    #[test]
    fn a_missing_folder_or_a_file_as_folder_is_one_line() {
        let dir = folder("errors", &["plain.toml"]);
        let error = complete(&format!("{}/gone/ch", dir.display()), &["toml"]).unwrap_err();
        assert!(error.starts_with("cannot list ") && error.ends_with("gone/: no such folder"), "{error}");
        let error = complete(&format!("{}/plain.toml/x", dir.display()), &["toml"]).unwrap_err();
        assert!(error.ends_with(": it is not a folder"), "{error}");
        let error = complete("nowhere\n/x", &["toml"]).unwrap_err();
        assert!(!error.contains('\n'), "{error}");
    }

    #[test]
    fn a_folder_that_cannot_be_read_is_one_line() {
        use std::os::unix::fs::PermissionsExt;
        let dir = folder("locked", &["shut/"]);
        let shut = dir.join("shut");
        std::fs::set_permissions(&shut, std::fs::Permissions::from_mode(0o000)).unwrap();
        let result = complete(&format!("{}/", shut.display()), &["toml"]);
        std::fs::set_permissions(&shut, std::fs::Permissions::from_mode(0o755)).unwrap();
        // Root reads any folder; others are refused.
        if let Err(error) = result {
            assert!(error.ends_with(": permission denied"), "{error}");
        }
    }

    #[test]
    fn home_is_expanded_and_other_tildes_are_not() {
        let Some(home) = std::env::var_os("HOME").filter(|h| !h.is_empty()) else { return };
        assert_eq!(expand_home("~"), PathBuf::from(&home));
        assert_eq!(expand_home("~/a/b.toml"), Path::new(&home).join("a/b.toml"));
        assert_eq!(expand_home("~bob/x"), PathBuf::from("~bob/x"));
        assert_eq!(expand_home("a/~/x"), PathBuf::from("a/~/x"));
    }

    #[test]
    fn common_start_of_names() {
        assert_eq!(common_start(["abc", "abd", "ab"].into_iter()), "ab");
        assert_eq!(common_start(["same", "same"].into_iter()), "same");
        assert_eq!(common_start(["x"].into_iter()), "x");
        assert_eq!(common_start(std::iter::empty()), "");
        assert_eq!(common_start(["äb", "äc"].into_iter()), "ä");
        assert_eq!(common_start(["äb", "ab"].into_iter()), "");
    }
}
