//! Help → About this scene (issue 37): the open scene's page on its physics, reached
//! through the menu as a user would, and the same page from `scenes --about`; the heap
//! scene's settled heap in the panel's table of runs; the panel in its dark theme.

use std::process::Command;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use particle_lab::scenes::about;
use particle_lab::ui::lab::Lab;
use particle_lab::ui::shell::LabUi;

fn harness(lab: Lab) -> Harness<'static, (LabUi, Lab)> {
    let mut h =
        Harness::builder().with_size([1280.0, 1600.0]).with_accessibility_check(false).build_ui_state(
            |ui, (shell, lab): &mut (LabUi, Lab)| {
                shell.show(ui, lab);
            },
            (LabUi::default(), lab),
        );
    h.run_steps(3);
    h
}

#[test]
fn help_about_this_scene_opens_the_scenes_page() {
    let mut h = harness(Lab::new("pendulum", &[]).unwrap());
    assert!(h.query_by_label("About this scene").is_none(), "closed at first");
    h.get_by_label("Help").click();
    h.run_steps(2);
    h.get_by_label("About this scene").click();
    h.run_steps(3);
    let page = about::page("pendulum").unwrap();
    assert!(h.query_by_label(page.title).is_some(), "the window shows the pendulum's page");
    for (heading, body) in page.sections {
        // A heading may also name a panel section ("Energy").
        assert!(h.query_all_by_label(heading).count() >= 1, "heading {heading}");
        assert!(h.query_by_label(body).is_some(), "the paragraph under {heading}");
    }
    assert!(h.state().0.layout.about, "the layout says the window is open");
    // The panel is dark whatever the system's theme, as the contrast test assumes.
    assert_eq!(h.ctx.options(|o| o.theme_preference), egui::ThemePreference::Dark);
    assert_eq!(h.ctx.style_of(egui::Theme::Dark).visuals, particle_lab::ui::style::visuals());
}

/// Every compiled scene's page opens in the window: each paragraph laid out with the
/// panel's fonts (a character they lack would stop the frame).
#[test]
fn every_scenes_page_opens_in_the_window() {
    for entry in particle_lab::scenes::SCENES {
        let name = entry.info().name.to_string();
        let start = if matches!(name.as_str(), "pile" | "hourglass" | "heap") {
            vec!["count=10".into()]
        } else {
            vec![]
        };
        let mut h = harness(Lab::new(&name, &start).unwrap());
        h.state_mut().0.layout.about = true;
        h.run_steps(3);
        let page = about::page(&name).unwrap();
        assert!(h.query_by_label(page.title).is_some(), "{name}'s page");
        for (_, body) in page.sections {
            assert!(h.query_by_label(body).is_some(), "{name}: {body}");
        }
    }
}

#[test]
fn a_scene_file_shows_its_summary_above_the_files_page() {
    let mut h = harness(Lab::new("chain", &[]).unwrap());
    h.state_mut().0.layout.about = true;
    h.run_steps(3);
    let summary = h.state().1.entry.info().summary.to_string();
    // Under the scene's name in the panel, and in the window.
    assert_eq!(h.query_all_by_label(&summary).count(), 2, "the file's own summary");
    assert!(h.query_by_label(about::FILE_PAGE.sections[0].1).is_some(), "the page shared by files");
}

#[test]
fn scenes_about_prints_the_same_page_and_refuses_an_unknown_scene() {
    let lab = || Command::new(env!("CARGO_BIN_EXE_particle-lab"));
    let out = lab().args(["scenes", "--about", "cradle"]).output().unwrap();
    assert!(out.status.success());
    assert_eq!(String::from_utf8(out.stdout).unwrap(), about::page("cradle").unwrap().text());
    let out = lab().args(["scenes", "--about", "no-such"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("unknown scene 'no-such'"), "{err}");
}

/// A settled heap is a row of the panel's table of runs, with its angle.
#[test]
fn a_settled_heap_is_a_row_of_the_panels_table() {
    let mut lab = Lab::new("heap", &[]).unwrap();
    lab.run_steps(2400);
    let table = lab.scene.runs().expect("the heap keeps a table");
    assert_eq!(table.rows.len(), 1, "one heap settled");
    let repose_column = table.columns.iter().position(|c| c.key == "repose_deg").unwrap();
    let repose = table.rows[0][repose_column];
    let shown = particle_lab::scenes::runs::significant(repose, particle_lab::scenes::runs::FIGURES);
    let mut h = harness(lab);
    assert!(h.query_by_label("repose (°)").is_some(), "the column's heading");
    assert!(h.query_by_label(&shown).is_some(), "the angle, {shown}, in the table");
    assert!(h.query_by_label("angle of repose").is_some(), "and the read-out");
    h.run_steps(1);
}
