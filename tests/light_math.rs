//! Light-matrix properties: cascade splits and fitting over many random directions and camera
//! poses, stable-fit invariances, and spot-light cones.

use glam::{Mat4, Quat, Vec3};
use umbra::components::{Camera, DirectionalLight, FlyCamera, ShadowCaster, ShadowMap, Transform, WorldBounds};
use umbra::shadow::{Aabb, FitMode, SceneBounds, ViewFrustum, depth_step, fit_cascade, split_depths, spot_projection};
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

/// Moves the sample's camera to a random pose in and around the scene.
fn random_pose(app: &mut App, rng: &mut Rng) {
    let mut q = app.world.query::<(&mut FlyCamera, &mut Transform)>();
    let (mut fly, mut t) = q.single_mut(&mut app.world).unwrap();
    fly.yaw = rng.range(-std::f32::consts::PI, std::f32::consts::PI);
    fly.pitch = rng.range(-1.2, 0.2);
    t.translation = Vec3::new(rng.range(-15.0, 15.0), rng.range(0.5, 12.0), rng.range(-15.0, 15.0));
}

/// A random camera pose somewhere in and around the scene.
fn random_frustum(rng: &mut Rng) -> ViewFrustum {
    let rotation = Quat::from_rotation_y(rng.range(-std::f32::consts::PI, std::f32::consts::PI))
        * Quat::from_rotation_x(rng.range(-1.5, 1.5));
    let position = Vec3::new(rng.range(-30.0, 30.0), rng.range(0.2, 20.0), rng.range(-30.0, 30.0));
    ViewFrustum { position, rotation, fov_y: rng.range(0.3, 2.0), aspect: rng.range(0.5, 2.5) }
}

fn scene_boxes() -> (Vec<Aabb>, Vec<Aabb>) {
    let casters = vec![
        Aabb::new(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 8.0, 1.0)),
        Aabb::new(Vec3::new(4.0, 1.0, 3.0), Vec3::new(5.0, 2.0, 4.0)),
    ];
    let ground = vec![Aabb::new(Vec3::new(-40.0, -0.01, -40.0), Vec3::new(40.0, 0.0, 40.0))];
    (casters, ground)
}

#[test]
fn matrices_are_finite_for_the_axes_and_ten_thousand_random_directions_and_poses() {
    let (casters, ground) = scene_boxes();
    let scene = SceneBounds { casters: &casters, receivers: &ground };
    let mut rng = Rng(0x5eed);
    let random: Vec<Vec3> = (0..10_000).map(|_| rng.direction()).collect();
    for (i, d) in axes().into_iter().chain(random).enumerate() {
        let frustum = random_frustum(&mut rng);
        let depths = split_depths(0.1, 60.0, 4, 0.75);
        for mode in [FitMode::Stable, FitMode::Tight] {
            let c = 1 + i % 4;
            let sun = fit_cascade(d, &frustum, depths[c - 1], depths[c], mode, scene, 2048);
            assert!(sun.view_proj.is_finite() && sun.view_proj.determinant() != 0.0, "sun {d:?} {mode:?} {frustum:?}");
            assert!(sun.texel.is_finite() && sun.texel.x > 0.0);
        }
        let spot = spot_projection(frustum.position, d, 0.4, 12.0, 1024);
        assert!(spot.view_proj.is_finite() && spot.view_proj.determinant() != 0.0, "spot {d:?}");
    }
}

#[test]
fn splits_increase_and_cover_near_to_the_shadow_distance() {
    let mut rng = Rng(3);
    for _ in 0..2000 {
        let near = rng.range(0.01, 2.0);
        let far = near + rng.range(0.5, 500.0);
        let count = 1 + (rng.next() * 4.0) as usize % 4;
        let lambda = rng.next();
        let d = split_depths(near, far, count, lambda);
        assert_eq!(d.len(), count + 1);
        assert_eq!((d[0], d[count]), (near, far), "the splits cover exactly [near, far]");
        assert!(d.windows(2).all(|w| w[1] > w[0]), "{d:?} do not increase");
    }
}

/// Projection of a cascade's slice of the view: what the camera sees between two depths.
fn slice_view_proj(f: &ViewFrustum, a: f32, b: f32) -> Mat4 {
    let proj = glam::camera::rh::proj::directx::perspective(f.fov_y, f.aspect, a, b);
    proj * Mat4::from_rotation_translation(f.rotation, f.position).inverse()
}

#[test]
fn every_caster_corner_inside_a_cascade_slice_lands_inside_its_clip_box() {
    let (mut casters, ground) = scene_boxes();
    let mut rng = Rng(42);
    for _ in 0..40 {
        let (x, z) = (rng.range(-20.0, 20.0), rng.range(-20.0, 20.0));
        let (w, h) = (rng.range(0.1, 2.0), rng.range(0.1, 6.0));
        casters.push(Aabb::new(Vec3::new(x, 0.0, z), Vec3::new(x + w, h, z + w)));
    }
    let scene = SceneBounds { casters: &casters, receivers: &ground };
    let mut checked = 0;
    for _ in 0..300 {
        let frustum = random_frustum(&mut rng);
        let dir = Vec3::new(rng.range(-1.0, 1.0), -rng.range(0.2, 1.0), rng.range(-1.0, 1.0));
        let depths = split_depths(0.1, 60.0, 4, 0.75);
        for c in 0..4 {
            let slice = slice_view_proj(&frustum, depths[c], depths[c + 1]);
            for mode in [FitMode::Stable, FitMode::Tight] {
                let fit = fit_cascade(dir, &frustum, depths[c], depths[c + 1], mode, scene, 2048);
                for b in &casters {
                    for corner in b.corners().into_iter().filter(|p| inside(&slice, *p)) {
                        checked += 1;
                        assert!(inside(&fit.view_proj, corner), "{mode:?} cascade {c}: {corner:?} of {b:?}");
                    }
                }
            }
        }
    }
    assert!(checked > 1000, "only {checked} corners were inside a slice: the test checks too little");
}

