//! Light matrices and dirty flags: each shadowed light's layers (as its kind fits them, in
//! [`crate::light`]), each marked dirty when its map must be drawn again, and given a new
//! static version when the part of it drawn from casters at rest changed (see
//! [`super::casters`]).

use super::ShadowAtlas;
use super::casters::CasterChanges;
use super::layers::fitted_layers;
use super::pages::{PagedLight, PagedUpdate, admit_limit, coarse_side, pool_capacity, refresh_paged};
use crate::components::{
    Camera, MarkedPages, Mesh, Notices, SeenByCamera, ShadowCaster, ShadowMap, ShadowMethod, SharedPool, Transform,
    Viewport, WorldBounds,
};
use crate::light::{CameraView, Kind, LayerContext, LayerFit, LightSources, ShadowShape};
use crate::settings::{CascadeSettings, CasterCulling, MapSettings, ShadowSettings};
use crate::shadow::{Aabb, PAGE_TILE, intersects_clip_volume};
use bevy_ecs::prelude::*;
use std::collections::{HashMap, HashSet};

/// The boxes light fitting can use, each with whether it casts a shadow, from each entity's
/// bounds, whether it is a caster and whether it has a mesh (is seen). `casts` says whether a
/// caster's box counts as one (it may be culled to the camera's view). An entity whose box is
/// broken (not finite, or beyond [`crate::shadow::MAX_WORLD_EXTENT`]) is left out and named once
/// in `notices`, so that one broken object cannot spoil every other shadow.
fn usable_boxes<'a>(
    boxes: impl Iterator<Item = (Entity, &'a WorldBounds, bool, bool)>,
    casts: impl Fn(&Aabb) -> bool,
    told: &mut HashSet<Entity>,
    notices: Option<&mut Notices>,
) -> Vec<(Aabb, bool)> {
    let mut broken = Vec::new();
    let mut usable = Vec::with_capacity(boxes.size_hint().0);
    for (e, b, caster, seen) in boxes {
        if b.0.is_usable() {
            let casts = caster && casts(&b.0);
            if casts || seen {
                usable.push((b.0, casts));
            }
        } else if b.0 != Aabb::EMPTY && told.insert(e) {
            // Nothing to fit is not broken: a mesh with no vertices, a part not posed yet.
            broken.push(format!(
                "entity {e} has bounds {:?}..{:?}: left out of shadow fitting",
                b.0.min.to_array(),
                b.0.max.to_array()
            ));
        }
    }
    if let Some(notices) = notices {
        notices.0.extend(broken);
    }
    usable
}

/// The settings that change what every map holds: a new map size, face choice, culling, cube
/// seams or spot limit redraws every map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapOptions {
    map_size: u32,
    faces: crate::settings::ShadowFaces,
    culling: CasterCulling,
    cube_seams: bool,
    spot_limit_bits: u32,
}

impl MapOptions {
    fn of(settings: &MapSettings) -> MapOptions {
        MapOptions {
            map_size: settings.shadow_map_size,
            faces: settings.shadow_faces,
            culling: settings.caster_culling,
            cube_seams: settings.cube_seams,
            spot_limit_bits: settings.spot_map_limit.to_bits(),
        }
    }
}

