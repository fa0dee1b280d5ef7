//! A loaded model: a node tree, the mesh parts hung on it, skins and animation clips.
//!
//! Posing is pure math over these: locals at rest, a clip's keys on top, then `parent × local`
//! down the tree, then each skin's `global joint × inverse bind` matrices.

use super::clip::Clip;
use super::mesh::MeshData;
use super::skin::posed_bounds;
use super::texture::TextureData;
use crate::components::{Material, Pose, Transform};
use crate::shadow::Aabb;
use bevy_ecs::prelude::Component;
use glam::{Mat4, Vec3};
use std::sync::Arc;

/// Models smaller than this across (metres) are taken to have no size: placed unscaled, with a
/// warning, rather than blown up to a sensible size by an absurd factor.
pub const MIN_MODEL_SIZE: f32 = 1e-3;

/// A loaded model placed in the world by this entity's [`Transform`]; its meshes are separate
/// entities with a [`crate::components::ModelPart`].
#[derive(Component, Clone, Debug)]
#[require(Transform, Pose)]
pub struct ModelInstance(pub Arc<Model>);

/// One node of the tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Its name in the file (or "node N").
    pub name: String,
    /// The node it hangs from.
    pub parent: Option<usize>,
    /// Its transform relative to the parent when no clip moves it.
    pub rest: Transform,
}

/// The joints of a skin and the matrices that take the bind pose into each joint's space.
#[derive(Clone, Debug, PartialEq)]
pub struct Skin {
    /// The node of each joint.
    pub joints: Vec<usize>,
    /// One per joint: model space in the bind pose to the joint's space.
    pub inverse_bind: Vec<Mat4>,
}

/// One mesh with one material, drawn at a node (rigid) or deformed by a skin. Nodes that
/// instance the same mesh share its data.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// The node it belongs to.
    pub node: usize,
    /// Its triangles (skinned: in the bind pose, with joint influences).
    pub mesh: Arc<MeshData>,
    /// Its colour and how it is drawn (its texture is in `texture`).
    pub material: Material,
    /// Its base-colour texture, if it has one that could be read.
    pub texture: Option<Arc<TextureData>>,
    /// The skin that deforms it, if any; then the node's own transform is not used.
    pub skin: Option<usize>,
    /// For a skinned part, the box around what each joint moves, in joint space.
    pub joint_boxes: Arc<[Aabb]>,
}

/// What kind of light a file's light is, as `KHR_lights_punctual` defines it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FileLightKind {
    /// Parallel light along the node's -Z axis; intensity in lux.
    Directional,
    /// Light every way from the node's origin; intensity in candela.
    Point,
    /// A cone along the node's -Z axis between two half angles (radians); intensity in candela.
    Spot {
        /// Where the edge starts to fade.
        inner: f32,
        /// Where the light ends.
        outer: f32,
    },
}

/// A light hung on a node, with the file's (photometric) values, checked to be finite and not
/// negative.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelLight {
    /// The node it hangs on.
    pub node: usize,
    /// Its kind and cone.
    pub kind: FileLightKind,
    /// Linear RGB colour.
    pub color: Vec3,
    /// Lux (directional) or candela (point, spot).
    pub intensity: f32,
    /// Where it ends, in metres; `None` means it never does.
    pub range: Option<f32>,
}

/// A camera hung on a node, looking along the node's -Z axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelCamera {
    /// The node it hangs on.
    pub node: usize,
    /// Vertical field of view in radians (`None`: an orthographic camera, shown in perspective).
    pub fov_y: Option<f32>,
    /// Near plane distance in metres (`None`: not a usable one).
    pub near: Option<f32>,
    /// Far plane distance in metres (`None`: infinite, or not beyond the near plane).
    pub far: Option<f32>,
}

/// A whole model as loaded from a file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Model {
    /// Where it came from, for messages.
    pub name: String,
    /// Every node of the file.
    pub nodes: Vec<Node>,
    /// Node indices with every parent before its children.
    pub order: Vec<usize>,
    /// The meshes of the scene's nodes.
    pub parts: Vec<Part>,
    /// Skins, referred to by [`Part::skin`].
    pub skins: Vec<Skin>,
    /// Animation clips.
    pub clips: Vec<Clip>,
    /// The lights (`KHR_lights_punctual`) of the scene's nodes.
    pub lights: Vec<ModelLight>,
    /// The first camera of the scene's nodes, if any.
    pub camera: Option<ModelCamera>,
    /// Things that were wrong with the file but could be mended, one line each.
    pub warnings: Vec<String>,
}

impl Model {
    /// Every node's transform at rest.
    pub fn rest_locals(&self) -> Vec<Transform> {
        self.nodes.iter().map(|n| n.rest).collect()
    }

    /// Model-space matrices of every node for the given locals: `parent × local` down the tree.
    pub fn globals(&self, locals: &[Transform]) -> Vec<Mat4> {
        let mut globals = vec![Mat4::IDENTITY; self.nodes.len()];
        for &i in &self.order {
            let local = locals.get(i).map_or(Mat4::IDENTITY, Transform::matrix);
            globals[i] = match self.nodes[i].parent {
                Some(p) => globals[p] * local,
                None => local,
            };
        }
        globals
    }

