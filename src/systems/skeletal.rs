//! Models in motion: a walker's path, its clip's pose, and the parts that follow the pose (rigid
//! parts by their node, skinned parts by their joint matrices and pose-fitted bounds).

use crate::assets::ModelInstance;
use crate::components::{
    Animator, AtNode, DirectionalLight, Joints, ModelPart, Pose, Time, Transform, Walker, WorldBounds,
};
use bevy_ecs::prelude::*;
use glam::{Quat, Vec3};

/// Moves each walker to where its circle has it at the current time, facing along the circle
/// (a model's front is its +Z axis).
pub fn walk(time: Res<Time>, mut walkers: Query<(&Walker, &mut Transform)>) {
    for (walker, mut transform) in &mut walkers {
        let turned = (walker.speed as f64 * time.t / walker.radius.max(1e-3) as f64) % std::f64::consts::TAU;
        let a = walker.phase + turned as f32;
        let at = walker.center + Vec3::new(a.cos(), 0.0, a.sin()) * walker.radius;
        let heading = Vec3::new(-a.sin(), 0.0, a.cos()) * walker.speed.signum();
        let rotation = Quat::from_rotation_y(heading.x.atan2(heading.z));
        transform.set_if_neq(Transform { translation: at, rotation, ..*transform });
    }
}

/// Samples each animated model's clip at the current time into its [`Pose`].
pub fn animate_models(time: Res<Time>, mut models: Query<(&ModelInstance, Option<&Animator>, &mut Pose)>) {
    for (model, animator, mut pose) in &mut models {
        let (clip, speed) = animator.map_or((None, 1.0), |a| (a.clip, a.speed));
        let t = clip.and_then(|c| model.0.clips.get(c)).map_or(0.0, |c| {
            // Wrapped in f64 so the clip stays smooth however long the game runs.
            if c.duration > 0.0 { (time.t * speed as f64).rem_euclid(c.duration as f64) as f32 } else { 0.0 }
        });
        pose.set_if_neq(Pose(model.0.pose(clip, t)));
    }
}

/// Places every model part from its model's transform and pose: a rigid part at its node, a
/// skinned part at the model with the joint matrices of its skin and bounds from the pose.
#[allow(clippy::type_complexity)]
pub fn pose_parts(
    models: Query<(&ModelInstance, &Transform, &Pose), Without<ModelPart>>,
    mut parts: Query<(&ModelPart, &mut Transform, Option<&mut Joints>, &mut WorldBounds), Without<ModelInstance>>,
) {
    for (link, mut transform, joints, mut bounds) in &mut parts {
        let Ok((model, placement, pose)) = models.get(link.root) else { continue };
        let (Some(part), false) = (model.0.parts.get(link.part), pose.0.is_empty()) else { continue };
        match (part.skin, joints) {
            (Some(skin), Some(mut joints)) => {
                transform.set_if_neq(*placement);
                joints.set_if_neq(Joints(model.0.joint_matrices(skin, &pose.0)));
                bounds.set_if_neq(WorldBounds(model.0.part_bounds(part, &pose.0, &placement.matrix())));
            }
            _ => {
                let (scale, rotation, translation) =
                    (placement.matrix() * pose.0[part.node]).to_scale_rotation_translation();
                transform.set_if_neq(Transform { translation, rotation, scale });
            }
        }
    }
}

