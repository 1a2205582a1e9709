//! The `particle-lab` binary: a thin wrapper over the library. In a browser its
//! `main` is the page's entry point, [`particle_lab::web::start`].

#[cfg(not(target_arch = "wasm32"))]
use std::io::{self, Write};
#[cfg(not(target_arch = "wasm32"))]
use std::process::ExitCode;

#[cfg(not(target_arch = "wasm32"))]
use particle_lab::app::{self, AppError};
#[cfg(not(target_arch = "wasm32"))]
use particle_lab::cli::{self, Command, USAGE_ERROR};
#[cfg(not(target_arch = "wasm32"))]
use particle_lab::settings::Launch;

#[cfg(target_arch = "wasm32")]
fn main() {
    particle_lab::web::start();
}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> ExitCode {
    // SAFETY: the first thing the process does; no other thread exists yet.
    unsafe { cli::setup::private_runtime_dir() };
    cli::setup::init_logging();
    cli::setup::plain_panics();
    let args = cli::parse();
    match args.command {
        Some(Command::Scenes { about: Some(name), .. }) => match cli::about_scene(&name) {
            Ok(page) => {
                print!("{page}");
                ExitCode::SUCCESS
            }
            Err(message) => usage_error(&message),
        },
        Some(Command::Scenes { format, about: None }) => {
            finish(cli::list_scenes(format, &mut io::stdout().lock()).map(Ok))
        }
        Some(Command::Simulate(simulate)) => match cli::prepare(&simulate) {
            Ok((mut scene, plan)) => {
                let mut out = io::BufWriter::new(io::stdout().lock());
                let result = cli::simulate(scene.as_mut(), plan, &mut out);
                finish(result.and_then(|r| out.flush().map(|()| r)))
            }
            Err(message) => usage_error(&message),
        },
        Some(Command::Render(render)) => match cli::render(&render) {
            Ok(message) => {
                println!("{message}");
                ExitCode::SUCCESS
            }
            Err((code, message)) => {
                eprintln!("particle-lab: {}", particle_lab::messages::one_line(&message));
                ExitCode::from(code)
            }
        },
        Some(Command::Link(link)) => match cli::link::link(&link) {
            Ok(link) => {
                println!("{link}");
                ExitCode::SUCCESS
            }
            Err(message) => usage_error(&message),
        },
        Some(Command::Open(open)) => window(Launch::from_link(&open.link)),
        Some(Command::Export(export)) => match cli::export::export(&export) {
            Ok(cli::export::Exported { text, left_out }) => match &export.out {
                None => {
                    if !left_out.is_empty() {
                        eprintln!("particle-lab: note: the file leaves out {}", left_out.join(", "));
                    }
                    print!("{text}");
                    ExitCode::SUCCESS
                }
                Some(path) => match particle_lab::writing::write_atomic(path, text.as_bytes()) {
                    Ok(()) => {
                        if !left_out.is_empty() {
                            eprintln!("particle-lab: note: the file leaves out {}", left_out.join(", "));
                        }
                        println!("wrote {}", particle_lab::messages::path(path));
                        ExitCode::SUCCESS
                    }
                    Err(error) => {
                        eprintln!(
                            "particle-lab: cannot write {}: {error}",
                            particle_lab::messages::path(path)
                        );
                        ExitCode::from(1)
                    }
                },
            },
            Err(message) => usage_error(&message),
        },
        Some(Command::Fit(fit)) => match cli::fit::fit(&fit) {
            Ok(line) => {
                println!("{line}");
                ExitCode::SUCCESS
            }
            Err(message) => usage_error(&message),
        },
        None => window(Launch::from_cli(&args)),
    }
}

/// Opens the window as `launch` asks; a bad command line or link is a usage error.
#[cfg(not(target_arch = "wasm32"))]
fn window(launch: Result<Launch, String>) -> ExitCode {
    match launch.map_err(AppError::Usage).and_then(|launch| app::run(&launch)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(AppError::Usage(message)) => usage_error(&message),
        Err(AppError::Fatal(message)) => {
            eprintln!("particle-lab: {}", particle_lab::messages::one_line(&message));
            ExitCode::from(1)
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
fn usage_error(message: &str) -> ExitCode {
    eprintln!("particle-lab: {}", particle_lab::messages::one_line(message));
    ExitCode::from(USAGE_ERROR as u8)
}

/// Maps a command's outcome to an exit code; a closed pipe (`| head`) is not an error.
#[cfg(not(target_arch = "wasm32"))]
fn finish(result: io::Result<Result<(), String>>) -> ExitCode {
    match result {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(message)) => {
            eprintln!("particle-lab: {}", particle_lab::messages::one_line(&message));
            ExitCode::from(1)
        }
        Err(error) if error.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(error) => {
            let _ = writeln!(io::stderr(), "particle-lab: cannot write output: {error}");
            ExitCode::from(1)
        }
    }
}
