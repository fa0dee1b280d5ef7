//! Headless rendering: a frame drawn into a texture and copied back to the CPU as RGBA8.

use super::gpu_types::MEASURED_PER_PASS;
use super::main_pass::DEBUG_FORMAT;
use super::page_marks::MARK_BATCH;
use super::{Gpu, RenderError, Renderer};
use crate::App;
use glam::Vec4;
use std::path::Path;

/// Format of headless frames: 8-bit sRGB, as a window would show them.
pub const HEADLESS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// An RGBA8 (sRGB) picture, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Four bytes per pixel.
    pub pixels: Vec<u8>,
}

impl Image {
    /// The pixel at (x, y), or `None` outside the picture.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        self.pixels[i..i + 4].try_into().ok()
    }

    /// Mean of the red, green and blue bytes at (x, y) (0 outside the picture).
    pub fn brightness(&self, x: u32, y: u32) -> f32 {
        self.pixel(x, y).map_or(0.0, |p| (p[0] as f32 + p[1] as f32 + p[2] as f32) / 3.0)
    }

    /// Writes a PNG; the file appears whole or not at all.
    pub fn save_png(&self, path: &Path) -> Result<(), RenderError> {
        let fail = |why: String| RenderError::Write { path: path.display().to_string(), why };
        let tmp = path.with_extension("png.partial");
        let write = || -> Result<(), String> {
            let file = std::fs::File::create(&tmp).map_err(|e| e.to_string())?;
            let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), self.width, self.height);
            encoder.set_color(png::ColorType::Rgba);
            encoder.set_depth(png::BitDepth::Eight);
            encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
            let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
            writer.write_image_data(&self.pixels).map_err(|e| e.to_string())?;
            writer.finish().map_err(|e| e.to_string())?;
            std::fs::rename(&tmp, path).map_err(|e| e.to_string())
        };
        write().map_err(|why| {
            let _ = std::fs::remove_file(&tmp);
            fail(why)
        })
    }
}

/// Opens the headless adapter, renders `app` at time `t` and writes a PNG.
///
/// The GPU and renderer are handed back so more frames can be drawn with them (and the caller
/// can say which adapter drew it).
pub fn render_png(
    app: &mut App,
    width: u32,
    height: u32,
    t: f64,
    path: &Path,
) -> Result<(Gpu, Renderer, Image), RenderError> {
    let gpu = Gpu::headless()?;
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT)?;
    app.hear(renderer.news());
    app.resize(width, height);
    app.set_time(t);
    let image = render_headless(&gpu, &mut renderer, app, width, height)?;
    image.save_png(path)?;
    Ok((gpu, renderer, image))
}

/// Renders one frame of `app` as it is now, `width` x `height`, and reads it back (the app hears
/// the renderer's news before and after).
pub fn render_headless(
    gpu: &Gpu,
    renderer: &mut Renderer,
    app: &mut App,
    width: u32,
    height: u32,
) -> Result<Image, RenderError> {
    app.hear(renderer.news());
    prime_sdsm(gpu, renderer, app, (width, height))?;
    prime_pages(gpu, renderer, app, (width, height))?;
    let texture = gpu.target("headless frame", (width, height), HEADLESS_FORMAT)?;
    renderer.render(gpu, &app.world, &texture.create_view(&Default::default()), width, height)?;
    app.hear(renderer.news());
    let pixels = read_texture(gpu, &texture, width, height, 4)?;
    Ok(Image { width, height, pixels })
}

/// With the SDSM fit the cascades follow what the camera saw a frame before: a headless frame
/// first draws the view once to see it, reads the reduction back and refits the lights (the
/// clock held), so the frame it returns is fitted to itself and the same every time. A reduction
/// of an earlier frame still under way is waited for first and dropped: else this view's would
/// not be made, and the fit would follow whatever the renderer drew before (another view,
/// another configuration's frame).
fn prime_sdsm(gpu: &Gpu, renderer: &mut Renderer, app: &mut App, (w, h): (u32, u32)) -> Result<(), RenderError> {
    if app.settings().cascade.fit_mode != crate::shadow::FitMode::Sdsm {
        return Ok(());
    }
    renderer.wait_for_samples(gpu);
    let texture = gpu.target("sdsm priming", (w, h), HEADLESS_FORMAT)?;
    renderer.render(gpu, &app.world, &texture.create_view(&Default::default()), w, h)?;
    renderer.wait_for_samples(gpu);
    app.hear(renderer.news());
    app.step_held();
    Ok(())
}

