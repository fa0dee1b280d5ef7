//! Playing the scene in a window: winit events in, fixed steps of the app, frames presented,
//! with the lab's panel and error overlay (see [`crate::ui`]) painted over them.

pub mod bench;
mod desk;
mod keys;
mod measuring;
mod screenshot;

pub use keys::{change_lab, change_setting, key_for, settings_line};
pub use measuring::{Measuring, ViewStamp, stamp};

use crate::App;
use crate::components::Input;
use crate::render::{Gpu, RenderError, Renderer, ShadowStats};
use crate::ui::{Gui, Lab};
use desk::Desk;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{DeviceEvent, DeviceId, ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

/// Why playing in a window stopped.
#[derive(Debug, thiserror::Error)]
pub enum PlayError {
    /// No display could be opened (no X server, say); the caller may render headless instead.
    #[error("no display could be opened: {0}")]
    NoDisplay(String),
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The window could not be created or driven.
    #[error("window: {0}")]
    Window(String),
}

/// Most fixed steps taken per presented frame, so a slow frame cannot snowball.
const MAX_STEPS_PER_FRAME: u32 = 8;

struct Shown {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    renderer: Renderer,
    gui: Gui,
}

struct Player {
    app: App,
    shown: Option<Shown>,
    error: Option<PlayError>,
    looking: bool,
    /// Where the pointer was last, while the left button drags.
    dragging: Option<(f64, f64)>,
    last: Option<Instant>,
    behind: f64,
    frames: u32,
    since: Instant,
    shown_frames: u32,
    max_frames: Option<u32>,
    lab: Lab,
    desk: Desk,
    frame_started: Option<Instant>,
}

/// Opens a window and plays `app` until the window is closed, Esc is pressed, or `frames` frames
/// (if given) have been shown; the window starts in the state `lab` describes.
pub fn play(app: App, frames: Option<u32>, lab: Lab) -> Result<(), PlayError> {
    let event_loop = EventLoop::new().map_err(|e| PlayError::NoDisplay(e.to_string()))?;
    run(event_loop, app, frames, lab)
}

/// Plays `app` in a window like [`play`]; where no display can be opened, says so in one line
/// and renders the scene headless to `fallback` instead, so the command always does something useful.
pub fn play_or_render(mut app: App, frames: Option<u32>, lab: Lab, fallback: &Path) -> Result<(), PlayError> {
    match EventLoop::new() {
        Ok(event_loop) => run(event_loop, app, frames, lab),
        Err(e) => {
            println!("no display ({e}); rendering the scene headless to {} instead", fallback.display());
            let (gpu, _, _) = crate::render::render_png(&mut app, 1280, 720, FALLBACK_TIME, fallback)?;
            println!("adapter: {}", gpu.describe());
            println!("wrote {} (1280x720)", fallback.display());
            Ok(())
        }
    }
}

/// Scene time of the picture rendered when there is no display.
pub const FALLBACK_TIME: f64 = 6.0;

fn run(event_loop: EventLoop<()>, app: App, frames: Option<u32>, lab: Lab) -> Result<(), PlayError> {
    let mut player = Player {
        app,
        shown: None,
        error: None,
        looking: false,
        dragging: None,
        last: None,
        behind: 0.0,
        frames: 0,
        since: Instant::now(),
        shown_frames: 0,
        max_frames: frames,
        lab,
        desk: Desk::default(),
        frame_started: None,
    };
    event_loop.run_app(&mut player).map_err(|e| PlayError::Window(e.to_string()))?;
    if frames.is_some() {
        println!("played {} frames", player.shown_frames);
    }
    player.error.map_or(Ok(()), Err)
}

impl Player {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: PlayError) {
        self.error.get_or_insert(error);
        event_loop.exit();
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<Shown, PlayError> {
        let attributes = Window::default_attributes()
            .with_title("umbra")
            .with_inner_size(winit::dpi::LogicalSize::new(1280.0, 720.0));
        let window = Arc::new(event_loop.create_window(attributes).map_err(|e| PlayError::Window(e.to_string()))?);
        let display = Box::new(event_loop.owned_display_handle());
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(display));
        let surface = instance.create_surface(window.clone()).map_err(|e| RenderError::Surface(e.to_string()))?;
        let gpu = Gpu::new(instance, Some(&surface))?;
        println!("adapter: {}", gpu.describe());
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = caps.formats.iter().copied().find(|f| f.is_srgb()).or(caps.formats.first().copied());
        let format = format.ok_or_else(|| RenderError::Surface("the surface offers no formats".into()))?;
        let size = window.inner_size();
        let (width, height) = (size.width.max(1), size.height.max(1));
        let mut config = surface
            .get_default_config(&gpu.adapter, width, height)
            .ok_or_else(|| RenderError::Surface("the adapter cannot present to this window".into()))?;
        config.format = format;
        config.present_mode = wgpu::PresentMode::AutoVsync;
        // Screenshots copy the frame out where the surface allows it.
        if caps.usages.contains(wgpu::TextureUsages::COPY_SRC) {
            config.usage |= wgpu::TextureUsages::COPY_SRC;
        }
        surface.configure(&gpu.device, &config);
        let mut renderer = Renderer::new(&gpu, format)?;
        self.app.hear(renderer.news());
        renderer.enable_timing(&gpu);
        let gui = Gui::new(&window, &gpu, format);
        self.app.resize(config.width, config.height);
        Ok(Shown { window, surface, config, gpu, renderer, gui })
    }

    /// Catches the simulation up with the wall clock in fixed steps (while the clock is held,
    /// one step that moves only the camera).
    fn advance(&mut self) {
        let now = Instant::now();
        let dt = self.app.world.resource::<crate::components::Time>().dt as f64;
        self.behind += self.last.map_or(dt, |last| (now - last).as_secs_f64());
        self.last = Some(now);
        if self.lab.hold {
            self.behind = 0.0;
            self.app.step_held();
        }
        let mut steps = 0;
        while self.behind >= dt && steps < MAX_STEPS_PER_FRAME {
            self.app.step();
            self.behind -= dt;
            steps += 1;
        }
        if steps == MAX_STEPS_PER_FRAME {
            self.behind = 0.0;
        }
        for notice in self.app.take_notices() {
            eprintln!("warning: {notice}");
        }
    }

    /// Whether egui runs this frame: only while it has something to show.
    fn gui_shown(&self) -> bool {
        self.desk.shows_anything(&self.lab)
    }

    /// The next frame to draw into, or `None` when there is none this time (the surface is
    /// being remade, or the window is hidden).
    fn acquire(shown: &mut Shown) -> Result<Option<wgpu::SurfaceTexture>, PlayError> {
        Ok(match shown.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) | wgpu::CurrentSurfaceTexture::Suboptimal(f) => Some(f),
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => None,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                shown.surface.configure(&shown.gpu.device, &shown.config);
                None
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                shown.gpu.check_errors()?;
                return Err(RenderError::Surface("validation error acquiring a frame".into()).into());
            }
        })
    }

    /// Once a second: frames per second, layers drawn and kept, the settings and the adapter.
    fn update_title(&mut self) {
        self.frames += 1;
        self.shown_frames += 1;
        let elapsed = self.since.elapsed();
        let Some(shown) = &self.shown else { return };
        if elapsed >= Duration::from_secs(1) {
            let fps = self.frames as f64 / elapsed.as_secs_f64();
            let passes = self.app.world.get_resource::<ShadowStats>().cloned().unwrap_or_default();
            let pages = crate::ui::panel::page_line(&self.app.world, &passes).map(|p| format!(" - {p}"));
            let title = format!(
                "umbra - {fps:.0} fps - shadow layers drawn/kept: {passes}{} - {} - {}",
                pages.unwrap_or_default(),
                settings_line(&self.app.settings()),
                shown.gpu.describe()
            );
            shown.window.set_title(&title);
            (self.frames, self.since) = (0, Instant::now());
        }
    }

    fn redraw(&mut self) -> Result<(), PlayError> {
        if let Some(started) = self.frame_started.replace(Instant::now()) {
            self.desk.history.frame(started.elapsed().as_secs_f32() * 1e3);
        }
        if std::mem::take(&mut self.lab.asked.camera) {
            self.desk.camera = crate::systems::switch_camera(&mut self.app.world);
            println!("{}", self.desk.camera);
        }
        self.advance();
        let gui_shown = self.gui_shown();
        let Some(shown) = self.shown.as_mut() else { return Ok(()) };
        self.desk.measuring.update(&mut self.app.world, shown.gui.ctx());
        let Some(frame) = Self::acquire(shown)? else { return Ok(()) };
        let view = frame.texture.create_view(&Default::default());
        let (w, h) = (shown.config.width, shown.config.height);
        // A frame that cannot be copied from is drawn twice for a screenshot: once into a copy.
        let shot = std::mem::take(&mut self.lab.asked.screenshot);
        let copy = shot.then(|| screenshot::copy_target(&shown.gpu, &frame.texture)).flatten();
        let copy_view = copy.as_ref().map(|t| t.create_view(&Default::default()));
        let mut targets = vec![&view];
        targets.extend(copy_view.as_ref());
        for target in &targets {
            shown.renderer.render(&shown.gpu, &self.app.world, target, w, h)?;
        }
        self.app.hear(shown.renderer.news());
        if gui_shown {
            self.desk.paint(shown, &mut self.app.world, &mut self.lab, (&targets, (w, h)));
        }
        if shot {
            screenshot::save(&shown.gpu, copy.as_ref().unwrap_or(&frame.texture));
        }
        shown.window.pre_present_notify();
        shown.gpu.queue.present(frame);
        if let Some(times) = shown.renderer.poll_pass_times(&shown.gpu) {
            self.desk.history.passes(times);
        }
        if self.desk.measuring.wanted(&self.lab) {
            self.lab.asked.measure = false;
            // A measurement is of one still moment: the clock waits while it runs and is shown.
            self.lab.hold = true;
            self.desk.measuring.start(&shown.gpu, &mut shown.renderer, &mut self.app, self.lab.measure_scale)?;
        }
        self.update_title();
        Ok(())
    }

    fn resize(&mut self, width: u32, height: u32) {
        // A minimized window has no size: keep the old surface until it comes back.
        let Some(shown) = self.shown.as_mut() else { return };
        if width == 0 || height == 0 {
            return;
        }
        shown.config.width = width;
        shown.config.height = height;
        shown.surface.configure(&shown.gpu.device, &shown.config);
        self.app.resize(width, height);
    }

    /// Changes the setting `code` is the key of, if it is one, and says what the keys' settings
    /// are now.
    fn change_setting(&mut self, code: KeyCode) -> bool {
        let mut settings = self.app.settings();
        if !change_setting(code, &mut settings) {
            return false;
        }
        println!("{}", settings_line(&settings));
        // Each key steps through valid values only.
        let _ = self.app.set_settings(&settings);
        true
    }

    /// A key pressed or let go (not taken by the panel).
    fn key(&mut self, event_loop: &ActiveEventLoop, code: KeyCode, down: bool, repeat: bool) {
        if code == KeyCode::Escape && down {
            event_loop.exit();
        } else if down && !repeat && (self.change_setting(code) || change_lab(code, &mut self.lab)) {
        } else if down && !repeat && code == KeyCode::KeyB {
            let names: Vec<String> =
                crate::light::light_list(&self.app.world).iter().map(|l| l.label.to_string()).collect();
            let mut settings = self.app.world.resource_mut::<crate::settings::ViewSettings>();
            settings.texel_density = keys::next_texel_view(&settings.texel_density, &names);
            println!("texel density: {}", settings.texel_density.as_deref().unwrap_or("off"));
        } else if let Some(key) = key_for(code) {
            self.app.world.resource_mut::<Input>().set(key, down);
        }
    }
}

