//! The keyboard and mouse controls: one table, [`SHORTCUTS`], that the key handler
//! reads and the Help window lists, so the two cannot disagree.

use egui::{Key, Modifiers};

use super::lab::{Lab, Purpose};
use super::layout::PanelLayout;
use crate::scenes::{LOAD_STEP, SceneAction};

/// What a control does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Command {
    /// Pause or resume.
    Pause,
    /// One physics step (pauses).
    Step,
    /// Rebuild the scene with its current parameters.
    Reset,
    /// Fire a round (projectile).
    Fire,
    /// Keep the state to go back to.
    QuickSave,
    /// Go back to the kept state.
    QuickLoad,
    /// Hide or show the side panel.
    Panel,
    /// The 2D side view on or off.
    SideView,
    /// The tape measure on or off.
    Tape,
    /// Frame the scene (follow goes off).
    Frame,
    /// Save a screenshot.
    Screenshot,
    /// Open or close the Controls window.
    Help,
    /// Close the window.
    Quit,
    /// Open a file or save one, as the File menu's item does: the platform's dialog,
    /// or the lab's path field where none opens.
    Ask(Purpose),
    /// Move the bridge's load by (dx, dz) deck pairs.
    MoveLoad(f32, f32),
    /// Open the builder on a copy of the scene, or, building, play.
    Build,
    /// Undo the builder's last edit.
    Undo,
    /// Redo the builder's last edit undone.
    Redo,
    /// Delete the builder's selected particle.
    Delete,
    /// Text and controls larger (+1) or smaller (-1) by a step, or (0) back to 100%.
    TextSize(i32),
}

/// How a control is reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Binding {
    /// Any of these keys, with these modifiers.
    Keys(Modifiers, &'static [Key]),
    /// With the mouse in the 3D view (handled by the view, listed for the reader).
    Mouse,
}

/// One row of the controls table.
#[derive(Clone, Copy, Debug)]
pub struct Shortcut {
    /// The keys as the Help window writes them.
    pub keys: &'static str,
    /// What it does, in a few words.
    pub meaning: &'static str,
    /// How it is reached.
    pub binding: Binding,
    /// What it does; `None` for the mouse's rows, which the 3D view handles.
    pub command: Option<Command>,
}

const fn key(keys: &'static str, meaning: &'static str, key: &'static [Key], command: Command) -> Shortcut {
    Shortcut { keys, meaning, binding: Binding::Keys(Modifiers::NONE, key), command: Some(command) }
}

const fn mouse(keys: &'static str, meaning: &'static str) -> Shortcut {
    Shortcut { keys, meaning, binding: Binding::Mouse, command: None }
}

