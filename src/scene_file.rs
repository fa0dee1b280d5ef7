//! A scene from a glTF file (`--scene`), played instead of the sample scene: its meshes where the
//! file puts them (playing its first clip), its `KHR_lights_punctual` lights as umbra lights with
//! shadows, its first camera (or one that frames the scene), and a sun when it has no light.
//!
//! # Light units
//! glTF gives a directional light's intensity in lux and a point or spot light's in candela. An
//! umbra light's intensity is a plain factor: a sun of intensity 1 lights a surface facing it
//! with its full colour. The scene's exposure ([`SceneSettings::exposure`], `--exposure`,
//! default 1) says what one lux is worth, so a directional light becomes an umbra sun of intensity `lux × exposure`. A point or
//! spot light of `I` candela gives `I / d²` lux at `d` metres, while umbra's falloff is
//! `1 / (1 + LIGHT_FALLOFF·d²)`; an intensity of `I × exposure × LIGHT_FALLOFF` makes the two agree
//! away from the light (and umbra's stays finite at it). With exposure 1 a file lit the way the
//! Khronos sample viewer or three.js show it looks the same in umbra; a file with physical values
//! (a 100 000 lux noon sun) wants an exposure near 0.00001.

use crate::assets::model::{FileLightKind, ModelCamera, ModelLight};
use crate::assets::{ModelError, load_model};
use crate::components::*;
use crate::scene::{SUN_DIRECTION, camera_looking, spawn_model};
use crate::settings::SceneSettings;
use crate::shadow::Aabb;
use bevy_ecs::prelude::*;
use glam::{Mat4, Vec3};
use std::sync::Arc;

/// A file's light as an umbra light: its component and where it stands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FileLight {
    /// A directional light, along its transform (which an animated node turns).
    Sun(DirectionalLight, Transform),
    /// A spot light, at and along its transform.
    Spot(SpotLight, Transform),
    /// A point light, at its transform.
    Point(PointLight, Transform),
}

/// The umbra light for `light`, hung on a node at `world_from_node`, under `exposure`; a light
/// without a range reaches across `bounds` (the scene's) twice over.
#[must_use]
pub fn file_light(light: &ModelLight, world_from_node: Mat4, exposure: f32, bounds: Aabb) -> FileLight {
    let (_, rotation, translation) = world_from_node.to_scale_rotation_translation();
    let transform = Transform { translation, rotation, scale: Vec3::ONE };
    let local = light.intensity * exposure * LIGHT_FALLOFF;
    let range = light.range.unwrap_or_else(|| unbounded_range(translation, bounds));
    match light.kind {
        FileLightKind::Directional => {
            let sun = DirectionalLight {
                direction: rotation * Vec3::NEG_Z,
                color: light.color,
                intensity: light.intensity * exposure,
                ..Default::default()
            };
            FileLight::Sun(sun, transform)
        }
        FileLightKind::Point => FileLight::Point(
            PointLight { color: light.color, intensity: local, range, ..Default::default() },
            transform,
        ),
        FileLightKind::Spot { inner, outer } => {
            let spot = SpotLight {
                color: light.color,
                intensity: local,
                range,
                inner_angle: inner,
                outer_angle: outer,
                ..Default::default()
            };
            FileLight::Spot(spot, transform)
        }
    }
}

/// The range given to a light whose file sets none (glTF's lights never end): twice the distance
/// from `position` to the farthest corner of `bounds`, so the range window barely dims the scene
/// while the shadow maps' depth still covers only it (10 m when there is nothing to light).
#[must_use]
pub fn unbounded_range(position: Vec3, bounds: Aabb) -> f32 {
    if bounds.is_empty() || !position.is_finite() {
        return 10.0;
    }
    let far = bounds.corners().iter().map(|c| c.distance(position)).fold(0.0, f32::max);
    (2.0 * far).clamp(0.1, 1.0e5)
}

