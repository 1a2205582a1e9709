//! The File menu: open a scene file, save and load snapshots, quick save. Open and
//! Save go through the platform's file dialog (the `rfd` crate: the desktop portal,
//! else zenity). Where no dialog can open (a bare X server, a remote session, a
//! container) the same items open a path field of the lab's own instead, and the
//! status line says why; the typed paths in the menu are the same fields, for those
//! who prefer typing. Both complete what is typed from its folder (the scene files
//! or snapshots and the folders there; `ui/path_completion.rs`): Tab completes, a
//! click on an entry takes it, Enter opens or saves. In a browser files come from the
//! browser's file chooser and snapshots go out as downloads. Copy link gives the link
//! that opens the experiment on screen in the web lab.

#[cfg(not(target_arch = "wasm32"))]
use std::path::{Path, PathBuf};
#[cfg(not(target_arch = "wasm32"))]
use std::time::Duration;

use egui::containers::menu::{MenuButton, MenuConfig};
#[cfg(not(target_arch = "wasm32"))]
use web_time::Instant;

use crate::ui::keys::{self, Command};
use crate::ui::lab::Lab;
pub use crate::ui::lab::Purpose;
use crate::ui::layout::PanelLayout;
#[cfg(not(target_arch = "wasm32"))]
use crate::ui::path_completion::{self, Completion};

/// Where the shipped scene files are, the dialog's first folder.
pub const SCENE_FOLDER: &str = "assets/scenes";

/// What Save scene as… does, on its button.
const SAVE_SCENE_HELP: &str = "The scene as a scene file, with the sliders' values as its defaults, to open \
                               again, edit or share";

/// The status line's word when a working dialog was cancelled.
pub const NO_FILE_CHOSEN: &str = "No file chosen";

/// A dialog that gave nothing sooner than this after it was asked failed to open: no
/// one sees a dialog and cancels it that fast. (rfd's `None` means either; where it
/// could not reach a portal nor start zenity it comes back within milliseconds.)
#[cfg(not(target_arch = "wasm32"))]
pub const FAILED_WITHIN: Duration = Duration::from_millis(300);

/// Why no dialog opens, where one was tried and failed.
#[cfg(not(target_arch = "wasm32"))]
const DIALOG_FAILED: &str = "the desktop portal and zenity failed, the log says why";

/// How long a listed folder is trusted before it is listed again (while the same
/// text stays typed).
#[cfg(not(target_arch = "wasm32"))]
const RELIST_AFTER: Duration = Duration::from_secs(1);

/// Rows of completions shown below a path field before they scroll.
#[cfg(not(target_arch = "wasm32"))]
const LIST_ROWS: f32 = 8.0;

/// Whether the platform's file dialog opens, as far as is known.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Dialogs {
    /// Not tried yet, or only cancelled (slowly, by a person).
    #[default]
    Unknown,
    /// It gave a file once: a `None` since is a cancel, however fast.
    Work,
    /// None can open: why, for the status line.
    Missing(&'static str),
}

/// A folder's completions as last listed for a field, so a frame does not list the
/// folder again while the same text stays typed.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Debug, Default)]
struct Listing {
    typed: String,
    extension: &'static str,
    at: Option<Instant>,
    found: Option<Result<Completion, String>>,
    /// The completions are shown under the field (from when it has the focus until
    /// it opens or saves).
    shown: bool,
}

#[cfg(not(target_arch = "wasm32"))]
impl Listing {
    /// What `typed` completes to among its folder's `extension` files and folders.
    fn of(&mut self, typed: &str, extension: &'static str) -> &Result<Completion, String> {
        let stale = self.at.is_none_or(|at| at.elapsed() >= RELIST_AFTER);
        if self.found.is_none() || stale || self.typed != typed || self.extension != extension {
            self.typed = typed.to_string();
            self.extension = extension;
            self.at = Some(Instant::now());
            self.found = Some(path_completion::complete(typed, &[extension]));
        }
        self.found.get_or_insert_with(|| path_completion::complete(typed, &[extension]))
    }
}

