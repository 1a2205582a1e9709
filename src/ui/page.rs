//! What the web page offers the lab besides its canvas (in a browser only): the canvas
//! and the GPU behind it (WebGPU, else WebGL2), the state element a test reads, files
//! from the visitor's disk through the browser's chooser, downloads, the clipboard and
//! the address bar, and the failure message in place of the lab.
//!
//! The page (`web/index.html`) keeps `<output id="state" data-step="N"
//! data-hash="HEX" data-gpu="webgpu|webgl2" ...>` up to date ([`Page`]): the hash is
//! `simulate`'s, so a test can compare the page with the desktop.

use std::cell::{Cell, RefCell};
use std::sync::Arc;

use wasm_bindgen::JsCast;

use crate::ui::lab::Lab;

thread_local! {
    /// `gpu=webgl2`: the instance is made without WebGPU.
    static WEBGL2_ONLY: Cell<bool> = const { Cell::new(false) };
    /// Files the visitor picked, read and waiting for the next frame.
    static PICKED: RefCell<Vec<Picked>> = const { RefCell::new(Vec::new()) };
    /// The canvas's window, woken when a picked file has been read.
    static WINDOW: RefCell<Option<Arc<winit::window::Window>>> = const { RefCell::new(None) };
}

/// `gpu=webgl2`: the page's GPU is asked for without WebGPU.
pub fn set_webgl2_only(only: bool) {
    WEBGL2_ONLY.with(|w| w.set(only));
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

/// The page's words when the browser gives it no GPU to draw with (`why`: wgpu's).
#[must_use]
pub fn no_gpu(why: &str) -> String {
    format!(
        "This browser gave the page neither WebGPU nor WebGL2 to draw with ({why}). A current Chrome, \
         Edge, Firefox or Safari has both; check that hardware acceleration is on in its settings."
    )
}

/// Shows `message` in the page in place of the lab (`<div id="failure">`), and takes
/// the loading message away.
pub fn show_failure(message: &str) {
    if let Some(loading) = element("loading") {
        loading.set_class_name("hidden");
    }
    let Some(failure) = element("failure") else { return };
    // A heading and the message as text (never as markup: it can quote a link).
    let document = web_sys::window().and_then(|w| w.document());
    let made = document.and_then(|d| Some((d.create_element("div").ok()?, d.create_element("h1").ok()?)));
    match made {
        Some((body, heading)) => {
            heading.set_text_content(Some("particle-lab cannot run here"));
            failure.set_text_content(None);
            let _ = body.append_child(&heading);
            let _ = body.append_with_str_1(message);
            let _ = failure.append_child(&body);
        }
        None => failure.set_text_content(Some(message)),
    }
    failure.set_class_name("shown");
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
    /// What the state element was last given (none before the first frame).
    shown: Option<String>,
}

impl Page {
    /// After each frame drawn: the state element gets what changed of the world's step
    /// and hash, the scene, its parameters and where their sliders are (CSS pixels: a
    /// test drags them there), and the first frame takes the loading message away.
    pub fn frame_drawn(&mut self, lab: &mut Lab, sliders: &[(String, egui::Rect)], gpu: &str) {
        let step = lab.scene.world().steps();
        let params: Vec<String> =
            lab.scene.params().iter().map(|(param, value)| format!("\"{}\":{value}", param.name)).collect();
        let sliders: Vec<String> = sliders
            .iter()
            .map(|(name, r)| format!("\"{name}\":[{},{},{},{}]", r.left(), r.top(), r.right(), r.bottom()))
            .collect();
        let fields = [
            ("data-hash", lab.state_hash()),
            ("data-gpu", gpu.to_string()),
            ("data-scene", lab.entry.info().name.to_string()),
            ("data-paused", lab.paused.to_string()),
            ("data-params", format!("{{{}}}", params.join(","))),
            ("data-sliders", format!("{{{}}}", sliders.join(","))),
            ("data-status", lab.status.clone()),
            // Last: a test waits for the step, then reads the rest.
            ("data-step", step.to_string()),
        ];
        let summary: String = fields.iter().map(|(_, v)| v.as_str()).collect::<Vec<_>>().join("|");
        if self.shown.as_deref() == Some(summary.as_str()) {
            return;
        }
        if self.shown.is_none()
            && let Some(loading) = element("loading")
        {
            loading.set_class_name("hidden");
        }
        self.shown = Some(summary);
        if let Some(state) = element("state") {
            for (name, value) in &fields {
                let _ = state.set_attribute(name, value);
            }
            state.set_text_content(Some(&format!("step {step}")));
        }
    }
}

/// What a picked file is to be opened as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A scene file (TOML).
    Scene,
    /// A snapshot (JSON).
    Snapshot,
}

/// A file the visitor picked, read.
#[derive(Debug)]
pub struct Picked {
    /// What it is to be opened as.
    pub kind: FileKind,
    /// Its name, for messages.
    pub name: String,
    /// Its text, or why it could not be read.
    pub text: Result<String, String>,
}

/// The window to wake when a file has been read (set once the page's window is open).
pub fn set_window(window: Arc<winit::window::Window>) {
    WINDOW.with(|w| *w.borrow_mut() = Some(window));
}

