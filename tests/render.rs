//! Render tests on the software adapter: they check where the shadows are, not only that a frame
//! came out. Each frame is 256x256; any wgpu error fails the test that caused it.

mod common;

use common::*;
use glam::Vec3;
use umbra::assets::{cube, plane};
use umbra::components::*;
use umbra::render::{Gpu, HEADLESS_FORMAT, RenderError, Renderer, render_headless};
use umbra::{App, Settings};

fn settings() -> Settings {
    Settings::default().with(|s| {
        s.maps.shadow_map_size = 1024;
        s.view.ambient = 0.1;
    })
}

/// A grey unit cube hovering at height 1..2 over a grey plane, seen from above and in front.
fn cube_over_plane(settings: Settings) -> App {
    let mut app = App::empty(settings).unwrap();
    let (ground, block) = {
        let mut meshes = app.world.resource_mut::<umbra::assets::MeshLibrary>();
        (meshes.add(plane(20.0)), meshes.add(cube(Vec3::splat(0.5))))
    };
    let grey = Material { specular: 0.0, shininess: 1.0, ..Material::color(0.6, 0.6, 0.6) };
    app.world.spawn((ground, Transform::default(), grey, ShadowReceiver));
    app.world.spawn((block, Transform::from_xyz(0.0, 1.5, 0.0), grey, ShadowCaster, ShadowReceiver));
    app.world.spawn(camera_at(Vec3::new(0.0, 6.0, 8.0), Vec3::ZERO));
    app
}

fn add_sun(app: &mut App, direction: Vec3) {
    let sun = DirectionalLight { direction, color: Vec3::ONE, intensity: 1.0, ..Default::default() };
    app.world.spawn((sun, ShadowMap::default()));
}

#[test]
fn straight_down_sun_shadows_the_ground_under_the_cube() {
    let mut app = cube_over_plane(settings());
    add_sun(&mut app, Vec3::NEG_Y);
    let image = render(&mut app, 0.0);
    let under = brightness_at(&mut app, &image, Vec3::ZERO);
    let under_edge = brightness_at(&mut app, &image, Vec3::new(0.35, 0.0, -0.35));
    let far = brightness_at(&mut app, &image, Vec3::new(2.5, 0.0, 1.0));
    let top = brightness_at(&mut app, &image, Vec3::new(0.0, 2.0, 0.0));
    assert!(under < 0.5 * far, "under the cube {under} should be dark next to lit ground {far}");
    assert!(under_edge < 0.5 * far, "inside the footprint {under_edge} vs {far}");
    assert!(top > 0.9 * far, "the cube's top {top} faces the sun and should be lit like the ground {far}");
    // Just outside the footprint the ground is lit again: the shadow is where the cube is.
    let beside = brightness_at(&mut app, &image, Vec3::new(0.8, 0.0, 0.0));
    assert!(beside > 0.9 * far, "beside the footprint {beside} vs {far}");
}

#[test]
fn slanted_sun_moves_the_shadow_away_from_under_the_cube() {
    let mut app = cube_over_plane(settings());
    // Travelling towards +X and down at 45 degrees: the shadow lands 1.5 m along +X.
    add_sun(&mut app, Vec3::new(1.0, -1.0, 0.0));
    let image = render(&mut app, 0.0);
    let far = brightness_at(&mut app, &image, Vec3::new(-2.5, 0.0, 1.0));
    let shifted = brightness_at(&mut app, &image, Vec3::new(1.5, 0.0, 0.0));
    let under = brightness_at(&mut app, &image, Vec3::new(-0.3, 0.0, 0.0));
    assert!(shifted < 0.6 * far, "shadow should fall at x=1.5: {shifted} vs lit {far}");
    assert!(under > 0.9 * far, "straight under the cube is lit now: {under} vs {far}");
}

#[test]
fn without_shadows_there_is_no_dark_region() {
    let mut app = cube_over_plane(settings().with(|s| s.shadow.enabled = false));
    add_sun(&mut app, Vec3::NEG_Y);
    let image = render(&mut app, 0.0);
    let far = brightness_at(&mut app, &image, Vec3::new(2.5, 0.0, 1.0));
    for x in [-0.4, -0.2, 0.0, 0.2, 0.4] {
        for z in [-0.4, 0.0, 0.4] {
            let b = brightness_at(&mut app, &image, Vec3::new(x, 0.0, z));
            assert!((b - far).abs() < 0.05 * far, "ground at ({x}, {z}) is {b}, lit ground is {far}");
        }
    }
}

