//! Animation clips: keyframed translation, rotation and scale of nodes, sampled at any time.
//!
//! The three interpolations of glTF: STEP holds a key until the next, LINEAR blends (rotations
//! along the shorter arc), CUBICSPLINE follows a Hermite curve through each key with the key's
//! own in and out tangents.

use crate::components::Transform;
use glam::{Quat, Vec4};

/// How values between two keys are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The earlier key's value until the next key.
    Step,
    /// A straight blend; rotations are slerped along the shorter arc.
    Linear,
    /// A cubic Hermite spline; each key stores an in-tangent, a value and an out-tangent.
    CubicSpline,
}

/// Which part of a node's transform a channel drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    /// Translation (xyz).
    Translation,
    /// Rotation (a quaternion, xyzw).
    Rotation,
    /// Scale (xyz).
    Scale,
}

/// Keys for one property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The node it moves.
    pub node: usize,
    /// What it moves.
    pub property: Property,
    /// How it blends between keys.
    pub interpolation: Interpolation,
    /// Key times in seconds, non-decreasing.
    pub times: Vec<f32>,
    /// One value per key (three per key for [`Interpolation::CubicSpline`]: in-tangent, value,
    /// out-tangent); vectors use xyz and leave w at 0.
    pub values: Vec<Vec4>,
}

/// A named set of channels that loops over its duration.
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    /// Its name in the file (or "animation N").
    pub name: String,
    /// Every keyed property.
    pub channels: Vec<Channel>,
    /// The last key time of any channel: the clip repeats after this.
    pub duration: f32,
}

impl Channel {
    /// The value at `t` seconds: held at the first key before it and at the last key after it.
    pub fn sample(&self, t: f32) -> Vec4 {
        let n = self.times.len();
        let value = |k: usize| match self.interpolation {
            Interpolation::CubicSpline => self.values[3 * k + 1],
            _ => self.values[k],
        };
        if n == 0 {
            return Vec4::ZERO;
        }
        // The first key after t; keys before it are at or before t.
        let next = self.times.partition_point(|&k| k <= t);
        if next == 0 {
            return value(0);
        }
        if next == n {
            return value(n - 1);
        }
        let k = next - 1;
        let dt = self.times[next] - self.times[k];
        if dt.is_nan() || dt <= 0.0 {
            return value(next);
        }
        let s = (t - self.times[k]) / dt;
        match self.interpolation {
            Interpolation::Step => value(k),
            Interpolation::Linear if self.property == Property::Rotation => {
                Vec4::from(slerp_short(quat(value(k)), quat(value(next)), s))
            }
            Interpolation::Linear => value(k).lerp(value(next), s),
            Interpolation::CubicSpline => {
                let (v0, out0) = (self.values[3 * k + 1], self.values[3 * k + 2]);
                let (in1, v1) = (self.values[3 * next], self.values[3 * next + 1]);
                let v = hermite(v0, out0 * dt, v1, in1 * dt, s);
                if self.property == Property::Rotation { Vec4::from(quat(v).normalize()) } else { v }
            }
        }
    }

    /// Writes the value at `t` into the node's local transform.
    pub fn apply(&self, t: f32, local: &mut Transform) {
        let v = self.sample(t);
        match self.property {
            Property::Translation => local.translation = v.truncate(),
            Property::Rotation => local.rotation = quat(v).normalize(),
            Property::Scale => local.scale = v.truncate(),
        }
    }
}

impl Clip {
    /// Poses `locals` (one transform per node, already at rest) as the clip has them at `t`
    /// seconds, looping: `t` is wrapped into `[0, duration)`.
    pub fn apply(&self, t: f32, locals: &mut [Transform]) {
        let t = if self.duration > 0.0 && t.is_finite() { t.rem_euclid(self.duration) } else { 0.0 };
        for channel in &self.channels {
            if let Some(local) = locals.get_mut(channel.node) {
                channel.apply(t, local);
            }
        }
    }
}

fn quat(v: Vec4) -> Quat {
    Quat::from_vec4(v)
}

/// Spherical blend from `a` to `b` that never goes the long way round.
fn slerp_short(a: Quat, b: Quat, s: f32) -> Quat {
    let b = if a.dot(b) < 0.0 { -b } else { b };
    a.slerp(b, s).normalize()
}