/// The File menu's drafts: the typed paths, the path field's window and what is known
/// of the file dialog.
#[derive(Debug)]
pub struct FileMenu {
    /// The scene file path being typed.
    pub scene_path: String,
    /// Where Save scene as… writes, when typed.
    pub save_scene_path: String,
    /// Where Save and Load snapshot write and read.
    pub snapshot_path: String,
    /// The path field's window, open for this, standing in for a file dialog that
    /// cannot open.
    pub prompt: Option<Purpose>,
    /// The path field's window has just opened: its field takes the keyboard.
    #[cfg(not(target_arch = "wasm32"))]
    focus_prompt: bool,
    #[cfg(not(target_arch = "wasm32"))]
    dialogs: Dialogs,
    #[cfg(not(target_arch = "wasm32"))]
    scene_listing: Listing,
    #[cfg(not(target_arch = "wasm32"))]
    snapshot_listing: Listing,
    #[cfg(not(target_arch = "wasm32"))]
    prompt_listing: Listing,
}

impl Default for FileMenu {
    fn default() -> Self {
        Self {
            scene_path: String::new(),
            save_scene_path: String::new(),
            snapshot_path: "snapshot.json".into(),
            prompt: None,
            #[cfg(not(target_arch = "wasm32"))]
            focus_prompt: false,
            #[cfg(not(target_arch = "wasm32"))]
            dialogs: Dialogs::Unknown,
            #[cfg(not(target_arch = "wasm32"))]
            scene_listing: Listing::default(),
            #[cfg(not(target_arch = "wasm32"))]
            snapshot_listing: Listing::default(),
            #[cfg(not(target_arch = "wasm32"))]
            prompt_listing: Listing::default(),
        }
    }
}

/// Asks the platform for a file to open (or, for a save, a file to write). `None`
/// from rfd means cancelled or no dialog at all: [`FileMenu::ask`] tells them apart.
#[cfg(not(target_arch = "wasm32"))]
fn dialog(purpose: Purpose) -> Option<PathBuf> {
    let folder = match purpose {
        Purpose::OpenScene => Path::new(SCENE_FOLDER),
        Purpose::OpenSnapshot | Purpose::SaveSnapshot | Purpose::SaveScene => Path::new("."),
    };
    // The portal takes an absolute folder.
    let folder = std::path::absolute(folder).unwrap_or_else(|_| folder.to_path_buf());
    let dialog =
        rfd::FileDialog::new().add_filter(purpose.kind(), &[purpose.extension()]).set_directory(folder);
    if purpose.saves() { dialog.save_file() } else { dialog.pick_file() }
}

/// Why no file dialog can open here, when that is certain before trying; `None` when
/// one may. rfd's `xdg-portal` backend asks the desktop portal over the D-Bus session
/// bus and, where that fails, runs `zenity` (it knows no other program, kdialog
/// included): with no `zenity` on `PATH` and no session bus to reach a portal on (no
/// `DBUS_SESSION_BUS_ADDRESS`, no `$XDG_RUNTIME_DIR/bus`, no `dbus-launch` for
/// libdbus to start one with) it can show nothing. `var` reads the environment,
/// `exists` says whether a path names something other than a folder.
#[cfg(not(target_arch = "wasm32"))]
fn no_dialog(
    var: &dyn Fn(&str) -> Option<std::ffi::OsString>,
    exists: &dyn Fn(&Path) -> bool,
) -> Option<&'static str> {
    // Windows' and macOS's own dialogs are always there.
    if !cfg!(all(unix, not(target_os = "macos"))) {
        return None;
    }
    let set = |name: &str| var(name).filter(|value| !value.is_empty());
    let path = set("PATH").unwrap_or_default();
    let on_path = |program: &str| std::env::split_paths(&path).any(|dir| exists(&dir.join(program)));
    let bus = set("DBUS_SESSION_BUS_ADDRESS").is_some()
        || set("XDG_RUNTIME_DIR").is_some_and(|dir| exists(&Path::new(&dir).join("bus")))
        || on_path("dbus-launch")
        || exists(Path::new("/usr/bin/dbus-launch"));
    (!on_path("zenity") && !bus).then_some("no desktop portal and no zenity")
}

/// [`no_dialog`] in this process's environment.
#[cfg(not(target_arch = "wasm32"))]
fn no_dialog_here() -> Option<&'static str> {
    no_dialog(&|name| std::env::var_os(name), &|path| std::fs::metadata(path).is_ok_and(|m| !m.is_dir()))
}

