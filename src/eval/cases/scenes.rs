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
    view: (Vec3, Vec3),
) -> Result<App, AppError> {
    let mut app = unlit_ground(settings, size, ground_casts, view)?;
    let light = DirectionalLight { direction: sun, color: Vec3::ONE, intensity: 1.0, ..Default::default() };
    app.world.spawn((light, ShadowMap::default()));
    Ok(app)
}

/// An app with a square ground `size` metres across (a caster too if `ground_casts`) and a
/// camera at `eye` looking at `target`, but no light.
pub fn unlit_ground(
    settings: &Settings,
    size: f32,
    ground_casts: bool,
    (eye, target): (Vec3, Vec3),
) -> Result<App, AppError> {
    let mut app = App::empty(settings.clone())?;
    let mesh = app.world.resource_mut::<MeshLibrary>().add(plane(size));
    let mut g = app.world.spawn((mesh, Transform::default(), grey(), ShadowReceiver));
    if ground_casts {
        g.insert(ShadowCaster);
    }
    app.world.spawn(camera_looking(eye, target));
    Ok(app)
}

/// Where the cube-seams case hangs its point light.
pub const SEAMS_LAMP: Vec3 = Vec3::new(0.0, 1.0, 0.0);

/// A point light 1 m over the ground, seen close up where the face looking down meets the
/// face looking along +X (the line x = 1 on the ground): a bar whose shadow's edge runs along that
/// seam, boxes whose shadows cross it and the diagonal seams. The lamp has the large normal bias a
/// point light often needs (2 texels), which moves a lookup next to a seam across it.
pub fn seams_scene(settings: &Settings) -> Result<App, AppError> {
    let mut app = unlit_ground(settings, 40.0, false, (Vec3::new(1.3, 1.1, 1.0), Vec3::new(1.0, 0.0, 0.1)))?;
    // The bar's top outer edge (x = 0.5, 0.5 m up) throws its shadow's edge onto x = 1.
    add_box(&mut app, Vec3::new(0.4, 0.25, 0.0), Vec3::new(0.1, 0.25, 0.8));
    for (x, z) in [(0.75, 0.55), (0.7, -0.6), (1.3, 1.25), (1.35, -1.3)] {
        add_box(&mut app, Vec3::new(x, 0.2, z), Vec3::new(0.06, 0.2, 0.06));
    }
    let lamp = PointLight { range: 15.0, intensity: 3.0, ..Default::default() };
    let bias = ShadowBias { constant: 1.0, slope: 1.0, normal: 2.0, scale: 0.0, receiver_plane: true };
    app.world.spawn((lamp, Transform::from_translation(SEAMS_LAMP), ShadowMap::default(), bias));
    Ok(app)
}

/// Where the wide-spot case hangs its spot, and the half angle of its cone (a 170° spot).
pub const WIDE_SPOT: (Vec3, f32) = (Vec3::new(0.0, 0.6, 0.0), 85.0);

/// A 170° spot 60 cm over the ground, shining down, with low boxes in the outer ring of its cone
/// (75° to 83° from its axis) whose long shadows reach outwards.
pub fn wide_spot_scene(settings: &Settings) -> Result<App, AppError> {
    let mut app = unlit_ground(settings, 80.0, false, (Vec3::new(0.0, 16.0, 7.0), Vec3::ZERO))?;
    for k in 0..7 {
        let a = k as f32 * 0.9;
        let r = 2.4 + (k % 3) as f32 * 1.2;
        add_box(&mut app, Vec3::new(a.cos() * r, 0.2, a.sin() * r), Vec3::new(0.25, 0.2, 0.25));
    }
    let outer = WIDE_SPOT.1.to_radians();
    let spot =
        SpotLight { range: 15.0, intensity: 4.0, inner_angle: outer - 0.1, outer_angle: outer, ..Default::default() };
    let at = Transform::from_translation(WIDE_SPOT.0).looking_to(Vec3::NEG_Y);
    app.world.spawn((spot, at, ShadowMap::default()));
    Ok(app)
}

/// A 2.5 m pole, 6 cm thick, on the ground at the origin, and a 10 cm spot 5 m up and 2.5 m to
/// its -X side aimed past it, so the pole's shadow runs 2.5 m along +X; seen from straight above.
pub fn pole_scene(settings: &Settings) -> Result<App, AppError> {
    let mut app = unlit_ground(settings, 40.0, false, (Vec3::new(1.25, 3.5, 0.01), Vec3::new(1.25, 0.0, 0.0)))?;
    add_box(&mut app, Vec3::new(0.0, 1.25, 0.0), Vec3::new(0.03, 1.25, 0.03));
    let spot = SpotLight { range: 15.0, intensity: 4.0, inner_angle: 0.5, outer_angle: 0.6, ..Default::default() };
    let position = Vec3::new(-2.5, 5.0, 0.0);
    let at = Transform::from_translation(position).looking_to(Vec3::new(1.5, 0.0, 0.0) - position);
    app.world.spawn((spot, at, ShadowMap::default()));
    Ok(app)
}

/// Where the atlas-seams case hangs its spot, and the spot's half angle in degrees.
pub const SEAMS_SPOT: (Vec3, f32) = (Vec3::new(0.0, 4.0, 0.0), 30.0);

/// A spot straight down over an open ground with a hard edge (full light right up to its cone,
/// which touches its map's edge at four points), sampled by Poisson 32, the widest fixed filter;
/// beside it a twin looking up into a box, whose tile (the same size, so the next one in the
/// atlas) is all near depth: a tap that strays into it reads shadow.
pub fn atlas_seams_scene(settings: &Settings) -> Result<App, AppError> {
    let mut app = unlit_ground(settings, 40.0, false, (Vec3::new(0.0, 9.0, 0.01), Vec3::ZERO))?;
    let outer = SEAMS_SPOT.1.to_radians();
    let spot =
        SpotLight { range: 10.0, intensity: 4.0, inner_angle: outer - 1e-4, outer_angle: outer, ..Default::default() };
    let at = Transform::from_translation(SEAMS_SPOT.0).looking_to(Vec3::NEG_Y);
    app.world.spawn((spot, at, ShadowMap::default(), ShadowMethod::Poisson32));
    let twin = SEAMS_SPOT.0 + Vec3::X * 0.2;
    app.world.spawn((spot, Transform::from_translation(twin).looking_to(Vec3::Y), ShadowMap::default()));
    add_box(&mut app, twin + Vec3::Y * 0.6, Vec3::new(1.0, 0.1, 1.0));
    Ok(app)
}

/// Adds a box with half extents `half` at `center`, casting and receiving.
pub fn add_box(app: &mut App, center: Vec3, half: Vec3) {
    add_block(app, Transform::from_translation(center).with_scale(half * 2.0));
}

/// Adds a unit box placed, turned and sized by `t`, casting and receiving.
pub fn add_block(app: &mut App, t: Transform) {
    let mesh = app.world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
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
