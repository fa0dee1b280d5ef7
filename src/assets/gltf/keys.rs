//! Animation clips from a file's samplers: key times and values checked by name (a NaN key, time
//! running backwards, a rotation of length 0), rotations made unit, and the quirks real files
//! have (equal key times, channels without a target node) taken with a warning.

use super::accessor::{Data, FLOAT, FLOAT_OR_NORM, check_format, components};
use crate::assets::clip::{Channel, Clip, Interpolation, Property};
use glam::{Vec3, Vec4};

/// The clip of animation `a`; channels in `untargeted` name no node and are skipped.
pub(super) fn clip(
    a: &gltf::Animation<'_>,
    data: &Data<'_>,
    untargeted: &[(usize, usize)],
    warnings: &mut Vec<String>,
) -> Result<Clip, String> {
    let name = a.name().map_or_else(|| format!("animation {}", a.index()), str::to_string);
    let mut channels = Vec::new();
    for c in a.channels() {
        let at = format!("animation {} channel {}", a.index(), c.index());
        if untargeted.contains(&(a.index(), c.index())) {
            warnings.push(format!("{at} targets no node (an extension's target, perhaps); ignored"));
            continue;
        }
        let property = match c.target().property() {
            gltf::animation::Property::Translation => Property::Translation,
            gltf::animation::Property::Rotation => Property::Rotation,
            gltf::animation::Property::Scale => Property::Scale,
            gltf::animation::Property::MorphTargetWeights => {
                warnings.push(format!("{at}: morph target weights are ignored"));
                continue;
            }
        };
        let channel = channel(&c, property, data, warnings).map_err(|e| format!("{at}: {e}"))?;
        channels.push(channel);
    }
    let duration = channels.iter().filter_map(|c| c.times.last()).fold(0.0f32, |a, &b| a.max(b));
    Ok(Clip { name, channels, duration })
}

/// One channel's keys, checked.
fn channel(
    c: &gltf::animation::Channel<'_>,
    property: Property,
    data: &Data<'_>,
    warnings: &mut Vec<String>,
) -> Result<Channel, String> {
    let sampler = c.sampler();
    let interpolation = match sampler.interpolation() {
        gltf::animation::Interpolation::Step => Interpolation::Step,
        gltf::animation::Interpolation::Linear => Interpolation::Linear,
        gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
    };
    let input = sampler.input();
    if components(&input) != 1 {
        return Err("key times must be scalars".into());
    }
    check_format(&input, FLOAT, "key times", None)?;
    let times = data.floats(&input).map_err(|e| format!("key times: {e}"))?.to_vec();
    check_times(&times, warnings)?;
    let width = if property == Property::Rotation { 4 } else { 3 };
    let output = sampler.output();
    if components(&output) != width {
        return Err(format!("{property:?} keys need {width} components, not {}", components(&output)));
    }
    let formats = if property == Property::Rotation { FLOAT_OR_NORM } else { FLOAT };
    check_format(&output, formats, &format!("{property:?} keys"), None)?;
    let raw = data.floats(&output).map_err(|e| format!("keys: {e}"))?;
    data.spend((times.len() + raw.len()) * 4)?;
    let per_key = if interpolation == Interpolation::CubicSpline { 3 } else { 1 };
    if raw.len() != times.len() * per_key * width {
        return Err(format!(
            "{} key times need {} values, found {}",
            times.len(),
            times.len() * per_key,
            raw.len() / width
        ));
    }
    let mut values: Vec<Vec4> = raw
        .chunks_exact(width)
        .map(|v| if width == 4 { Vec4::from_slice(v) } else { Vec3::from_slice(v).extend(0.0) })
        .collect();
    let what = format!("{property:?}").to_lowercase();
    for (i, v) in values.iter().enumerate() {
        if let Some(bad) = v.to_array().into_iter().find(|x| !x.is_finite()) {
            let kind = if bad.is_nan() { "NaN" } else { "infinite" };
            return Err(format!("{what} {} is {kind}", key_name(i, per_key)));
        }
    }
    if property == Property::Rotation {
        // Keys must be unit quaternions; quantized ones are only nearly so, and some files write
        // them at any scale.
        for (i, q) in values.iter_mut().enumerate().skip(per_key / 2).step_by(per_key) {
            *q =
                unit(*q).ok_or_else(|| format!("rotation {} has length 0: it is no rotation", key_name(i, per_key)))?;
        }
    }
    let node = c.target().node().index();
    Ok(Channel { node, property, interpolation, times, values })
}

