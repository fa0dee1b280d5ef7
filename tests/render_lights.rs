//! Render tests of the light-fitting features: a caster off screen still shadows the view, the
//! cascade debug view shows one tint per cascade, and a cookie shapes a spot light's pool.

mod common;

use common::*;
use glam::Vec3;
use umbra::assets::{MeshLibrary, cube, plane};
use umbra::components::*;
use umbra::render::Image;
use umbra::{App, Settings};

fn grey() -> Material {
    Material { specular: 0.0, shininess: 1.0, ..Material::color(0.6, 0.6, 0.6) }
}

/// An app with a 60 m grey ground and a camera at `eye` looking at `target`.
fn ground_app(settings: Settings, eye: Vec3, target: Vec3) -> App {
    let mut app = App::empty(settings).unwrap();
    let ground = app.world.resource_mut::<MeshLibrary>().add(plane(200.0));
    app.world.spawn((ground, Transform::default(), grey(), ShadowReceiver));
    app.world.spawn(camera_at(eye, target));
    app
}

#[test]
fn a_tall_caster_behind_the_camera_shadows_the_visible_ground() {
    let scene = |shadows| {
        let mut app =
            ground_app(Settings::default().with(|s| s.shadow.enabled = shadows), Vec3::new(0.0, 3.0, 10.0), Vec3::ZERO);
        let block = app.world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
        // 20 m tall at z = 16, behind the camera; the sun travels towards -z at 45 degrees, so the
        // pillar's shadow runs along x = 0 from z = 16 to z = -4, right through the view.
        let pillar = Transform::from_xyz(0.0, 10.0, 16.0).with_scale(Vec3::new(1.0, 20.0, 1.0));
        app.world.spawn((block, pillar, grey(), ShadowCaster));
        let sun = DirectionalLight {
            direction: Vec3::new(0.0, -1.0, -1.0),
            color: Vec3::ONE,
            intensity: 1.0,
            ..Default::default()
        };
        app.world.spawn((sun, ShadowMap::default()));
        app
    };
    let (mut on, mut off) = (scene(true), scene(false));
    let (a, b) = (render(&mut on, 0.0), render(&mut off, 0.0));
    // The pillar is nowhere in the picture: every corner is behind the camera.
    let vp = {
        let (c, t) = on.world.query::<(&Camera, &Transform)>().single(&on.world).unwrap();
        c.view_proj(t, 1.0)
    };
    let pillar = on.world.query::<(&ShadowCaster, &WorldBounds)>().single(&on.world).unwrap().1.0;
    assert!(pillar.corners().iter().all(|c| (vp * c.extend(1.0)).w < 0.0), "the pillar must be off screen");
    for z in [2.0, 0.0, -2.0] {
        let (x, y) = pixel_of(&mut on, Vec3::new(0.0, 0.0, z));
        assert!(a.brightness(x, y) < 0.5 * b.brightness(x, y), "the pillar's shadow is missing at z = {z}");
        let (x, y) = pixel_of(&mut on, Vec3::new(2.0, 0.0, z));
        assert!((a.brightness(x, y) - b.brightness(x, y)).abs() < 2.0, "beside the shadow at z = {z}");
    }
}

/// Which debug tint a pixel wears, from its colour with tints over its colour without: 0..3 for
/// the cascades, 4 for none (past the shadow distance), `None` for too dark to tell.
fn tint_of(tinted: [u8; 4], plain: [u8; 4]) -> Option<usize> {
    let linear = |c: u8| {
        let c = c as f32 / 255.0;
        if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
    };
    if plain[..3].iter().any(|c| *c < 20) {
        return None;
    }
    let ratio = Vec3::from_array(std::array::from_fn(|i| linear(tinted[i]) / linear(plain[i])));
    let ratio = ratio / ratio.max_element();
    let tints = [
        Vec3::new(1.0, 0.3, 0.3),
        Vec3::new(0.3, 1.0, 0.3),
        Vec3::new(0.35, 0.45, 1.0),
        Vec3::new(1.0, 0.9, 0.25),
        Vec3::ONE,
    ];
    let (best, distance) =
        tints.iter().map(|t| (ratio - *t / t.max_element()).length()).enumerate().min_by(|a, b| a.1.total_cmp(&b.1))?;
    (distance < 0.15).then_some(best)
}

