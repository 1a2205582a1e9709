//! Recording a run: `render --frames N --every K` draws N frames, K physics steps
//! apart, the first after `--steps`. What is written follows `--out`'s extension:
//!
//! - `run.png`: a numbered PNG sequence, `run-0001.png`, `run-0002.png`, ... (four
//!   digits, more when N needs them);
//! - `run.gif`: an animated GIF, looping;
//! - `run.apng`: an animated PNG, looping, full colour.
//!
//! Each frame is shown for the simulated time between frames, K × dt: exactly in an
//! APNG (a fraction of a second), to the nearest 1/100 s in a GIF, whose delays are
//! whole hundredths; the rounding is carried from frame to frame so the GIF's total
//! length stays true. A GIF cannot show frames closer than 0.02 s apart (viewers
//! slow them down), so a faster one is refused with the `--every` that would do.
//!
//! Every file is written through [`crate::writing`]: at a temporary name beside it
//! (`run.gif.part`) and renamed into place when complete, so a recording stopped part
//! way (Ctrl-C, a full disk) leaves nothing half-written under the name asked for; on a
//! failure the temporary file is removed. An `--out` that is a link writes the file it
//! names; a device, FIFO or directory is refused before the first frame is drawn.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use super::clock::Step;
use super::progress::Progress;
use crate::capture::FrameCapture;
use crate::messages;
use crate::ui::Lab;
use crate::writing::{AtomicFile, Pending};

/// Most frames one recording takes.
pub const MAX_FRAMES: u32 = 10_000;
/// Most steps between two frames.
pub const MAX_EVERY: u64 = 100_000;
/// Frames a second the default `--every` aims at (simulated time).
const DEFAULT_FPS: f64 = 30.0;
/// Shortest delay a GIF can show as asked (1/100 s).
const GIF_MIN_DELAY_CS: u64 = 2;
/// NeuQuant's speed for GIF palettes: 1 (best) to 30 (fastest); 10 is its default.
const GIF_QUANTIZE_SPEED: i32 = 10;

/// What `--out` names, by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Container {
    /// `.png`: one frame, or with `--frames` a numbered sequence.
    Png,
    /// `.gif`: an animated GIF.
    Gif,
    /// `.apng`: an animated PNG.
    Apng,
}

impl Container {
    /// The container `--out` names, checked against whether `--frames` (and `--every`)
    /// were given.
    pub fn of(out: &Path, frames: bool, every: bool) -> Result<Self, String> {
        let extension = out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        let container = match extension.as_deref() {
            Some("png") => Self::Png,
            Some("gif") => Self::Gif,
            Some("apng") => Self::Apng,
            _ => {
                return Err(format!(
                    "--out {} must name a .png file, or with --frames a .png (numbered sequence), \
                     .gif or .apng file",
                    messages::path(out)
                ));
            }
        };
        if !frames && every {
            return Err("--every K sets the steps between recorded frames: give --frames N too".into());
        }
        if !frames && container != Self::Png {
            return Err(format!(
                "--out {} is an animation: give --frames N (and --every K)",
                messages::path(out)
            ));
        }
        Ok(container)
    }
}

/// A checked recording: how many frames, how far apart, into what.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Plan {
    /// Where the frames go.
    pub container: Container,
    /// Frames to draw.
    pub frames: u32,
    /// Physics steps between frames.
    pub every: u64,
    /// The physics time step, as the fraction it stands for.
    pub step: Step,
}

