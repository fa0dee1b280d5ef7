//! The cameras: the fly camera (WASD to move, mouse to look, Shift to go faster) and the orbit
//! camera (drag to turn round a focus, wheel to zoom), one of them steering at a time.

use crate::components::{FlyCamera, Input, Key, OrbitCamera, OrbitFocus, Time, Transform};
use bevy_ecs::prelude::*;
use glam::{Quat, Vec3};

/// How much faster the camera moves while [`Key::Fast`] is held.
pub const FAST_FACTOR: f32 = 4.0;
const PITCH_LIMIT: f32 = 1.55;
/// Closest and farthest an orbit camera goes from its focus, in metres.
pub const ORBIT_DISTANCE: (f32, f32) = (0.5, 500.0);
/// Share of the distance one wheel step takes off.
const ZOOM_STEP: f32 = 0.1;

/// Turns and moves every fly camera by this step's input (not while its orbit camera steers).
pub fn fly_camera(
    time: Res<Time>,
    input: Res<Input>,
    mut query: Query<(&mut FlyCamera, &mut Transform, Option<&OrbitCamera>)>,
) {
    for (mut fly, mut transform, orbit) in &mut query {
        if orbit.is_some_and(|o| o.active) {
            continue;
        }
        fly.yaw -= input.look_delta.x * fly.sensitivity;
        fly.pitch = (fly.pitch - input.look_delta.y * fly.sensitivity).clamp(-PITCH_LIMIT, PITCH_LIMIT);
        transform.rotation = fly.rotation();
        let axis = |plus: Key, minus: Key| input.pressed(plus) as i32 as f32 - input.pressed(minus) as i32 as f32;
        let forward = transform.rotation * Vec3::NEG_Z;
        let right = transform.rotation * Vec3::X;
        let wish = forward * axis(Key::Forward, Key::Back)
            + right * axis(Key::Right, Key::Left)
            + Vec3::Y * axis(Key::Up, Key::Down);
        let speed = fly.speed * if input.pressed(Key::Fast) { FAST_FACTOR } else { 1.0 };
        transform.translation += wish.normalize_or_zero() * speed * time.dt;
    }
}

/// Turns every active orbit camera by this step's drag and wheel, and places it at its distance
/// from its focus, looking at it. The fly camera's yaw and pitch follow, so switching back to it
/// keeps the view.
pub fn orbit_camera(
    input: Res<Input>,
    foci: Query<&Transform, Without<OrbitCamera>>,
    mut query: Query<(&mut OrbitCamera, &mut Transform, Option<&mut FlyCamera>)>,
) {
    for (mut orbit, mut transform, fly) in &mut query {
        if !orbit.active {
            continue;
        }
        orbit.yaw -= input.drag_delta.x * orbit.sensitivity;
        orbit.pitch = (orbit.pitch - input.drag_delta.y * orbit.sensitivity).clamp(-PITCH_LIMIT, PITCH_LIMIT);
        let zoomed = orbit.distance * (1.0 - ZOOM_STEP).powf(input.zoom);
        orbit.distance =
            if zoomed.is_finite() { zoomed.clamp(ORBIT_DISTANCE.0, ORBIT_DISTANCE.1) } else { orbit.distance };
        let focus = focus_point(orbit.focus, &foci);
        *transform = orbit_pose(focus, orbit.yaw, orbit.pitch, orbit.distance).with_scale(transform.scale);
        if let Some(mut fly) = fly {
            (fly.yaw, fly.pitch) = (orbit.yaw, orbit.pitch);
        }
    }
}

/// Where an orbit camera's focus is now (the scene's middle when its entity is gone).
fn focus_point(focus: OrbitFocus, foci: &Query<&Transform, Without<OrbitCamera>>) -> Vec3 {
    match focus {
        OrbitFocus::Point(p) => p,
        OrbitFocus::Entity(e, above) => foci.get(e).map_or(Vec3::Y, |t| t.translation + Vec3::Y * above),
    }
}

/// The pose `distance` metres from `focus`, turned by `yaw` and `pitch` (as a fly camera's), looking at it.
#[must_use]
pub fn orbit_pose(focus: Vec3, yaw: f32, pitch: f32, distance: f32) -> Transform {
    let rotation = Quat::from_rotation_y(yaw) * Quat::from_rotation_x(pitch);
    Transform { translation: focus - rotation * Vec3::NEG_Z * distance, rotation, ..Default::default() }
}

/// The yaw, pitch and distance that put a camera at `eye` looking at `focus` (straight down when
/// they are the same point).
#[must_use]
pub fn orbit_facing(eye: Vec3, focus: Vec3) -> (f32, f32, f32) {
    let to = focus - eye;
    let distance = to.length();
    if !distance.is_finite() || distance <= 1e-4 {
        return (0.0, -PITCH_LIMIT, ORBIT_DISTANCE.0);
    }
    let pitch = (to.y / distance).clamp(-1.0, 1.0).asin().clamp(-PITCH_LIMIT, PITCH_LIMIT);
    ((-to.x).atan2(-to.z), pitch, distance.clamp(ORBIT_DISTANCE.0, ORBIT_DISTANCE.1))
}

