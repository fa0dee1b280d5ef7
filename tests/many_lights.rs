//! Many lights: every light of a scene is shaded, through the clustered light lists, wherever
//! the ray-traced truth says its light arrives; shadowed lights the shadow-map array cannot hold
//! are lit without their shadow, and the user is told which.

mod common;

use bevy_ecs::prelude::Entity;
use common::*;
use glam::Vec3;
use umbra::assets::{MeshLibrary, plane};
use umbra::components::*;
use umbra::eval::truth;
use umbra::light::clusters::CLUSTERS;
use umbra::render::{Gpu, HEADLESS_FORMAT, Renderer, ShadowStats, extract, render_debug_frame, render_headless};
use umbra::settings::LightMaps;
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
    let data = extract(&app.world);
    assert_eq!(data.lights.len(), 1024, "every light is lit");
    // The lists are short: a cluster holds the few lights round it, not the scene's thousand.
    let listed = data.grid.indices.len() as f32 / CLUSTERS as f32;
    assert!(listed < 8.0, "{listed} lights per cluster on average");

    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let frame = render_debug_frame(&gpu, &mut renderer, &mut app, SIDE, SIDE).unwrap();
    drop((renderer, gpu));
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
fn shadowed_lamps_share_the_atlas_and_those_it_cannot_hold_are_lit_and_named() {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    // 25 shadowed lamps: 150 cube faces, all in the default atlas.
    let mut app = lamp_field(5, true);
    app.resize(SIZE, SIZE);
    app.set_time(0.0);
    render_headless(&gpu, &mut renderer, &mut app, SIZE, SIZE).unwrap();
    assert!(app.take_notices().iter().all(|n| !n.contains("lit without")));
    let data = extract(&app.world);
    assert!(data.lights.iter().all(|l| l.layer_count == 6), "every lamp keeps its cube");

    // 900 in the least memory: 5,400 faces of 32² at the least, and the atlas holds 4,096 of
    // them: the lamps past them are named.
    let mut app = lamp_field(30, true);
    app.world.resource_mut::<umbra::settings::MapSettings>().shadow_memory = 16;
    app.resize(SIZE, SIZE);
    app.set_time(0.0);
    render_headless(&gpu, &mut renderer, &mut app, SIZE, SIZE).unwrap();
    let notices = app.take_notices();
    let told: Vec<&String> = notices.iter().filter(|n| n.contains("lit without their shadow")).collect();
    assert_eq!(told.len(), 1, "{notices:?}");
    let atlas = app.world.resource::<umbra::systems::ShadowAtlas>().shape;
    let fit = atlas.texels() / (32 * 32) / 6;
    let named = format!("{} lights", 900 - fit);
    assert!(told[0].starts_with(&named) && told[0].contains("--shadow-memory"), "{told:?}, {fit} fit {atlas:?}");
    // Said once, not every frame.
    render_headless(&gpu, &mut renderer, &mut app, SIZE, SIZE).unwrap();
    assert!(app.take_notices().iter().all(|n| !n.contains("lit without")));
}

#[test]
fn a_still_field_of_shadowed_lamps_draws_nothing_and_a_moving_cube_only_the_lamps_it_passes() {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    // 64 shadowed lamps, and a cube that will move under one of them.
    let mut app = lamp_field(8, true);
    let block = app.world.resource_mut::<MeshLibrary>().add(umbra::assets::cube(Vec3::splat(0.5)));
    let at = Transform::from_xyz(-12.0, 0.2, -14.0).with_scale(Vec3::splat(0.4));
    let cube = app.world.spawn((block, at, Material::color(0.8, 0.2, 0.2), ShadowCaster, ShadowReceiver)).id();
    app.resize(SIZE, SIZE);
    let mut frame = |app: &mut App| {
        app.step_held();
        render_headless(&gpu, &mut renderer, app, SIZE, SIZE).unwrap();
        app.world.resource::<ShadowStats>().clone()
    };
    let first = frame(&mut app);
    assert_eq!(first.drawn(), 64 * 6, "every face drawn once: {first}");
    let still = frame(&mut app);
    assert_eq!((still.drawn(), still.kept()), (0, 64 * 6), "a still scene draws no tile");
    app.world.get_mut::<Transform>(cube).unwrap().translation.x += 0.1;
    let moved = frame(&mut app);
    let lamps = moved.lights.iter().filter(|l| l.drawn > 0).count();
    assert!((1..=4).contains(&lamps), "only the lamps round the cube: {moved}");
    assert!(moved.drawn() < 24, "only faces the cube is in are drawn: {moved}");
}

/// Share of the pixels `light` truly reaches where the frame's lit-or-shadowed disagrees with the
/// ray-traced truth.
fn misclassified(truth: &[Option<truth::Truth>], rendered: &[f32]) -> f32 {
    let reached: Vec<(bool, f32)> = truth.iter().zip(rendered).filter_map(|(t, &r)| t.map(|t| (t.lit, r))).collect();
    let wrong = reached.iter().filter(|&&(lit, r)| lit != (r > 0.5)).count();
    wrong as f32 / reached.len().max(1) as f32
}

