//! What an 8192² texture costs the whole process, GPU driver included (a software adapter keeps its
//! textures in the process's memory): a model with one, placed in the sample scene and drawn, as
//! `umbra render --model` does, stays under 1 GB of resident memory (1.53 GB when umbra kept every
//! image whole: it now keeps an image's first mipmap within 4096²). Alone in its binary, so that no
//! other test's memory lands in the count.

mod common;

use common::gltf::TestModel;
use umbra::assets::TextureLibrary;

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
    let (app, _) = common::draw_model(path);
    let kept: Vec<_> =
        app.world.resource::<TextureLibrary>().all().iter().map(|t| (t.image.width, t.image.height)).collect();
    let most = umbra::assets::MAX_KEPT_SIZE;
    // The model's texture beside the sample scene's own, from its first mipmap within 4096².
    assert!(kept.contains(&(most, most)) && kept.iter().all(|&(w, h)| w.max(h) <= most), "{kept:?}");
    let Some(peak) = common::peak_resident() else { return };
    eprintln!(
        "an 8192² texture drawn at 1280x720 on {}: peak resident {:.0} MB",
        common::gpu().describe(),
        peak as f64 / 1e6
    );
    assert!(peak < 1_000_000_000, "peak resident {peak} bytes: over 1 GB");
}
