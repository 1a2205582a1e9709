//! The window: winit events in, egui and the 3D view out. A thin shell around
//! [`Lab`], [`LabUi`] and [`Painter`]. It redraws while something moves, and
//! otherwise only when egui asks (input, an animation): a paused, untouched window
//! burns no CPU, and one at rest ([`Lab::at_rest`]) only steps its physics every
//! [`REST_TICK`](crate::ui::lab::REST_TICK) without drawing, so its clock keeps counting.
//!
//! The window is never larger than the GPU can draw: a saved size beyond the screen
//! opens at the screen's size, the surface stays within the device's largest texture,
//! and a frame the GPU runs out of memory for makes the window smaller; the status line
//! says so once.

#[cfg(not(target_arch = "wasm32"))]
use crate::scenes::snapshot::Snapshot;
#[cfg(not(target_arch = "wasm32"))]
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use web_time::Instant;

use winit::application::ApplicationHandler;
#[cfg(not(target_arch = "wasm32"))]
use winit::dpi::LogicalSize;
use winit::event::WindowEvent;
#[cfg(not(target_arch = "wasm32"))]
use winit::event_loop::EventLoop;
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

use crate::render::gpu::fit_surface;
use crate::render::{Gpu, GpuError, OffscreenTarget};
#[cfg(not(target_arch = "wasm32"))]
use crate::settings::{self, Launch};
use crate::settings::{Settings, Store};
use crate::ui::paint::{Painter, UiFrame};
use crate::ui::{Lab, LabUi};

/// Why the window could not run.
#[derive(Debug)]
pub enum AppError {
    /// Bad command-line input (exit code 2).
    Usage(String),
    /// No display, no GPU, or another failure (exit code 1).
    Fatal(String),
}

/// Opens the window as the command line and the saved settings say (see
/// [`settings`]) and runs until it is closed, keeping the settings as it goes.
#[cfg(not(target_arch = "wasm32"))]
pub fn run(launch: &Launch) -> Result<(), AppError> {
    let opened = settings::open(launch, Store::from_platform()).map_err(AppError::Usage)?;
    if let Some(warning) = &opened.warning {
        eprintln!("{warning}");
    }
    log::info!("{}", opened.summary);
    let settings::Opened { mut lab, layout, window: window_size, store, kept, .. } = opened;
    if let Some(path) = &launch.from {
        // Read before any window opens: a bad file is a usage error, said in one line.
        let snapshot = Snapshot::load(path).map_err(AppError::Usage)?;
        lab.load_snapshot(&snapshot).map_err(|e| AppError::Usage(format!("{}: {e}", path.display())))?;
        lab.frame_scene();
        log::info!("opened snapshot {} at step {}", path.display(), lab.scene.world().steps());
    }
    // A link's view and camera, then its `steps=N`: a launcher's round at step 0 and N
    // steps at once, then paused there, as the page does (and `simulate --steps N`).
    launch.view.apply(&mut lab);
    if let Some(steps) = launch.steps {
        lab.fire_at_start();
        lab.run_steps_recorded(steps);
        lab.paused = true;
        log::info!("paused at step {}, state hash {}", lab.scene.world().steps(), lab.state_hash());
    }
    // A scene from a file reloads when the file changes.
    lab.watch_scene_file();
    let event_loop = EventLoop::<AppEvent>::with_user_event()
        .build()
        .map_err(|e| AppError::Fatal(crate::messages::no_display(&e.to_string())))?;
    let mut app = App::new(lab, layout, store, window_size);
    app.kept = kept;
    app.proxy = Some(event_loop.create_proxy());
    event_loop.run_app(&mut app).map_err(|e| {
        AppError::Fatal(format!("the window's event loop failed: {}", crate::messages::plain(&e.to_string())))
    })?;
    match app.error {
        Some(message) => Err(AppError::Fatal(message)),
        None => Ok(()),
    }
}

/// What the window's event loop is told besides the window's own events: on the
/// desktop, a screen reader's requests through AccessKit (egui-winit's adapter).
#[derive(Debug)]
pub enum AppEvent {
    /// A request from the accessibility adapter: the panel's tree, an action on a
    /// control, or that no screen reader listens any more.
    #[cfg(not(target_arch = "wasm32"))]
    Access(egui_winit::accesskit_winit::Event),
}

#[cfg(not(target_arch = "wasm32"))]
impl From<egui_winit::accesskit_winit::Event> for AppEvent {
    fn from(event: egui_winit::accesskit_winit::Event) -> Self {
        Self::Access(event)
    }
}

