//! Dirty flags on a World: which lights must redraw their shadow maps after what changed.

use glam::Vec3;
use umbra::assets::{MeshLibrary, cube, plane};
use umbra::components::*;
use umbra::shadow::{Aabb, intersects_clip_volume};
use umbra::{App, Settings};

struct Scene {
    app: App,
    sun: bevy_ecs::entity::Entity,
    left_spot: bevy_ecs::entity::Entity,
    right_spot: bevy_ecs::entity::Entity,
    left_cube: bevy_ecs::entity::Entity,
}

fn spot_at(x: f32) -> (SpotLight, Transform, ShadowMap) {
    let spot = SpotLight {
        color: Vec3::ONE,
        intensity: 2.0,
        range: 12.0,
        inner_angle: 0.3,
        outer_angle: 0.4,
        ..Default::default()
    };
    (spot, Transform::from_xyz(x, 5.0, -6.0).looking_to(Vec3::NEG_Y), ShadowMap::default())
}

/// Ground, a cube under each of two spot lights, a sun with three cascades and a camera; updated
/// twice so everything has settled.
fn scene() -> Scene {
    let mut app = App::empty(Settings::default().with(|s| s.cascade.cascades = 3)).unwrap();
    let (ground, block) = {
        let mut meshes = app.world.resource_mut::<MeshLibrary>();
        (meshes.add(plane(40.0)), meshes.add(cube(Vec3::splat(0.5))))
    };
    app.world.spawn((ground, ShadowReceiver));
    let left_cube = app.world.spawn((block, Transform::from_xyz(-4.0, 0.5, -6.0), ShadowCaster)).id();
    app.world.spawn((block, Transform::from_xyz(5.0, 0.5, -6.0), ShadowCaster));
    let sun = DirectionalLight {
        direction: Vec3::new(-0.3, -1.0, -0.2),
        color: Vec3::ONE,
        intensity: 1.0,
        ..Default::default()
    };
    let sun = app.world.spawn((sun, ShadowMap::default())).id();
    let left_spot = app.world.spawn(spot_at(-4.0)).id();
    let right_spot = app.world.spawn(spot_at(5.0)).id();
    let eye = Vec3::new(0.0, 6.0, 12.0);
    app.world.spawn((Camera::default(), Transform::from_xyz(eye.x, eye.y, eye.z).looking_to(-eye)));
    app.set_time(0.0);
    app.set_time(0.0);
    Scene { app, sun, left_spot, right_spot, left_cube }
}

fn layers(s: &Scene, light: bevy_ecs::entity::Entity) -> Vec<ShadowLayer> {
    s.app.world.get::<ShadowMap>(light).unwrap().layers.clone()
}

fn dirty(s: &Scene, light: bevy_ecs::entity::Entity) -> bool {
    s.app.world.get::<ShadowMap>(light).unwrap().dirty()
}

#[test]
fn new_lights_are_dirty_and_a_still_frame_dirties_nothing() {
    let mut app = scene().app;
    let mut fresh = App::empty(Settings::default()).unwrap();
    fresh.world.spawn(spot_at(0.0));
    fresh.set_time(0.0);
    let all_dirty = fresh.world.query::<&ShadowMap>().iter(&fresh.world).all(|m| m.dirty());
    assert!(all_dirty, "a light seen for the first time must be drawn");
    app.set_time(0.0);
    let maps: Vec<ShadowMap> = app.world.query::<&ShadowMap>().iter(&app.world).cloned().collect();
    assert_eq!(maps.iter().map(|m| m.layers.len()).sum::<usize>(), 5, "3 cascades and 2 spots");
    assert!(maps.iter().all(|m| !m.dirty()), "nothing changed, so nothing is dirty");
}