/// Most frames a headless frame draws first for each batch of paged lights' virtual pages.
pub const PRIME_ROUNDS: u32 = 6;

/// With virtual shadow maps a frame reads the pages the camera's pixels asked for a frame or two
/// before: a headless frame first draws its view's depth alone (the clock held; see
/// [`Renderer::render_priming`]) until what it asks for has slots and is drawn, at most
/// [`PRIME_ROUNDS`] times for each batch of [`MARK_BATCH`] paged lights (the batches take turns
/// at the marking), so the frame it returns reads the pages its own view needs and is the same
/// every time. A view whose pages do not all fit the pool stops at the limit, its pixels on
/// coarser pages, and says how many lights it left so.
fn prime_pages(gpu: &Gpu, renderer: &mut Renderer, app: &mut App, (w, h): (u32, u32)) -> Result<(), RenderError> {
    // Each paged light's last marking (its number, and what taking it in did) and its
    // pressure since.
    let paged = |app: &mut App| {
        let mut maps = app.world.query::<(bevy_ecs::entity::Entity, &crate::components::ShadowMap)>();
        let marked = maps
            .iter(&app.world)
            .filter_map(|(e, m)| m.pages.as_ref().map(|p| (e, (p.marks_seen, p.marked, p.pressure))));
        marked.collect::<std::collections::HashMap<_, _>>()
    };
    let before = paged(app);
    let mut last = before.clone();
    // The lights whose last marking left their pressure as it was (it would ask for other pages).
    let mut steady = std::collections::HashSet::new();
    if !app.settings().maps.paged() && before.is_empty() {
        return Ok(());
    }
    // A marking of an earlier frame still under way would keep this view's from being made.
    renderer.wait_for_samples(gpu);
    app.hear(renderer.news());
    // The batches of paged lights take turns at the marking: each has its rounds.
    let rounds = PRIME_ROUNDS as usize * paged(app).len().div_ceil(MARK_BATCH).max(1);
    // Lights marked since priming began, and those of them not done: where none is ever
    // marked (no compute pass here), the renderer has said why already.
    let (mut marked_since, mut unsettled) = (0, 0);
    for _ in 0..rounds {
        renderer.render_priming(gpu, &app.world, (w, h))?;
        renderer.wait_for_samples(gpu);
        app.hear(renderer.news());
        app.step_held();
        // Done when every paged light has been marked since priming began, its last marking
        // found every page it asked for resident and left its pressure where it was.
        let marked = paged(app);
        for (e, (seen, _, pressure)) in &marked {
            match last.get(e) {
                Some((then, _, _)) if then == seen => {}
                Some((_, _, was)) if was == pressure => _ = steady.insert(*e),
                _ => _ = steady.remove(e),
            }
        }
        let done = |(e, (seen, update, _)): (&_, &(u64, crate::components::PageUpdate, _))| {
            before.get(e).is_none_or(|(then, _, _)| seen > then) && update.settled() && steady.contains(e)
        };
        marked_since =
            marked.iter().filter(|(e, (seen, ..))| before.get(*e).is_none_or(|(then, ..)| seen > then)).count();
        unsettled = marked.iter().filter(|&m| !done(m)).count();
        if !marked.is_empty() && unsettled == 0 {
            return Ok(());
        }
        last = marked;
    }
    if marked_since > 0 {
        let line = format!(
            "virtual pages: {unsettled} of {} paged lights still wanted pages after {rounds} priming frames \
             (the pool too small for the view, or their pressure still moving): their pixels read coarser pages",
            paged(app).len()
        );
        app.world.get_resource_or_init::<crate::components::Notices>().0.push(line);
    }
    Ok(())
}