fn spot_over_plane(intensity: f32) -> App {
    let mut app = cube_over_plane(settings());
    let spot = SpotLight {
        color: Vec3::new(1.0, 0.6, 0.2),
        intensity,
        range: 10.0,
        inner_angle: 15f32.to_radians(),
        outer_angle: 20f32.to_radians(),
        ..Default::default()
    };
    let at = Transform::from_xyz(0.0, 4.0, 0.0).looking_to(Vec3::NEG_Y);
    app.world.spawn((spot, at, ShadowMap::default()));
    app
}

#[test]
fn ground_outside_the_spot_cone_gets_none_of_its_light() {
    let mut lit = spot_over_plane(3.0);
    let mut dark = spot_over_plane(0.0);
    let (with, without) = (render(&mut lit, 0.0), render(&mut dark, 0.0));
    // 4 m up with a 20 degree cone: the cone meets the ground at r = 1.46 m.
    for p in [Vec3::new(2.0, 0.0, 0.0), Vec3::new(-1.7, 0.0, 1.0), Vec3::new(0.0, 0.0, -2.5)] {
        let (x, y) = pixel_of(&mut lit, p);
        assert_eq!(with.pixel(x, y), without.pixel(x, y), "outside the cone at {p:?}");
    }
    // Inside the cone but beside the cube's shadow, the spot adds light.
    let inside = Vec3::new(1.1, 0.0, 0.0);
    let (x, y) = pixel_of(&mut lit, inside);
    assert!(with.brightness(x, y) > without.brightness(x, y) + 20.0, "inside the cone at {inside:?}");
}

#[test]
fn spot_light_casts_the_cube_shadow() {
    let mut app = spot_over_plane(3.0);
    let image = render(&mut app, 0.0);
    let mut unlit = spot_over_plane(0.0);
    let ambient_only = render(&mut unlit, 0.0);
    // Straight under the cube the spot is blocked: only ambient light remains there.
    let (x, y) = pixel_of(&mut app, Vec3::new(0.0, 0.0, 0.2));
    assert!((image.brightness(x, y) - ambient_only.brightness(x, y)).abs() < 3.0);
    let (x, y) = pixel_of(&mut app, Vec3::new(1.1, 0.0, 0.0));
    assert!(image.brightness(x, y) > ambient_only.brightness(x, y) + 20.0);
}

#[test]
fn the_sample_scene_is_deterministic_in_time() {
    let frame = |t| render(&mut App::new(Settings::default()).unwrap(), t);
    let (a, b, c) = (frame(1.5), frame(1.5), frame(2.25));
    assert_eq!(a, b, "the same time gives the same frame");
    assert_ne!(a, c, "the cubes move between 1.5 s and 2.25 s");
}

#[test]
fn a_main_pass_drawn_in_parts_is_the_main_pass_drawn_whole() {
    let gpu = gpu();
    let frame = |most| {
        let mut app = App::new(Settings::default()).unwrap();
        app.resize(SIZE, SIZE);
        app.set_time(1.5);
        let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).expect("renderer");
        renderer.draw_in_parts(most);
        render_headless(&gpu, &mut renderer, &mut app, SIZE, SIZE).expect("frame renders without wgpu errors")
    };
    let whole = frame(0);
    // Parts of three draws: each draws onto what the ones before drew, clearing none of it.
    assert!(frame(3) == whole, "the frame drawn in parts of three draws differs from the frame drawn whole");
}

