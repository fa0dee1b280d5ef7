//! Virtual shadow maps for the sun (`--sun-maps virtual`): the sun's shadow where the ray-traced
//! truth puts it, through pages that are marked from the camera's depth, drawn once and kept;
//! nothing drawn for a still view, only the pages a moving caster crosses drawn again (and its
//! old shadow gone with them), a pool too small made do with coarser levels (counted), and a
//! camera cut shadowed by what is resident until its own pages arrive; and the shadow-map viewer
//! drawing every one of the hundreds of layers the pages make. Where the device runs no
//! compute shaders, pages cannot be marked: the sun reads its coarse map, and the tests say
//! SKIPPED after checking that it does so.

mod common;

use bevy_ecs::prelude::*;
use common::gpu;
use glam::Vec3;
use umbra::components::{DirectionalLight, ShadowMap, SharedPool, Spin, Transform, VirtualPages};
use umbra::eval::{metrics, truth};
use umbra::render::{
    AtlasTile, DebugFrame, Gpu, HEADLESS_FORMAT, PRIME_ROUNDS, Renderer, ShadowStats, read_map_atlas,
    render_debug_frame, render_debug_frame_as_is, render_headless,
};
use umbra::settings::SunMaps;
use umbra::{App, Settings};

const W: u32 = 640;
const H: u32 = 360;

/// The sample scene at t = 6 s, `W` x `H`, with `change` made to the default settings.
fn app(change: impl FnOnce(&mut Settings)) -> App {
    let mut app = App::new(Settings::default().with(change)).unwrap();
    app.resize(W, H);
    app.set_time(6.0);
    app
}

/// [`app`] with virtual sun maps.
fn paged(change: impl FnOnce(&mut Settings)) -> App {
    app(|s| {
        s.maps.sun_maps = SunMaps::Virtual;
        change(s);
    })
}

/// The sun's virtual map in `app`.
fn pages(app: &mut App) -> VirtualPages {
    let mut q = app.world.query::<(&DirectionalLight, &ShadowMap)>();
    q.iter(&app.world).next().unwrap().1.pages.clone().expect("the sun is paged")
}

/// The sun's pixels of `frame` against the truth, and the truth itself.
fn sun_tally(app: &mut App, frame: &DebugFrame) -> (metrics::Tally, Vec<Option<truth::Truth>>) {
    let t = truth::truth_of(&mut app.world, frame, truth::SizeOverride::default(), 1);
    (metrics::tally(frame, &t[0], 0, |_| true), t[0].clone())
}

/// Of the pixels truly in the sun's shadow and more than `margin` pixels from any lit pixel,
/// the share rendered dark: a lookup that found no page and read nothing would be lit.
fn deep_shadow_dark(frame: &DebugFrame, truth: &[Option<truth::Truth>], margin: i32) -> f64 {
    let (w, h) = (frame.width as i32, frame.height as i32);
    let lit = |x: i32, y: i32| {
        (0..w).contains(&x) && (0..h).contains(&y) && truth[(y * w + x) as usize].is_some_and(|t| t.lit)
    };
    let (mut deep, mut dark) = (0u64, 0u64);
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let shadowed = truth[i].is_some_and(|t| !t.lit);
            if !shadowed || (-margin..=margin).any(|d| (-margin..=margin).any(|e| lit(x + d, y + e))) {
                continue;
            }
            deep += 1;
            dark += metrics::rendered(frame, 0, i).is_some_and(|v| v < metrics::DARK) as u64;
        }
    }
    assert!(deep > 1000, "the view shows the sun's shadows: {deep} deep pixels");
    dark as f64 / deep as f64
}

/// True (and SKIPPED said) when the device cannot mark pages; then the sun reads its coarse
/// map, and every deep shadow must still be dark.
fn cannot_mark(app: &mut App, frame: &DebugFrame) -> bool {
    let notices = app.take_notices();
    if !notices.iter().any(|n| n.contains("compute pass")) {
        return false;
    }
    let (_, truth) = sun_tally(app, frame);
    assert!(deep_shadow_dark(frame, &truth, 6) > 0.95, "the coarse map shadows the sun's deep shadows");
    eprintln!("SKIPPED: this device runs no compute shaders; the sun reads its coarse map alone");
    true
}

/// The sample view with virtual sun maps (`change` made to the settings), drawn once its pages
/// are resident, with its renderer; none (SKIPPED said) where pages cannot be marked.
fn primed(gpu: &Gpu, change: impl FnOnce(&mut Settings)) -> Option<(Renderer, App, DebugFrame)> {
    let mut renderer = Renderer::new(gpu, HEADLESS_FORMAT).unwrap();
    let mut app = paged(change);
    let frame = render_debug_frame(gpu, &mut renderer, &mut app, W, H).expect("no wgpu error");
    (!cannot_mark(&mut app, &frame)).then_some((renderer, app, frame))
}

