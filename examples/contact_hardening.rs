//! The book's contact-hardening picture (docs/book/2-methods.md): the failure case's 2.5 m pole
//! under a 10 cm spot light, seen from the side, with the hardware's bilinear filter (left) and
//! with PCSS (right). PCSS's
//! penumbra is sharp at the pole's foot and widens towards the tip's shadow, as the ray-traced
//! soft truth's does; bilinear draws one narrow edge all along.
//!
//! `cargo run --release --example contact_hardening -- docs/contact-hardening.png`

use glam::Vec3;
use umbra::Settings;
use umbra::components::ShadowMethod;
use umbra::eval::cases::scenes::pole_scene;
use umbra::eval::measure::place_camera;
use umbra::render::{Gpu, HEADLESS_FORMAT, Image, Renderer, render_headless};

const HALF: (u32, u32) = (640, 480);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).unwrap_or_else(|| "contact-hardening.png".into());
    let gpu = Gpu::headless()?;
    let mut halves = Vec::new();
    for method in [ShadowMethod::Bilinear, ShadowMethod::Pcss] {
        let mut app = pole_scene(&Settings::default().with(|s| s.shadow.method = method))?;
        app.resize(HALF.0, HALF.1);
        place_camera(&mut app.world, Vec3::new(0.6, 1.6, 2.4), Vec3::new(1.2, 0.0, 0.0));
        app.set_time(0.0);
        let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT)?;
        halves.push(render_headless(&gpu, &mut renderer, &mut app, HALF.0, HALF.1)?);
    }
    // Side by side, row by row.
    let row = (HALF.0 * 4) as usize;
    let pixels = (0..HALF.1 as usize)
        .flat_map(|y| halves.iter().flat_map(move |h| h.pixels[y * row..(y + 1) * row].iter().copied()))
        .collect();
    Image { width: 2 * HALF.0, height: HALF.1, pixels }.save_png(std::path::Path::new(&out))?;
    println!("wrote {out}: bilinear (left) and PCSS (right)");
    Ok(())
}