impl Plan {
    /// Checks `--frames` and `--every` for a run of `steps` warm-up steps of `dt`;
    /// `every` defaults to the steps nearest 1/30 s.
    pub fn new(
        container: Container,
        frames: u32,
        every: Option<u64>,
        steps: u64,
        dt: f32,
        max_steps: u64,
    ) -> Result<Self, String> {
        if !(1..=MAX_FRAMES).contains(&frames) {
            return Err(format!("--frames {frames} is out of range; valid range: 1 to {MAX_FRAMES}"));
        }
        let step =
            Step::of(dt).ok_or_else(|| format!("a time step of {dt} s is too fine to time frames by"))?;
        let every = match every {
            Some(every) if !(1..=MAX_EVERY).contains(&every) => {
                return Err(format!("--every {every} is out of range; valid range: 1 to {MAX_EVERY}"));
            }
            Some(every) => every,
            None => ((1.0 / DEFAULT_FPS / step.seconds()).round() as u64).clamp(1, MAX_EVERY),
        };
        let total = steps.saturating_add(u64::from(frames - 1).saturating_mul(every));
        if total > max_steps {
            return Err(format!(
                "--steps {steps} and --frames {frames} --every {every} make {total} steps; at most \
                 {max_steps}"
            ));
        }
        let plan = Self { container, frames, every, step };
        if container == Container::Gif {
            let (numerator, denominator) = step.times(every);
            // K dt >= 0.02 s, in whole numbers: 100 numerator >= 2 denominator.
            if u128::from(numerator) * 100 < u128::from(GIF_MIN_DELAY_CS) * u128::from(denominator) {
                let needed = (GIF_MIN_DELAY_CS as f64 / 100.0 / step.seconds()).ceil() as u64;
                return Err(format!(
                    "--every {every} puts frames {} s apart, faster than a GIF can show (0.02 s); \
                     use --every {needed} or more, or write an .apng",
                    plan.interval_text()
                ));
            }
        }
        Ok(plan)
    }

    /// Steps from the first frame to the last.
    #[must_use]
    pub fn span(&self) -> u64 {
        u64::from(self.frames - 1) * self.every
    }

    /// The simulated time between frames, as text: `1/30` or `0.05`.
    #[must_use]
    pub fn interval_text(&self) -> String {
        let (numerator, denominator) = self.step.times(self.every);
        Step { numerator, denominator }.to_string()
    }
}

/// The path of frame `index` (from 1) of a sequence of `frames` written for `out`:
/// `run.png` gives `run-0001.png`.
#[must_use]
pub fn frame_path(out: &Path, index: u32, frames: u32) -> PathBuf {
    let digits = frames.to_string().len().max(4);
    let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let extension = out.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
    out.with_file_name(format!("{stem}-{index:0digits$}.{extension}"))
}

/// Runs `steps` steps of `lab` (stopping if it pauses itself: the state blew up),
/// moving `progress` on from `done`; returns the steps done now.
pub fn step(lab: &mut Lab, steps: u64, progress: &mut Progress, done: u64) -> u64 {
    // The lab logs a blow-up for the window's log; here the one line that ends the run
    // says it (unless RUST_LOG asked for more than warnings).
    let level = log::max_level();
    if level <= log::LevelFilter::Warn {
        log::set_max_level(log::LevelFilter::Error);
    }
    let ran = step_quietly(lab, steps, progress, done);
    log::set_max_level(level);
    ran
}

fn step_quietly(lab: &mut Lab, steps: u64, progress: &mut Progress, done: u64) -> u64 {
    const CHUNK: u64 = 64;
    let mut ran = 0;
    while ran < steps {
        let chunk = CHUNK.min(steps - ran);
        lab.run_steps_recorded(chunk);
        ran += chunk;
        progress.set(done + ran);
        if lab.paused {
            break;
        }
    }
    done + ran
}