/// Refuses key times that are not finite or run backwards; warns of equal ones (taken as a step
/// from one key to the next) and of a channel whose every key is at 0 s.
fn check_times(times: &[f32], warnings: &mut Vec<String>) -> Result<(), String> {
    if let Some(k) = times.iter().position(|t| !t.is_finite()) {
        return Err(format!("key time {k} is {}", if times[k].is_nan() { "NaN" } else { "infinite" }));
    }
    if let Some(k) = (1..times.len()).find(|&k| times[k] < times[k - 1]) {
        return Err(format!(
            "key time {k} ({} s) comes before key time {} ({} s): key times must not run backwards",
            times[k],
            k - 1,
            times[k - 1]
        ));
    }
    if times.len() > 1 && times.iter().all(|&t| t == times[0]) {
        warnings.push(format!("every one of its {} key times is {} s: it holds its last key", times.len(), times[0]));
    } else if let Some(k) = (1..times.len()).find(|&k| times[k] == times[k - 1]) {
        warnings.push(format!(
            "key times {} and {k} are both {} s (glTF asks for increasing times): taken as a step from one to the next",
            k - 1,
            times[k]
        ));
    }
    Ok(())
}

/// "key 3", or for cubic splines "the in-tangent of key 3" and so on.
fn key_name(value: usize, per_key: usize) -> String {
    let key = value / per_key;
    match (per_key, value % per_key) {
        (3, 0) => format!("in-tangent of key {key}"),
        (3, 2) => format!("out-tangent of key {key}"),
        _ => format!("key {key}"),
    }
}

/// `q` scaled to unit length, whatever its size (1e30 as well as 1e-30); none for length 0.
#[must_use]
pub(super) fn unit(q: Vec4) -> Option<Vec4> {
    let largest = q.abs().max_element();
    (largest > 0.0 && largest.is_finite()).then(|| (q / largest).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotations_of_any_size_become_unit_and_zero_is_refused() {
        for scale in [1e-30f32, 1.0, 1e30, f32::MAX] {
            let q = unit(Vec4::new(0.0, 0.0, 0.6, 0.8) * scale).unwrap();
            assert!(q.abs_diff_eq(Vec4::new(0.0, 0.0, 0.6, 0.8), 1e-6), "{scale}: {q}");
        }
        assert_eq!(unit(Vec4::ZERO), None);
    }

    #[test]
    fn times_may_repeat_but_not_run_backwards() {
        let mut w = Vec::new();
        check_times(&[0.0, 0.5, 0.5, 1.0], &mut w).unwrap();
        assert!(w[0].contains("key times 1 and 2 are both 0.5 s"), "{w:?}");
        w.clear();
        check_times(&[0.0, 0.0, 0.0], &mut w).unwrap();
        assert!(w[0].contains("every one of its 3 key times is 0 s"), "{w:?}");
        let err = check_times(&[0.0, 1.0, 0.5], &mut w).unwrap_err();
        assert!(err.contains("key time 2 (0.5 s) comes before key time 1 (1 s)"), "{err}");
        assert_eq!(check_times(&[0.0, f32::NAN], &mut w).unwrap_err(), "key time 1 is NaN");
        assert_eq!(key_name(6, 3), "in-tangent of key 2");
        assert_eq!(key_name(7, 3), "key 2");
        assert_eq!(key_name(5, 3), "out-tangent of key 1");
        assert_eq!(key_name(3, 1), "key 3");
    }
}
