//! Writing is safe (issue 40, "Nothing lost"): whatever a path names, saving to it
//! replaces a regular file whole, writes through symlinks to the file they name (the
//! links stay links) and refuses a device, FIFO, socket or directory in one line,
//! leaving the node as it was. Each case on a real filesystem in a fresh directory;
//! the command line's `--save` and `--out`, and the settings file, the same way.

#![cfg(unix)]

use std::io::Write;
use std::os::unix::fs::{FileTypeExt, PermissionsExt, symlink};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use particle_lab::render::offscreen::read_png;
use particle_lab::scenes::snapshot::Snapshot;
use particle_lab::settings::{self, FILE_NAME, Loaded, Settings, Store};
use particle_lab::ui::{Lab, PanelLayout};
use particle_lab::writing::{self, AtomicFile, WriteError};

/// A fresh, empty directory for one test (short: a socket's path is at most 108 bytes).
fn scratch(tag: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("sw-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn is_link(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
}

fn is_fifo(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_fifo())
}

fn mkfifo(path: &Path) {
    assert!(Command::new("mkfifo").arg(path).status().unwrap().success(), "mkfifo {}", path.display());
}

/// No file in `dir` but those named: nothing temporary is left behind.
fn only(dir: &Path, names: &[&str]) {
    let mut found: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    found.sort();
    let mut names: Vec<String> = names.iter().map(|n| n.to_string()).collect();
    names.sort();
    assert_eq!(found, names, "in {}", dir.display());
}

/// `write_atomic(path, bytes)` on another thread: `None` if it did not return in 10 s
/// (it opened a FIFO and waits for a reader).
fn write_within_10_s(path: &Path, bytes: &'static [u8]) -> Option<Result<(), WriteError>> {
    let path = path.to_path_buf();
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = send.send(writing::write_atomic(&path, bytes));
    });
    receive.recv_timeout(Duration::from_secs(10)).ok()
}

/// A regular file at `path` holding `text`, with permissions `mode`.
fn file_with(path: &Path, text: &str, mode: u32) -> PathBuf {
    std::fs::write(path, text).unwrap();
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).unwrap();
    path.to_path_buf()
}

#[test]
fn a_regular_file_is_replaced_whole_and_keeps_its_permissions() {
    let dir = scratch("regular");
    let file = file_with(&dir.join("snapshot.json"), "old text, longer than the new", 0o640);
    writing::write_atomic(&file, b"new").unwrap();
    assert_eq!(std::fs::read(&file).unwrap(), b"new");
    assert!(std::fs::symlink_metadata(&file).unwrap().is_file());
    assert_eq!(std::fs::metadata(&file).unwrap().permissions().mode() & 0o7777, 0o640, "permissions kept");
    only(&dir, &["snapshot.json"]);

    let new = dir.join("new.csv");
    writing::write_atomic(&new, b"t,kinetic\n").unwrap();
    assert_eq!(std::fs::read(&new).unwrap(), b"t,kinetic\n");
    only(&dir, &["snapshot.json", "new.csv"]);
}

#[test]
fn a_read_only_file_is_refused_and_kept() {
    let dir = scratch("readonly");
    let file = file_with(&dir.join("kept.json"), "kept", 0o444);
    assert_eq!(writing::write_atomic(&file, b"new"), Err(WriteError::Io("it is read-only".into())));
    assert_eq!(std::fs::read(&file).unwrap(), b"kept");
    only(&dir, &["kept.json"]);
}

#[test]
fn a_symlink_writes_the_file_it_names_and_stays_a_link() {
    let dir = scratch("link");
    std::fs::create_dir(dir.join("kept")).unwrap();
    let target = file_with(&dir.join("kept/run.json"), "old", 0o600);
    let link = dir.join("run.json");
    symlink("kept/run.json", &link).unwrap();
    writing::write_atomic(&link, b"new").unwrap();
    assert!(is_link(&link), "the link is still a link");
    assert_eq!(std::fs::read_link(&link).unwrap(), Path::new("kept/run.json"), "pointing where it did");
    assert_eq!(std::fs::read(&target).unwrap(), b"new", "the file it names has the new bytes");
    assert_eq!(std::fs::metadata(&target).unwrap().permissions().mode() & 0o777, 0o600);
    only(&dir, &["kept", "run.json"]);
    only(&dir.join("kept"), &["run.json"]);
}

