//! Ground truth: shadow rays cast on the CPU, against exactly the triangles the GPU drew into
//! the shadow maps, from every pixel of a measured frame.
//!
//! Ray origins are pushed 2 mm off the surface along the normal the renderer shaded with (on the
//! sample's flat-shaded boxes that is the geometric normal; on the smooth-shaded character it
//! differs by a few degrees, which does not matter at 2 mm). 2 mm is far above the float error
//! of a position 60 m away (about 0.05 mm) and far below the thinnest caster tested (2 cm poles),
//! so a surface never shadows itself and no real occluder is skipped.

use crate::assets::skin::skin_vertices;
use crate::assets::{MeshLibrary, TextureData, TextureLibrary};
use crate::components::{Joints, Material, Mesh, ShadowCaster, Transform};
use crate::light::{Emitter, Kind, light_list};
use crate::render::DebugFrame;
use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3, Vec4};
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use std::sync::Arc;

/// How far shadow rays start off the surface, in metres (see the module notes).
pub const RAY_OFFSET: f32 = 0.002;

/// Where a cut-out caster's surface is there: alpha (texture × vertex colour × the material's
/// opacity) at or above its cutoff, sampled at a ray's hit as the shadow pass samples it.
#[derive(Clone, Debug)]
pub struct Cutout {
    /// Texture coordinates at the three corners.
    pub uv: [Vec2; 3],
    /// Alpha before the texture (vertex colour × opacity) at the three corners.
    pub alpha: [f32; 3],
    /// The base-colour texture, if any.
    pub texture: Option<Arc<TextureData>>,
    /// Alpha below which the surface is not there.
    pub cutoff: f32,
}

impl Cutout {
    /// True when the surface is there at barycentric weights `w` of the triangle.
    #[must_use]
    pub fn solid_at(&self, w: Vec3) -> bool {
        let uv = self.uv[0] * w.x + self.uv[1] * w.y + self.uv[2] * w.z;
        let alpha = self.alpha[0] * w.x + self.alpha[1] * w.y + self.alpha[2] * w.z;
        alpha * self.texture.as_ref().map_or(1.0, |t| t.alpha(uv)) >= self.cutoff
    }
}

/// One triangle of a shadow caster, in world space, and its cutout if its material has one.
#[derive(Clone, Debug)]
pub struct CasterTriangle {
    /// The corners.
    pub corners: [Vec3; 3],
    /// Where the surface is there (none: everywhere).
    pub cutout: Option<Cutout>,
}

/// The shadow casters of a scene as triangles in a BVH.
pub struct Occluders {
    bvh: CwBvh,
    triangles: Vec<Triangle>,
    /// For each triangle, its cutout, if any.
    cutouts: Vec<Option<Cutout>>,
}

/// World-space triangles of every shadow caster of `world` as it is now: each mesh skinned on
/// the CPU with the joint matrices the GPU was given, then placed by its model matrix; masked
/// and blended materials carry their cutout (blended ones cut at [`crate::components::BLEND_CUTOFF`],
/// as in the shadow pass).
pub fn caster_triangles(world: &mut World) -> Vec<CasterTriangle> {
    let mut out = Vec::new();
    let mut casters =
        world.query_filtered::<(&Mesh, &Transform, Option<&Joints>, Option<&Material>), With<ShadowCaster>>();
    let library = world.resource::<MeshLibrary>();
    let textures = world.get_resource::<TextureLibrary>();
    for (mesh, transform, joints, material) in casters.iter(world) {
        let Some(data) = library.get(*mesh) else { continue };
        let vertices = match joints {
            Some(j) if data.skin.is_some() => skin_vertices(data, &j.0),
            _ => data.vertices.clone(),
        };
        let material = material.copied().unwrap_or_default();
        let texture = material.texture.and_then(|t| textures.and_then(|l| l.get(t)).cloned());
        let model = transform.matrix();
        for t in data.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| &vertices[t[k] as usize]);
            let cutout = material.alpha_mode.cutoff().map(|cutoff| Cutout {
                uv: [a, b, c].map(|v| Vec2::from(v.uv)),
                alpha: [a, b, c].map(|v| v.color[3] * material.opacity),
                texture: texture.clone(),
                cutoff,
            });
            let corners = [a, b, c].map(|v| model.transform_point3(Vec3::from(v.position)));
            out.push(CasterTriangle { corners, cutout });
        }
    }
    out
}