#[test]
fn a_stable_cascade_ignores_sub_texel_moves_and_keeps_its_texel_size_when_turned() {
    let (casters, ground) = scene_boxes();
    let scene = SceneBounds { casters: &casters, receivers: &ground };
    let mut rng = Rng(11);
    let dir = Vec3::new(-0.45, -1.0, -0.35);
    let light = umbra::shadow::light_view(Vec3::ZERO, dir);
    let (a, b) = (4.0, 12.0);
    for _ in 0..200 {
        let mut f = random_frustum(&mut rng);
        let fit = fit_cascade(dir, &f, a, b, FitMode::Stable, scene, 1024);
        // Put the slice's sphere exactly on a texel corner (where the snap rounds to) and midway
        // between two depth steps, then move by less than a quarter texel: nothing may change.
        let (centre, r) = f.slice_sphere(a, b);
        let (texel, step) = (fit.texel.x, depth_step(r));
        let c = light.transform_point3(centre);
        let far = c.z - r;
        let target = Vec3::new(
            (c.x / texel).round() * texel,
            (c.y / texel).round() * texel,
            c.z + ((far / step).floor() + 0.5) * step - far,
        );
        f.position += light.inverse().transform_vector3(target - c);
        let start = fit_cascade(dir, &f, a, b, FitMode::Stable, scene, 1024);
        for _ in 0..10 {
            let nudge = rng.direction() * 0.25 * texel;
            let moved = ViewFrustum { position: f.position + nudge, ..f };
            let after = fit_cascade(dir, &moved, a, b, FitMode::Stable, scene, 1024);
            assert_eq!(
                start.view_proj,
                after.view_proj,
                "a {:.3}-texel move changed the cascade",
                nudge.length() / texel
            );
        }
        // Turning the camera changes where the cascade is, never its texel size.
        let turned = ViewFrustum { rotation: Quat::from_rotation_y(rng.range(-3.0, 3.0)) * f.rotation, ..f };
        assert_eq!(fit_cascade(dir, &turned, a, b, FitMode::Stable, scene, 1024).texel, start.texel);
    }
}

/// Width times height of an orthographic projection's box.
fn ortho_area(proj: &Mat4) -> f32 {
    (2.0 / proj.x_axis.x) * (2.0 / proj.y_axis.y)
}

#[test]
fn tight_mode_covers_no_more_area_than_stable_and_touches_the_slice() {
    let (casters, ground) = scene_boxes();
    let scene = SceneBounds { casters: &casters, receivers: &ground };
    let mut rng = Rng(5);
    for _ in 0..1000 {
        let f = random_frustum(&mut rng);
        let dir = rng.direction();
        let a = rng.range(0.1, 20.0);
        let b = a + rng.range(0.5, 40.0);
        let stable = fit_cascade(dir, &f, a, b, FitMode::Stable, scene, 2048);
        let tight = fit_cascade(dir, &f, a, b, FitMode::Tight, scene, 2048);
        assert!(ortho_area(&tight.proj) <= ortho_area(&stable.proj) * (1.0 + 1e-4), "{f:?} {dir:?} {a}..{b}");
        // And it is tight: the slice touches the box on both axes.
        let ndc: Vec<Vec3> = f.slice_corners(a, b).iter().map(|c| tight.view_proj.project_point3(*c)).collect();
        assert!(ndc.iter().all(|n| n.x.abs() <= 1.0 + 1e-4 && n.y.abs() <= 1.0 + 1e-4));
        assert!(ndc.iter().any(|n| n.x.abs() > 0.999) && ndc.iter().any(|n| n.y.abs() > 0.999));
    }
}

#[test]
fn every_caster_in_view_lands_inside_the_cascade_that_covers_it() {
    let settings = Settings::default();
    let mut app = App::new(settings.clone()).unwrap();
    let mut rng = Rng(42);
    let mut checked = 0;
    for step in 0..150 {
        if step > 0 {
            random_pose(&mut app, &mut rng);
        }
        app.set_time(step as f64 * 0.37);
        let (camera, transform) =
            app.world.query::<(&Camera, &Transform)>().single(&app.world).map(|(c, t)| (*c, *t)).unwrap();
        let sun = app.world.query::<(&DirectionalLight, &ShadowMap)>().single(&app.world).unwrap().1.clone();
        let casters: Vec<Aabb> = app
            .world
            .query_filtered::<&WorldBounds, bevy_ecs::query::With<ShadowCaster>>()
            .iter(&app.world)
            .map(|b| b.0)
            .collect();
        let mut start = camera.near;
        for cascade in &sun.layers {
            let view = Camera { near: start, far: cascade.far, ..camera }.view_proj(&transform, 1280.0 / 720.0);
            for b in &casters {
                if b.corners().iter().all(|c| inside(&view, *c)) {
                    checked += 1;
                    for c in b.corners() {
                        assert!(
                            inside(&cascade.clip_from_world, c),
                            "step {step}: {c:?} of {b:?} is outside its cascade"
                        );
                    }
                }
            }
            start = cascade.far - cascade.blend;
        }
    }
    assert!(checked > 100, "only {checked} casters were in view: the test checks too little");
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
