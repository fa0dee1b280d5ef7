//! From a validated document to a [`Model`]: nodes, mesh parts, skins and clips, each checked.
//!
//! Every (mesh, primitive) is built once and shared by the nodes that instance it, so a file of
//! many nodes costs little more than its node tree; the tree, the parts and all that is decoded
//! are paid from the model's budget.

use super::accessor::{Data, FLOAT, check_format, components};
use super::budget::{Budget, MAX_PARTS};
use super::container::Source;
use super::keys::clip;
use super::material::Materials;
use super::primitive::{Shape, shape};
use super::punctual;
use crate::assets::mesh::MeshData;
use crate::assets::model::{MIN_MODEL_SIZE, Model, Node, Part, Skin, hierarchy};
use crate::assets::skin::{MAX_JOINTS, joint_boxes};
use crate::components::Transform;
use crate::shadow::Aabb;
use glam::{Mat4, Quat, Vec3};
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::sync::Arc;

/// A (mesh, primitive) drawn by a skin (or rigid), as the file has it or mirrored.
type ShapeKey = (usize, usize, Option<usize>, bool);

/// Builds the model; `warnings` collects what was mended or ignored.
pub(super) fn build(src: &Source, name: &str, input: &Budget, warnings: &mut Vec<String>) -> Result<Model, String> {
    let doc = &src.doc;
    let data = Data::new(&src.buffers, doc.extensions_used().any(|e| e == "KHR_mesh_quantization"));
    let all_nodes: Vec<gltf::Node<'_>> = doc.nodes().collect();
    let children: Vec<Vec<usize>> = all_nodes.iter().map(|n| n.children().map(|c| c.index()).collect()).collect();
    let (parents, order) = hierarchy(&children)?;
    let nodes = nodes(&all_nodes, &parents, &data)?;
    let skins = doc.skins().map(|s| skin(&s, &data)).collect::<Result<Vec<_>, _>>()?;
    warn_of_broken_rules(doc, warnings);
    let scene = scene_nodes(doc, &children);
    count_parts(&all_nodes, &scene)?;
    let mut model = Model {
        name: name.to_string(),
        nodes,
        order,
        parts: Vec::new(),
        skins,
        clips: Vec::new(),
        lights: punctual::lights(&all_nodes, &scene, &data, warnings)?,
        camera: punctual::camera(&all_nodes, &scene, warnings),
        warnings: Vec::new(),
    };
    let globals = model.globals(&model.rest_locals());
    let mut materials = Materials::new(src, input, &data, warnings);
    let mut shapes: HashMap<ShapeKey, Option<Shape>> = HashMap::new();
    let mut boxes: HashMap<(usize, usize, usize), Arc<[Aabb]>> = HashMap::new();
    for &n in &scene {
        let node = &all_nodes[n];
        let Some(mesh) = node.mesh() else { continue };
        let skin = node.skin().map(|s| s.index());
        for primitive in mesh.primitives() {
            let at = match mesh.name() {
                Some(name) => format!("mesh {} primitive {} ({name})", mesh.index(), primitive.index()),
                None => format!("mesh {} primitive {}", mesh.index(), primitive.index()),
            };
            let key = (mesh.index(), primitive.index(), skin, false);
            let base = match shapes.entry(key) {
                Entry::Occupied(e) => e.get().clone(),
                Entry::Vacant(e) => {
                    let joints = skin.map(|s| model.skins[s].joints.len());
                    let built =
                        shape(&primitive, joints, &data, &mut materials, warnings).map_err(|e| format!("{at}: {e}"))?;
                    match &built {
                        None => warnings.push(format!("{at} has no whole triangle: nothing to draw")),
                        Some(s) if skin.is_some() && s.mesh.skin.is_none() => {
                            warnings.push(format!("{at}: its node has a skin but the mesh has no joints; drawn rigid"))
                        }
                        _ => {}
                    }
                    e.insert(built).clone()
                }
            };
            let Some(base) = base else { continue };
            let skin = skin.filter(|_| base.mesh.skin.is_some());
            // A rigid part under a mirroring transform is wound the other way round, as the
            // format asks, so that its outside still faces out.
            let shape = if skin.is_none() && globals[n].determinant() < 0.0 {
                match shapes.entry((key.0, key.1, key.2, true)) {
                    Entry::Occupied(e) => e.get().clone().unwrap_or(base),
                    Entry::Vacant(e) => {
                        data.spend(base.mesh.indices.len() * 4)?;
                        let turned = Shape { mesh: Arc::new(turned(&base.mesh)), ..base };
                        e.insert(Some(turned.clone()));
                        turned
                    }
                }
            } else {
                base
            };
            let joint_boxes = match skin {
                Some(s) => match boxes.get(&(key.0, key.1, s)) {
                    Some(b) => b.clone(),
                    None => {
                        let b: Arc<[Aabb]> = joint_boxes(&shape.mesh, &model.skins[s].inverse_bind).into();
                        data.spend(b.len() * size_of::<Aabb>())?;
                        boxes.insert((key.0, key.1, s), b.clone());
                        b
                    }
                },
                None => Arc::new([]),
            };
            data.spend(size_of::<Part>())?;
            model.parts.push(Part {
                node: n,
                mesh: shape.mesh,
                material: shape.material,
                texture: shape.texture,
                skin,
                joint_boxes,
            });
        }
    }
    model.clips = doc.animations().map(|a| clip(&a, &data, &src.untargeted, warnings)).collect::<Result<_, _>>()?;
    check_size(&model, warnings)?;
    Ok(model)
}