#[test]
fn the_cascade_debug_view_shows_one_tint_per_cascade() {
    for cascades in [1, 2, 4] {
        // Low over the ground looking at the horizon: the view runs from 1.6 m to past 60 m.
        let shot = |debug| {
            let settings = Settings::default().with(|s| {
                s.cascade.cascades = cascades;
                s.view.cascade_debug = debug;
            });
            let mut app = ground_app(settings, Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.6, -30.0));
            let sun = DirectionalLight {
                direction: Vec3::new(0.3, -1.0, 0.2),
                color: Vec3::ONE,
                intensity: 1.0,
                ..Default::default()
            };
            app.world.spawn((sun, ShadowMap::default()));
            render(&mut app, 0.0)
        };
        let (tinted, plain): (Image, Image) = (shot(true), shot(false));
        let mut counts = [0usize; 5];
        for (t, p) in tinted.pixels.chunks(4).zip(plain.pixels.chunks(4)) {
            if let Some(i) = tint_of(t.try_into().unwrap(), p.try_into().unwrap()) {
                counts[i] += 1;
            }
        }
        let shown = counts[..4].iter().filter(|n| **n > (SIZE * SIZE / 200) as usize).count();
        assert_eq!(shown, cascades as usize, "{cascades} cascades, tinted pixels per cascade {counts:?}");
        assert!(counts[..cascades as usize].iter().all(|n| *n > 0), "{counts:?}");
    }
}

#[test]
fn a_window_cookie_casts_bars_and_panes_in_the_spot_light() {
    let shot = |intensity, cookie: Option<Cookie>| {
        let mut app = ground_app(Settings::default(), Vec3::new(0.0, 6.0, 3.0), Vec3::ZERO);
        let spot = SpotLight {
            color: Vec3::ONE,
            intensity,
            range: 10.0,
            inner_angle: 15f32.to_radians(),
            outer_angle: 20f32.to_radians(),
            ..Default::default()
        };
        let mut light =
            app.world.spawn((spot, Transform::from_xyz(0.0, 4.0, 0.0).looking_to(Vec3::NEG_Y), ShadowMap::default()));
        if let Some(c) = cookie {
            light.insert(c);
        }
        let image = render(&mut app, 0.0);
        (app, image)
    };
    let (mut app, window) = shot(3.0, Some(Cookie::Window));
    let (_, open) = shot(3.0, None);
    let (_, dark) = shot(0.0, None);
    let at = |app: &mut App, img: &Image, p: Vec3| brightness_at(app, img, p);
    // The cone reaches 1.46 m on the ground; the cookie's square spans the cone, its cross bars
    // run along x = 0 and z = 0 and its frame covers the outer 12 % of each side.
    for bar in [Vec3::new(0.0, 0.0, 0.6), Vec3::new(0.6, 0.0, 0.0), Vec3::new(-1.3, 0.0, 0.0)] {
        let (w, o, d) = (at(&mut app, &window, bar), at(&mut app, &open, bar), at(&mut app, &dark, bar));
        assert!((w - d).abs() < 3.0, "the bar at {bar:?} lets light through: {w} vs unlit {d}");
        assert!(o > d + 5.0, "without the cookie the spot lights {bar:?}: {o} vs {d}");
    }
    for pane in
        [Vec3::new(0.6, 0.0, 0.6), Vec3::new(-0.6, 0.0, 0.6), Vec3::new(0.6, 0.0, -0.6), Vec3::new(-0.6, 0.0, -0.6)]
    {
        let (w, o, d) = (at(&mut app, &window, pane), at(&mut app, &open, pane), at(&mut app, &dark, pane));
        assert!(w > d + 20.0, "the pane at {pane:?} is dark: {w} vs unlit {d}");
        assert!((w - o).abs() < 3.0, "the pane at {pane:?} lets all the light through: {w} vs {o}");
    }
}