impl FileMenu {
    /// Draws the menu. It stays open while a path is typed (a menu closes on any
    /// click by default, the text field's too).
    pub fn ui(&mut self, ui: &mut egui::Ui, lab: &mut Lab, layout: &mut PanelLayout) {
        let config = MenuConfig::new().close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside);
        MenuButton::new("File").config(config).ui(ui, |ui| {
            #[cfg(target_arch = "wasm32")]
            {
                Self::page_items(ui, lab);
                ui.separator();
                Self::quick_save_items(ui, lab, layout);
                ui.separator();
                Self::link_item(ui, lab);
            }
            #[cfg(not(target_arch = "wasm32"))]
            {
                self.scene_items(ui, lab);
                ui.separator();
                self.snapshot_items(ui, lab);
                ui.separator();
                Self::quick_save_items(ui, lab, layout);
                ui.separator();
                Self::link_item(ui, lab);
                // Last, so that no item above moves when a scene file is open (a click
                // meant for one hit another).
                if let Some((_, Some(path))) = lab.scene.source() {
                    ui.separator();
                    ui.label(format!("Watching {} for changes", path.display()));
                }
            }
        });
    }

    /// In a browser: files come from the visitor's disk through the browser's file
    /// chooser, and snapshots go back as downloads.
    #[cfg(target_arch = "wasm32")]
    fn page_items(ui: &mut egui::Ui, lab: &mut Lab) {
        if ui.button("Open scene file…").on_hover_text("A TOML scene file from your disk").clicked() {
            crate::ui::page::pick_file(crate::ui::page::FileKind::Scene);
            ui.close();
        }
        if ui.button("Download snapshot").on_hover_text("The whole state, as a JSON file").clicked() {
            Self::download_snapshot(lab);
            ui.close();
        }
        if ui.button("Open snapshot…").on_hover_text("A snapshot JSON file from your disk").clicked() {
            crate::ui::page::pick_file(crate::ui::page::FileKind::Snapshot);
            ui.close();
        }
        let saveable = crate::scenes::file::writable(&lab.entry);
        let download = ui
            .add_enabled(saveable.is_ok(), egui::Button::new("Download scene file"))
            .on_hover_text(SAVE_SCENE_HELP)
            .on_disabled_hover_text(saveable.err().unwrap_or_default());
        if download.clicked() {
            Self::download_scene(lab);
            ui.close();
        }
    }

    /// In a browser: the scene file goes out as a download.
    #[cfg(target_arch = "wasm32")]
    fn download_scene(lab: &mut Lab) {
        lab.status = match lab.scene_file_text().and_then(|(name, text)| {
            crate::ui::page::download(&name, "application/toml", text.as_bytes()).map(|()| name)
        }) {
            Ok(name) => format!("Downloaded {name}"),
            Err(error) => error,
        };
    }

    /// In a browser: the snapshot goes out as a download.
    #[cfg(target_arch = "wasm32")]
    fn download_snapshot(lab: &mut Lab) {
        lab.status = match lab.snapshot_download().and_then(|(name, text)| {
            crate::ui::page::download(&name, "application/json", text.as_bytes()).map(|()| name)
        }) {
            Ok(name) => format!("Downloaded {name}"),
            Err(error) => error,
        };
    }

    /// What a key asking for a file does (Ctrl+O, Ctrl+S): what the File menu's item
    /// for `purpose` does.
    pub fn asked(&mut self, purpose: Purpose, lab: &mut Lab) {
        #[cfg(not(target_arch = "wasm32"))]
        self.ask(purpose, lab);
        #[cfg(target_arch = "wasm32")]
        {
            let _ = self;
            match purpose {
                Purpose::OpenScene => crate::ui::page::pick_file(crate::ui::page::FileKind::Scene),
                Purpose::OpenSnapshot => crate::ui::page::pick_file(crate::ui::page::FileKind::Snapshot),
                Purpose::SaveSnapshot => Self::download_snapshot(lab),
                Purpose::SaveScene => Self::download_scene(lab),
            }
        }
    }

    /// Copy link: the query string that opens this experiment as it is now.
    fn link_item(ui: &mut egui::Ui, lab: &mut Lab) {
        let hover = "A link that opens this scene with its parameters, solver and integrator in the web \
                     version of the lab";
        if ui.button("Copy link").on_hover_text(hover).clicked() {
            let query = match crate::ui::lab::Link::of(lab, false) {
                Ok(query) => query,
                Err(message) => {
                    lab.status = message;
                    ui.close();
                    return;
                }
            };
            #[cfg(target_arch = "wasm32")]
            {
                lab.status = format!("Link copied: {}", crate::ui::page::copy_link(&query));
            }
            #[cfg(not(target_arch = "wasm32"))]
            {
                ui.ctx().copy_text(query.clone());
                lab.status = format!("Link (after the web page's address): {query}");
            }
            ui.close();
        }
    }

    /// The scene items: Open… through the dialog, and the typed path.
    #[cfg(not(target_arch = "wasm32"))]
    fn scene_items(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        let open = egui::Button::new("Open scene file…").shortcut_text("Ctrl+O");
        if ui.add(open).on_hover_text("A TOML scene file, in the file dialog").clicked() {
            ui.close();
            self.ask(Purpose::OpenScene, lab);
        }
        ui.label("or type its path:");
        let field =
            PathField { id: "scene path", hint: "assets/scenes/cloth.toml", extension: "toml", width: 260.0 };
        let entered = field.show(ui, &mut self.scene_path, &mut self.scene_listing, lab, false);
        if (ui.button("Open").clicked() || entered) && self.act_typed(Purpose::OpenScene, lab) {
            ui.close();
        }
        let saveable = crate::scenes::file::writable(&lab.entry);
        let save = ui
            .add_enabled(saveable.is_ok(), egui::Button::new("Save scene as…").shortcut_text("Ctrl+Shift+S"))
            .on_hover_text(SAVE_SCENE_HELP)
            .on_disabled_hover_text(saveable.err().unwrap_or_default());
        if save.clicked() {
            ui.close();
            self.ask(Purpose::SaveScene, lab);
        }
    }

    /// The snapshot items: Save as… and Open… through the dialog, the typed path
    /// with Save and Load, and the quick save keys.
    #[cfg(not(target_arch = "wasm32"))]
    fn snapshot_items(&mut self, ui: &mut egui::Ui, lab: &mut Lab) {
        ui.horizontal(|ui| {
            if ui.add(egui::Button::new("Save snapshot as…").shortcut_text("Ctrl+S")).clicked() {
                ui.close();
                self.ask(Purpose::SaveSnapshot, lab);
            }
            if ui.button("Open snapshot…").clicked() {
                ui.close();
                self.ask(Purpose::OpenSnapshot, lab);
            }
        });
        ui.label("Snapshot file").on_hover_text(
            "A snapshot holds the whole state: scene, parameters, solver, every particle and link, time",
        );
        let field = PathField { id: "snapshot path", hint: "snapshot.json", extension: "json", width: 260.0 };
        let entered = field.show(ui, &mut self.snapshot_path, &mut self.snapshot_listing, lab, false);
        ui.horizontal(|ui| {
            if ui.button("Save snapshot").clicked() && self.act_typed(Purpose::SaveSnapshot, lab) {
                ui.close();
            }
            let load = ui
                .button("Load snapshot")
                .on_hover_text("A bad file changes nothing; the status line says why");
            if (load.clicked() || entered) && self.act_typed(Purpose::OpenSnapshot, lab) {
                ui.close();
            }
        });
    }

    /// What a dialog item does: the platform's dialog where one opens, else the path
    /// field's window, with the status line saying why. A dialog that gives nothing
    /// is a cancel ("No file chosen") unless it came back faster than a person could
    /// cancel ([`FAILED_WITHIN`]) before any dialog had worked: then it could not open.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn ask(&mut self, purpose: Purpose, lab: &mut Lab) {
        if purpose == Purpose::SaveScene
            && let Err(why) = crate::scenes::file::writable(&lab.entry)
        {
            log::info!("cannot save the scene as a file: {why}");
            lab.status = why;
            return;
        }
        if self.dialogs == Dialogs::Unknown
            && let Some(reason) = no_dialog_here()
        {
            log::info!("no file dialog can open ({reason}): the File menu takes typed paths");
            self.dialogs = Dialogs::Missing(reason);
        }
        if let Dialogs::Missing(reason) = self.dialogs {
            self.open_prompt(purpose, lab, reason);
            return;
        }
        let asked = Instant::now();
        let chosen = dialog(purpose);
        let took = asked.elapsed();
        match chosen {
            Some(path) => {
                self.dialogs = Dialogs::Work;
                match purpose {
                    Purpose::OpenScene => self.scene_path = path.display().to_string(),
                    Purpose::SaveScene => self.save_scene_path = path.display().to_string(),
                    Purpose::OpenSnapshot | Purpose::SaveSnapshot => {
                        self.snapshot_path = path.display().to_string();
                    }
                }
                Self::act(purpose, &path, lab);
            }
            None if self.dialogs == Dialogs::Unknown && took < FAILED_WITHIN => {
                log::warn!(
                    "the file dialog gave nothing after {} ms, too soon for a cancel: it could not open; the File \
                     menu takes typed paths",
                    took.as_millis()
                );
                self.dialogs = Dialogs::Missing(DIALOG_FAILED);
                self.open_prompt(purpose, lab, DIALOG_FAILED);
            }
            None => {
                log::info!("the file dialog was cancelled after {} ms", took.as_millis());
                lab.status = NO_FILE_CHOSEN.into();
            }
        }
    }

    /// Opens the path field's window for `purpose`, saying why in the status line.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn open_prompt(&mut self, purpose: Purpose, lab: &mut Lab, reason: &str) {
        let verb = if purpose.saves() { "saves" } else { "opens" };
        if purpose == Purpose::SaveScene && self.save_scene_path.is_empty() {
            self.save_scene_path = lab.scene_file_text().map(|(name, _)| name).unwrap_or_default();
        }
        lab.status =
            format!("No file dialog on this system ({reason}): type a path (Tab completes, Enter {verb})");
        self.prompt = Some(purpose);
        self.focus_prompt = true;
        self.prompt_listing.shown = true;
    }

    /// The path field's window, while a dialog item is waiting for a typed path: the
    /// field with its completions, the button that opens or saves, and Cancel (or
    /// Escape). It closes once the file opened or was saved; on an error it stays, and
    /// the status line says why.
    pub fn prompt_ui(&mut self, ctx: &egui::Context, lab: &mut Lab) {
        #[cfg(target_arch = "wasm32")]
        let _ = (ctx, lab);
        #[cfg(not(target_arch = "wasm32"))]
        {
            let Some(purpose) = self.prompt else { return };
            let mut open = true;
            let (mut go, mut cancel) = (false, false);
            // Asked for until a frame begins with it: the click that opened the window
            // may take it away again in the frame it was given.
            if ctx.memory(|m| m.has_focus(PathField::id("prompt path"))) {
                self.focus_prompt = false;
            }
            let focus = self.focus_prompt;
            let Self { scene_path, save_scene_path, snapshot_path, prompt_listing, .. } = self;
            let text = match purpose {
                Purpose::OpenScene => scene_path,
                Purpose::SaveScene => save_scene_path,
                Purpose::OpenSnapshot | Purpose::SaveSnapshot => snapshot_path,
            };
            egui::Window::new(purpose.title())
                .id(egui::Id::unique("path prompt"))
                .open(&mut open)
                .collapsible(false)
                .resizable(false)
                .default_pos([24.0, 48.0])
                .show(ctx, |ui| {
                    ui.label(format!("The path of a {} (.{}):", purpose.kind(), purpose.extension()));
                    let field = PathField {
                        id: "prompt path",
                        hint: match purpose {
                            Purpose::OpenScene => "assets/scenes/chain.toml",
                            Purpose::SaveScene => "my-experiment.toml",
                            Purpose::OpenSnapshot | Purpose::SaveSnapshot => "snapshot.json",
                        },
                        extension: purpose.extension(),
                        width: 380.0,
                    };
                    go = field.show(ui, text, prompt_listing, lab, focus);
                    ui.horizontal(|ui| {
                        go |= ui.button(purpose.action()).clicked();
                        cancel = ui.button("Cancel").clicked();
                    });
                });
            cancel |= ctx.input(|i| i.key_pressed(egui::Key::Escape));
            if go && self.act_typed(purpose, lab) {
                cancel = true;
            }
            if cancel || !open {
                self.prompt = None;
            }
        }
    }

    /// Opens or saves the typed path for `purpose`; true if that worked (the status
    /// line says what happened either way).
    #[cfg(not(target_arch = "wasm32"))]
    fn act_typed(&mut self, purpose: Purpose, lab: &mut Lab) -> bool {
        let typed = match purpose {
            Purpose::OpenScene => self.scene_path.trim(),
            Purpose::SaveScene => self.save_scene_path.trim(),
            Purpose::OpenSnapshot | Purpose::SaveSnapshot => self.snapshot_path.trim(),
        };
        if typed.is_empty() {
            lab.status = format!("Type the path of a {} first", purpose.kind());
            return false;
        }
        let path = path_completion::expand_home(typed);
        let done = Self::act(purpose, &path, lab);
        if done {
            for listing in [&mut self.scene_listing, &mut self.snapshot_listing, &mut self.prompt_listing] {
                listing.shown = false;
            }
        }
        done
    }

    /// Opens or saves `path` for `purpose`; true if that worked. A snapshot that
    /// cannot be read, or a folder that is not there to save in, is said before
    /// anything changes.
    #[cfg(not(target_arch = "wasm32"))]
    fn act(purpose: Purpose, path: &Path, lab: &mut Lab) -> bool {
        let shown = crate::messages::path(path);
        match purpose {
            Purpose::OpenScene => lab.open_scene_file(path),
            Purpose::OpenSnapshot => match crate::scenes::snapshot::Snapshot::load(path) {
                Ok(_) => {
                    lab.load_snapshot_from(path);
                    true
                }
                Err(error) => {
                    lab.status = error;
                    false
                }
            },
            Purpose::SaveSnapshot | Purpose::SaveScene => {
                let folder = match path.parent() {
                    Some(parent) if !parent.as_os_str().is_empty() => parent,
                    _ => Path::new("."),
                };
                if path.is_dir() {
                    lab.status = format!("cannot save to {shown}: it is a folder; type a file name after it");
                    false
                } else if !folder.is_dir() {
                    lab.status =
                        format!("cannot save to {shown}: no folder {}", crate::messages::path(folder));
                    false
                } else if purpose == Purpose::SaveScene {
                    lab.save_scene_to(path)
                } else {
                    lab.save_snapshot_to(path);
                    true
                }
            }
        }
    }

    /// Quick save and back to it (F5, F9).
    fn quick_save_items(ui: &mut egui::Ui, lab: &mut Lab, layout: &mut PanelLayout) {
        if ui.button("Quick save (F5)").clicked() {
            keys::run(Command::QuickSave, lab, layout);
            ui.close();
        }
        if ui.button("Back to quick save (F9)").clicked() {
            keys::run(Command::QuickLoad, lab, layout);
            ui.close();
        }
    }
}

