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

/// How many characters of a user's text a message quotes before it cuts.
pub const QUOTE_CHARS: usize = 80;

/// A user's text (a name, an expression, a path) made safe to put in a one-line
/// message: control characters (`\n`, `\r`, `\t`, an ANSI escape's `\u{1b}`, …) are
/// shown as escapes, and text past [`QUOTE_CHARS`] characters is cut with `…` and the
/// count of what was left out, so a 20 KB expression does not fill the terminal.
#[must_use]
pub fn quote(text: &str) -> String {
    let total = text.chars().count();
    let mut shown = String::new();
    for c in text.chars().take(QUOTE_CHARS) {
        push_escaped(&mut shown, c);
    }
    if total > QUOTE_CHARS {
        shown.push_str(&format!("… ({} more characters)", total - QUOTE_CHARS));
    }
    shown
}

/// A whole message made one line, whatever it quotes: a control character that reached
/// it raw (a newline or an escape in a name some part echoed) is shown as an escape, as
/// [`quote`] shows it; nothing is cut.
#[must_use]
pub fn one_line(message: &str) -> String {
    let mut line = String::with_capacity(message.len());
    for c in message.chars() {
        push_escaped(&mut line, c);
    }
    line
}

/// `c`, or its escape if it is a control or line-breaking character.
fn push_escaped(out: &mut String, c: char) {
    match c {
        '\n' => out.push_str("\\n"),
        '\r' => out.push_str("\\r"),
        '\t' => out.push_str("\\t"),
        c if c.is_control() || matches!(c, '\u{2028}' | '\u{2029}' | '\u{85}') => {
            out.push_str(&format!("\\u{{{:x}}}", c as u32));
        }
        c => out.push(c),
    }
}

/// A path for a one-line message: [`quote`]d, but cut at the front (the file's name
/// is the part worth keeping).
#[must_use]
pub fn path(path: &std::path::Path) -> String {
    let text = path.display().to_string();
    let total = text.chars().count();
    if total <= QUOTE_CHARS {
        return quote(&text);
    }
    let tail: String = text.chars().skip(total - QUOTE_CHARS).collect();
    format!("…{}", quote(&tail))
}

/// An I/O error's reason in words, without the OS's error number ("(os error 2)").
#[must_use]
pub fn io_reason(error: &std::io::Error) -> String {
    use std::io::ErrorKind;
    match error.kind() {
        ErrorKind::NotFound => "no such file".into(),
        ErrorKind::PermissionDenied => "permission denied".into(),
        ErrorKind::IsADirectory => "it is a directory".into(),
        ErrorKind::NotADirectory => "a part of the path is not a directory".into(),
        _ => {
            let text = error.to_string();
            let text = text.split(" (os error").next().unwrap_or(&text);
            quote(text)
        }
    }
}

/// `value` with `decimals` decimals, and never "-0.0": a value that rounds to zero
/// is shown as zero.
#[must_use]
pub fn fixed(value: f32, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => text,
    }
}

/// [`fixed`] with its sign always shown, "+" for zero.
#[must_use]
pub fn signed(value: f32, decimals: usize) -> String {
    let text = fixed(value, decimals);
    if text.starts_with('-') { text } else { format!("+{text}") }
}

/// `text` for a one-line message: [`quote`]d (control characters escaped) and cut so
/// that the quoted form holds at most `room` characters, with the count of what was
/// left out.
pub fn clip(text: &str, room: usize) -> String {
    let mut out = String::new();
    let mut used = 0;
    let mut rest = text.chars();
    for c in rest.by_ref() {
        // One character at a time, so the cut is at `room`, not at `quote`'s own.
        let shown = quote(c.encode_utf8(&mut [0; 4]));
        let width = shown.chars().count();
        if used + width > room {
            let left = 1 + rest.count();
            out.push_str(&format!("… ({left} more characters)"));
            break;
        }
        used += width;
        out.push_str(&shown);
    }
    out
}

/// Names for a one-line message: joined with commas, cut after a few.
pub fn name_list<'a>(names: impl Iterator<Item = &'a str>) -> String {
    const ROOM: usize = 60;
    let mut out = String::new();
    let mut left = 0;
    for name in names {
        if left > 0 || out.chars().count() + name.chars().count() > ROOM {
            left += 1;
            continue;
        }
        if !out.is_empty() {
            out.push_str(", ");
        }
        out.push_str(&quote(name));
    }
    if left > 0 {
        out.push_str(&format!(" and {left} more"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoted_text_stays_on_one_line() {
        assert_eq!(quote("a\nb\rc\u{1b}[31m"), "a\\nb\\rc\\u{1b}[31m");
        let long = "1+".repeat(10_000);
        let shown = quote(&long);
        assert!(shown.chars().count() < 120, "{shown}");
        assert!(shown.ends_with("(19920 more characters)"), "{shown}");
        assert_eq!(quote("plain"), "plain");
    }

    #[test]
    fn a_whole_message_is_made_one_line_without_a_cut() {
        assert_eq!(one_line("unknown scene 'a\nb\r\u{1b}[2J'"), "unknown scene 'a\\nb\\r\\u{1b}[2J'");
        let long = "x".repeat(500);
        assert_eq!(one_line(&long), long);
    }

    #[test]
    fn figures_never_read_minus_zero() {
        assert_eq!(fixed(-0.0, 1), "0.0");
        assert_eq!(fixed(-0.004, 2), "0.00");
        assert_eq!(fixed(-0.006, 2), "-0.01");
        assert_eq!(signed(-0.0001, 3), "+0.000");
        assert_eq!(signed(-2.5, 1), "-2.5");
    }

    #[test]
    fn long_paths_keep_their_file_name() {
        let long = format!("/{}/scene.toml", "d/".repeat(100));
        let shown = path(std::path::Path::new(&long));
        assert!(shown.starts_with('…') && shown.ends_with("scene.toml"), "{shown}");
        assert_eq!(path(std::path::Path::new("/tmp/a\nb.toml")), "/tmp/a\\nb.toml");
    }

    #[test]
    fn io_reasons_have_no_os_numbers() {
        let missing = std::fs::read("/nonexistent/particle-lab").unwrap_err();
        assert_eq!(io_reason(&missing), "no such file");
        let other = std::io::Error::from_raw_os_error(28);
        assert!(!io_reason(&other).contains("os error"), "{}", io_reason(&other));
    }

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
