//! Small scenes for the failure cases: a ground, some boxes or poles, a sun, a camera.

use crate::assets::clip::{Channel, Clip, Interpolation, Property};
use crate::assets::{MeshLibrary, Model, cube, parse_model, plane};
use crate::components::*;
use crate::scene::{CHARACTER_GLB, camera_looking, spawn_model};
use crate::settings::Settings;
use crate::{App, AppError};
use glam::Vec3;
use std::sync::Arc;

fn grey() -> Material {
    Material { specular: 0.0, shininess: 1.0, ..Material::color(0.6, 0.6, 0.6) }
}

/// The direction sunlight travels for a sun `elevation` degrees above the horizon, coming from
/// `azimuth` degrees (0 is from +Z, 90 from +X).
pub fn sun_direction(elevation: f32, azimuth: f32) -> Vec3 {
    let (e, a) = (elevation.to_radians(), azimuth.to_radians());
    -Vec3::new(e.cos() * a.sin(), e.sin(), e.cos() * a.cos())
}

/// An app with a square ground `size` metres across (a caster too if `ground_casts`), a sun
/// along `sun` and a camera at `eye` looking at `target`.
pub fn ground(
    settings: &Settings,
    size: f32,
    ground_casts: bool,
    sun: Vec3,
    (eye, target): (Vec3, Vec3),
) -> Result<App, AppError> {
    let mut app = App::empty(settings.clone())?;
    let mesh = app.world.resource_mut::<MeshLibrary>().add(plane(size));
    let mut g = app.world.spawn((mesh, Transform::default(), grey(), ShadowReceiver));
    if ground_casts {
        g.insert(ShadowCaster);
    }
    let light = DirectionalLight { direction: sun, color: Vec3::ONE, intensity: 1.0, ..Default::default() };
    app.world.spawn((light, ShadowMap::default()));
    app.world.spawn(camera_looking(eye, target));
    Ok(app)
}

/// Adds a box with half extents `half` at `center`, casting and receiving.
pub fn add_box(app: &mut App, center: Vec3, half: Vec3) {
    let mesh = app.world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
    let t = Transform::from_xyz(center.x, center.y, center.z).with_scale(half * 2.0);
    app.world.spawn((mesh, t, grey(), ShadowCaster, ShadowReceiver));
}

/// Points the (only) sun along `direction`.
pub fn set_sun(app: &mut App, direction: Vec3) {
    for mut sun in app.world.query::<&mut DirectionalLight>().iter_mut(&mut app.world) {
        sun.direction = direction;
    }
}

/// The walking character with one more clip, "leap", that carries its hips `offset` away from
/// where they are bound, so the posed body leaves its bind-pose bounds; returns the model and the
/// clip's index.
pub fn leaping_character(offset: Vec3) -> Result<(Model, usize), AppError> {
    let mut model = parse_model(CHARACTER_GLB, None, "character.glb")?;
    let hips = model.nodes.iter().position(|n| n.name == "hips").unwrap_or(0);
    let at = (model.nodes[hips].rest.translation + offset).extend(0.0);
    let channel = Channel {
        node: hips,
        property: Property::Translation,
        interpolation: Interpolation::Step,
        times: vec![0.0, 1.0],
        values: vec![at, at],
    };
    model.clips.push(Clip { name: "leap".into(), channels: vec![channel], duration: 1.0 });
    let clip = model.clips.len() - 1;
    Ok((model, clip))
}

/// A ground with the leaping character on it at the origin.
pub fn with_leaper(settings: &Settings, offset: Vec3, sun: Vec3, view: (Vec3, Vec3)) -> Result<App, AppError> {
    let mut app = ground(settings, 60.0, false, sun, view)?;
    let (model, clip) = leaping_character(offset)?;
    spawn_model(&mut app.world, Arc::new(model), Transform::default(), Some(clip));
    Ok(app)
}
