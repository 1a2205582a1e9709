//! Scene files in the real window on a virtual X display (Xvfb): `--scene-file` opens
//! one, saving the file reloads it, a bad edit logs its one line and keeps the scene,
//! and the Scene menu opens a shipped file. `bash scripts/test.sh` installs the tools.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const TIMEOUT: Duration = Duration::from_secs(30);

/// Kills what it started when the test ends, passing or not.
struct Started(Vec<Child>);

impl Drop for Started {
    fn drop(&mut self) {
        for child in &mut self.0 {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// A private X display (Xvfb picks a free number and prints it).
fn display(started: &mut Started) -> String {
    for tool in ["Xvfb", "xdotool"] {
        let found = Command::new("sh").args(["-c", &format!("command -v {tool}")]).output().unwrap();
        assert!(found.status.success(), "{tool} is missing; 'bash scripts/test.sh' installs it");
    }
    // A server whose display does not answer within 10 s is started again (three tries).
    for _ in 0..3 {
        let mut server = Command::new("Xvfb")
            .args(["-displayfd", "1", "-screen", "0", "1280x800x24", "-nolisten", "tcp", "-noreset"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb starts");
        let mut number = String::new();
        std::io::BufRead::read_line(&mut std::io::BufReader::new(server.stdout.take().unwrap()), &mut number)
            .expect("Xvfb prints its display number");
        let name = format!(":{}", number.trim());
        started.0.push(server);
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(10) {
            let probe = Command::new("xdotool")
                .env("DISPLAY", &name)
                .arg("getdisplaygeometry")
                .output()
                .is_ok_and(|o| o.status.success());
            if probe {
                return name;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
    panic!("Xvfb did not answer, three times");
}

fn wait_for_log(log: &Path, needle: &str) -> String {
    let start = Instant::now();
    loop {
        let text = std::fs::read_to_string(log).unwrap_or_default();
        if let Some(line) = text.lines().find(|l| l.contains(needle)) {
            return line.to_string();
        }
        assert!(start.elapsed() < TIMEOUT, "no '{needle}' in the log:\n{text}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn scene(count: &str) -> String {
    format!(
        "[scene]\nname = \"row\"\n[[param]]\nname = \"gap\"\ndefault = 0.5\nmin = 0.1\nmax = 2\n\
         [[row]]\ncount = {count}\nstart = [0, 1, 0]\nstep = [\"gap\", 0, 0]\n"
    )
}

#[test]
fn the_window_reloads_an_edited_scene_file_and_keeps_it_through_a_bad_edit() {
    let mut started = Started(Vec::new());
    let name = display(&mut started);
    let dir: PathBuf =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("scene-files-window-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("row.toml");
    std::fs::write(&file, scene("3")).unwrap();
    let log = dir.join("app.log");
    let app = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(["--scene-file", file.to_str().unwrap()])
        .current_dir(&dir)
        .env("DISPLAY", &name)
        // Its own settings, so neither a developer's nor this run's change the test.
        .env("XDG_CONFIG_HOME", dir.join("config"))
        .env("RUST_LOG", "warn,particle_lab=info")
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .expect("particle-lab starts");
    started.0.push(app);
    wait_for_log(&log, "window open: scene row");

    std::fs::write(&file, scene("5")).unwrap();
    wait_for_log(&log, &format!("scene file reloaded: {}", file.display()));

    std::fs::write(&file, scene("\"5 +\"")).unwrap();
    let line = wait_for_log(&log, "9:13:");
    assert_eq!(
        line,
        format!(
            "particle-lab: {}:9:13: in the expression \"5 +\": expected a number, a parameter name or '(', \
             found the end",
            file.display()
        )
    );

    // Scene menu -> cloth (file): the second file, under the eight compiled scenes (a
    // menu row is 23 pixels high).
    let window = Command::new("xdotool")
        .env("DISPLAY", &name)
        .args(["search", "--sync", "--name", "^particle-lab$"])
        .output()
        .unwrap();
    let window = String::from_utf8_lossy(&window.stdout).lines().next().unwrap_or("").to_string();
    assert!(!window.is_empty(), "no window found");
    let click = |x: &str, y: &str| {
        Command::new("xdotool")
            .env("DISPLAY", &name)
            .args(["mousemove", "--window", &window, x, y, "click", "1"])
            .status()
            .unwrap();
        std::thread::sleep(Duration::from_millis(600));
    };
    click("58", "12");
    click("72", "255");
    wait_for_log(&log, "scene: cloth");
}