/// Records `plan.frames` frames of `lab` at `size` after `warm_up` steps, into `out`.
/// Returns what was written, or `(exit code, message)`.
pub fn record(
    lab: &mut Lab,
    plan: &Plan,
    out: &Path,
    size: [u32; 2],
    with_ui: bool,
    warm_up: u64,
) -> Result<String, (u8, String)> {
    // The GPU and the file first: a missing driver or directory is said before a long run.
    let mut capture = FrameCapture::new().map_err(|e| (1, e))?;
    let mut sink = Sink::create(out, size, plan).map_err(|e| (1, e))?;
    let mut progress = Progress::new(warm_up + plan.span(), "steps", Progress::for_terminal(true));
    let mut done = step(lab, warm_up, &mut progress, 0);
    // The first frame that shows the state the run stopped in, if it blew up.
    let mut frozen_from = lab.paused.then_some(1);
    for index in 1..=plan.frames {
        if index > 1 && !lab.paused {
            done = step(lab, plan.every, &mut progress, done);
            if lab.paused {
                frozen_from = Some(index);
            }
        }
        let pixels = capture.render(lab, size, with_ui).map_err(|e| (1, e))?;
        sink.push(index, pixels).map_err(|e| (1, e))?;
    }
    let written = sink.finish()?;
    drop(progress);
    let name = lab.entry.info().name.to_string();
    if let Some(index) = frozen_from {
        return Err((
            1,
            format!(
                "wrote {written}, but {name} stopped at step {}: {} (frames {index} to {} show where)",
                lab.scene.world().steps(),
                lab.status,
                plan.frames
            ),
        ));
    }
    Ok(format!(
        "wrote {written}: {} frames of {name}, {}x{}, steps {warm_up} to {}, {} s apart",
        plan.frames,
        size[0],
        size[1],
        warm_up + plan.span(),
        plan.interval_text()
    ))
}

/// "cannot write PATH: why", in one line and without the OS's error number.
fn cannot(out: &Path, error: &dyn std::fmt::Display) -> String {
    let text = error.to_string();
    let reason = text.split(" (os error").next().unwrap_or(&text);
    format!("cannot write {}: {}", messages::path(out), messages::quote(reason))
}

/// The temporary file for `out`, beside the file it will replace; a device, FIFO,
/// socket or directory (or a link to one) is refused, naming `out`.
fn create(out: &Path) -> Result<AtomicFile, String> {
    AtomicFile::create(out).map_err(|e| cannot(out, &e))
}

/// Puts the complete file in place of `out`.
fn keep(out: &Path, pending: Pending) -> Result<(), String> {
    pending.commit().map_err(|e| cannot(out, &e))
}

/// Writes one PNG frame to `out`, whole or not at all.
pub fn write_png(out: &Path, size: [u32; 2], rgba: &[u8]) -> Result<(), String> {
    crate::render::offscreen::write_png(out, size, rgba)
}

/// Where frames go as they are drawn.
enum Sink {
    Sequence {
        out: PathBuf,
        frames: u32,
        size: [u32; 2],
    },
    Gif {
        // A dropped encoder finishes writing into the file, then the file is removed.
        encoder: gif::Encoder<AtomicFile>,
        out: PathBuf,
        size: [u16; 2],
        delays: GifDelays,
    },
    Apng {
        // Before the pending rename: dropped first, then the file goes.
        writer: png::Writer<BufWriter<File>>,
        pending: Pending,
        out: PathBuf,
    },
}

impl Sink {
    fn create(out: &Path, size: [u32; 2], plan: &Plan) -> Result<Self, String> {
        let cannot = |e: &dyn std::fmt::Display| cannot(out, e);
        match plan.container {
            Container::Png => {
                // Each frame is its own file, written when drawn: the first is checked now.
                let first = frame_path(out, 1, plan.frames);
                crate::writing::target(&first).map_err(|e| self::cannot(&first, &e))?;
                Ok(Self::Sequence { out: out.to_path_buf(), frames: plan.frames, size })
            }
            Container::Gif => {
                let (Ok(width), Ok(height)) = (u16::try_from(size[0]), u16::try_from(size[1])) else {
                    return Err(format!("a GIF is at most {0}x{0} pixels", u16::MAX));
                };
                let mut encoder =
                    gif::Encoder::new(create(out)?, width, height, &[]).map_err(|e| cannot(&e))?;
                encoder.set_repeat(gif::Repeat::Infinite).map_err(|e| cannot(&e))?;
                let (numerator, denominator) = plan.step.times(plan.every);
                Ok(Self::Gif {
                    encoder,
                    out: out.to_path_buf(),
                    size: [width, height],
                    delays: GifDelays { numerator, denominator, frames: 0 },
                })
            }
            Container::Apng => {
                let (file, pending) = create(out)?.split();
                let mut encoder = png::Encoder::new(file, size[0], size[1]);
                encoder.set_color(png::ColorType::Rgba);
                encoder.set_depth(png::BitDepth::Eight);
                encoder.set_animated(plan.frames, 0).map_err(|e| cannot(&e))?;
                let (numerator, denominator) = apng_delay(plan.step.times(plan.every));
                encoder.set_frame_delay(numerator, denominator).map_err(|e| cannot(&e))?;
                let writer = encoder.write_header().map_err(|e| cannot(&e))?;
                Ok(Self::Apng { writer, pending, out: out.to_path_buf() })
            }
        }
    }

