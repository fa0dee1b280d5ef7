//! Light matrices: world bounds of casters, then each shadowed light's projection.

use crate::assets::MeshLibrary;
use crate::components::{
    Camera, DirectionalLight, Mesh, ShadowCaster, ShadowMap, SpotLight, Transform, Viewport, WorldBounds,
};
use crate::settings::Settings;
use crate::shadow::{Aabb, fit_directional, frustum_corners, spot_projection};
use bevy_ecs::prelude::*;

/// Recomputes the world bounds of every mesh entity that moved or changed mesh.
pub fn update_bounds(
    meshes: Res<MeshLibrary>,
    mut query: Query<(&Transform, &Mesh, &mut WorldBounds), Or<(Changed<Transform>, Changed<Mesh>)>>,
) {
    for (transform, mesh, mut bounds) in &mut query {
        let local = meshes.get(*mesh).map_or(Aabb::EMPTY, |m| m.bounds);
        bounds.0 = if local.is_empty() { local } else { local.transformed(&transform.matrix()) };
    }
}

/// Assigns shadow-map layers and recomputes every shadowed light's view-projection.
///
/// The sun's box is fitted to the camera's view out to the shadow distance and stretched towards
/// the light to hold the casters in front of it; a spot light's frustum follows its cone.
pub fn update_light_matrices(
    settings: Res<Settings>,
    viewport: Res<Viewport>,
    cameras: Query<(&Camera, &Transform)>,
    casters: Query<&WorldBounds, With<ShadowCaster>>,
    mut suns: Query<(&DirectionalLight, &mut ShadowMap), Without<SpotLight>>,
    mut spots: Query<(&SpotLight, &Transform, &mut ShadowMap), Without<DirectionalLight>>,
) {
    let size = settings.shadow_map_size;
    let mut layer = 0;
    if let Some((camera, transform)) = cameras.iter().next() {
        let view_camera = Camera { far: camera.far.min(settings.shadow_distance).max(camera.near * 2.0), ..*camera };
        let corners = frustum_corners(&view_camera.view_proj(transform, viewport.aspect()));
        let caster_bounds: Vec<Aabb> = casters.iter().map(|b| b.0).filter(|b| !b.is_empty()).collect();
        for (sun, mut map) in &mut suns {
            let fit = fit_directional(sun.direction, &corners, &caster_bounds, size);
            *map = ShadowMap { view_proj: fit.view_proj, texel: fit.texel, layer };
            layer += 1;
        }
    }
    for (spot, transform, mut map) in &mut spots {
        let fit = spot_projection(transform.translation, transform.forward(), spot.outer_angle, spot.range, size);
        *map = ShadowMap { view_proj: fit.view_proj, texel: fit.texel, layer };
        layer += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy_ecs::system::RunSystemOnce;
    use crate::assets::cube;
    use glam::{Mat4, Vec3};

    fn world() -> World {
        let mut world = World::new();
        world.insert_resource(Settings::default());
        world.insert_resource(Viewport { width: 320, height: 240 });
        world.insert_resource(MeshLibrary::default());
        world
    }

    #[test]
    fn bounds_follow_the_transform() {
        let mut world = world();
        let mesh = world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
        let e = world.spawn((mesh, Transform::from_xyz(2.0, 1.0, 0.0))).id();
        world.run_system_once(update_bounds).unwrap();
        let b = world.get::<WorldBounds>(e).unwrap().0;
        assert_eq!(b, Aabb::new(Vec3::new(1.5, 0.5, -0.5), Vec3::new(2.5, 1.5, 0.5)));
    }

    #[test]
    fn sun_matrix_is_recalculated_when_the_camera_moves() {
        let mut world = world();
        let cam = world.spawn((Camera::default(), Transform::from_xyz(0.0, 2.0, 5.0))).id();
        let sun = DirectionalLight { direction: Vec3::new(0.3, -1.0, 0.2), color: Vec3::ONE, intensity: 1.0 };
        let light = world.spawn((sun, ShadowMap::default())).id();
        world.run_system_once(update_light_matrices).unwrap();
        let before = world.get::<ShadowMap>(light).unwrap().view_proj;
        assert_ne!(before, Mat4::IDENTITY);
        world.get_mut::<Transform>(cam).unwrap().translation.x += 10.0;
        world.run_system_once(update_light_matrices).unwrap();
        let after = world.get::<ShadowMap>(light).unwrap().view_proj;
        assert_ne!(before, after);
    }

    #[test]
    fn layers_are_given_sun_first_then_spots() {
        let mut world = world();
        world.spawn((Camera::default(), Transform::default()));
        let spot = SpotLight { color: Vec3::ONE, intensity: 1.0, range: 10.0, inner_angle: 0.2, outer_angle: 0.3 };
        let s = world.spawn((spot, Transform::from_xyz(0.0, 4.0, 0.0), ShadowMap::default())).id();
        let sun = DirectionalLight { direction: Vec3::NEG_Y, color: Vec3::ONE, intensity: 1.0 };
        let d = world.spawn((sun, ShadowMap::default())).id();
        world.run_system_once(update_light_matrices).unwrap();
        assert_eq!(world.get::<ShadowMap>(d).unwrap().layer, 0);
        assert_eq!(world.get::<ShadowMap>(s).unwrap().layer, 1);
    }
}