/// A path field with completion: the text field, and under it (once it has had the
/// focus) the entries of the typed folder that match, folders first. Tab completes
/// as far as the entries agree (a folder's `/` included), a click on an entry takes
/// it, a double click on a file takes it and acts; a folder that cannot be listed
/// is one line in the status line when Tab is pressed.
#[cfg(not(target_arch = "wasm32"))]
struct PathField {
    id: &'static str,
    hint: &'static str,
    extension: &'static str,
    width: f32,
}

#[cfg(not(target_arch = "wasm32"))]
impl PathField {
    /// The text field's id.
    fn id(name: &'static str) -> egui::Id {
        egui::Id::unique(("path field", name))
    }

    /// Draws the field; true when Enter was pressed in it (or a file double-clicked).
    fn show(
        &self,
        ui: &mut egui::Ui,
        text: &mut String,
        listing: &mut Listing,
        lab: &mut Lab,
        focus: bool,
    ) -> bool {
        let id = Self::id(self.id);
        let edit = egui::TextEdit::singleline(text).id(id).hint_text(self.hint).desired_width(self.width);
        // Tab stays in the field, to complete.
        let filter = edit.get_event_filter();
        let edit = edit.event_filter(egui::EventFilter { tab: true, ..filter });
        let response = ui.add(edit);
        if focus {
            response.request_focus();
            // What the field holds is selected, as a dialog selects its file name:
            // typing replaces it, an arrow key keeps it.
            let mut state = egui::text_edit::TextEditState::load(ui.ctx(), id).unwrap_or_default();
            let (start, end) = (egui::text::CCursor::new(0), egui::text::CCursor::new(text.chars().count()));
            state.cursor.set_char_range(Some(egui::text::CCursorRange::two(start, end)));
            state.store(ui.ctx(), id);
        }
        if response.has_focus() {
            listing.shown = true;
        }
        let mut entered = response.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        let mut chosen = None;
        if response.has_focus() && ui.input_mut(|i| i.consume_key(egui::Modifiers::NONE, egui::Key::Tab)) {
            match listing.of(text, self.extension) {
                Ok(completion) => chosen = Some(completion.completed()),
                Err(error) => lab.status = error.clone(),
            }
        }
        if listing.shown
            && !entered
            && let Ok(completion) = listing.of(text, self.extension)
        {
            let (taken, acted) = Self::entries(ui, completion, self.width);
            entered |= acted;
            chosen = chosen.or(taken);
        }
        if let Some(new) = chosen {
            if new != *text {
                *text = new;
                // The cursor after the completion, to type on.
                let mut state = egui::text_edit::TextEditState::load(ui.ctx(), id).unwrap_or_default();
                let end = egui::text::CCursor::new(text.chars().count());
                state.cursor.set_char_range(Some(egui::text::CCursorRange::one(end)));
                state.store(ui.ctx(), id);
            }
            if !entered {
                response.request_focus();
            }
        }
        entered
    }