impl ApplicationHandler for Player {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.shown.is_none() {
            match self.open(event_loop) {
                Ok(shown) => self.shown = Some(shown),
                Err(e) => self.fail(event_loop, e),
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let gui_shown = self.gui_shown();
        let Some(shown) = self.shown.as_mut() else { return };
        // egui hears every event while it is shown; what it takes, the scene does not.
        let taken = gui_shown && shown.gui.on_event(&shown.window, &event);
        let over_panel = gui_shown && shown.gui.wants_pointer();
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => self.resize(size.width, size.height),
            WindowEvent::KeyboardInput { event, .. } if !(taken && shown.gui.wants_keyboard()) => {
                if let PhysicalKey::Code(code) = event.physical_key {
                    self.key(event_loop, code, event.state == ElementState::Pressed, event.repeat);
                }
            }
            WindowEvent::MouseInput { state, button: MouseButton::Right, .. } => {
                self.looking = state == ElementState::Pressed && !over_panel;
                shown.window.set_cursor_visible(!self.looking);
            }
            WindowEvent::MouseInput { state, button: MouseButton::Left, .. } => {
                self.dragging = (state == ElementState::Pressed && !over_panel).then_some((f64::NAN, f64::NAN));
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some((x, y)) = self.dragging.replace((position.x, position.y))
                    && x.is_finite()
                {
                    let delta = glam::Vec2::new((position.x - x) as f32, (position.y - y) as f32);
                    self.app.world.resource_mut::<Input>().drag_delta += delta;
                }
            }
            WindowEvent::MouseWheel { delta, .. } if !over_panel => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.app.world.resource_mut::<Input>().zoom += steps;
            }
            WindowEvent::Focused(false) => {
                (self.looking, self.dragging) = (false, None);
                self.app.world.resource_mut::<Input>().held.clear();
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw() {
                    self.fail(event_loop, e);
                } else if self.max_frames.is_some_and(|n| self.shown_frames >= n) {
                    event_loop.exit();
                }
            }
            _ => {}
        }
    }

    fn device_event(&mut self, _event_loop: &ActiveEventLoop, _id: DeviceId, event: DeviceEvent) {
        if let DeviceEvent::MouseMotion { delta } = event
            && self.looking
        {
            self.app.world.resource_mut::<Input>().look_delta += glam::Vec2::new(delta.0 as f32, delta.1 as f32);
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(shown) = &self.shown {
            shown.window.request_redraw();
        }
    }
}
