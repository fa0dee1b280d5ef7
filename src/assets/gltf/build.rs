//! From a validated document to a [`Model`]: nodes, mesh parts, skins and clips, each checked.

use super::accessor::{Data, components};
use super::container::Source;
use crate::assets::clip::{Channel, Clip, Interpolation, Property};
use crate::assets::mesh::{MeshData, SkinVertex, Vertex};
use crate::assets::model::{Model, Node, Part, Skin, hierarchy};
use crate::assets::skin::{InfluenceFixes, MAX_JOINTS, four_largest, joint_boxes};
use crate::components::{Material, Transform};
use glam::{Mat4, Quat, Vec3, Vec4};
use gltf::mesh::{Mode, Semantic};

/// Most sets of joints and weights a primitive may have (four influences each).
const MAX_JOINT_SETS: u32 = 8;

/// Builds the model; `warnings` collects what was mended.
pub(super) fn build(src: &Source, name: &str, warnings: &mut Vec<String>) -> Result<Model, String> {
    let doc = &src.doc;
    let nodes = nodes(doc)?;
    let children: Vec<Vec<usize>> = doc.nodes().map(|n| n.children().map(|c| c.index()).collect()).collect();
    let (parents, order) = hierarchy(&children)?;
    let nodes = nodes.into_iter().zip(parents).map(|((name, rest), parent)| Node { name, parent, rest }).collect();
    let data = Data::new(&src.buffers);
    let skins = doc.skins().map(|s| skin(&s, &data)).collect::<Result<Vec<_>, _>>()?;
    let mut parts = Vec::new();
    for node in scene_nodes(doc, &children) {
        let node = doc.nodes().nth(node).ok_or("a scene names a missing node")?;
        let Some(mesh) = node.mesh() else { continue };
        let skin = node.skin().map(|s| s.index());
        for primitive in mesh.primitives() {
            let at = format!("mesh {} primitive {}", mesh.index(), primitive.index());
            let at = match mesh.name() {
                Some(n) => format!("{at} ({n})"),
                None => at,
            };
            let joints = skin.map(|s| skins[s].joints.len());
            let part =
                part(&primitive, node.index(), skin, joints, &data, warnings).map_err(|e| format!("{at}: {e}"))?;
            let part = match (part.skin, &part.mesh.skin) {
                (Some(s), Some(_)) => Part { joint_boxes: joint_boxes(&part.mesh, &skins[s].inverse_bind), ..part },
                (Some(_), None) => {
                    warnings.push(format!("{at}: its node has a skin but the mesh has no joints; drawn rigid"));
                    Part { skin: None, ..part }
                }
                _ => part,
            };
            parts.push(part);
        }
    }
    let clips = doc.animations().map(|a| clip(&a, &data, warnings)).collect::<Result<_, _>>()?;
    let mut model = Model { name: name.to_string(), nodes, order, parts, skins, clips, warnings: Vec::new() };
    turn_mirrored_parts(&mut model);
    Ok(model)
}

/// A rigid part whose node is mirrored (a negative determinant) has its triangles wound the other
/// way round, as the format asks, so that its outside still faces out.
fn turn_mirrored_parts(model: &mut Model) {
    let globals = model.globals(&model.rest_locals());
    for part in model.parts.iter_mut().filter(|p| p.skin.is_none() && globals[p.node].determinant() < 0.0) {
        for t in part.mesh.indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
    }
}