    /// The completions, scrolling past [`LIST_ROWS`]; what a click took (and whether a
    /// file was double-clicked).
    fn entries(ui: &mut egui::Ui, completion: &Completion, width: f32) -> (Option<String>, bool) {
        if completion.entries.is_empty() {
            return (None, false);
        }
        let (mut taken, mut acted) = (None, false);
        let row = ui.text_style_height(&egui::TextStyle::Button) + ui.spacing().button_padding.y * 2.0;
        let count = completion.entries.len();
        egui::ScrollArea::vertical()
            .id_salt(("completions", &completion.folder))
            .max_height(row * LIST_ROWS)
            .max_width(width)
            .auto_shrink([false, true])
            .show_rows(ui, row, count, |ui, rows| {
                for entry in &completion.entries[rows] {
                    let label = entry.written();
                    let button = egui::Button::new(label).frame(false);
                    let response = ui.add(button);
                    if response.clicked() {
                        taken = Some(completion.with(entry));
                    }
                    if response.double_clicked() && !entry.folder {
                        taken = Some(completion.with(entry));
                        acted = true;
                    }
                }
            });
        (taken, acted)
    }
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use std::ffi::OsString;

    use super::*;

    /// [`no_dialog`] in an environment of `vars` where the paths `present` exist.
    fn verdict(vars: &[(&str, &str)], present: &[&str]) -> Option<&'static str> {
        let vars: Vec<(String, OsString)> =
            vars.iter().map(|(k, v)| (k.to_string(), OsString::from(v))).collect();
        no_dialog(&|name| vars.iter().find(|(k, _)| k == name).map(|(_, v)| v.clone()), &|path| {
            present.iter().any(|p| Path::new(p) == path)
        })
    }

    #[test]
    fn a_dialog_is_missing_only_without_zenity_and_without_a_session_bus() {
        let path = ("PATH", "/usr/local/bin:/usr/bin");
        assert_eq!(verdict(&[path], &[]), Some("no desktop portal and no zenity"));
        assert_eq!(verdict(&[], &[]), Some("no desktop portal and no zenity"), "no PATH at all");
        assert_eq!(verdict(&[path], &["/usr/bin/zenity"]), None, "zenity on PATH");
        assert_eq!(verdict(&[("PATH", "/opt/z")], &["/opt/z/zenity"]), None);
        assert_eq!(
            verdict(&[path], &["/opt/z/zenity"]),
            Some("no desktop portal and no zenity"),
            "not on PATH"
        );
        assert_eq!(verdict(&[path, ("DBUS_SESSION_BUS_ADDRESS", "unix:path=/run/user/1/bus")], &[]), None);
        assert_eq!(
            verdict(&[path, ("DBUS_SESSION_BUS_ADDRESS", "")], &[]),
            Some("no desktop portal and no zenity")
        );
        assert_eq!(verdict(&[path, ("XDG_RUNTIME_DIR", "/run/user/1")], &["/run/user/1/bus"]), None);
        assert_eq!(
            verdict(&[path, ("XDG_RUNTIME_DIR", "/tmp/private")], &[]),
            Some("no desktop portal and no zenity"),
            "a runtime folder with no bus in it"
        );
        assert_eq!(verdict(&[path], &["/usr/bin/dbus-launch"]), None, "libdbus can start a bus");
    }

    /// One frame of the interface with `events`.
    fn frame(ctx: &egui::Context, menu: &mut FileMenu, lab: &mut Lab, events: Vec<egui::Event>) {
        let time = ctx.input(|i| i.time) + 0.1;
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1280.0, 800.0))),
            events,
            time: Some(time),
            ..Default::default()
        };
        let _ = ctx.run_ui(input, |ui| menu.prompt_ui(ui.ctx(), lab));
    }

    fn key(key: egui::Key) -> Vec<egui::Event> {
        vec![egui::Event::Key {
            key,
            physical_key: None,
            pressed: true,
            repeat: false,
            modifiers: egui::Modifiers::NONE,
        }]
    }

    /// Where no dialog opens, the path field's window takes the keyboard: typed text,
    /// Tab to complete it from the folder, Enter to open the file.
    #[test]
    fn the_path_field_completes_with_tab_and_opens_with_enter() {
        let ctx = egui::Context::default();
        let mut menu = FileMenu::default();
        let mut lab = Lab::new("projectile", &[]).unwrap();
        menu.open_prompt(Purpose::OpenScene, &mut lab, "no desktop portal and no zenity");
        assert!(
            lab.status
                .starts_with("No file dialog on this system (no desktop portal and no zenity): type a path")
        );
        frame(&ctx, &mut menu, &mut lab, Vec::new());
        frame(&ctx, &mut menu, &mut lab, vec![egui::Event::Text("assets/sc".into())]);
        assert_eq!(menu.scene_path, "assets/sc", "the field has the keyboard at once");
        frame(&ctx, &mut menu, &mut lab, key(egui::Key::Tab));
        assert_eq!(menu.scene_path, "assets/scenes/");
        frame(&ctx, &mut menu, &mut lab, vec![egui::Event::Text("ch".into())]);
        assert_eq!(menu.scene_path, "assets/scenes/ch", "typing goes on after the completion");
        frame(&ctx, &mut menu, &mut lab, key(egui::Key::Tab));
        assert_eq!(menu.scene_path, "assets/scenes/chain.toml");
        frame(&ctx, &mut menu, &mut lab, key(egui::Key::Enter));
        assert_eq!(lab.entry.info().name, "chain");
        assert_eq!(menu.prompt, None, "the window closes once the file opened");
    }

    /// Saving through the path field: the name it holds is selected, so what is typed
    /// replaces it (as a dialog's file name), and Enter writes the snapshot there.
    #[test]
    fn the_save_field_replaces_its_selected_name_and_saves_with_enter() {
        let ctx = egui::Context::default();
        let mut menu = FileMenu::default();
        let mut lab = Lab::new("bridge", &[]).unwrap();
        lab.run_steps(5);
        let dir = std::env::temp_dir().join(format!("particle-lab-save-field-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        menu.snapshot_path = dir.join("old-name.json").display().to_string();
        menu.open_prompt(Purpose::SaveSnapshot, &mut lab, "test");
        frame(&ctx, &mut menu, &mut lab, Vec::new());
        let typed = dir.join("kept.json").display().to_string();
        frame(&ctx, &mut menu, &mut lab, vec![egui::Event::Text(typed.clone())]);
        assert_eq!(menu.snapshot_path, typed, "the old name was replaced");
        frame(&ctx, &mut menu, &mut lab, key(egui::Key::Enter));
        assert!(dir.join("kept.json").is_file(), "{}", lab.status);
        assert!(!dir.join("old-name.json").exists());
        assert_eq!(menu.prompt, None, "the window closes once saved");
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A missing folder or file is a line in the status line, and the window stays.
    #[test]
    fn a_missing_folder_or_file_is_one_line_and_the_field_stays() {
        let ctx = egui::Context::default();
        let mut menu = FileMenu::default();
        let mut lab = Lab::new("projectile", &[]).unwrap();
        menu.open_prompt(Purpose::OpenScene, &mut lab, "test");
        frame(&ctx, &mut menu, &mut lab, Vec::new());
        frame(&ctx, &mut menu, &mut lab, vec![egui::Event::Text("no-such-folder/x".into())]);
        frame(&ctx, &mut menu, &mut lab, key(egui::Key::Tab));
        assert_eq!(lab.status, "cannot list no-such-folder/: no such folder");
        assert_eq!(menu.scene_path, "no-such-folder/x");
        frame(&ctx, &mut menu, &mut lab, key(egui::Key::Enter));
        assert_eq!(lab.entry.info().name, "projectile");
        assert!(lab.status.contains("no-such-folder/x") && !lab.status.contains('\n'), "{}", lab.status);
        assert_eq!(menu.prompt, Some(Purpose::OpenScene), "the window stays for another try");
        frame(&ctx, &mut menu, &mut lab, key(egui::Key::Escape));
        assert_eq!(menu.prompt, None, "Escape closes it");

        menu.snapshot_path = "no-such-folder/s.json".into();
        assert!(!FileMenu::act(Purpose::SaveSnapshot, Path::new(&menu.snapshot_path), &mut lab));
        assert_eq!(lab.status, "cannot save to no-such-folder/s.json: no folder no-such-folder");
        assert!(!FileMenu::act(Purpose::SaveSnapshot, Path::new("assets"), &mut lab));
        assert!(!FileMenu::act(Purpose::OpenSnapshot, Path::new("no-such.json"), &mut lab));
        assert!(lab.status.starts_with("cannot read no-such.json: "), "{}", lab.status);
    }
}