#[test]
fn the_sample_scene_has_pillar_shadows_where_the_sun_puts_them() {
    let mut on = App::new(Settings::default()).unwrap();
    let mut off = App::new(Settings::default().with(|s| s.shadow.enabled = false)).unwrap();
    let (a, b) = (render(&mut on, 2.0), render(&mut off, 2.0));
    // The pillar at (7.5, -4) is 6 m tall; the sun travels along SUN_DIRECTION (y = -1), so its
    // shadow runs from the foot to the top's image at the foot + 6 * (x, z) of that direction.
    let d = umbra::scene::SUN_DIRECTION;
    let foot = Vec3::new(7.5, 0.0, -4.0);
    let tip = foot + 6.0 * Vec3::new(d.x, 0.0, d.z) / -d.y;
    for s in [0.3, 0.5, 0.7] {
        let p = foot.lerp(tip, s);
        let (x, y) = pixel_of(&mut on, p);
        assert!(a.brightness(x, y) < 0.6 * b.brightness(x, y), "pillar shadow missing at {p:?}");
    }
    // Open ground near the camera, away from every caster, is lit the same with shadows on or off.
    for p in [Vec3::new(0.0, 0.0, 7.6), Vec3::new(-3.0, 0.0, 7.6)] {
        let (x, y) = pixel_of(&mut on, p);
        assert!((a.brightness(x, y) - b.brightness(x, y)).abs() < 2.0, "false shadow at {p:?}");
    }
    // And shadows cover some of the frame, not all of it.
    let darker = a.pixels.chunks(4).zip(b.pixels.chunks(4)).filter(|(p, q)| p[1] as i32 + 25 < q[1] as i32).count();
    let share = darker as f32 / (SIZE * SIZE) as f32;
    assert!((0.02..0.4).contains(&share), "{:.1}% of the frame is in shadow", share * 100.0);
}

#[test]
fn a_wgpu_validation_error_is_reported_not_ignored() {
    let gpu = gpu();
    gpu.check_errors().unwrap();
    // Mappable for reading and usable as a vertex buffer at once is invalid without a feature.
    let _bad = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("invalid on purpose"),
        size: 16,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::VERTEX,
        mapped_at_creation: false,
    });
    let err = gpu.check_errors().unwrap_err();
    assert!(matches!(err, RenderError::Wgpu(_)), "{err}");
    gpu.check_errors().unwrap();
}

#[test]
fn oversized_shadow_maps_and_frames_are_clear_errors() {
    let gpu: std::sync::MutexGuard<'_, Gpu> = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let mut app = App::new(Settings::default()).unwrap();
    let err = render_headless(&gpu, &mut renderer, &mut app, 0, 10).unwrap_err();
    assert!(err.to_string().contains("0x10"), "{err}");
    let max = gpu.device.limits().max_texture_dimension_2d;
    if max < umbra::settings::MAX_SHADOW_MAP_SIZE {
        app.world.resource_mut::<umbra::settings::MapSettings>().shadow_map_size = max * 2;
        let err = render_headless(&gpu, &mut renderer, &mut app, 8, 8).unwrap_err();
        assert!(err.to_string().contains("shadow_map_size"), "{err}");
    }
    gpu.check_errors().unwrap();
}

#[test]
fn the_renderer_only_reads_the_world_and_what_it_learns_comes_back_as_news() {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let mut app = cube_over_plane(settings());
    add_sun(&mut app, Vec3::new(0.3, -1.0, 0.2));
    app.resize(SIZE, SIZE);
    app.set_time(0.0);
    let texture = gpu.target("news", (SIZE, SIZE), HEADLESS_FORMAT).unwrap();
    let view = texture.create_view(&Default::default());
    // A world that has not heard what this device keeps of shadows is refused, by name.
    let err = renderer.render(&gpu, &app.world, &view, SIZE, SIZE).unwrap_err();
    assert!(matches!(err, RenderError::NotTold) && err.to_string().contains("app.hear(renderer.news())"), "{err}");
    app.hear(renderer.news());
    renderer.render(&gpu, &app.world, &view, SIZE, SIZE).unwrap();
    assert!(app.world.get_resource::<umbra::render::ShadowStats>().is_none(), "drawing wrote into the world");
    let news = renderer.news();
    let drawn = news.stats.as_ref().map_or(0, |s| s.drawn());
    assert!(drawn > 0, "the first frame draws the sun's cascades: {news:?}");
    app.hear(news);
    assert_eq!(app.world.resource::<umbra::render::ShadowStats>().drawn(), drawn);
    // News is handed over once: what is left is the device's capabilities alone.
    let left = renderer.news();
    assert!(left.stats.is_none() && left.seen.is_none() && left.notices.is_empty(), "{left:?}");
    gpu.check_errors().unwrap();
}