/// The window's application: the lab, its interface and, once open, the window.
pub struct App {
    /// The desktop event loop's way back in, for the accessibility adapter.
    #[cfg(not(target_arch = "wasm32"))]
    proxy: Option<winit::event_loop::EventLoopProxy<AppEvent>>,
    lab: Lab,
    /// The interface: its views and the panel's layout.
    ui: LabUi,
    window: Option<WindowState>,
    error: Option<String>,
    /// When the frame timings last went to the debug log.
    timing_logged: Instant,
    /// The settings file, written every few seconds when something changed and on exit.
    store: Store,
    /// The window's inner size as last seen, not minimised (logical pixels).
    window_size: [u32; 2],
    /// The settings as read, while they name a scene file that could not be opened:
    /// saved back as they were until another scene is opened ([`Settings::keeping`]).
    kept: Option<Settings>,
    /// When a still window last looked for a change of its scene file.
    scene_file_polled: Instant,
    /// The lab was at rest when the loop last went to wait (for the log's one line
    /// each time it comes to rest and wakes).
    resting: bool,
    /// In a browser: the window waiting for its GPU, which comes asynchronously.
    #[cfg(target_arch = "wasm32")]
    pending: std::rc::Rc<std::cell::RefCell<Option<Result<WindowState, String>>>>,
    /// In a browser: what the page shows besides the canvas (the state element).
    #[cfg(target_arch = "wasm32")]
    pub page: crate::ui::page::Page,
}

/// How often the frame timings go to the log at debug level (`RUST_LOG=particle_lab=debug`),
/// for measuring the window where its panel cannot be read.
const TIMING_LOG_INTERVAL: Duration = Duration::from_secs(2);

/// How often a still window wakes to look for a change of the watched scene file.
const SCENE_FILE_POLL: Duration = Duration::from_millis(250);

/// The smallest side the window's surface is cut to after the GPU ran out of memory
/// drawing a frame (physical pixels): below this the lab gives up with a message.
#[cfg(not(target_arch = "wasm32"))]
const SMALLEST_SURFACE_SIDE: u32 = 320;

/// Everything that exists once the window does.
struct WindowState {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    painter: Painter,
    egui: egui::Context,
    egui_winit: egui_winit::State,
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    screenshot_target: Option<OffscreenTarget>,
    /// How a frame reaches the surface.
    present: Present,
    /// When egui asked to draw again (none: only on input).
    next_repaint: Option<Instant>,
    /// Frames drawn so far (the log gives it with the timings).
    frames: u64,
    /// False while minimised (size 0) or hidden: no frames are drawn or requested then,
    /// so the loop waits for events instead of spinning.
    visible: bool,
    /// The largest side the surface is configured with (physical pixels): the device's
    /// largest texture, lowered when the GPU ran out of memory drawing a frame.
    max_side: u32,
    /// The surface was last cut to `max_side` and the status line said so (said once).
    said_limit: bool,
    /// What the status line should say at the first frame (a saved size that did not
    /// fit the screen).
    note: Option<String>,
}

