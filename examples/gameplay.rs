//! Adding a gameplay system without touching umbra: a cube that follows the camera.
//!
//! `cargo run --example gameplay` plays it in a window (or renders `gameplay.png` without one).

use bevy_ecs::prelude::*;
use glam::Vec3;
use umbra::assets::{MeshLibrary, cube};
use umbra::components::{Camera, Material, ShadowCaster, ShadowReceiver, Transform};
use umbra::{App, Settings};

/// Marks the cube that follows the camera.
#[derive(Component)]
struct Follower;

/// Keeps the follower 4 m ahead of the camera and 1.5 m lower, so it casts a shadow you can watch.
fn follow_camera(
    camera: Query<&Transform, (With<Camera>, Without<Follower>)>,
    mut followers: Query<&mut Transform, With<Follower>>,
) {
    let Some(eye) = camera.iter().next() else { return };
    for mut t in &mut followers {
        t.translation = eye.translation + eye.forward() * 4.0 - Vec3::Y * 1.5;
    }
}

fn main() -> anyhow::Result<()> {
    let mut app = App::new(Settings::default())?;
    let mesh = app.world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.4)));
    app.world.spawn((mesh, Material::color(0.95, 0.85, 0.2), Follower, ShadowCaster, ShadowReceiver));
    app.add_systems(follow_camera);
    umbra::play::play_or_render(app, None, umbra::ui::Lab::default(), "gameplay.png".as_ref())?;
    Ok(())
}
