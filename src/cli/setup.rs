//! What the binary arranges before anything else runs: the log's shape and level, and
//! a runtime directory for the C graphics libraries when the session has none.

use std::io::Write;

/// Starts the log: warnings and errors only, unless `RUST_LOG` asks for more.
///
/// Each record is one line with the same prefix as every other message,
/// `particle-lab: warning: ...`. With `RUST_LOG` set (someone debugging) the record's
/// module is shown too, `particle-lab: info [particle_lab::app]: window open`.
pub fn init_logging() {
    let debugging = std::env::var_os("RUST_LOG").is_some_and(|v| !v.is_empty());
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format(move |out, record| {
            let level = match record.level() {
                log::Level::Error => "error",
                log::Level::Warn => "warning",
                log::Level::Info => "info",
                log::Level::Debug => "debug",
                log::Level::Trace => "trace",
            };
            if debugging {
                writeln!(out, "particle-lab: {level} [{}]: {}", record.target(), record.args())
            } else {
                writeln!(out, "particle-lab: {level}: {}", record.args())
            }
        })
        .init();
}

/// Points `XDG_RUNTIME_DIR` at a private directory when it is unset or names no
/// directory.
///
/// Mesa and the Vulkan loader complain on stderr ("XDG_RUNTIME_DIR is invalid or not
/// set in the environment") on machines without a login session: a server, a
/// container, CI. Nothing is wrong there, so the message is kept from the user by
/// giving them a directory that passes their check: `$TMPDIR/particle-lab-UID`, mode
/// 0700, owned by this user. A directory of that name that is not ours is left alone.
///
/// # Safety
/// Changes the process environment: call it first in `main`, before any thread starts.
pub unsafe fn private_runtime_dir() {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::{DirBuilderExt, MetadataExt, PermissionsExt};
        use std::path::Path;

        let Ok(uid) = std::fs::metadata("/proc/self").map(|m| m.uid()) else { return };
        let private = |path: &Path| {
            std::fs::symlink_metadata(path)
                .is_ok_and(|m| m.is_dir() && m.uid() == uid && m.permissions().mode() & 0o777 == 0o700)
        };
        // A directory the session set is kept even if loosely protected: a Wayland
        // display's socket lives there.
        if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|dir| {
            let dir = Path::new(&dir);
            dir.is_absolute() && dir.is_dir()
        }) {
            return;
        }
        let dir = std::env::temp_dir().join(format!("particle-lab-{uid}"));
        // Fails harmlessly when it exists; `private` then says whether it is ours.
        let _ = std::fs::DirBuilder::new().mode(0o700).create(&dir);
        if private(&dir) {
            debug_assert!(
                std::fs::read_dir("/proc/self/task").map_or(true, |tasks| tasks.count() == 1),
                "the environment is changed while other threads run"
            );
            // SAFETY: the caller runs this before any other thread exists (debug builds
            // count the process's threads above).
            unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
        }
    }
}

/// A panic is a bug, never the user's input: it gets one line in the common shape,
/// without the source location, unless `RUST_BACKTRACE` asks for the details.
pub fn plain_panics() {
    if std::env::var_os("RUST_BACKTRACE").is_some() {
        return;
    }
    std::panic::set_hook(Box::new(|info| {
        let payload = info.payload();
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".into());
        let message = crate::messages::plain(&message).replace('\n', " ");
        eprintln!(
            "particle-lab: internal error, the program panicked: {message}; please report it \
             (RUST_BACKTRACE=1 shows where)"
        );
    }));
}
