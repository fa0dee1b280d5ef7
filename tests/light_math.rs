//! Light-matrix properties over the sample scene and many random directions and camera poses.

use glam::{Mat4, Vec3};
use umbra::components::{Camera, DirectionalLight, FlyCamera, ShadowCaster, ShadowMap, Transform, WorldBounds};
use umbra::shadow::{Aabb, fit_directional, frustum_corners, spot_projection};
use umbra::{App, Settings};

/// A small deterministic generator (xorshift) so failures reproduce.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }
    fn direction(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

fn inside(view_proj: &Mat4, p: Vec3) -> bool {
    let c = *view_proj * p.extend(1.0);
    let n = c.truncate() / c.w;
    let eps = 1e-4;
    c.w > 0.0 && n.x.abs() <= 1.0 + eps && n.y.abs() <= 1.0 + eps && n.z >= -eps && n.z <= 1.0 + eps
}

fn axes() -> [Vec3; 6] {
    [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z]
}

#[test]
fn matrices_are_finite_for_the_axes_and_a_thousand_random_directions() {
    let corners = Aabb::new(Vec3::new(-10.0, 0.0, -10.0), Vec3::new(10.0, 4.0, 10.0)).corners();
    let casters = [Aabb::new(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 8.0, 1.0))];
    let mut rng = Rng(0x5eed);
    let random: Vec<Vec3> = (0..1000).map(|_| rng.direction()).collect();
    for d in axes().into_iter().chain(random) {
        let sun = fit_directional(d, &corners, &casters, 2048);
        assert!(sun.view_proj.is_finite() && sun.view_proj.determinant() != 0.0, "sun {d:?}");
        let spot = spot_projection(Vec3::new(1.0, 5.0, 2.0), d, 0.4, 12.0, 1024);
        assert!(spot.view_proj.is_finite() && spot.view_proj.determinant() != 0.0, "spot {d:?}");
    }
}

/// Moves the sample's camera to a random pose in and around the scene.
fn random_pose(app: &mut App, rng: &mut Rng) {
    let mut q = app.world.query::<(&mut FlyCamera, &mut Transform)>();
    let (mut fly, mut t) = q.single_mut(&mut app.world).unwrap();
    fly.yaw = rng.range(-3.14, 3.14);
    fly.pitch = rng.range(-1.2, 0.2);
    t.translation = Vec3::new(rng.range(-15.0, 15.0), rng.range(0.5, 12.0), rng.range(-15.0, 15.0));
}

#[test]
fn every_caster_in_view_lands_inside_the_sun_volume() {
    let settings = Settings::default();
    let mut app = App::new(settings.clone()).unwrap();
    let mut rng = Rng(42);
    let mut checked = 0;
    for step in 0..150 {
        if step > 0 {
            random_pose(&mut app, &mut rng);
        }
        app.set_time(step as f64 * 0.37);
        let (camera, transform) = app.world.query::<(&Camera, &Transform)>().single(&app.world).map(|(c, t)| (*c, *t)).unwrap();
        let view_camera = Camera { far: settings.shadow_distance, ..camera };
        let view = view_camera.view_proj(&transform, 1280.0 / 720.0);
        let sun = *app.world.query::<(&DirectionalLight, &ShadowMap)>().single(&app.world).unwrap().1;
        let casters: Vec<Aabb> = app
            .world
            .query_filtered::<&WorldBounds, bevy_ecs::query::With<ShadowCaster>>()
            .iter(&app.world)
            .map(|b| b.0)
            .collect();
        for b in casters {
            if b.corners().iter().all(|c| inside(&view, *c)) {
                checked += 1;
                for c in b.corners() {
                    assert!(inside(&sun.view_proj, c), "step {step}: corner {c:?} of {b:?} is outside the sun's volume");
                }
            }
        }
    }
    assert!(checked > 100, "only {checked} casters were in view: the test checks too little");
}

#[test]
fn the_fitted_box_is_no_bigger_than_the_view_needs() {
    // The sun's box around the view volume is at most the volume's light-space extent across.
    let mut app = App::new(Settings::default()).unwrap();
    app.set_time(0.0);
    let (camera, transform) = app.world.query::<(&Camera, &Transform)>().single(&app.world).map(|(c, t)| (*c, *t)).unwrap();
    let view_camera = Camera { far: Settings::default().shadow_distance, ..camera };
    let corners = frustum_corners(&view_camera.view_proj(&transform, 1280.0 / 720.0));
    let sun = *app.world.query::<(&DirectionalLight, &ShadowMap)>().single(&app.world).unwrap().1;
    // Every view-volume corner is inside, and at least one touches the box's side (tight fit).
    let ndc: Vec<Vec3> = corners.iter().map(|c| sun.view_proj.project_point3(*c)).collect();
    assert!(ndc.iter().all(|n| n.x.abs() <= 1.0 + 1e-4 && n.y.abs() <= 1.0 + 1e-4));
    assert!(ndc.iter().any(|n| n.x.abs() > 0.999) && ndc.iter().any(|n| n.y.abs() > 0.999));
}

#[test]
fn points_inside_a_spot_cone_land_inside_its_volume() {
    let mut rng = Rng(7);
    for _ in 0..200 {
        let pos = Vec3::new(rng.range(-5.0, 5.0), rng.range(1.0, 8.0), rng.range(-5.0, 5.0));
        let dir = rng.direction();
        let (half, range) = (rng.range(0.05, 1.2), rng.range(2.0, 30.0));
        let fit = spot_projection(pos, dir, half, range, 512);
        for _ in 0..20 {
            // A point at a random distance and at most 95% of the cone's half angle off its axis.
            let off = rng.direction().reject_from(dir).normalize_or(dir.any_orthonormal_vector());
            let angle = half * 0.95 * rng.next();
            let dist = rng.range(0.05, 0.99) * range;
            let p = pos + (dir * angle.cos() + off * angle.sin()) * dist;
            if dist * angle.cos() > range * 0.006 {
                assert!(inside(&fit.view_proj, p), "{p:?} in cone of half angle {half} from {pos:?}");
            }
        }
    }
}