impl App {
    /// The application for `lab`, with the panel `layout`, saving to `store`, its
    /// window to open at `window_size` logical pixels.
    #[must_use]
    pub fn new(
        lab: Lab,
        layout: crate::ui::layout::PanelLayout,
        store: Store,
        window_size: [u32; 2],
    ) -> Self {
        Self {
            #[cfg(not(target_arch = "wasm32"))]
            proxy: None,
            lab,
            ui: LabUi::new(layout),
            window: None,
            error: None,
            timing_logged: Instant::now(),
            store,
            window_size,
            scene_file_polled: Instant::now(),
            resting: false,
            kept: None,
            #[cfg(target_arch = "wasm32")]
            pending: Default::default(),
            #[cfg(target_arch = "wasm32")]
            page: crate::ui::page::Page::default(),
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, message: String) {
        // main prints it once, as it does every other error.
        log::debug!("{message}");
        self.error = Some(message);
        event_loop.exit();
    }

    /// Writes the settings now, as the window closes.
    fn save_settings(&mut self) {
        let settings = Settings::keeping(&mut self.kept, &self.lab, &self.ui.layout, self.window_size);
        if self.store.save_reporting(&settings)
            && let Some(path) = self.store.path()
        {
            log::info!("settings saved to {}", path.display());
        }
    }
}

impl ApplicationHandler<AppEvent> for App {
    #[cfg(not(target_arch = "wasm32"))]
    fn user_event(&mut self, _event_loop: &ActiveEventLoop, event: AppEvent) {
        use egui_winit::accesskit_winit::WindowEvent as Access;
        let Some(state) = &mut self.window else { return };
        let AppEvent::Access(event) = event;
        match event.window_event {
            Access::InitialTreeRequested => {
                log::info!("a screen reader asked for the panel: AccessKit on");
                state.egui.enable_accesskit();
                state.window.request_redraw();
            }
            Access::ActionRequested(request) => {
                state.egui_winit.on_accesskit_action_request(request);
                state.window.request_redraw();
            }
            Access::AccessibilityDeactivated => state.egui.disable_accesskit(),
        }
    }

    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        #[cfg(not(target_arch = "wasm32"))]
        match WindowState::open(event_loop, self.window_size, self.proxy.clone()) {
            Ok((state, opened_at)) => {
                log::info!("window open: scene {}", self.lab.entry.info().name);
                // A size cut to fit is what the settings keep from now on.
                self.window_size = opened_at;
                self.window = Some(state);
            }
            Err(message) => self.fail(event_loop, message),
        }
        #[cfg(target_arch = "wasm32")]
        if let Err(message) = WindowState::open_in_page(event_loop, self.pending.clone()) {
            self.fail(event_loop, message);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        #[cfg(target_arch = "wasm32")]
        if self.window.is_none() {
            let pending = self.pending.borrow_mut().take();
            match pending {
                Some(Ok(state)) => {
                    log::info!("page open: scene {}", self.lab.entry.info().name);
                    crate::ui::page::set_window(state.window.clone());
                    state.window.request_redraw();
                    self.window = Some(state);
                }
                Some(Err(message)) => {
                    crate::ui::page::show_failure(&message);
                    self.fail(event_loop, message);
                }
                None => {}
            }
        }
        let Some(state) = &mut self.window else { return };
        // egui sees every event first; the 3D view only gets what reaches its area.
        let response = state.egui_winit.on_window_event(&state.window, &event);
        // egui-winit answers "repaint" to RedrawRequested itself, which would redraw for
        // ever: a redraw asks for the next one only through egui's repaint delay.
        if response.repaint && !matches!(event, WindowEvent::RedrawRequested) {
            state.window.request_redraw();
        }
        match event {
            WindowEvent::CloseRequested => {
                log::info!("window closed");
                self.save_settings();
                event_loop.exit();
            }
            WindowEvent::Resized(size) => {
                state.visible = size.width > 0 && size.height > 0;
                if state.visible {
                    let logical = size.to_logical::<f64>(state.window.scale_factor());
                    self.window_size = [logical.width.round() as u32, logical.height.round() as u32];
                }
                state.resize(size.width, size.height);
                state.window.request_redraw();
            }
            WindowEvent::Occluded(hidden) => {
                log::info!("occluded: {hidden}");
                state.visible = !hidden;
                state.window.request_redraw();
            }
            WindowEvent::RedrawRequested => {
                #[cfg(target_arch = "wasm32")]
                crate::ui::page::open_picked(&mut self.lab);
                if let Err(message) = state.frame(&mut self.lab, &mut self.ui) {
                    self.fail(event_loop, message);
                    return;
                }
                #[cfg(target_arch = "wasm32")]
                self.page.frame_drawn(
                    &mut self.lab,
                    &self.ui.params.sliders,
                    crate::ui::page::gpu_name(&state.gpu),
                );
                if self.timing_logged.elapsed() >= TIMING_LOG_INTERVAL {
                    self.timing_logged = Instant::now();
                    let stats = self.lab.stats;
                    log::debug!(
                        "timing: {:.1} fps, {:.1} ms a frame, {:.2} ms a physics step, {} steps a frame, \
                         sim speed {:.2}x, {} particles, {} frames drawn",
                        stats.fps,
                        stats.frame_ms,
                        stats.step_ms,
                        stats.steps_last_frame,
                        stats.sim_speed,
                        self.lab.scene.world().particles.len(),
                        state.frames
                    );
                }
                // A page is left by closing its tab; its settings are saved already.
                #[cfg(target_arch = "wasm32")]
                if std::mem::take(&mut self.lab.requests.quit) {
                    self.save_settings();
                    self.lab.status = "Settings saved; close the tab to leave the lab".into();
                }
                if self.lab.requests.quit {
                    log::info!("quit");
                    self.save_settings();
                    event_loop.exit();
                    return;
                }
                // A page is never told it closes, and a still one draws no frames: it saves
                // each frame drawn (the store writes only what changed).
                #[cfg(target_arch = "wasm32")]
                self.store.save_reporting(&Settings::of(&self.lab, &self.ui.layout, self.window_size));
                #[cfg(not(target_arch = "wasm32"))]
                self.store.autosave(|| {
                    Settings::keeping(&mut self.kept, &self.lab, &self.ui.layout, self.window_size)
                });
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(state) = &self.window else { return };
        if !state.visible {
            event_loop.set_control_flow(ControlFlow::Wait);
            return;
        }
        let now = Instant::now();
        // At rest the physics steps on without a frame; a world that woke by itself is
        // drawn from the next frame on (needs_animation below).
        if self.lab.next_rest_tick().is_some_and(|at| at <= now) {
            self.lab.advance_at_rest();
        }
        let earliest = |wake: Option<Instant>, at: Instant| Some(wake.map_or(at, |w| w.min(at)));
        let mut wake = state.next_repaint;
        if self.lab.scene_file.is_some() && !self.lab.needs_animation() {
            // A still window looks for a change of its scene file without drawing; a
            // reload, or a bad edit's message, is drawn at once.
            if now >= self.scene_file_polled + SCENE_FILE_POLL {
                self.scene_file_polled = now;
                let (entry, status) = (self.lab.entry.clone(), self.lab.status.clone());
                self.lab.poll_scene_file();
                if !entry.same(&self.lab.entry) || status != self.lab.status {
                    state.window.request_redraw();
                }
            }
            wake = earliest(wake, self.scene_file_polled + SCENE_FILE_POLL);
        }
        if let Some(tick) = self.lab.next_rest_tick() {
            wake = earliest(wake, tick);
        }
        let resting = self.lab.at_rest();
        if resting != self.resting {
            self.resting = resting;
            let world = self.lab.scene.world();
            let (t, steps) = (world.time(), world.steps());
            if resting {
                log::info!("at rest at t = {t:.3} s (step {steps}): drawing on input only");
            } else if !self.lab.paused {
                log::info!("awake at t = {t:.3} s (step {steps}): drawing every frame");
            }
        }
        let repaint_due = state.next_repaint.is_some_and(|at| at <= now);
        if self.lab.needs_animation() || repaint_due {
            event_loop.set_control_flow(ControlFlow::Poll);
            state.window.request_redraw();
        } else {
            match wake {
                Some(at) if at <= now => event_loop.set_control_flow(ControlFlow::Poll),
                Some(at) => event_loop.set_control_flow(ControlFlow::WaitUntil(at)),
                None => event_loop.set_control_flow(ControlFlow::Wait),
            }
        }
    }
}

/// How a frame reaches the window's surface.
#[derive(Debug)]
enum Present {
    /// The 3D pass through an sRGB view of the surface texture, the panel into the
    /// texture itself, in gamma space (the desktop).
    Views,
    /// Both into the surface's own sRGB format: a GPU without view formats (WebGL2).
    Srgb,
    /// Both into an sRGB texture of the window's own, copied to the surface: a
    /// browser's WebGPU canvas has no sRGB format, and resolving multisampled pixels
    /// into an sRGB view of a texture was seen to skip the sRGB encoding (Chromium 156
    /// on SwiftShader: the background came out at 12 of 255 instead of 60).
    Copy(Option<(wgpu::Texture, wgpu::TextureView)>),
}

impl Present {
    fn choose(gpu: &Gpu, offered: &[wgpu::TextureFormat]) -> Self {
        if cfg!(target_arch = "wasm32") && gpu.adapter.get_info().backend == wgpu::Backend::BrowserWebGpu {
            Self::Copy(None)
        } else if gpu.has_view_formats(true) {
            Self::Views
        } else if offered.iter().any(|f| f.is_srgb()) {
            Self::Srgb
        } else {
            Self::Copy(None)
        }
    }
}

impl WindowState {
    /// Opens a window of `size` logical pixels, or the screen's size where that is
    /// smaller, with its GPU; returns it and the size it was opened at.
    #[cfg(not(target_arch = "wasm32"))]
    fn open(
        event_loop: &ActiveEventLoop,
        size: [u32; 2],
        proxy: Option<winit::event_loop::EventLoopProxy<AppEvent>>,
    ) -> Result<(Self, [u32; 2]), String> {
        let (size, note) = fit_screen(event_loop, size);
        let [min_width, min_height] = settings::MIN_WINDOW;
        // Shown once AccessKit's adapter is in place, as the adapter requires.
        let attributes = Window::default_attributes()
            .with_visible(false)
            .with_title("particle-lab")
            .with_inner_size(LogicalSize::new(size[0], size[1]))
            .with_min_inner_size(LogicalSize::new(min_width, min_height));
        let window =
            Arc::new(event_loop.create_window(attributes).map_err(|e| {
                format!("cannot create the window: {}", crate::messages::plain(&e.to_string()))
            })?);
        let instance = wgpu::Instance::new(crate::render::gpu::instance_descriptor(Some(Box::new(
            event_loop.owned_display_handle(),
        ))));
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| crate::render::gpu::surface_error(&instance, &e.to_string()).to_string())?;
        let gpu = Gpu::with_instance(instance, Some(&surface)).map_err(|e| e.to_string())?;
        let mut state = Self::new(window, surface, gpu)?;
        if let Some(proxy) = proxy {
            state.egui_winit.init_accesskit(event_loop, &state.window, proxy);
        }
        state.window.set_visible(true);
        // No window larger than the device's largest texture: the window manager keeps
        // a resize within it, and one already larger is asked to shrink.
        let side = state.max_side;
        state.window.set_max_inner_size(Some(winit::dpi::PhysicalSize::new(side, side)));
        let inner = state.window.inner_size();
        if state.surface_size(inner) != [inner.width, inner.height] {
            state.resize(inner.width, inner.height);
        }
        if note.is_some() {
            state.note = note;
        }
        Ok((state, size))
    }

    /// Opens the page's canvas as the window; its GPU comes asynchronously, and the
    /// window state, or why there is none, lands in `pending` (the next event adopts it).
    #[cfg(target_arch = "wasm32")]
    fn open_in_page(
        event_loop: &ActiveEventLoop,
        pending: std::rc::Rc<std::cell::RefCell<Option<Result<Self, String>>>>,
    ) -> Result<(), String> {
        use winit::platform::web::WindowAttributesExtWebSys;
        let attributes = Window::default_attributes()
            .with_title("particle-lab")
            .with_canvas(Some(crate::ui::page::canvas()?))
            .with_prevent_default(true)
            .with_focusable(true);
        let window =
            Arc::new(event_loop.create_window(attributes).map_err(|e| {
                format!("cannot create the canvas: {}", crate::messages::plain(&e.to_string()))
            })?);
        wasm_bindgen_futures::spawn_local(async move {
            let result = async {
                let instance = crate::ui::page::instance().await;
                let surface = instance
                    .create_surface(window.clone())
                    .map_err(|e| crate::ui::page::no_gpu(&crate::messages::plain(&e.to_string())))?;
                let gpu = Gpu::request(instance, Some(&surface)).await.map_err(|e| {
                    let why = match e {
                        GpuError::NoAdapter(why) | GpuError::NoDevice(why) | GpuError::Surface(why) => why,
                        GpuError::Unsupported(why) => why,
                    };
                    crate::ui::page::no_gpu(&why)
                })?;
                Self::new(window.clone(), surface, gpu)
            }
            .await;
            *pending.borrow_mut() = Some(result);
            // An event, so that the application adopts it.
            window.request_redraw();
        });
        Ok(())
    }

    /// The window's state once it has a surface and a GPU.
    fn new(window: Arc<Window>, surface: wgpu::Surface<'static>, gpu: Gpu) -> Result<Self, String> {
        let capabilities = surface.get_capabilities(&gpu.adapter);
        let present = Present::choose(&gpu, &capabilities.formats);
        let shared = !matches!(present, Present::Views);
        // The first 8-bit RGBA or BGRA format the surface lists (its preferred one: a
        // browser copies every frame of any other).
        let eight_bit = [wgpu::TextureFormat::Bgra8Unorm, wgpu::TextureFormat::Rgba8Unorm];
        let wants_srgb = matches!(present, Present::Srgb);
        let format = capabilities
            .formats
            .iter()
            .find(|c| eight_bit.contains(&c.remove_srgb_suffix()) && (!wants_srgb || c.is_srgb()))
            .map(|c| if wants_srgb { *c } else { c.remove_srgb_suffix() })
            .ok_or_else(|| {
                GpuError::Surface(format!(
                    "the window offers no 8-bit RGBA or BGRA format (only {:?})",
                    capabilities.formats
                ))
                .to_string()
            })?;
        log::info!("surface format {format:?}, {present:?} (offered: {:?})", capabilities.formats);
        let alpha_mode = if capabilities.alpha_modes.contains(&wgpu::CompositeAlphaMode::Opaque) {
            wgpu::CompositeAlphaMode::Opaque
        } else {
            capabilities.alpha_modes.first().copied().unwrap_or(wgpu::CompositeAlphaMode::Auto)
        };
        let size = window.inner_size();
        let max_side = gpu.device.limits().max_texture_dimension_2d;
        let [width, height] = fit_surface([size.width, size.height], max_side);
        let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
        if matches!(present, Present::Copy(_)) {
            usage |= wgpu::TextureUsages::COPY_DST;
        }
        let config = wgpu::SurfaceConfiguration {
            usage,
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width,
            height,
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode,
            view_formats: if shared { Vec::new() } else { vec![format.add_srgb_suffix()] },
        };
        if size.width > 0 && size.height > 0 {
            surface.configure(&gpu.device, &config);
        }
        // The panel draws in gamma space into a gamma-space target, or into the sRGB one
        // both share.
        let painted = if shared { format.add_srgb_suffix() } else { format };
        let painter =
            Painter::new(&gpu.device, painted, crate::render::SpherePath::for_adapter(&gpu.adapter));
        let egui = egui::Context::default();
        let max_texture_side = max_side as usize;
        let egui_winit = egui_winit::State::new(
            egui.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(max_texture_side),
        );
        Ok(Self {
            window,
            surface,
            config,
            gpu,
            painter,
            egui,
            egui_winit,
            screenshot_target: None,
            present,
            next_repaint: Some(Instant::now()),
            frames: 0,
            visible: true,
            max_side,
            said_limit: false,
            note: None,
        })
    }

    /// The surface's size for a window of `size` physical pixels: within `max_side`.
    fn surface_size(&self, size: winit::dpi::PhysicalSize<u32>) -> [u32; 2] {
        fit_surface([size.width, size.height], self.max_side)
    }

    /// Reconfigures the surface for a new size; a minimised window (size 0) waits. A
    /// window larger than [`Self::max_side`] is asked to shrink, and drawn at the
    /// largest size meanwhile; the status line says so once.
    fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            return;
        }
        log::info!("resized to {width}x{height}");
        let [fit_width, fit_height] = self.surface_size(winit::dpi::PhysicalSize::new(width, height));
        if [fit_width, fit_height] != [width, height] {
            #[cfg(not(target_arch = "wasm32"))]
            let _ = self.window.request_inner_size(winit::dpi::PhysicalSize::new(fit_width, fit_height));
            if !self.said_limit {
                self.said_limit = true;
                let side = self.max_side;
                self.note = Some(format!(
                    "The window can be at most {side}x{side} pixels on this GPU: {width}x{height} is drawn \
                     at {fit_width}x{fit_height}"
                ));
            }
        }
        self.config.width = fit_width;
        self.config.height = fit_height;
        self.surface.configure(&self.gpu.device, &self.config);
    }

