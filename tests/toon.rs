//! Toon shading: a point light over an open ground falls into exactly as many bands as asked,
//! and a box's shadow takes the ground under it exactly one band down.

mod common;

use common::*;
use glam::Vec3;
use umbra::assets::{MeshLibrary, cube, plane};
use umbra::components::*;
use umbra::render::Image;
use umbra::{App, Settings};

const BANDS: u32 = 4;
const LAMP: Vec3 = Vec3::new(0.0, 1.5, 0.0);

fn grey() -> Material {
    Material { specular: 0.0, shininess: 1.0, ..Material::color(0.6, 0.6, 0.6) }
}

/// A lamp 1.5 m over the ground and a 50 cm box 1.5 m to its +X side, seen from above.
fn scene(shadows: bool) -> App {
    // A plain ground: the test counts its levels, which the checker would double.
    let settings = Settings::default().with(|s| {
        s.view.toon_bands = BANDS;
        s.shadow.enabled = shadows;
        s.view.ground_grid = false;
    });
    let mut app = App::empty(settings).unwrap();
    let (ground, block) = {
        let mut meshes = app.world.resource_mut::<MeshLibrary>();
        (meshes.add(plane(40.0)), meshes.add(cube(Vec3::splat(0.5))))
    };
    app.world.spawn((ground, Transform::default(), grey(), ShadowReceiver));
    let at = Transform::from_xyz(1.5, 0.25, 0.0).with_scale(Vec3::splat(0.5));
    app.world.spawn((block, at, grey(), ShadowCaster, ShadowReceiver));
    let lamp = PointLight { range: 10.0, intensity: 1.0, ..Default::default() };
    app.world.spawn((lamp, Transform::from_translation(LAMP), ShadowMap::default()));
    app.world.spawn(camera_at(Vec3::new(0.0, 11.0, 0.01), Vec3::ZERO));
    app
}

/// Ground points every 5 cm over 8 m by 8 m, leaving out the box's foot.
fn ground_points() -> Vec<Vec3> {
    let steps = (-80..=80).map(|i| i as f32 * 0.05);
    let grid: Vec<Vec3> = steps.clone().flat_map(|x| steps.clone().map(move |z| Vec3::new(x, 0.0, z))).collect();
    grid.into_iter().filter(|p| !((1.15..1.85).contains(&p.x) && p.z.abs() < 0.35)).collect()
}

fn colour(app: &mut App, image: &Image, p: Vec3) -> [u8; 4] {
    let (x, y) = pixel_of(app, p);
    image.pixel(x, y).unwrap()
}

/// Deep in the box's shadow: the box's top (x 1.25..1.75, 50 cm up) seen from the lamp covers the
/// ground from x = 1.9 to 2.6 and |z| < 0.37.
fn shadowed(p: Vec3) -> bool {
    (1.95..2.5).contains(&p.x) && p.z.abs() < 0.2
}

/// Clear of the box's shadow.
fn clear(p: Vec3) -> bool {
    p.x < 1.0 || p.z.abs() > 0.6
}

#[test]
fn the_ground_falls_into_the_bands_asked_for_and_a_shadow_is_one_band_down() {
    let mut on = scene(true);
    let mut off = scene(false);
    let (lit, unshadowed) = (render(&mut on, 0.0), render(&mut off, 0.0));
    let points = ground_points();
    // Without shadows: the lamp's strength (its angle and falloff) over the ground in exactly
    // BANDS levels, brightest under it.
    let mut levels: Vec<[u8; 4]> = points.iter().map(|&p| colour(&mut off, &unshadowed, p)).collect();
    levels.sort_by_key(|c| c[0] as u32 + c[1] as u32 + c[2] as u32);
    levels.dedup();
    assert_eq!(levels.len(), BANDS as usize, "levels of the lit ground: {levels:?}");
    assert_eq!(colour(&mut off, &unshadowed, Vec3::ZERO), *levels.last().unwrap(), "brightest under the lamp");
    let rank = |c: [u8; 4]| levels.iter().position(|l| *l == c);
    let (mut down, mut same) = (0, 0);
    // A pixel on the line between two bands may fall either side of it in two pipelines (the
    // one with shadows compiles the same sum differently): judge the pixels inside a band.
    let inside_band = |x: u32, y: u32| {
        let c = unshadowed.pixel(x, y);
        [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)].iter().all(|&(i, j)| unshadowed.pixel(i, j) == c)
    };
    for &p in &points {
        let (x, y) = pixel_of(&mut off, p);
        if !inside_band(x, y) {
            continue;
        }
        let (with, without) = (colour(&mut on, &lit, p), colour(&mut off, &unshadowed, p));
        let without = rank(without).expect("a band");
        if shadowed(p) {
            // One band down (from the lowest, to the ambient light alone: no band).
            assert_eq!(rank(with), without.checked_sub(1), "{p}: shadowed, yet not one band down");
            down += 1;
        } else if clear(p) {
            assert_eq!(rank(with), Some(without), "{p}: clear of the shadow, yet not its band");
            same += 1;
        }
    }
    assert!(down > 50 && same > 10_000, "{down} shadowed and {same} clear points");
}