/// Cubic Hermite curve from `p0` (tangent `m0`) to `p1` (tangent `m1`) at `s` in 0..1; the
/// tangents are already scaled by the interval.
fn hermite(p0: Vec4, m0: Vec4, p1: Vec4, m1: Vec4, s: f32) -> Vec4 {
    let (s2, s3) = (s * s, s * s * s);
    p0 * (2.0 * s3 - 3.0 * s2 + 1.0) + m0 * (s3 - 2.0 * s2 + s) + p1 * (-2.0 * s3 + 3.0 * s2) + m1 * (s3 - s2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn vec3_value(v: Vec3) -> Vec4 {
        v.extend(0.0)
    }

    fn channel(property: Property, interpolation: Interpolation, times: &[f32], values: &[Vec4]) -> Channel {
        Channel { node: 0, property, interpolation, times: times.to_vec(), values: values.to_vec() }
    }

    fn translation(interpolation: Interpolation) -> Channel {
        let values = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(2.0, 4.0, 0.0)].map(vec3_value);
        channel(Property::Translation, interpolation, &[0.0, 1.0, 3.0], &values)
    }

    #[test]
    fn keys_are_returned_exactly_and_held_outside_the_range() {
        for interpolation in [Interpolation::Step, Interpolation::Linear] {
            let c = translation(interpolation);
            assert_eq!(c.sample(0.0), Vec4::ZERO);
            assert_eq!(c.sample(1.0), Vec4::new(2.0, 0.0, 0.0, 0.0));
            assert_eq!(c.sample(3.0), Vec4::new(2.0, 4.0, 0.0, 0.0));
            assert_eq!(c.sample(-1.0), Vec4::ZERO);
            assert_eq!(c.sample(9.0), Vec4::new(2.0, 4.0, 0.0, 0.0));
        }
    }

    #[test]
    fn linear_blends_and_step_holds() {
        let c = translation(Interpolation::Linear);
        assert!(c.sample(2.0).abs_diff_eq(Vec4::new(2.0, 2.0, 0.0, 0.0), 1e-6));
        assert!(c.sample(0.25).abs_diff_eq(Vec4::new(0.5, 0.0, 0.0, 0.0), 1e-6));
        let c = translation(Interpolation::Step);
        assert_eq!(c.sample(2.9), Vec4::new(2.0, 0.0, 0.0, 0.0));
    }

    #[test]
    fn rotations_take_the_shorter_arc() {
        // +170° and -170° about Y are 20° apart the short way; the midpoint is 180°, not 0°.
        let a = Quat::from_rotation_y(170f32.to_radians());
        let b = Quat::from_rotation_y(-170f32.to_radians());
        let c = channel(Property::Rotation, Interpolation::Linear, &[0.0, 1.0], &[Vec4::from(a), Vec4::from(b)]);
        let mid = quat(c.sample(0.5));
        let half_turn = Quat::from_rotation_y(std::f32::consts::PI);
        assert!(mid.angle_between(half_turn) < 1e-3, "{mid:?}");
        // The same two keys stored with opposite signs (the same rotations) blend the same way.
        let c = channel(Property::Rotation, Interpolation::Linear, &[0.0, 1.0], &[Vec4::from(a), Vec4::from(-b)]);
        assert!(quat(c.sample(0.5)).angle_between(half_turn) < 1e-3);
    }

    #[test]
    fn cubic_spline_uses_its_tangents() {
        // A scalar path 0 -> 1 over 2 s with zero tangents: smoothstep, so 0.5 at the middle and
        // 0.15625 at a quarter; with out-tangent 1 at the start it leaves along slope 1.
        let v = |x: f32| Vec4::new(x, 0.0, 0.0, 0.0);
        let flat = [v(0.0), v(0.0), v(0.0), v(0.0), v(1.0), v(0.0)];
        let c = channel(Property::Translation, Interpolation::CubicSpline, &[0.0, 2.0], &flat);
        assert!((c.sample(1.0).x - 0.5).abs() < 1e-6);
        assert!((c.sample(0.5).x - 0.15625).abs() < 1e-6);
        assert_eq!(c.sample(2.0).x, 1.0, "the key itself, not a tangent");
        let sloped = [v(0.0), v(0.0), v(1.0), v(0.0), v(1.0), v(0.0)];
        let c = channel(Property::Translation, Interpolation::CubicSpline, &[0.0, 2.0], &sloped);
        let slope = (c.sample(1e-3).x - c.sample(0.0).x) / 1e-3;
        assert!((slope - 1.0).abs() < 1e-2, "{slope}");
        // Hermite with m0 = 1·dt: p(s) = -2s³ + 3s² + 2(s³ - 2s² + s); at s = 0.5 that is 0.75.
        assert!((c.sample(1.0).x - 0.75).abs() < 1e-6);
    }

    #[test]
    fn clips_loop() {
        let clip = Clip { name: "walk".into(), channels: vec![translation(Interpolation::Linear)], duration: 3.0 };
        let at = |t: f32| {
            let mut locals = [Transform::default()];
            clip.apply(t, &mut locals);
            locals[0].translation
        };
        assert!(at(2.0).abs_diff_eq(at(5.0), 1e-5));
        assert!(at(0.5).abs_diff_eq(at(-2.5), 1e-5));
        assert_eq!(at(f32::NAN), Vec3::ZERO);
    }
}
