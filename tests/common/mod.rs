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

/// The frame sizes the memory tests draw a model at: a thumbnail and 1920x1080, where the frame's
/// own targets are larger than at the sample's 1280x720 (each size is a process of its own, and a
/// peak only grows with the frame). At 3840x2160 the 100,000 nodes and the 20,000 primitives
/// peak over 1 GB on Vulkan: not held (chapter 8 of the book gives the numbers).
pub const MEMORY_FRAMES: [(u32, u32); 2] = [(64, 64), (1920, 1080)];

/// Names the one frame size a memory test's child process draws at, `WIDTHxHEIGHT`.
const MEMORY_FRAME: &str = "UMBRA_MEMORY_FRAME";
/// How a child says its peak, on a line of its own.
const PEAK_LINE: &str = "umbra-memory-test-peak-bytes:";

/// The sample scene with the model at `path` placed in it, drawn at `width`x`height` as `umbra
/// render --model` draws it (t = 2 s), checked to have made a picture.
pub fn draw_model(path: std::path::PathBuf, (width, height): (u32, u32)) -> (App, Image) {
    let mut app = App::new(umbra::Settings::default().with(|s| s.scene.model = Some(path))).unwrap();
    app.resize(width, height);
    app.set_time(2.0);
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let image = render_headless(&gpu, &mut renderer, &mut app, width, height).unwrap();
    assert!(image.pixels.chunks(4).any(|p| p[..3] != image.pixels[..3]), "a picture came out");
    (app, image)
}

/// The peak resident bytes of drawing a model at each size of [`MEMORY_FRAMES`], each in a
/// process of its own (a peak only grows, and a renderer let go of does not give all its memory
/// back to the system), said with `name`; `None` where the system does not tell (not Linux).
///
/// The test calling it runs this test binary again once a size (that test alone), and in that
/// child process this draws the model `make` writes to a file (let go of before drawing) at the
/// size asked, `check` looking at the frame's world, and reports its peak to the parent. `file`
/// names the model's file (its extension says how it is read).
pub fn peaks_drawing(name: &str, file: &str, make: impl Fn() -> Vec<u8>, check: impl Fn(&App)) -> Option<Vec<u64>> {
    if let Ok(size) = std::env::var(MEMORY_FRAME) {
        let (w, h) = size.split_once('x').and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?))).unwrap();
        let path = scratch("scene-memory").join(file);
        std::fs::write(&path, make()).unwrap();
        let (app, _) = draw_model(path, (w, h));
        check(&app);
        println!("\n{PEAK_LINE} {} on {}", peak_resident().unwrap_or(0), gpu().describe());
        return None;
    }
    let test = std::thread::current().name().expect("libtest names a test's thread").to_string();
    let mut peaks = Vec::new();
    for (w, h) in MEMORY_FRAMES {
        let out = std::process::Command::new(std::env::current_exe().unwrap())
            .args([test.as_str(), "--exact", "--nocapture"])
            .env(MEMORY_FRAME, format!("{w}x{h}"))
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "drawing at {w}x{h} failed:\n{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
        let said = stdout.lines().find_map(|l| l.strip_prefix(PEAK_LINE)).expect("the child says its peak");
        let (peak, adapter) = said.trim().split_once(" on ").unwrap();
        let peak: u64 = peak.parse().unwrap();
        if peak == 0 {
            return None;
        }
        eprintln!("{name} drawn at {w}x{h} on {adapter}: peak resident {:.0} MB", peak as f64 / 1e6);
        peaks.push(peak);
    }
    Some(peaks)
}

/// [`peaks_drawing`] for `model` (written as an embedded `.gltf`), checking that its shadows
/// were drawn; the most of its peaks.
pub fn peak_drawing(name: &str, model: impl Fn() -> gltf::TestModel) -> Option<u64> {
    let drawn = |app: &App| assert!(app.world.resource::<umbra::render::ShadowStats>().drawn() > 0, "shadows drawn");
    peaks_drawing(name, "model.gltf", || model().gltf_embedded(), drawn)?.into_iter().max()
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
