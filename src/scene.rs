//! The sample scene: ground, pillars, a wall, animated cubes, a walking character, a sun and two
//! coloured spot lights.
//!
//! Everything here is a pure function of the settings, so the scene at time t is reproducible.

use crate::assets::character::WALK_SPEED;
use crate::assets::model::MIN_MODEL_SIZE;
use crate::assets::{
    MeshLibrary, Model, ModelError, ModelInstance, TextureLibrary, cube, load_model, parse_model, plane, sphere,
};
use crate::components::*;
use crate::settings::SceneSettings;
use bevy_ecs::prelude::*;
use glam::{Quat, Vec3};
use std::sync::Arc;

/// The walking character, built into the program so the scene needs no files at run time
/// (`cargo run --example make_character` writes it from `src/assets/character/`).
pub const CHARACTER_GLB: &[u8] = include_bytes!("../assets/character.glb");

/// The circle the character walks: round the middle of the scene, inside the ring of cubes,
/// through both spot lights and the shadows of the cubes above.
pub fn character_walker() -> Walker {
    Walker { center: Vec3::new(0.0, 0.0, 0.5), radius: 2.6, speed: WALK_SPEED, phase: 0.0 }
}

/// Where a user's model stands: the middle of the scene, inside the character's circle.
pub const MODEL_SPOT: Vec3 = Vec3::new(0.0, 0.0, 0.5);

/// The sample sun's direction of travel: high in the south-east sky.
pub const SUN_DIRECTION: Vec3 = Vec3::new(-0.45, -1.0, -0.35);

/// Spawns the whole sample scene into `world` (which must hold a [`MeshLibrary`]); fails only
/// when the user's model (`settings.model`) cannot be loaded.
pub fn spawn_sample_scene(world: &mut World, settings: &SceneSettings) -> Result<(), ModelError> {
    let (ground, unit_cube) = {
        let mut meshes = world.resource_mut::<MeshLibrary>();
        (meshes.add(plane(80.0)), meshes.add(cube(Vec3::splat(0.5))))
    };
    world.spawn((ground, Material::color(0.45, 0.47, 0.42), ShadowReceiver));

    let stone = Material::color(0.62, 0.58, 0.52);
    let pillars = [(-7.0, -5.0), (7.5, -4.0), (-3.0, -9.0), (7.0, 5.0)];
    for (x, z) in pillars {
        let t = Transform::from_xyz(x, 3.0, z).with_scale(Vec3::new(0.9, 6.0, 0.9));
        world.spawn((unit_cube, t, stone, ShadowCaster, ShadowReceiver));
    }
    let wall = Transform::from_xyz(1.0, 1.5, -7.0).with_scale(Vec3::new(7.0, 3.0, 0.5));
    world.spawn((unit_cube, wall, stone, ShadowCaster, ShadowReceiver));
    // A curved caster that shadows itself: at its terminator every bias is tested hardest.
    let ball = world.resource_mut::<MeshLibrary>().add(sphere(BALL.1, 24));
    let ball_material = Material { specular: 0.6, shininess: 64.0, ..Material::color(0.75, 0.72, 0.68) };
    world.spawn((ball, Transform::from_translation(BALL.0), ball_material, ShadowCaster, ShadowReceiver));

    let ring = settings.cubes.min(RING_CUBES);
    for i in 0..ring {
        world.spawn(animated_cube(i, ring, unit_cube));
    }
    for (i, spot) in (ring..settings.cubes).zip(field_spots((settings.cubes - ring) as usize)) {
        world.spawn(field_cube(i, spot, unit_cube));
    }

    let sun = DirectionalLight {
        direction: SUN_DIRECTION.normalize(),
        color: Vec3::new(1.0, 0.95, 0.85),
        intensity: if settings.lanterns > 0 { crate::lanterns::DUSK } else { 1.0 },
        ..Default::default()
    };
    world.spawn((sun, ShadowMap::default()));
    for (spot, at, target, cookie) in sample_spots() {
        let transform = Transform { translation: at, ..Default::default() }.looking_to(target - at);
        let mut light = world.spawn((spot, transform, ShadowMap::default()));
        if let Some(cookie) = cookie {
            light.insert(cookie);
        }
    }

    let (lamp, at) = sample_lamp();
    world.spawn((lamp, Transform::from_translation(at), ShadowMap::default()));
    crate::lanterns::spawn_lanterns(world, settings.lanterns);

    if settings.character {
        let character = parse_model(CHARACTER_GLB, None, "character.glb")?;
        let root = spawn_model(world, Arc::new(character), Transform::default(), Some(0));
        world.entity_mut(root).insert(character_walker());
    }
    if let Some(path) = &settings.model {
        let model = load_model(path)?;
        if model.parts.is_empty() {
            let problem = "its scene has no triangle meshes to draw".to_string();
            return Err(ModelError { path: path.display().to_string(), problem });
        }
        let placement = stand_at(&model, MODEL_SPOT);
        let clip = (!model.clips.is_empty()).then_some(0);
        spawn_model(world, Arc::new(model), placement, clip);
    }

    world.spawn(default_camera());
    Ok(())
}

