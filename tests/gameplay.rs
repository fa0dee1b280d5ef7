//! A user's gameplay system runs in the update schedule without changes to umbra.

use bevy_ecs::prelude::*;
use glam::Vec3;
use umbra::assets::{MeshLibrary, cube};
use umbra::components::{Camera, ShadowCaster, Transform, WorldBounds};
use umbra::{App, Settings};

#[derive(Component)]
struct Follower;

fn follow_camera(
    camera: Query<&Transform, With<Camera>>,
    mut followers: Query<&mut Transform, (With<Follower>, Without<Camera>)>,
) {
    let eye = camera.iter().next().unwrap();
    for mut t in &mut followers {
        t.translation = eye.translation + eye.forward() * 4.0;
    }
}

#[test]
fn a_gameplay_system_moves_a_caster_before_the_lights_are_fitted() {
    let mut app = App::new(Settings::default()).unwrap();
    let mesh = app.world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
    let e = app.world.spawn((mesh, Follower, ShadowCaster)).id();
    app.add_systems(follow_camera);
    app.step();
    let eye = *app.world.query_filtered::<&Transform, With<Camera>>().single(&app.world).unwrap();
    let want = eye.translation + eye.forward() * 4.0;
    assert!((app.world.get::<Transform>(e).unwrap().translation - want).length() < 1e-5);
    // The bounds were recomputed in the same step, after the gameplay system moved the cube.
    let bounds = app.world.get::<WorldBounds>(e).unwrap().0;
    assert!((bounds.center() - want).length() < 1e-5, "{bounds:?}");
}

#[test]
fn steps_are_a_pure_function_of_time() {
    let mut a = App::new(Settings::default()).unwrap();
    for _ in 0..90 {
        a.step();
    }
    let mut b = App::new(Settings::default()).unwrap();
    b.set_time(90.0 * Settings::default().scene.dt as f64);
    let poses = |app: &mut App| app.world.query::<&Transform>().iter(&app.world).copied().collect::<Vec<_>>();
    assert_eq!(poses(&mut a), poses(&mut b));
}