/// Refuses a model whose rest pose is not finite, and warns of one with no size (it is placed
/// as it is rather than scaled up by an absurd factor).
fn check_size(model: &Model, warnings: &mut Vec<String>) -> Result<(), String> {
    let bounds = model.rest_bounds();
    if bounds.is_empty() {
        return Ok(());
    }
    if !(bounds.min.is_finite() && bounds.max.is_finite()) {
        return Err("its rest pose is not finite: its node transforms multiply out past what a float holds".into());
    }
    let size = (bounds.max - bounds.min).max_element();
    if size < MIN_MODEL_SIZE {
        warnings
            .push(format!("it is {size} m across in its rest pose (all its vertices at one point): placed unscaled"));
    }
    Ok(())
}

/// The same triangles wound the other way round.
fn turned(mesh: &MeshData) -> MeshData {
    let mut out = mesh.clone();
    for t in out.indices.chunks_exact_mut(3) {
        t.swap(1, 2);
    }
    out
}

/// Refuses a scene that would draw more parts than umbra draws, before any is built.
fn count_parts(nodes: &[gltf::Node<'_>], scene: &[usize]) -> Result<(), String> {
    let parts =
        scene.iter().filter_map(|&n| nodes[n].mesh()).fold(0usize, |a, m| a.saturating_add(m.primitives().len()));
    if parts > MAX_PARTS {
        return Err(format!(
            "its scene draws {parts} mesh parts (each node draws every primitive of its mesh); umbra draws at most {MAX_PARTS}"
        ));
    }
    Ok(())
}

/// Each node with its name, parent and rest transform, paid from the budget.
fn nodes(all: &[gltf::Node<'_>], parents: &[Option<usize>], data: &Data<'_>) -> Result<Vec<Node>, String> {
    all.iter()
        .zip(parents)
        .map(|(n, &parent)| {
            let (t, r, s) = n.transform().decomposed();
            let rest = Transform {
                translation: Vec3::from(t),
                rotation: Quat::from_array(r).normalize(),
                scale: Vec3::from(s),
            };
            if !(rest.translation.is_finite() && rest.rotation.is_finite() && rest.scale.is_finite()) {
                return Err(format!(
                    "node {} has a transform that is not a finite translation, rotation and scale",
                    n.index()
                ));
            }
            let name = n.name().map_or_else(|| format!("node {}", n.index()), str::to_string);
            data.spend(size_of::<Node>() + name.len() + n.children().len() * size_of::<usize>())?;
            Ok(Node { name, parent, rest })
        })
        .collect()
}

/// Warns of what glTF forbids but umbra can still draw one way: a node with both a matrix and a
/// translation, rotation or scale (the matrix is used), and a skin listing a joint twice (both
/// entries are posed alike).
fn warn_of_broken_rules(doc: &gltf::Document, warnings: &mut Vec<String>) {
    for (i, node) in doc.as_json().nodes.iter().enumerate() {
        if node.matrix.is_some() && (node.translation.is_some() || node.rotation.is_some() || node.scale.is_some()) {
            warnings.push(format!(
                "node {i} has both a matrix and a translation, rotation or scale; glTF allows one or the \
                 other (the matrix is used)"
            ));
        }
    }
    for s in doc.skins() {
        let mut seen = std::collections::HashSet::new();
        if let Some(twice) = s.joints().map(|j| j.index()).find(|&j| !seen.insert(j)) {
            warnings.push(format!(
                "skin {} lists node {twice} twice among its joints; glTF asks for each joint once",
                s.index()
            ));
        }
    }
}

/// The nodes of the default scene (or the first, or every node when there is no scene).
fn scene_nodes(doc: &gltf::Document, children: &[Vec<usize>]) -> Vec<usize> {
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    let mut stack: Vec<usize> = match scene {
        Some(s) => s.nodes().map(|n| n.index()).collect(),
        None => return (0..children.len()).collect(),
    };
    let mut seen = vec![false; children.len()];
    let mut out = Vec::new();
    while let Some(i) = stack.pop() {
        if !std::mem::replace(&mut seen[i], true) {
            out.push(i);
            stack.extend(&children[i]);
        }
    }
    out.sort_unstable();
    out
}

fn skin(s: &gltf::Skin<'_>, data: &Data<'_>) -> Result<Skin, String> {
    let at = format!("skin {}", s.index());
    let joints: Vec<usize> = s.joints().map(|j| j.index()).collect();
    if joints.is_empty() || joints.len() > MAX_JOINTS {
        return Err(format!("{at} has {} joints; umbra takes 1 to {MAX_JOINTS}", joints.len()));
    }
    data.spend(joints.len() * (size_of::<usize>() + size_of::<Mat4>()))?;
    let inverse_bind = match s.inverse_bind_matrices() {
        None => vec![Mat4::IDENTITY; joints.len()],
        Some(acc) => {
            if components(&acc) != 16 {
                return Err(format!("{at}: its inverse bind matrices are not 4x4 matrices"));
            }
            check_format(&acc, FLOAT, &format!("{at}: inverse bind matrices"), None)?;
            let m: Vec<Mat4> = data
                .floats(&acc)
                .map_err(|e| format!("{at}: {e}"))?
                .chunks_exact(16)
                .map(Mat4::from_cols_slice)
                .collect();
            if m.len() < joints.len() {
                return Err(format!(
                    "{at} has {} joints but its buffer holds only {} inverse bind matrices",
                    joints.len(),
                    m.len()
                ));
            }
            if !m.iter().all(|m| m.is_finite()) {
                return Err(format!("{at}: an inverse bind matrix is not finite"));
            }
            m[..joints.len()].to_vec()
        }
    };
    Ok(Skin { joints, inverse_bind })
}