#[test]
fn a_chain_of_two_links_writes_the_file_at_its_end() {
    let dir = scratch("chain");
    let target = dir.join("file.csv");
    std::fs::write(&target, "old").unwrap();
    symlink(&target, dir.join("second")).unwrap();
    symlink("second", dir.join("first")).unwrap();
    writing::write_atomic(&dir.join("first"), b"new").unwrap();
    assert!(is_link(&dir.join("first")) && is_link(&dir.join("second")));
    assert_eq!(std::fs::read(&target).unwrap(), b"new");
    only(&dir, &["file.csv", "first", "second"]);
}

#[test]
fn a_dangling_link_gets_its_target_created() {
    let dir = scratch("dangling");
    std::fs::create_dir(dir.join("dotfiles")).unwrap();
    let link = dir.join("settings.json");
    symlink("dotfiles/settings.json", &link).unwrap();
    writing::write_atomic(&link, b"{}").unwrap();
    assert!(is_link(&link));
    assert_eq!(std::fs::read(dir.join("dotfiles/settings.json")).unwrap(), b"{}");
    only(&dir.join("dotfiles"), &["settings.json"]);
}

#[test]
fn a_fifo_is_refused_at_once_and_stays_a_fifo() {
    let dir = scratch("fifo");
    let fifo = dir.join("pipe.json");
    mkfifo(&fifo);
    let result = write_within_10_s(&fifo, b"never").expect("writing to a FIFO blocked");
    assert_eq!(result.unwrap_err().to_string(), "it is a FIFO (named pipe), not a regular file");
    assert!(is_fifo(&fifo), "still a FIFO");
    // Through a link too, and the link stays.
    let link = dir.join("link.json");
    symlink(&fifo, &link).unwrap();
    let result = write_within_10_s(&link, b"never").expect("writing through a link to a FIFO blocked");
    assert_eq!(result, Err(WriteError::NotAFile("a FIFO (named pipe)")));
    assert!(is_fifo(&fifo) && is_link(&link));
    only(&dir, &["pipe.json", "link.json"]);
}

#[test]
fn a_directory_and_a_socket_are_refused_untouched() {
    let dir = scratch("nodes");
    let directory = dir.join("out.png");
    std::fs::create_dir(&directory).unwrap();
    assert_eq!(writing::write_atomic(&directory, b"x"), Err(WriteError::NotAFile("a directory")));
    assert!(directory.is_dir() && std::fs::read_dir(&directory).unwrap().next().is_none());
    let socket = dir.join("lab.sock");
    let _listener = std::os::unix::net::UnixListener::bind(&socket).unwrap();
    assert_eq!(writing::write_atomic(&socket, b"x"), Err(WriteError::NotAFile("a socket")));
    assert!(std::fs::symlink_metadata(&socket).unwrap().file_type().is_socket());
    // A streaming writer is refused the same way, before any temporary file is made.
    assert_eq!(AtomicFile::create(&socket).err(), Some(WriteError::NotAFile("a socket")));
    only(&dir, &["out.png", "lab.sock"]);
}

#[test]
fn a_character_device_is_refused_by_the_check_alone() {
    // Only looks: /dev/null is never opened here.
    assert_eq!(writing::target(Path::new("/dev/null")), Err(WriteError::NotAFile("a device")));
    assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
}

#[test]
fn a_streamed_file_goes_through_a_link_when_committed_and_leaves_nothing_when_dropped() {
    let dir = scratch("stream");
    let target = dir.join("kept.gif");
    std::fs::write(&target, "old").unwrap();
    let link = dir.join("run.gif");
    symlink("kept.gif", &link).unwrap();
    let mut file = AtomicFile::create(&link).unwrap();
    assert_eq!(file.temporary().parent(), Some(dir.as_path()), "beside the file it replaces");
    file.write_all(b"half").unwrap();
    drop(file);
    assert_eq!(std::fs::read(&target).unwrap(), b"old", "a stopped write leaves the old file");
    only(&dir, &["kept.gif", "run.gif"]);
    let mut file = AtomicFile::create(&link).unwrap();
    file.write_all(b"whole").unwrap();
    file.commit().unwrap();
    assert!(is_link(&link));
    assert_eq!(std::fs::read(&target).unwrap(), b"whole");
    only(&dir, &["kept.gif", "run.gif"]);
}

