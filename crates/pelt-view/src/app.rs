//! The window of `pelt view` (winit 0.30): events to camera moves and actions, a redraw
//! per frame into the surface, reloads when the input or the shaders change on disk, and the
//! scripted mode (`--frames N --screenshot FILE`) that draws N frames and exits.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use pelt_preview::features::overlay::Overlay;
use pelt_preview::knobs::{Knobs, ShellCount, spec};
use pelt_preview::{Gpu, Preview};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use crate::ViewArgs;
use crate::controls::{self, Action, ORBIT_PER_PIXEL, Settings, ZOOM_PER_PIXEL};
use crate::viewer::{Surface, ViewError, Viewer, WindowError, ms_since};
use crate::watch::Watch;

/// How long after the last input the camera counts as moving.
const SETTLE: Duration = Duration::from_millis(150);
/// How often files are polled for changes.
const POLL: Duration = Duration::from_millis(500);

/// A running window.
struct Running {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    preview: Preview,
    viewer: Viewer,
    shaders: Option<(PathBuf, Watch)>,
    last_poll: Instant,
    last_input: Option<Instant>,
    drag: Option<(MouseButton, (f64, f64))>,
    cursor: (f64, f64),
    shift: bool,
    frames: u32,
    frame_ms: f64,
    screenshots: u32,
    message: Option<String>,
    /// The surface allows reading frames back.
    capture: bool,
    /// The last frame read back from the surface.
    captured: Option<pelt_preview::Image>,
    /// The text overlay, and whether it shows.
    overlay: Overlay,
    show_overlay: bool,
    /// When the animation last advanced.
    last_tick: Instant,
}

/// The application.
pub struct App {
    args: ViewArgs,
    running: Option<Running>,
    /// What stopped it, if anything failed.
    pub error: Option<ViewError>,
}

impl App {
    /// An app for `args`.
    pub fn new(args: ViewArgs) -> App {
        App {
            args,
            running: None,
            error: None,
        }
    }

    fn start(&mut self, el: &ActiveEventLoop) -> Result<Running, ViewError> {
        let a = &self.args;
        let (w, h) = crate::window_size(a);
        let attrs = Window::default_attributes()
            .with_title("pelt view")
            .with_inner_size(PhysicalSize::new(w, h));
        let window = Arc::new(el.create_window(attrs).map_err(WindowError::from)?);
        let (gpu, surface) = Gpu::for_window(a.backend, Arc::clone(&window))
            .map_err(|e| ViewError::Render(e.into()))?;
        let size = window.inner_size();
        let size = (size.width.max(1), size.height.max(1));
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(wgpu::TextureFormat::is_srgb)
            .or_else(|| caps.formats.first().copied())
            .ok_or(WindowError::NoFormat)?;
        // Screenshots read the window's own frame back where the surface allows copies.
        let capture = caps.usages.contains(wgpu::TextureUsages::COPY_SRC)
            && matches!(
                format,
                wgpu::TextureFormat::Rgba8UnormSrgb | wgpu::TextureFormat::Bgra8UnormSrgb
            );
        let config = wgpu::SurfaceConfiguration {
            usage: if capture {
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC
            } else {
                wgpu::TextureUsages::RENDER_ATTACHMENT
            },
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width: size.0,
            height: size.1,
            desired_maximum_frame_latency: 2,
            present_mode: wgpu::PresentMode::AutoVsync,
            alpha_mode: wgpu::CompositeAlphaMode::Auto,
            view_formats: vec![],
        };
        surface.configure(&gpu.device, &config);
        let mut preview = Preview::on(gpu);
        if !a.quiet {
            eprintln!("adapter: {}", preview.adapter());
        }
        let settings = Settings {
            mode: a.mode,
            // The size is the window's, not an override of the scene's.
            knobs: Knobs {
                size: None,
                ..a.knobs
            },
        };
        let mut viewer = Viewer::open(
            &mut preview,
            &a.input,
            settings,
            Surface { size, format },
            a.budget_ms,
            (a.animation.as_deref(), a.time, a.frames.is_none() || a.play),
        )?;
        let scripted = a.frames.is_some();
        if !scripted {
            // The pass times for the overlay and the budget's costs, before the first frame.
            viewer.measure(&mut preview)?;
        }
        let overlay = Overlay::new(&preview.renderer, 1.0);
        let shaders = a.shaders.clone().map(|dir| {
            let files = pelt_preview::shaders::FILES
                .iter()
                .map(|(n, _)| dir.join(n));
            let watch = Watch::new(files);
            (dir, watch)
        });
        Ok(Running {
            window,
            surface,
            config,
            preview,
            viewer,
            shaders,
            last_poll: Instant::now(),
            last_input: None,
            drag: None,
            cursor: (0.0, 0.0),
            shift: false,
            frames: 0,
            frame_ms: 0.0,
            screenshots: 0,
            message: None,
            capture,
            captured: None,
            overlay,
            show_overlay: !scripted || a.overlay,
            last_tick: Instant::now(),
        })
    }
}