    /// Model-space node matrices with `clip` (if any) at `t` seconds, looping.
    pub fn pose(&self, clip: Option<usize>, t: f32) -> Vec<Mat4> {
        let mut locals = self.rest_locals();
        if let Some(clip) = clip.and_then(|c| self.clips.get(c)) {
            clip.apply(t, &mut locals);
        }
        self.globals(&locals)
    }

    /// The joint matrices of `skin` for node matrices `globals`: what the vertex shader blends.
    pub fn joint_matrices(&self, skin: usize, globals: &[Mat4]) -> Vec<Mat4> {
        let Some(skin) = self.skins.get(skin) else { return Vec::new() };
        skin.joints.iter().zip(&skin.inverse_bind).map(|(&j, ibm)| globals[j] * *ibm).collect()
    }

    /// Bounds of `part` posed by `globals` and placed by `placement`.
    pub fn part_bounds(&self, part: &Part, globals: &[Mat4], placement: &Mat4) -> Aabb {
        match part.skin.and_then(|s| self.skins.get(s)) {
            Some(skin) => posed_bounds(&part.joint_boxes, |j| *placement * globals[skin.joints[j]]),
            None if part.mesh.bounds.is_empty() => Aabb::EMPTY,
            None => part.mesh.bounds.transformed(&(*placement * globals[part.node])),
        }
    }

    /// Bounds of the whole model in its rest pose, in model space.
    pub fn rest_bounds(&self) -> Aabb {
        let globals = self.globals(&self.rest_locals());
        self.parts.iter().fold(Aabb::EMPTY, |b, p| b.union(self.part_bounds(p, &globals, &Mat4::IDENTITY)))
    }
}

/// Each node's parent and an order with parents first, from each node's children; an error
/// names a node with two parents or a node that is its own ancestor.
pub fn hierarchy(children: &[Vec<usize>]) -> Result<(Vec<Option<usize>>, Vec<usize>), String> {
    let n = children.len();
    let mut parent = vec![None; n];
    for (p, kids) in children.iter().enumerate() {
        for &c in kids {
            if c >= n {
                return Err(format!("node {p} has child {c}, but there are only {n} nodes"));
            }
            if let Some(other) = parent[c].replace(p) {
                return Err(format!("node {c} has two parents (nodes {other} and {p})"));
            }
        }
    }
    let mut order = Vec::with_capacity(n);
    let mut placed = vec![false; n];
    let mut stack: Vec<usize> = (0..n).filter(|&i| parent[i].is_none()).rev().collect();
    while let Some(i) = stack.pop() {
        order.push(i);
        placed[i] = true;
        stack.extend(children[i].iter().rev());
    }
    if let Some(stuck) = placed.iter().position(|p| !p) {
        return Err(format!("node {stuck} is its own ancestor: the node tree has a cycle"));
    }
    Ok((parent, order))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn hierarchy_puts_parents_first_and_refuses_cycles_and_shared_children() {
        let (parent, order) = hierarchy(&[vec![2], vec![], vec![1]]).unwrap();
        assert_eq!(parent, vec![None, Some(2), Some(0)]);
        assert_eq!(order, vec![0, 2, 1]);
        assert!(hierarchy(&[vec![1], vec![0]]).unwrap_err().contains("cycle"));
        assert!(hierarchy(&[vec![0]]).unwrap_err().contains("cycle"));
        assert!(hierarchy(&[vec![2], vec![2], vec![]]).unwrap_err().contains("two parents"));
        assert!(hierarchy(&[vec![5]]).unwrap_err().contains("only 1 nodes"));
    }

    #[test]
    fn globals_compose_parent_times_local() {
        let node = |parent, rest| Node { name: String::new(), parent, rest };
        let a = Transform::from_xyz(1.0, 0.0, 0.0).with_rotation(Quat::from_rotation_y(0.7));
        let b = Transform::from_xyz(0.0, 2.0, 0.5).with_scale(Vec3::splat(2.0));
        let c = Transform::from_xyz(0.0, 0.0, 3.0).with_rotation(Quat::from_rotation_x(-0.3));
        let model = Model {
            name: String::new(),
            nodes: vec![node(None, a), node(Some(2), c), node(Some(0), b)],
            order: vec![0, 2, 1],
            parts: Vec::new(),
            skins: Vec::new(),
            clips: Vec::new(),
            lights: Vec::new(),
            camera: None,
            warnings: Vec::new(),
        };
        let g = model.globals(&model.rest_locals());
        assert!(g[0].abs_diff_eq(a.matrix(), 1e-6));
        assert!(g[2].abs_diff_eq(a.matrix() * b.matrix(), 1e-6));
        assert!(g[1].abs_diff_eq(a.matrix() * b.matrix() * c.matrix(), 1e-6));
    }
}