#[test]
fn the_energy_csv_is_refused_over_a_fifo_and_written_through_a_link() {
    let dir = scratch("csv");
    let lab = Lab::new("bridge", &[]).unwrap();
    let fifo = dir.join("energy.csv");
    mkfifo(&fifo);
    let error = lab.export_energy_csv(&fifo).unwrap_err();
    assert_eq!(error.to_string(), "it is a FIFO (named pipe), not a regular file");
    assert!(is_fifo(&fifo));
    let link = dir.join("link.csv");
    symlink("kept.csv", &link).unwrap();
    lab.export_energy_csv(&link).unwrap();
    assert!(is_link(&link));
    assert!(std::fs::read_to_string(dir.join("kept.csv")).unwrap().starts_with("t,kinetic,"));
}

fn binary() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_particle-lab"));
    command.env("RUST_BACKTRACE", "1").stdin(Stdio::null());
    command
}

/// Runs `command`, killed after 120 s (a write that blocks on a FIFO would wait forever).
fn run(command: &mut Command) -> Output {
    let mut child = command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("{command:?} did not finish in 120 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// A refusal: exit `code`, one line on stderr naming `shown` and saying `what`, no panic.
fn assert_refused(output: &Output, code: i32, shown: &str, what: &str) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(code), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    assert!(stderr.contains("cannot write ") && stderr.contains(shown), "{stderr}");
    assert!(stderr.contains(what), "{stderr}");
    assert!(!stderr.contains("panicked") && !stderr.contains("backtrace"), "{stderr}");
}

fn simulate_save(path: &Path) -> Output {
    run(binary().args(["simulate", "--scene", "bridge", "--steps", "1", "--save"]).arg(path))
}

#[test]
fn simulate_saves_through_a_link_and_refuses_a_fifo() {
    let dir = scratch("simulate");
    let link = dir.join("run.json");
    symlink("kept.json", &link).unwrap();
    let output = simulate_save(&link);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(is_link(&link), "--save kept the link a link");
    let snapshot = Snapshot::load(&dir.join("kept.json")).unwrap();
    assert_eq!(snapshot.scene, "bridge");
    only(&dir, &["kept.json", "run.json"]);

    let fifo = dir.join("pipe.json");
    mkfifo(&fifo);
    // Refused before the run, as a usage error, so no run's work is lost at the end.
    assert_refused(&simulate_save(&fifo), 2, "pipe.json", "it is a FIFO (named pipe), not a regular file");
    assert!(is_fifo(&fifo), "the FIFO is untouched");
    only(&dir, &["kept.json", "run.json", "pipe.json"]);
}

#[test]
fn simulate_refuses_dev_null_and_leaves_it_a_device() {
    // The check first, by looking only: were it to pass, the command below could
    // replace /dev/null (as root), so it is not run.
    assert_eq!(writing::target(Path::new("/dev/null")), Err(WriteError::NotAFile("a device")));
    assert_refused(
        &simulate_save(Path::new("/dev/null")),
        2,
        "/dev/null",
        "it is a device, not a regular file",
    );
    assert!(
        std::fs::metadata("/dev/null").unwrap().file_type().is_char_device(),
        "/dev/null is still a device"
    );
}

fn render(out: &Path, extra: &[&str]) -> Output {
    run(binary()
        .args(["render", "--scene", "bridge", "--steps", "2", "--size", "64x48"])
        .args(extra)
        .arg("--out")
        .arg(out))
}

#[test]
fn render_writes_through_a_link_and_refuses_a_directory() {
    let dir = scratch("render");
    let link = dir.join("frame.png");
    symlink("kept.png", &link).unwrap();
    let output = render(&link, &[]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(is_link(&link), "--out kept the link a link");
    assert_eq!(read_png(&dir.join("kept.png")).unwrap().1, [64, 48]);

    let directory = dir.join("shots.png");
    std::fs::create_dir(&directory).unwrap();
    assert_refused(&render(&directory, &[]), 1, "shots.png", "it is a directory, not a regular file");
    assert!(directory.is_dir() && std::fs::read_dir(&directory).unwrap().next().is_none());
    only(&dir, &["frame.png", "kept.png", "shots.png"]);
}

#[test]
fn a_recording_goes_through_a_link_and_is_refused_over_a_fifo_before_it_runs() {
    let dir = scratch("record");
    let link = dir.join("run.gif");
    symlink("kept.gif", &link).unwrap();
    let output = render(&link, &["--frames", "2", "--every", "8"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(is_link(&link));
    assert!(std::fs::read(dir.join("kept.gif")).unwrap().starts_with(b"GIF89a"));

    let fifo = dir.join("run.apng");
    mkfifo(&fifo);
    assert_refused(&render(&fifo, &["--frames", "2"]), 1, "run.apng", "it is a FIFO (named pipe)");
    assert!(is_fifo(&fifo));
    only(&dir, &["kept.gif", "run.gif", "run.apng"]);
}

/// What a window on the default scene saves.
fn defaults() -> Settings {
    let lab = Lab::new(settings::DEFAULT_SCENE, &[]).unwrap();
    Settings::of(&lab, &PanelLayout::default(), settings::DEFAULT_WINDOW)
}

/// A config directory whose settings file is a link to a dotfile holding `text`, kept
/// in a directory of its own: (config, dotfiles, the dotfile, the link).
fn linked_settings(tag: &str, text: &str) -> (PathBuf, PathBuf, PathBuf, PathBuf) {
    let dir = scratch(tag);
    let (config, dotfiles) = (dir.join("config"), dir.join("dotfiles"));
    std::fs::create_dir_all(&config).unwrap();
    std::fs::create_dir_all(&dotfiles).unwrap();
    let dotfile = dotfiles.join("particle-lab.json");
    std::fs::write(&dotfile, text).unwrap();
    let link = config.join(FILE_NAME);
    symlink(&dotfile, &link).unwrap();
    (config, dotfiles, dotfile, link)
}

#[test]
fn a_settings_file_linked_to_a_kept_dotfile_stays_a_link_when_saved() {
    let (config, dotfiles, dotfile, link) = linked_settings("settings", "{}");
    let mut store = Store::in_dir(&config);
    assert!(store.save(&defaults()).unwrap());
    assert!(is_link(&link), "settings.json is still a link");
    assert_eq!(Settings::parse(&std::fs::read_to_string(&dotfile).unwrap()).unwrap(), defaults());
    only(&config, &[FILE_NAME]);
    only(&dotfiles, &["particle-lab.json"]);
}

#[test]
fn a_bad_settings_file_behind_a_link_is_copied_aside_and_the_link_kept() {
    let (config, dotfiles, dotfile, link) = linked_settings("aside", "garbage");
    let mut store = Store::in_dir(&config);
    let Loaded::Unusable { warning } = store.load() else { panic!("garbage was used") };
    assert!(warning.contains("moved it to") && warning.contains("settings.json.bad"), "{warning}");
    assert!(is_link(&link), "the link is left in place");
    assert_eq!(std::fs::read(config.join("settings.json.bad")).unwrap(), b"garbage", "the bad text is kept");
    assert!(store.save(&defaults()).unwrap());
    assert!(is_link(&link), "and stays a link when the settings are written");
    assert_eq!(Settings::parse(&std::fs::read_to_string(&dotfile).unwrap()).unwrap(), defaults());
    only(&config, &[FILE_NAME, "settings.json.bad"]);
    only(&dotfiles, &["particle-lab.json"]);
}

#[test]
fn a_settings_file_linked_to_a_fifo_is_refused_on_save_and_the_fifo_kept() {
    let dir = scratch("settings-fifo");
    let fifo = dir.join("pipe");
    mkfifo(&fifo);
    symlink(&fifo, dir.join(FILE_NAME)).unwrap();
    let error = Store::in_dir(&dir).save(&defaults()).unwrap_err();
    assert!(error.starts_with("cannot save the settings to "), "{error}");
    assert!(error.ends_with("it is a FIFO (named pipe), not a regular file"), "{error}");
    assert!(is_fifo(&fifo) && is_link(&dir.join(FILE_NAME)));
}
