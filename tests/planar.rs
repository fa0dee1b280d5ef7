//! Planar projected shadows (the `planar` method) against the truth and in the picture: exact
//! on the ground and absent everywhere else; hidden behind what stands on the ground; each
//! pixel darkened once per light however many casters overlap, in each light's own colour; and
//! none from a light below the ground or a caster behind a spot.

mod common;

use common::*;
use glam::Vec3;
use umbra::assets::{MeshLibrary, cube, plane};
use umbra::components::*;
use umbra::eval::truth;
use umbra::render::{DebugFrame, HEADLESS_FORMAT, Renderer, extract, render_debug_frame};
use umbra::{App, Settings};

fn grey() -> Material {
    Material { specular: 0.0, shininess: 1.0, ..Material::color(0.6, 0.6, 0.6) }
}

/// Planar shadows on a plain ground: the tests compare the brightness of ground points that
/// would lie on different squares of the checker.
fn planar() -> Settings {
    Settings::default().with(|s| {
        s.shadow.method = ShadowMethod::Planar;
        s.view.ground_grid = false;
    })
}

/// An app with a 40 m ground, the boxes `boxes` (centre, half extents) and a camera.
fn scene(boxes: &[(Vec3, Vec3)], (eye, target): (Vec3, Vec3)) -> App {
    let mut app = App::empty(planar()).unwrap();
    let (ground, block) = {
        let mut meshes = app.world.resource_mut::<MeshLibrary>();
        (meshes.add(plane(40.0)), meshes.add(cube(Vec3::splat(0.5))))
    };
    app.world.spawn((ground, Transform::default(), grey(), ShadowReceiver));
    for &(at, half) in boxes {
        let t = Transform::from_translation(at).with_scale(half * 2.0);
        app.world.spawn((block, t, grey(), ShadowCaster, ShadowReceiver));
    }
    app.world.spawn(camera_at(eye, target));
    app.resize(SIZE, SIZE);
    app
}

fn sun(app: &mut App, direction: Vec3, color: Vec3) {
    let light = DirectionalLight { direction: direction.normalize(), color, intensity: 1.0, ..Default::default() };
    app.world.spawn((light, ShadowMap::default()));
}

fn measure(app: &mut App) -> DebugFrame {
    let gpu = gpu();
    let mut renderer = Renderer::new(&gpu, HEADLESS_FORMAT).unwrap();
    app.set_time(0.0);
    render_debug_frame(&gpu, &mut renderer, app, SIZE, SIZE).unwrap()
}

fn on_ground(frame: &DebugFrame, i: usize) -> bool {
    frame.covered(i) && frame.position[i].y.abs() < 1e-3 && frame.normal[i].y > 0.99
}

/// Per light of the sample scene under `settings`: ground pixels, those in true shadow, those
/// wrong more than 2 pixels from an edge, truly shadowed pixels off the ground drawn lit, and
/// ground pixels partly lit (a planar shadow is all or nothing; a filtered map is not).
fn sample_ground(settings: Settings) -> Vec<[usize; 5]> {
    let mut app = App::new(settings).unwrap();
    app.resize(SIZE, SIZE);
    let frame = measure(&mut app);
    let truth = truth::truth_of(&mut app.world, &frame, truth::SizeOverride::default(), 0);
    let (w, h) = (frame.width as i64, frame.height as i64);
    let mut out = Vec::new();
    for (light, column) in truth.iter().enumerate() {
        let lit = |i: usize| column[i].map(|t| t.lit);
        // Within 2 pixels of a true edge the pixel grid decides; elsewhere planar must be right.
        // The edge of the light itself (a spot's cone, where the truth stops) is an edge too: the
        // overlay finds the light's reach at a point it rebuilt from the flattened caster, which
        // can round to the other side of the cone than the ground's own point.
        let near_edge = |i: usize| {
            let (x, y) = (i as i64 % w, i as i64 / w);
            (-2..=2)
                .flat_map(|dy| (-2..=2).map(move |dx| (x + dx, y + dy)))
                .any(|(a, b)| (0..w).contains(&a) && (0..h).contains(&b) && lit((b * w + a) as usize) != lit(i))
        };
        let mut counts = [0; 5];
        for (i, t) in column.iter().enumerate() {
            let (Some(t), Some(r)) = (t, umbra::eval::metrics::rendered(&frame, light, i)) else { continue };
            if on_ground(&frame, i) {
                counts[0] += 1;
                counts[1] += !t.lit as usize;
                counts[2] += (!near_edge(i) && (r < 0.5) == t.lit) as usize;
                counts[4] += (r > 0.0 && r < 1.0) as usize;
            } else {
                counts[3] += (!t.lit && r >= 0.5) as usize;
            }
        }
        eprintln!(
            "light {light}: {counts:?} (ground, in shadow, wrong away from edges, lost off the ground, partly lit)"
        );
        out.push(counts);
    }
    out
}

