//! Virtual shadow maps for spot and point lights (`--light-maps virtual`): each spot's
//! perspective map, and each face of a point light's cube, in pages, marked from the camera's
//! depth where its light reaches and on its map, drawn once and kept. Their shadows land where
//! the ray-traced truth puts them, much sharper than the coarse maps alone (the atlas's numbers
//! are printed beside them); a still view draws no page. Where the device runs no compute
//! shaders, pages cannot be marked: the tests say SKIPPED.

mod common;

use common::gpu;
use glam::Vec3;
use umbra::components::{ShadowMap, VirtualPages};
use umbra::eval::{metrics, truth};
use umbra::render::{DebugFrame, HEADLESS_FORMAT, Renderer, ShadowStats, render_debug_frame, render_debug_frame_as_is};
use umbra::settings::LightMaps;
use umbra::shadow::PageSpace;
use umbra::{App, Settings};

const W: u32 = 640;
const H: u32 = 360;

/// For each spot and the lamp (lights 1, 2 and 3: the sun comes first), a view from a few
/// metres over its pool of light, where its shadows want finer texels than its coarse map holds.
const VIEWS: [(usize, Vec3, Vec3); 3] = [
    (1, Vec3::new(-1.5, 2.5, 3.0), Vec3::new(-3.0, 0.0, 0.5)),
    (2, Vec3::new(5.5, 2.5, 3.5), Vec3::new(4.0, 0.0, 1.0)),
    (3, Vec3::new(4.5, 3.5, 3.0), Vec3::new(1.0, 0.0, -1.5)),
];

/// The sample scene at t = 6 s, `W` x `H`, seen from `eye` towards `target`, with `change` made
/// to the default settings.
fn app((eye, target): (Vec3, Vec3), change: impl FnOnce(&mut Settings)) -> App {
    let mut app = App::new(Settings::default().with(change)).unwrap();
    app.resize(W, H);
    app.set_time(6.0);
    umbra::scene::place_camera(&mut app.world, eye, target);
    app
}

/// [`app`] with virtual light maps.
fn paged(view: (Vec3, Vec3)) -> App {
    app(view, |s| s.maps.light_maps = LightMaps::Virtual)
}

/// Light `light`'s virtual map in `app` (light order: the sun, then the spots).
fn light_pages(app: &App, light: usize) -> VirtualPages {
    let entity = umbra::light::light_list(&app.world)[light].entity;
    app.world.get::<ShadowMap>(entity).and_then(|m| m.pages.clone()).expect("the light is paged")
}

/// Light `light`'s pixels of `frame` against the truth.
fn tally(app: &mut App, frame: &DebugFrame, light: usize) -> metrics::Tally {
    let t = truth::truth_of(&mut app.world, frame, truth::SizeOverride::default(), 1);
    metrics::tally(frame, &t[light], light, |_| true)
}

/// The median texels across a pixel where light `light`'s lookups are made in `frame`.
fn texels_across(app: &mut App, frame: &DebugFrame, light: usize) -> f32 {
    let eye = umbra::eval::texels::Eye::of(&mut app.world, H).expect("a camera");
    let lights = umbra::light::light_list(&app.world);
    umbra::eval::texels::density(frame, light, &lights[light], eye).quantile(0.5).unwrap_or(f32::NAN)
}

/// True (and SKIPPED said) when the device cannot mark pages.
fn cannot_mark(app: &mut App) -> bool {
    let skip = app.take_notices().iter().any(|n| n.contains("compute pass"));
    if skip {
        eprintln!("SKIPPED: this device runs no compute shaders; the spots read their coarse maps alone");
    }
    skip
}

#[test]
fn paged_lights_put_their_shadows_where_the_truth_does_sharper_than_their_coarse_maps() {
    let gpu = gpu();
    for (light, eye, target) in VIEWS {
        let mut atlas = app((eye, target), |_| ());
        let frame = render_debug_frame(&gpu, &mut Renderer::new(&gpu, HEADLESS_FORMAT).unwrap(), &mut atlas, W, H)
            .expect("no wgpu error");
        let by_atlas = tally(&mut atlas, &frame, light);
        // Before any marking, a fresh renderer's spots read their coarse maps alone.
        let mut coarse = paged((eye, target));
        let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
        coarse.hear(renderer.news());
        let frame = render_debug_frame_as_is(&gpu, &mut renderer, &mut coarse, W, H).expect("no wgpu error");
        let by_coarse = tally(&mut coarse, &frame, light);
        let mut virt = paged((eye, target));
        let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
        let frame = render_debug_frame(&gpu, &mut renderer, &mut virt, W, H).expect("no wgpu error");
        if cannot_mark(&mut virt) {
            return;
        }
        let by_pages = tally(&mut virt, &frame, light);
        let pages = &light_pages(&virt, light);
        let percent = |t: &metrics::Tally| 100.0 * t.misclassified();
        let pressures: Vec<f32> = (1..4).map(|l| light_pages(&virt, l).pressure.octaves).collect();
        let texels = texels_across(&mut virt, &frame, light);
        eprintln!(
            "light {light}: {} pixels; misclassified atlas {:.4} %, coarse map {:.4} %, pages {:.4} % ({} resident, \
             {texels:.2} texels across a pixel at the median; the paged lights' pressures {pressures:?})",
            by_pages.pixels,
            percent(&by_atlas),
            percent(&by_coarse),
            percent(&by_pages),
            pages.resident
        );
        assert!(by_pages.pixels > 20_000, "the view shows light {light}'s light");
        assert!(pages.resident > 4 && pages.marked.residency.missing == 0, "{:?}", pages.marked);
        assert!(by_pages.misclassified() * 2.0 < by_coarse.misclassified(), "the pages are read");
        // Only pages on its map, or on its cube's faces, are asked for: the spots' views show
        // ground past their maps' edges.
        let map = virt.world.get::<ShadowMap>(umbra::light::light_list(&virt.world)[light].entity).unwrap();
        for page in map.layers.iter().filter_map(|l| l.page.map(|p| p.id)) {
            let on = match pages.space {
                PageSpace::Frustum(map) => {
                    let side = map.pages_across(page.level) as i32;
                    (0..side).contains(&page.x) && (0..side).contains(&page.y)
                }
                PageSpace::Cube(cube) => cube.face_of(page).is_some(),
                PageSpace::Clipmap(_) => panic!("light {light} is a spot or a point light"),
            };
            assert!(on, "{page:?} is off the map");
        }
        // A still view draws no page.
        virt.step_held();
        render_debug_frame_as_is(&gpu, &mut renderer, &mut virt, W, H).expect("no wgpu error");
        let still = virt.world.resource::<ShadowStats>().pages;
        assert_eq!(still.drawn, 0, "a still view keeps every page: {still:?}");
    }
}