/// The picture in `texture` (`width` x `height`, an 8-bit RGBA or BGRA format, a window's frame
/// say), read back as RGBA8; the texture must allow copies out of it.
pub fn read_picture(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Image, RenderError> {
    use wgpu::TextureFormat as F;
    let (width, height) = (texture.width(), texture.height());
    let bgra = match texture.format() {
        F::Rgba8Unorm | F::Rgba8UnormSrgb => false,
        F::Bgra8Unorm | F::Bgra8UnormSrgb => true,
        _ => return Err(RenderError::Unsupported("reading back a picture that is not 8-bit RGBA or BGRA")),
    };
    let mut pixels = read_texture(gpu, texture, width, height, 4)?;
    if bgra {
        pixels.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
    }
    Ok(Image { width, height, pixels })
}

/// One measured frame: for each pixel (rows top to bottom), the visible surface and what each
/// light's shadow test gave there.
#[derive(Clone, Debug, PartialEq)]
pub struct DebugFrame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// xyz: world position of the visible surface; w: 1 where there is one, 0 for the sky.
    pub position: Vec<Vec4>,
    /// xyz: its unit normal; w: its view depth in metres.
    pub normal: Vec<Vec4>,
    /// One column per light ([`crate::light::light_list`] order), one entry per pixel: the
    /// shadow visibility (0 shadowed .. 1 lit), or -1 where the light does not reach the surface
    /// and no test was made.
    pub visibility: Vec<Vec<f32>>,
}

impl DebugFrame {
    /// True when pixel `i` shows a surface (not the sky).
    pub fn covered(&self, i: usize) -> bool {
        self.position[i].w > 0.5
    }
}

/// Visibilities read back as vec4s, one column per light of `first..first + count`.
fn columns(vectors: &[Vec4], count: usize) -> Vec<Vec<f32>> {
    (0..count.min(MEASURED_PER_PASS)).map(|k| vectors.iter().map(|v| v[k]).collect()).collect()
}

fn read_vectors(gpu: &Gpu, texture: &wgpu::Texture, (width, height): (u32, u32)) -> Result<Vec<Vec4>, RenderError> {
    let bytes = read_texture(gpu, texture, width, height, 16)?;
    Ok(bytes.chunks_exact(16).map(|c| Vec4::from_array(bytemuck::pod_read_unaligned(c))).collect())
}

/// Renders the measuring view of `app` as it is now, `width` x `height`, and reads it back: one
/// pass for every [`MEASURED_PER_PASS`] lights (the shadow maps are drawn once). The view is
/// primed first: its SDSM fit and its virtual pages are its own.
pub fn render_debug_frame(
    gpu: &Gpu,
    renderer: &mut Renderer,
    app: &mut App,
    width: u32,
    height: u32,
) -> Result<DebugFrame, RenderError> {
    app.hear(renderer.news());
    prime_sdsm(gpu, renderer, app, (width, height))?;
    prime_pages(gpu, renderer, app, (width, height))?;
    render_debug_frame_as_is(gpu, renderer, app, width, height)
}

/// [`render_debug_frame`] with nothing drawn first: the view reads the SDSM fit and the virtual
/// pages that earlier frames left (what a window shows the frame after a camera cut).
pub fn render_debug_frame_as_is(
    gpu: &Gpu,
    renderer: &mut Renderer,
    app: &mut App,
    width: u32,
    height: u32,
) -> Result<DebugFrame, RenderError> {
    let textures = [
        gpu.target("measured positions", (width, height), DEBUG_FORMAT)?,
        gpu.target("measured normals", (width, height), DEBUG_FORMAT)?,
        gpu.target("measured visibility", (width, height), DEBUG_FORMAT)?,
    ];
    app.hear(renderer.news());
    let views = textures.each_ref().map(|t| t.create_view(&Default::default()));
    let lights = crate::light::light_list(&app.world).len();
    let mut visibility = Vec::with_capacity(lights);
    let mut first = 0;
    loop {
        renderer.render_debug(gpu, &app.world, &views, (width, height), first)?;
        app.hear(renderer.news());
        visibility.extend(columns(&read_vectors(gpu, &textures[2], (width, height))?, lights - first));
        first += MEASURED_PER_PASS;
        if first >= lights {
            break;
        }
    }
    Ok(DebugFrame {
        width,
        height,
        position: read_vectors(gpu, &textures[0], (width, height))?,
        normal: read_vectors(gpu, &textures[1], (width, height))?,
        visibility,
    })
}