/// Opens the browser's file chooser for a file of `kind`; once one is picked and read
/// it waits in [`take_picked`] and the window is woken.
pub fn pick_file(kind: FileKind) {
    use wasm_bindgen::closure::Closure;
    let Some(document) = web_sys::window().and_then(|w| w.document()) else { return };
    let Ok(input) = document.create_element("input") else { return };
    let Ok(input) = input.dyn_into::<web_sys::HtmlInputElement>() else { return };
    input.set_type("file");
    input.set_accept(match kind {
        FileKind::Scene => ".toml,text/plain",
        FileKind::Snapshot => ".json,application/json",
    });
    let chosen = input.clone();
    let on_change = Closure::once_into_js(move || {
        let Some(file) = chosen.files().and_then(|files| files.get(0)) else { return };
        let name = file.name();
        wasm_bindgen_futures::spawn_local(async move {
            // The same limits as a file on the desktop.
            let limit = match kind {
                FileKind::Scene => crate::scenes::file::MAX_FILE_BYTES,
                FileKind::Snapshot => crate::scenes::snapshot::MAX_FILE_BYTES,
            };
            let text = if file.size() > limit as f64 {
                Err(format!("{name} is larger than the limit of {}", crate::reading::bytes(limit)))
            } else {
                wasm_bindgen_futures::JsFuture::from(file.text())
                    .await
                    .ok()
                    .and_then(|t| t.as_string())
                    .ok_or_else(|| format!("cannot read {name}"))
            };
            PICKED.with(|p| p.borrow_mut().push(Picked { kind, name, text }));
            WINDOW.with(|w| {
                if let Some(window) = w.borrow().as_ref() {
                    window.request_redraw();
                }
            });
        });
    });
    input.set_onchange(Some(on_change.unchecked_ref()));
    input.click();
}

/// The files picked and read since the last call.
#[must_use]
pub fn take_picked() -> Vec<Picked> {
    PICKED.with(|p| std::mem::take(&mut *p.borrow_mut()))
}

/// Opens what was picked in `lab`: a scene file or a snapshot; a bad one changes
/// nothing and the status line says why.
pub fn open_picked(lab: &mut Lab) {
    for picked in take_picked() {
        match (picked.kind, picked.text) {
            (_, Err(why)) => lab.status = why,
            (FileKind::Scene, Ok(text)) => {
                lab.open_scene_text(&picked.name, &text);
                lab.frame_scene();
            }
            (FileKind::Snapshot, Ok(text)) => lab.load_snapshot_text(&picked.name, &text),
        }
    }
}

/// Hands `bytes` to the browser as a download named `name`.
pub fn download(name: &str, mime: &str, bytes: &[u8]) -> Result<(), String> {
    let fail = |_| format!("the browser refused to download {name}");
    let parts = js_sys::Array::of1(&js_sys::Uint8Array::from(bytes));
    let options = web_sys::BlobPropertyBag::new();
    options.set_type(mime);
    let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &options).map_err(fail)?;
    let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(fail)?;
    let saved = save_as(&url, name);
    let _ = web_sys::Url::revoke_object_url(&url);
    saved
}

/// Has the browser save what `href` names (an object or data URL) as `name`, the way
/// a link with a `download` attribute does when clicked.
fn save_as(href: &str, name: &str) -> Result<(), String> {
    let anchor = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.create_element("a").ok())
        .and_then(|a| a.dyn_into::<web_sys::HtmlAnchorElement>().ok())
        .ok_or_else(|| format!("no page to download {name} from"))?;
    anchor.set_href(href);
    anchor.set_download(name);
    anchor.click();
    Ok(())
}

/// The page's own address with `query` for its query string; it becomes the address
/// shown, and goes to the clipboard where the browser allows. Returns the link.
pub fn copy_link(query: &str) -> String {
    let Some(window) = web_sys::window() else { return query.to_string() };
    let location = window.location();
    let base =
        format!("{}{}", location.origin().unwrap_or_default(), location.pathname().unwrap_or_default());
    let link = format!("{base}{query}");
    if let Ok(history) = window.history() {
        let _ = history.replace_state_with_url(&wasm_bindgen::JsValue::NULL, "", Some(&link));
    }
    // A promise; where the page may not write the clipboard the address bar has it.
    let _ = window.navigator().clipboard().write_text(&link);
    link
}

/// Downloads what the canvas shows as a PNG; the status line's words.
#[must_use]
pub fn download_canvas(scene: &str) -> String {
    let seconds = web_time::SystemTime::now()
        .duration_since(web_time::UNIX_EPOCH)
        .map(|d| d.as_millis())
        .unwrap_or_default();
    let name = format!("particle-lab-{scene}-{seconds}.png");
    let url = match canvas().and_then(|c| c.to_data_url_with_type("image/png").map_err(|_| String::new())) {
        Ok(url) => url,
        Err(_) => return "screenshot failed: the browser would not give the canvas's picture".into(),
    };
    match save_as(&url, &name) {
        Ok(()) => format!("screenshot downloaded as {name}"),
        Err(why) => format!("screenshot failed: {why}"),
    }
}
