//! `--scene`: a glTF file's lights (KHR_lights_punctual) become umbra lights whose shadows land
//! where the ray-traced truth says; a file without lights gets a sun, one without a camera is
//! framed, and a file's broken lights are refused or mended with words that name them.

mod common;

use common::scene_file::{BOX, PILLAR, SceneFile};
use common::*;
use glam::Vec3;
use serde_json::json;
use umbra::assets::ModelInstance;
use umbra::components::*;
use umbra::eval::{metrics, truth};
use umbra::light::light_list;
use umbra::render::{HEADLESS_FORMAT, Renderer, render_debug_frame};
use umbra::{App, Settings};

const SPOT_AT: Vec3 = Vec3::new(-3.0, 5.0, 2.0);
const LAMP_AT: Vec3 = Vec3::new(1.2, 1.6, 1.0);
const EYE: Vec3 = Vec3::new(3.0, 9.0, 9.0);

/// The scene with a directional light (from +X, low), a spot aimed at the pillar's foot, a point
/// light between the pillar and the box, and a camera looking down at it all.
fn lit_scene() -> SceneFile {
    let sun = json!({ "type": "directional", "color": [1.0, 0.9, 0.8], "intensity": 0.8 });
    let spot = json!({ "type": "spot", "intensity": 20.0, "range": 14.0,
        "spot": { "innerConeAngle": 0.4, "outerConeAngle": 0.6 } });
    let lamp = json!({ "type": "point", "color": [1.0, 0.7, 0.4], "intensity": 12.0 });
    SceneFile::new()
        .light(sun, Vec3::new(5.0, 5.0, 0.0), Vec3::new(-1.0, -0.6, 0.2))
        .light(spot, SPOT_AT, Vec3::new(0.0, 0.0, 0.0) - SPOT_AT)
        .light(lamp, LAMP_AT, Vec3::NEG_Y)
        .camera(0.9, EYE, Vec3::ZERO)
}

