//! The documentation and the program cannot drift apart: every flag of every command is
//! in `docs/cli.md`, every key of the scene format in `docs/scene-format.md` (whose
//! examples load and run), every key binding in `docs/guide.md` and the Help window,
//! every read-out of every scene in `docs/cli.md`, and the README stays a short front
//! door whose scene file runs.

use std::collections::BTreeSet;
use std::path::Path;

use clap::CommandFactory;
use particle_lab::cli::Cli;
use particle_lab::scenes::{self, SCENES, Scene, SceneEntry, file};
use particle_lab::ui::keys::SHORTCUTS;
use particle_lab::ui::views::help::HelpWindow;

/// Longest the README may be (lines).
const README_LINES: usize = 250;
/// Steps each example scene file is run for.
const EXAMPLE_STEPS: usize = 10;

fn read(path: &str) -> String {
    let full = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("cannot read {path}: {e}"))
}

/// The sections of a Markdown page: each heading line (`#` to `######`) with the text
/// under it, up to the next heading of any level. Fenced blocks are not headings.
fn sections(page: &str) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = vec![(String::new(), String::new())];
    let mut fenced = false;
    for line in page.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        if !fenced && line.starts_with('#') {
            out.push((line.to_string(), String::new()));
        } else if let Some((_, body)) = out.last_mut() {
            body.push_str(line);
            body.push('\n');
        }
    }
    out
}

/// The text under every heading that contains `needle` (with the headings).
fn under(page: &str, needle: &str) -> String {
    sections(page)
        .into_iter()
        .filter(|(heading, _)| heading.contains(needle))
        .map(|(heading, body)| format!("{heading}\n{body}"))
        .collect()
}

/// The contents of every fenced block opened with ```` ```lang ````.
fn fenced(page: &str, lang: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in page.lines() {
        let trimmed = line.trim_start();
        match &mut current {
            None if trimmed.starts_with("```") && trimmed[3..].trim() == lang => {
                current = Some(String::new())
            }
            Some(_) if trimmed.starts_with("```") => blocks.extend(current.take()),
            Some(block) => {
                block.push_str(line);
                block.push('\n');
            }
            None => {}
        }
    }
    blocks
}

/// Loads `text` as a scene file and runs it a few steps; the error as one line.
fn load_and_run(text: &str, shown: &str) -> Result<Box<dyn Scene>, String> {
    let entry = file::load_text(text, shown, None).map_err(|e| e.to_string())?;
    let mut scene = scenes::build_entry(&entry, &[])?;
    let dt = scene.info().dt;
    for _ in 0..EXAMPLE_STEPS {
        scene.step(dt).map_err(|e| format!("{shown}: {e}"))?;
    }
    Ok(scene)
}

#[test]
fn every_flag_of_every_command_is_in_the_cli_reference() {
    let page = read("docs/cli.md");
    let root = Cli::command();
    // The window's flags under the heading naming `particle-lab`, each command's under
    // the heading naming it.
    let mut commands = vec![("particle-lab".to_string(), root.clone())];
    commands.extend(root.get_subcommands().map(|c| (c.get_name().to_string(), c.clone())));
    assert!(commands.len() >= 4, "the window, scenes, simulate and render");
    let mut missing = Vec::new();
    for (name, command) in &commands {
        let section = under(&page, &format!("`{name}`"));
        if section.is_empty() {
            missing.push(format!("a heading naming `{name}`"));
            continue;
        }
        for arg in command.get_arguments() {
            if matches!(arg.get_id().as_str(), "help" | "version") {
                continue;
            }
            let Some(long) = arg.get_long() else { continue };
            if !section.contains(&format!("`--{long}")) {
                missing.push(format!("{name}: `--{long}`"));
            }
            // A switch's true/false are not values to document.
            let values = if arg.get_action().takes_values() { arg.get_possible_values() } else { Vec::new() };
            for value in values {
                if !value.is_hide_set() && !section.contains(&format!("`{}`", value.get_name())) {
                    missing.push(format!("{name} --{long}: the value `{}`", value.get_name()));
                }
            }
        }
    }
    assert!(missing.is_empty(), "docs/cli.md lacks: {missing:#?}");
}

#[test]
fn every_key_of_the_scene_format_is_in_its_reference() {
    let page = read("docs/scene-format.md");
    let mut missing = Vec::new();
    for (table, keys) in file::accepted_keys() {
        // `[scene]` or `[[row]]`: the heading names the table as a file writes it.
        let section = under(&page, &format!("[{table}]"));
        if section.is_empty() {
            missing.push(format!("a heading naming [{table}]"));
            continue;
        }
        for key in *keys {
            if !section.contains(&format!("| `{key}` |")) {
                missing.push(format!("[{table}] `{key}`"));
            }
        }
    }
    assert!(missing.is_empty(), "docs/scene-format.md lacks a table row for: {missing:#?}");
}

#[test]
fn every_scene_file_example_in_the_reference_loads_and_runs() {
    let page = read("docs/scene-format.md");
    let examples = fenced(&page, "toml");
    assert!(examples.len() >= 5, "only {} ```toml examples", examples.len());
    for (k, text) in examples.iter().enumerate() {
        if let Err(message) = load_and_run(text, &format!("example-{}.toml", k + 1)) {
            panic!("docs/scene-format.md, example {}: {message}\n{text}", k + 1);
        }
    }
}