/// A camera that frames `bounds` with vertical field of view `fov_y`: from the south and above,
/// as the sample's camera looks at its scene, far enough that the bounds' sphere fits the view.
/// Returns the camera and its eye and target.
#[must_use]
pub fn framing_camera(bounds: Aabb, fov_y: f32) -> (Camera, Vec3, Vec3) {
    let (center, radius) = if bounds.is_empty() || !(bounds.min.is_finite() && bounds.max.is_finite()) {
        (Vec3::ZERO, 1.0)
    } else {
        (bounds.center(), (0.5 * (bounds.max - bounds.min).length()).max(1e-3))
    };
    let distance = radius / (0.5 * fov_y).sin() * 1.05;
    let eye = center + Vec3::new(2.5, 4.5, 12.5).normalize() * distance;
    let far = ((distance + radius) * 1.5).max(Camera::default().far);
    let near = (0.01 * distance).min(Camera::default().near);
    (Camera { fov_y, near, far }, eye, center)
}

/// Spawns the scene of the glTF file `settings.file` into `world` (which must hold a
/// [`MeshLibrary`](crate::assets::MeshLibrary)); what had to be left out or mended is added to
/// the model's warnings.
pub fn spawn_file_scene(world: &mut World, settings: &SceneSettings) -> Result<(), ModelError> {
    let Some(path) = &settings.file else { return Ok(()) };
    let model = load_model(path)?;
    if model.parts.is_empty() {
        let problem = "its scene has no triangle meshes to draw".to_string();
        return Err(ModelError { path: path.display().to_string(), problem });
    }
    let globals = model.globals(&model.rest_locals());
    let bounds = model.rest_bounds();
    let (lights, camera) = (model.lights.clone(), model.camera);
    let clip = (!model.clips.is_empty()).then_some(0);
    let root = spawn_model(world, Arc::new(model), Transform::default(), clip);
    for light in &lights {
        let at = AtNode { root, node: light.node };
        match file_light(light, globals[light.node], settings.exposure, bounds) {
            FileLight::Sun(sun, t) => world.spawn((sun, t, at, ShadowMap::default())),
            FileLight::Spot(spot, t) => world.spawn((spot, t, at, ShadowMap::default())),
            FileLight::Point(point, t) => world.spawn((point, t, at, ShadowMap::default())),
        };
    }
    if lights.is_empty() {
        let sun = DirectionalLight { direction: SUN_DIRECTION.normalize(), ..Default::default() };
        world.spawn((sun, ShadowMap::default()));
    }
    world.spawn(scene_camera(camera, &globals, bounds));
    Ok(())
}

