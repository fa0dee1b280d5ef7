//! Casters from frame to frame: their world bounds, which of them changed in this update, and
//! which have been at rest long enough to count as static scenery.
//!
//! Shadow maps are kept in two parts (as Unity HDRP's mixed cached shadow maps are): the casters
//! at rest, drawn once into a static map, and the rest, drawn over a copy of it each time the
//! layer is dirty. So the light-matrix system must know, besides what moved, where the static
//! part changed: where a caster at rest started to move or went away, and where one came to rest.

use crate::assets::MeshLibrary;
use crate::components::{Joints, Mesh, ShadowCaster, Transform, WorldBounds};
use crate::shadow::Aabb;
use bevy_ecs::entity::{EntityHashMap, EntityHashSet};
use bevy_ecs::prelude::*;

/// Updates a caster must go unchanged before it counts as at rest (half a second at 60 Hz):
/// long enough that a caster pausing for a frame or two is not drawn into the static map and
/// straight out again.
pub const REST_AFTER: u64 = 30;

/// Recomputes the world bounds of every rigid mesh entity that moved or changed mesh (skinned
/// ones get theirs from the pose, in [`crate::systems::pose_parts`]).
#[allow(clippy::type_complexity)]
pub fn update_bounds(
    meshes: Res<MeshLibrary>,
    mut query: Query<(&Transform, &Mesh, &mut WorldBounds), (Without<Joints>, Or<(Changed<Transform>, Changed<Mesh>)>)>,
) {
    for (transform, mesh, mut bounds) in &mut query {
        let local = meshes.get(*mesh).map_or(Aabb::EMPTY, |m| m.bounds);
        bounds.0 = if local.is_empty() { local } else { local.transformed(&transform.matrix()) };
    }
}

/// What changed among the casters in this update (broken boxes left out: they would dirty
/// every layer, and light fitting leaves them out too).
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct CasterChanges {
    /// Casters that moved, changed mesh or pose (their boxes before and after), or were added or
    /// removed (their one box).
    pub moved: Vec<Aabb>,
    /// Where the casters at rest changed: one at rest that moved or was removed (its box
    /// before), and one that came to rest (its box).
    pub settled: Vec<Aabb>,
}

/// The casters that have not changed for [`REST_AFTER`] updates: what the static part of a
/// shadow map holds.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct CastersAtRest(pub EntityHashSet);

/// What a caster's shadow depends on: where it is, how it is placed, what it is and its pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CasterState {
    bounds: Aabb,
    transform: Transform,
    mesh: Mesh,
    pose: u64,
}

/// A fingerprint of joint matrices, so a new pose counts as a change and a repeated one does not.
fn pose_hash(joints: Option<&Joints>) -> u64 {
    use std::hash::{Hash, Hasher};
    let Some(joints) = joints else { return 0 };
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for m in &joints.0 {
        m.to_cols_array().map(f32::to_bits).hash(&mut h);
    }
    h.finish()
}

/// What [`track_casters`] remembers of a caster.
#[derive(Clone, Copy, Debug)]
struct Known {
    state: CasterState,
    /// The update it last changed in.
    changed: u64,
    /// In [`CastersAtRest`].
    resting: bool,
}

/// What [`track_casters`] remembers between updates.
#[derive(Default)]
pub struct Tracked {
    /// Every caster as it was at the last update.
    known: EntityHashMap<Known>,
    /// Updates so far.
    update: u64,
}

