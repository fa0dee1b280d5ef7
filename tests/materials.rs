//! Materials on the GPU: textures where the model is, cut-out shadows where the truth says,
//! double-sided surfaces seen from behind, blending over what is behind, and a model with no
//! size that leaves every other shadow as it was.

mod common;

use common::gltf::{checker, png_rgba, quad_glb};
use common::*;
use glam::{Quat, Vec3};
use serde_json::{Value, json};
use std::sync::Arc;
use umbra::assets::{MeshLibrary, parse_model, plane};
use umbra::components::*;
use umbra::eval::{metrics, truth};
use umbra::render::{HEADLESS_FORMAT, Image, Renderer, render_debug_frame};
use umbra::scene::spawn_model;
use umbra::{App, Settings};

const RED: [u8; 4] = [255, 0, 0, 255];
const BLUE: [u8; 4] = [0, 0, 255, 255];

/// An empty scene: optionally a ground plane, a sun travelling along `sun`, a camera.
fn scene(ground: bool, sun: Vec3, eye: Vec3, target: Vec3) -> App {
    let mut app = App::empty(Settings::default().with(|s| {
        s.maps.shadow_map_size = 1024;
        s.cascade.cascades = 2;
        s.view.ambient = 0.1;
    }))
    .unwrap();
    if ground {
        let mesh = app.world.resource_mut::<MeshLibrary>().add(plane(20.0));
        app.world.spawn((mesh, Material::color(0.6, 0.6, 0.6), ShadowReceiver));
    }
    let sun = DirectionalLight { direction: sun.normalize(), color: Vec3::ONE, intensity: 1.0, ..Default::default() };
    app.world.spawn((sun, ShadowMap::default()));
    app.world.spawn(camera_at(eye, target));
    app
}

/// Loads a .glb (warnings returned) and stands it at `placement`.
fn place(app: &mut App, glb: &[u8], placement: Transform) -> Vec<String> {
    let model = parse_model(glb, None, "quad.glb").unwrap();
    let warnings = model.warnings.clone();
    spawn_model(&mut app.world, Arc::new(model), placement, None);
    warnings
}

fn rgb(app: &mut App, image: &Image, p: Vec3) -> [f32; 3] {
    let (x, y) = pixel_of(app, p);
    let c = image.pixel(x, y).unwrap();
    [c[0] as f32, c[1] as f32, c[2] as f32]
}

