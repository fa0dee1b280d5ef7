//! What an 8192² texture costs the whole process, GPU driver included (a software adapter keeps its
//! textures in the process's memory): a model with one, placed in the sample scene and drawn, as
//! `umbra render --model` does, stays under 1 GB of resident memory (1.53 GB when umbra kept every
//! image whole: it now keeps an image's first mipmap within 4096²). Alone in its binary, so that no
//! other test's memory lands in the count.

mod common;

use common::gltf::TestModel;
use umbra::render::{HEADLESS_FORMAT, Renderer, render_headless};
use umbra::{App, Settings};

#[test]
fn a_model_with_an_8192_texture_is_drawn_in_under_a_gigabyte() {
    let side = umbra::assets::MAX_TEXTURE_SIZE;
    let mut png = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut png, side, side);
        encoder.set_color(png::ColorType::Rgba);
        let mut writer = encoder.write_header().unwrap();
        let row: Vec<u8> = (0..side).flat_map(|x| [(x % 256) as u8, 100, 50, 255]).collect();
        let mut stream = writer.stream_writer().unwrap();
        for _ in 0..side {
            std::io::Write::write_all(&mut stream, &row).unwrap();
        }
        stream.finish().unwrap();
    }
    let path = common::scratch("texture-memory").join("big.glb");
    std::fs::write(&path, TestModel::new().with_texture(&png, None).glb()).unwrap();
    drop(png);
    let mut app = App::new(Settings::default().with(|s| s.scene.model = Some(path))).unwrap();
    app.resize(1280, 720);
    app.set_time(2.0);
    let gpu = common::gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let image = render_headless(&gpu, &mut renderer, &mut app, 1280, 720).unwrap();
    assert!(image.pixels.chunks(4).any(|p| p[..3] != image.pixels[..3]), "a picture came out");
    let Some(peak) = common::peak_resident() else { return };
    eprintln!("an 8192² texture drawn at 1280x720 on {}: peak resident {:.0} MB", gpu.describe(), peak as f64 / 1e6);
    assert!(peak < 1_000_000_000, "peak resident {peak} bytes: over 1 GB");
}
