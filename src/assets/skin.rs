//! Linear blend skinning on the CPU: the sums the vertex shader does (`shaders/skinning.wgsl`),
//! for tests and for the ray-traced ground truth, plus the joint boxes that bound a posed mesh.

use super::mesh::{MeshData, SkinVertex, Vertex};
use crate::shadow::Aabb;
use glam::{Mat3, Mat4, Vec3};

/// Most joints one skin may have (the joint indices of a vertex are 16-bit).
pub const MAX_JOINTS: usize = 1024;

/// The blend of joint matrices that moves a vertex: `Σ weight · joint`.
pub fn skin_matrix(influence: &SkinVertex, joints: &[Mat4]) -> Mat4 {
    let mut m = Mat4::ZERO;
    for (&j, &w) in influence.joints.iter().zip(&influence.weights) {
        if w > 0.0
            && let Some(joint) = joints.get(j as usize)
        {
            m += *joint * w;
        }
    }
    m
}

/// A normal carried through `m`: by the cofactor matrix, which is the inverse transpose up to a
/// positive scale once the determinant's sign is applied, so no inverse is needed.
pub fn transform_normal(m: &Mat4, n: Vec3) -> Vec3 {
    let (a, b, c) = (m.x_axis.truncate(), m.y_axis.truncate(), m.z_axis.truncate());
    let cofactor = Mat3::from_cols(b.cross(c), c.cross(a), a.cross(b));
    let sign = if a.dot(b.cross(c)) < 0.0 { -1.0 } else { 1.0 };
    (cofactor * n * sign).normalize_or_zero()
}

/// The mesh's vertices posed by `joints` (each `global joint · inverse bind`), positions and
/// normals in the same space as the joints. A rigid mesh comes back unchanged.
pub fn skin_vertices(mesh: &MeshData, joints: &[Mat4]) -> Vec<Vertex> {
    let Some(skin) = &mesh.skin else { return mesh.vertices.clone() };
    mesh.vertices
        .iter()
        .zip(skin)
        .map(|(v, influence)| {
            let m = skin_matrix(influence, joints);
            Vertex {
                position: m.transform_point3(Vec3::from(v.position)).to_array(),
                normal: transform_normal(&m, Vec3::from(v.normal)).to_array(),
                ..*v
            }
        })
        .collect()
}

/// For each joint, the box around the vertices it moves, in the joint's own space (the vertex
/// times the joint's inverse bind matrix); empty for a joint that moves nothing.
///
/// A posed vertex is a weighted mean of its joints' images of it, so it lies inside the union of
/// these boxes carried by each joint's world matrix: bounds that follow the pose, not the bind.
pub fn joint_boxes(mesh: &MeshData, inverse_bind: &[Mat4]) -> Vec<Aabb> {
    let mut boxes = vec![Aabb::EMPTY; inverse_bind.len()];
    let Some(skin) = &mesh.skin else { return boxes };
    for (v, influence) in mesh.vertices.iter().zip(skin) {
        for (&j, &w) in influence.joints.iter().zip(&influence.weights) {
            if let (true, Some(b), Some(ibm)) = (w > 0.0, boxes.get_mut(j as usize), inverse_bind.get(j as usize)) {
                *b = b.grow(ibm.transform_point3(Vec3::from(v.position)));
            }
        }
    }
    boxes
}

/// World bounds of a posed mesh from its [`joint_boxes`] and each joint's world matrix.
pub fn posed_bounds(boxes: &[Aabb], joint_world: impl Fn(usize) -> Mat4) -> Aabb {
    boxes
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.is_empty())
        .fold(Aabb::EMPTY, |acc, (j, b)| acc.union(b.transformed(&joint_world(j))))
}

/// What was done to a vertex's influences to make them usable.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct InfluenceFixes {
    /// It had more than four non-zero influences; the four largest were kept.
    pub dropped: bool,
    /// Its weights did not sum to 1 and were scaled.
    pub renormalized: bool,
    /// It had no positive weight at all and was tied to its first joint.
    pub unweighted: bool,
}