#[test]
fn a_starved_budget_draws_one_map_a_frame_and_the_other_keeps_its_old_shadow_until_its_turn() {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    // A block on the ground between two spots, seen from above.
    let mut app = App::empty(Settings::default()).unwrap();
    let ground = app.world.resource_mut::<MeshLibrary>().add(plane(20.0));
    app.world.spawn((ground, Transform::default(), Material::color(0.6, 0.6, 0.6), ShadowReceiver));
    let block = app.world.resource_mut::<MeshLibrary>().add(umbra::assets::cube(Vec3::splat(0.5)));
    let at = Transform::from_xyz(0.0, 0.5, 0.0);
    let cube = app.world.spawn((block, at, Material::color(0.8, 0.2, 0.2), ShadowCaster, ShadowReceiver)).id();
    for x in [-3.0, 3.0] {
        let spot = SpotLight { range: 15.0, intensity: 4.0, inner_angle: 0.6, outer_angle: 0.7, ..Default::default() };
        let from = Vec3::new(x, 5.0, 0.0);
        app.world.spawn((spot, Transform::from_translation(from).looking_to(-from), ShadowMap::default()));
    }
    app.world.spawn(camera_at(Vec3::new(0.0, 12.0, 0.01), Vec3::ZERO));
    app.resize(SIDE, SIDE);
    let mut seen = Vec::new();
    let mut frame = |app: &mut App| {
        app.step_held();
        let frame = render_debug_frame(&gpu, &mut renderer, app, SIDE, SIDE).unwrap();
        let truth = truth::truth_of(&mut app.world, &frame, truth::SizeOverride::default(), 0);
        let wrong: Vec<f32> = truth.iter().zip(&frame.visibility).map(|(t, r)| misclassified(t, r)).collect();
        seen.push(frame.visibility);
        (app.world.resource::<ShadowStats>().clone(), wrong)
    };
    let (first, wrong) = frame(&mut app);
    assert_eq!(first.drawn(), 2, "new tiles are drawn whatever the budget: {first}");
    assert!(wrong.iter().all(|&w| w < 0.01), "both right to begin with: {wrong:?}");
    // A budget for one spot's map a frame; the block moves in both spots' views.
    let side = |app: &mut App| app.world.query::<&ShadowMap>().iter(&app.world).map(|m| m.resolution).max().unwrap();
    let side = side(&mut app);
    app.world.resource_mut::<umbra::settings::MapSettings>().shadow_updates = side * side;
    app.world.get_mut::<Transform>(cube).unwrap().translation.z += 1.5;
    let (moved, wrong) = frame(&mut app);
    assert_eq!((moved.drawn(), moved.stale()), (1, 1), "one drawn, one waits: {moved}");
    assert!(moved.texels <= u64::from(side * side), "{} texels drawn", moved.texels);
    let waiting = moved.lights.iter().position(|l| l.stale > 0).unwrap();
    let drawn = 1 - waiting;
    // The waiting spot's shadow is where the block was: wrong where it left and where it came.
    assert!(wrong[drawn] < 0.01 && wrong[waiting] > 0.02, "{wrong:?}");
    eprintln!("while it waits: {:.1} % of the waiting spot's pixels misclassified", wrong[waiting] * 100.0);
    // Its turn comes the next frame, and then it is right.
    let (caught_up, wrong) = frame(&mut app);
    assert_eq!((caught_up.drawn(), caught_up.stale()), (1, 0), "{caught_up}");
    assert!(wrong.iter().all(|&w| w < 0.01), "{wrong:?}");

    // Both spots swing: the one left waiting is sampled with the projection its map was drawn
    // with, so its shadow stays as it was (read with the new one, the old map would land askew).
    let mut spots = app.world.query_filtered::<&mut Transform, bevy_ecs::query::With<SpotLight>>();
    for mut at in spots.iter_mut(&mut app.world) {
        at.translation.z += 1.0;
        *at = at.looking_to(-at.translation);
    }
    let (swung, _) = frame(&mut app);
    let waiting = swung.lights.iter().position(|l| l.stale > 0).expect("one waits");
    let (before, now) = (&seen[seen.len() - 2][waiting], &seen[seen.len() - 1][waiting]);
    let both: Vec<(f32, f32)> =
        before.iter().zip(now).filter(|(b, n)| **b >= 0.0 && **n >= 0.0).map(|(b, n)| (*b, *n)).collect();
    let changed = both.iter().filter(|(b, n)| (b > &0.5) != (n > &0.5)).count();
    assert!(changed * 200 <= both.len(), "{changed} of {} pixels changed while it waited", both.len());
}

/// The lamp field of 64 shadowed lamps, paged where `paged`, and a cube between the first two
/// lamps (its entity), level with them.
fn paged_field(paged: bool) -> (App, Entity) {
    let mut app = lamp_field(8, true);
    let light_maps = if paged { LightMaps::Virtual } else { LightMaps::Atlas };
    app.set_settings(&app.settings().with(|s| s.maps.light_maps = light_maps)).unwrap();
    let block = app.world.resource_mut::<MeshLibrary>().add(umbra::assets::cube(Vec3::splat(0.5)));
    let at = Transform::from_xyz(-12.0, 0.2, -14.0).with_scale(Vec3::splat(0.4));
    let cube = app.world.spawn((block, at, Material::color(0.8, 0.2, 0.2), ShadowCaster, ShadowReceiver)).id();
    (app, cube)
}