/// Each node's name and rest transform.
fn nodes(doc: &gltf::Document) -> Result<Vec<(String, Transform)>, String> {
    doc.nodes()
        .map(|n| {
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
            Ok((n.name().map_or_else(|| format!("node {}", n.index()), str::to_string), rest))
        })
        .collect()
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
    let inverse_bind = match s.inverse_bind_matrices() {
        None => vec![Mat4::IDENTITY; joints.len()],
        Some(acc) => {
            if components(&acc) != 16 {
                return Err(format!("{at}: its inverse bind matrices are not 4x4 matrices"));
            }
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

/// Reads an attribute of `n` elements of `comps` components as floats.
fn attribute(
    p: &gltf::Primitive<'_>,
    semantic: &Semantic,
    comps: usize,
    n: Option<usize>,
    data: &Data<'_>,
) -> Result<Option<std::rc::Rc<Vec<f32>>>, String> {
    let Some(acc) = p.get(semantic) else { return Ok(None) };
    let name = semantic.to_string();
    if components(&acc) != comps {
        return Err(format!("{name} has {} components per element, not {comps}", components(&acc)));
    }
    if let Some(n) = n.filter(|&n| n != acc.count()) {
        return Err(format!("{name} has {} elements but POSITION has {n}", acc.count()));
    }
    data.floats(&acc).map(Some).map_err(|e| format!("{name}: {e}"))
}

fn part(
    p: &gltf::Primitive<'_>,
    node: usize,
    skin: Option<usize>,
    joint_count: Option<usize>,
    data: &Data<'_>,
    warnings: &mut Vec<String>,
) -> Result<Part, String> {
    if !matches!(p.mode(), Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        return Err(format!("its mode is {:?}, not triangles; umbra draws triangles only", p.mode()));
    }
    let positions = attribute(p, &Semantic::Positions, 3, None, data)?.ok_or("it has no POSITION attribute")?;
    let n = positions.len() / 3;
    if positions.iter().any(|x| !x.is_finite()) {
        return Err("a POSITION is not finite".into());
    }
    let normals = attribute(p, &Semantic::Normals, 3, Some(n), data)?;
    if normals.as_ref().is_some_and(|v| v.iter().any(|x| !x.is_finite())) {
        return Err("a NORMAL is not finite".into());
    }
    let indices = match p.indices() {
        Some(acc) => data.ints(&acc).map_err(|e| format!("indices: {e}"))?.to_vec(),
        None => (0..n as u32).collect(),
    };
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(format!("index {bad} is out of range: there are {n} vertices"));
    }
    data.spend(n.saturating_mul(14).saturating_add(indices.len()))?;
    let indices = triangle_list(p.mode(), &indices, warnings);
    if p.morph_targets().len() > 0 {
        warnings.push(format!("primitive {}: morph targets are ignored", p.index()));
    }
    let influences = match joint_count {
        Some(joints) if p.get(&Semantic::Joints(0)).is_some() => Some(influences(p, n, joints, data, warnings)?),
        _ => None,
    };
    let vertices: Vec<Vertex> = (0..n)
        .map(|i| Vertex {
            position: [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]],
            normal: normals.as_ref().map_or([0.0; 3], |v| [v[3 * i], v[3 * i + 1], v[3 * i + 2]]),
        })
        .collect();
    let mesh = match normals {
        Some(_) => mesh_data(vertices, indices, influences),
        None => flat_shaded(&vertices, &indices, influences.as_deref()),
    };
    let c = p.material().pbr_metallic_roughness().base_color_factor();
    let material = Material::color(c[0], c[1], c[2]);
    Ok(Part { node, mesh, material, skin, joint_boxes: Vec::new() })
}

fn mesh_data(vertices: Vec<Vertex>, indices: Vec<u32>, skin: Option<Vec<SkinVertex>>) -> MeshData {
    match skin {
        Some(skin) => MeshData::skinned(vertices, indices, skin),
        None => MeshData::new(vertices, indices),
    }
}

/// Strips and fans turned into a plain triangle list.
fn triangle_list(mode: Mode, indices: &[u32], warnings: &mut Vec<String>) -> Vec<u32> {
    match mode {
        Mode::TriangleStrip => (2..indices.len())
            .flat_map(|k| {
                if k % 2 == 0 {
                    [indices[k - 2], indices[k - 1], indices[k]]
                } else {
                    [indices[k - 1], indices[k - 2], indices[k]]
                }
            })
            .collect(),
        Mode::TriangleFan => (2..indices.len()).flat_map(|k| [indices[0], indices[k - 1], indices[k]]).collect(),
        _ => {
            if !indices.len().is_multiple_of(3) {
                warnings.push(format!(
                    "{} indices are not whole triangles; the last {} are ignored",
                    indices.len(),
                    indices.len() % 3
                ));
            }
            indices[..indices.len() / 3 * 3].to_vec()
        }
    }
}

/// Every vertex's four strongest joints, normalized; sets beyond JOINTS_0 are merged in.
fn influences(
    p: &gltf::Primitive<'_>,
    n: usize,
    joint_count: usize,
    data: &Data<'_>,
    warnings: &mut Vec<String>,
) -> Result<Vec<SkinVertex>, String> {
    let mut all: Vec<Vec<(u16, f32)>> = vec![Vec::new(); n];
    for set in 0.. {
        let (Some(j), Some(w)) = (p.get(&Semantic::Joints(set)), p.get(&Semantic::Weights(set))) else { break };
        if set >= MAX_JOINT_SETS {
            return Err(format!("it has more than {MAX_JOINT_SETS} sets of joints and weights"));
        }
        if components(&j) != 4 || components(&w) != 4 || j.count() != n || w.count() != n {
            return Err(format!("JOINTS_{set} and WEIGHTS_{set} must hold 4 values for each of the {n} vertices"));
        }
        let joints = data.ints(&j).map_err(|e| format!("JOINTS_{set}: {e}"))?;
        let weights = data.floats(&w).map_err(|e| format!("WEIGHTS_{set}: {e}"))?;
        for (v, list) in all.iter_mut().enumerate() {
            for k in 0..4 {
                let (joint, weight) = (joints[4 * v + k], weights[4 * v + k]);
                if joint as usize >= joint_count {
                    if weight > 0.0 {
                        return Err(format!("vertex {v} uses joint {joint}, but its skin has {joint_count} joints"));
                    }
                    // A joint that moves nothing may name anything; it is taken as the first.
                    list.push((0, 0.0));
                    continue;
                }
                list.push((joint as u16, weight));
            }
        }
    }
    let mut fixed = [0usize; 3];
    let out = all
        .iter()
        .map(|list| {
            let (v, fixes): (SkinVertex, InfluenceFixes) = four_largest(list);
            for (count, happened) in fixed.iter_mut().zip([fixes.dropped, fixes.renormalized, fixes.unweighted]) {
                *count += happened as usize;
            }
            v
        })
        .collect();
    let what = [
        "had more than 4 joints: kept the 4 largest, renormalized",
        "had weights not summing to 1: normalized",
        "had no weight: tied to their first joint",
    ];
    for (count, what) in fixed.iter().zip(what) {
        if *count > 0 {
            warnings.push(format!("primitive {}: {count} vertices {what}", p.index()));
        }
    }
    Ok(out)
}

/// One vertex per triangle corner with the face normal, for meshes that give no normals.
fn flat_shaded(vertices: &[Vertex], indices: &[u32], skin: Option<&[SkinVertex]>) -> MeshData {
    let mut out = Vec::with_capacity(indices.len());
    let mut out_skin = Vec::with_capacity(if skin.is_some() { indices.len() } else { 0 });
    for t in indices.chunks_exact(3) {
        let p = [t[0], t[1], t[2]].map(|i| Vec3::from(vertices[i as usize].position));
        let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero().to_array();
        for (k, &i) in t.iter().enumerate() {
            out.push(Vertex { position: p[k].to_array(), normal });
            out_skin.extend(skin.map(|s| s[i as usize]));
        }
    }
    let indices = (0..out.len() as u32).collect();
    mesh_data(out, indices, skin.map(|_| out_skin))
}

fn clip(a: &gltf::Animation<'_>, data: &Data<'_>, warnings: &mut Vec<String>) -> Result<Clip, String> {
    let name = a.name().map_or_else(|| format!("animation {}", a.index()), str::to_string);
    let mut channels = Vec::new();
    for c in a.channels() {
        let at = format!("animation {} channel {}", a.index(), c.index());
        let property = match c.target().property() {
            gltf::animation::Property::Translation => Property::Translation,
            gltf::animation::Property::Rotation => Property::Rotation,
            gltf::animation::Property::Scale => Property::Scale,
            gltf::animation::Property::MorphTargetWeights => {
                warnings.push(format!("{at}: morph target weights are ignored"));
                continue;
            }
        };
        let sampler = c.sampler();
        let interpolation = match sampler.interpolation() {
            gltf::animation::Interpolation::Step => Interpolation::Step,
            gltf::animation::Interpolation::Linear => Interpolation::Linear,
            gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
        };
        if components(&sampler.input()) != 1 {
            return Err(format!("{at}: key times must be scalars"));
        }
        let times = data.floats(&sampler.input()).map_err(|e| format!("{at} input: {e}"))?.to_vec();
        if times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|w| w[1] < w[0]) {
            return Err(format!("{at}: key times are not finite and increasing"));
        }
        let width = if property == Property::Rotation { 4 } else { 3 };
        let output = sampler.output();
        if components(&output) != width {
            return Err(format!("{at}: {property:?} keys need {width} components, not {}", components(&output)));
        }
        let raw = data.floats(&output).map_err(|e| format!("{at} output: {e}"))?;
        data.spend(times.len() + raw.len())?;
        let per_key = if interpolation == Interpolation::CubicSpline { 3 } else { 1 };
        if raw.len() != times.len() * per_key * width || raw.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "{at}: {} key times need {} finite values, found {}",
                times.len(),
                times.len() * per_key,
                raw.len() / width
            ));
        }
        let values: Vec<Vec4> = raw
            .chunks_exact(width)
            .map(|v| if width == 4 { Vec4::from_slice(v) } else { Vec3::from_slice(v).extend(0.0) })
            .collect();
        let mut values = values;
        if property == Property::Rotation {
            // Keys must be unit quaternions; quantized ones are only nearly so.
            for q in values.iter_mut().skip(per_key / 2).step_by(per_key) {
                if q.length() < 1e-6 {
                    return Err(format!("{at}: a rotation key is not a quaternion (its length is 0)"));
                }
                *q = q.normalize();
            }
        }
        channels.push(Channel { node: c.target().node().index(), property, interpolation, times, values });
    }
    let duration = channels.iter().filter_map(|c| c.times.last()).fold(0.0f32, |a, &b| a.max(b));
    Ok(Clip { name, channels, duration })
}