#[test]
fn virtual_maps_put_the_suns_shadows_where_the_truth_does_with_fewer_wrong_pixels_than_cascades() {
    let gpu = gpu();
    let mut cascades = app(|_| ());
    let frame = render_debug_frame(&gpu, &mut Renderer::new(&gpu, HEADLESS_FORMAT).unwrap(), &mut cascades, W, H)
        .expect("no wgpu error");
    let (by_cascades, _) = sun_tally(&mut cascades, &frame);
    // Before any marking, a fresh renderer's sun reads its coarse map alone: what the pages add.
    let mut coarse = paged(|_| ());
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    coarse.hear(renderer.news());
    let frame = render_debug_frame_as_is(&gpu, &mut renderer, &mut coarse, W, H).expect("no wgpu error");
    let (by_coarse, truth) = sun_tally(&mut coarse, &frame);
    // Its texels are 12 cm and its bias shifts shadows by 1.5 of them: thin shadows thin out, but
    // what it shows is shadowed (a lookup that read nothing would light all of it).
    assert!(deep_shadow_dark(&frame, &truth, 6) > 0.95, "the coarse map alone shadows the deep shadows");
    let Some((_, mut virt, frame)) = primed(&gpu, |_| ()) else { return };
    let (by_pages, truth) = sun_tally(&mut virt, &frame);
    let p = pages(&mut virt);
    let percent = |t: &metrics::Tally| 100.0 * t.misclassified();
    eprintln!(
        "sun misclassified: cascades {:.4} %, coarse map {:.4} %, pages {:.4} % ({} resident, {:?})",
        percent(&by_cascades),
        percent(&by_coarse),
        percent(&by_pages),
        p.resident,
        p.pressure
    );
    assert!(by_pages.misclassified() < by_cascades.misclassified(), "pages beat four 2048² cascades");
    assert!(by_pages.misclassified() * 3.0 < by_coarse.misclassified(), "the pages are read, not the coarse map");
    assert!(deep_shadow_dark(&frame, &truth, 3) > 0.999);
    let capacity = virt.world.resource::<SharedPool>().pages.capacity();
    assert!(p.resident <= capacity && capacity == 2048, "32 MiB of 64² depth pages");
    assert!(p.resident > 100 && p.marked.residency.missing == 0, "{:?}", p.marked);
}

#[test]
fn a_still_view_draws_no_page_and_a_moving_cube_redraws_only_the_pages_it_crosses() {
    let gpu = gpu();
    let Some((mut renderer, mut app, frame)) = primed(&gpu, |_| ()) else { return };
    let (before, _) = sun_tally(&mut app, &frame);
    app.step_held();
    render_debug_frame_as_is(&gpu, &mut renderer, &mut app, W, H).expect("no wgpu error");
    let still = app.world.resource::<ShadowStats>().pages;
    assert_eq!(still.drawn, 0, "a still view keeps every page: {still:?}");
    assert!(still.kept > 100);
    // One cube jumps 40 cm sideways.
    let cube = app.world.query_filtered::<Entity, With<Spin>>().iter(&app.world).next().unwrap();
    app.world.get_mut::<Transform>(cube).unwrap().translation += Vec3::new(0.4, 0.0, 0.0);
    app.step_held();
    let frame = render_debug_frame_as_is(&gpu, &mut renderer, &mut app, W, H).expect("no wgpu error");
    let moved = app.world.resource::<ShadowStats>().pages;
    let p = pages(&mut app);
    eprintln!("one cube moved: {} of {} resident pages drawn again", moved.drawn, p.resident);
    assert_eq!(moved.drawn, p.update.invalidated, "the pages it crossed, each once");
    assert!(moved.drawn > 0 && moved.drawn * 20 <= p.resident, "{moved:?} of {}", p.resident);
    // Its old shadow went with the pages drawn again: no more false shadow than before.
    let (after, _) = sun_tally(&mut app, &frame);
    assert!(after.false_shadow <= before.false_shadow + 20, "{} then {}", before.false_shadow, after.false_shadow);
}

#[test]
fn a_pool_too_small_reads_coarser_levels_counts_what_it_lacks_and_leaves_no_deep_shadow_lit() {
    let gpu = gpu();
    let Some((_, mut app, frame)) = primed(&gpu, |s| s.maps.page_memory = 1) else { return };
    let p = pages(&mut app);
    assert_eq!(app.world.resource::<SharedPool>().pages.capacity(), 64, "1 MiB of 64² depth pages");
    assert!(p.resident <= 64);
    assert!(p.pressure.octaves > 0.0, "coarser: {:?}", p.pressure);
    let (tally, truth) = sun_tally(&mut app, &frame);
    assert!(deep_shadow_dark(&frame, &truth, 6) > 0.98);
    assert!(tally.misclassified() < 0.03, "coarser, not broken: {:.3} %", 100.0 * tally.misclassified());
}

