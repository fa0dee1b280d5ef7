//! The skinned character on the GPU: its vertices land where CPU skinning puts them, and its
//! shadow on the ground changes with the pose and follows it as it walks.

mod common;

use bevy_ecs::entity::Entity;
use common::{SIZE, camera_at, gpu};
use glam::{Mat4, Vec2, Vec3};
use std::sync::Arc;
use umbra::assets::{MeshLibrary, parse_model, plane};
use umbra::components::*;
use umbra::eval::{metrics, truth};
use umbra::render::{DebugFrame, HEADLESS_FORMAT, Renderer, render_debug_frame};
use umbra::scene::{CHARACTER_GLB, spawn_model};
use umbra::{App, Settings};

/// The character alone (on a ground plane if `ground`), lit by a high sun, seen from `eye`.
fn character_scene(ground: bool, eye: Vec3, target: Vec3) -> (App, Entity) {
    let mut app = App::empty(Settings::default().with(|s| {
        s.maps.shadow_map_size = 1024;
        s.cascade.cascades = 2;
    }))
    .unwrap();
    if ground {
        let mesh = app.world.resource_mut::<MeshLibrary>().add(plane(20.0));
        app.world.spawn((mesh, Material::color(0.6, 0.6, 0.6), ShadowReceiver));
    }
    let model = Arc::new(parse_model(CHARACTER_GLB, None, "character.glb").unwrap());
    let character = spawn_model(&mut app.world, model, Transform::default(), Some(0));
    let sun = DirectionalLight {
        direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
        color: Vec3::ONE,
        intensity: 1.0,
        ..Default::default()
    };
    app.world.spawn((sun, ShadowMap::default()));
    app.world.spawn(camera_at(eye, target));
    app.resize(SIZE, SIZE);
    (app, character)
}

fn measure(app: &mut App, t: f64) -> DebugFrame {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    app.set_time(t);
    render_debug_frame(&gpu, &mut renderer, app, SIZE, SIZE).expect("measured frame")
}

/// The world ray through the centre of pixel `i`.
fn pixel_ray(app: &mut App, i: usize) -> (Vec3, Vec3) {
    let (camera, transform) = app.world.query::<(&Camera, &Transform)>().iter(&app.world).next().unwrap();
    let inv: Mat4 = camera.view_proj(transform, 1.0).inverse();
    let (x, y) = ((i as u32 % SIZE) as f32 + 0.5, (i as u32 / SIZE) as f32 + 0.5);
    let ndc = Vec2::new(x / SIZE as f32 * 2.0 - 1.0, 1.0 - y / SIZE as f32 * 2.0);
    let near = inv.project_point3(ndc.extend(0.0));
    let far = inv.project_point3(ndc.extend(1.0));
    (transform.translation, (far - near).normalize())
}

/// For every pixel showing the character: how far the GPU's surface point is from where a ray
/// through the pixel meets the CPU-skinned triangles of time `cpu_t`.
fn gpu_vs_cpu(app: &mut App, frame: &DebugFrame, cpu_t: f64) -> Vec<f32> {
    app.set_time(cpu_t);
    let occluders = truth::Occluders::from_world(&mut app.world);
    (0..frame.position.len())
        .filter(|&i| frame.covered(i))
        .filter_map(|i| {
            let (eye, dir) = pixel_ray(app, i);
            let hit = occluders.first_hit(eye, dir)?;
            Some((eye + dir * hit).distance(frame.position[i].truncate()))
        })
        .collect()
}

#[test]
fn gpu_skinning_puts_every_vertex_where_cpu_skinning_does() {
    let (mut app, _) = character_scene(false, Vec3::new(1.2, 1.4, 2.2), Vec3::new(0.0, 0.95, 0.0));
    let t = 0.3;
    let frame = measure(&mut app, t);
    let covered = frame.position.iter().filter(|p| p.w > 0.5).count();
    assert!(covered > 3000, "the character fills part of the frame: {covered} pixels");
    let mut gaps = gpu_vs_cpu(&mut app, &frame, t);
    gaps.sort_by(f32::total_cmp);
    let median = gaps[gaps.len() / 2];
    let within = gaps.iter().filter(|&&g| g < 1e-3).count() as f32 / gaps.len() as f32;
    // Silhouette pixels can meet a different surface than the pixel's own fragment; everything
    // else agrees to well under a millimetre.
    assert!(median < 1e-4 && within > 0.97, "median {median} m, {:.1}% within 1 mm", 100.0 * within);
    // The comparison sees a pose a tenth of a second off (the arms and legs have moved).
    let gaps = gpu_vs_cpu(&mut app, &frame, t + 0.1);
    let within = gaps.iter().filter(|&&g| g < 1e-3).count() as f32 / gaps.len() as f32;
    assert!(within < 0.9, "{:.1}% within 1 mm of the wrong pose", 100.0 * within);
}

