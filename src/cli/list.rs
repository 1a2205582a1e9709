//! `scenes`: lists the compiled scenes and the shipped scene files, as a table or JSON.

use std::io::{self, Write};

use clap::ValueEnum;
use serde::Serialize;

use super::clock;
use crate::scenes::{self, SCENES};

/// Output format of `scenes`.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Format {
    /// Human-readable table.
    Text,
    /// One JSON array.
    Json,
}

/// The scenes `scenes` lists: the compiled ones, then the shipped scene files.
fn listed() -> impl Iterator<Item = &'static scenes::SceneEntry> {
    SCENES.iter().chain(scenes::file::shipped())
}

/// `scenes --about NAME`: the scene's page on its physics as plain text (a scene file's
/// summary above the page shared by files), or why there is none.
pub fn about_scene(name: &str) -> Result<String, String> {
    let info = scenes::find(name)?.info();
    Ok(match scenes::about::page(&info.name) {
        Some(page) => page.text(),
        None => format!("{}: {}\n\n{}", info.name, info.summary, scenes::about::FILE_PAGE.text()),
    })
}

/// Runs `scenes`.
pub fn list_scenes(format: Format, out: &mut impl Write) -> io::Result<()> {
    match format {
        Format::Json => {
            let list: Vec<SceneJson> = listed()
                .map(|entry| {
                    let info = entry.info();
                    SceneJson {
                        name: &info.name,
                        summary: &info.summary,
                        dt: clock::Step::of(info.dt).map_or(f64::from(info.dt), clock::Step::seconds),
                        default_steps: info.default_steps,
                        params: info
                            .params
                            .iter()
                            .map(|p| ParamJson {
                                name: &p.name,
                                unit: &p.unit,
                                default: p.default,
                                min: p.min,
                                max: p.max,
                                help: &p.help,
                            })
                            .collect(),
                        presets: info.presets.iter().map(|p| p.name).collect(),
                        actions: info.actions.iter().map(|a| a.label).collect(),
                    }
                })
                .collect();
            serde_json::to_writer(&mut *out, &list)?;
            writeln!(out)
        }
        Format::Text => {
            for entry in listed() {
                let info = entry.info();
                writeln!(out, "{} — {}", info.name, info.summary)?;
                writeln!(
                    out,
                    "  dt {} s ({:.0} Hz), {} steps by default",
                    clock::Step::of(info.dt).map_or(info.dt.to_string(), |step| step.to_string()),
                    1.0 / info.dt,
                    info.default_steps
                )?;
                for p in info.params.iter() {
                    let unit = if p.unit.is_empty() { String::new() } else { format!(" {}", p.unit) };
                    writeln!(
                        out,
                        "  {:<12} {:>9}{unit:<6} [{} .. {}]  {}",
                        p.name, p.default, p.min, p.max, p.help
                    )?;
                }
                if !info.presets.is_empty() {
                    let names: Vec<_> = info.presets.iter().map(|p| p.name).collect();
                    writeln!(out, "  presets: {}", names.join(", "))?;
                }
                writeln!(out)?;
            }
            Ok(())
        }
    }
}

#[derive(Serialize)]
struct SceneJson {
    name: &'static str,
    summary: &'static str,
    /// The step it stands for (1/240 s), not its f32.
    dt: f64,
    default_steps: u32,
    params: Vec<ParamJson>,
    presets: Vec<&'static str>,
    actions: Vec<&'static str>,
}

#[derive(Serialize)]
struct ParamJson {
    name: &'static str,
    unit: &'static str,
    default: f32,
    min: f32,
    max: f32,
    help: &'static str,
}
