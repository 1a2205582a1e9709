//! Issue 17, the scene-file findings: nothing a scene file holds crashes the loader,
//! costs unbounded memory or time, or breaks the one-line rule of its messages.
//!
//! The last test feeds mutated versions of the shipped files to the loader: a few
//! thousand cases by default (a second or two), `FUZZ_CASES=100000` (and `FUZZ_SEED=N`) for a longer run.

mod common;

use std::path::Path;
use std::time::{Duration, Instant};

use particle_lab::scenes::file::expr::Expr;
use particle_lab::scenes::{self, Scene, file};

/// Loads a scene from text as a file named `test.toml`; the error as its one line.
fn load(text: &str) -> Result<Box<dyn Scene>, String> {
    let entry = file::load_text(text, "test.toml", None).map_err(|e| e.to_string())?;
    scenes::build_entry(&entry, &[])
}

fn load_err(text: &str) -> String {
    match load(text) {
        Ok(_) => panic!("loaded, but should not have: {}", &text[..text.len().min(300)]),
        Err(message) => message,
    }
}

/// The one-line rule: no line break or control character, and short enough to read.
fn assert_one_line(message: &str) {
    assert!(!message.chars().any(char::is_control), "a control character in: {message:?}");
    assert!(message.chars().count() <= 300, "{} characters: {message}", message.chars().count());
}

const HEAD: &str = "[scene]\nname = \"t\"\n";

#[test]
fn a_long_flat_chain_of_any_operator_is_refused_with_one_line() {
    for op in ["+", "-", "*", "/"] {
        let chain = format!("1{}", format!("{op}1").repeat(150_000));
        let text = format!("{HEAD}[[particle]]\nposition = [0, \"{chain}\", 0]\n");
        let error = load_err(&text);
        assert!(error.starts_with("test.toml:4:"), "{error}");
        assert!(error.contains("too long"), "{error}");
        assert_one_line(&error);
    }
    // The evaluator itself refuses it, whoever calls it.
    let chain = "x".to_string() + &"+x".repeat(150_000);
    let error = Expr::parse(&chain, &["x"]).unwrap_err();
    assert!(error.message.contains("too long"), "{}", error.message);
    // A long but sane chain is still an expression, and means what it says.
    let chain = "1".to_string() + &"+1".repeat(199);
    let scene = load(&format!("{HEAD}[[particle]]\nposition = [0, \"{chain}\", 0]\n")).unwrap();
    assert_eq!(scene.world().particles.positions()[0].y, 200.0);
}

#[test]
fn deep_nesting_of_every_kind_is_refused_with_a_short_line() {
    let deep = ["(".repeat(10_000) + "1" + &")".repeat(10_000), "-".repeat(100_000) + "1", {
        "2".to_string() + &"^2".repeat(100_000)
    }];
    for expression in deep {
        let error = load_err(&format!("{HEAD}[[particle]]\nposition = [0, \"{expression}\", 0]\n"));
        assert!(error.contains("nested") || error.contains("too long"), "{error}");
        assert_one_line(&error);
    }
}

/// A row of `count` particles named `r`, and `drags` drag tables acting on all of them.
fn drags(count: usize, drags: usize) -> String {
    let mut text = format!("{HEAD}[[row]]\nname = \"r\"\ncount = {count}\nstart = [0, 0, 0]\n");
    for _ in 0..drags {
        text.push_str("[[drag]]\nk1 = 0.1\n");
    }
    text
}

#[test]
fn generators_times_the_particles_they_act_on_are_counted_against_a_budget() {
    // The finding: 216 KB that asked for 8 GB.
    let text = drags(200_000, 12_000);
    assert!(text.len() < 250_000);
    let started = Instant::now();
    let error = load_err(&text);
    assert!(started.elapsed() < Duration::from_secs(20), "took {:?}", started.elapsed());
    assert!(error.contains("[[drag]]") && error.contains("1000000"), "{error}");
    assert!(error.contains("1200000"), "says what the file costs: {error}");
    assert_one_line(&error);
    // One drag naming the whole row again and again.
    let targets = vec!["\"r\""; 12_000].join(", ");
    let text = format!(
        "{HEAD}[[row]]\nname = \"r\"\ncount = 200000\nstart = [0, 0, 0]\n[[drag]]\nk1 = 1\ntargets = [{targets}]\n"
    );
    let error = load_err(&text);
    assert!(error.contains("1000000"), "{error}");
    assert_one_line(&error);
    // Buoyancy: one generator per particle it floats.
    let mut text = format!("{HEAD}[[row]]\nname = \"r\"\ncount = 200000\nstart = [0, 0, 0]\n");
    for _ in 0..12 {
        text.push_str("[[buoyancy]]\nparticle = \"r\"\nsurface = 0\nhalf_height = 0.1\nvolume = 0.001\n");
    }
    let error = load_err(&text);
    assert!(error.contains("[[buoyancy]]") && error.contains("1000000"), "{error}");
    assert_one_line(&error);
    // Within the budget is fine: the whole row under five drags.
    let scene = load(&drags(200_000, 5)).unwrap();
    assert_eq!(scene.world().particles.len(), 200_000);
}

