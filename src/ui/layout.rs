//! The panel's layout as the user left it: whether the side panel and the Controls
//! window are open, which sections are expanded, and the text size. Saved with the settings
//! (`settings.json`'s `panel`), so the panel comes back as it was.

use serde::{Deserialize, Serialize};

/// The side panel's sections, top to bottom.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Section {
    /// The selected particle: forces, velocity, edits.
    Inspector,
    /// Pause, step, reset, time scale, physics rate, solver and integrator.
    Run,
    /// The scene's sliders, presets and actions (Fire).
    Parameters,
    /// The energy plot, the distance from the exact answer, and the bars.
    Energy,
    /// The scene's read-outs and the colour keys.
    Readouts,
    /// A second copy of the scene with one setting changed.
    Compare,
    /// Frame and physics timings, contacts, the state hash.
    Stats,
}

impl Section {
    /// Every section, top to bottom.
    pub const ALL: [Section; 7] = [
        Section::Inspector,
        Section::Run,
        Section::Parameters,
        Section::Energy,
        Section::Readouts,
        Section::Compare,
        Section::Stats,
    ];

    /// The heading the panel shows.
    #[must_use]
    pub fn title(self) -> &'static str {
        match self {
            Section::Inspector => "Inspector",
            Section::Run => "Run",
            Section::Parameters => "Parameters",
            Section::Energy => "Energy",
            Section::Readouts => "Read-outs",
            Section::Compare => "Compare",
            Section::Stats => "Stats",
        }
    }
}

/// The side panel and its sections; a field missing from a settings file takes its
/// default (files from before the sections were saved have only `open`, `help` and
/// `compare`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PanelLayout {
    /// The side panel is shown (P hides it).
    pub open: bool,
    /// The Controls window is open (F1).
    pub help: bool,
    /// The About this scene window is open (Help > About this scene).
    pub about: bool,
    /// The Inspector section is expanded (it opens by itself when a particle is picked).
    pub inspector: bool,
    /// The Run section is expanded.
    pub run: bool,
    /// The Parameters section is expanded.
    pub parameters: bool,
    /// The Energy section is expanded.
    pub energy: bool,
    /// The Read-outs section is expanded.
    pub readouts: bool,
    /// The Compare section is expanded.
    pub compare: bool,
    /// The Stats section is expanded (shown when View → Stats is on).
    pub stats: bool,
    /// Size of the text and controls, in percent: 100 to 250 ([`TEXT_SIZE`]), for a
    /// projector (View → Text size, Ctrl+= and Ctrl+-).
    pub text_size: u32,
}

/// The text sizes View → Text size offers (percent), and the step of Ctrl+= and Ctrl+-.
pub const TEXT_SIZE: std::ops::RangeInclusive<u32> = 100..=250;
/// The step of Ctrl+= and Ctrl+- (percent).
pub const TEXT_SIZE_STEP: u32 = 10;

impl Default for PanelLayout {
    fn default() -> Self {
        Self {
            open: true,
            help: false,
            about: false,
            inspector: true,
            run: true,
            parameters: true,
            energy: true,
            readouts: true,
            compare: false,
            stats: true,
            text_size: 100,
        }
    }
}

impl PanelLayout {
    /// The interface's zoom for egui: the text size, kept to [`TEXT_SIZE`] (a settings
    /// file edited by hand may say anything).
    #[must_use]
    pub fn zoom(&self) -> f32 {
        self.text_size.clamp(*TEXT_SIZE.start(), *TEXT_SIZE.end()) as f32 / 100.0
    }

    /// The text size `steps` steps of [`TEXT_SIZE_STEP`] larger (smaller if negative),
    /// kept to [`TEXT_SIZE`].
    pub fn step_text_size(&mut self, steps: i32) {
        let size =
            self.text_size.clamp(*TEXT_SIZE.start(), *TEXT_SIZE.end()) as i32 + steps * TEXT_SIZE_STEP as i32;
        self.text_size = (size.max(0) as u32).clamp(*TEXT_SIZE.start(), *TEXT_SIZE.end());
    }

    /// Whether `section` is expanded.
    #[must_use]
    pub fn is_open(&self, section: Section) -> bool {
        *self.flag(section)
    }

    /// Expands or collapses `section`.
    pub fn set_open(&mut self, section: Section, open: bool) {
        *self.flag_mut(section) = open;
    }

    fn flag(&self, section: Section) -> &bool {
        match section {
            Section::Inspector => &self.inspector,
            Section::Run => &self.run,
            Section::Parameters => &self.parameters,
            Section::Energy => &self.energy,
            Section::Readouts => &self.readouts,
            Section::Compare => &self.compare,
            Section::Stats => &self.stats,
        }
    }

    fn flag_mut(&mut self, section: Section) -> &mut bool {
        match section {
            Section::Inspector => &mut self.inspector,
            Section::Run => &mut self.run,
            Section::Parameters => &mut self.parameters,
            Section::Energy => &mut self.energy,
            Section::Readouts => &mut self.readouts,
            Section::Compare => &mut self.compare,
            Section::Stats => &mut self.stats,
        }
    }
}