/// Every object that bounds casters or meshes: its entity, bounds, and whether it casts and is a mesh.
type BoundedObjects<'w, 's> =
    Query<'w, 's, (Entity, &'static WorldBounds, Has<ShadowCaster>, Has<Mesh>), Or<(With<ShadowCaster>, With<Mesh>)>>;

/// Recomputes every shadowed light's layers (each kind fits its own: a sun's cascades, a spot's
/// cone, a cube's faces) and sets their dirty flags.
///
/// A layer is dirty when it is new, its matrix changed (in stable mode a cascade only when it
/// snaps to a new texel or its split changes; a light whose pose, cone or range changed moves
/// its matrices), the map size, faces, culling or cube margin changed, or a caster that changed
/// this update overlaps its volume, before or after the change. Colour, bias and method are
/// applied when the map is sampled, so they dirty nothing.
#[allow(clippy::too_many_arguments)]
pub fn update_light_matrices(
    settings: Res<MapSettings>,
    cascade: Res<CascadeSettings>,
    viewport: Res<Viewport>,
    changes: Res<CasterChanges>,
    mut last_maps: Local<Option<MapOptions>>,
    mut told: Local<HashSet<Entity>>,
    mut refused: Local<HashSet<(Entity, ShadowMethod)>>,
    mut notices: Option<ResMut<Notices>>,
    seen: Option<Res<SeenByCamera>>,
    (shadow, atlas, marked): (Res<ShadowSettings>, Option<Res<ShadowAtlas>>, Option<Res<MarkedPages>>),
    mut pool: ResMut<SharedPool>,
    cameras: Query<(&Camera, Ref<Transform>)>,
    boxes: BoundedObjects,
    lights: LightSources,
    mut maps: Query<(Entity, &mut ShadowMap, Option<&ShadowMethod>)>,
) {
    let options = MapOptions::of(&settings);
    // Culled to the camera's view, what a map holds changes whenever the camera moves.
    let camera_moved = cameras.iter().any(|(_, t)| t.is_changed());
    let all_dirty = last_maps.replace(options) != Some(options)
        || (settings.caster_culling == CasterCulling::CameraView && camera_moved);
    let camera = cameras.iter().next().map(|(c, t)| (c, t.into_inner()));
    // The shortcut of culling casters to the camera's view keeps only those the camera sees.
    let in_view = |b: &Aabb| match (settings.caster_culling, camera) {
        (CasterCulling::CameraView, Some((c, t))) => intersects_clip_volume(&c.view_proj(t, viewport.aspect()), b),
        _ => true,
    };
    // Everything that casts must lie inside a cascade's depth range, and everything that can be
    // seen (has a mesh) in front of its far plane.
    let scene = usable_boxes(boxes.iter(), in_view, &mut told, notices.as_deref_mut());
    let context = LayerContext {
        maps: &settings,
        cascade: &cascade,
        view: camera.map(|(camera, transform)| CameraView { camera, transform, aspect: viewport.aspect() }),
        scene: &scene,
        seen: seen.as_deref().map(|s| &s.0),
    };
    let texel_bytes = atlas.map_or(4, |a| a.texel_bytes);
    // The paged lights' fits, and the side their pages' tiles were given.
    let mut paged_fits = HashMap::new();
    let mut page_side = PAGE_TILE;
    for source in lights.all() {
        if let Ok((_, mut map, method)) = maps.get_mut(source.entity) {
            let resolution = if map.resolution > 0 { map.resolution } else { settings.shadow_map_size };
            let method = method.copied().unwrap_or(shadow.method);
            let shape = source.kind.shape(&settings, method);
            // A light that would be paged but for its method keeps its layers, and says so once.
            let pageable = source.kind.shape(&settings, ShadowMethod::default()) == ShadowShape::Pages;
            if pageable && shape != ShadowShape::Pages && refused.insert((source.entity, method)) {
                let why = format!(
                    "a {}'s {} shadow reads a colour map (or none), which virtual pages do not hold: it keeps \
                     the maps it has without them",
                    source.kind.word(),
                    method.name()
                );
                if let Some(n) = notices.as_deref_mut() {
                    n.0.push(why);
                }
            }
            let paged = (shape == ShadowShape::Pages)
                .then(|| {
                    let depth = map.pages.as_ref().and_then(|p| p.space.depth());
                    source.kind.pages(&context, coarse_side(&settings), depth)
                })
                .flatten();
            match paged {
                Some(fit) => {
                    page_side = page_side.min(resolution);
                    paged_fits.insert(source.entity, fit);
                }
                None => {
                    let fits = source.kind.layers(&context, resolution);
                    refresh_layers(&mut map, &fits, resolution, all_dirty, &changes);
                }
            }
        }
    }
    let mut paged: Vec<PagedLight> = maps
        .iter_mut()
        .filter_map(|(light, map, _)| {
            paged_fits.remove(&light).map(|fit| PagedLight { light, map: map.into_inner(), fit })
        })
        .collect();
    let how = PagedUpdate {
        marked: marked.as_deref(),
        changes: &changes,
        forced: all_dirty,
        capacity: if paged.is_empty() { 0 } else { pool_capacity(&settings, texel_bytes, page_side) },
        admit: admit_limit(&settings),
        bias: settings.page_bias,
    };
    refresh_paged(&mut pool, &mut paged, &how);
}

/// Replaces a light's layers with `fits` (see [`fitted_layers`]); it is no longer paged.
fn refresh_layers(map: &mut ShadowMap, fits: &[LayerFit], resolution: u32, forced: bool, changes: &CasterChanges) {
    let layers = fitted_layers(&map.layers, fits, resolution, forced, changes);
    // Writing only on a difference keeps `Changed<ShadowMap>` meaningful.
    if map.layers != layers {
        map.layers = layers;
    }
    if map.pages.is_some() {
        map.pages = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assets::MeshLibrary;
    use crate::components::{DirectionalLight, PointLight, SpotLight};
    use crate::settings::Settings;
    use bevy_ecs::system::RunSystemOnce;
    use glam::{Mat4, Vec3};

    fn world() -> World {
        let mut world = World::new();
        Settings::default().put(&mut world).unwrap();
        world.insert_resource(Viewport { width: 320, height: 240 });
        world.insert_resource(MeshLibrary::default());
        world.insert_resource(CasterChanges::default());
        world.insert_resource(SharedPool::default());
        world
    }

    #[test]
    fn sun_cascades_are_recalculated_when_the_camera_moves() {
        let mut world = world();
        let cam = world.spawn((Camera::default(), Transform::from_xyz(0.0, 2.0, 5.0))).id();
        let sun = DirectionalLight {
            direction: Vec3::new(0.3, -1.0, 0.2),
            color: Vec3::ONE,
            intensity: 1.0,
            ..Default::default()
        };
        let light = world.spawn((sun, ShadowMap::default())).id();
        world.run_system_once(update_light_matrices).unwrap();
        let before = world.get::<ShadowMap>(light).unwrap().layers.clone();
        assert_eq!(before.len(), Settings::default().cascade.cascades as usize);
        assert!(before.iter().all(|l| l.clip_from_world != Mat4::IDENTITY && l.clip_from_world.is_finite()));
        world.get_mut::<Transform>(cam).unwrap().translation.x += 10.0;
        world.run_system_once(update_light_matrices).unwrap();
        let after = &world.get::<ShadowMap>(light).unwrap().layers;
        assert!(before.iter().zip(after).all(|(b, a)| b.clip_from_world != a.clip_from_world));
    }

    #[test]
    fn culled_to_the_camera_a_moving_camera_dirties_every_layer() {
        let mut world = world();
        world.resource_mut::<crate::settings::MapSettings>().caster_culling = CasterCulling::CameraView;
        let cam = world.spawn((Camera::default(), Transform::default())).id();
        let spot = SpotLight {
            color: Vec3::ONE,
            intensity: 1.0,
            range: 10.0,
            inner_angle: 0.2,
            outer_angle: 0.3,
            ..Default::default()
        };
        let s = world.spawn((spot, Transform::from_xyz(0.0, 4.0, 0.0), ShadowMap::default())).id();
        let mut schedule = Schedule::default();
        schedule.add_systems(update_light_matrices);
        schedule.run(&mut world);
        schedule.run(&mut world);
        assert!(!world.get::<ShadowMap>(s).unwrap().dirty(), "nothing moved");
        world.get_mut::<Transform>(cam).unwrap().translation.x += 1.0;
        schedule.run(&mut world);
        assert!(world.get::<ShadowMap>(s).unwrap().dirty(), "the spot's casters depend on the camera now");
        world.resource_mut::<crate::settings::MapSettings>().caster_culling = CasterCulling::LightVolume;
        schedule.run(&mut world);
        world.get_mut::<Transform>(cam).unwrap().translation.x += 1.0;
        schedule.run(&mut world);
        assert!(!world.get::<ShadowMap>(s).unwrap().dirty(), "culled to its own volume, a spot ignores the camera");
    }

    #[test]
    fn broken_caster_bounds_are_left_out_of_fitting_and_named_once() {
        let mut world = world();
        world.insert_resource(Notices::default());
        world.spawn((Camera::default(), Transform::from_xyz(0.0, 2.0, 6.0)));
        let sun = DirectionalLight {
            direction: Vec3::new(0.3, -1.0, 0.2),
            color: Vec3::ONE,
            intensity: 1.0,
            ..Default::default()
        };
        let light = world.spawn((sun, ShadowMap::default())).id();
        let pillar = WorldBounds(Aabb::new(Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 6.0, 0.5)));
        world.spawn((Mesh(0), pillar, ShadowCaster));
        let mut schedule = Schedule::default();
        schedule.add_systems(update_light_matrices);
        schedule.run(&mut world);
        let matrices = |world: &World| {
            world.get::<ShadowMap>(light).unwrap().layers.iter().map(|l| l.clip_from_world).collect::<Vec<_>>()
        };
        let clean = matrices(&world);
        // A caster a million metres tall over the pillar, and one whose bounds are NaN.
        let huge = WorldBounds(Aabb::new(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 1.5e6, 1.0)));
        world.spawn((Mesh(0), huge, ShadowCaster));
        world.spawn((Mesh(0), WorldBounds(Aabb { min: Vec3::NAN, max: Vec3::NAN }), ShadowCaster));
        schedule.run(&mut world);
        schedule.run(&mut world);
        assert_eq!(matrices(&world), clean, "the cascades are fitted as if they were not there");
        let notices = &world.resource::<Notices>().0;
        assert_eq!(notices.len(), 2, "each named once: {notices:?}");
        assert!(notices.iter().all(|n| n.contains("left out of shadow fitting")), "{notices:?}");
    }

    #[test]
    fn each_light_kind_gets_its_layers() {
        let mut world = world();
        world.resource_mut::<crate::settings::CascadeSettings>().cascades = 3;
        world.spawn((Camera::default(), Transform::default()));
        let narrow = SpotLight { inner_angle: 0.2, outer_angle: 0.3, ..Default::default() };
        let wide = SpotLight { inner_angle: 0.2, outer_angle: 80f32.to_radians(), ..Default::default() };
        let at = Transform::from_xyz(0.0, 4.0, 0.0);
        let lights = [
            world.spawn((narrow, at, ShadowMap::default())).id(),
            world.spawn((wide, at, ShadowMap::default())).id(),
            world.spawn((PointLight::default(), at, ShadowMap::default())).id(),
            world.spawn((DirectionalLight::default(), ShadowMap::default())).id(),
            world.spawn((DirectionalLight::default(), ShadowMap::default())).id(),
        ];
        world.run_system_once(update_light_matrices).unwrap();
        let layers: Vec<usize> = lights.iter().map(|&e| world.get::<ShadowMap>(e).unwrap().layers.len()).collect();
        assert_eq!(layers, vec![1, 6, 6, 3, 3], "every sun gets its cascades, wide spots and points a cube");
        // The point light's faces look along +X, -X, +Y, -Y, +Z, -Z: a point 2 m along each
        // direction from the light lands in the middle of its face.
        let cube = &world.get::<ShadowMap>(lights[2]).unwrap().layers;
        for (face, d) in crate::shadow::CUBE_FACES.iter().enumerate() {
            let p = cube[face].clip_from_world.project_point3(at.translation + *d * 2.0);
            assert!(p.x.abs() < 1e-4 && p.y.abs() < 1e-4 && (0.0..1.0).contains(&p.z), "face {face}: {p:?}");
        }
    }
}
