//! The `particle-lab` binary: a thin wrapper over the library.

use std::io::{self, Write};
use std::process::ExitCode;

use particle_lab::cli::{self, Command, USAGE_ERROR};

fn main() -> ExitCode {
    let args = cli::parse();
    match args.command {
        Some(Command::Scenes { format }) => {
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
        None => {
            eprintln!(
                "particle-lab: the window is not built yet; try 'particle-lab simulate --scene projectile'"
            );
            ExitCode::from(1)
        }
    }
}

fn usage_error(message: &str) -> ExitCode {
    eprintln!("particle-lab: {message}");
    ExitCode::from(USAGE_ERROR as u8)
}

/// Maps a command's outcome to an exit code; a closed pipe (`| head`) is not an error.
fn finish(result: io::Result<Result<(), String>>) -> ExitCode {
    match result {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(message)) => {
            eprintln!("particle-lab: {message}");
            ExitCode::from(1)
        }
        Err(error) if error.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(error) => {
            let _ = writeln!(io::stderr(), "particle-lab: cannot write output: {error}");
            ExitCode::from(1)
        }
    }
}
