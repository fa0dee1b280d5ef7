//! What an 8192² texture costs the whole process, GPU driver included (a software adapter keeps its
//! textures in the process's memory): a model with one, placed in the sample scene and drawn, as
//! `umbra render --model` does, stays under 1 GB of resident memory at each frame size of
//! `common::MEMORY_FRAMES` (1.53 GB at 1280x720 when umbra kept every image whole: it now keeps an
//! image's first mipmap within 4096²). Alone in its binary, so that no other test's memory lands in
//! the count.

mod common;

use common::gltf::TestModel;
use umbra::assets::TextureLibrary;

/// A model with one 8192² PNG texture, as a `.glb`.
fn textured_model() -> Vec<u8> {
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
    TestModel::new().with_texture(&png, None).glb()
}

#[test]
fn a_model_with_an_8192_texture_is_drawn_in_under_a_gigabyte() {
    let most = umbra::assets::MAX_KEPT_SIZE;
    let kept_within = |app: &umbra::App| {
        let library = app.world.resource::<TextureLibrary>();
        let kept: Vec<_> = library.all().iter().map(|t| (t.image.width, t.image.height)).collect();
        // The model's texture beside the sample scene's own, from its first mipmap within 4096².
        assert!(kept.contains(&(most, most)) && kept.iter().all(|&(w, h)| w.max(h) <= most), "{kept:?}");
    };
    let Some(peaks) = common::peaks_drawing("an 8192² texture", "big.glb", textured_model, kept_within) else {
        return;
    };
    let peak = peaks.into_iter().max().unwrap_or_default();
    assert!(peak < 1_000_000_000, "peak resident {peak} bytes: over 1 GB");
}