#[test]
fn per_particle_expressions_times_the_particles_are_counted_against_a_budget() {
    // 7 KB that took 10 s to load: 200,000 particles, each evaluating seven
    // expressions of nearly a thousand terms, twice (to check, then to run).
    let long = format!("\"{}\"", vec!["i"; 480].join("+"));
    let text = format!(
        "{HEAD}[[row]]\ncount = 200000\nposition = [{long}, {long}, {long}]\nvelocity = [{long}, {long}, {long}]\n\
         mass = \"1 + 0 * ({})\"\n",
        &long[1..long.len() - 1]
    );
    assert!(text.len() < 8_000);
    let started = Instant::now();
    let error = load_err(&text);
    assert!(started.elapsed() < Duration::from_secs(5), "took {:?}", started.elapsed());
    assert!(error.starts_with("test.toml:3:1: this [[row]]"), "{error}");
    assert!(error.contains("50000000") && error.contains("200000"), "{error}");
    assert_one_line(&error);
    // The same in a grid.
    let text = format!("{HEAD}[[grid]]\nrows = 400\ncols = 500\nposition = [{long}, {long}, {long}]\n");
    assert!(load_err(&text).contains("this [[grid]]"));
    // Short expressions for as many particles are fine.
    let scene =
        load(&format!("{HEAD}[[row]]\ncount = 200000\nposition = [\"i * 0.1\", \"sin(i)\", 0]\n")).unwrap();
    assert_eq!(scene.world().particles.len(), 200_000);
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("particle-lab-limits-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `load_path` in a thread, so a read that blocks fails the test instead of hanging it.
fn load_path_within(path: &Path, limit: Duration) -> Result<String, String> {
    let (send, receive) = std::sync::mpsc::channel();
    let owned = path.to_path_buf();
    std::thread::spawn(move || {
        let _ =
            send.send(file::load_path(&owned).map(|e| e.info().name.to_string()).map_err(|e| e.to_string()));
    });
    receive
        .recv_timeout(limit)
        .unwrap_or_else(|_| panic!("load_path({}) did not return within {limit:?}", path.display()))
}

#[test]
fn devices_fifos_directories_and_huge_files_are_refused_at_once() {
    let started = Instant::now();
    let error = load_path_within(Path::new("/dev/zero"), Duration::from_secs(10)).unwrap_err();
    assert!(started.elapsed() < Duration::from_secs(2), "took {:?}", started.elapsed());
    assert_eq!(error, "/dev/zero: cannot read it: it is a device, not a regular file");
    let dir = scratch("kinds");
    let error = load_path_within(&dir, Duration::from_secs(10)).unwrap_err();
    assert!(error.ends_with("cannot read it: it is a directory, not a regular file"), "{error}");
    let fifo = dir.join("fifo.toml");
    let made = Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success());
    if made {
        let error = load_path_within(&fifo, Duration::from_secs(10)).unwrap_err();
        assert!(error.ends_with("it is a FIFO (named pipe), not a regular file"), "{error}");
    }
    let big = dir.join("big.toml");
    std::fs::write(&big, vec![b'#'; (4 << 20) + 1]).unwrap();
    let error = load_path_within(&big, Duration::from_secs(10)).unwrap_err();
    assert!(error.ends_with("it is larger than the limit of 4 MB"), "{error}");
    // The same limit for text that comes another way (a snapshot holds its scene file).
    let text = format!("{HEAD}{}", "#".repeat(4 << 20));
    let error = file::load_text(&text, "test.toml", None).err().unwrap().to_string();
    assert_eq!(error, "test.toml: it is larger than the limit of 4 MB for a scene file");
    let error = load_path_within(&dir.join("missing.toml"), Duration::from_secs(10)).unwrap_err();
    assert!(error.ends_with("missing.toml: cannot read it: no such file"), "{error}");
    std::fs::remove_dir_all(&dir).unwrap();
}

use std::process::Command;

use common::Random;

/// `n` named particles (inline tables, so that 100,000 fit in a file's 4 MB), every
/// twentieth linked by name to the one before.
fn named_particles(n: usize) -> String {
    // Top-level keys come before the first table header.
    let mut text = String::from("particle = [\n");
    for k in 0..n {
        text.push_str(&format!("{{name=\"p{k}\",position=[0,{},0]}},\n", k % 7));
    }
    text.push_str("]\nlink = [\n");
    for k in (1..n).step_by(20) {
        text.push_str(&format!("{{kind=\"rod\",a=\"p{}\",b=\"p{k}\",length=1}},\n", k - 1));
    }
    text + "]\n" + HEAD
}

/// `n` named rows of two particles, every twentieth linked by name to the next row.
fn named_rows(n: usize) -> String {
    let mut text = String::from("row = [\n");
    for k in 0..n {
        text.push_str(&format!("{{name=\"r{k}\",count=2,start=[{},0,0]}},\n", k % 7));
    }
    text.push_str("]\nlink = [\n");
    for k in (1..n).step_by(20) {
        text.push_str(&format!("{{kind=\"spring\",k=1,a=\"r{}.1\",b=\"r{k}.0\"}},\n", k - 1));
    }
    text + "]\n" + HEAD
}

/// The quickest of three loads of `text` (the machine is shared: the least disturbed).
fn load_time(text: &str, particles: usize) -> Duration {
    (0..3)
        .map(|_| {
            let started = Instant::now();
            let scene = load(text).unwrap();
            let took = started.elapsed();
            assert_eq!(scene.world().particles.len(), particles);
            took
        })
        .min()
        .unwrap()
}

#[test]
fn loading_named_particles_and_rows_takes_linear_time() {
    for (make, per) in [(named_particles as fn(usize) -> String, 1), (named_rows, 2)] {
        let text = make(100_000);
        assert!(text.len() < 4 << 20, "a file of {} bytes", text.len());
        let small = load_time(&make(6_250), 6_250 * per);
        let large = load_time(&text, 100_000 * per);
        eprintln!("6,250: {small:?}; 100,000: {large:?}");
        // The target is 2 s for 100,000 (0.8 s and 1.1 s here, each load building twice:
        // once to check the file, once to run it); three times that on a busy machine.
        assert!(large < Duration::from_secs(6), "100,000 took {large:?}");
        // Sixteen times the file: about sixteen times the time, where quadratic would be
        // 256. Seen here: 27x and 40x (memory grows too), and for a 4x file 4x and 11x,
        // too close to that size's quadratic 16x. The bound sits between with room.
        let ratio = large.as_secs_f64() / small.as_secs_f64().max(1e-3);
        assert!(ratio < 100.0, "6,250 took {small:?}, 100,000 took {large:?}: {ratio:.1} times");
    }
}

#[test]
fn user_text_in_messages_is_escaped_and_cut() {
    let cases = [
        // A name with a line break and an ANSI escape.
        format!("{HEAD}[[particle]]\nname = \"a\\nb\\u001b[31m\"\nposition = [0, 0, 0]\n"),
        // A link kind.
        format!("{HEAD}[[row]]\ncount = 2\nstart = [0, 0, 0]\nlink = \"ro\\rd\\n\"\n"),
        // An expression, with a control character where an operator belongs.
        format!("{HEAD}[[particle]]\nposition = [0, \"1\\r\\n2\", 0]\n"),
        format!("{HEAD}[[particle]]\nposition = [0, \"1 \\u001b 2\", 0]\n"),
        // A particle reference.
        format!(
            "{HEAD}[[particle]]\nname = \"a\"\nposition = [0, 0, 0]\n[[link]]\nkind = \"rod\"\na = \"a\"\nb = \"b\\n\\r\"\n"
        ),
        format!(
            "{HEAD}[[row]]\nname = \"a\"\ncount = 2\nstart = [0, 0, 0]\n[[link]]\nkind = \"rod\"\na = \"a.0\"\nb = \"a.\\n\"\n"
        ),
        // A parameter's name.
        format!("{HEAD}[[param]]\nname = \"x\\ny\"\ndefault = 1\nmin = 0\nmax = 2\n"),
        // A key TOML does not know, with a line break in it.
        format!("{HEAD}[[particle]]\n\"pos\\nition\\r\" = [0, 0, 0]\n"),
        // 20 KB of user text.
        format!("{HEAD}[[particle]]\nname = \"{}\"\nposition = [0, 0, 0]\n", "é".repeat(20_000) + "-"),
        format!(
            "{HEAD}[[particle]]\nposition = [0, \"{}\", 0]\n",
            "(".repeat(10_000) + "1" + &")".repeat(10_000)
        ),
        format!("{HEAD}[[particle]]\nposition = [0, \"{}\", 0]\n", "1.".repeat(10_000)),
        format!("{HEAD}[[particle]]\nposition = [0, \"{}\", 0]\n", "x".repeat(20_000)),
        format!("{HEAD}[[particle]]\n\"{}\" = 1\n", "k".repeat(20_000)),
    ];
    for text in &cases {
        let error = load_err(text);
        assert!(error.starts_with("test.toml:"), "{error}");
        assert_one_line(&error);
    }
    // Many names: the list of valid ones is cut, not all echoed.
    let mut text = String::from(HEAD);
    for k in 0..2000 {
        text.push_str(&format!("[[param]]\nname = \"parameter_{k}\"\ndefault = 1\nmin = 0\nmax = 2\n"));
    }
    text.push_str("[[particle]]\nposition = [0, \"nope\", 0]\n");
    assert_one_line(&load_err(&text));
    let mut text = String::from(HEAD);
    for k in 0..2000 {
        text.push_str(&format!("[[particle]]\nname = \"particle_{k}\"\nposition = [{k}, 0, 0]\n"));
    }
    text.push_str("[[link]]\nkind = \"rod\"\na = 0\nb = \"nope\"\n");
    assert_one_line(&load_err(&text));
    // The file's name, as the caller gives it and as a path.
    let error =
        file::load_text("[scene]\nname = \"\"\n", "bad\nname\u{1b}.toml", None).err().unwrap().to_string();
    assert!(error.starts_with("bad\\nname\\u{1b}.toml:"), "{error}");
    assert_one_line(&error);
    let error = file::load_path(Path::new("/nonexistent/a\r\nb.toml")).err().unwrap().to_string();
    assert_eq!(error, "/nonexistent/a\\r\\nb.toml: cannot read it: no such file");
}

#[test]
fn a_number_beyond_single_precision_is_called_too_large_not_infinite() {
    let error = load_err(&format!("{HEAD}[[particle]]\nposition = [0, 1e39, 0]\n"));
    assert!(error.contains("too large"), "{error}");
    assert!(!error.contains("not a finite number"), "{error}");
    assert!(error.contains("1e39"), "{error}");
    assert_one_line(&error);
    // Infinity and NaN are still not finite.
    let error = load_err(&format!("{HEAD}[[particle]]\nposition = [0, \"1 / 0\", 0]\n"));
    assert!(error.contains("not a finite number"), "{error}");
    // Tiny and huge values in range errors are written with an exponent, not 300 digits.
    let error = load_err(&format!("{HEAD}[[particle]]\nposition = [0, 0, 0]\nmass = 1e-300\n"));
    assert!(error.contains("mass = 1e-300 is out of range"), "{error}");
    let error = load_err(&format!("{HEAD}[[particle]]\nposition = [0, 0, 0]\nmass = 1e30\n"));
    assert!(error.contains("mass = 1e30 is out of range"), "{error}");
}

#[test]
fn a_snapshot_naming_an_unknown_parameter_says_so_once() {
    let scene = scenes::build("pendulum", &[]).unwrap();
    let mut snapshot = particle_lab::scenes::snapshot::Snapshot::of(scene.as_ref(), 1.0 / 240.0).unwrap();
    snapshot.params.push(("size".into(), 1.0));
    let error = snapshot.restore().err().expect("an unknown parameter is refused");
    assert!(!error.contains("parameter unknown parameter"), "{error}");
    assert!(error.contains("unknown parameter 'size'"), "{error}");
}

// ---------------------------------------------------------------------------------------
// The mutation loop.

const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "1e39",
    "-1e39",
    "1e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "199999",
    "200000",
    "200001",
    "1e9",
    "4294967296",
    "9223372036854775807",
    "-9223372036854775808",
    "0.5",
    "\"1/0\"",
    "\"-1\"",
    "\"i\"",
    "\"j * 1e30\"",
    "\"sqrt(-1)\"",
    "\"ln(0)\"",
    "\"g\"",
    "\"0 * i\"",
    "64",
    "1000",
];

