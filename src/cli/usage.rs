//! clap's errors in the shape of every other error: one line after `particle-lab: `,
//! keeping what clap suggests ("a similar argument exists: '--scene'").

/// Folds clap's rendered error into one line.
///
/// clap renders `error: MESSAGE`, indented detail and tip lines, then a usage block and
/// "For more information, try '--help'.". The message, details and tips are kept, joined
/// with "; "; the usage block becomes a pointer to the help of the command it names,
/// or without one, of `command` (`particle-lab scenes`: the subcommand typed).
#[must_use]
pub fn one_line(rendered: &str, command: &str) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut help = format!("{command} --help");
    for line in rendered.lines().map(str::trim) {
        if let Some(usage) = line.strip_prefix("Usage:") {
            help = help_command(usage);
            break;
        }
        if line.is_empty() || line.starts_with("For more information") {
            continue;
        }
        let line = line.strip_prefix("error:").map_or(line, str::trim_start);
        match parts.last_mut() {
            // "the following required arguments were not provided:" lists them below.
            Some(last) if last.ends_with(':') => {
                last.push(' ');
                last.push_str(line);
            }
            _ => parts.push(line.to_string()),
        }
    }
    if parts.is_empty() {
        parts.push("the command line was not understood".into());
    }
    format!("{} (see '{help}')", cut_quoted(&parts.join("; ")))
}

/// clap quotes what was typed in single quotes ("invalid value '…' for '--solver'"):
/// each quoted span is [`crate::messages::quote`]d, so a 20 KB value is cut to a
/// readable length.
fn cut_quoted(text: &str) -> String {
    let mut out = String::with_capacity(text.len().min(1024));
    let mut rest = text;
    while let Some(open) = rest.find('\'') {
        let Some(close) = rest[open + 1..].find('\'') else { break };
        out.push_str(&rest[..=open]);
        out.push_str(&crate::messages::quote(&rest[open + 1..open + 1 + close]));
        out.push('\'');
        rest = &rest[open + close + 2..];
    }
    out.push_str(rest);
    out
}

/// `particle-lab simulate --help` from a usage line such as
/// ` particle-lab simulate [OPTIONS] --scene <SCENE>`: the words before the first flag
/// or placeholder.
fn help_command(usage: &str) -> String {
    let words: Vec<&str> = usage
        .split_whitespace()
        .take_while(|word| !word.starts_with(['-', '[', '<']) && *word != "|")
        .collect();
    if words.is_empty() { "particle-lab --help".into() } else { format!("{} --help", words.join(" ")) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_suggestion_is_kept_on_the_same_line() {
        let rendered = "error: unexpected argument '--sene' found\n\n  tip: a similar argument exists: \
                        '--scene'\n\nUsage: particle-lab simulate --scene <SCENE>\n\nFor more \
                        information, try '--help'.\n";
        assert_eq!(
            one_line(rendered, "particle-lab"),
            "unexpected argument '--sene' found; tip: a similar argument exists: '--scene' \
             (see 'particle-lab simulate --help')"
        );
    }

    #[test]
    fn a_list_under_a_colon_joins_its_line() {
        let rendered = "error: the following required arguments were not provided:\n  --scene \
                        <SCENE>\n\nUsage: particle-lab render --scene <SCENE> --out <FILE>\n";
        assert_eq!(
            one_line(rendered, "particle-lab"),
            "the following required arguments were not provided: --scene <SCENE> \
             (see 'particle-lab render --help')"
        );
    }

    #[test]
    fn a_long_typed_value_is_cut() {
        let rendered = format!("error: invalid value '{}' for '--solver <NAME>'\n", "y".repeat(5000));
        let line = one_line(&rendered, "particle-lab");
        assert!(line.chars().count() < 250, "{line}");
        assert!(line.contains("(4920 more characters)' for '--solver <NAME>'"), "{line}");
    }

    #[test]
    fn possible_values_and_no_usage_block() {
        let rendered = "error: invalid value 'xml' for '--format <FORMAT>'\n  [possible values: text, \
                        json]\n\nFor more information, try '--help'.\n";
        assert_eq!(
            one_line(rendered, "particle-lab scenes"),
            "invalid value 'xml' for '--format <FORMAT>'; [possible values: text, json] \
             (see 'particle-lab scenes --help')"
        );
    }
}