    /// Adds frame `index` (from 1), RGBA bytes.
    fn push(&mut self, index: u32, mut rgba: Vec<u8>) -> Result<(), String> {
        match self {
            Self::Sequence { out, frames, size } => write_png(&frame_path(out, index, *frames), *size, &rgba),
            Self::Gif { encoder, out, size, delays } => {
                let mut frame = gif::Frame::from_rgba_speed(size[0], size[1], &mut rgba, GIF_QUANTIZE_SPEED);
                frame.delay = delays.next();
                encoder.write_frame(&frame).map_err(|e| cannot(out, &e))
            }
            Self::Apng { writer, out, .. } => writer.write_image_data(&rgba).map_err(|e| cannot(out, &e)),
        }
    }

    /// Closes the file and puts it in place; says what was written.
    fn finish(self) -> Result<String, (u8, String)> {
        match self {
            Self::Sequence { out, frames, .. } => Ok(format!(
                "{} to {}",
                messages::path(&frame_path(&out, 1, frames)),
                messages::path(&frame_path(&out, frames, frames))
            )),
            Self::Gif { encoder, out, .. } => {
                let file = encoder.into_inner().map_err(|e| (1, cannot(&out, &e)))?;
                file.commit().map_err(|e| (1, cannot(&out, &e)))?;
                Ok(format!("{} (GIF)", messages::path(&out)))
            }
            Self::Apng { writer, pending, out } => {
                writer.finish().map_err(|e| (1, cannot(&out, &e)))?;
                keep(&out, pending).map_err(|e| (1, e))?;
                Ok(format!("{} (animated PNG)", messages::path(&out)))
            }
        }
    }
}

/// GIF delays in 1/100 s for frames `numerator/denominator` s apart: each frame ends at
/// its true time rounded, so the rounding never adds up.
struct GifDelays {
    numerator: u64,
    denominator: u64,
    frames: u64,
}

impl GifDelays {
    fn next(&mut self) -> u16 {
        let centiseconds = |frames: u64| {
            let hundredths = u128::from(frames) * u128::from(self.numerator) * 100;
            let denominator = u128::from(self.denominator);
            (hundredths + denominator / 2) / denominator
        };
        let delay = centiseconds(self.frames + 1) - centiseconds(self.frames);
        self.frames += 1;
        u16::try_from(delay).unwrap_or(u16::MAX)
    }
}