#[test]
fn moving_one_cube_dirties_exactly_the_layers_whose_volume_holds_it() {
    let mut s = scene();
    let before = s.app.world.get::<WorldBounds>(s.left_cube).unwrap().0;
    let versions: Vec<u64> =
        [s.sun, s.left_spot, s.right_spot].iter().flat_map(|l| layers(&s, *l)).map(|l| l.version).collect();
    s.app.world.get_mut::<Transform>(s.left_cube).unwrap().translation.x += 0.2;
    s.app.set_time(0.0);
    let after = s.app.world.get::<WorldBounds>(s.left_cube).unwrap().0;
    let holds = |l: &ShadowLayer, b: &Aabb| intersects_clip_volume(&l.clip_from_world, b);
    let all: Vec<ShadowLayer> = [s.sun, s.left_spot, s.right_spot].iter().flat_map(|l| layers(&s, *l)).collect();
    for (i, (layer, old_version)) in all.iter().zip(versions).enumerate() {
        let expected = holds(layer, &before) || holds(layer, &after);
        assert_eq!(layer.dirty, expected, "layer {i}: holds the cube = {expected}");
        assert_eq!(layer.version != old_version, expected, "a dirty layer gets a new version, a clean one keeps it");
    }
    assert!(dirty(&s, s.left_spot), "the spot over the cube");
    assert!(!dirty(&s, s.right_spot), "the other spot does not see the cube");
    assert!(layers(&s, s.sun).iter().any(|l| l.dirty), "some cascade holds the cube");
    assert!(layers(&s, s.sun).iter().any(|l| !l.dirty), "not every cascade does");
}

#[test]
fn a_lights_bias_or_method_dirties_no_map() {
    // Both are applied when the map is sampled; the map itself stays as it was.
    let mut s = scene();
    let bias = ShadowBias { constant: 2.5, slope: 0.0, normal: 0.0, scale: 0.0, receiver_plane: true };
    s.app.world.entity_mut(s.right_spot).insert((bias, umbra::components::ShadowMethod::Pcf5));
    s.app.set_time(0.0);
    assert!(!dirty(&s, s.right_spot) && !dirty(&s, s.left_spot) && !dirty(&s, s.sun));
}

#[test]
fn adding_or_removing_a_caster_dirties_the_lights_that_see_it() {
    let mut s = scene();
    let block = s.app.world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.3)));
    let added = s.app.world.spawn((block, Transform::from_xyz(5.0, 1.5, -5.5), ShadowCaster)).id();
    s.app.set_time(0.0);
    assert!(dirty(&s, s.right_spot) && !dirty(&s, s.left_spot), "added under the right spot");
    s.app.set_time(0.0);
    assert!(!dirty(&s, s.right_spot));
    s.app.world.despawn(added);
    s.app.set_time(0.0);
    assert!(dirty(&s, s.right_spot) && !dirty(&s, s.left_spot), "removed from under the right spot");
}

#[test]
fn moving_a_light_or_resizing_the_maps_dirties_it() {
    let mut s = scene();
    s.app.world.get_mut::<Transform>(s.left_spot).unwrap().translation.y += 0.5;
    s.app.set_time(0.0);
    assert!(dirty(&s, s.left_spot) && !dirty(&s, s.right_spot));
    s.app.world.resource_mut::<umbra::settings::MapSettings>().shadow_map_size = 1024;
    s.app.set_time(0.0);
    assert!(dirty(&s, s.left_spot) && dirty(&s, s.right_spot) && dirty(&s, s.sun));
}

#[test]
fn a_stable_cascade_stays_clean_while_the_camera_creeps_and_a_tight_one_does_not() {
    for (mode, expect_dirty) in [(umbra::shadow::FitMode::Stable, false), (umbra::shadow::FitMode::Tight, true)] {
        let mut s = scene();
        s.app.world.resource_mut::<umbra::settings::CascadeSettings>().fit_mode = mode;
        s.app.set_time(0.0);
        s.app.set_time(0.0);
        let texel = layers(&s, s.sun)[2].texel.x;
        let mut dirtied = 0;
        for _ in 0..10 {
            let mut q = s.app.world.query_filtered::<&mut Transform, bevy_ecs::query::With<Camera>>();
            q.single_mut(&mut s.app.world).unwrap().translation.x += texel * 0.01;
            s.app.set_time(0.0);
            dirtied += layers(&s, s.sun)[2].dirty as u32;
        }
        // A hundredth of a texel per step: the stable cascade may snap once at most.
        if expect_dirty {
            assert_eq!(dirtied, 10, "{mode:?}");
        } else {
            assert!(dirtied <= 1, "{mode:?}: dirty {dirtied} times of 10");
        }
    }
}