impl Occluders {
    /// A BVH over solid `triangles`.
    pub fn new(triangles: &[[Vec3; 3]]) -> Occluders {
        Occluders::with_cutouts(triangles.iter().map(|&corners| CasterTriangle { corners, cutout: None }).collect())
    }

    /// A BVH over caster triangles, some of them cut out.
    pub fn with_cutouts(triangles: Vec<CasterTriangle>) -> Occluders {
        let (triangles, cutouts): (Vec<Triangle>, Vec<Option<Cutout>>) = triangles
            .into_iter()
            .filter(|t| t.corners.iter().all(|p| p.is_finite()))
            .map(|t| {
                let [v0, v1, v2] = t.corners.map(Into::into);
                (Triangle { v0, v1, v2 }, t.cutout)
            })
            .unzip();
        let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(
            &triangles,
            obvhs::BvhBuildParams::fast_build(),
            &mut std::time::Duration::default(),
        );
        Occluders { bvh, triangles, cutouts }
    }

    /// The casters of `world` as they are now.
    pub fn from_world(world: &mut World) -> Occluders {
        Occluders::with_cutouts(caster_triangles(world))
    }

    /// Distance along `r` to BVH primitive `i`, infinite where it misses or its cutout is not
    /// there.
    fn hit(&self, r: &Ray, i: usize) -> f32 {
        let k = self.bvh.primitive_indices[i] as usize;
        let tri = &self.triangles[k];
        let t = tri.intersect(r);
        match &self.cutouts[k] {
            Some(cutout) if t.is_finite() => {
                let p = Vec3::from(r.origin + r.direction * t);
                let w = barycentric(p, [tri.v0.into(), tri.v1.into(), tri.v2.into()]);
                if cutout.solid_at(w) { t } else { f32::INFINITY }
            }
            _ => t,
        }
    }

    /// True when a caster lies on the segment from `origin` along unit `dir` up to `max`.
    pub fn occluded(&self, origin: Vec3, dir: Vec3, max: f32) -> bool {
        if self.triangles.is_empty() || !origin.is_finite() || !dir.is_finite() {
            return false;
        }
        let ray = Ray::new(origin.into(), positive_zeros(dir), 0.0, max);
        !self.bvh.ray_traverse_miss(ray, |r, i| self.hit(r, i))
    }

    /// Distance along unit `dir` from `origin` to the nearest caster, if any.
    pub fn first_hit(&self, origin: Vec3, dir: Vec3) -> Option<f32> {
        if self.triangles.is_empty() || !origin.is_finite() || !dir.is_finite() {
            return None;
        }
        let mut hit = RayHit::none();
        let ray = Ray::new_inf(origin.into(), positive_zeros(dir));
        self.bvh.ray_traverse(ray, &mut hit, |r, i| self.hit(r, i)).then_some(hit.t)
    }
}

/// Barycentric weights of `p` (in the triangle's plane) against `corners`.
fn barycentric(p: Vec3, [a, b, c]: [Vec3; 3]) -> Vec3 {
    let (e1, e2, d) = (b - a, c - a, p - a);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = d11 * d22 - d12 * d12;
    if det.abs() <= f32::MIN_POSITIVE {
        return Vec3::X;
    }
    let (dp1, dp2) = (d.dot(e1), d.dot(e2));
    let v = (d22 * dp1 - d12 * dp2) / det;
    let w = (d11 * dp2 - d12 * dp1) / det;
    Vec3::new(1.0 - v - w, v, w)
}

/// `d` with any -0.0 made +0.0: the BVH picks its traversal order from the sign bits of the
/// direction, and a negative zero (from negating an axis) sends it the wrong way.
fn positive_zeros(d: Vec3) -> glam::Vec3A {
    (d + Vec3::ZERO).into()
}

/// Light sizes that replace the scene's own for the soft truth (`bench --sun-radius`,
/// `--spot-radius`), where given.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SizeOverride {
    /// Angular radius of every sun, in radians.
    pub sun_angular_radius: Option<f32>,
    /// Radius of every spot and point light, in metres.
    pub light_radius: Option<f32>,
}