/// Spawns `model` at `placement` playing `clip`: one entity for the model, one per mesh part
/// (casting and taking shadows); parts that share a mesh or a texture share it in the libraries
/// too. Returns the model's entity.
pub fn spawn_model(world: &mut World, model: Arc<Model>, placement: Transform, clip: Option<usize>) -> Entity {
    let root = world.spawn((ModelInstance(model.clone()), Animator { clip, speed: 1.0 }, placement)).id();
    let mut meshes = std::collections::HashMap::new();
    for (i, part) in model.parts.iter().enumerate() {
        let mesh = *meshes
            .entry(Arc::as_ptr(&part.mesh))
            .or_insert_with(|| world.resource_mut::<MeshLibrary>().add_shared(part.mesh.clone()));
        let texture = part.texture.clone().map(|t| world.get_resource_or_init::<TextureLibrary>().add(t));
        let material = Material { texture, ..part.material };
        let mut e = world.spawn((mesh, material, placement, ModelPart { root, part: i }, ShadowCaster, ShadowReceiver));
        if part.skin.is_some() {
            e.insert(Joints::default());
        }
    }
    root
}

/// A placement that stands `model` on the ground at `spot`, scaled into a 3 m box when it is
/// bigger than that or smaller than 30 cm (models come in every unit).
pub fn stand_at(model: &Model, spot: Vec3) -> Transform {
    let bounds = model.rest_bounds();
    if bounds.is_empty() {
        return Transform { translation: spot, ..Default::default() };
    }
    let size = (bounds.max - bounds.min).max_element();
    // A model with no size (its loader warned) is placed as it is: scaling it up would only
    // spread float error over the scene.
    let scale = if size >= MIN_MODEL_SIZE && !(0.3..=3.0).contains(&size) { 3.0 / size } else { 1.0 };
    let foot = Vec3::new(bounds.center().x, bounds.min.y, bounds.center().z) * scale;
    Transform { translation: spot - foot, scale: Vec3::splat(scale), ..Default::default() }
}

/// The stone ball: its centre and radius, resting on the ground behind the character's circle.
pub const BALL: (Vec3, f32) = (Vec3::new(-1.4, 0.7, -3.6), 0.7);

/// The sample's lantern: a warm point light hanging inside the ring of cubes, above the
/// character's circle, so its shadows fall every way.
pub fn sample_lamp() -> (PointLight, Vec3) {
    let lamp = PointLight { color: Vec3::new(1.0, 0.75, 0.45), intensity: 3.0, range: 10.0, ..Default::default() };
    (lamp, Vec3::new(1.8, 2.9, -1.2))
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
        ..Default::default()
    };
    [
        (
            spot(Vec3::new(0.35, 0.75, 1.0), 4.0),
            Vec3::new(-5.0, 7.0, 3.0),
            Vec3::new(-3.0, 0.0, 0.5),
            Some(Cookie::Window),
        ),
        (spot(Vec3::new(1.0, 0.55, 0.25), 3.5), Vec3::new(6.0, 6.5, 4.0), Vec3::new(4.0, 0.0, 1.0), None),
    ]
}

