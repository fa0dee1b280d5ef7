//! The renderer: wgpu only. It reads components, draws the shadow pass, then the main pass.
//!
//! Sections follow the data flow: `gpu.rs` opens a device, [`extract`] turns the world into the
//! frame's structs ([`FrameData`]) and culls casters per layer, `shadow_pass.rs` draws the layers
//! of dirty lights (one per spot, one per sun cascade), `main_pass.rs` lights the scene, and
//! `readback.rs` brings a frame back to the CPU for headless use. The renderer only reads the
//! world: what it learns that the game needs comes back as [`RenderNews`], which the app takes in.

mod async_read;
mod bare_depth;
mod camera_depth;
mod depth_compute;
mod depth_reduction;
mod extract;
mod frame;
mod gpu;
pub mod gpu_types;
mod growing;
mod instances;
pub mod lines;
mod main_pass;
pub mod map_view;
mod mesh;
mod moment_blur;
mod moment_compute;
mod moment_samples;
mod moments;
mod news;
mod page_marks;
pub mod page_table;
mod parts;
mod planar;
mod readback;
mod renderer;
mod shaders;
mod shadow_atlas;
mod shadow_pass;
mod shadow_stats;
mod shadow_tiles;
mod static_maps;
mod texture;
mod tile_fill;
mod timing;
mod uniform_array;
mod wait;

pub use extract::{extract, extract_shadow_maps};
pub use frame::{DrawItem, FrameData, FrameLight, LayerDraw, SHADOW_FADE, Shadowless};
pub use gpu::{Gpu, colour_pass, instance};
pub use moment_samples::sample_counts;
pub use news::RenderNews;
pub use parts::PART_DRAWS;
pub use readback::{
    DebugFrame, HEADLESS_FORMAT, Image, PRIME_ROUNDS, probe_visibility, read_map_atlas, read_picture,
    render_debug_frame, render_debug_frame_as_is, render_headless, render_png,
};
pub use renderer::{AtlasTile, MapAtlas, Renderer};
pub use shadow_stats::{LightPasses, PagePasses, ShadowStats};
pub use timing::PassTimes;

/// Everything that can go wrong between the world and a finished frame.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No adapter at all on the enabled backends.
    #[error(
        "no GPU adapter found (backends: {backends}); install a driver, or Mesa for software rendering \
         (`apt-get install mesa-vulkan-drivers libegl1`), or choose a backend with WGPU_BACKEND=vulkan|gl"
    )]
    NoAdapter {
        /// The backends that were searched.
        backends: String,
    },
    /// The adapter refused to open a device.
    #[error("the GPU adapter could not open a device: {0}")]
    Device(String),
    /// wgpu reported a validation or other error.
    #[error("wgpu error: {0}")]
    Wgpu(String),
    /// The scene's lights, or their clustered lists, need more than one storage binding holds.
    #[error(
        "the scene's {lights} lights need a storage buffer of {bytes} bytes; this device binds at most \
         {limit} (max_storage_buffer_binding_size): use fewer lights, or shorter ranges"
    )]
    TooManyLights {
        /// Lights in the scene.
        lights: usize,
        /// The largest buffer they need.
        bytes: u64,
        /// The device's limit.
        limit: u64,
    },
    /// The clustered light lists need more rows than a texture has.
    #[error(
        "the lists of the scene's {lights} lights take {rows} rows of a texture; this device allows {most} \
         (max_texture_dimension_2d): use fewer lights, or shorter ranges"
    )]
    TooManyLists {
        /// Lights in the scene.
        lights: usize,
        /// Rows the lists take.
        rows: u32,
        /// The device's limit.
        most: u32,
    },
    /// The device cannot make a shadow map this large.
    #[error("shadow_map_size {size} is larger than this GPU allows ({max})")]
    ShadowMapTooLarge {
        /// Requested size.
        size: u32,
        /// Device limit.
        max: u32,
    },
    /// The image size is zero or beyond the device limit.
    #[error("image size {width}x{height} is not allowed: each side must be 1..={max}")]
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// Device limit.
        max: u32,
    },
    /// The world was drawn before it heard what this device keeps of shadows, so its tiles are
    /// sized for another device.
    #[error(
        "the world has not heard this renderer's news: call `app.hear(renderer.news())` after making the \
         renderer and before drawing, so that its shadow tiles are sized for this device"
    )]
    NotTold,
    /// The world lacks a group of settings, so it was not made by `App::new` or `App::empty`.
    #[error("the world holds no settings (shadow, maps, cascade and view): make it with `App::new` or `App::empty`")]
    NoSettings,
    /// The adapter lacks something umbra needs.
    #[error("this GPU adapter cannot do {0}; try another backend (WGPU_BACKEND=vulkan|gl) or adapter")]
    Unsupported(&'static str),
    /// The window surface could not be used.
    #[error("window surface: {0}")]
    Surface(String),
    /// Writing the picture failed.
    #[error("could not write {path}: {why}")]
    Write {
        /// Where.
        path: String,
        /// Why.
        why: String,
    },
}
