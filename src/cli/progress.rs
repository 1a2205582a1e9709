//! A progress bar on stderr for long `simulate` and `render` runs, only where a person
//! watches: stderr is a terminal, and the run has gone on for half a second. Piped or
//! redirected, nothing is drawn, so scripts and tests see clean output.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How long a run goes before its bar appears: short runs never flash one.
const SHOW_AFTER: Duration = Duration::from_millis(500);

/// A bar counting `unit`s (steps, frames) to a known total; cleared when dropped.
pub struct Progress {
    bar: Option<ProgressBar>,
    started: Instant,
    shown: bool,
}

impl Progress {
    /// A bar for `total` `unit`s, drawn only if `wanted` (see [`Self::for_terminal`]).
    #[must_use]
    pub fn new(total: u64, unit: &str, wanted: bool) -> Self {
        let bar = wanted.then(|| {
            let template = format!("{{bar:40}} {{pos}}/{{len}} {unit}, {{elapsed}} (about {{eta}} left)");
            let style = ProgressStyle::with_template(&template)
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> ");
            ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::hidden()).with_style(style)
        });
        Self { bar, started: Instant::now(), shown: false }
    }

    /// Whether a bar would reach a person: stderr is a terminal and, when `with_stdout`
    /// is false, stdout is not the same screen (its own lines already show progress).
    #[must_use]
    pub fn for_terminal(with_stdout: bool) -> bool {
        std::io::stderr().is_terminal() && (with_stdout || !std::io::stdout().is_terminal())
    }

    /// `done` units are done.
    pub fn set(&mut self, done: u64) {
        let Some(bar) = &self.bar else { return };
        bar.set_position(done);
        if !self.shown && self.started.elapsed() >= SHOW_AFTER {
            self.shown = true;
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