#[test]
fn a_camera_cut_reads_what_is_resident_until_its_own_pages_come_and_is_never_unshadowed() {
    let gpu = gpu();
    let Some((mut renderer, mut app, _)) = primed(&gpu, |_| ()) else { return };
    // A cut to the far side of the scene, looking back.
    umbra::scene::place_camera(&mut app.world, Vec3::new(-6.0, 2.5, -9.0), Vec3::new(1.0, 0.5, 2.0));
    app.step_held();
    let first = render_debug_frame_as_is(&gpu, &mut renderer, &mut app, W, H).expect("no wgpu error");
    let (cut, truth) = sun_tally(&mut app, &first);
    assert!(deep_shadow_dark(&first, &truth, 3) > 0.99, "the frame of the cut shadows what it shows");
    // Frames as a window draws them: each hears the last marking and takes its pages.
    let mut frames = 1;
    loop {
        renderer.wait_for_samples(&gpu);
        app.hear(renderer.news());
        app.step_held();
        let frame = render_debug_frame_as_is(&gpu, &mut renderer, &mut app, W, H).expect("no wgpu error");
        frames += 1;
        let update = pages(&mut app).update;
        if update.settled() && update.needed > 0 {
            let (settled, _) = sun_tally(&mut app, &frame);
            eprintln!(
                "camera cut: {:.4} % of the sun's pixels wrong on its frame, {:.4} % once its pages came, \
                 {frames} frames later",
                100.0 * cut.misclassified(),
                100.0 * settled.misclassified()
            );
            assert!(settled.misclassified() < cut.misclassified(), "its own pages are sharper");
            break;
        }
        assert!(frames <= PRIME_ROUNDS as usize + 1, "its pages came within {PRIME_ROUNDS} frames");
    }
}

/// The shadow-map viewer's picture after one headless picture of the sample with `change` made to
/// the settings, and each layer's tile; none where no page can be marked (no compute shaders).
fn viewer(gpu: &Gpu, change: impl FnOnce(&mut Settings)) -> Option<(umbra::render::Image, Vec<AtlasTile>)> {
    let mut renderer = Renderer::new(gpu, HEADLESS_FORMAT).unwrap();
    let mut app = app(change);
    // A picture, as the window draws (the viewer shows the layers of the last one).
    render_headless(gpu, &mut renderer, &mut app, W, H).expect("no wgpu error");
    if app.take_notices().iter().any(|n| n.contains("compute pass")) {
        return None;
    }
    Some(read_map_atlas(gpu, &mut renderer).expect("no wgpu error"))
}

/// The pixels of `picture` under `tile`, row by row.
fn tile_pixels(picture: &umbra::render::Image, tile: &AtlasTile) -> Vec<[u8; 4]> {
    let [x, y, side] = tile.rect.map(|v| v as u32);
    (y..y + side).flat_map(|y| (x..x + side).filter_map(move |x| picture.pixel(x, y))).collect()
}

#[test]
fn the_map_viewer_draws_every_tile_of_the_paged_sun_and_of_the_lights_beside_it() {
    // The viewer's shader sees MAX_LAYERS layers at a time; a paged sun's pages are layers too,
    // so the spots' tiles and most cube faces once came after the first chunk and were left
    // black, and a chunk bound at the wrong offset would draw another layer's texels there.
    let gpu = gpu();
    let Some((picture, tiles)) = viewer(&gpu, |s| s.maps.sun_maps = SunMaps::Virtual) else {
        eprintln!("SKIPPED: this device runs no compute shaders, so no page is marked");
        return;
    };
    let at_once = umbra::render::gpu_types::MAX_LAYERS;
    assert!(tiles.len() > at_once, "more layers than the shader sees at once ({at_once}): {}", tiles.len());
    let black: Vec<String> = tiles
        .iter()
        .enumerate()
        .filter(|(_, t)| tile_pixels(&picture, t).iter().all(|p| p[..3].iter().all(|&c| c <= 8)))
        .map(|(i, t)| format!("layer {i}: {} {:?}", t.light, t.level))
        .collect();
    assert!(
        black.is_empty(),
        "{} of {} tiles left black: {:?}",
        black.len(),
        tiles.len(),
        &black[..black.len().min(8)]
    );
    // A spot's map does not depend on how the sun keeps its shadows: its tile, far past the first
    // chunk here, shows what it shows with cascades, where it is in the first.
    let (cascaded, cascade_tiles) = viewer(&gpu, |_| {}).expect("cascades need no compute");
    let spot =
        |tiles: &[AtlasTile]| tiles.iter().position(|t| t.light.to_string() == "spot 1").expect("spot 1 has a tile");
    let (paged_at, cascaded_at) = (spot(&tiles), spot(&cascade_tiles));
    assert!(
        paged_at >= at_once && cascaded_at < at_once,
        "spot 1 is layer {paged_at} paged, {cascaded_at} with cascades"
    );
    let (a, b) = (tile_pixels(&picture, &tiles[paged_at]), tile_pixels(&cascaded, &cascade_tiles[cascaded_at]));
    assert_eq!(a.len(), b.len(), "spot 1's tile is as large either way");
    let differ = a.iter().zip(&b).filter(|(p, q)| p[..3].iter().zip(&q[..3]).any(|(x, y)| x.abs_diff(*y) > 2)).count();
    assert!(differ * 100 <= a.len(), "spot 1's tile differs from its cascaded twin in {differ} of {} pixels", a.len());
}
