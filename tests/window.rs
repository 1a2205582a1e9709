//! End-to-end: the real binary in a real window on a virtual X display (Xvfb, with the
//! openbox window manager so closing and minimising work as on a desktop), driven with
//! xdotool the way a person would use it. `bash scripts/test.sh` installs the tools.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use particle_lab::ui::{Lab, LabUi};

const TIMEOUT: Duration = Duration::from_secs(30);

/// The panel as a 1280x720 window lays it out on `scene` with the default settings:
/// the same interface run headless, so the test presses where the window draws a
/// control instead of at numbers copied from a screenshot.
fn panel_on(scene: &str) -> LabUi {
    let mut lab = Lab::new(scene, &[]).unwrap();
    let mut shell = LabUi::default();
    let ctx = egui::Context::default();
    for _ in 0..3 {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1280.0, 720.0))),
            ..Default::default()
        };
        let _ = ctx.run_ui(input, |ui| {
            shell.show(ui, &mut lab);
        });
    }
    shell
}

/// Where a hand takes hold of `scene`'s slider for `param` (window pixels): near the
/// slider's left end, halfway down it.
fn slider_grip(scene: &str, param: &str) -> (i32, i32) {
    let shell = panel_on(scene);
    let (_, rect) = shell.params.sliders.iter().find(|(name, _)| *name == param).expect("the scene has it");
    (rect.left() as i32 + 20, rect.center().y as i32)
}

/// The solver menu's button on `scene` (window pixels).
fn solver_menu(scene: &str) -> (i32, i32) {
    let rect = panel_on(scene).run.solver_menu.expect("the run section is open by default");
    (rect.center().x as i32, rect.center().y as i32)
}

/// Drags from `(x, y)` to the right in small steps, like a hand.
fn drag_right(display: &Display, window: &str, (x, y): (i32, i32)) {
    let y = y.to_string();
    display.xdotool(&["mousemove", "--window", window, &x.to_string(), &y, "mousedown", "1"]);
    for step in 1..=6 {
        std::thread::sleep(Duration::from_millis(100));
        display.xdotool(&["mousemove", "--window", window, &(x + step * 8).to_string(), &y]);
    }
    display.xdotool(&["mouseup", "1"]);
}

/// A private X display with a window manager; both are killed on drop.
struct Display {
    name: String,
    server: Child,
    window_manager: Child,
    /// One display at a time: windows drawn side by side on a software GPU, on a busy
    /// machine, can take longer than the tests' pauses to draw their first frame.
    _serial: std::sync::MutexGuard<'static, ()>,
}

static ONE_DISPLAY_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

impl Display {
    fn start() -> Self {
        // A test that failed holding the lock has let go of its display all the same.
        let serial = ONE_DISPLAY_AT_A_TIME.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        for tool in ["Xvfb", "xdotool", "openbox", "wmctrl", "import"] {
            let found = Command::new("sh").args(["-c", &format!("command -v {tool}")]).output().unwrap();
            assert!(found.status.success(), "{tool} is missing; 'bash scripts/test.sh' installs it");
        }
        // A server and window manager that do not come up in time (a busy machine, a
        // display number still being let go) are started again, up to three times.
        let (name, server, window_manager) = Self::launch();
        let mut display = Self { name, server, window_manager, _serial: serial };
        for attempt in 1..=3 {
            let up = wait_for(Duration::from_secs(15), || {
                Command::new("wmctrl")
                    .env("DISPLAY", &display.name)
                    .arg("-m")
                    .output()
                    .is_ok_and(|o| o.status.success())
            });
            if up {
                return display;
            }
            assert!(attempt < 3, "timed out waiting for the window manager, three times");
            let _ = display.window_manager.kill();
            let _ = display.server.kill();
            let _ = display.window_manager.wait();
            let _ = display.server.wait();
            (display.name, display.server, display.window_manager) = Self::launch();
        }
        unreachable!("returned or panicked above")
    }

    /// Starts Xvfb on a free display (it picks the number and prints it) and openbox on it.
    fn launch() -> (String, Child, Child) {
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
        let window_manager = Command::new("openbox")
            .env("DISPLAY", &name)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("openbox starts");
        (name, server, window_manager)
    }

    fn run(&self, program: &str, args: &[&str]) -> String {
        let output = Command::new(program).env("DISPLAY", &self.name).args(args).output().unwrap();
        String::from_utf8_lossy(&output.stdout).into_owned()
    }

    fn xdotool(&self, args: &[&str]) -> String {
        self.run("xdotool", args)
    }
}

impl Drop for Display {
    fn drop(&mut self) {
        let _ = self.window_manager.kill();
        let _ = self.server.kill();
        let _ = self.window_manager.wait();
        let _ = self.server.wait();
    }
}