/// The four largest of a vertex's (joint, weight) influences, scaled to sum to 1. Negative or
/// non-finite weights count as zero.
pub fn four_largest(influences: &[(u16, f32)]) -> (SkinVertex, InfluenceFixes) {
    let mut fixes = InfluenceFixes::default();
    let mut kept: Vec<(u16, f32)> =
        influences.iter().map(|&(j, w)| (j, if w.is_finite() && w > 0.0 { w } else { 0.0 })).collect();
    kept.sort_by(|a, b| b.1.total_cmp(&a.1));
    fixes.dropped = kept.iter().skip(4).any(|&(_, w)| w > 0.0);
    kept.truncate(4);
    let sum: f32 = kept.iter().map(|&(_, w)| w).sum();
    let mut out = SkinVertex::default();
    if sum <= 0.0 {
        fixes.unweighted = true;
        out.joints[0] = influences.first().map_or(0, |&(j, _)| j);
        out.weights[0] = 1.0;
        return (out, fixes);
    }
    fixes.renormalized = (sum - 1.0).abs() > 1e-3;
    // Zero-weight slots point at joint 0, so no slot ever names a joint that is not there.
    for (k, &(j, w)) in kept.iter().enumerate().filter(|(_, (_, w))| *w > 0.0) {
        out.joints[k] = j;
        out.weights[k] = w / sum;
    }
    (out, fixes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assets::cube;
    use glam::Quat;

    fn two_joint_cube() -> MeshData {
        // A unit cube whose top half follows joint 1 and bottom half joint 0.
        let c = cube(Vec3::splat(0.5));
        let skin = c
            .vertices
            .iter()
            .map(|v| SkinVertex { joints: [(v.position[1] > 0.0) as u16, 0, 0, 0], weights: [1.0, 0.0, 0.0, 0.0] })
            .collect();
        MeshData::skinned(c.vertices, c.indices, skin)
    }

    #[test]
    fn identity_joints_give_the_bind_pose() {
        let mesh = two_joint_cube();
        assert_eq!(skin_vertices(&mesh, &[Mat4::IDENTITY; 2]), mesh.vertices);
    }

    #[test]
    fn each_vertex_follows_its_joint_and_normals_turn_with_it() {
        let mesh = two_joint_cube();
        let lift = Mat4::from_translation(Vec3::Y * 2.0) * Mat4::from_quat(Quat::from_rotation_z(0.5));
        let posed = skin_vertices(&mesh, &[Mat4::IDENTITY, lift]);
        for (before, after) in mesh.vertices.iter().zip(&posed) {
            let top = before.position[1] > 0.0;
            let m = if top { lift } else { Mat4::IDENTITY };
            assert!(Vec3::from(after.position).abs_diff_eq(m.transform_point3(Vec3::from(before.position)), 1e-6));
            assert!(Vec3::from(after.normal).abs_diff_eq(m.transform_vector3(Vec3::from(before.normal)), 1e-6));
        }
    }

    #[test]
    fn normals_stay_perpendicular_under_non_uniform_scale_and_mirroring() {
        // A surface x + y = 0 has normal (1, 1, 0)/√2; stretching x by 3 moves the surface to
        // x/3 + y = 0, whose normal is (1, 3, 0)/√10, which a plain matrix product gets wrong.
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        let stretch = Mat4::from_scale(Vec3::new(3.0, 1.0, 1.0));
        assert!(transform_normal(&stretch, n).abs_diff_eq(Vec3::new(1.0, 3.0, 0.0).normalize(), 1e-6));
        let mirror = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        assert!(transform_normal(&mirror, Vec3::X).abs_diff_eq(Vec3::NEG_X, 1e-6));
    }

    #[test]
    fn posed_bounds_hold_every_posed_vertex() {
        let mesh = two_joint_cube();
        let inverse_bind = [Mat4::IDENTITY, Mat4::from_translation(Vec3::NEG_Y * 0.5)];
        let boxes = joint_boxes(&mesh, &inverse_bind);
        let globals = [Mat4::IDENTITY, Mat4::from_translation(Vec3::new(1.0, 3.0, 0.0)) * Mat4::from_rotation_x(1.0)];
        let joints: Vec<Mat4> = globals.iter().zip(&inverse_bind).map(|(g, i)| *g * *i).collect();
        let bounds = posed_bounds(&boxes, |j| globals[j]);
        for v in skin_vertices(&mesh, &joints) {
            let p = Vec3::from(v.position);
            assert!(p.cmpge(bounds.min - 1e-5).all() && p.cmple(bounds.max + 1e-5).all(), "{p:?} outside {bounds:?}");
        }
        // Far from the bind pose's box: the top half is lifted 3 m.
        assert!(bounds.max.y > 3.0);
    }

    #[test]
    fn influences_keep_the_four_largest_and_sum_to_one() {
        let (v, fixes) = four_largest(&[(1, 0.1), (2, 0.4), (3, 0.05), (4, 0.2), (5, 0.25)]);
        assert_eq!(v.joints, [2, 5, 4, 1]);
        assert!((v.weights.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        assert!((v.weights[0] - 0.4 / 0.95).abs() < 1e-6);
        assert!(fixes.dropped && fixes.renormalized && !fixes.unweighted);
        let (v, fixes) = four_largest(&[(7, 2.0), (8, 2.0)]);
        assert_eq!((v.joints[..2].to_vec(), v.weights), (vec![7, 8], [0.5, 0.5, 0.0, 0.0]));
        assert!(fixes.renormalized && !fixes.dropped);
        let (v, fixes) = four_largest(&[(3, 0.0), (4, f32::NAN), (5, -1.0)]);
        assert_eq!((v.joints[0], v.weights[0]), (3, 1.0));
        assert!(fixes.unweighted);
        let (_, fixes) = four_largest(&[(0, 0.5), (1, 0.5), (2, 0.0), (3, 0.0), (4, 0.0)]);
        assert_eq!(fixes, InfluenceFixes::default(), "zero weights beyond four are no loss");
    }
}