/// Finds the casters that changed since the last update and lists their old and new bounds, and
/// those that came to rest or left it.
///
/// A caster changed when its bounds, transform, mesh or pose differ by value from the last
/// update, so a system that rewrites a transform with the same value (an animation at an
/// unchanged time) dirties nothing, while a turn that leaves the bounds as they were still counts.
#[allow(clippy::type_complexity)]
pub fn track_casters(
    mut tracked: Local<Tracked>,
    mut changes: ResMut<CasterChanges>,
    mut at_rest: ResMut<CastersAtRest>,
    casters: Query<
        (Entity, &WorldBounds, &Transform, &Mesh, Option<&Joints>),
        (
            With<ShadowCaster>,
            Or<(Changed<WorldBounds>, Changed<Transform>, Changed<Mesh>, Changed<Joints>, Added<ShadowCaster>)>,
        ),
    >,
    mut removed: RemovedComponents<ShadowCaster>,
    settings: Res<crate::settings::MapSettings>,
) {
    let Tracked { known, update } = &mut *tracked;
    *update += 1;
    let CasterChanges { moved, settled } = &mut *changes;
    moved.clear();
    settled.clear();
    for entity in removed.read() {
        if let Some(old) = known.remove(&entity) {
            moved.push(old.state.bounds);
            if old.resting {
                at_rest.0.remove(&entity);
                settled.push(old.state.bounds);
            }
        }
    }
    for (entity, bounds, transform, mesh, joints) in &casters {
        let state = CasterState { bounds: bounds.0, transform: *transform, mesh: *mesh, pose: pose_hash(joints) };
        let fresh = Known { state, changed: *update, resting: false };
        match known.get_mut(&entity) {
            Some(old) if old.state == state => {}
            Some(old) => {
                // Without the old box (a setting, to show what it guards) an old shadow stays.
                moved.extend(settings.old_bounds.then_some(old.state.bounds).into_iter().chain([bounds.0]));
                if old.resting {
                    at_rest.0.remove(&entity);
                    settled.push(old.state.bounds);
                }
                *old = fresh;
            }
            None => {
                moved.push(bounds.0);
                known.insert(entity, fresh);
            }
        }
    }
    for (entity, k) in known.iter_mut() {
        if !k.resting && *update - k.changed >= REST_AFTER {
            k.resting = true;
            at_rest.0.insert(*entity);
            settled.push(k.state.bounds);
        }
    }
    moved.retain(Aabb::is_usable);
    settled.retain(Aabb::is_usable);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assets::cube;
    use glam::{Mat4, Vec3};

    fn world() -> World {
        let mut world = World::new();
        world.insert_resource(MeshLibrary::default());
        world.insert_resource(CasterChanges::default());
        world.insert_resource(CastersAtRest::default());
        world.insert_resource(crate::settings::MapSettings::default());
        world
    }

    fn moved(world: &World) -> Vec<Aabb> {
        world.resource::<CasterChanges>().moved.clone()
    }

    #[test]
    fn bounds_follow_the_transform() {
        let mut world = world();
        let mesh = world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
        let e = world.spawn((mesh, Transform::from_xyz(2.0, 1.0, 0.0))).id();
        bevy_ecs::system::RunSystemOnce::run_system_once(&mut world, update_bounds).unwrap();
        let b = world.get::<WorldBounds>(e).unwrap().0;
        assert_eq!(b, Aabb::new(Vec3::new(1.5, 0.5, -0.5), Vec3::new(2.5, 1.5, 0.5)));
    }

    #[test]
    fn caster_changes_hold_old_and_new_bounds_and_removals() {
        let mut world = world();
        let mesh = world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
        let mut schedule = Schedule::default();
        schedule.add_systems((update_bounds, track_casters).chain());
        let e = world.spawn((mesh, Transform::default(), ShadowCaster)).id();
        let a = Aabb::new(Vec3::splat(-0.5), Vec3::splat(0.5));
        schedule.run(&mut world);
        assert_eq!(moved(&world), vec![a], "an added caster");
        schedule.run(&mut world);
        assert!(moved(&world).is_empty(), "nothing changed");
        world.get_mut::<Transform>(e).unwrap().translation = Vec3::ZERO; // same value, written again
        schedule.run(&mut world);
        assert!(moved(&world).is_empty(), "rewritten with the same value");
        world.get_mut::<Transform>(e).unwrap().rotation = glam::Quat::from_rotation_y(std::f32::consts::PI);
        schedule.run(&mut world);
        assert_eq!(moved(&world).len(), 2, "a half turn keeps the box but counts");
        world.get_mut::<Transform>(e).unwrap().translation = Vec3::ONE;
        schedule.run(&mut world);
        // The half turn leaves the box as it was, up to rounding.
        let near = |x: Aabb, y: Aabb| (x.min - y.min).length() < 1e-5 && (x.max - y.max).length() < 1e-5;
        let b = Aabb::new(Vec3::splat(0.5), Vec3::splat(1.5));
        let after = moved(&world);
        assert!(after.len() == 2 && near(after[0], a) && near(after[1], b), "moved: before and after: {after:?}");
        world.despawn(e);
        schedule.run(&mut world);
        assert_eq!(moved(&world), vec![after[1]], "removed");
    }

    #[test]
    fn without_old_bounds_a_move_names_only_where_the_caster_went() {
        let mut world = world();
        world.resource_mut::<crate::settings::MapSettings>().old_bounds = false;
        let mesh = world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
        let mut schedule = Schedule::default();
        schedule.add_systems((update_bounds, track_casters).chain());
        let e = world.spawn((mesh, Transform::default(), ShadowCaster)).id();
        schedule.run(&mut world);
        world.get_mut::<Transform>(e).unwrap().translation = Vec3::new(3.0, 0.0, 0.0);
        schedule.run(&mut world);
        assert_eq!(moved(&world), vec![Aabb::new(Vec3::new(2.5, -0.5, -0.5), Vec3::new(3.5, 0.5, 0.5))]);
    }

    #[test]
    fn a_new_pose_counts_even_when_bounds_and_transform_stay() {
        let mut world = world();
        let mut schedule = Schedule::default();
        schedule.add_systems(track_casters);
        let bounds = WorldBounds(Aabb::new(Vec3::ZERO, Vec3::ONE));
        let e = world.spawn((Mesh(0), Transform::default(), bounds, Joints(vec![Mat4::IDENTITY]), ShadowCaster)).id();
        schedule.run(&mut world);
        world.get_mut::<Joints>(e).unwrap().0[0] = Mat4::IDENTITY; // the same pose again
        schedule.run(&mut world);
        assert!(moved(&world).is_empty());
        world.get_mut::<Joints>(e).unwrap().0[0] = Mat4::from_rotation_z(0.3);
        schedule.run(&mut world);
        assert_eq!(moved(&world), vec![bounds.0, bounds.0], "an arm turned inside the box");
    }

    #[test]
    fn a_caster_comes_to_rest_after_its_still_updates_and_leaves_rest_when_it_moves() {
        let mut world = world();
        let mesh = world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
        let mut schedule = Schedule::default();
        schedule.add_systems((update_bounds, track_casters).chain());
        let e = world.spawn((mesh, Transform::default(), ShadowCaster)).id();
        let other = world.spawn((mesh, Transform::from_xyz(5.0, 0.0, 0.0), ShadowCaster)).id();
        let box_at = |x: f32| Aabb::new(Vec3::new(x - 0.5, -0.5, -0.5), Vec3::new(x + 0.5, 0.5, 0.5));
        let settled = |w: &World| w.resource::<CasterChanges>().settled.clone();
        let resting = |w: &World, e: Entity| w.resource::<CastersAtRest>().0.contains(&e);
        // Added in the first update; at rest once REST_AFTER updates have passed with no change.
        for update in 1..=REST_AFTER {
            schedule.run(&mut world);
            assert!(!resting(&world, e), "update {update}: still counting");
            assert!(settled(&world).is_empty());
        }
        schedule.run(&mut world);
        assert!(resting(&world, e) && resting(&world, other));
        assert_eq!(settled(&world).len(), 2, "both came to rest: their boxes");
        schedule.run(&mut world);
        assert!(settled(&world).is_empty(), "nothing new at rest");
        // The first one moves: it leaves rest, and the static part loses it where it was.
        world.get_mut::<Transform>(e).unwrap().translation.x = 1.0;
        schedule.run(&mut world);
        assert!(!resting(&world, e) && resting(&world, other));
        assert_eq!(settled(&world), vec![box_at(0.0)]);
        assert_eq!(moved(&world), vec![box_at(0.0), box_at(1.0)]);
        // The other is removed while at rest.
        world.despawn(other);
        schedule.run(&mut world);
        assert_eq!(settled(&world), vec![box_at(5.0)]);
        assert!(!resting(&world, other));
        // Still again for long enough (the update that removed the other counts): back at rest
        // where it now stands.
        for _ in 0..REST_AFTER - 2 {
            schedule.run(&mut world);
        }
        assert!(!resting(&world, e));
        schedule.run(&mut world);
        assert!(resting(&world, e));
        assert_eq!(settled(&world), vec![box_at(1.0)]);
    }
}
