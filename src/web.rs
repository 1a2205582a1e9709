//! The lab in a browser: the page's entry point. Everything else (the engine, the
//! scenes, the renderer, the panel, the lab's tools) is the desktop's own code, and what
//! the page itself offers (its canvas, GPU, files, downloads and state element) is in
//! [`crate::ui::page`]; this file reads the link, opens the lab it asks for and hands the
//! canvas to the event loop.
//!
//! A link opens an exact experiment ([`Link`]: its query string read as the window's
//! command line, with the same checks and one-line messages, shown in the status line).

use wasm_bindgen::JsCast;
use winit::event_loop::EventLoop;
use winit::platform::web::EventLoopExtWebSys;

use crate::app::App;
use crate::settings::{self, Launch, Store};
use crate::ui::lab::Link;
use crate::ui::page;

/// The page's query string and fragment (a scene file carried in the link is there,
/// out of any server's log) as decoded pairs, the query's first.
fn query_pairs() -> Vec<(String, String)> {
    let location = web_sys::window().map(|w| w.location());
    let search = location.as_ref().and_then(|l| l.search().ok()).unwrap_or_default();
    let hash = location.as_ref().and_then(|l| l.hash().ok()).unwrap_or_default();
    let mut pairs = Vec::new();
    for part in [search, hash.trim_start_matches('#').to_string()] {
        let Ok(params) = web_sys::UrlSearchParams::new_with_str(&part) else { continue };
        if let Ok(Some(entries)) = js_sys::try_iter(&params) {
            for entry in entries.flatten() {
                let entry: js_sys::Array = entry.unchecked_into();
                let text = |i| entry.get(i).as_string().unwrap_or_default();
                pairs.push((text(0), text(1)));
            }
        }
    }
    pairs
}

/// The page's entry point (the binary's `main` in a browser): reads the link, opens
/// the lab it asks for (the defaults, with the message in the status line, for a bad
/// one) and hands the page's canvas to the event loop.
pub fn start() {
    std::panic::set_hook(Box::new(|info| {
        let message = format!("particle-lab stopped: {info}");
        web_sys::console::error_1(&message.as_str().into());
        page::show_failure(&message);
    }));
    let _ = log::set_logger(&CONSOLE).map(|()| log::set_max_level(log::LevelFilter::Info));
    reload_on_new_fragment();

    let mut problems = Vec::new();
    let mut link = Link::parse(&query_pairs()).unwrap_or_else(|message| {
        problems.push(message);
        Link::default()
    });
    page::set_webgl2_only(link.webgl2_only);
    let mut launch = Launch::from_args(&link.args).unwrap_or_else(|message| {
        problems.push(message);
        Launch::default()
    });
    launch.scene_text = link.scene_text.take();
    if link.names_experiment() {
        launch.link = Some(settings::LinkRate(link.rate));
    }
    let opened = settings::open(&launch, Store::from_platform()).or_else(|message| {
        problems.push(message);
        settings::open(&Launch { fresh: launch.fresh, ..Launch::default() }, Store::from_platform())
    });
    let opened = match opened {
        Ok(opened) => opened,
        Err(message) => {
            page::show_failure(&format!("particle-lab cannot open: {message}"));
            return;
        }
    };
    if let Some(warning) = &opened.warning {
        problems.push(warning.trim_start_matches("particle-lab: ").to_string());
    }
    let settings::Opened { mut lab, layout, window, store, .. } = opened;
    link.view.apply(&mut lab);
    link.run_steps(&mut lab);
    if !problems.is_empty() {
        lab.status = problems.join("; ");
        log::warn!("{}", lab.status);
    }
    let event_loop = match EventLoop::<crate::app::AppEvent>::with_user_event().build() {
        Ok(event_loop) => event_loop,
        Err(error) => {
            page::show_failure(&format!("particle-lab cannot start: {error}"));
            return;
        }
    };
    event_loop.spawn_app(App::new(lab, layout, store, window));
}

/// A link pasted into the same tab that differs only after the `#` (another scene
/// file carried in it) moves to the new fragment without loading the page again:
/// the page then loads itself again, so the new link is read. (Copy link changes the
/// address with `history.replaceState`, which fires no `hashchange`.)
fn reload_on_new_fragment() {
    let Some(window) = web_sys::window() else { return };
    let reload = wasm_bindgen::closure::Closure::<dyn FnMut()>::new(|| {
        if let Some(window) = web_sys::window() {
            let _ = window.location().reload();
        }
    });
    window.set_onhashchange(Some(reload.as_ref().unchecked_ref()));
    // The page keeps it for its lifetime.
    reload.forget();
}

/// The log, to the browser's console.
struct Console;

static CONSOLE: Console = Console;

impl log::Log for Console {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.level() <= log::Level::Info && metadata.target().starts_with("particle_lab")
    }

    fn log(&self, record: &log::Record<'_>) {
        if !self.enabled(record.metadata()) {
            return;
        }
        let text = format!("{}: {}", record.level(), record.args());
        let text = wasm_bindgen::JsValue::from_str(&text);
        match record.level() {
            log::Level::Error => web_sys::console::error_1(&text),
            log::Level::Warn => web_sys::console::warn_1(&text),
            _ => web_sys::console::log_1(&text),
        }
    }

    fn flush(&self) {}
}