/// The GPU, where it runs compute shaders; none (SKIPPED said) where it cannot mark pages.
fn marking_gpu() -> Option<std::sync::MutexGuard<'static, Gpu>> {
    let gpu = gpu();
    if !gpu.computes() {
        eprintln!("SKIPPED: this device runs no compute shaders, so no page is marked");
        return None;
    }
    Some(gpu)
}

/// Renders `app` a frame at a time as a window would (nothing drawn first), each marking of
/// pages read back before the next frame, and hands each frame's stats to `each` until it says
/// stop, 16 frames at most; false if it never did.
fn frames(
    gpu: &Gpu,
    renderer: &mut Renderer,
    app: &mut App,
    mut each: impl FnMut(&mut App, &ShadowStats) -> bool,
) -> bool {
    let texture = gpu.target("frame", (SIDE, SIDE), HEADLESS_FORMAT).unwrap();
    let view = texture.create_view(&Default::default());
    for _ in 0..16 {
        app.hear(renderer.news());
        app.step_held();
        renderer.render(gpu, &app.world, &view, SIDE, SIDE).unwrap();
        renderer.wait_for_samples(gpu);
        app.hear(renderer.news());
        let stats = app.world.resource::<ShadowStats>().clone();
        if each(app, &stats) {
            return true;
        }
    }
    false
}

/// Frames of `app` until two in a row draw nothing: the lights that drew in them (in light
/// order).
fn settle(gpu: &Gpu, renderer: &mut Renderer, app: &mut App) -> std::collections::BTreeSet<usize> {
    let (mut drew, mut idle) = (std::collections::BTreeSet::new(), 0);
    let settled = frames(gpu, renderer, app, |_, stats| {
        drew.extend((0..stats.lights.len()).filter(|&i| stats.lights[i].drawn > 0));
        idle = if stats.drawn() == 0 { idle + 1 } else { 0 };
        idle == 2
    });
    assert!(settled, "no two frames in a row drew nothing: {}", app.world.resource::<ShadowStats>());
    drew
}

#[test]
fn a_still_field_of_paged_lamps_draws_no_page_and_a_bobbing_lamp_or_a_moving_cube_only_the_pages_they_touch() {
    let Some(gpu) = marking_gpu() else { return };
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let (mut app, cube) = paged_field(true);
    assert_eq!(settle(&gpu, &mut renderer, &mut app).len(), 64, "every lamp draws its pages");
    let still = app.world.resource::<ShadowStats>();
    assert!(still.pages.kept >= 64 && still.pages.drawn == 0, "a still field keeps every page: {still}");
    let lamps: Vec<_> = umbra::light::light_list(&app.world).iter().map(|l| l.entity).collect();
    let bob = 27;
    app.world.get_mut::<Transform>(lamps[bob]).unwrap().translation.y += 0.05;
    assert_eq!(settle(&gpu, &mut renderer, &mut app), [bob].into(), "only the bobbing lamp draws");
    // The planes through the lamps of its row cut the cube: a box cut so once counted as
    // crossing every page of the faces either side, however far past a lamp's reach it lay.
    app.world.get_mut::<Transform>(cube).unwrap().translation.x += 0.1;
    let near_cube = settle(&gpu, &mut renderer, &mut app);
    assert!((1..=4).contains(&near_cube.len()), "only the lamps round the cube draw: {near_cube:?}");
}

#[test]
fn a_quarter_of_the_lamps_bobbing_redraw_fewer_texels_on_pages_than_in_the_atlas() {
    let Some(gpu) = marking_gpu() else { return };
    let texels = |paged: bool| {
        let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
        let (mut app, _) = paged_field(paged);
        settle(&gpu, &mut renderer, &mut app);
        let lamps: Vec<_> = umbra::light::light_list(&app.world).iter().map(|l| l.entity).collect();
        let (mut texels, mut frame) = (0, 0);
        frames(&gpu, &mut renderer, &mut app, |app, stats| {
            texels += if frame > 0 { stats.texels } else { 0 };
            for lamp in lamps.iter().step_by(4) {
                app.world.get_mut::<Transform>(*lamp).unwrap().translation.y +=
                    if frame % 2 == 0 { 0.05 } else { -0.05 };
            }
            frame += 1;
            frame == 9
        });
        texels / 8
    };
    let (atlas, pages) = (texels(false), texels(true));
    eprintln!("16 of 64 lamps bobbing: {atlas} texels a frame drawn in the atlas, {pages} on pages");
    // Each bobbing lamp redraws its coarse cube (6 x 128²) and its pages; the atlas, its six
    // faces whole. The target is a third of the atlas's; this field gives about half.
    assert!(pages < atlas, "{pages} texels on pages against {atlas} in the atlas");
}
