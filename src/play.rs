//! Playing the scene in a window: winit events in, fixed steps of the app, frames presented.

use crate::components::{Input, Key};
use crate::render::{Gpu, RenderError, Renderer, ShadowStats};
use crate::{App, Settings};
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{DeviceEvent, DeviceId, ElementState, MouseButton, WindowEvent};
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
}

struct Player {
    app: App,
    shown: Option<Shown>,
    error: Option<PlayError>,
    looking: bool,
    last: Option<Instant>,
    behind: f64,
    frames: u32,
    since: Instant,
    shown_frames: u32,
    max_frames: Option<u32>,
}

/// Opens a window and plays `app` until the window is closed, Esc is pressed, or `frames` frames
/// (if given) have been shown.
pub fn play(app: App, frames: Option<u32>) -> Result<(), PlayError> {
    let event_loop = EventLoop::new().map_err(|e| PlayError::NoDisplay(e.to_string()))?;
    run(event_loop, app, frames)
}

/// Plays `app` in a window like [`play`]; where no display can be opened, says so in one line
/// and renders the scene headless to `fallback` instead, so the command always does something useful.
pub fn play_or_render(mut app: App, frames: Option<u32>, fallback: &Path) -> Result<(), PlayError> {
    match EventLoop::new() {
        Ok(event_loop) => run(event_loop, app, frames),
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

fn run(event_loop: EventLoop<()>, app: App, frames: Option<u32>) -> Result<(), PlayError> {
    let mut player = Player {
        app,
        shown: None,
        error: None,
        looking: false,
        last: None,
        behind: 0.0,
        frames: 0,
        since: Instant::now(),
        shown_frames: 0,
        max_frames: frames,
    };
    event_loop.run_app(&mut player).map_err(|e| PlayError::Window(e.to_string()))?;
    if frames.is_some() {
        println!("played {} frames", player.shown_frames);
    }
    player.error.map_or(Ok(()), Err)
}

/// Changes the setting a key stands for (F: fit mode, C: cascade tints, 1-4: cascades, P:
/// filter, R: receiver plane, K: caster culling, T: toon shading, G: planar shadows on the
/// ground); false for any other key.
pub fn change_setting(code: KeyCode, settings: &mut Settings) -> bool {
    match code {
        KeyCode::KeyF => settings.fit_mode = settings.fit_mode.next(),
        KeyCode::KeyC => settings.cascade_debug = !settings.cascade_debug,
        KeyCode::KeyP => settings.method = settings.method.next(),
        KeyCode::KeyR => settings.receiver_plane = !settings.receiver_plane,
        KeyCode::KeyK => settings.caster_culling = settings.caster_culling.next(),
        KeyCode::KeyG => settings.planar_ground = !settings.planar_ground,
        KeyCode::KeyT => {
            settings.toon_bands = if settings.toon_bands == 0 { crate::settings::DEFAULT_TOON_BANDS } else { 0 }
        }
        KeyCode::Digit1 => settings.cascades = 1,
        KeyCode::Digit2 => settings.cascades = 2,
        KeyCode::Digit3 => settings.cascades = 3,
        KeyCode::Digit4 => settings.cascades = 4,
        _ => return false,
    }
    true
}

/// The shadow settings the keys change, in a few words.
fn settings_line(settings: &Settings) -> String {
    let tints = if settings.cascade_debug { ", tinted" } else { "" };
    let flat = if settings.receiver_plane { "" } else { " without receiver plane" };
    let culling = match settings.caster_culling {
        crate::settings::CasterCulling::LightVolume => "",
        crate::settings::CasterCulling::CameraView => ", culling to the camera view",
    };
    let toon = if settings.toon_bands > 0 { format!(", toon {}", settings.toon_bands) } else { String::new() };
    let planar = if settings.planar_ground { ", planar ground" } else { "" };
    format!(
        "{} cascades, {} fit, {} filter{flat}{culling}{tints}{toon}{planar}",
        settings.cascades,
        settings.fit_mode.name(),
        settings.method.name()
    )
}

/// The sample's key for a physical key, if it has one.
fn key_for(code: KeyCode) -> Option<Key> {
    Some(match code {
        KeyCode::KeyW | KeyCode::ArrowUp => Key::Forward,
        KeyCode::KeyS | KeyCode::ArrowDown => Key::Back,
        KeyCode::KeyA | KeyCode::ArrowLeft => Key::Left,
        KeyCode::KeyD | KeyCode::ArrowRight => Key::Right,
        KeyCode::KeyE | KeyCode::Space => Key::Up,
        KeyCode::KeyQ | KeyCode::ControlLeft => Key::Down,
        KeyCode::ShiftLeft | KeyCode::ShiftRight => Key::Fast,
        _ => return None,
    })
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
        surface.configure(&gpu.device, &config);
        let renderer = Renderer::new(&gpu, format)?;
        self.app.resize(config.width, config.height);
        Ok(Shown { window, surface, config, gpu, renderer })
    }

    /// Catches the simulation up with the wall clock in fixed steps.
    fn advance(&mut self) {
        let now = Instant::now();
        let dt = self.app.settings().dt as f64;
        self.behind += self.last.map_or(dt, |last| (now - last).as_secs_f64());
        self.last = Some(now);
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

    fn redraw(&mut self) -> Result<(), PlayError> {
        self.advance();
        let Some(shown) = self.shown.as_mut() else { return Ok(()) };
        let frame = match shown.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => return Ok(()),
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                shown.surface.configure(&shown.gpu.device, &shown.config);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                shown.gpu.check_errors()?;
                return Err(RenderError::Surface("validation error acquiring a frame".into()).into());
            }
        };
        let view = frame.texture.create_view(&Default::default());
        let (w, h) = (shown.config.width, shown.config.height);
        shown.renderer.render(&shown.gpu, &mut self.app.world, &view, w, h)?;
        shown.window.pre_present_notify();
        shown.gpu.queue.present(frame);
        self.frames += 1;
        self.shown_frames += 1;
        let elapsed = self.since.elapsed();
        if elapsed >= Duration::from_secs(1) {
            let fps = self.frames as f64 / elapsed.as_secs_f64();
            let passes = self.app.world.get_resource::<ShadowStats>().cloned().unwrap_or_default();
            let title = format!(
                "umbra - {fps:.0} fps - shadow layers drawn/kept: {passes} - {} - {}",
                settings_line(self.app.settings()),
                shown.gpu.describe()
            );
            shown.window.set_title(&title);
            (self.frames, self.since) = (0, Instant::now());
        }
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
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => self.resize(size.width, size.height),
            WindowEvent::KeyboardInput { event, .. } => {
                let down = event.state == ElementState::Pressed;
                if let PhysicalKey::Code(code) = event.physical_key {
                    if code == KeyCode::Escape && down {
                        event_loop.exit();
                    } else if down
                        && !event.repeat
                        && change_setting(code, &mut self.app.world.resource_mut::<Settings>())
                    {
                        let settings = self.app.settings();
                        println!("{}", settings_line(settings));
                    } else if let Some(key) = key_for(code) {
                        self.app.world.resource_mut::<Input>().set(key, down);
                    }
                }
            }
            WindowEvent::MouseInput { state, button: MouseButton::Right, .. } => {
                self.looking = state == ElementState::Pressed;
                if let Some(shown) = &self.shown {
                    shown.window.set_cursor_visible(!self.looking);
                }
            }
            WindowEvent::Focused(false) => {
                self.looking = false;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::ShadowMethod;
    use crate::settings::CasterCulling;
    use crate::shadow::FitMode;

    #[test]
    fn setting_keys_toggle_and_choose_and_others_do_nothing() {
        let mut s = Settings::default();
        assert!(change_setting(KeyCode::KeyF, &mut s));
        assert_eq!(s.fit_mode, FitMode::Unsnapped);
        assert!(change_setting(KeyCode::KeyC, &mut s) && s.cascade_debug);
        assert!(change_setting(KeyCode::Digit2, &mut s));
        assert_eq!(s.cascades, 2);
        assert!(change_setting(KeyCode::KeyP, &mut s));
        assert_eq!(s.method, ShadowMethod::Pcf3);
        assert!(change_setting(KeyCode::KeyK, &mut s));
        assert_eq!(s.caster_culling, CasterCulling::CameraView);
        assert_eq!(settings_line(&s), "2 cascades, unsnapped fit, pcf3 filter, culling to the camera view, tinted");
        assert!(change_setting(KeyCode::KeyR, &mut s) && !s.receiver_plane);
        assert!(change_setting(KeyCode::KeyT, &mut s) && s.toon_bands == crate::settings::DEFAULT_TOON_BANDS);
        assert!(change_setting(KeyCode::KeyT, &mut s) && s.toon_bands == 0);
        assert!(change_setting(KeyCode::KeyG, &mut s) && s.planar_ground);
        assert!(settings_line(&s).contains("pcf3 filter without receiver plane"));
        let before = s.clone();
        assert!(!change_setting(KeyCode::KeyW, &mut s));
        assert_eq!(s, before);
    }
}