/// Places every entity hung on a model's node (a file's light) where its model's transform and
/// pose put the node, unscaled; a directional light also turns to shine along the node's -Z axis.
pub fn follow_nodes(
    models: Query<(&Transform, &Pose), With<ModelInstance>>,
    mut hung: Query<(&AtNode, &mut Transform, Option<&mut DirectionalLight>), Without<ModelInstance>>,
) {
    for (at, mut transform, sun) in &mut hung {
        let Ok((placement, pose)) = models.get(at.root) else { continue };
        let Some(node) = pose.0.get(at.node) else { continue };
        let (_, rotation, translation) = (placement.matrix() * *node).to_scale_rotation_translation();
        transform.set_if_neq(Transform { translation, rotation, scale: Vec3::ONE });
        if let Some(mut sun) = sun {
            let direction = rotation * Vec3::NEG_Z;
            sun.set_if_neq(DirectionalLight { direction, ..*sun });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assets::parse_model;
    use bevy_ecs::system::RunSystemOnce;
    use std::sync::Arc;

    fn at_time(t: f64) -> World {
        let mut world = World::new();
        world.insert_resource(Time { t, dt: 1.0 / 60.0, frame: 0, updates: 0 });
        world
    }

    #[test]
    fn a_walker_goes_round_its_circle_facing_ahead() {
        let mut world = at_time(std::f64::consts::PI);
        let walker = Walker { center: Vec3::new(1.0, 0.0, 2.0), radius: 2.0, speed: 1.0, phase: 0.0 };
        let e = world.spawn((walker, Transform::default())).id();
        world.run_system_once(walk).unwrap();
        // π metres at 1 m/s on a 2 m circle is a quarter turn: from +X to +Z of the centre.
        let t = *world.get::<Transform>(e).unwrap();
        assert!(t.translation.abs_diff_eq(Vec3::new(1.0, 0.0, 4.0), 1e-5), "{t:?}");
        let front = t.rotation * Vec3::Z;
        assert!(front.abs_diff_eq(Vec3::NEG_X, 1e-5), "going on round, it faces -X: {front:?}");
    }

    fn character() -> Arc<crate::assets::Model> {
        Arc::new(parse_model(&crate::assets::character::character_glb(), None, "character").unwrap())
    }

    #[test]
    fn parts_follow_the_pose_and_their_bounds_hold_the_skinned_mesh() {
        let model = character();
        let mut world = at_time(0.3);
        let placement = Transform::from_xyz(5.0, 0.0, -2.0).with_rotation(Quat::from_rotation_y(2.0));
        let root = world.spawn((ModelInstance(model.clone()), Animator { clip: Some(0), speed: 1.0 }, placement)).id();
        let part = world
            .spawn((ModelPart { root, part: 2 }, Transform::default(), Joints::default(), WorldBounds::default()))
            .id();
        world.run_system_once(animate_models).unwrap();
        world.run_system_once(pose_parts).unwrap();
        let joints = &world.get::<Joints>(part).unwrap().0;
        assert_eq!(joints.len(), 14);
        assert_eq!(*world.get::<Transform>(part).unwrap(), placement);
        let bounds = world.get::<WorldBounds>(part).unwrap().0;
        let posed = crate::assets::skin::skin_vertices(&model.parts[2].mesh, joints);
        for v in posed {
            let p = placement.matrix().transform_point3(Vec3::from(v.position));
            assert!(p.cmpge(bounds.min - 1e-4).all() && p.cmple(bounds.max + 1e-4).all(), "{p:?} outside {bounds:?}");
        }
    }

    #[test]
    fn lights_hung_on_nodes_follow_them() {
        let model = character();
        let mut world = at_time(0.3);
        let placement = Transform::from_xyz(5.0, 0.0, -2.0).with_rotation(Quat::from_rotation_y(2.0));
        let root = world.spawn((ModelInstance(model.clone()), Animator { clip: Some(0), speed: 1.0 }, placement)).id();
        let node = model.nodes.len() - 1;
        let lamp = world.spawn((AtNode { root, node }, Transform::default())).id();
        let sun = world.spawn((AtNode { root, node }, Transform::default(), DirectionalLight::default())).id();
        world.run_system_once(animate_models).unwrap();
        world.run_system_once(follow_nodes).unwrap();
        let pose = world.get::<Pose>(root).unwrap().0[node];
        let (_, rotation, translation) = (placement.matrix() * pose).to_scale_rotation_translation();
        let t = *world.get::<Transform>(lamp).unwrap();
        assert!(t.translation.abs_diff_eq(translation, 1e-5) && t.scale == Vec3::ONE, "{t:?}");
        let d = world.get::<DirectionalLight>(sun).unwrap().direction;
        assert!(d.abs_diff_eq(rotation * Vec3::NEG_Z, 1e-5), "{d:?}");
        // A link to something that is not a model leaves the entity where it is.
        let stray = world.spawn((AtNode { root: lamp, node: 0 }, Transform::from_xyz(1.0, 2.0, 3.0))).id();
        world.run_system_once(follow_nodes).unwrap();
        assert_eq!(world.get::<Transform>(stray).unwrap().translation, Vec3::new(1.0, 2.0, 3.0));
    }

    #[test]
    fn a_still_pose_is_not_rewritten() {
        let mut world = at_time(0.0);
        let root = world.spawn((ModelInstance(character()), Animator { clip: None, speed: 1.0 })).id();
        let mut schedule = Schedule::default();
        schedule.add_systems(animate_models);
        schedule.run(&mut world);
        world.clear_trackers();
        world.resource_mut::<Time>().t = 5.0;
        schedule.run(&mut world);
        assert!(!world.entity(root).get_ref::<Pose>().unwrap().is_changed(), "the rest pose does not change");
    }
}