/// One mutation of `text`.
fn mutate(text: &str, rng: &mut Random) -> String {
    if text.is_empty() {
        return String::new();
    }
    let bytes = text.as_bytes();
    let at = rng.below(bytes.len());
    match rng.below(8) {
        // A byte flipped.
        0 => {
            let mut out = bytes.to_vec();
            out[at] ^= 1 << rng.below(8);
            String::from_utf8_lossy(&out).into_owned()
        }
        // Cut short.
        1 => String::from_utf8_lossy(&bytes[..at]).into_owned(),
        // A line repeated.
        2 => {
            let lines: Vec<&str> = text.lines().collect();
            let k = rng.below(lines.len());
            let times = 1 + rng.below(4);
            let mut out = Vec::new();
            for (n, line) in lines.iter().enumerate() {
                out.push(*line);
                if n == k {
                    out.extend(std::iter::repeat_n(*line, times));
                }
            }
            out.join("\n")
        }
        // A number replaced by another, possibly absurd.
        3 | 4 => {
            let starts: Vec<usize> = text
                .char_indices()
                .filter(|&(k, c)| {
                    c.is_ascii_digit() && (k == 0 || !text.as_bytes()[k - 1].is_ascii_alphanumeric())
                })
                .map(|(k, _)| k)
                .collect();
            let Some(&start) = starts.get(rng.below(starts.len())) else { return text.to_string() };
            let end = text[start..]
                .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == '-'))
                .map_or(text.len(), |e| start + e);
            let number = NUMBERS[rng.below(NUMBERS.len())];
            format!("{}{number}{}", &text[..start], &text[end..])
        }
        // A line of one file spliced into another place.
        5 => {
            let lines: Vec<&str> = text.lines().collect();
            let (from, to) = (rng.below(lines.len()), rng.below(lines.len()));
            let mut out = lines.clone();
            out.insert(to, lines[from]);
            out.join("\n")
        }
        // A long chain or deep nest put in a value.
        6 => {
            let long = match rng.below(4) {
                0 => format!("\"1{}\"", "+1".repeat(1 + rng.below(200_000))),
                1 => format!("\"{}1{}\"", "(".repeat(rng.below(200)), ")".repeat(rng.below(200))),
                2 => format!("\"{}1\"", "-".repeat(rng.below(100_000))),
                _ => format!("\"{}\"", "a*".repeat(rng.below(5000)) + "a"),
            };
            let lines: Vec<&str> = text.lines().collect();
            let k = rng.below(lines.len());
            let mut out: Vec<String> = lines.iter().map(|l| (*l).to_string()).collect();
            if let Some(eq) = out[k].find('=') {
                out[k] = format!("{}= {long}", &out[k][..eq]);
            }
            out.join("\n")
        }
        // A control character or a stray quote inserted.
        _ => {
            let mut at = at;
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            let insert = ["\\n", "\\r", "\\u001b[31m", "\"", "[", "]", "\n[[row]]\n", "\n[[drag]]\n", "é"];
            format!("{}{}{}", &text[..at], insert[rng.below(insert.len())], &text[at..])
        }
    }
}

