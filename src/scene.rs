//! The sample scene: ground, pillars, a wall, animated cubes, a sun and two coloured spot lights.
//!
//! Everything here is a pure function of the settings, so the scene at time t is reproducible.

use crate::assets::{MeshLibrary, cube, plane};
use crate::components::*;
use crate::settings::Settings;
use bevy_ecs::prelude::*;
use glam::{Quat, Vec3};

/// The sample sun's direction of travel: high in the south-east sky.
pub const SUN_DIRECTION: Vec3 = Vec3::new(-0.45, -1.0, -0.35);

/// Spawns the whole sample scene into `world` (which must hold a [`MeshLibrary`]).
pub fn spawn_sample_scene(world: &mut World, settings: &Settings) {
    let (ground, unit_cube) = {
        let mut meshes = world.resource_mut::<MeshLibrary>();
        (meshes.add(plane(80.0)), meshes.add(cube(Vec3::splat(0.5))))
    };
    world.spawn((ground, Material::color(0.45, 0.47, 0.42), ShadowReceiver));

    let stone = Material::color(0.62, 0.58, 0.52);
    let pillars = [(-7.0, -5.0), (7.5, -4.0), (-3.0, -9.0), (5.0, 6.5)];
    for (x, z) in pillars {
        let t = Transform::from_xyz(x, 3.0, z).with_scale(Vec3::new(0.9, 6.0, 0.9));
        world.spawn((unit_cube, t, stone, ShadowCaster, ShadowReceiver));
    }
    let wall = Transform::from_xyz(1.0, 1.5, -7.0).with_scale(Vec3::new(7.0, 3.0, 0.5));
    world.spawn((unit_cube, wall, stone, ShadowCaster, ShadowReceiver));

    for i in 0..settings.cubes {
        world.spawn(animated_cube(i, settings.cubes, unit_cube));
    }

    let bias = ShadowBias { constant: settings.depth_bias, slope: settings.slope_bias, normal: settings.normal_bias };
    let sun = DirectionalLight { direction: SUN_DIRECTION.normalize(), color: Vec3::new(1.0, 0.95, 0.85), intensity: 1.0 };
    world.spawn((sun, ShadowMap::default(), bias));
    for (spot, at, target, cookie) in sample_spots() {
        let transform = Transform { translation: at, ..Default::default() }.looking_to(target - at);
        let mut light = world.spawn((spot, transform, ShadowMap::default(), bias));
        if let Some(cookie) = cookie {
            light.insert(cookie);
        }
    }

    world.spawn(default_camera());
}

/// The sample's shadowed spot lights (seed 004 keeps an array of them, each its own colour): a cool
/// light thrown through a window cookie and a warm one, each with its position and aim point.
pub fn sample_spots() -> [(SpotLight, Vec3, Vec3, Option<Cookie>); 2] {
    let spot = |color, intensity| SpotLight {
        color,
        intensity,
        range: 16.0,
        inner_angle: 16f32.to_radians(),
        outer_angle: 24f32.to_radians(),
    };
    [
        (spot(Vec3::new(0.35, 0.75, 1.0), 4.0), Vec3::new(-5.0, 7.0, 3.0), Vec3::new(-3.0, 0.0, 0.5), Some(Cookie::Window)),
        (spot(Vec3::new(1.0, 0.55, 0.25), 3.5), Vec3::new(6.0, 6.5, 4.0), Vec3::new(4.0, 0.0, 1.0), None),
    ]
}

/// The camera the sample starts with: south of the scene, looking down at the ring of cubes.
pub fn default_camera() -> (Camera, FlyCamera, Transform) {
    let eye = Vec3::new(2.0, 7.5, 17.0);
    let to = Vec3::new(-0.5, 1.0, 0.0) - eye;
    let fly = FlyCamera::new((-to.x).atan2(-to.z), (to.y / to.length()).asin());
    (Camera::default(), fly, Transform { translation: eye, rotation: fly.rotation(), ..Default::default() })
}

/// Cube `i` of `n`: placed on a ring, spinning and bobbing at its own rates (as in seed 000).
fn animated_cube(i: u32, n: u32, mesh: Mesh) -> impl Bundle {
    // The golden ratio spreads rates and phases so no two cubes move in step.
    let g = (i as f32 * 0.618_034).fract();
    let angle = i as f32 / n.max(1) as f32 * std::f32::consts::TAU;
    let radius = 4.0 + 2.5 * (i % 2) as f32;
    let size = 0.7 + 0.6 * g;
    let base_y = 1.2 + 1.5 * ((i * 7 % 5) as f32 / 4.0);
    let axis = Vec3::new(g - 0.5, 1.0, (1.0 - g) * 0.6).normalize();
    let palette = [
        Vec3::new(0.80, 0.25, 0.20),
        Vec3::new(0.90, 0.65, 0.15),
        Vec3::new(0.25, 0.60, 0.30),
        Vec3::new(0.25, 0.40, 0.85),
        Vec3::new(0.70, 0.30, 0.70),
    ];
    let c = palette[i as usize % palette.len()];
    (
        mesh,
        Transform::from_xyz(radius * angle.cos(), base_y, radius * angle.sin()).with_scale(Vec3::splat(size)),
        Material { base_color: c, specular: 0.5, shininess: 48.0 },
        Spin { axis, rate: 0.4 + 1.2 * g, base: Quat::from_rotation_y(angle) },
        Bob { base_y, amplitude: 0.3 + 0.4 * g, frequency: 0.8 + 1.1 * (1.0 - g), phase: angle },
        ShadowCaster,
        ShadowReceiver,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_scene_has_what_the_card_asks_for() {
        let mut world = World::new();
        world.insert_resource(MeshLibrary::default());
        spawn_sample_scene(&mut world, &Settings::default());
        let animated = world.query_filtered::<(), (With<Spin>, With<Bob>)>().iter(&world).count();
        assert!(animated >= 8);
        assert_eq!(world.query::<&DirectionalLight>().iter(&world).count(), 1);
        assert_eq!(world.query::<(&SpotLight, &ShadowMap)>().iter(&world).count(), 2);
        assert_eq!(world.query::<(&SpotLight, &Cookie)>().iter(&world).count(), 1);
        assert_eq!(world.query::<&Camera>().iter(&world).count(), 1);
    }

    #[test]
    fn default_camera_looks_at_the_scene_centre() {
        let (_, _, t) = default_camera();
        let to_centre = (Vec3::new(-0.5, 1.0, 0.0) - t.translation).normalize();
        assert!(t.forward().dot(to_centre) > 0.9999);
    }
}
