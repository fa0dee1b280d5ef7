//! Many lights: every light of a scene is shaded, through the clustered light lists, wherever
//! the ray-traced truth says its light arrives; shadowed lights the shadow-map array cannot hold
//! are lit without their shadow, and the user is told which.

mod common;

use common::*;
use glam::Vec3;
use umbra::assets::{MeshLibrary, plane};
use umbra::components::*;
use umbra::eval::truth;
use umbra::light::clusters::CLUSTERS;
use umbra::render::{HEADLESS_FORMAT, Renderer, extract, render_debug_frame, render_headless};
use umbra::{App, Settings};

/// Side of the measured frames: small, since every light needs its own column of the truth.
const SIDE: u32 = 96;

/// A ground seen from straight above, lit by `n` × `n` small point lights in a grid over it.
fn lamp_field(n: usize, shadowed: bool) -> App {
    let mut app = App::empty(Settings::default()).unwrap();
    let ground = app.world.resource_mut::<MeshLibrary>().add(plane(40.0));
    let grey = Material { specular: 0.0, shininess: 1.0, ..Material::color(0.6, 0.6, 0.6) };
    app.world.spawn((ground, Transform::default(), grey, ShadowReceiver));
    let spacing = 32.0 / n as f32;
    for i in 0..n * n {
        let (x, z) = ((i % n) as f32, (i / n) as f32);
        let at = Transform::from_xyz(-16.0 + spacing * (x + 0.5), 0.4, -16.0 + spacing * (z + 0.5));
        let lamp = PointLight { range: 1.2 * spacing, intensity: 2.0, ..Default::default() };
        let lamp = app.world.spawn((lamp, at)).id();
        if shadowed {
            app.world.entity_mut(lamp).insert(ShadowMap::default());
        }
    }
    app.world.spawn(camera_at(Vec3::new(0.0, 30.0, 0.01), Vec3::ZERO));
    app.resize(SIDE, SIDE);
    app
}

#[test]
fn a_thousand_lights_each_reach_just_where_the_truth_says() {
    let mut app = lamp_field(32, false);
    app.set_time(0.0);
    let data = extract(&mut app.world);
    assert_eq!(data.lights.len(), 1024, "every light is lit");
    // The lists are short: a cluster holds the few lights round it, not the scene's thousand.
    let listed = data.grid.indices.len() as f32 / CLUSTERS as f32;
    assert!(listed < 8.0, "{listed} lights per cluster on average");

    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let frame = render_debug_frame(&gpu, &mut renderer, &mut app, SIDE, SIDE).unwrap();
    drop(gpu);
    let truth = truth::truth_of(&mut app.world, &frame, truth::SizeOverride::default(), 0);
    assert_eq!(frame.visibility.len(), 1024);
    let (mut reached, mut disagree, mut lights_seen) = (0, 0, 0);
    for (light, (truth, rendered)) in truth.iter().zip(&frame.visibility).enumerate() {
        let mine: Vec<usize> = (0..truth.len()).filter(|&i| truth[i].is_some()).collect();
        let shaded = mine.iter().filter(|&&i| rendered[i] >= 0.0).count();
        // Where it truly reaches, it is shaded (a light left out of its clusters reports -1),
        // and nowhere else: a pixel it cannot reach is left alone.
        let strays = (0..truth.len()).filter(|&i| truth[i].is_none() && rendered[i] >= 0.0).count();
        if mine.len() >= 5 {
            lights_seen += 1;
            assert!(shaded * 10 >= mine.len() * 9, "light {light}: {shaded} of its {} pixels shaded", mine.len());
        }
        assert!(mine.iter().all(|&i| rendered[i] < 0.0 || rendered[i] > 0.999), "light {light} casts no shadow");
        (reached, disagree) = (reached + mine.len(), disagree + (mine.len() - shaded) + strays);
    }
    eprintln!("{lights_seen} lights seen, {reached} pixels reached, {disagree} disagree with the truth");
    assert!(lights_seen > 900, "{lights_seen} lights reach five pixels or more");
    assert!(disagree * 200 <= reached, "{disagree} of {reached} disagree (only at the edge of a light's range)");
}

#[test]
fn shadowed_lights_the_array_cannot_hold_are_lit_and_named() {
    // 25 point lights with shadows need 150 layers; the array holds 96 (sixteen cubes).
    let mut app = lamp_field(5, true);
    app.resize(SIZE, SIZE);
    app.set_time(0.0);
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    render_headless(&gpu, &mut renderer, &mut app, SIZE, SIZE).unwrap();
    let notices = app.take_notices();
    let told: Vec<&String> = notices.iter().filter(|n| n.contains("lit without their shadow")).collect();
    assert_eq!(told.len(), 1, "{notices:?}");
    assert!(told[0].starts_with("9 lights") && told[0].contains("point 17") && told[0].contains("96 layers"), "{told:?}");
    let data = extract(&mut app.world);
    let shadowed = data.lights.iter().filter(|l| l.layer_count > 0).count();
    assert_eq!((data.lights.len(), shadowed), (25, 16), "all lit, sixteen with their cubes");
    // Said once, not every frame.
    render_headless(&gpu, &mut renderer, &mut app, SIZE, SIZE).unwrap();
    assert!(app.take_notices().iter().all(|n| !n.contains("lit without")));
}
