//! Shared helpers for the render tests: one GPU per test binary, used by one test at a time.

#![allow(dead_code)]

pub mod gltf;
pub mod scene_file;

use glam::{Vec2, Vec3};
use std::sync::{Mutex, MutexGuard, OnceLock};
use umbra::App;
use umbra::components::{Camera, Transform, Viewport};
use umbra::render::{Gpu, HEADLESS_FORMAT, Image, Renderer, render_headless};

/// A fresh folder for this test process's files called `name`.
pub fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("umbra-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The sample scene with the model at `path` placed in it, drawn at 1280x720 as `umbra render
/// --model` draws it (t = 2 s), checked to have made a picture.
pub fn draw_model(path: std::path::PathBuf) -> (App, Image) {
    let mut app = App::new(umbra::Settings::default().with(|s| s.scene.model = Some(path))).unwrap();
    app.resize(1280, 720);
    app.set_time(2.0);
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let image = render_headless(&gpu, &mut renderer, &mut app, 1280, 720).unwrap();
    assert!(image.pixels.chunks(4).any(|p| p[..3] != image.pixels[..3]), "a picture came out");
    (app, image)
}

/// Writes `model` to a file (and lets go of it), draws it as `umbra render --model` does (see
/// [`draw_model`]) and checks its shadows were drawn; returns the process's peak resident bytes,
/// said with `name`, where the system tells (Linux). A test calling it belongs alone in its
/// binary, so that no other test's memory lands in the count.
pub fn peak_drawing(name: &str, model: gltf::TestModel) -> Option<u64> {
    let path = scratch("scene-memory").join("model.gltf");
    std::fs::write(&path, model.gltf_embedded()).unwrap();
    drop(model);
    let (app, _) = draw_model(path);
    let drawn = app.world.resource::<umbra::render::ShadowStats>().drawn();
    assert!(drawn > 0, "the model's shadows were drawn");
    let peak = peak_resident()?;
    eprintln!("{name} drawn at 1280x720 on {}: peak resident {:.0} MB", gpu().describe(), peak as f64 / 1e6);
    Some(peak)
}

/// The most this process was ever resident, in bytes (Linux's VmHWM); `None` elsewhere.
pub fn peak_resident() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.trim_start_matches("VmHWM:").trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kib * 1024)
}

/// An 8-bit RGBA PNG as umbra writes them (`render --out`, screenshots), or `None` while the file
/// is missing or not whole.
pub fn read_png(path: &std::path::Path) -> Option<Image> {
    let file = std::io::BufReader::new(std::fs::File::open(path).ok()?);
    let mut reader = png::Decoder::new(file).read_info().ok()?;
    let mut pixels = vec![0; reader.output_buffer_size()?];
    let info = reader.next_frame(&mut pixels).ok()?;
    let rgba8 = info.color_type == png::ColorType::Rgba && info.bit_depth == png::BitDepth::Eight;
    rgba8.then_some(Image { width: info.width, height: info.height, pixels })
}

/// Side of the square test frames.
pub const SIZE: u32 = 256;

/// The software (or whatever) adapter, opened once; the lock keeps each test's wgpu errors its own.
///
/// A renderer goes before the guard (`drop((renderer, gpu))`): on GL, freeing its GPU objects
/// takes the adapter's context, which another test's frame may hold for longer than wgpu waits for
/// it (6 s) while this one is not holding the GPU.
pub fn gpu() -> MutexGuard<'static, Gpu> {
    static GPU: OnceLock<Mutex<Gpu>> = OnceLock::new();
    let gpu = GPU.get_or_init(|| {
        let gpu = Gpu::headless().expect("the render tests need an adapter (Mesa gives a software one)");
        eprintln!("render tests on: {}", gpu.describe());
        Mutex::new(gpu)
    });
    gpu.lock().unwrap_or_else(|p| p.into_inner())
}

/// Renders `app` at time `t` into a SIZE x SIZE frame; any wgpu error fails the test.
pub fn render(app: &mut App, t: f64) -> Image {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).expect("renderer");
    app.resize(SIZE, SIZE);
    app.set_time(t);
    render_headless(&gpu, &mut renderer, app, SIZE, SIZE).expect("frame renders without wgpu errors")
}

/// Where world point `p` lands in the last frame of `app`.
pub fn pixel_of(app: &mut App, p: Vec3) -> (u32, u32) {
    let viewport = *app.world.resource::<Viewport>();
    let (camera, transform) = app.world.query::<(&Camera, &Transform)>().iter(&app.world).next().unwrap();
    let at: Vec2 = viewport.project(&camera.view_proj(transform, viewport.aspect()), p).expect("in front");
    assert!(at.x >= 0.0 && at.y >= 0.0 && at.x < SIZE as f32 && at.y < SIZE as f32, "{p:?} is off screen");
    (at.x as u32, at.y as u32)
}

/// Brightness (0..255) of the pixel showing world point `p`.
pub fn brightness_at(app: &mut App, image: &Image, p: Vec3) -> f32 {
    let (x, y) = pixel_of(app, p);
    image.brightness(x, y)
}

/// A camera at `eye` looking at `target`.
pub fn camera_at(eye: Vec3, target: Vec3) -> (Camera, Transform) {
    (Camera::default(), Transform { translation: eye, ..Default::default() }.looking_to(target - eye))
}