/// The lights of `world` in the order the measuring view reports them, as the truth casts rays
/// to them, each with its own size (or the one `sizes` gives).
pub fn truth_lights(world: &mut World, sizes: SizeOverride) -> Vec<Emitter> {
    light_list(world)
        .iter()
        .map(|l| match l.kind.emitter() {
            Emitter::Distant { towards, angular_radius } => {
                Emitter::Distant { towards, angular_radius: sizes.sun_angular_radius.unwrap_or(angular_radius) }
            }
            Emitter::Local { position, range, radius, facing, cos_cone } => {
                let radius = sizes.light_radius.unwrap_or(radius);
                Emitter::Local { position, range, radius, facing, cos_cone }
            }
        })
        .collect()
}

/// What the truth says of one pixel for one light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Truth {
    /// The centre of the light is visible (hard shadow truth).
    pub lit: bool,
    /// The fraction of the light's disc that is visible (soft shadow truth), 0..1.
    pub soft: f32,
}

/// `n` points spread evenly over the unit disc (a sunflower pattern: the same every time).
pub fn disc_samples(n: usize) -> Vec<glam::Vec2> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|k| {
            let r = ((k as f32 + 0.5) / n as f32).sqrt();
            let a = k as f32 * golden;
            glam::Vec2::new(r * a.cos(), r * a.sin())
        })
        .collect()
}

/// Two unit vectors perpendicular to unit `d` and to each other.
fn basis(d: Vec3) -> (Vec3, Vec3) {
    let u = d.any_orthonormal_vector();
    (u, d.cross(u))
}

impl Emitter {
    /// The truth at surface point `p` with unit normal `n`, or `None` where the light does not
    /// reach it (facing away, outside the cone or range, behind the light).
    pub fn truth(&self, occluders: &Occluders, p: Vec3, n: Vec3, disc: &[glam::Vec2]) -> Option<Truth> {
        let origin = p + n * RAY_OFFSET;
        match *self {
            Emitter::Distant { towards: l, angular_radius } => {
                if n.dot(l) <= 0.0 {
                    return None;
                }
                let lit = !occluders.occluded(origin, l, f32::INFINITY);
                let (u, v) = basis(l);
                let spread = angular_radius.tan();
                let seen = disc
                    .iter()
                    .filter(|s| {
                        !occluders.occluded(origin, (l + (u * s.x + v * s.y) * spread).normalize(), f32::INFINITY)
                    })
                    .count();
                Some(Truth { lit, soft: soft_fraction(seen, disc.len(), lit) })
            }
            Emitter::Local { position, range, radius, facing, cos_cone } => {
                let from_light = (p - position).normalize_or_zero();
                if facing.is_some_and(|f| from_light.dot(f) < cos_cone) {
                    return None;
                }
                // A sphere seen from the point is a disc facing it.
                let facing = facing.unwrap_or_else(|| (position - p).normalize_or(Vec3::Y));
                let light = Disc { centre: position, range, axes: basis(facing), radius };
                local_truth(occluders, p, origin, n, light, disc)
            }
        }
    }
}

/// A local light's disc as a surface point sees it.
struct Disc {
    /// Its centre, the light's position.
    centre: Vec3,
    /// How far its light reaches.
    range: f32,
    /// Two unit vectors across the disc, perpendicular to each other.
    axes: (Vec3, Vec3),
    /// Its radius.
    radius: f32,
}

/// The truth at surface point `p` with normal `n` (rays from `origin`, just off the surface)
/// from the light `disc`, sampled at `samples` (points of the unit disc): `None` where it does
/// not reach (facing away, out of range).
fn local_truth(
    occluders: &Occluders,
    p: Vec3,
    origin: Vec3,
    n: Vec3,
    disc: Disc,
    samples: &[glam::Vec2],
) -> Option<Truth> {
    let Disc { centre: position, range, axes: (u, v), radius } = disc;
    let to_light = position - p;
    let d = to_light.length();
    let l = to_light / d.max(1e-6);
    if n.dot(l) <= 0.0 || d >= range {
        return None;
    }
    let lit = !occluders.occluded(origin, (position - origin).normalize_or(l), (position - origin).length());
    let seen = samples
        .iter()
        .filter(|s| {
            let to = position + (u * s.x + v * s.y) * radius - origin;
            !occluders.occluded(origin, to.normalize(), to.length())
        })
        .count();
    Some(Truth { lit, soft: soft_fraction(seen, samples.len(), lit) })
}