fn white() -> Value {
    json!({ "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0] } })
}

#[test]
fn a_textured_model_shows_its_texture_and_a_missing_image_its_factor() {
    let texture = png_rgba(2, 2, &checker(2, RED, BLUE));
    let upright = Transform::from_xyz(0.0, 1.5, 0.0);
    let mut app = scene(false, Vec3::new(0.0, -0.3, -1.0), Vec3::new(0.0, 1.5, 4.0), Vec3::new(0.0, 1.5, 0.0));
    let warnings = place(&mut app, &quad_glb(white(), Some((json!({}), Some(&texture)))), upright);
    assert!(warnings.is_empty(), "{warnings:?}");
    let image = render(&mut app, 0.0);
    // Texel (0, 0) is red: the quad's top left; (1, 0) is blue: its top right.
    let [r, g, b] = rgb(&mut app, &image, Vec3::new(-0.5, 2.0, 0.0));
    assert!(r > 100.0 && r > 2.0 * b && r > 2.0 * g, "top left {r} {g} {b}");
    let [r, g, b] = rgb(&mut app, &image, Vec3::new(0.5, 2.0, 0.0));
    assert!(b > 100.0 && b > 2.0 * r && b > 2.0 * g, "top right {r} {g} {b}");
    let [r, _, b] = rgb(&mut app, &image, Vec3::new(0.5, 1.0, 0.0));
    assert!(r > 2.0 * b, "bottom right is red again");

    let mut app = scene(false, Vec3::new(0.0, -0.3, -1.0), Vec3::new(0.0, 1.5, 4.0), Vec3::new(0.0, 1.5, 0.0));
    let warnings = place(&mut app, &quad_glb(white(), Some((json!({ "uri": "gone.png" }), None))), upright);
    assert!(warnings.iter().any(|w| w.contains("image 0 (gone.png) cannot be read")), "{warnings:?}");
    let image = render(&mut app, 0.0);
    for p in [Vec3::new(-0.5, 2.0, 0.0), Vec3::new(0.5, 2.0, 0.0)] {
        let [r, g, b] = rgb(&mut app, &image, p);
        assert!(r > 100.0 && (r - b).abs() < 8.0 && (r - g).abs() < 8.0, "white where the texture was: {r} {g} {b}");
    }
}

/// The quad lying flat at height 2, a 4x4 checker of solid and cut-away cells, over the ground.
fn cutout_scene() -> App {
    let mask = png_rgba(4, 4, &checker(4, [255, 255, 255, 255], [255, 255, 255, 0]));
    let material = json!({ "alphaMode": "MASK", "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0] } });
    let mut app = scene(true, Vec3::NEG_Y, Vec3::new(0.0, 1.0, 5.0), Vec3::new(0.0, 0.0, 0.0));
    let flat = Transform::from_xyz(0.0, 2.0, 0.0).with_rotation(Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2));
    place(&mut app, &quad_glb(material, Some((json!({}), Some(&mask)))), flat);
    app
}

#[test]
fn a_cut_out_caster_casts_a_cut_out_shadow_where_the_truth_says() {
    let mut app = cutout_scene();
    let image = render(&mut app, 0.0);
    let lit = brightness_at(&mut app, &image, Vec3::new(1.8, 0.0, 0.5));
    // Ground under cell (i, j) of the mask: x = -1 + (i + 0.5) / 2, z = -1 + (j + 0.5) / 2.
    let (mut dark, mut light) = (0, 0);
    for i in 0..4 {
        for j in 0..4 {
            let p = Vec3::new(-0.75 + 0.5 * i as f32, 0.0, -0.75 + 0.5 * j as f32);
            let b = brightness_at(&mut app, &image, p);
            if (i + j) % 2 == 0 {
                assert!(b < 0.5 * lit, "under solid cell ({i}, {j}): {b} vs lit {lit}");
                dark += 1;
            } else {
                assert!(b > 0.85 * lit, "under cut-away cell ({i}, {j}): {b} vs lit {lit}");
                light += 1;
            }
        }
    }
    assert_eq!((dark, light), (8, 8));
    // The measuring view and the ray-traced truth, which samples the same mask, agree.
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let frame = render_debug_frame(&gpu, &mut renderer, &mut app, SIZE, SIZE).unwrap();
    drop((renderer, gpu));
    let truth = truth::truth_of(&mut app.world, &frame, truth::SizeOverride::default(), 0);
    let on_ground = |i: usize| frame.covered(i) && frame.position[i].y.abs() < 1e-3;
    let tally = metrics::tally(&frame, &truth[0], 0, on_ground);
    let truly_dark = (0..truth[0].len()).filter(|&i| on_ground(i) && truth[0][i].is_some_and(|t| !t.lit)).count();
    let truly_lit_under = (0..truth[0].len())
        .filter(|&i| on_ground(i) && frame.position[i].x.abs() < 1.0 && frame.position[i].z.abs() < 1.0)
        .filter(|&i| truth[0][i].is_some_and(|t| t.lit))
        .count();
    let wrong = tally.false_shadow + tally.false_lit;
    assert!(truly_dark > 300 && truly_lit_under > 300, "{truly_dark} dark, {truly_lit_under} lit under the quad");
    assert!(wrong * 20 < truly_dark as u64, "{wrong} pixels wrong of a {truly_dark}-pixel shadow");
}

#[test]
fn double_sided_surfaces_are_drawn_from_behind_with_their_normal_turned() {
    // The quad faces +Z; the camera looks at it from -Z.
    let behind = |double_sided: bool, sun: Vec3| {
        let mut app = scene(false, sun, Vec3::new(0.0, 1.5, -4.0), Vec3::new(0.0, 1.5, 0.0));
        let mut material = white();
        material["doubleSided"] = json!(double_sided);
        place(&mut app, &quad_glb(material, None), Transform::from_xyz(0.0, 1.5, 0.0));
        let image = render(&mut app, 0.0);
        rgb(&mut app, &image, Vec3::new(0.2, 1.6, 0.0))
    };
    let single = behind(false, Vec3::Z);
    assert!(single[2] > single[0] + 40.0, "a one-sided quad seen from behind is not drawn: sky {single:?}");
    // Lit from the camera's side, the back face is bright: its normal was turned to face it.
    let lit = behind(true, Vec3::Z);
    let unlit = behind(true, Vec3::NEG_Z);
    assert!((lit[0] - lit[2]).abs() < 8.0 && lit[0] > 150.0, "a double-sided quad's back, lit: {lit:?}");
    assert!(unlit[0] < 0.4 * lit[0], "its back in its own shadow side: {unlit:?} vs {lit:?}");
}

#[test]
fn blended_surfaces_are_drawn_over_what_is_behind_them() {
    let mut app = scene(false, Vec3::new(0.0, -0.3, -1.0), Vec3::new(0.0, 1.5, 4.0), Vec3::new(0.0, 1.5, 0.0));
    let glass = json!({ "alphaMode": "BLEND", "pbrMetallicRoughness": { "baseColorFactor": [1.0, 0.0, 0.0, 0.5] } });
    place(&mut app, &quad_glb(glass, None), Transform::from_xyz(0.0, 1.5, 0.0));
    // An opaque blue wall behind the glass, spawned after it: it is still drawn first.
    let wall = app.world.resource_mut::<MeshLibrary>().add(umbra::assets::cube(Vec3::new(3.0, 3.0, 0.1)));
    app.world.spawn((
        wall,
        Transform::from_xyz(0.0, 1.5, -1.0),
        Material { specular: 0.0, ..Material::color(0.0, 0.0, 1.0) },
    ));
    let image = render(&mut app, 0.0);
    let [r, _, b] = rgb(&mut app, &image, Vec3::new(0.0, 1.5, 0.0));
    assert!(r > 60.0 && b > 60.0, "red glass over a blue wall shows both: {r} {b}");
    let [r, _, b] = rgb(&mut app, &image, Vec3::new(2.0, 1.5, -0.9));
    assert!(b > 60.0 && r < 10.0, "the wall beside the glass: {r} {b}");
}

#[test]
fn a_model_with_no_size_leaves_every_other_shadow_as_it_was() {
    let path = scratch("point-model").join("point.glb");
    let mut model = common::gltf::TestModel::new();
    let same = model.add_floats(&[0.5; 36], "VEC3");
    model.json["accessors"][same]["min"] = json!([0.5, 0.5, 0.5]);
    model.json["accessors"][same]["max"] = json!([0.5, 0.5, 0.5]);
    model.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(same);
    std::fs::write(&path, model.glb()).unwrap();
    // At 2.5 s the clip has turned the column's tip but not moved its root, so a model blown up
    // by millions would reach from the middle of the scene out over every cascade.
    let frame = |model: Option<std::path::PathBuf>| {
        let mut app = App::new(Settings::default().with(|s| {
            s.scene.character = false;
            s.scene.model = model;
        }))
        .unwrap();
        render(&mut app, 2.5)
    };
    let without = frame(None);
    let with = frame(Some(path));
    let differ =
        (0..SIZE * SIZE).filter(|&i| without.pixel(i % SIZE, i / SIZE) != with.pixel(i % SIZE, i / SIZE)).count();
    assert_eq!(differ, 0, "{differ} pixels changed");
}
