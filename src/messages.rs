//! Our own words for failures of the window and GPU libraries. Their error texts can
//! name the source file and line they come from (winit's "os error at
//! /root/.cargo/registry/src/.../mod.rs:765: ..."): a user has no use for that, so it
//! is cut before a message reaches them.

/// `text` without source locations: winit's `os error at FILE:LINE: ` and any word
/// that is a path into Rust sources (`.rs:`, `/.cargo/`, `/rustc/`).
#[must_use]
pub fn plain(text: &str) -> String {
    let mut text = text.to_string();
    const OS_ERROR: &str = "os error at ";
    while let Some(start) = text.find(OS_ERROR) {
        let rest = &text[start + OS_ERROR.len()..];
        let Some(at) = rest.find(".rs:") else { break };
        let after = rest[at + ".rs:".len()..].trim_start_matches(|c: char| c.is_ascii_digit());
        let after = after.strip_prefix(':').unwrap_or(after).trim_start().to_string();
        text.replace_range(start.., &after);
    }
    let words: Vec<&str> = text.split(' ').filter(|word| !is_source_location(word)).collect();
    words.join(" ")
}

fn is_source_location(word: &str) -> bool {
    word.contains(".rs:") || word.contains("/.cargo/") || word.contains("/rustc/")
}

/// Why the window could not open, from the event loop's error: no display at all, or
/// one that does not answer.
#[must_use]
pub fn no_display(error: &str) -> String {
    let set = |name: &str| std::env::var(name).ok().filter(|v| !v.is_empty());
    let hint = "run it on a desktop, or under a virtual display: apt-get install xvfb, then \
                'Xvfb :99 &' and 'DISPLAY=:99 particle-lab'";
    // winit tries Wayland first when both are set.
    let named = if let Some(wayland) = set("WAYLAND_DISPLAY") {
        format!("WAYLAND_DISPLAY={wayland}")
    } else if let Some(display) = set("DISPLAY") {
        format!("DISPLAY={display}")
    } else {
        return format!(
            "cannot open a window: no display (neither DISPLAY nor WAYLAND_DISPLAY is set); {hint}"
        );
    };
    format!("cannot open a window: the display {named} does not answer ({}); {hint}", plain(error))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn winit_locations_are_cut() {
        let text = "os error at /root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/winit-0.30.13/\
                    src/platform_impl/linux/mod.rs:788: Failed to open connection to X server";
        assert_eq!(plain(text), "Failed to open connection to X server");
        assert_eq!(plain("failed (os error at src/x.rs:1: boom) here"), "failed (boom) here");
    }

    #[test]
    fn other_locations_are_dropped_and_plain_text_kept() {
        assert_eq!(plain("panicked at /rustc/abc/library/core.rs:12:5 oops"), "panicked at oops");
        assert_eq!(
            plain("No suitable graphics adapter found; vulkan drivers/libraries could not be loaded"),
            "No suitable graphics adapter found; vulkan drivers/libraries could not be loaded"
        );
    }
}