fn soft_fraction(seen: usize, of: usize, lit: bool) -> f32 {
    if of == 0 { lit as u32 as f32 } else { seen as f32 / of as f32 }
}

/// The truth for `frame`, measured from `world` as it is now: its occluders and its lights (with
/// `sizes` where given), `soft_rays` rays over each light's disc (see [`truth_frame`]).
pub fn truth_of(
    world: &mut World,
    frame: &DebugFrame,
    sizes: SizeOverride,
    soft_rays: usize,
) -> Vec<Vec<Option<Truth>>> {
    let lights = truth_lights(world, sizes);
    truth_frame(frame, &Occluders::from_world(world), &lights, soft_rays)
}

/// The truth for every pixel of a measured frame and every light (in the frame's order):
/// `None` for the sky and where a light does not reach. `soft_rays` rays sample each light's
/// disc. Rows are shared out over the machine's cores.
pub fn truth_frame(
    frame: &DebugFrame,
    occluders: &Occluders,
    lights: &[Emitter],
    soft_rays: usize,
) -> Vec<Vec<Option<Truth>>> {
    let disc = disc_samples(soft_rays);
    let pixels = frame.position.len();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).clamp(1, 16);
    let chunk = pixels.div_ceil(threads).max(1);
    let mut out: Vec<Vec<Option<Truth>>> = lights.iter().map(|_| vec![None; pixels]).collect();
    let pixel = |i: usize, light: &Emitter| -> Option<Truth> {
        if !frame.covered(i) {
            return None;
        }
        let (p, n): (Vec4, Vec4) = (frame.position[i], frame.normal[i]);
        light.truth(occluders, p.truncate(), n.truncate().normalize_or_zero(), &disc)
    };
    for (light, column) in lights.iter().zip(out.iter_mut()) {
        std::thread::scope(|scope| {
            for (c, part) in column.chunks_mut(chunk).enumerate() {
                let pixel = &pixel;
                scope.spawn(move || {
                    for (k, slot) in part.iter_mut().enumerate() {
                        *slot = pixel(c * chunk + k, light);
                    }
                });
            }
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_quad_at(y: f32) -> Vec<[Vec3; 3]> {
        let (a, b, c, d) =
            (Vec3::new(-1.0, y, -1.0), Vec3::new(1.0, y, -1.0), Vec3::new(1.0, y, 1.0), Vec3::new(-1.0, y, 1.0));
        vec![[a, b, c], [a, c, d]]
    }

    #[test]
    fn rays_are_stopped_by_casters_and_only_within_their_length() {
        let occ = Occluders::new(&unit_quad_at(2.0));
        assert!(occ.occluded(Vec3::ZERO, Vec3::Y, f32::INFINITY));
        assert!(!occ.occluded(Vec3::ZERO, Vec3::Y, 1.5), "the quad is beyond the light");
        assert!(!occ.occluded(Vec3::new(3.0, 0.0, 0.0), Vec3::Y, f32::INFINITY));
        assert_eq!(occ.first_hit(Vec3::ZERO, Vec3::Y), Some(2.0));
        assert!(occ.occluded(Vec3::new(0.3, 0.0, 0.1), -Vec3::NEG_Y, 9.0), "an up vector with negative zeros");
        assert!(!Occluders::new(&[]).occluded(Vec3::ZERO, Vec3::Y, 1.0));
    }

    #[test]
    fn a_sun_behind_a_quad_shadows_hard_and_its_disc_half_at_the_edge() {
        let occ = Occluders::new(&unit_quad_at(2.0));
        let sun = Emitter::Distant { towards: Vec3::Y, angular_radius: 0.1 };
        let disc = disc_samples(256);
        // (Off the quad's diagonal: a ray exactly through the edge two triangles share may slip.)
        let under = sun.truth(&occ, Vec3::new(0.3, 0.0, 0.1), Vec3::Y, &disc).unwrap();
        assert_eq!(under, Truth { lit: false, soft: 0.0 });
        let beside = sun.truth(&occ, Vec3::new(3.0, 0.0, 0.0), Vec3::Y, &disc).unwrap();
        assert_eq!(beside, Truth { lit: true, soft: 1.0 });
        // Under the quad's edge the sun's disc is half covered.
        let edge = sun.truth(&occ, Vec3::new(1.0, 0.0, 0.3), Vec3::Y, &disc).unwrap();
        assert!((edge.soft - 0.5).abs() < 0.08, "{edge:?}");
        assert!(sun.truth(&occ, Vec3::ZERO, Vec3::NEG_Y, &disc).is_none(), "facing away");
    }

    #[test]
    fn a_spot_reaches_only_inside_its_cone_and_range() {
        let occ = Occluders::new(&[]);
        let spot = Emitter::Local {
            position: Vec3::Y * 4.0,
            facing: Some(Vec3::NEG_Y),
            cos_cone: 0.5f32.cos(),
            range: 6.0,
            radius: 0.1,
        };
        let disc = disc_samples(8);
        assert_eq!(spot.truth(&occ, Vec3::ZERO, Vec3::Y, &disc), Some(Truth { lit: true, soft: 1.0 }));
        assert!(spot.truth(&occ, Vec3::new(3.0, 0.0, 0.0), Vec3::Y, &disc).is_none(), "outside the cone");
        assert!(spot.truth(&occ, Vec3::new(0.0, 8.0, 0.0), Vec3::NEG_Y, &disc).is_none(), "behind the light");
        let short = Emitter::Local {
            position: Vec3::Y * 4.0,
            facing: Some(Vec3::NEG_Y),
            cos_cone: 0.5,
            range: 3.0,
            radius: 0.1,
        };
        assert!(short.truth(&occ, Vec3::ZERO, Vec3::Y, &disc).is_none(), "out of range");
    }

    #[test]
    fn cut_out_casters_stop_rays_only_where_they_are_there() {
        // A quad at height 2 whose left half (u < 0.5) is cut away by its vertex alpha.
        let [a, b, c, d] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, z)| Vec3::new(x, 2.0, z));
        let cut = |corners: [Vec3; 3]| CasterTriangle {
            corners,
            cutout: Some(Cutout {
                uv: corners.map(|p| Vec2::new((p.x + 1.0) / 2.0, 0.0)),
                alpha: corners.map(|p| (p.x + 1.0) / 2.0),
                texture: None,
                cutoff: 0.5,
            }),
        };
        let occ = Occluders::with_cutouts(vec![cut([a, b, c]), cut([a, c, d])]);
        assert!(occ.occluded(Vec3::new(0.5, 0.0, 0.1), Vec3::Y, f32::INFINITY), "alpha 0.75");
        assert!(!occ.occluded(Vec3::new(-0.5, 0.0, 0.1), Vec3::Y, f32::INFINITY), "alpha 0.25: cut away");
        assert_eq!(occ.first_hit(Vec3::new(-0.5, 0.0, 0.3), Vec3::Y), None);
        // A solid quad below the cut-away part still stops the ray: traversal goes on past it.
        let mut both = vec![cut([a, b, c]), cut([a, c, d])];
        both.extend(unit_quad_at(1.0).into_iter().map(|corners| CasterTriangle { corners, cutout: None }));
        let occ = Occluders::with_cutouts(both);
        assert_eq!(occ.first_hit(Vec3::new(-0.5, 0.0, 0.3), Vec3::Y), Some(1.0));
        assert_eq!(occ.first_hit(Vec3::new(-0.5, 3.0, 0.3), Vec3::NEG_Y), Some(2.0), "from above, the solid quad");
    }

    #[test]
    fn barycentric_weights_rebuild_the_point() {
        let t = [Vec3::ZERO, Vec3::X * 2.0, Vec3::new(0.0, 1.0, 3.0)];
        let w = barycentric(Vec3::new(0.5, 0.25, 0.75), t);
        assert!((t[0] * w.x + t[1] * w.y + t[2] * w.z).abs_diff_eq(Vec3::new(0.5, 0.25, 0.75), 1e-6));
        assert_eq!(barycentric(Vec3::ONE, [Vec3::ZERO; 3]), Vec3::X, "a degenerate triangle");
    }

    #[test]
    fn disc_samples_fill_the_disc_evenly() {
        let s = disc_samples(1000);
        assert!(s.iter().all(|p| p.length() <= 1.0));
        let inner = s.iter().filter(|p| p.length() < std::f32::consts::FRAC_1_SQRT_2).count();
        assert!((inner as i32 - 500).abs() < 10, "half the area, half the samples: {inner}");
    }
}