/// The camera the sample starts with: south of the scene, looking down at the ring of cubes.
pub fn default_camera() -> (Camera, FlyCamera, Transform) {
    camera_looking(Vec3::new(2.0, 5.5, 12.5), Vec3::new(-0.5, 1.0, 0.0))
}

/// Points the world's camera from `eye` at `target` (turning its fly camera to match, so the
/// update does not turn it back).
pub fn place_camera(world: &mut World, eye: Vec3, target: Vec3) {
    let (_, fly, transform) = camera_looking(eye, target);
    for (mut t, f) in world.query_filtered::<(&mut Transform, Option<&mut FlyCamera>), With<Camera>>().iter_mut(world) {
        *t = transform;
        if let Some(mut f) = f {
            (f.yaw, f.pitch) = (fly.yaw, fly.pitch);
        }
    }
}

/// A fly camera at `eye` looking at `target`.
pub fn camera_looking(eye: Vec3, target: Vec3) -> (Camera, FlyCamera, Transform) {
    let to = target - eye;
    let fly = FlyCamera::new((-to.x).atan2(-to.z), (to.y / to.length().max(1e-6)).asin());
    (Camera::default(), fly, Transform { translation: eye, rotation: fly.rotation(), ..Default::default() })
}

/// Most cubes the sample's ring holds; more (`--cubes N`, the stress scene) stand in a field
/// round it.
pub const RING_CUBES: u32 = 64;

/// Spacing of the field's grid, in metres.
pub const FIELD_SPACING: f32 = 0.75;

/// Nearest to the scene's middle a field cube stands, in metres: outside the ring, the pillars
/// and the wall, so the sample's shadows stay as they are.
pub const FIELD_INNER_RADIUS: f32 = 10.0;

/// Where the first `n` field cubes stand on the ground: the grid's points outside
/// [`FIELD_INNER_RADIUS`], nearest first, so a bigger field adds cubes only at its rim (beyond
/// the 80 m ground once it holds about 10,000).
#[must_use]
pub fn field_spots(n: usize) -> Vec<glam::Vec2> {
    let mut spots = Vec::with_capacity(n);
    let mut reach = FIELD_INNER_RADIUS + 4.0;
    while spots.len() < n {
        let cells = (reach / FIELD_SPACING).ceil() as i32;
        spots = (-cells..=cells)
            .flat_map(|x| (-cells..=cells).map(move |z| glam::Vec2::new(x as f32, z as f32) * FIELD_SPACING))
            .filter(|p| (FIELD_INNER_RADIUS..=reach).contains(&p.length()))
            .collect();
        reach *= 1.5;
    }
    // Ties in distance are broken by position, so the order is the same on every machine.
    spots.sort_by(|a, b| a.length().total_cmp(&b.length()).then(a.x.total_cmp(&b.x)).then(a.y.total_cmp(&b.y)));
    spots.truncate(n);
    spots
}

/// Field cube `i` standing at `spot`: small, spinning and bobbing like the ring's.
fn field_cube(i: u32, spot: glam::Vec2, mesh: Mesh) -> impl Bundle {
    let (_, mut transform, material, mut spin, bob, caster, receiver) = animated_cube(i, RING_CUBES, mesh);
    let g = (i as f32 * 0.618_034).fract();
    let base_y = 0.5 + 0.4 * g;
    transform.translation = glam::Vec3::new(spot.x, base_y, spot.y);
    transform.scale = glam::Vec3::splat(0.3 + 0.15 * g);
    spin.base = Quat::from_rotation_y(spot.x + spot.y);
    let bob = Bob { base_y, amplitude: 0.15 * bob.amplitude, ..bob };
    (mesh, transform, material, spin, bob, caster, receiver)
}