#[test]
fn on_the_sample_ground_planar_shadows_match_the_truth_and_elsewhere_there_are_none() {
    for (light, [ground, shadowed, wrong, lost_elsewhere, partial]) in sample_ground(planar()).into_iter().enumerate() {
        assert!(wrong <= ground / 1000, "light {light}: {wrong} of {ground} ground pixels wrong");
        assert_eq!(partial, 0, "light {light}: a planar shadow has no partly lit pixels");
        if light == 0 {
            // The sun shadows the ground and the boxes: on the ground planar has it, on the boxes
            // and the pillars nothing does.
            assert!(shadowed > 500, "the sun's shadow is on the ground: {shadowed}");
            assert!(lost_elsewhere > 100, "shadows off the ground are missing: {lost_elsewhere}");
        }
    }
}

#[test]
fn with_planar_ground_the_ground_takes_planar_shadows_and_the_rest_keeps_the_maps() {
    let settings = Settings::default().with(|s| s.shadow.planar_ground = true);
    let maps_only: Vec<[usize; 5]> = sample_ground(Settings::default());
    for (light, [ground, _, wrong, lost_elsewhere, partial]) in sample_ground(settings).into_iter().enumerate() {
        assert!(wrong <= ground / 1000, "light {light}: {wrong} of {ground} ground pixels wrong");
        // The ground's shadow is planar (all or nothing) where the maps' bilinear edge is not...
        assert_eq!(partial, 0, "light {light}: the ground reads a map");
        assert!(maps_only[light][4] > 0, "light {light}: the maps draw no partly lit edge to tell them apart");
        // ...and off the ground the maps still shadow: a few edge pixels lost (2 of the sun's
        // here), where planar alone loses over a hundred.
        assert!(lost_elsewhere <= 10, "light {light}: {lost_elsewhere} shadowed pixels off the ground drawn lit");
    }
}

#[test]
fn a_box_top_under_a_floating_cube_stays_lit() {
    let boxes = [(Vec3::new(0.0, 0.5, 0.0), Vec3::splat(0.5)), (Vec3::new(0.0, 2.5, 0.0), Vec3::splat(0.3))];
    let mut app = scene(&boxes, (Vec3::new(0.0, 4.0, 3.0), Vec3::new(0.0, 0.5, 0.0)));
    sun(&mut app, Vec3::NEG_Y, Vec3::ONE);
    let frame = measure(&mut app);
    let truth = truth::truth_of(&mut app.world, &frame, truth::SizeOverride::default(), 0);
    let under_cube = |i: usize| {
        let p = frame.position[i];
        frame.covered(i) && (p.y - 1.0).abs() < 1e-3 && p.x.abs() < 0.25 && p.z.abs() < 0.25
    };
    let pixels: Vec<usize> = (0..truth[0].len()).filter(|&i| under_cube(i)).collect();
    assert!(pixels.len() > 100, "the box top is in view: {}", pixels.len());
    assert!(pixels.iter().all(|&i| truth[0][i].is_some_and(|t| !t.lit)), "the truth shadows the box top");
    assert!(pixels.iter().all(|&i| frame.visibility[0][i] == 1.0), "planar shadows fall on the ground only");
}

/// Two plates, over x -0.9..0.1 at 1 m and over -0.1..0.9 at 1.5 m, seen from low down so the
/// ground under them is in view.
fn plates() -> App {
    let boxes =
        [(Vec3::new(-0.4, 1.0, 0.0), Vec3::new(0.5, 0.02, 0.5)), (Vec3::new(0.4, 1.5, 0.0), Vec3::new(0.5, 0.02, 0.5))];
    scene(&boxes, (Vec3::new(0.0, 0.4, 4.0), Vec3::ZERO))
}