#[test]
fn mutated_shipped_files_load_or_fail_with_one_line_and_never_panic() {
    let cases: usize = std::env::var("FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(2000);
    let seed: u64 = std::env::var("FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(17);
    let mut rng = Random(seed);
    let (mut loaded, mut refused) = (0, 0);
    for case in 0..cases {
        let (name, original) = file::SHIPPED[case % file::SHIPPED.len()];
        let mut text = original.to_string();
        for _ in 0..1 + rng.below(3) {
            text = mutate(&text, &mut rng);
        }
        let outcome = std::panic::catch_unwind(|| match file::load_text(&text, "test.toml", None) {
            Err(error) => Err(error.to_string()),
            Ok(entry) => {
                let mut scene = scenes::build_entry(&entry, &[])?;
                let dt = entry.info().dt;
                for _ in 0..3 {
                    scene.step(dt).map_err(|e| e.to_string())?;
                }
                // Every parameter at its ends: a rebuild, or a refusal in one line.
                for param in entry.info().params.iter() {
                    for value in [param.min, param.max] {
                        if let Err(error) = scene.set_param(&param.name, value) {
                            let message = error.to_string();
                            assert!(
                                !message.chars().any(char::is_control) && message.chars().count() <= 300,
                                "{message:?}"
                            );
                        }
                        scene.step(dt).map_err(|e| e.to_string())?;
                    }
                }
                Ok(())
            }
        });
        match outcome {
            Ok(Ok(())) => loaded += 1,
            Ok(Err(message)) => {
                refused += 1;
                assert!(
                    !message.chars().any(char::is_control) && message.chars().count() <= 300,
                    "case {case} (seed {seed}, from {name}): {message:?}\n{}",
                    &text[..text.len().min(2000)]
                );
            }
            Err(_) => {
                panic!("case {case} (seed {seed}, from {name}) panicked:\n{}", &text[..text.len().min(2000)])
            }
        }
    }
    eprintln!("{cases} cases from seed {seed}: {loaded} loaded and stepped, {refused} refused with one line");
    assert_eq!(loaded + refused, cases);
    assert!(loaded > 0 && refused > 0, "the mutations reach both outcomes");
}
