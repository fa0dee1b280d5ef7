//! The in-window lab: a panel (egui) that reads and writes the settings and the lights' own
//! settings, the live numbers it shows, and the error overlay laid over the picture. It never
//! decides game state: it edits what a command-line option could have set.
//!
//! [`Gui`] is the glue: window events into egui (egui-winit), egui's shapes onto the frame
//! (egui-wgpu). [`panel()`] is the panel itself; [`history`] keeps the numbers it graphs.

pub mod history;
pub mod panel;
pub mod viewer;

pub use history::History;
pub use panel::{Lab, Live, panel};

use crate::render::Gpu;
use winit::window::Window;

/// egui in one window: its input state, and the painter.
pub struct Gui {
    state: egui_winit::State,
    painter: Painter,
}

/// egui without a window: a context and its renderer, painting over frames of one format (the
/// window's, or a headless target's for the bench).
pub struct Painter {
    ctx: egui::Context,
    renderer: egui_wgpu::Renderer,
}

/// One frame of egui, laid out and ready to paint.
pub struct Painted {
    primitives: Vec<egui::ClippedPrimitive>,
    textures: egui::TexturesDelta,
    pixels_per_point: f32,
}

impl Gui {
    /// egui for `window`, painting into frames of `format`.
    pub fn new(window: &Window, gpu: &Gpu, format: wgpu::TextureFormat) -> Gui {
        let painter = Painter::new(gpu, format);
        let max_texture = gpu.device.limits().max_texture_dimension_2d as usize;
        let viewport = egui::ViewportId::ROOT;
        let scale = Some(window.scale_factor() as f32);
        let state = egui_winit::State::new(painter.ctx.clone(), viewport, window, scale, None, Some(max_texture));
        Gui { state, painter }
    }

    /// The egui context (for textures the panel shows).
    pub fn ctx(&self) -> &egui::Context {
        &self.painter.ctx
    }

    /// Hands a window event to egui; true when egui took it (a click on the panel, typing in a
    /// field), so the scene should not react to it too.
    pub fn on_event(&mut self, window: &Window, event: &winit::event::WindowEvent) -> bool {
        self.state.on_window_event(window, event).consumed
    }

    /// True while the pointer is over something of egui's (the panel, a window).
    pub fn wants_pointer(&self) -> bool {
        self.ctx().egui_wants_pointer_input() || self.ctx().is_pointer_over_egui()
    }

    /// True while egui takes the keyboard (a text field has focus).
    pub fn wants_keyboard(&self) -> bool {
        self.ctx().egui_wants_keyboard_input()
    }

    /// Runs `ui` for this frame with the window's input and lays out what it drew.
    pub fn run(&mut self, window: &Window, ui: impl FnMut(&mut egui::Ui)) -> Painted {
        let input = self.state.take_egui_input(window);
        let (painted, platform) = self.painter.run(input, ui);
        self.state.handle_platform_output(window, platform);
        painted
    }

    /// Paints `painted` over each of `targets` (`size` pixels), keeping what is there.
    pub fn paint(&mut self, gpu: &Gpu, targets: &[&wgpu::TextureView], size: (u32, u32), painted: Painted) {
        self.painter.paint(gpu, targets, size, painted);
    }

    /// Lets egui show `view` (an sRGB RGBA8 texture of the renderer's) as the image `id`, or as
    /// a new image when there is none yet; its id.
    pub fn show_texture(
        &mut self,
        gpu: &Gpu,
        view: &wgpu::TextureView,
        id: Option<egui::TextureId>,
    ) -> egui::TextureId {
        let renderer = &mut self.painter.renderer;
        match id {
            Some(known) => {
                renderer.update_egui_texture_from_wgpu_texture(&gpu.device, view, wgpu::FilterMode::Linear, known);
                known
            }
            None => renderer.register_native_texture(&gpu.device, view, wgpu::FilterMode::Linear),
        }
    }
}

impl Painter {
    /// A painter for frames of `format`.
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> Painter {
        let renderer = egui_wgpu::Renderer::new(&gpu.device, format, egui_wgpu::RendererOptions::default());
        Painter { ctx: egui::Context::default(), renderer }
    }

    /// The egui context.
    pub fn ctx(&self) -> &egui::Context {
        &self.ctx
    }

    /// Runs `ui` with `input` and lays out what it drew; what egui asks of the platform (a
    /// cursor, say) is handed back.
    pub fn run(&mut self, input: egui::RawInput, ui: impl FnMut(&mut egui::Ui)) -> (Painted, egui::PlatformOutput) {
        let output = self.ctx.run_ui(input, ui);
        let primitives = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        let painted =
            Painted { primitives, textures: output.textures_delta, pixels_per_point: output.pixels_per_point };
        (painted, output.platform_output)
    }

    /// Paints `painted` over each of `targets` (`size` pixels), keeping what is there.
    pub fn paint(&mut self, gpu: &Gpu, targets: &[&wgpu::TextureView], size: (u32, u32), mut painted: Painted) {
        let (device, queue) = (&gpu.device, &gpu.queue);
        for (id, delta) in &painted.textures.set {
            for delta in delta {
                self.renderer.update_texture(device, queue, *id, delta);
            }
        }
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [size.0, size.1],
            pixels_per_point: painted.pixels_per_point,
        };
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("panel") });
        let mut buffers = self.renderer.update_buffers(device, queue, &mut encoder, &painted.primitives, &screen);
        for target in targets {
            let mut pass = crate::render::colour_pass(&mut encoder, "panel", target, None).forget_lifetime();
            self.renderer.render(&mut pass, &painted.primitives, &screen);
        }
        buffers.push(encoder.finish());
        queue.submit(buffers);
        for id in &painted.textures.free {
            self.renderer.free_texture(id);
        }
        // Every delta is applied above; egui checks that none is dropped unseen.
        painted.textures.clear();
    }
}