fn scene_app(scene: &SceneFile, name: &str) -> App {
    let path = scene.write(&scratch("scene-file"), name);
    App::new(Settings::default().with(|s| s.scene.file = Some(path))).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_files_lights_shadow_the_scene_where_the_truth_says() {
    let mut app = scene_app(&lit_scene(), "lit.gltf");
    app.resize(SIZE, SIZE);
    app.set_time(0.0);
    let lights = light_list(&app.world);
    let names: Vec<String> = lights.iter().map(|l| l.label.to_string()).collect();
    assert_eq!(names, ["sun", "spot 1", "point 1"], "the file's three lights and no added sun");

    // Where the file put them, in umbra's units (exposure 1: lux as is, candela × the falloff).
    let (sun, _, _) = app.world.query::<(&DirectionalLight, &Transform, &AtNode)>().single(&app.world).unwrap();
    let sun = *sun;
    assert!(sun.direction.abs_diff_eq(Vec3::new(-1.0, -0.6, 0.2).normalize(), 1e-5), "{:?}", sun.direction);
    assert_eq!((sun.intensity, sun.color), (0.8, Vec3::new(1.0, 0.9, 0.8)));
    let (spot, at) = app.world.query::<(&SpotLight, &Transform)>().single(&app.world).map(|(s, t)| (*s, *t)).unwrap();
    assert!(at.translation.abs_diff_eq(SPOT_AT, 1e-5) && at.forward().abs_diff_eq(-SPOT_AT.normalize(), 1e-5));
    assert_eq!((spot.intensity, spot.range, spot.outer_angle), (20.0 * LIGHT_FALLOFF, 14.0, 0.6));
    let (lamp, at) = app.world.query::<(&PointLight, &Transform)>().single(&app.world).map(|(p, t)| (*p, *t)).unwrap();
    assert!(at.translation.abs_diff_eq(LAMP_AT, 1e-5));
    assert_eq!(lamp.intensity, 12.0 * LIGHT_FALLOFF);
    assert!(lamp.range > 20.0, "a light without a range reaches across the scene: {}", lamp.range);

    // The file's camera.
    let (camera, eye) = app.world.query::<(&Camera, &Transform)>().single(&app.world).map(|(c, t)| (*c, *t)).unwrap();
    assert!(eye.translation.abs_diff_eq(EYE, 1e-5) && eye.forward().abs_diff_eq(-EYE.normalize(), 1e-5));
    assert_eq!((camera.fov_y, camera.near, camera.far), (0.9, 0.05, 120.0));

    // Each light's shadow, pixel by pixel, against the truth; each has a real shadow to find.
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    let frame = render_debug_frame(&gpu, &mut renderer, &mut app, SIZE, SIZE).unwrap();
    drop((renderer, gpu));
    let truth = truth::truth_of(&mut app.world, &frame, truth::SizeOverride::default(), 0);
    for (light, column) in truth.iter().enumerate() {
        let dark = column.iter().filter(|t| t.is_some_and(|t| !t.lit)).count();
        let tally = metrics::tally(&frame, column, light, |_| true);
        let wrong = tally.false_shadow + tally.false_lit;
        eprintln!("{}: {dark} truly dark pixels, {wrong} wrong", names[light]);
        assert!(dark > 300, "{}: {dark} truly dark pixels", names[light]);
        assert!(wrong * 25 < dark as u64, "{}: {wrong} wrong of a {dark}-pixel shadow", names[light]);
    }

    // And in the picture, the low sun from +X throws the pillar's shadow 3.4 m to -X (and a
    // little +Z): there the ground is darker than a metre to the side, which the spot and the
    // lamp light alike.
    let image = render(&mut app, 0.0);
    let shade = brightness_at(&mut app, &image, Vec3::new(-2.5, 0.0, 0.5));
    let lit = brightness_at(&mut app, &image, Vec3::new(-2.5, 0.0, -0.5));
    eprintln!("in the pillar's shadow {shade}, beside it {lit}");
    assert!(shade + 10.0 < lit, "in the pillar's shadow {shade}, beside it {lit}");
}

#[test]
fn a_file_without_lights_gets_a_sun_and_one_without_a_camera_is_framed() {
    let mut app = scene_app(&SceneFile::new(), "bare.gltf");
    let names: Vec<String> = light_list(&app.world).iter().map(|l| l.label.to_string()).collect();
    assert_eq!(names, ["sun"]);
    let sun = app.world.query::<(&DirectionalLight, &ShadowMap)>().single(&app.world).map(|(s, _)| *s).unwrap();
    assert!(sun.direction.abs_diff_eq(umbra::scene::SUN_DIRECTION.normalize(), 1e-6));
    app.resize(SIZE, SIZE);
    app.set_time(0.0);
    // Every corner of the ground (30 m across) and the casters is in view.
    for corner in [Vec3::new(-15.0, 0.0, -15.0), Vec3::new(15.0, 0.0, 15.0), Vec3::new(15.0, 0.0, -15.0), BOX, PILLAR] {
        pixel_of(&mut app, corner);
    }
    // No sample scene: no cubes, no character, no ground of umbra's.
    assert_eq!(app.world.query::<&Spin>().iter(&app.world).count(), 0);
    assert_eq!(app.world.query::<&ModelInstance>().iter(&app.world).count(), 1);
}

#[test]
fn a_files_broken_lights_are_named() {
    let dir = scratch("scene-file-broken");
    let load = |scene: SceneFile, name: &str| {
        let path = scene.write(&dir, name);
        umbra::assets::load_model(&path)
    };
    // A node naming a light the file does not have, and a light of no known type: refused.
    let mut missing = SceneFile::new().light(json!({ "type": "point" }), Vec3::ONE, Vec3::NEG_Y);
    missing.node(json!({ "extensions": { "KHR_lights_punctual": { "light": 7 } } }));
    let err = load(missing, "missing.gltf").unwrap_err().to_string();
    assert!(err.contains("missing.gltf") && err.contains("light"), "{err}");
    let strange = SceneFile::new().light(json!({ "type": "area" }), Vec3::ONE, Vec3::NEG_Y);
    let err = load(strange, "strange.gltf").unwrap_err().to_string();
    assert!(err.contains("type"), "{err}");
    // Numbers that make no light are left out, a range that makes no sense is dropped; each
    // with a warning that names the light.
    let odd = SceneFile::new()
        .light(json!({ "type": "point", "intensity": -3.0 }), Vec3::ONE, Vec3::NEG_Y)
        .light(json!({ "type": "point", "range": 0.0 }), Vec3::ONE, Vec3::NEG_Y)
        .light(
            json!({ "type": "spot", "spot": { "innerConeAngle": 1.0, "outerConeAngle": 0.5 } }),
            Vec3::ONE,
            Vec3::NEG_Y,
        );
    let model = load(odd, "odd.gltf").unwrap();
    assert_eq!(model.lights.len(), 2, "the negative light is left out");
    assert_eq!(model.lights[0].range, None);
    let warnings = model.warnings.join("\n");
    for expected in ["light 0 (on node 3) has intensity -3", "light 1 (on node 4) has range 0", "light 2 (on node 5)"] {
        assert!(warnings.contains(expected), "{expected:?} in {warnings}");
    }
    // A file that requires the lights extension is read; one requiring another is refused by name.
    let mut required = lit_scene();
    required.0.json["extensionsRequired"] = json!(["KHR_lights_punctual"]);
    assert_eq!(load(required, "required.gltf").unwrap().lights.len(), 3);
    let mut draco = lit_scene();
    draco.0.json["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    let err = load(draco, "draco.gltf").unwrap_err().to_string();
    assert!(err.contains("KHR_draco_mesh_compression"), "{err}");
}

#[test]
fn scene_and_model_together_are_refused_and_a_scene_without_meshes_too() {
    let dir = scratch("scene-file-refused");
    let path = lit_scene().write(&dir, "lit.gltf");
    let both = Settings::default().with(|s| {
        s.scene.file = Some(path.clone());
        s.scene.model = Some(path);
    });
    let err = App::new(both).err().expect("refused").to_string();
    assert!(err.contains("model") && err.contains("one or the other"), "{err}");
    let mut empty = SceneFile::new();
    empty.0.json["scenes"][0]["nodes"] = json!([]);
    let path = empty.write(&dir, "empty.gltf");
    let err = App::new(Settings::default().with(|s| s.scene.file = Some(path))).err().expect("refused").to_string();
    assert!(err.contains("empty.gltf") && err.contains("no triangle meshes"), "{err}");
}
