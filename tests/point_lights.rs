//! Point lights and spots too wide for one map: shadowed through six cube faces, their shadows
//! land where the ray-traced truth says, on every side of the light.

mod common;

use common::*;
use glam::Vec3;
use umbra::assets::{MeshLibrary, cube, plane};
use umbra::components::*;
use umbra::eval::{metrics, truth};
use umbra::light::light_list;
use umbra::render::{HEADLESS_FORMAT, Renderer, render_debug_frame};
use umbra::{App, Settings};

fn grey() -> Material {
    Material { specular: 0.0, shininess: 1.0, ..Material::color(0.6, 0.6, 0.6) }
}

/// A ground with four boxes round the origin (+X, -X, +Z, -Z) and one over it, seen from above.
fn boxes(settings: Settings) -> App {
    let mut app = App::empty(settings).unwrap();
    let (ground, block) = {
        let mut meshes = app.world.resource_mut::<MeshLibrary>();
        (meshes.add(plane(40.0)), meshes.add(cube(Vec3::splat(0.5))))
    };
    app.world.spawn((ground, Transform::default(), grey(), ShadowReceiver));
    for (x, z, y) in [(2.0, 0.0, 0.6), (-2.5, 0.5, 0.6), (0.3, 2.2, 0.6), (-0.4, -2.0, 0.6), (0.8, 0.7, 1.4)] {
        let t = Transform::from_xyz(x, y, z).with_scale(Vec3::new(0.6, 1.2, 0.6));
        app.world.spawn((block, t, grey(), ShadowCaster, ShadowReceiver));
    }
    app.world.spawn(camera_at(Vec3::new(0.5, 11.0, 3.0), Vec3::ZERO));
    app.resize(SIZE, SIZE);
    app
}

/// For light `light` of `app` at time 0: ground pixels whose truth is dark, and the pixels the
/// measuring view gets wrong (false shadow + false lit) against the truth.
fn ground_errors(app: &mut App, light: usize) -> (usize, u64) {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    app.set_time(0.0);
    let frame = render_debug_frame(&gpu, &mut renderer, app, SIZE, SIZE).unwrap();
    drop((renderer, gpu));
    let truth = truth::truth_of(&mut app.world, &frame, truth::SizeOverride::default(), 0);
    let on_ground = |i: usize| frame.covered(i) && frame.position[i].y.abs() < 1e-3;
    let tally = metrics::tally(&frame, &truth[light], light, on_ground);
    let dark = (0..truth[light].len()).filter(|&i| on_ground(i) && truth[light][i].is_some_and(|t| !t.lit)).count();
    let wrong = tally.false_shadow + tally.false_lit;
    eprintln!("light {light}: {dark} truly dark ground pixels, {wrong} wrong");
    (dark, wrong)
}

#[test]
fn a_point_light_shadows_every_way_as_the_truth_does() {
    let mut app = boxes(Settings::default());
    let lamp = PointLight { range: 12.0, intensity: 3.0, ..Default::default() };
    app.world.spawn((lamp, Transform::from_xyz(0.0, 1.6, 0.0), ShadowMap::default()));
    app.set_time(0.0);
    let lights = light_list(&app.world);
    assert_eq!(lights[0].label.to_string(), "point 1");
    let map = app.world.query::<&ShadowMap>().single(&app.world).unwrap().layers.len();
    assert_eq!(map, 6, "a cube");
    let (dark, wrong) = ground_errors(&mut app, 0);
    // Shadows fall outwards from all four side boxes and under the one above the light's level.
    assert!(dark > 1500, "{dark} truly dark ground pixels");
    assert!(wrong * 25 < dark as u64, "{wrong} wrong of a {dark}-pixel shadow");
}

#[test]
fn a_spot_wider_than_one_map_is_shadow_tested_over_all_its_cone() {
    // An 80° half angle: beyond what one perspective map holds, so it takes a cube; its outer
    // ring (beyond 60°) holds boxes whose shadows must be there.
    let mut app = boxes(Settings::default());
    let wide = SpotLight {
        range: 14.0,
        intensity: 3.0,
        inner_angle: 1.2,
        outer_angle: 80f32.to_radians(),
        ..Default::default()
    };
    let at = Transform::from_xyz(0.0, 0.9, 0.0).looking_to(Vec3::NEG_Y);
    app.world.spawn((wide, at, ShadowMap::default()));
    app.set_time(0.0);
    let map = app.world.query::<&ShadowMap>().single(&app.world).unwrap().layers.len();
    assert_eq!(map, 6, "a wide spot takes a cube");
    let (dark, wrong) = ground_errors(&mut app, 0);
    assert!(dark > 1000, "{dark} truly dark ground pixels");
    assert!(wrong * 25 < dark as u64, "{wrong} wrong of a {dark}-pixel shadow");
}

#[test]
fn a_sun_four_spots_and_two_point_lights_are_each_measured_against_the_truth() {
    // Seven lights: the measuring view takes two passes (four lights each); every light's column
    // is compared with its own truth, as `bench` and `tune` compare them.
    let mut app = boxes(Settings::default().with(|s| s.maps.shadow_map_size = 1024));
    let sun = DirectionalLight { direction: Vec3::new(0.3, -1.0, 0.2), intensity: 0.6, ..Default::default() };
    app.world.spawn((sun, ShadowMap::default()));
    for (x, z) in [(-3.0, -3.0), (3.0, -3.0), (-3.0, 3.0), (3.0, 3.0)] {
        let spot = SpotLight { range: 12.0, intensity: 2.0, inner_angle: 0.5, outer_angle: 0.7, ..Default::default() };
        let at = Transform::from_xyz(x, 4.0, z).looking_to(Vec3::new(-x, -4.0, -z));
        app.world.spawn((spot, at, ShadowMap::default()));
    }
    for at in [Vec3::new(0.0, 1.6, 0.0), Vec3::new(-1.5, 2.5, 1.5)] {
        let lamp = PointLight { range: 10.0, intensity: 2.0, ..Default::default() };
        app.world.spawn((lamp, Transform::from_translation(at), ShadowMap::default()));
    }
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    app.set_time(0.0);
    let frame = render_debug_frame(&gpu, &mut renderer, &mut app, SIZE, SIZE).unwrap();
    drop((renderer, gpu));
    let names: Vec<String> = light_list(&app.world).iter().map(|l| l.label.to_string()).collect();
    assert_eq!(names, ["sun", "spot 1", "spot 2", "spot 3", "spot 4", "point 1", "point 2"]);
    assert_eq!(frame.visibility.len(), 7, "a column per light");
    let truth = truth::truth_of(&mut app.world, &frame, truth::SizeOverride::default(), 0);
    for (light, report) in metrics::report(&frame, &truth, 2).iter().enumerate() {
        let t = report.all;
        eprintln!("{}: {} pixels, {:.4} % misclassified", names[light], t.pixels, 100.0 * t.misclassified());
        assert!(t.pixels > 2000, "{}: only {} pixels reached", names[light], t.pixels);
        assert!(t.misclassified() < 0.01, "{}: {:.4} misclassified", names[light], t.misclassified());
    }
}
