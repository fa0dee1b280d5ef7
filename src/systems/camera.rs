//! The fly camera: WASD to move, mouse to look, Shift to go faster.

use crate::components::{FlyCamera, Input, Key, Time, Transform};
use bevy_ecs::prelude::*;
use glam::Vec3;

/// How much faster the camera moves while [`Key::Fast`] is held.
pub const FAST_FACTOR: f32 = 4.0;
const PITCH_LIMIT: f32 = 1.55;

/// Turns and moves every fly camera by this step's input.
pub fn fly_camera(time: Res<Time>, input: Res<Input>, mut query: Query<(&mut FlyCamera, &mut Transform)>) {
    for (mut fly, mut transform) in &mut query {
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

#[cfg(test)]
mod tests {
    use super::*;
    use bevy_ecs::system::RunSystemOnce;
    use glam::Vec2;

    fn run(input: Input, fly: FlyCamera) -> (FlyCamera, Transform) {
        let mut world = World::new();
        world.insert_resource(Time { t: 0.0, dt: 0.5, frame: 0 });
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
        let input = Input { held: vec![], look_delta: Vec2::new(100.0, -10_000.0) };
        let (fly, t) = run(input, FlyCamera::new(0.0, 0.0));
        assert!((fly.yaw + 0.3).abs() < 1e-6);
        assert_eq!(fly.pitch, PITCH_LIMIT);
        assert!(t.rotation.abs_diff_eq(fly.rotation(), 1e-6));
        assert_eq!(t.translation, Vec3::ZERO);
    }
}