    /// Draws a frame. On the desktop the GPU's errors are caught here: running out of
    /// memory (a window too large for it) makes the window smaller instead of ending the
    /// lab; any other is said in one line, and the window closes.
    fn frame(&mut self, lab: &mut Lab, shell: &mut LabUi) -> Result<(), String> {
        #[cfg(not(target_arch = "wasm32"))]
        let scopes = (
            self.gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory),
            self.gpu.device.push_error_scope(wgpu::ErrorFilter::Validation),
        );
        let drawn = self.draw(lab, shell);
        #[cfg(not(target_arch = "wasm32"))]
        {
            let (out_of_memory, invalid) = scopes;
            let invalid = pollster::block_on(invalid.pop());
            if pollster::block_on(out_of_memory.pop()).is_some() {
                // What failed after the allocation did only because of it.
                return self.shrink(lab);
            }
            if let Some(error) = invalid {
                // wgpu's report runs over several lines ("Caused by:" ...): one line.
                let text = error.to_string();
                let lines: Vec<&str> = text.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
                return Err(format!(
                    "the GPU refused to draw a frame: {}",
                    crate::messages::plain(&lines.join(" "))
                ));
            }
        }
        if let Some(note) = self.note.take() {
            log::warn!("{note}");
            lab.status = note;
        }
        drawn
    }

    /// After the GPU ran out of memory drawing a frame: the surface (and the window)
    /// three quarters as large, down to [`SMALLEST_SURFACE_SIDE`].
    #[cfg(not(target_arch = "wasm32"))]
    fn shrink(&mut self, lab: &mut Lab) -> Result<(), String> {
        let (width, height) = (self.config.width, self.config.height);
        let largest = width.max(height);
        if largest <= SMALLEST_SURFACE_SIDE {
            return Err(format!("the GPU ran out of memory drawing even a {width}x{height} frame"));
        }
        self.max_side = (largest / 4 * 3).max(SMALLEST_SURFACE_SIDE);
        let side = self.max_side;
        self.window.set_max_inner_size(Some(winit::dpi::PhysicalSize::new(side, side)));
        lab.status = format!(
            "The GPU ran out of memory drawing a {width}x{height} frame: the window is limited to \
             {side}x{side} pixels"
        );
        log::warn!("{}", lab.status);
        // Said already: the resize need not say it again, nor an earlier limit.
        self.said_limit = true;
        self.note = None;
        let size = self.window.inner_size();
        self.resize(size.width, size.height);
        self.window.request_redraw();
        Ok(())
    }

    fn draw(&mut self, lab: &mut Lab, shell: &mut LabUi) -> Result<(), String> {
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(()); // minimised
        }
        if self.surface_size(size) != [self.config.width, self.config.height] {
            self.resize(size.width, size.height);
        }
        // Step first, then lay out the panel and the labels, then draw: the labels
        // (and the follow camera) then show the positions the frame draws, not the
        // ones a step before.
        lab.advance();
        let mut input = self.egui_winit.take_egui_input(&self.window);
        // A window larger than its surface: the panel lays out on what is drawn.
        if let Some(screen) = &mut input.screen_rect
            && [self.config.width, self.config.height] != [size.width, size.height]
        {
            let scale = egui::vec2(
                self.config.width as f32 / size.width as f32,
                self.config.height as f32 / size.height as f32,
            );
            *screen = egui::Rect::from_min_size(screen.min, screen.size() * scale);
        }
        let mut rect = egui::Rect::NOTHING;
        let output = self.egui.run_ui(input, |ui| rect = shell.show(ui, lab));
        // When egui wants the next frame (at once for an animation, later for a
        // tooltip's delay, never for a still picture).
        let delay = output.viewport_output.get(&egui::ViewportId::ROOT).map(|v| v.repaint_delay);
        log::trace!("egui asks for the next frame in {delay:?}");
        self.next_repaint = delay.and_then(|d| Instant::now().checked_add(d));
        self.frames += 1;
        self.egui_winit.handle_platform_output(&self.window, output.platform_output);

        let ppp = output.pixels_per_point;
        let primitives = self.egui.tessellate(output.shapes, ppp);
        let viewport = [rect.left() * ppp, rect.top() * ppp, rect.width() * ppp, rect.height() * ppp];
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        self.painter.update_textures(device, queue, &output.textures_delta);

        let texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) => Some((t, false)),
            wgpu::CurrentSurfaceTexture::Suboptimal(t) => Some((t, true)),
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => None,
            wgpu::CurrentSurfaceTexture::Outdated => {
                self.surface.configure(device, &self.config);
                None
            }
            wgpu::CurrentSurfaceTexture::Lost => {
                log::warn!("surface lost; recreating it");
                let instance = &self.gpu.instance;
                self.surface = instance.create_surface(self.window.clone()).map_err(|e| {
                    format!("cannot recreate the surface: {}", crate::messages::plain(&e.to_string()))
                })?;
                self.surface.configure(device, &self.config);
                None
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                log::warn!("surface texture failed validation; skipping a frame");
                None
            }
        };
        let target_size = [self.config.width, self.config.height];
        if let Some((texture, suboptimal)) = texture {
            let view = texture.texture.create_view(&Default::default());
            let ui = UiFrame { primitives: &primitives, pixels_per_point: ppp };
            match &mut self.present {
                Present::Views => {
                    let srgb_view = texture.texture.create_view(&wgpu::TextureViewDescriptor {
                        format: Some(self.config.format.add_srgb_suffix()),
                        ..Default::default()
                    });
                    self.painter.paint(
                        device,
                        queue,
                        &srgb_view,
                        &view,
                        target_size,
                        viewport,
                        lab,
                        Some(ui),
                    );
                }
                Present::Srgb => {
                    self.painter.paint(device, queue, &view, &view, target_size, viewport, lab, Some(ui))
                }
                Present::Copy(own) => {
                    let stale = own.as_ref().is_none_or(|(t, _)| [t.width(), t.height()] != target_size);
                    if stale {
                        let texture = device.create_texture(&wgpu::TextureDescriptor {
                            label: Some("frame (sRGB, copied to the canvas)"),
                            size: wgpu::Extent3d {
                                width: target_size[0],
                                height: target_size[1],
                                depth_or_array_layers: 1,
                            },
                            mip_level_count: 1,
                            sample_count: 1,
                            dimension: wgpu::TextureDimension::D2,
                            format: self.config.format.add_srgb_suffix(),
                            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                            view_formats: &[],
                        });
                        let view = texture.create_view(&Default::default());
                        *own = Some((texture, view));
                    }
                    let (own, own_view) = own.as_ref().expect("made above");
                    self.painter.paint(
                        device,
                        queue,
                        own_view,
                        own_view,
                        target_size,
                        viewport,
                        lab,
                        Some(ui),
                    );
                    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("to the canvas"),
                    });
                    encoder.copy_texture_to_texture(
                        own.as_image_copy(),
                        texture.texture.as_image_copy(),
                        own.size(),
                    );
                    queue.submit([encoder.finish()]);
                }
            }
            self.window.pre_present_notify();
            queue.present(texture);
            if suboptimal {
                self.surface.configure(device, &self.config);
            }
        }
        // In a browser the canvas still holds this frame until the page's task ends: it
        // is the screenshot, downloaded.
        #[cfg(target_arch = "wasm32")]
        if std::mem::take(&mut lab.requests.screenshot) {
            lab.status = crate::ui::page::download_canvas(&lab.entry.info().name);
            log::info!("{}", lab.status);
        }
        #[cfg(not(target_arch = "wasm32"))]
        if std::mem::take(&mut lab.requests.screenshot) {
            let ui = UiFrame { primitives: &primitives, pixels_per_point: ppp };
            lab.status = match self.screenshot(lab, target_size, viewport, ui) {
                Ok(path) => format!("screenshot saved to {}", path.display()),
                Err(error) => format!("screenshot failed: {error}"),
            };
            log::info!("{}", lab.status);
        }
        self.painter.free_textures(&output.textures_delta);
        Ok(())
    }

    /// Draws the frame again into an off-screen texture and writes it as a PNG in the
    /// current directory.
    #[cfg(not(target_arch = "wasm32"))]
    fn screenshot(
        &mut self,
        lab: &Lab,
        size: [u32; 2],
        viewport: [f32; 4],
        ui: UiFrame<'_>,
    ) -> Result<PathBuf, String> {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        if self.screenshot_target.as_ref().is_none_or(|t| t.size != size) {
            self.screenshot_target = Some(OffscreenTarget::with_format(device, size, self.config.format));
        }
        let target = self.screenshot_target.as_ref().expect("created above");
        self.painter.paint(device, queue, &target.srgb_view, &target.view, size, viewport, lab, Some(ui));
        let pixels = target.read_rgba(device, queue)?;
        let seconds = web_time::SystemTime::now()
            .duration_since(web_time::UNIX_EPOCH)
            .map(|d| d.as_millis())
            .unwrap_or_default();
        let directory = std::env::current_dir().map_err(|e| format!("no current directory: {e}"))?;
        let path = directory.join(format!("particle-lab-{}-{seconds}.png", lab.entry.info().name));
        crate::render::offscreen::write_png(&path, size, &pixels)?;
        Ok(path)
    }
}

/// `size` (logical pixels) cut to the screen the window opens on, if the platform says
/// which (a window larger than its screen is never seen whole, and its frames can be
/// more than a GPU can hold), with the line saying so when it was cut.
#[cfg(not(target_arch = "wasm32"))]
fn fit_screen(event_loop: &ActiveEventLoop, size: [u32; 2]) -> ([u32; 2], Option<String>) {
    let Some(monitor) = event_loop.primary_monitor().or_else(|| event_loop.available_monitors().next())
    else {
        return (size, None);
    };
    let screen = monitor.size().to_logical::<f64>(monitor.scale_factor());
    let screen = [screen.width.floor() as u32, screen.height.floor() as u32];
    if screen.contains(&0) {
        return (size, None);
    }
    let fit = [
        size[0].min(screen[0].max(settings::MIN_WINDOW[0])),
        size[1].min(screen[1].max(settings::MIN_WINDOW[1])),
    ];
    let note = (fit != size).then(|| {
        format!(
            "A window of {}x{} does not fit the screen ({}x{}): opened at {}x{}",
            size[0], size[1], screen[0], screen[1], fit[0], fit[1]
        )
    });
    (fit, note)
}