impl Running {
    fn moving(&self) -> bool {
        self.last_input.is_some_and(|t| t.elapsed() < SETTLE)
    }

    fn report(&mut self, e: impl std::fmt::Display) {
        eprintln!("pelt view: error: {e}");
        self.message = Some(format!("error: {e}"));
    }

    /// Polls the input and the shaders for changes.
    fn poll(&mut self) {
        if self.last_poll.elapsed() < POLL {
            return;
        }
        self.last_poll = Instant::now();
        if self.viewer.input_changed() {
            let path = self.viewer.path.clone();
            match self.viewer.reload(&mut self.preview, &path) {
                Ok(()) => {
                    eprintln!("pelt view: reloaded {}", path.display());
                    self.message = None;
                }
                Err(e) => self.report(e),
            }
            self.window.request_redraw();
        }
        let changed = self.shaders.as_mut().is_some_and(|(_, w)| w.changed());
        if changed {
            self.reload_shaders();
        }
    }

    fn reload_shaders(&mut self) {
        let Some((dir, _)) = &self.shaders else {
            return;
        };
        match self.preview.renderer.load_shaders(dir) {
            Ok(()) => {
                eprintln!("pelt view: shaders reloaded from {}", dir.display());
                self.message = None;
            }
            // The last good pipelines stay.
            Err(e) => self.report(e),
        }
        self.window.request_redraw();
    }

    fn act(&mut self, a: Action, el: &ActiveEventLoop, screenshot: Option<&PathBuf>) {
        let base = scene_knobs(&self.viewer);
        if self.viewer.settings.apply(a, &base) {
            if let Err(e) = self.viewer.refresh(&mut self.preview) {
                self.report(e);
            }
        } else {
            match a {
                Action::Frame => self.viewer.frame(),
                Action::Screenshot => self.screenshot(screenshot),
                Action::Reload => {
                    let path = self.viewer.path.clone();
                    if let Err(e) = self.viewer.reload(&mut self.preview, &path) {
                        self.report(e);
                    }
                    self.reload_shaders();
                }
                Action::Measure => {
                    if let Err(e) = self.viewer.measure(&mut self.preview) {
                        self.report(e);
                    }
                }
                Action::Help => println!("{}", controls::HELP),
                Action::ToggleOverlay => self.show_overlay = !self.show_overlay,
                Action::Quit => el.exit(),
                Action::PlayPause | Action::Step(_) | Action::NextClip => self.timeline(a),
                _ => {}
            }
        }
        self.window.request_redraw();
    }

    /// A timeline key: play/pause, step, next clip; the asset is posed at the new time.
    fn timeline(&mut self, a: Action) {
        if self.viewer.timeline.is_none() {
            return self.clock(a);
        }
        let Some(t) = &mut self.viewer.timeline else {
            return;
        };
        match a {
            Action::PlayPause => t.toggle(),
            Action::Step(d) => t.step(i32::from(d)),
            Action::NextClip => t.next_clip(),
            _ => return,
        }
        self.last_tick = Instant::now();
        if let Err(e) = self.viewer.follow_timeline(&mut self.preview) {
            self.report(e);
        }
    }

    /// The timeline keys for a scene with wind and no animation: play/pause and step its
    /// clock.
    fn clock(&mut self, a: Action) {
        let Some(c) = &mut self.viewer.clock else {
            self.message = Some("no animation or wind to play".into());
            return;
        };
        match a {
            Action::PlayPause => c.playing = !c.playing,
            Action::Step(d) => {
                c.time += f32::from(d) * crate::timeline::FRAME_S;
                c.playing = false;
            }
            _ => {
                self.message = Some("no animation clips (the wind has no clips)".into());
                return;
            }
        }
        self.last_tick = Instant::now();
        if let Err(e) = self.viewer.follow_time(&mut self.preview) {
            self.report(e);
        }
    }

    /// Advances a playing animation (and its wind), or a scene's wind clock, by `dt` seconds.
    fn tick(&mut self, dt: f32) -> Result<(), ViewError> {
        if let Some(t) = &mut self.viewer.timeline
            && t.advance(dt)
        {
            self.viewer.follow_timeline(&mut self.preview)?;
        } else if let Some(c) = &mut self.viewer.clock
            && c.playing
        {
            c.time += dt;
            self.viewer.follow_time(&mut self.preview)?;
        }
        Ok(())
    }

