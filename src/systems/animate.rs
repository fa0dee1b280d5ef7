//! Animation of the sample's cubes: a pure function of time, so any frame can be reproduced.

use crate::components::{Bob, Spin, Time, Transform};
use bevy_ecs::prelude::*;
use glam::Quat;

/// Sets each spinning entity's rotation for the current time.
pub fn spin(time: Res<Time>, mut query: Query<(&Spin, &mut Transform)>) {
    for (spin, mut transform) in &mut query {
        let angle = (spin.rate as f64 * time.t) % std::f64::consts::TAU;
        transform.rotation = Quat::from_axis_angle(spin.axis, angle as f32) * spin.base;
    }
}

/// Sets each bobbing entity's height for the current time.
pub fn bob(time: Res<Time>, mut query: Query<(&Bob, &mut Transform)>) {
    for (bob, mut transform) in &mut query {
        let phase = (bob.frequency as f64 * time.t + bob.phase as f64) % std::f64::consts::TAU;
        transform.translation.y = bob.base_y + bob.amplitude * (phase as f32).sin();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy_ecs::system::RunSystemOnce;
    use glam::Vec3;

    fn world_at(t: f64) -> World {
        let mut world = World::new();
        world.insert_resource(Time { t, dt: 0.25, frame: 0 });
        world
    }

    #[test]
    fn spin_at_a_fixed_step_gives_the_exact_rotation() {
        let mut world = world_at(0.0);
        let axis = Vec3::new(0.0, 1.0, 0.0);
        let e = world.spawn((Spin { axis, rate: 0.5, base: Quat::IDENTITY }, Transform::default())).id();
        let mut schedule = Schedule::default();
        schedule.add_systems(spin);
        for step in 1..=8 {
            world.resource_mut::<Time>().t = step as f64 * 0.25;
            schedule.run(&mut world);
        }
        // 8 steps of 0.25 s at 0.5 rad/s is exactly 1 radian.
        let got = world.get::<Transform>(e).unwrap().rotation;
        let want = Quat::from_axis_angle(axis, 1.0);
        assert!(got.abs_diff_eq(want, 1e-6), "{got:?} vs {want:?}");
    }

    #[test]
    fn bob_follows_the_sine() {
        let mut world = world_at(std::f64::consts::FRAC_PI_2);
        let b = Bob { base_y: 2.0, amplitude: 0.5, frequency: 1.0, phase: 0.0 };
        let e = world.spawn((b, Transform::from_xyz(3.0, 0.0, -1.0))).id();
        world.run_system_once(bob).unwrap();
        let t = world.get::<Transform>(e).unwrap().translation;
        assert!((t - Vec3::new(3.0, 2.5, -1.0)).length() < 1e-6, "{t:?}");
    }
}
