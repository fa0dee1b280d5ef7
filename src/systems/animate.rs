//! Animation of the sample's cubes: a pure function of time, so any frame can be reproduced.

use crate::components::{Bob, Spin, Time, Transform};
use bevy_ecs::prelude::*;
use glam::Quat;

/// `x` radians brought into `0..TAU`, in f64 so that the time steps stay exact however long the
/// scene runs. Whole turns are taken off by truncation, a fraction of the cost of `%` (a software
/// fmod), which is kept for the huge times where the truncation's rounding would leave the range.
#[must_use]
fn wrap_angle(x: f64) -> f32 {
    use std::f64::consts::TAU;
    let mut wrapped = x - (x / TAU) as i64 as f64 * TAU;
    if wrapped < 0.0 {
        wrapped += TAU;
    }
    if (0.0..TAU).contains(&wrapped) { wrapped as f32 } else { wrap_exactly(x) }
}

/// [`wrap_angle`] for huge or broken `x`; apart, so that the optimiser does not work out the
/// fmod on every call and then throw it away.
#[cold]
#[inline(never)]
fn wrap_exactly(x: f64) -> f32 {
    x.rem_euclid(std::f64::consts::TAU) as f32
}

/// Sets each spinning entity's rotation for the current time.
pub fn spin(time: Res<Time>, mut query: Query<(&Spin, &mut Transform)>) {
    for (spin, mut transform) in &mut query {
        let angle = wrap_angle(spin.rate as f64 * time.t);
        transform.rotation = Quat::from_axis_angle(spin.axis, angle) * spin.base;
    }
}

/// Sets each bobbing entity's height for the current time.
pub fn bob(time: Res<Time>, mut query: Query<(&Bob, &mut Transform)>) {
    for (bob, mut transform) in &mut query {
        let phase = wrap_angle(bob.frequency as f64 * time.t + bob.phase as f64);
        transform.translation.y = bob.base_y + bob.amplitude * phase.sin();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy_ecs::system::RunSystemOnce;
    use glam::Vec3;

    fn world_at(t: f64) -> World {
        let mut world = World::new();
        world.insert_resource(Time { t, dt: 0.25, frame: 0, updates: 0 });
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
    fn angles_wrap_into_one_turn_for_odd_inputs() {
        use std::f64::consts::TAU;
        assert_eq!(wrap_angle(0.0), 0.0);
        assert!((wrap_angle(TAU + 1.0) - 1.0).abs() < 1e-6);
        assert!((wrap_angle(-1.0) - (TAU - 1.0) as f32).abs() < 1e-6);
        for x in [1e7, -1e7, 1e15, 1e300, -1e300, f64::MAX, f64::MIN_POSITIVE, -0.0] {
            let w = wrap_angle(x);
            assert!(w.is_finite() && w.abs() < TAU as f32 + 1e-6, "{x}: {w}");
            let fmod = (x % TAU) as f32;
            let same = (w - fmod).abs() < 1e-3 || (w - fmod).abs() > TAU as f32 - 1e-3;
            assert!(same || x.abs() >= 1e12, "{x}: {w} against fmod {fmod}");
        }
        assert!(wrap_angle(f64::NAN).is_nan() && wrap_angle(f64::INFINITY).is_nan());
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