    fn screenshot(&mut self, to: Option<&PathBuf>) {
        let path = to.cloned().unwrap_or_else(|| {
            self.screenshots += 1;
            PathBuf::from(format!("pelt-view-{:03}.png", self.screenshots))
        });
        match self
            .viewer
            .screenshot(&mut self.preview)
            .map(|i| i.save(&path))
        {
            Ok(Ok(())) => eprintln!("pelt view: wrote {}", path.display()),
            Ok(Err(e)) => self.report(e),
            Err(e) => self.report(e),
        }
    }

    /// Draws one frame (with `capture`, reading it back from the surface before presenting
    /// it); returns whether it was presented.
    fn redraw(&mut self, moving: bool, capture: bool) -> Result<bool, ViewError> {
        let t = Instant::now();
        let texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface
                    .configure(&self.preview.renderer.gpu.device, &self.config);
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err(WindowError::SurfaceValidation.into());
            }
        };
        let view = texture
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        self.viewer.draw(&mut self.preview, &view, moving)?;
        if self.show_overlay {
            let mut lines = self.viewer.status_lines(self.frame_ms);
            if let Some(m) = &self.message {
                lines.insert(0, m.clone());
            }
            self.overlay.set(&self.preview.renderer, lines);
            let output = pelt_preview::features::Output {
                view: &view,
                format: self.config.format,
            };
            pelt_preview::frame::overlay(&self.preview.renderer, &self.overlay, output)
                .map_err(pelt_preview::RenderError::from)?;
        }
        pelt_preview::frame::wait(&self.preview.renderer)
            .map_err(pelt_preview::RenderError::from)?;
        if capture && self.capture {
            let size = (self.config.width, self.config.height);
            let mut image =
                pelt_preview::frame::read_back(&self.preview.renderer, &texture.texture, size)?;
            if self.config.format == wgpu::TextureFormat::Bgra8UnormSrgb {
                for p in image.rgba.chunks_exact_mut(4) {
                    p.swap(0, 2);
                }
            }
            self.captured = Some(image);
        }
        self.preview.renderer.gpu.queue.present(texture);
        self.frame_ms = ms_since(t);
        self.viewer.observe(self.frame_ms);
        let mut title = self.viewer.status(self.frame_ms);
        if let Some(m) = &self.message {
            title = format!("{m} | {title}");
        }
        self.window.set_title(&title);
        Ok(true)
    }
}

/// The scene's own knob values (what a toggle starts from), from each knob's spec; the
/// shells key halves or doubles the count the view starts from, so where the scene leaves
/// the count to the manifest's rule it starts from the manifest's count (the most the rule
/// draws).
fn scene_knobs(v: &Viewer) -> Knobs {
    let own = spec::Own::of(&v.input.scene, &v.input.meshes);
    let mut k = spec::own_knobs(&own);
    if k.shells == Some(ShellCount::BySize) {
        k.shells = own.fur.map(|f| ShellCount::Fixed(f.look.shells));
    }
    k
}