/// The main pass's shadow tests at each of `points` (a position and a unit normal each): one
/// column per light, as [`DebugFrame::visibility`] gives them per pixel, for the world as it is.
pub fn probe_visibility(
    gpu: &Gpu,
    renderer: &mut Renderer,
    app: &mut App,
    points: &[crate::assets::Vertex],
) -> Result<Vec<Vec<f32>>, RenderError> {
    let lights = crate::light::light_list(&app.world).len();
    if points.is_empty() {
        return Ok(vec![Vec::new(); lights]);
    }
    // The probes see the maps of the camera's view, so SDSM fits them to that view first.
    let viewport = *app.world.resource::<crate::components::Viewport>();
    app.hear(renderer.news());
    let size = (viewport.width.max(1), viewport.height.max(1));
    prime_sdsm(gpu, renderer, app, size)?;
    prime_pages(gpu, renderer, app, size)?;
    let width = (points.len() as u32).min(256);
    let height = (points.len() as u32).div_ceil(width);
    let texture = gpu.target("probes", (width, height), DEBUG_FORMAT)?;
    use wgpu::util::DeviceExt;
    let buffer = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("probe points"),
        contents: bytemuck::cast_slice(points),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let view = texture.create_view(&Default::default());
    let mut out = Vec::with_capacity(lights);
    for first in (0..lights).step_by(MEASURED_PER_PASS) {
        let target = (&view, (width, height));
        renderer.render_probes(gpu, &app.world, target, (&buffer, points.len() as u32), first)?;
        app.hear(renderer.news());
        let mut vectors = read_vectors(gpu, &texture, (width, height))?;
        vectors.truncate(points.len());
        out.extend(columns(&vectors, lights - first));
    }
    Ok(out)
}

/// The shadow-map viewer's picture of the atlas as the renderer's last frame left it (see
/// [`Renderer::shadow_map_atlas`]), read back, with each layer's tile in it.
pub fn read_map_atlas(gpu: &Gpu, renderer: &mut Renderer) -> Result<(Image, Vec<super::AtlasTile>), RenderError> {
    let atlas = renderer.shadow_map_atlas(gpu);
    let (width, height) = (atlas.texture.width(), atlas.texture.height());
    let pixels = read_texture(gpu, atlas.texture, width, height, 4)?;
    Ok((Image { width, height, pixels }, atlas.tiles))
}

/// The pixels of `texture`, `bytes` per pixel, rows top to bottom without padding.
fn read_texture(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    width: u32,
    height: u32,
    bytes: u32,
) -> Result<Vec<u8>, RenderError> {
    let row = bytes * width;
    let padded = row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: padded as u64 * height as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(padded), rows_per_image: None },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
    gpu.queue.submit([encoder.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    gpu.wait()?;
    rx.recv()
        .map_err(|e| RenderError::Wgpu(format!("readback never completed: {e}")))?
        .map_err(|e| RenderError::Wgpu(format!("readback failed: {e}")))?;
    let mapped = buffer.get_mapped_range(..).map_err(|e| RenderError::Wgpu(e.to_string()))?;
    let mut pixels = Vec::with_capacity((row * height) as usize);
    for r in mapped.chunks(padded as usize) {
        pixels.extend_from_slice(&r[..row as usize]);
    }
    drop(mapped);
    buffer.unmap();
    gpu.check_errors()?;
    Ok(pixels)
}