/// An APNG delay: the exact fraction when it fits in 16 bits, else milliseconds, else
/// whole seconds.
fn apng_delay((numerator, denominator): (u64, u64)) -> (u16, u16) {
    if let (Ok(n), Ok(d)) = (u16::try_from(numerator), u16::try_from(denominator)) {
        return (n, d);
    }
    let seconds = numerator as f64 / denominator as f64;
    if seconds * 1000.0 <= f64::from(u16::MAX) {
        ((seconds * 1000.0).round().max(1.0) as u16, 1000)
    } else {
        (seconds.round().min(f64::from(u16::MAX)) as u16, 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sequence_frames_are_numbered_from_one_with_four_digits_or_more() {
        let out = Path::new("shots/run.png");
        assert_eq!(frame_path(out, 1, 30), Path::new("shots/run-0001.png"));
        assert_eq!(frame_path(out, 12345, 20000), Path::new("shots/run-12345.png"));
        assert_eq!(frame_path(out, 7, 20000), Path::new("shots/run-00007.png"));
    }

    #[test]
    fn gif_delays_carry_their_rounding() {
        // 1/30 s apart: 3.33 hundredths a frame, 10 every three frames.
        let mut delays = GifDelays { numerator: 1, denominator: 30, frames: 0 };
        let first: Vec<u16> = (0..6).map(|_| delays.next()).collect();
        assert_eq!(first, vec![3, 4, 3, 3, 4, 3]);
    }

    #[test]
    fn the_default_every_is_about_a_thirtieth_of_a_second() {
        let plan = Plan::new(Container::Gif, 10, None, 0, 1.0 / 240.0, 1_000_000).unwrap();
        assert_eq!((plan.every, plan.interval_text()), (8, "1/30".to_string()));
        let plan = Plan::new(Container::Apng, 10, None, 0, 1.0 / 60.0, 1_000_000).unwrap();
        assert_eq!(plan.every, 2);
    }

    #[test]
    fn bad_recordings_are_refused_with_one_line() {
        let dt = 1.0 / 240.0;
        let error = Plan::new(Container::Gif, 10, Some(1), 0, dt, 1_000_000).unwrap_err();
        assert_eq!(
            error,
            "--every 1 puts frames 1/240 s apart, faster than a GIF can show (0.02 s); use --every 5 \
             or more, or write an .apng"
        );
        assert!(Plan::new(Container::Gif, 10, Some(5), 0, dt, 1_000_000).is_ok());
        let error = Plan::new(Container::Png, 0, None, 0, dt, 1_000_000).unwrap_err();
        assert_eq!(error, "--frames 0 is out of range; valid range: 1 to 10000");
        let error = Plan::new(Container::Png, 3, Some(0), 0, dt, 1_000_000).unwrap_err();
        assert_eq!(error, "--every 0 is out of range; valid range: 1 to 100000");
        let error = Plan::new(Container::Png, 10_000, Some(100_000), 5, dt, 1_000_000).unwrap_err();
        assert!(error.contains("999900005 steps; at most 1000000"), "{error}");
        let error = Container::of(Path::new("run.gif"), false, false).unwrap_err();
        assert!(error.contains("give --frames N"), "{error}");
        let error = Container::of(Path::new("run.jpg"), true, false).unwrap_err();
        assert!(error.contains(".gif or .apng"), "{error}");
        assert!(Container::of(Path::new("run.png"), false, true).is_err());
        assert_eq!(Container::of(Path::new("RUN.APNG"), true, true), Ok(Container::Apng));
    }

    #[test]
    fn a_recording_is_refused_before_its_first_frame_where_it_cannot_be_written() {
        let dir = std::env::temp_dir().join(format!("particle-lab-sink-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("run.gif")).unwrap();
        std::fs::create_dir_all(dir.join("shot-0001.png")).unwrap();
        let dt = 1.0 / 240.0;
        for (name, container) in [("run.gif", Container::Gif), ("shot.png", Container::Png)] {
            let plan = Plan::new(container, 3, Some(8), 0, dt, 1_000_000).unwrap();
            let error = Sink::create(&dir.join(name), [8, 8], &plan).err().unwrap();
            assert!(
                error.starts_with("cannot write ")
                    && error.ends_with("it is a directory, not a regular file")
            );
        }
        // A whole APNG, then one stopped part way: the second leaves the first whole.
        let out = dir.join("run.apng");
        let plan = Plan::new(Container::Apng, 1, Some(8), 0, dt, 1_000_000).unwrap();
        let mut sink = Sink::create(&out, [2, 2], &plan).unwrap();
        sink.push(1, vec![255; 16]).unwrap();
        sink.finish().unwrap();
        let whole = std::fs::read(&out).unwrap();
        drop(Sink::create(&out, [2, 2], &plan).unwrap());
        assert_eq!(std::fs::read(&out).unwrap(), whole);
        assert!(!dir.join("run.apng.part").exists(), "a stopped recording leaves nothing");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn apng_delays_are_exact_fractions_when_they_fit() {
        assert_eq!(apng_delay((1, 30)), (1, 30));
        assert_eq!(apng_delay((1, 100_000)), (1, 1000));
        assert_eq!(apng_delay((100_000, 1)), (u16::MAX, 1));
    }
}