/// Every control, in the order the Help window lists them.
pub const SHORTCUTS: &[Shortcut] = &[
    key("Space", "pause / resume (building: play)", &[Key::Space], Command::Pause),
    key(".", "one physics step", &[Key::Period], Command::Step),
    key("R", "reset the scene", &[Key::R], Command::Reset),
    key("F", "fire (projectile)", &[Key::F], Command::Fire),
    key("F5", "quick save the state", &[Key::F5], Command::QuickSave),
    key("F9", "back to the quick save", &[Key::F9], Command::QuickLoad),
    key("P", "hide / show the panel", &[Key::P], Command::Panel),
    key("V", "2D side view on / off", &[Key::V], Command::SideView),
    key("M", "tape measure on / off", &[Key::M], Command::Tape),
    key("Home", "frame the scene (follow off)", &[Key::Home], Command::Frame),
    key("F12", "save a screenshot", &[Key::F12], Command::Screenshot),
    key("F1", "this list of controls", &[Key::F1], Command::Help),
    key("B", "build: edit a copy of the scene / play what is built", &[Key::B], Command::Build),
    key("Delete", "delete the selected particle (building)", &[Key::Delete], Command::Delete),
    // Before Ctrl+Z, which would take Ctrl+Shift+Z too (egui matches it ignoring Shift).
    Shortcut {
        keys: "Ctrl+Shift+Z",
        meaning: "redo (building)",
        binding: Binding::Keys(Modifiers::COMMAND.plus(Modifiers::SHIFT), &[Key::Z]),
        command: Some(Command::Redo),
    },
    Shortcut {
        keys: "Ctrl+Z",
        meaning: "undo (building)",
        binding: Binding::Keys(Modifiers::COMMAND, &[Key::Z]),
        command: Some(Command::Undo),
    },
    Shortcut {
        keys: "Ctrl+Y",
        meaning: "redo (building)",
        binding: Binding::Keys(Modifiers::COMMAND, &[Key::Y]),
        command: Some(Command::Redo),
    },
    Shortcut {
        keys: "Ctrl+Q",
        meaning: "quit",
        binding: Binding::Keys(Modifiers::COMMAND, &[Key::Q]),
        command: Some(Command::Quit),
    },
    Shortcut {
        keys: "Ctrl+O",
        meaning: "open a scene file",
        binding: Binding::Keys(Modifiers::COMMAND, &[Key::O]),
        command: Some(Command::Ask(Purpose::OpenScene)),
    },
    // Before Ctrl+S, which would take Ctrl+Shift+S too (egui matches it ignoring Shift).
    Shortcut {
        keys: "Ctrl+Shift+S",
        meaning: "save the scene as a scene file",
        binding: Binding::Keys(Modifiers::COMMAND.plus(Modifiers::SHIFT), &[Key::S]),
        command: Some(Command::Ask(Purpose::SaveScene)),
    },
    Shortcut {
        keys: "Ctrl+S",
        meaning: "save a snapshot",
        binding: Binding::Keys(Modifiers::COMMAND, &[Key::S]),
        command: Some(Command::Ask(Purpose::SaveSnapshot)),
    },
    key(
        "Left / A",
        "move the load left (bridge)",
        &[Key::ArrowLeft, Key::A],
        Command::MoveLoad(-LOAD_STEP, 0.0),
    ),
    key(
        "Right / D",
        "move the load right (bridge)",
        &[Key::ArrowRight, Key::D],
        Command::MoveLoad(LOAD_STEP, 0.0),
    ),
    key("Up / W", "move the load back (bridge)", &[Key::ArrowUp, Key::W], Command::MoveLoad(0.0, -LOAD_STEP)),
    key(
        "Down / S",
        "move the load forward (bridge)",
        &[Key::ArrowDown, Key::S],
        Command::MoveLoad(0.0, LOAD_STEP),
    ),
    Shortcut {
        keys: "Ctrl+= / Ctrl++",
        meaning: "larger text and controls (View > Text size)",
        binding: Binding::Keys(Modifiers::COMMAND, &[Key::Equals, Key::Plus]),
        command: Some(Command::TextSize(1)),
    },
    Shortcut {
        keys: "Ctrl+-",
        meaning: "smaller text and controls",
        binding: Binding::Keys(Modifiers::COMMAND, &[Key::Minus]),
        command: Some(Command::TextSize(-1)),
    },
    Shortcut {
        keys: "Ctrl+0",
        meaning: "text size back to 100%",
        binding: Binding::Keys(Modifiers::COMMAND, &[Key::Num0]),
        command: Some(Command::TextSize(0)),
    },
    mouse("Left drag on a particle", "drag it (let go to throw); a hard pull tears cloth"),
    mouse("Click a particle", "inspect it (click empty space to clear)"),
    mouse("Left drag elsewhere", "orbit the camera (pan in the side view)"),
    mouse("Right or middle drag", "pan"),
    mouse("Wheel", "zoom"),
];

/// Runs the commands whose keys were pressed this frame (none while a text field
/// has the keyboard).
pub fn handle(ctx: &egui::Context, lab: &mut Lab, layout: &mut PanelLayout) {
    if ctx.egui_wants_keyboard_input() {
        return;
    }
    // The lab and the layout are not egui's: each command runs as its key is consumed.
    ctx.input_mut(|input| {
        for shortcut in SHORTCUTS {
            let (Binding::Keys(modifiers, keys), Some(command)) = (shortcut.binding, shortcut.command) else {
                continue;
            };
            for &key in keys {
                if input.consume_key(modifiers, key) {
                    run(command, lab, layout);
                }
            }
        }
    });
}

/// Does what `command` says, as its key or its button would.
pub fn run(command: Command, lab: &mut Lab, layout: &mut PanelLayout) {
    match command {
        Command::Pause if lab.editing() => lab.play(),
        Command::Pause => {
            lab.paused = !lab.paused;
            log::info!("paused: {}", lab.paused);
            if lab.paused {
                // What the window test compares with `simulate`'s hash at that step.
                log::info!("paused at step {}, state hash {}", lab.scene.world().steps(), lab.state_hash());
            }
        }
        Command::Step => {
            lab.paused = true;
            lab.run_steps(1);
        }
        Command::Reset => lab.reset(),
        Command::Fire => lab.act(SceneAction::Fire),
        Command::QuickSave => lab.quick_save(),
        Command::QuickLoad => lab.quick_load(),
        Command::Panel => {
            layout.open = !layout.open;
            log::info!("panel open: {}", layout.open);
        }
        Command::SideView => {
            let side = !lab.side_view;
            lab.set_side_view(side);
        }
        Command::Tape => lab.set_tape(!lab.tape),
        Command::Frame => lab.home(),
        Command::Screenshot => lab.requests.screenshot = true,
        Command::Help => layout.help = !layout.help,
        Command::Quit => lab.requests.quit = true,
        Command::Ask(purpose) => lab.requests.file = Some(purpose),
        Command::MoveLoad(dx, dz) => lab.act(SceneAction::MoveLoad { dx, dz }),
        Command::Build => {
            if lab.editing() {
                lab.play();
            } else {
                lab.edit_copy();
            }
        }
        Command::Undo => lab.undo(),
        Command::Redo => lab.redo(),
        Command::Delete => lab.delete_selected(),
        Command::TextSize(0) => layout.text_size = 100,
        Command::TextSize(steps) => layout.step_text_size(steps),
    }
}