/// Cube `i` of `n`: placed on a ring, spinning and bobbing at its own rates (as in seed 000).
fn animated_cube(i: u32, n: u32, mesh: Mesh) -> (Mesh, Transform, Material, Spin, Bob, ShadowCaster, ShadowReceiver) {
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
        Material { specular: 0.5, shininess: 48.0, ..Material::color(c.x, c.y, c.z) },
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
        spawn_sample_scene(&mut world, &SceneSettings::default()).unwrap();
        let animated = world.query_filtered::<(), (With<Spin>, With<Bob>)>().iter(&world).count();
        assert!(animated >= 8);
        assert_eq!(world.query::<&DirectionalLight>().iter(&world).count(), 1);
        assert_eq!(world.query::<(&SpotLight, &ShadowMap)>().iter(&world).count(), 2);
        assert_eq!(world.query::<(&SpotLight, &Cookie)>().iter(&world).count(), 1);
        assert_eq!(world.query::<(&PointLight, &ShadowMap)>().iter(&world).count(), 1, "the lantern");
        assert_eq!(world.query::<&Camera>().iter(&world).count(), 1);
        let walkers = world.query_filtered::<(), (With<Walker>, With<ModelInstance>)>().iter(&world).count();
        assert_eq!(walkers, 1, "the walking character");
        assert!(world.query_filtered::<(), (With<Joints>, With<ShadowCaster>)>().iter(&world).count() >= 1);
    }

    #[test]
    fn models_stand_on_the_ground_at_their_spot_in_any_unit() {
        let model = parse_model(CHARACTER_GLB, None, "character.glb").unwrap();
        let t = stand_at(&model, Vec3::new(1.0, 0.0, 2.0));
        assert_eq!(t.scale, Vec3::ONE, "a 1.8 m character keeps its size");
        let b = model.rest_bounds().transformed(&t.matrix());
        assert!(b.min.y.abs() < 1e-5 && (b.center().x - 1.0).abs() < 1e-5 && (b.center().z - 2.0).abs() < 1e-5);
        // The same character a hundred times bigger (authored in centimetres) is brought to 3 m.
        let mut big = model.clone();
        big.nodes[0].rest.scale = Vec3::splat(100.0);
        let t = stand_at(&big, Vec3::ZERO);
        let b = big.rest_bounds().transformed(&t.matrix());
        assert!(((b.max - b.min).max_element() - 3.0).abs() < 1e-3, "{b:?}");
    }

    #[test]
    fn a_field_of_cubes_grows_at_its_rim_and_keeps_clear_of_the_ring() {
        let small = field_spots(500);
        let big = field_spots(10_000);
        assert_eq!((small.len(), big.len()), (500, 10_000));
        assert_eq!(small[..], big[..500], "adding cubes leaves the first ones where they were");
        assert!(big.iter().all(|p| p.length() >= FIELD_INNER_RADIUS));
        let mut unique: Vec<(i32, i32)> =
            big.iter().map(|p| ((p.x / FIELD_SPACING).round() as i32, (p.y / FIELD_SPACING).round() as i32)).collect();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), 10_000, "no two cubes share a spot");
        assert!(big.windows(2).all(|w| w[0].length() <= w[1].length()), "nearest first");
        assert!(field_spots(0).is_empty());
    }

    #[test]
    fn more_cubes_than_the_ring_holds_leave_the_ring_as_it_was() {
        let cubes = |n: u32| {
            let mut world = World::new();
            world.insert_resource(MeshLibrary::default());
            let settings = SceneSettings { cubes: n, character: false, ..SceneSettings::default() };
            spawn_sample_scene(&mut world, &settings).unwrap();
            let mut spots: Vec<[f32; 3]> = world
                .query_filtered::<&Transform, With<Spin>>()
                .iter(&world)
                .map(|t| t.translation.to_array())
                .collect();
            spots.sort_by(|a, b| a.partial_cmp(b).unwrap());
            spots
        };
        let ring = cubes(RING_CUBES);
        let stress = cubes(RING_CUBES + 2000);
        assert_eq!(stress.len(), ring.len() + 2000);
        assert!(ring.iter().all(|c| stress.contains(c)), "the ring is kept");
    }

    #[test]
    fn default_camera_looks_at_the_scene_centre() {
        let (_, _, t) = default_camera();
        let to_centre = (Vec3::new(-0.5, 1.0, 0.0) - t.translation).normalize();
        assert!(t.forward().dot(to_centre) > 0.9999);
    }
}