/// Polls `done` until it holds (true) or `limit` passes (false).
fn wait_for(limit: Duration, mut done: impl FnMut() -> bool) -> bool {
    let start = Instant::now();
    while !done() {
        if start.elapsed() > limit {
            return false;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    true
}

fn wait_until(what: &str, mut done: impl FnMut() -> bool) {
    let start = Instant::now();
    while !done() {
        assert!(start.elapsed() < TIMEOUT, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The app under test, its log going to a file we can read while it runs.
struct App {
    child: Child,
    log: PathBuf,
    dir: PathBuf,
}

impl App {
    /// Starts the app with settings of its own (a fresh config directory), so that a
    /// developer's saved settings never change what a test sees.
    fn start(display: &Display, args: &[&str], tag: &str) -> Self {
        let config = test_dir(tag).join("config");
        let _ = std::fs::remove_dir_all(&config);
        Self::start_with_config(display, args, tag, &config)
    }

    /// Starts the app with its settings in `config` (its `XDG_CONFIG_HOME`).
    fn start_with_config(display: &Display, args: &[&str], tag: &str, config: &Path) -> Self {
        let dir = test_dir(tag);
        std::fs::create_dir_all(&dir).unwrap();
        let log = dir.join("app.log");
        let child = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
            .args(args)
            .current_dir(&dir)
            .env("DISPLAY", &display.name)
            .env("XDG_CONFIG_HOME", config)
            .env("RUST_LOG", "warn,particle_lab=info")
            .env_remove("WAYLAND_DISPLAY")
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&log).unwrap())
            .spawn()
            .expect("particle-lab starts");
        Self { child, log, dir }
    }

    fn log(&self) -> String {
        std::fs::read_to_string(&self.log).unwrap_or_default()
    }

    fn expect_log(&mut self, needle: &str) -> String {
        let start = Instant::now();
        loop {
            let log = self.log();
            if let Some(line) = log.lines().find(|l| l.contains(needle)) {
                return line.to_string();
            }
            if let Ok(Some(status)) = self.child.try_wait() {
                panic!("particle-lab exited ({status}) before logging '{needle}':\n{log}");
            }
            assert!(start.elapsed() < TIMEOUT, "no '{needle}' in the log:\n{log}");
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    fn window(&mut self, display: &Display) -> String {
        let mut id = String::new();
        wait_until("the window", || {
            id = display
                .xdotool(&["search", "--name", "^particle-lab$"])
                .lines()
                .next()
                .unwrap_or("")
                .to_string();
            !id.is_empty()
        });
        self.expect_log("window open");
        id
    }

    fn wait_exit(&mut self) -> ExitStatus {
        let start = Instant::now();
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return status;
            }
            assert!(start.elapsed() < TIMEOUT, "particle-lab did not exit:\n{}", self.log());
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for App {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A directory of the test's own under the target directory.
fn test_dir(tag: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("window-{tag}-{}", std::process::id()))
}

fn pause() {
    std::thread::sleep(Duration::from_millis(600));
}

#[test]
fn a_person_switches_scene_drags_a_slider_pauses_resizes_minimises_and_closes() {
    let display = Display::start();
    let mut app = App::start(&display, &[], "person");
    let window = app.window(&display);
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();

    // Scene menu -> bridge.
    display.xdotool(&["mousemove", "--window", &window, "58", "12", "click", "1"]);
    pause();
    display.xdotool(&["mousemove", "--window", &window, "68", "85", "click", "1"]);
    app.expect_log("scene: bridge");

    // Drag the g slider to the right, in small steps like a hand.
    drag_right(&display, &window, slider_grip("bridge", "g"));
    app.expect_log("set bridge.g = ");
    pause();
    let log = app.log();
    let values: Vec<f32> = log
        .lines()
        .filter(|l| l.contains("set bridge.g = "))
        .map(|l| l.rsplit(' ').next().unwrap().trim().parse().unwrap())
        .collect();
    assert!(values.len() >= 2 && values.last() > values.first(), "dragging right should raise g: {values:?}");

    // Space pauses; F12 saves a screenshot of the window.
    display.xdotool(&["key", "space"]);
    app.expect_log("paused: true");
    display.xdotool(&["key", "F12"]);
    let saved = app.expect_log("screenshot saved to ");
    let path = saved.split("screenshot saved to ").nth(1).unwrap().trim();
    let (pixels, size) = particle_lab::render::offscreen::read_png(Path::new(path)).unwrap();
    assert_eq!(size, [1280, 720], "the screenshot has the window's size");
    let distinct: std::collections::HashSet<&[u8]> = pixels.chunks(4).step_by(97).collect();
    assert!(distinct.len() > 50, "the screenshot looks blank");

    // A screenshot of the whole screen, as a person would see it (kept for a look).
    let screen = app.dir.join("screen.png");
    display.run("import", &["-window", "root", screen.to_str().unwrap()]);
    assert!(screen.exists());

    // The lab's keys: V for the 2D side view, P to hide the panel; then both back.
    display.xdotool(&["key", "v"]);
    app.expect_log("side view: true");
    display.xdotool(&["key", "p"]);
    app.expect_log("panel open: false");
    pause();
    let bare = app.dir.join("side-view.png");
    display.run("import", &["-window", "root", bare.to_str().unwrap()]);
    display.xdotool(&["key", "v"]);
    app.expect_log("side view: false");
    display.xdotool(&["key", "p"]);
    app.expect_log("panel open: true");

    // Resize, minimise, restore: it keeps running.
    display.xdotool(&["windowsize", &window, "900", "600"]);
    app.expect_log("resized to 900x600");
    display.xdotool(&["windowminimize", &window]);
    pause();
    assert!(app.child.try_wait().unwrap().is_none(), "died when minimised:\n{}", app.log());
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();
    assert!(app.child.try_wait().unwrap().is_none(), "died when restored:\n{}", app.log());
    // It draws again after being restored: a second screenshot comes out.
    display.xdotool(&["key", "F12"]);
    wait_until("a second screenshot", || app.log().matches("screenshot saved to ").count() == 2);

    // Close it as a window manager does.
    display.run("wmctrl", &["-i", "-c", &window]);
    let status = app.wait_exit();
    let log = app.log();
    assert!(status.success(), "exit status {status}:\n{log}");
    assert!(log.contains("window closed"), "{log}");
    assert!(!log.contains("panicked"), "{log}");
    // Passed: the screenshots are only worth keeping when something failed.
    std::fs::remove_dir_all(&app.dir).ok();
}

#[test]
fn opens_on_the_scene_and_settings_given_picks_the_pile_and_its_solver_and_quits_with_ctrl_q() {
    let display = Display::start();
    let mut app = App::start(&display, &["--scene", "bridge", "--set", "g=5"], "ctrl-q");
    let window = app.window(&display);
    app.expect_log("window open: scene bridge");
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();

    // Scene menu -> pile (the fourth entry).
    display.xdotool(&["mousemove", "--window", &window, "58", "12", "click", "1"]);
    pause();
    display.xdotool(&["mousemove", "--window", &window, "68", "107", "click", "1"]);
    app.expect_log("scene: pile");
    // The solver menu under the run controls -> paper (the second entry).
    pause();
    let (x, y) = solver_menu("pile");
    display.xdotool(&["mousemove", "--window", &window, &x.to_string(), &y.to_string(), "click", "1"]);
    pause();
    // The menu opens under its button, an entry a row each: paper is the second.
    let entry = (y + 50).to_string();
    display.xdotool(&["mousemove", "--window", &window, &x.to_string(), &entry, "click", "1"]);
    app.expect_log("solver: paper");

    display.xdotool(&["key", "ctrl+q"]);
    let status = app.wait_exit();
    let log = app.log();
    assert!(status.success(), "exit status {status}:\n{log}");
    assert!(log.contains("quit"), "{log}");
    assert!(!log.contains("panicked"), "{log}");
    std::fs::remove_dir_all(&app.dir).ok();
}

#[test]
fn the_window_left_alone_has_the_state_hash_simulate_prints_at_the_same_step() {
    let display = Display::start();
    let mut app = App::start(&display, &["--scene", "pendulum", "--set", "links=2"], "hash");
    let window = app.window(&display);
    display.xdotool(&["windowactivate", "--sync", &window]);
    std::thread::sleep(Duration::from_millis(1500));
    display.xdotool(&["key", "space"]);
    let line = app.expect_log("paused at step");
    // "... paused at step 123, state hash 0123456789abcdef"
    let rest = line.split("paused at step ").nth(1).expect("the step");
    let (step, hash) = rest.split_once(", state hash ").expect("the hash");
    let step: u64 = step.trim().parse().expect("a step number");
    assert!(step > 0, "{line}");
    let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(["simulate", "--scene", "pendulum", "--set", "links=2", "--steps", &step.to_string()])
        .args(["--every", &step.to_string()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let last: serde_json::Value = serde_json::from_str(stdout.lines().last().expect("a line")).unwrap();
    assert_eq!(last["step"], step);
    assert_eq!(last["hash"].as_str(), Some(hash.trim()), "window: {line}");
    display.xdotool(&["key", "ctrl+q"]);
    assert!(app.wait_exit().success(), "{}", app.log());
    std::fs::remove_dir_all(&app.dir).ok();
}

/// CPU time the process has used so far (clock ticks, user and system), from /proc.
fn cpu_ticks(pid: u32) -> u64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap();
    // The fields after the command name in parentheses; utime and stime are 14 and 15.
    let after = &stat[stat.rfind(')').unwrap() + 2..];
    let fields: Vec<&str> = after.split(' ').collect();
    fields[11].parse::<u64>().unwrap() + fields[12].parse::<u64>().unwrap()
}

#[test]
fn a_paused_untouched_window_burns_no_cpu_and_a_running_one_draws() {
    let display = Display::start();
    let mut app = App::start(&display, &["--scene", "pendulum"], "idle");
    let window = app.window(&display);
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();
    let pid = app.child.id();
    let busy = |seconds: u64| {
        let before = cpu_ticks(pid);
        std::thread::sleep(Duration::from_secs(seconds));
        cpu_ticks(pid) - before
    };
    let running = busy(3);
    display.xdotool(&["key", "space"]);
    app.expect_log("paused: true");
    pause();
    let paused = busy(3);
    // Running, it draws every frame on a software GPU (well over a core here); paused
    // and untouched it waits for input. 100 ticks a second is Linux's USER_HZ.
    assert!(running > 60, "running used only {running} ticks in 3 s");
    assert!(paused * 10 < running && paused < 30, "paused used {paused} ticks in 3 s (running: {running})");
    // It still answers: a key redraws and resumes.
    display.xdotool(&["key", "space"]);
    app.expect_log("paused: false");
    display.xdotool(&["key", "ctrl+q"]);
    assert!(app.wait_exit().success(), "{}", app.log());
    std::fs::remove_dir_all(&app.dir).ok();
}

#[test]
fn the_window_comes_back_as_it_was_left_and_fresh_starts_from_the_defaults() {
    let display = Display::start();
    let config = test_dir("settings-config");
    let _ = std::fs::remove_dir_all(&config);

    // First launch: nothing saved yet.
    let mut app = App::start_with_config(&display, &[], "settings-1", &config);
    let window = app.window(&display);
    app.expect_log("settings none saved yet at ");
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();
    // Scene menu -> bridge; drag its g slider right; the side view on; a smaller window.
    display.xdotool(&["mousemove", "--window", &window, "58", "12", "click", "1"]);
    pause();
    display.xdotool(&["mousemove", "--window", &window, "68", "85", "click", "1"]);
    app.expect_log("scene: bridge");
    drag_right(&display, &window, slider_grip("bridge", "g"));
    app.expect_log("set bridge.g = ");
    pause();
    let log = app.log();
    let last_set = log.lines().rfind(|l| l.contains("set bridge.g = ")).unwrap();
    let g = last_set.rsplit(' ').next().unwrap().trim().to_string();
    assert_ne!(g, "9.81", "the drag changed g");
    display.xdotool(&["key", "v"]);
    app.expect_log("side view: true");
    display.xdotool(&["windowsize", &window, "900", "600"]);
    app.expect_log("resized to 900x600");
    pause();
    display.xdotool(&["key", "ctrl+q"]);
    let status = app.wait_exit();
    assert!(
        status.success(),
        "exit status {status}:
{}",
        app.log()
    );
    app.expect_log("settings saved to ");
    let file = config.join("particle-lab").join("settings.json");
    let saved: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_eq!(saved["scene"], "bridge", "{saved}");
    assert_eq!(saved["view"]["side_view"], true, "{saved}");
    assert_eq!(saved["window"]["width"], 900, "{saved}");

    // Second launch, same config: the bridge, its g, the side view and the size are back.
    let mut app = App::start_with_config(&display, &[], "settings-2", &config);
    let window = app.window(&display);
    app.expect_log("window open: scene bridge");
    let restored = app.expect_log("settings restored from ");
    assert!(
        restored.contains("scene bridge [") && restored.contains(&format!("g={g} ")),
        "g={g}: {restored}"
    );
    assert!(restored.contains(" side") && restored.contains("window 900x600"), "{restored}");
    let geometry = display.xdotool(&["getwindowgeometry", &window]);
    assert!(geometry.contains("Geometry: 900x600"), "{geometry}");
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();
    // The side view is on: V turns it off, as a person would find it.
    display.xdotool(&["key", "v"]);
    app.expect_log("side view: false");
    display.xdotool(&["key", "ctrl+q"]);
    assert!(app.wait_exit().success(), "{}", app.log());

    // --fresh: the defaults, whatever was saved.
    let mut app = App::start_with_config(&display, &["--fresh"], "settings-3", &config);
    let window = app.window(&display);
    app.expect_log("window open: scene projectile");
    app.expect_log("settings --fresh: starting from the defaults");
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();
    display.xdotool(&["key", "ctrl+q"]);
    assert!(app.wait_exit().success(), "{}", app.log());
    let log = app.log();
    assert!(!log.contains("settings restored"), "{log}");
    assert!(!log.contains("panicked"), "{log}");
    for tag in ["settings-1", "settings-2", "settings-3", "settings-config"] {
        std::fs::remove_dir_all(test_dir(tag)).ok();
    }
}

/// Opened on a snapshot, the window steps on from it with the bits `simulate --from`
/// gives: the same hash at the same step.
#[test]
fn the_window_opened_on_a_snapshot_steps_on_as_simulate_does() {
    let dir = test_dir("from-snapshot");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("half.json");
    let file = file.to_str().unwrap();
    let saved = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(["simulate", "--scene", "cradle", "--steps", "200", "--every", "200", "--save", file])
        .output()
        .unwrap();
    assert!(saved.status.success(), "{}", String::from_utf8_lossy(&saved.stderr));
    let display = Display::start();
    let mut app = App::start(&display, &["--from", file], "from");
    let window = app.window(&display);
    app.expect_log("opened snapshot");
    display.xdotool(&["windowactivate", "--sync", &window]);
    std::thread::sleep(Duration::from_millis(1500));
    display.xdotool(&["key", "space"]);
    let line = app.expect_log("paused at step");
    let rest = line.split("paused at step ").nth(1).expect("the step");
    let (step, hash) = rest.split_once(", state hash ").expect("the hash");
    let step: u64 = step.trim().parse().expect("a step number");
    assert!(step > 200, "it went on from step 200: {line}");
    let more = (step - 200).to_string();
    let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(["simulate", "--from", file, "--steps", &more, "--every", &more])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let last: serde_json::Value = serde_json::from_str(stdout.lines().last().expect("a line")).unwrap();
    assert_eq!(last["step"], step);
    assert_eq!(last["hash"].as_str(), Some(hash.trim()), "window: {line}");
    display.xdotool(&["key", "ctrl+q"]);
    assert!(app.wait_exit().success(), "{}", app.log());
    std::fs::remove_dir_all(&app.dir).ok();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn without_a_display_it_says_what_is_missing() {
    let config = test_dir("no-display").join("config");
    let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .env("XDG_CONFIG_HOME", &config)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    let last = stderr.trim_end().lines().last().unwrap_or("");
    assert!(last.contains("no display") && last.contains("Xvfb"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// Issue 17, finding 1: springForces at g = 0 (in its range) panicked when the window
/// opened on it, and a settings file holding it crashed every start after. Opened with
/// `--set g=0`, it runs; quit, the saved g = 0 opens again and runs.
#[test]
fn the_window_runs_spring_forces_at_g_zero_and_opens_again_on_the_saved_value() {
    let display = Display::start();
    let config = test_dir("g-zero").join("config");
    let _ = std::fs::remove_dir_all(&config);
    for (round, args) in [&["--scene", "springForces", "--set", "g=0"][..], &[][..]].into_iter().enumerate() {
        let mut app = App::start_with_config(&display, args, "g-zero", &config);
        let window = app.window(&display);
        app.expect_log("window open: scene springForces");
        if round == 1 {
            let restored = app.expect_log("settings restored");
            assert!(restored.contains("g=0"), "the saved g = 0: {restored}");
        }
        display.xdotool(&["windowactivate", "--sync", &window]);
        std::thread::sleep(Duration::from_millis(1500));
        display.xdotool(&["key", "space"]);
        let paused = app.expect_log("paused at step");
        assert!(!paused.contains("step 0,"), "round {round}: the scene ran: {paused}");
        display.xdotool(&["key", "ctrl+q"]);
        let status = app.wait_exit();
        let log = app.log();
        assert!(status.success(), "round {round}: exit status {status}:\n{log}");
        assert!(!log.contains("panicked"), "round {round}: {log}");
    }
    std::fs::remove_dir_all(test_dir("g-zero")).ok();
}

/// Issue 40: a scene where nothing moves, left running, came to redraw at 34 fps on
/// 168% CPU. A small pile settles; then the window draws nothing until something
/// changes, while its physics steps on: paused later, the step it shows is the one the
/// wall clock asks for, with `simulate`'s state hash; a slider wakes it at once.
#[test]
fn a_window_at_rest_draws_nothing_keeps_its_clock_and_a_slider_wakes_it() {
    let display = Display::start();
    let mut app = App::start(&display, &["--scene", "pile", "--set", "count=20"], "rest");
    let window = app.window(&display);
    display.xdotool(&["windowactivate", "--sync", &window]);
    let line = app.expect_log("at rest at t = ");
    let rested = Instant::now();
    // "... at rest at t = 14.100 s (step 846): drawing on input only"
    let step_of = |line: &str, after: &str| -> u64 {
        let rest = line.split(after).nth(1).expect("a step");
        rest.split(|c: char| !c.is_ascii_digit()).next().unwrap().parse().expect("a step number")
    };
    let rest_step = step_of(&line, "(step ");
    let pid = app.child.id();
    let before = cpu_ticks(pid);
    std::thread::sleep(Duration::from_secs(3));
    let resting = cpu_ticks(pid) - before;
    // Drawing this window takes well over half a core on a software GPU; at rest it
    // only steps a sleeping pile twenty times a second. 100 ticks a second is one core.
    assert!(resting < 30, "at rest it used {resting} ticks in 3 s");

    // The clock kept counting: pausing shows the step the wall clock asks for (60 Hz),
    // and its state is the one `simulate` reaches in as many steps.
    display.xdotool(&["key", "space"]);
    let paused = app.expect_log("paused at step");
    let elapsed = rested.elapsed().as_secs_f64();
    let step = step_of(&paused, "paused at step ");
    let counted = (step - rest_step) as f64 / 60.0;
    assert!(
        counted > elapsed - 1.0 && counted < elapsed + 0.5,
        "{counted:.2} s counted at rest in {elapsed:.2} s: {line} / {paused}"
    );
    let hash = paused.split(", state hash ").nth(1).expect("the hash").trim();
    let output = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(["simulate", "--scene", "pile", "--set", "count=20", "--steps", &step.to_string()])
        .args(["--every", &step.to_string()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let last: serde_json::Value = serde_json::from_str(stdout.lines().last().expect("a line")).unwrap();
    assert_eq!(last["step"], step);
    assert_eq!(last["hash"].as_str(), Some(hash), "window: {paused}");

    // Running again, it is still at rest; a slider wakes it at once.
    display.xdotool(&["key", "space"]);
    wait_until("at rest again", || app.log().matches("at rest at t = ").count() == 2);
    drag_right(&display, &window, slider_grip("pile", "count"));
    app.expect_log("set pile.count = ");
    app.expect_log("awake at t = ");
    display.xdotool(&["key", "ctrl+q"]);
    assert!(app.wait_exit().success(), "{}", app.log());
    assert!(!app.log().contains("panicked"), "{}", app.log());
    std::fs::remove_dir_all(&app.dir).ok();
}

/// Issue 40: a settings file with a window of 16384 x 16384 (in range) panicked at every
/// start on a GPU that cannot draw so large a frame. It opens at the screen's size, says
/// so once, and saves that size; a resize past what the GPU can draw is held to it.
#[test]
fn a_saved_window_too_large_for_the_screen_opens_at_its_size_and_a_huge_resize_is_held() {
    let display = Display::start();
    let config = test_dir("huge-config");
    let _ = std::fs::remove_dir_all(&config);
    // A settings file as the window writes it, then made huge.
    let mut app = App::start_with_config(&display, &["--scene", "pendulum"], "huge-1", &config);
    let window = app.window(&display);
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();
    display.xdotool(&["key", "ctrl+q"]);
    assert!(app.wait_exit().success(), "{}", app.log());
    let file = config.join("particle-lab").join("settings.json");
    let mut saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    saved["window"]["width"] = 16_384.into();
    saved["window"]["height"] = 16_384.into();
    std::fs::write(&file, saved.to_string()).unwrap();

    let mut app = App::start_with_config(&display, &[], "huge-2", &config);
    let window = app.window(&display);
    app.expect_log("window 16384x16384");
    app.expect_log("A window of 16384x16384 does not fit the screen (1280x800): opened at 1280x800");
    display.xdotool(&["windowactivate", "--sync", &window]);
    std::thread::sleep(Duration::from_millis(1500));
    assert!(app.child.try_wait().unwrap().is_none(), "died:\n{}", app.log());
    let geometry = display.xdotool(&["getwindowgeometry", &window]);
    assert!(geometry.contains("Geometry: 1280x800"), "{geometry}");
    // Paused, so that only the resizes draw (each frame that large is slow).
    display.xdotool(&["key", "space"]);
    app.expect_log("paused: true");

    // Far past the largest texture: held to what the GPU draws (on a software GPU,
    // the memory runs out before the texture limit, and the window is made smaller).
    display.xdotool(&["windowsize", &window, "20000", "20000"]);
    wait_until("the limit said", || {
        let log = app.log();
        log.contains("The window can be at most") || log.contains("The GPU ran out of memory drawing a")
    });
    std::thread::sleep(Duration::from_secs(2));
    assert!(app.child.try_wait().unwrap().is_none(), "died when resized:\n{}", app.log());
    // It is usable again at a size that fits.
    display.xdotool(&["windowsize", &window, "1000", "700"]);
    app.expect_log("resized to 1000x700");
    display.xdotool(&["key", "ctrl+q"]);
    let status = app.wait_exit();
    let log = app.log();
    assert!(status.success(), "exit status {status}:\n{log}");
    assert!(!log.contains("panicked"), "{log}");
    assert_eq!(log.matches("does not fit the screen").count(), 1, "said once:\n{log}");
    let saved: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_eq!(saved["window"]["width"], 1000, "{saved}");
    for tag in ["huge-1", "huge-2", "huge-config"] {
        std::fs::remove_dir_all(test_dir(tag)).ok();
    }
}

/// The lab rests only once the energy plot and the trails have nothing left to show
/// of the motion: `REST_DELAY` covers both.
#[test]
fn the_rest_delay_outlasts_the_energy_plot_and_the_trails() {
    use particle_lab::ui::lab::{MAX_FRAME_TIME, REST_DELAY, REST_TICK};
    const {
        assert!(REST_DELAY >= particle_lab::ui::views::energy::PLOT_SECONDS);
        assert!(REST_DELAY >= particle_lab::render::Trails::LIFETIME);
    }
    assert!(REST_TICK.as_secs_f64() < MAX_FRAME_TIME);
}

/// Issue 40, "File → Open works everywhere": where no file dialog can open (no desktop
/// portal, no zenity: this test's display has neither), Ctrl+O opens the lab's own path
/// field and the status line says why; Tab completes from the folder's scene files and
/// folders, Enter opens. Ctrl+S does the same for a snapshot, which opens again.
#[test]
fn where_no_file_dialog_opens_a_path_field_completes_opens_and_saves() {
    let display = Display::start();
    let dir = test_dir("no-dialog");
    let folder = dir.join("my-scenes");
    std::fs::create_dir_all(&folder).unwrap();
    let chain =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/chain.toml"))
            .unwrap()
            .replacen("name = \"chain\"\n", "name = \"hanging\"\n", 1);
    std::fs::write(folder.join("hanging-chain.toml"), chain).unwrap();
    std::fs::write(folder.join("notes.txt"), "not a scene").unwrap();
    let mut app = App::start(&display, &["--scene", "projectile"], "no-dialog");
    let window = app.window(&display);
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();

    display.xdotool(&["key", "ctrl+o"]);
    // Known before trying (no zenity, no session bus), or found by trying (it gave
    // nothing sooner than a person could cancel).
    wait_until("the fallback said", || {
        let log = app.log();
        log.contains("no file dialog can open (") || log.contains("too soon for a cancel: it could not open")
    });
    pause();
    // The field has the keyboard: a folder completes, then the one scene file in it.
    // (A pause between keys, as a person leaves: each is drawn before the next.)
    display.xdotool(&["type", "--delay", "80", "my-sc"]);
    pause();
    display.xdotool(&["key", "Tab"]);
    pause();
    display.xdotool(&["type", "--delay", "80", "h"]);
    pause();
    display.xdotool(&["key", "Tab"]);
    pause();
    display.xdotool(&["key", "Return"]);
    let opened = app.expect_log("scene file opened: ");
    assert!(opened.ends_with("my-scenes/hanging-chain.toml"), "{opened}");
    app.expect_log("scene: hanging");

    // Ctrl+S: a snapshot saved through the same field, which opens again.
    display.xdotool(&["key", "ctrl+s"]);
    pause();
    display.xdotool(&["type", "--delay", "80", "kept.json"]);
    pause();
    display.xdotool(&["key", "Return"]);
    let snapshot = dir.join("kept.json");
    wait_until("the snapshot written", || snapshot.is_file());
    display.xdotool(&["key", "ctrl+q"]);
    assert!(app.wait_exit().success(), "{}", app.log());
    let log = app.log();
    assert!(!log.contains("panicked"), "{log}");
    let reopened = Command::new(env!("CARGO_BIN_EXE_particle-lab"))
        .args(["simulate", "--steps", "1", "--from"])
        .arg(&snapshot)
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(reopened.status.success(), "{}", String::from_utf8_lossy(&reopened.stderr));
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 38: a link a teacher sends works on the desktop too. `particle-lab open LINK`
/// with a scene file of one's own carried in the link (from `particle-lab link`) opens
/// it in the window, runs the link's steps and pauses with `simulate`'s state hash.
#[test]
fn open_opens_a_link_that_carries_a_scene_file_in_the_window() {
    let display = Display::start();
    let dir = test_dir("open-link");
    std::fs::create_dir_all(&dir).unwrap();
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/chain.toml"))
            .unwrap()
            .replacen("name = \"chain\"\n", "name = \"sent-chain\"\n", 1);
    let file = dir.join("sent-chain.toml");
    let again = dir.join("again.toml");
    std::fs::write(&file, &text).unwrap();
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_particle-lab")).args(args).output().unwrap();
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).unwrap()
    };
    let file = file.to_str().unwrap();
    let link = run(&["link", "--scene-file", file, "--set", "links=9", "--steps", "150"]);
    let link = link.trim();
    assert!(link.starts_with("#file="), "{link}");
    // The file is gone: only the link has it.
    std::fs::remove_file(file).unwrap();

    let mut app = App::start(&display, &["open", link], "open-link");
    app.window(&display);
    app.expect_log("scene sent-chain [damping=0.8 g=9.81 links=9 ");
    let paused = app.expect_log("paused at step ");
    let hash = paused.split(", state hash ").nth(1).expect("the hash").trim().to_string();
    assert!(paused.contains("paused at step 150,"), "{paused}");

    // The same text written again, for simulate.
    std::fs::write(&again, &text).unwrap();
    let out = run(&[
        "simulate",
        "--scene-file",
        again.to_str().unwrap(),
        "--set",
        "links=9",
        "--steps",
        "150",
        "--every",
        "150",
    ]);
    let last: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
    assert_eq!(last["step"], 150);
    assert_eq!(last["hash"].as_str(), Some(hash.as_str()), "window: {paused}");
    let _ = app.child.kill();
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 38, "Keep it as a file": Ctrl+Shift+S saves the running scene as a scene file
/// (here through the lab's path field, filled with the scene's name), with the values
/// it runs at as its defaults; the file is what `export` prints and runs as the scene
/// did. On a scene built into the program it says why it cannot, and writes nothing.
#[test]
fn ctrl_shift_s_saves_the_scene_as_a_file_that_runs_as_it_did() {
    let display = Display::start();
    let dir = test_dir("save-scene");
    let _ = std::fs::remove_dir_all(&dir);
    let mut app = App::start(&display, &["--scene", "chain", "--set", "links=9"], "save-scene");
    let window = app.window(&display);
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();
    display.xdotool(&["key", "ctrl+shift+s"]);
    wait_until("the fallback said", || {
        let log = app.log();
        log.contains("no file dialog can open (") || log.contains("too soon for a cancel: it could not open")
    });
    pause();
    // The field holds the scene's name; Enter saves.
    display.xdotool(&["key", "Return"]);
    app.expect_log("scene file saved: chain.toml");
    let saved = std::fs::read_to_string(dir.join("chain.toml")).expect("the saved file");
    display.xdotool(&["key", "ctrl+q"]);
    assert!(app.wait_exit().success(), "{}", app.log());
    assert!(!app.log().contains("panicked"), "{}", app.log());

    let run = |args: &[&str]| {
        let out =
            Command::new(env!("CARGO_BIN_EXE_particle-lab")).args(args).current_dir(&dir).output().unwrap();
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).unwrap()
    };
    assert_eq!(saved, run(&["export", "--scene", "chain", "--set", "links=9"]));
    let hash = |args: &[&str]| {
        let out = run(args);
        let last: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
        last["hash"].as_str().unwrap().to_string()
    };
    assert_eq!(
        hash(&["simulate", "--scene-file", "chain.toml", "--steps", "200", "--every", "200"]),
        hash(&["simulate", "--scene", "chain", "--set", "links=9", "--steps", "200", "--every", "200"]),
    );

    // A built-in scene: the status line says why, nothing is written.
    let mut app = App::start(&display, &["--scene", "projectile"], "save-scene");
    let window = app.window(&display);
    display.xdotool(&["windowactivate", "--sync", &window]);
    pause();
    display.xdotool(&["key", "ctrl+shift+s"]);
    app.expect_log("cannot save the scene as a file: 'projectile' is built into the program");
    display.xdotool(&["key", "ctrl+q"]);
    assert!(app.wait_exit().success(), "{}", app.log());
    assert!(!app.log().contains("no file dialog can open ("), "{}", app.log());
    assert!(!dir.join("projectile.toml").exists());
    std::fs::remove_dir_all(&dir).ok();
}