/// Ground pixels the renderer shadowed from the sun, checked against the ray-traced truth.
fn ground_shadow(app: &mut App, frame: &DebugFrame) -> Vec<bool> {
    let truth = truth::truth_of(&mut app.world, frame, truth::SizeOverride::default(), 0);
    let on_ground = |i: usize| frame.covered(i) && frame.position[i].y.abs() < 1e-3;
    let tally = metrics::tally(frame, &truth[0], 0, on_ground);
    let truly_dark = (0..truth[0].len()).filter(|&i| on_ground(i) && truth[0][i].is_some_and(|t| !t.lit)).count();
    let wrong = tally.false_shadow + tally.false_lit;
    assert!(truly_dark > 150 && wrong * 10 < truly_dark as u64, "{wrong} pixels wrong of a {truly_dark}-pixel shadow");
    (0..frame.position.len()).map(|i| on_ground(i) && metrics::rendered(frame, 0, i).is_some_and(|v| v < 0.5)).collect()
}

#[test]
fn the_shadow_changes_with_the_pose() {
    let (mut app, _) = character_scene(true, Vec3::new(1.0, 3.0, 3.0), Vec3::new(0.3, 0.0, 0.2));
    // A quarter cycle apart the legs and arms swing from one side to the other.
    let a = measure(&mut app, 0.25);
    let shadow_a = ground_shadow(&mut app, &a);
    let b = measure(&mut app, 0.75);
    let shadow_b = ground_shadow(&mut app, &b);
    let count = |s: &[bool]| s.iter().filter(|&&x| x).count();
    let differ = shadow_a.iter().zip(&shadow_b).filter(|(x, y)| x != y).count();
    assert!(count(&shadow_a) > 300 && count(&shadow_b) > 300, "{} {}", count(&shadow_a), count(&shadow_b));
    assert!(differ > count(&shadow_a) / 5, "{differ} of {} shadow pixels changed", count(&shadow_a));
    // A full cycle later the pose and its shadow are back.
    let c = measure(&mut app, 1.25);
    assert_eq!(ground_shadow(&mut app, &c), shadow_a);
}

#[test]
fn the_shadow_follows_the_character_as_it_walks() {
    let (mut app, character) = character_scene(true, Vec3::new(2.5, 4.5, 4.5), Vec3::new(2.4, 0.0, 1.2));
    app.world.entity_mut(character).insert(Walker { center: Vec3::ZERO, radius: 3.0, speed: 1.35, phase: 0.0 });
    let centroid = |app: &mut App, t: f64| {
        let frame = measure(app, t);
        let shadow = ground_shadow(app, &frame);
        let points: Vec<Vec3> =
            (0..shadow.len()).filter(|&i| shadow[i]).map(|i| frame.position[i].truncate()).collect();
        points.iter().sum::<Vec3>() / points.len().max(1) as f32
    };
    let (t0, t1) = (0.0, 2.0);
    let (c0, c1) = (centroid(&mut app, t0), centroid(&mut app, t1));
    let walker_at = |t: f64| {
        let a = 1.35 * t as f32 / 3.0;
        Vec3::new(a.cos(), 0.0, a.sin()) * 3.0
    };
    let moved = walker_at(t1) - walker_at(t0);
    assert!((c1 - c0).distance(moved) < 0.3, "the shadow moved {:?}, the character {moved:?}", c1 - c0);
}

#[test]
fn the_character_wears_its_striped_texture() {
    let mut app = App::empty(Settings::default().with(|s| {
        s.maps.shadow_map_size = 1024;
        s.view.ambient = 0.2;
    }))
    .unwrap();
    let model = Arc::new(parse_model(CHARACTER_GLB, None, "character.glb").unwrap());
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    assert!(model.parts.iter().filter(|p| p.texture.is_some()).count() == 1, "the shirt is textured");
    spawn_model(&mut app.world, model, Transform::default(), None);
    let sun = DirectionalLight {
        direction: Vec3::new(0.0, -0.3, -1.0).normalize(),
        color: Vec3::ONE,
        intensity: 1.0,
        ..Default::default()
    };
    app.world.spawn((sun, ShadowMap::default()));
    app.world.spawn(camera_at(Vec3::new(0.0, 1.2, 2.0), Vec3::new(0.0, 1.2, 0.0)));
    let image = common::render(&mut app, 0.0);
    // Down the front of the torso, a pixel every centimetre: cream and navy bands alternate.
    let bands: Vec<bool> = (0..45)
        .filter_map(|k| {
            let (x, y) = common::pixel_of(&mut app, Vec3::new(0.0, 1.38 - 0.01 * k as f32, 0.12));
            let [r, _, b, _] = image.pixel(x, y)?;
            let (r, b) = (r as i32, b as i32);
            match (r > 150 && r + 10 > b, b > r + 30) {
                (true, false) => Some(true),
                (false, true) => Some(false),
                _ => None,
            }
        })
        .collect();
    let changes = bands.windows(2).filter(|w| w[0] != w[1]).count();
    let (cream, navy) = (bands.iter().filter(|&&c| c).count(), bands.iter().filter(|&&c| !c).count());
    assert!(cream > 8 && navy > 8 && changes >= 4, "{cream} cream, {navy} navy, {changes} changes: {bands:?}");
}
