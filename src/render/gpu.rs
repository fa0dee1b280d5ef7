//! Choosing an adapter, opening a device, and catching every wgpu error.

use super::RenderError;
use std::sync::{Arc, Mutex};

/// An open GPU device with its queue and a log of uncaptured errors.
pub struct Gpu {
    /// The wgpu instance the adapter came from.
    pub instance: wgpu::Instance,
    /// The chosen adapter.
    pub adapter: wgpu::Adapter,
    /// The logical device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    errors: Arc<Mutex<Vec<String>>>,
}

/// A wgpu instance for the backends `WGPU_BACKEND` names, or all of them.
pub fn instance() -> wgpu::Instance {
    wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env())
}

/// Preference order: a real GPU first, a software rasterizer last; Vulkan/Metal/DX12 before GL.
fn rank(info: &wgpu::AdapterInfo) -> (u8, u8) {
    let device = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    };
    (device, (info.backend == wgpu::Backend::Gl) as u8)
}

impl Gpu {
    /// Opens the best adapter of a fresh [`instance`] for rendering off screen.
    pub fn headless() -> Result<Gpu, RenderError> {
        Gpu::new(instance(), None)
    }

    /// Opens the best adapter of `instance` that can present to `surface` (if given).
    pub fn new(instance: wgpu::Instance, surface: Option<&wgpu::Surface<'_>>) -> Result<Gpu, RenderError> {
        let backends = wgpu::Backends::all().with_env();
        let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
        adapters.retain(|a| surface.is_none_or(|s| a.is_surface_supported(s)));
        adapters.sort_by_key(|a| rank(&a.get_info()));
        let adapter =
            adapters.into_iter().next().ok_or_else(|| RenderError::NoAdapter { backends: format!("{backends:?}") })?;
        let desc = wgpu::DeviceDescriptor {
            label: Some("umbra"),
            // Timestamps let the benchmark time each pass on the GPU; filtering 32-bit floats
            // allows full-float moment maps; the adapter's own format features may let compute
            // store half-float moment pairs. None is needed.
            required_features: adapter.features()
                & (wgpu::Features::TIMESTAMP_QUERY
                    | super::moments::FULL_FEATURES
                    | super::main_pass::DEPTH_STENCIL_FEATURES
                    | wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES),
            required_limits: adapter.limits(),
            ..Default::default()
        };
        let (device, queue) =
            pollster::block_on(adapter.request_device(&desc)).map_err(|e| RenderError::Device(e.to_string()))?;
        let errors = Arc::new(Mutex::new(Vec::new()));
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            sink.lock().unwrap_or_else(|p| p.into_inner()).push(e.to_string());
        }));
        Ok(Gpu { instance, adapter, device, queue, errors })
    }

    /// True when the device runs compute shaders (the SDSM reduction and the marking of virtual
    /// pages need them).
    pub fn computes(&self) -> bool {
        super::depth_reduction::computes(&self.adapter)
    }

    /// One line naming the adapter, its kind and its backend.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {:?} backend)", info.name, info.device_type, info.backend)
    }

    /// True when the adapter is a software rasterizer (lavapipe, llvmpipe).
    pub fn software(&self) -> bool {
        self.adapter.get_info().device_type == wgpu::DeviceType::Cpu
    }

    /// True when moment maps can be 32-bit floats here (GL cannot render into them).
    pub fn full_float_moments(&self) -> bool {
        super::moments::full_supported(&self.adapter, self.device.features())
    }

    /// Fails with every wgpu error raised since the last check (and forgets them).
    pub fn check_errors(&self) -> Result<(), RenderError> {
        let mut errors = self.errors.lock().unwrap_or_else(|p| p.into_inner());
        if errors.is_empty() { Ok(()) } else { Err(RenderError::Wgpu(std::mem::take(&mut *errors).join("\n"))) }
    }

    /// A 2D texture of `format` to render into and copy out of, once its size is checked against
    /// the device.
    pub fn target(
        &self,
        label: &str,
        (width, height): (u32, u32),
        format: wgpu::TextureFormat,
    ) -> Result<wgpu::Texture, RenderError> {
        let max = self.device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RenderError::BadSize { width, height, max });
        }
        Ok(self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        }))
    }

    /// Blocks until the GPU has finished all submitted work.
    pub fn wait(&self) -> Result<(), RenderError> {
        super::wait::wait_for(&self.device)
    }
}

/// A render pass over the one colour target `view`, cleared to `clear` or, without it, drawing
/// over what is there.
pub fn colour_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    clear: Option<wgpu::Color>,
) -> wgpu::RenderPass<'e> {
    let load = clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear);
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load, store: wgpu::StoreOp::Store },
        })],
        ..Default::default()
    })
}