fn key_name(key: &Key) -> Option<String> {
    match key {
        Key::Character(c) => Some(c.to_lowercase()),
        Key::Named(NamedKey::Escape) => Some("Escape".into()),
        Key::Named(NamedKey::Space) => Some("Space".into()),
        _ => None,
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, el: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match self.start(el) {
            Ok(r) => {
                r.window.request_redraw();
                self.running = Some(r);
            }
            Err(e) => {
                self.error = Some(e);
                el.exit();
            }
        }
    }

    fn window_event(&mut self, el: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(r) = &mut self.running else { return };
        let scripted = self.args.frames.is_some();
        match event {
            WindowEvent::CloseRequested => el.exit(),
            WindowEvent::Resized(size) => {
                r.config.width = size.width.max(1);
                r.config.height = size.height.max(1);
                r.surface
                    .configure(&r.preview.renderer.gpu.device, &r.config);
                if let Err(e) = r
                    .viewer
                    .resize(&mut r.preview, (r.config.width, r.config.height))
                {
                    r.report(e);
                }
                r.window.request_redraw();
            }
            WindowEvent::DroppedFile(path) => {
                match r.viewer.reload(&mut r.preview, &path) {
                    Ok(()) => r.message = None,
                    Err(e) => r.report(e),
                }
                r.window.request_redraw();
            }
            WindowEvent::ModifiersChanged(m) => r.shift = m.state().shift_key(),
            WindowEvent::KeyboardInput { event, .. } if !scripted => {
                if event.state == ElementState::Pressed
                    && let Some(a) = key_name(&event.logical_key)
                        .as_deref()
                        .and_then(controls::action)
                {
                    r.act(a, el, None);
                }
            }
            WindowEvent::MouseInput { state, button, .. } if !scripted => {
                r.drag = (state == ElementState::Pressed).then_some((button, r.cursor));
            }
            WindowEvent::CursorMoved { position, .. } => {
                let p = (position.x, position.y);
                if let Some((button, last)) = r.drag {
                    let (dx, dy) = ((p.0 - last.0) as f32, (p.1 - last.1) as f32);
                    let h = r.config.height as f32;
                    if button == MouseButton::Right || (button == MouseButton::Left && r.shift) {
                        r.viewer.orbit.pan(-dx / h, dy / h);
                    } else if button == MouseButton::Left {
                        r.viewer
                            .orbit
                            .rotate(-dx * ORBIT_PER_PIXEL, dy * ORBIT_PER_PIXEL);
                    }
                    r.viewer.camera_moved();
                    r.last_input = Some(Instant::now());
                    r.drag = Some((button, p));
                    r.window.request_redraw();
                }
                r.cursor = p;
            }
            WindowEvent::MouseWheel { delta, .. } if !scripted => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 * ZOOM_PER_PIXEL,
                };
                r.viewer.orbit.zoom(steps);
                r.viewer.camera_moved();
                r.last_input = Some(Instant::now());
                r.window.request_redraw();
            }
            WindowEvent::RedrawRequested => {
                let result = if let Some(n) = self.args.frames {
                    scripted_frame(r, &self.args, n, el)
                } else {
                    let dt = r.last_tick.elapsed().as_secs_f32();
                    r.last_tick = Instant::now();
                    let moving = r.moving();
                    let first = r.frame_ms == 0.0;
                    let drawn = r.tick(dt).and_then(|()| r.redraw(moving, false));
                    // The overlay shows the previous frame's time: draw the first one twice.
                    if first {
                        r.window.request_redraw();
                    }
                    drawn.map(|_| ())
                };
                if let Err(e) = result {
                    if scripted {
                        self.error = Some(e);
                        el.exit();
                    } else {
                        r.report(e);
                    }
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, el: &ActiveEventLoop) {
        let Some(r) = &mut self.running else { return };
        r.poll();
        if self.args.frames.is_some() {
            r.window.request_redraw();
            el.set_control_flow(ControlFlow::Poll);
            return;
        }
        // While moving, keep drawing; once settled, one full-quality frame.
        let settled_after_motion = !r.moving()
            && r.viewer
                .last_quality
                .zip(r.viewer.budget)
                .is_some_and(|(q, b)| q != b.costs.full);
        let playing = r.viewer.timeline.as_ref().is_some_and(|t| t.playing)
            || r.viewer.clock.is_some_and(|c| c.playing);
        // Strands mode keeps drawing while it refines a still frame.
        if r.moving() || settled_after_motion || playing || r.viewer.refining() {
            r.window.request_redraw();
        }
        el.set_control_flow(ControlFlow::WaitUntil(Instant::now() + POLL));
    }
}

/// One frame of the scripted mode: orbit (after the first), draw, and after the last the
/// still full-quality frame as the screenshot, then exit.
fn scripted_frame(
    r: &mut Running,
    args: &ViewArgs,
    n: u32,
    el: &ActiveEventLoop,
) -> Result<(), ViewError> {
    if r.frames >= n {
        return Ok(());
    }
    let orbiting = args.orbit != 0.0;
    if r.frames > 0 && orbiting {
        r.viewer.orbit.rotate(args.orbit.to_radians(), 0.0);
        r.viewer.camera_moved();
    }
    if r.frames > 0 {
        // Scripted playback: one 1/30 s frame per frame drawn.
        r.tick(crate::timeline::FRAME_S)?;
    }
    let last = r.frames + 1 == n;
    let moving = orbiting && !last;
    if r.redraw(moving, last && args.screenshot.is_some())? {
        if !args.quiet {
            eprintln!(
                "frame {}: {:.1} ms ({})",
                r.frames,
                r.frame_ms,
                r.viewer.status(r.frame_ms)
            );
        }
        r.frames += 1;
    }
    if r.frames >= n {
        if let Some(path) = &args.screenshot {
            // The window's own last frame; where the surface cannot be read, the same frame
            // rendered again into a texture.
            let (image, from) = match r.captured.take() {
                Some(i) => (i, "the window's last frame"),
                None => (
                    r.viewer.screenshot(&mut r.preview)?,
                    "rendered offscreen: this surface cannot be read back",
                ),
            };
            image.save(path)?;
            if !args.quiet {
                eprintln!(
                    "wrote {} ({}×{}, {from})",
                    path.display(),
                    image.width,
                    image.height
                );
            }
        }
        el.exit();
    }
    Ok(())
}