#[test]
fn every_key_binding_is_in_the_guide_and_the_help_window() {
    let guide = read("docs/guide.md");
    let rows = HelpWindow::rows();
    let mut missing = Vec::new();
    for shortcut in SHORTCUTS {
        if !rows.contains(&(shortcut.keys, shortcut.meaning)) {
            missing.push(format!("Help → Controls: {}", shortcut.keys));
        }
        if !guide.lines().any(|line| line.starts_with(&format!("| {} |", shortcut.keys))) {
            missing.push(format!("docs/guide.md: a table row `| {} | ... |`", shortcut.keys));
        }
    }
    assert!(missing.is_empty(), "{missing:#?}");
}

/// Every read-out row a scene shows along a run of up to 10 s (some appear only once
/// something happened: a round landed, a second of flow measured), looked at every 30
/// steps; for each of the eight compiled scenes and four shipped files.
fn rows_along_a_run() -> &'static [(String, Vec<particle_lab::scenes::Readout>)] {
    static ROWS: std::sync::OnceLock<Vec<(String, Vec<particle_lab::scenes::Readout>)>> =
        std::sync::OnceLock::new();
    ROWS.get_or_init(run_every_scene)
}

fn run_every_scene() -> Vec<(String, Vec<particle_lab::scenes::Readout>)> {
    let entries: Vec<&'static SceneEntry> = SCENES.iter().chain(file::shipped()).collect();
    assert!(entries.len() >= 12, "eight compiled scenes and four shipped files");
    entries
        .into_iter()
        .map(|entry| {
            let mut scene = scenes::build_entry(entry, &[]).unwrap();
            // As `simulate` starts it: the projectile's round fired at step 0.
            scenes::fire_at_start(scene.as_mut());
            let dt = scene.info().dt;
            let steps = (10.0 / dt) as usize;
            let mut rows = Vec::new();
            for step in 0..=steps {
                if step % 30 == 0 {
                    rows.extend(scene.readout_rows(dt));
                }
                if step < steps {
                    scene.step(dt).unwrap();
                }
            }
            (entry.info().name.to_string(), rows)
        })
        .collect()
}

#[test]
fn every_read_out_of_every_scene_is_in_the_cli_reference() {
    let page = read("docs/cli.md");
    let mut missing = BTreeSet::new();
    for (name, rows) in rows_along_a_run() {
        let section = under(&page, &format!("`{name}`"));
        let mut seen = BTreeSet::new();
        for row in rows {
            seen.insert(row.label.trim().to_string());
            // Each number's key, as `simulate` prints it, in the same section.
            seen.extend(row.values.iter().map(|(key, _)| key.to_string()));
        }
        for label in seen {
            if !section.contains(&format!("`{label}`")) {
                missing.insert(format!("{name}: `{label}`"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "docs/cli.md lacks, under each scene's heading, the read-outs or their keys: {missing:#?}"
    );
}

/// Issue 37, "read-outs a student understands": every read-out the panel shows has a
/// tooltip saying what it is; a prediction's (a value under a `…_predicted_…` or
/// `…_exact_s` key) also says what its formula leaves out.
#[test]
fn every_read_out_has_a_tooltip_and_a_prediction_says_what_it_leaves_out() {
    let mut missing = BTreeSet::new();
    for (name, rows) in rows_along_a_run() {
        for row in rows {
            let label = row.label.trim();
            if row.help.len() < 25 {
                missing.insert(format!("{name}: `{label}` has no tooltip"));
            }
            let predicted =
                row.values.iter().any(|(key, _)| key.contains("_predicted") || key.ends_with("_exact_s"));
            if predicted && !row.help.to_lowercase().contains("leaves out") {
                missing.insert(format!("{name}: `{label}` does not say what it leaves out"));
            }
        }
    }
    assert!(missing.is_empty(), "{missing:#?}");
}

#[test]
fn the_readme_is_a_short_front_door_whose_scene_file_runs() {
    let readme = read("README.md");
    let lines = readme.lines().count();
    assert!(lines <= README_LINES, "README.md has {lines} lines; at most {README_LINES}");
    assert!(readme.contains("bash scripts/test.sh"), "the test command CI runs is in the README");
    assert!(readme.contains("cargo run --release"), "the command that opens the demo");
    let examples = fenced(&readme, "toml");
    assert_eq!(examples.len(), 1, "one scene file in the README");
    let example = &examples[0];
    let example_lines = example.lines().filter(|l| !l.trim().is_empty()).count();
    assert!(example_lines <= 12, "the README's scene file has {example_lines} lines; about ten");
    let scene = load_and_run(example, "my-experiment.toml").unwrap_or_else(|e| panic!("README's scene: {e}"));
    assert!(!scene.world().particles.is_empty(), "it makes particles");
}

#[test]
fn every_relative_link_of_the_docs_names_a_file_that_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let pages = [
        "README.md",
        "docs/guide.md",
        "docs/scene-format.md",
        "docs/cli.md",
        "docs/physics.md",
        "docs/engine.md",
        "docs/convergence.md",
    ];
    let mut broken = Vec::new();
    for page in pages {
        let text = read(page);
        let base = root.join(page).parent().unwrap().to_path_buf();
        // Markdown links and images: `](target)`.
        for piece in text.split("](").skip(1) {
            let Some(end) = piece.find(')') else { continue };
            let target = piece[..end].split('#').next().unwrap_or("");
            if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            if !base.join(target).exists() {
                broken.push(format!("{page}: {target}"));
            }
        }
    }
    assert!(broken.is_empty(), "links to nothing: {broken:#?}");
}