/// Steps the camera to its next mode: fly → orbit round the scene's middle → orbit round the
/// walking character (where there is one) → fly; the new mode in a few words. The view turns to
/// face the new focus; going back to the fly camera keeps the view.
pub fn switch_camera(world: &mut World) -> &'static str {
    let character = world
        .query_filtered::<Entity, (With<crate::components::Walker>, With<crate::assets::ModelInstance>)>()
        .iter(world)
        .next();
    let mut cameras =
        world.query_filtered::<(Entity, Option<&OrbitCamera>, &Transform), With<crate::components::Camera>>();
    let Some((camera, orbit, eye)) = cameras.iter(world).next().map(|(e, o, t)| (e, o.copied(), t.translation)) else {
        return "no camera";
    };
    let middle = OrbitCamera::default().focus;
    let next = match orbit.filter(|o| o.active).map(|o| o.focus) {
        None => Some((middle, "orbit round the scene's middle")),
        Some(OrbitFocus::Point(_)) => character.map(|c| (OrbitFocus::Entity(c, 1.0), "orbit round the character")),
        Some(OrbitFocus::Entity(..)) => None,
    };
    let Some((focus, name)) = next else {
        if let Some(mut o) = world.get_mut::<OrbitCamera>(camera) {
            o.active = false;
        }
        return "fly camera";
    };
    let at = match focus {
        OrbitFocus::Point(p) => p,
        OrbitFocus::Entity(e, above) => world.get::<Transform>(e).map_or(Vec3::Y, |t| t.translation + Vec3::Y * above),
    };
    let (yaw, pitch, distance) = orbit_facing(eye, at);
    let base = orbit.unwrap_or_default();
    world.entity_mut(camera).insert(OrbitCamera { active: true, focus, yaw, pitch, distance, ..base });
    name
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy_ecs::system::RunSystemOnce;
    use glam::Vec2;

    fn run(input: Input, fly: FlyCamera) -> (FlyCamera, Transform) {
        let mut world = World::new();
        world.insert_resource(Time { t: 0.0, dt: 0.5, frame: 0, updates: 0 });
        world.insert_resource(input);
        let e = world.spawn((fly, Transform::default())).id();
        world.run_system_once(fly_camera).unwrap();
        (*world.get::<FlyCamera>(e).unwrap(), *world.get::<Transform>(e).unwrap())
    }

    #[test]
    fn forward_moves_along_the_view_by_speed_times_dt() {
        let mut input = Input::default();
        input.set(Key::Forward, true);
        let (_, t) = run(input, FlyCamera::new(0.0, 0.0));
        // 6 m/s for 0.5 s along -Z.
        assert!((t.translation - Vec3::new(0.0, 0.0, -3.0)).length() < 1e-5, "{:?}", t.translation);
    }

    #[test]
    fn shift_is_faster_and_diagonals_are_not() {
        let mut input = Input::default();
        input.set(Key::Forward, true);
        input.set(Key::Right, true);
        input.set(Key::Fast, true);
        let (_, t) = run(input, FlyCamera::new(0.0, 0.0));
        assert!((t.translation.length() - 3.0 * FAST_FACTOR).abs() < 1e-4);
        assert!(t.translation.x > 0.0 && t.translation.z < 0.0);
    }

    #[test]
    fn mouse_turns_and_pitch_is_clamped() {
        let input = Input { look_delta: Vec2::new(100.0, -10_000.0), ..Default::default() };
        let (fly, t) = run(input, FlyCamera::new(0.0, 0.0));
        assert!((fly.yaw + 0.3).abs() < 1e-6);
        assert_eq!(fly.pitch, PITCH_LIMIT);
        assert!(t.rotation.abs_diff_eq(fly.rotation(), 1e-6));
        assert_eq!(t.translation, Vec3::ZERO);
    }

    fn orbit(input: Input, orbit: OrbitCamera) -> (OrbitCamera, Transform) {
        let mut world = World::new();
        world.insert_resource(input);
        let e = world.spawn((orbit, FlyCamera::new(0.0, 0.0), Transform::default())).id();
        world.run_system_once(orbit_camera).unwrap();
        (*world.get::<OrbitCamera>(e).unwrap(), *world.get::<Transform>(e).unwrap())
    }

    #[test]
    fn the_orbit_camera_looks_at_its_focus_from_its_distance() {
        let focus = Vec3::new(1.0, 2.0, 3.0);
        let start = OrbitCamera { active: true, focus: OrbitFocus::Point(focus), distance: 5.0, ..Default::default() };
        let drag = Input { drag_delta: glam::Vec2::new(40.0, -25.0), zoom: 2.0, ..Default::default() };
        let (o, t) = orbit(drag, start);
        assert!((o.distance - 5.0 * 0.81).abs() < 1e-4, "two wheel steps in: {}", o.distance);
        assert!(((t.translation - focus).length() - o.distance).abs() < 1e-4);
        assert!((t.forward() - (focus - t.translation).normalize()).length() < 1e-4, "it looks at the focus");
        assert!(o.yaw < 0.0 && o.pitch > start.pitch, "dragging turns it");
        // Facing recovers the orbit from the pose.
        let (yaw, pitch, distance) = orbit_facing(t.translation, focus);
        assert!((yaw - o.yaw).abs() < 1e-4 && (pitch - o.pitch).abs() < 1e-4 && (distance - o.distance).abs() < 1e-3);
    }

    #[test]
    fn odd_orbit_input_keeps_the_camera_finite_and_in_range() {
        let start = OrbitCamera { active: true, ..Default::default() };
        for zoom in [f32::NAN, f32::INFINITY, -f32::INFINITY, 1e9, -1e9] {
            let (o, t) = orbit(Input { zoom, drag_delta: glam::Vec2::new(0.0, 1e9), ..Default::default() }, start);
            assert!((ORBIT_DISTANCE.0..=ORBIT_DISTANCE.1).contains(&o.distance), "zoom {zoom}: {}", o.distance);
            assert!(o.pitch.abs() <= PITCH_LIMIT && t.translation.is_finite() && t.rotation.is_finite());
        }
        assert_eq!(orbit_facing(Vec3::ONE, Vec3::ONE), (0.0, -PITCH_LIMIT, ORBIT_DISTANCE.0), "eye on the focus");
        assert_eq!(orbit_facing(Vec3::NAN, Vec3::ONE).2, ORBIT_DISTANCE.0);
    }

    #[test]
    fn only_one_camera_steers() {
        let mut world = World::new();
        world.insert_resource(Time { t: 0.0, dt: 0.5, frame: 0, updates: 0 });
        let mut input = Input { drag_delta: glam::Vec2::new(50.0, 0.0), ..Default::default() };
        input.set(Key::Forward, true);
        world.insert_resource(input);
        let idle = OrbitCamera::default();
        let e = world.spawn((idle, FlyCamera::new(0.0, 0.0), Transform::default())).id();
        let mut schedule = Schedule::default();
        schedule.add_systems((fly_camera, orbit_camera).chain());
        schedule.run(&mut world);
        assert_eq!(*world.get::<OrbitCamera>(e).unwrap(), idle, "an idle orbit camera ignores the drag");
        assert!(world.get::<Transform>(e).unwrap().translation.z < 0.0, "the fly camera moved");
        world.get_mut::<OrbitCamera>(e).unwrap().active = true;
        schedule.run(&mut world);
        let (t, o) = (*world.get::<Transform>(e).unwrap(), *world.get::<OrbitCamera>(e).unwrap());
        assert_eq!(t, orbit_pose(Vec3::new(0.0, 1.0, 0.0), o.yaw, o.pitch, o.distance), "W moves nothing now");
        assert_eq!(world.get::<FlyCamera>(e).unwrap().yaw, o.yaw, "the fly camera keeps the view");
    }

    #[test]
    fn the_camera_key_steps_fly_orbit_character_fly() {
        let mut world = World::new();
        world.insert_resource(Time::default());
        world.insert_resource(Input::default());
        let cam = world
            .spawn((
                crate::components::Camera::default(),
                FlyCamera::new(0.0, 0.0),
                Transform::from_xyz(0.0, 5.0, 10.0),
            ))
            .id();
        assert_eq!(switch_camera(&mut world), "orbit round the scene's middle");
        let o = *world.get::<OrbitCamera>(cam).unwrap();
        assert!(o.active && (o.distance - Vec3::new(0.0, 4.0, 10.0).length()).abs() < 1e-4);
        assert_eq!(switch_camera(&mut world), "fly camera", "no character: straight back to flying");
        assert!(!world.get::<OrbitCamera>(cam).unwrap().active);
        let model = std::sync::Arc::new(crate::assets::Model::default());
        let walker = crate::components::Walker { center: Vec3::ZERO, radius: 1.0, speed: 1.0, phase: 0.0 };
        world.spawn((crate::assets::ModelInstance(model), walker, Transform::from_xyz(2.0, 0.0, 0.0)));
        switch_camera(&mut world);
        assert_eq!(switch_camera(&mut world), "orbit round the character");
        let mut schedule = Schedule::default();
        schedule.add_systems(orbit_camera);
        schedule.run(&mut world);
        let t = *world.get::<Transform>(cam).unwrap();
        let to_focus = (Vec3::new(2.0, 1.0, 0.0) - t.translation).normalize();
        assert!((t.forward() - to_focus).length() < 1e-4, "it looks at the character's chest");
        assert_eq!(switch_camera(&mut world), "fly camera");
    }
}