#[test]
fn overlapping_casters_darken_the_ground_once_per_light() {
    let mut app = plates();
    sun(&mut app, Vec3::NEG_Y, Vec3::ONE);
    let image = render(&mut app, 0.0);
    let at = |app: &mut App, x: f32| brightness_at(app, &image, Vec3::new(x, 0.0, 0.0));
    let (only_low, both, only_high, open) =
        (at(&mut app, -0.6), at(&mut app, 0.0), at(&mut app, 0.6), at(&mut app, 1.6));
    eprintln!("brightness: low plate's shadow {only_low}, both {both}, high plate's {only_high}, lit {open}");
    assert!(open > only_low + 40.0, "the shadow darkens: {only_low} against {open}");
    assert!((both - only_low).abs() <= 2.0 && (both - only_high).abs() <= 2.0, "the overlap is darkened once");
}

#[test]
fn two_lights_darken_the_ground_twice_each_in_its_own_colour() {
    let mut app = plates();
    // A red sun from +X throws the plates' shadows towards -X, a blue one from -X towards +X.
    sun(&mut app, Vec3::new(-1.0, -2.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
    sun(&mut app, Vec3::new(1.0, -2.0, 0.0), Vec3::new(0.0, 0.0, 1.0));
    let image = render(&mut app, 0.0);
    let rgb = |app: &mut App, x: f32| {
        let (px, py) = pixel_of(app, Vec3::new(x, 0.0, 0.0));
        image.pixel(px, py).map(|p| [p[0] as i32, p[2] as i32]).unwrap()
    };
    // Each sun moves a shadow half the plate's height sideways: red's fall over x -1.4..-0.4
    // (low plate) and -0.85..0.15 (high), blue's over -0.4..0.6 and 0.65..1.65. So -1.1 is in
    // red's shadow only, 0 in both, 1 in blue's only, and -2 in neither.
    let (red_only, both, blue_only, open) =
        (rgb(&mut app, -1.1), rgb(&mut app, 0.0), rgb(&mut app, 1.0), rgb(&mut app, -2.0));
    eprintln!("[red, blue]: red's shadow {red_only:?}, both {both:?}, blue's {blue_only:?}, lit {open:?}");
    assert!(red_only[0] < open[0] - 40 && (red_only[1] - open[1]).abs() <= 2, "red's shadow takes red only");
    assert!(blue_only[1] < open[1] - 40 && (blue_only[0] - open[0]).abs() <= 2, "blue's shadow takes blue only");
    assert!((both[0] - red_only[0]).abs() <= 2 && (both[1] - blue_only[1]).abs() <= 2, "both take both, once each");
}

#[test]
fn no_planar_shadow_from_a_lamp_below_the_ground_or_a_caster_behind_a_spot() {
    let mut below = scene(&[(Vec3::new(0.0, 1.0, 0.0), Vec3::splat(0.3))], (Vec3::new(0.0, 4.0, 4.0), Vec3::ZERO));
    let lamp = PointLight { range: 10.0, ..Default::default() };
    below.world.spawn((lamp, Transform::from_xyz(0.0, -1.0, 0.0), ShadowMap::default()));
    below.set_time(0.0);
    assert!(extract(&below.world).planar.is_empty());
    // A spot 1 m up aimed along +X and down: a box in front of it shadows the ground, a box
    // behind it (a planar projection would throw its shadow back across the ground) does not.
    let boxes = [(Vec3::new(2.0, 0.3, 0.0), Vec3::splat(0.3)), (Vec3::new(-1.0, 0.3, 0.0), Vec3::splat(0.3))];
    let mut app = scene(&boxes, (Vec3::new(0.5, 6.0, 0.01), Vec3::new(0.5, 0.0, 0.0)));
    let spot = SpotLight { range: 12.0, intensity: 4.0, inner_angle: 0.6, outer_angle: 0.7, ..Default::default() };
    let at = Transform::from_xyz(0.0, 1.0, 0.0).looking_to(Vec3::new(1.0, -0.6, 0.0));
    app.world.spawn((spot, at, ShadowMap::default()));
    let frame = measure(&mut app);
    let dark = |side: f32| {
        (0..frame.position.len())
            .filter(|&i| on_ground(&frame, i) && frame.position[i].x * side > 0.0)
            .filter(|&i| (0.0..0.5).contains(&frame.visibility[0][i]))
            .count()
    };
    let (ahead, behind) = (dark(1.0), dark(-1.0));
    eprintln!("ground pixels shadowed: {ahead} ahead of the spot, {behind} behind it");
    assert!(ahead > 100, "the box in the cone casts");
    assert_eq!(behind, 0, "nothing is thrown back from behind the spot");
}
