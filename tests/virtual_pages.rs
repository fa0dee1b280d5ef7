//! Virtual shadow maps for the sun.

mod common;

use common::gpu;
use umbra::components::{DirectionalLight, ShadowMap};
use umbra::render::{HEADLESS_FORMAT, Renderer, render_debug_frame};
use umbra::settings::SunMaps;
use umbra::{App, Settings};

#[test]
fn diagnose() {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let mut app = App::new(Settings::default().with(|s| s.maps.sun_maps = SunMaps::Virtual)).unwrap();
    app.hear(renderer.news());
    app.resize(640, 360);
    app.set_time(6.0);
    let frame = render_debug_frame(&gpu, &mut renderer, &mut app, 640, 360).unwrap();
    let (_, map) = app.world.query::<(&DirectionalLight, &ShadowMap)>().iter(&app.world).next().unwrap();
    let pages = map.pages.as_ref().unwrap();
    let c = pages.clipmap;
    for (x, y) in [(290u32, 285u32), (395, 295), (200, 300), (480, 300), (300, 250)] {
        let i = (y * 640 + x) as usize;
        let p = frame.position[i].truncate();
        let n = frame.normal[i].truncate();
        let depth = frame.normal[i].w;
        let at = c.across(p);
        let res: Vec<(u32, bool)> =
            (0..c.levels).map(|l| (l, pages.pool.slot_of(c.page_at(l, at)).is_some())).collect();
        let px = depth * 2.0 * (30f32.to_radians()).tan() / 360.0;
        eprintln!(
            "pixel ({x},{y}) p {p} n {n} depth {depth:.2} pixel size {px:.4} -> resident {:?}",
            res.iter().filter(|r| r.1).map(|r| r.0).collect::<Vec<_>>()
        );
    }
}
