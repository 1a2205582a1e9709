//! The lab in a browser: the page's entry point and what differs there. Everything
//! else (the engine, the scenes, the renderer, the panel, the lab's tools) is the
//! desktop's own code; this file only reads the link, finds the canvas and the GPU,
//! and keeps the page's state element up to date.
//!
//! A link opens an exact experiment ([`Link`]: its query string read as the window's
//! command line, with the same checks and one-line messages, shown in the status line).
//!
//! The page (`web/index.html`) keeps `<output id="state" data-step="N"
//! data-hash="HEX" data-gpu="webgpu|webgl2">`, updated as the world steps: the hash is
//! `simulate`'s, so a test can compare the page with the desktop.

use std::cell::Cell;

use wasm_bindgen::JsCast;
use winit::event_loop::EventLoop;
use winit::platform::web::EventLoopExtWebSys;

use crate::app::App;
use crate::settings::{self, Launch, Link, Store};
use crate::ui::Lab;

thread_local! {
    /// `gpu=webgl2`: the instance is made without WebGPU.
    static WEBGL2_ONLY: Cell<bool> = const { Cell::new(false) };
}

/// The page's query string as decoded pairs.
fn query_pairs() -> Vec<(String, String)> {
    let search = web_sys::window().and_then(|w| w.location().search().ok()).unwrap_or_default();
    let Ok(params) = web_sys::UrlSearchParams::new_with_str(&search) else { return Vec::new() };
    let mut pairs = Vec::new();
    if let Ok(Some(entries)) = js_sys::try_iter(&params) {
        for entry in entries.flatten() {
            let entry: js_sys::Array = entry.unchecked_into();
            let text = |i| entry.get(i).as_string().unwrap_or_default();
            pairs.push((text(0), text(1)));
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
        show_failure(&message);
    }));
    let _ = log::set_logger(&CONSOLE).map(|()| log::set_max_level(log::LevelFilter::Info));

    let mut problems = Vec::new();
    let link = Link::parse(&query_pairs()).unwrap_or_else(|message| {
        problems.push(message);
        Link::default()
    });
    WEBGL2_ONLY.with(|only| only.set(link.webgl2_only));
    let launch = Launch::from_args(&link.args).unwrap_or_else(|message| {
        problems.push(message);
        Launch::default()
    });
    let opened = settings::open(&launch, Store::from_platform()).or_else(|message| {
        problems.push(message);
        settings::open(&Launch { fresh: launch.fresh, ..Launch::default() }, Store::from_platform())
    });
    let opened = match opened {
        Ok(opened) => opened,
        Err(message) => {
            show_failure(&format!("particle-lab cannot open: {message}"));
            return;
        }
    };
    if let Some(warning) = &opened.warning {
        problems.push(warning.trim_start_matches("particle-lab: ").to_string());
    }
    let settings::Opened { mut lab, layout, window, store, .. } = opened;
    link.run_steps(&mut lab);
    if !problems.is_empty() {
        lab.status = problems.join("; ");
        log::warn!("{}", lab.status);
    }
    let event_loop = match EventLoop::new() {
        Ok(event_loop) => event_loop,
        Err(error) => {
            show_failure(&format!("particle-lab cannot start: {error}"));
            return;
        }
    };
    event_loop.spawn_app(App::new(lab, layout, store, window));
}

/// The page's canvas, `<canvas id="lab">`.
pub fn canvas() -> Result<web_sys::HtmlCanvasElement, String> {
    element("lab")
        .and_then(|e| e.dyn_into::<web_sys::HtmlCanvasElement>().ok())
        .ok_or_else(|| "the page has no <canvas id=\"lab\">".to_string())
}

fn element(id: &str) -> Option<web_sys::Element> {
    web_sys::window()?.document()?.get_element_by_id(id)
}

/// A wgpu instance for the page: WebGPU where the browser has it (and the link did not
/// say `gpu=webgl2`), WebGL2 otherwise.
pub async fn instance() -> wgpu::Instance {
    let mut descriptor = crate::render::gpu::instance_descriptor(None);
    if WEBGL2_ONLY.with(Cell::get) {
        descriptor.backends.remove(wgpu::Backends::BROWSER_WEBGPU);
    }
    wgpu::util::new_instance_with_webgpu_detection(descriptor).await
}

/// Shows `message` in the page in place of the lab (`<div id="failure">`), and takes
/// the loading message away.
pub fn show_failure(message: &str) {
    if let Some(loading) = element("loading") {
        loading.set_class_name("hidden");
    }
    if let Some(failure) = element("failure") {
        failure.set_text_content(Some(message));
        failure.set_class_name("shown");
    }
}

/// `webgpu` or `webgl2`: which of the browser's GPUs the lab draws with.
#[must_use]
pub fn gpu_name(gpu: &crate::render::Gpu) -> &'static str {
    match gpu.adapter.get_info().backend {
        wgpu::Backend::BrowserWebGpu => "webgpu",
        wgpu::Backend::Gl => "webgl2",
        _ => "other",
    }
}

/// What the page shows besides the canvas, kept by the application.
#[derive(Debug, Default)]
pub struct Page {
    /// The step last written to the state element (none before the first frame).
    shown_step: Option<u64>,
}

impl Page {
    /// After each frame drawn: the state element gets the world's step and hash when
    /// they changed, and the first frame takes the loading message away.
    pub fn frame_drawn(&mut self, lab: &mut Lab, gpu: &str) {
        let step = lab.scene.world().steps();
        if self.shown_step == Some(step) {
            return;
        }
        if self.shown_step.is_none()
            && let Some(loading) = element("loading")
        {
            loading.set_class_name("hidden");
        }
        self.shown_step = Some(step);
        if let Some(state) = element("state") {
            let _ = state.set_attribute("data-hash", &lab.state_hash());
            let _ = state.set_attribute("data-gpu", gpu);
            // Last: a test waits for the step, then reads the rest.
            let _ = state.set_attribute("data-step", &step.to_string());
            state.set_text_content(Some(&format!("step {step}")));
        }
    }
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