/// The file's camera where its node stands (umbra's defaults for what it lacks), or a camera
/// that frames the scene.
fn scene_camera(camera: Option<ModelCamera>, globals: &[Mat4], bounds: Aabb) -> (Camera, FlyCamera, Transform) {
    let default = Camera::default();
    let framing = framing_camera(bounds, default.fov_y);
    let Some(file) = camera else {
        let (camera, eye, target) = framing;
        let (_, fly, transform) = camera_looking(eye, target);
        return (camera, fly, transform);
    };
    let (_, rotation, eye) = globals[file.node].to_scale_rotation_translation();
    let (_, fly, transform) = camera_looking(eye, eye + rotation * Vec3::NEG_Z);
    let near = file.near.unwrap_or(default.near);
    let far = file.far.unwrap_or(framing.0.far.max(default.far));
    (Camera { fov_y: file.fov_y.unwrap_or(default.fov_y), near, far }, fly, transform)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(kind: FileLightKind, intensity: f32, range: Option<f32>) -> ModelLight {
        ModelLight { node: 0, kind, color: Vec3::new(1.0, 0.5, 0.25), intensity, range }
    }

    #[test]
    fn lux_and_candela_become_umbra_intensities() {
        let bounds = Aabb { min: Vec3::splat(-1.0), max: Vec3::splat(1.0) };
        // A node at (0, 5, 0) turned to look straight down.
        let node = Mat4::from_rotation_translation(
            glam::Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2),
            Vec3::new(0.0, 5.0, 0.0),
        );
        let FileLight::Sun(sun, _) = file_light(&light(FileLightKind::Directional, 3.0, None), node, 0.5, bounds)
        else {
            panic!("a directional light is a sun")
        };
        assert_eq!(sun.intensity, 1.5, "lux × exposure");
        assert!(sun.direction.abs_diff_eq(Vec3::NEG_Y, 1e-6), "along the node's -Z: {:?}", sun.direction);
        assert_eq!(sun.color, Vec3::new(1.0, 0.5, 0.25));
        let FileLight::Point(point, t) = file_light(&light(FileLightKind::Point, 40.0, Some(7.0)), node, 0.5, bounds)
        else {
            panic!("a point light stays one")
        };
        assert_eq!(point.intensity, 40.0 * 0.5 * LIGHT_FALLOFF);
        assert_eq!((point.range, t.translation), (7.0, Vec3::new(0.0, 5.0, 0.0)));
        // Far from the light, umbra's falloff gives what the candela give: I / d² lux × exposure.
        let d = 100.0f32;
        let umbra = point.intensity / (1.0 + LIGHT_FALLOFF * d * d);
        assert!((umbra / (40.0 * 0.5 / (d * d)) - 1.0).abs() < 0.01);
        let spot = FileLightKind::Spot { inner: 0.2, outer: 0.5 };
        let FileLight::Spot(s, t) = file_light(&light(spot, 10.0, None), node, 1.0, bounds) else {
            panic!("a spot light stays one")
        };
        assert_eq!((s.inner_angle, s.outer_angle), (0.2, 0.5));
        assert!(t.forward().abs_diff_eq(Vec3::NEG_Y, 1e-6), "it shines along the node's -Z");
        assert_eq!(s.range, unbounded_range(Vec3::new(0.0, 5.0, 0.0), bounds));
    }

    #[test]
    fn unbounded_lights_reach_across_the_scene_twice() {
        let bounds = Aabb { min: Vec3::ZERO, max: Vec3::new(3.0, 4.0, 0.0) };
        assert_eq!(unbounded_range(Vec3::ZERO, bounds), 10.0, "twice the 5 m to the far corner");
        assert_eq!(unbounded_range(Vec3::ZERO, Aabb::EMPTY), 10.0);
        assert_eq!(unbounded_range(Vec3::NAN, bounds), 10.0);
        assert_eq!(unbounded_range(Vec3::splat(1e30), bounds), 1.0e5);
        assert!(unbounded_range(Vec3::ZERO, Aabb { min: Vec3::ZERO, max: Vec3::ZERO }) >= 0.1);
    }

    #[test]
    fn the_framing_camera_sees_every_corner() {
        for bounds in [
            Aabb { min: Vec3::new(-40.0, 0.0, -10.0), max: Vec3::new(40.0, 3.0, 10.0) },
            Aabb { min: Vec3::splat(0.01), max: Vec3::splat(0.02) },
            Aabb { min: Vec3::new(100.0, 0.0, 0.0), max: Vec3::new(101.0, 1.0, 1.0) },
        ] {
            let (camera, eye, target) = framing_camera(bounds, 1.0);
            let (_, _, transform) = camera_looking(eye, target);
            let clip_from_world = camera.view_proj(&transform, 1.0);
            for corner in bounds.corners() {
                let c = clip_from_world * corner.extend(1.0);
                let ndc = c.truncate() / c.w;
                assert!(c.w > 0.0 && ndc.abs().max_element() <= 1.0 && ndc.z >= 0.0, "{bounds:?}: {corner} at {ndc}");
            }
        }
        let (camera, eye, target) = framing_camera(Aabb::EMPTY, 1.0);
        assert!(eye.is_finite() && target == Vec3::ZERO && camera.near > 0.0);
    }
}
