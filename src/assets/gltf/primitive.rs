//! One mesh primitive as umbra draws it: its vertices (position, normal, texture coordinates and
//! colour), triangles and joint influences, each attribute checked against the formats glTF
//! allows it.

use super::accessor::{
    Data, FLOAT, FLOAT_OR_SNORM, FLOAT_OR_UNORM, Formats, QUANTIZED, UINT, UINT_SMALL, check_format,
    check_vertex_alignment, components,
};
use super::material::Materials;
use crate::assets::mesh::{MeshData, SkinVertex, Vertex};
use crate::assets::skin::{InfluenceFixes, four_largest};
use crate::assets::texture::TextureData;
use crate::components::Material;
use glam::Vec3;
use gltf::mesh::{Mode, Semantic};
use std::rc::Rc;
use std::sync::Arc;

/// Most sets of joints and weights a primitive may have (four influences each).
const MAX_JOINT_SETS: u32 = 8;

/// The extension that lets vertex attributes be stored as small integers.
const QUANTIZATION: &str = "KHR_mesh_quantization";

/// A primitive ready to draw: its mesh and its material.
#[derive(Clone)]
pub(super) struct Shape {
    pub mesh: Arc<MeshData>,
    pub material: Material,
    pub texture: Option<Arc<TextureData>>,
}

/// What an attribute may hold: element widths, and component formats without and with
/// KHR_mesh_quantization.
struct Rule {
    widths: &'static [usize],
    formats: Formats,
    quantized: Formats,
}

const POSITION: Rule = Rule { widths: &[3], formats: FLOAT, quantized: QUANTIZED };
const NORMAL: Rule = Rule { widths: &[3], formats: FLOAT, quantized: FLOAT_OR_SNORM };
const TEXCOORD: Rule = Rule { widths: &[2], formats: FLOAT_OR_UNORM, quantized: QUANTIZED };
const COLOR: Rule = Rule { widths: &[3, 4], formats: FLOAT_OR_UNORM, quantized: FLOAT_OR_UNORM };
const JOINTS: Rule = Rule { widths: &[4], formats: UINT_SMALL, quantized: UINT_SMALL };
const WEIGHTS: Rule = Rule { widths: &[4], formats: FLOAT_OR_UNORM, quantized: FLOAT_OR_UNORM };

/// An attribute read as floats, with its components per element.
type Attribute = (usize, Rc<Vec<f32>>);

/// Reads attribute `semantic` of primitive `p` under `rule`: `n` elements (POSITION's count) if
/// given, as floats.
fn attribute(
    p: &gltf::Primitive<'_>,
    semantic: &Semantic,
    rule: &Rule,
    n: Option<usize>,
    data: &Data<'_>,
) -> Result<Option<Attribute>, String> {
    let Some(acc) = p.get(semantic) else { return Ok(None) };
    let name = semantic.to_string();
    check(&acc, &name, rule, n, data)?;
    let values = data.floats(&acc).map_err(|e| format!("{name}: {e}"))?;
    Ok(Some((components(&acc), values)))
}

/// Checks an attribute's width, count, format and alignment.
fn check(acc: &gltf::Accessor<'_>, name: &str, rule: &Rule, n: Option<usize>, data: &Data<'_>) -> Result<(), String> {
    let width = components(acc);
    if !rule.widths.contains(&width) {
        let widths: Vec<String> = rule.widths.iter().map(usize::to_string).collect();
        return Err(format!("{name} has {width} components per element, not {}", widths.join(" or ")));
    }
    if let Some(n) = n.filter(|&n| n != acc.count()) {
        return Err(format!("{name} has {} elements but POSITION has {n}", acc.count()));
    }
    let quantized = data.quantized;
    let formats = if quantized { rule.quantized } else { rule.formats };
    let extension = (!quantized && rule.quantized != rule.formats).then_some(QUANTIZATION);
    check_format(acc, formats, name, extension)?;
    check_vertex_alignment(acc, name)
}

/// Builds primitive `p`; `joints` is the joint count of the skin of the node drawing it. `None`
/// when it has no whole triangle.
pub(super) fn shape(
    p: &gltf::Primitive<'_>,
    joints: Option<usize>,
    data: &Data<'_>,
    materials: &mut Materials<'_, '_>,
    warnings: &mut Vec<String>,
) -> Result<Option<Shape>, String> {
    if !matches!(p.mode(), Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        return Err(format!("its mode is {:?}, not triangles; umbra draws triangles only", p.mode()));
    }
    let (_, positions) =
        attribute(p, &Semantic::Positions, &POSITION, None, data)?.ok_or("it has no POSITION attribute")?;
    let n = positions.len() / 3;
    if let Some(i) = positions.iter().position(|x| !x.is_finite()) {
        return Err(format!("POSITION {} is not finite", i / 3));
    }
    let normals = attribute(p, &Semantic::Normals, &NORMAL, Some(n), data)?.map(|(_, v)| v);
    if let Some(i) = normals.as_ref().and_then(|v| v.iter().position(|x| !x.is_finite())) {
        return Err(format!("NORMAL {} is not finite", i / 3));
    }
    let (material, mut texture, coords) = materials.get(&p.material(), warnings)?;
    let set = coords.set;
    let uvs = match texture {
        Some(_) => match attribute(p, &Semantic::TexCoords(set), &TEXCOORD, Some(n), data)? {
            Some((_, uv)) => Some(moved(uv, coords.transform, data)?),
            None => {
                warnings.push(format!(
                    "primitive {}: its material's texture reads TEXCOORD_{set}, which it lacks: drawn untextured",
                    p.index()
                ));
                texture = None;
                None
            }
        },
        None => None,
    };
    warn_of_unread_tex_coords(p, uvs.is_some().then_some(set), n, data, warnings);
    let colors = attribute(p, &Semantic::Colors(0), &COLOR, Some(n), data)?;
    let indices = match p.indices() {
        Some(acc) => {
            if components(&acc) != 1 {
                return Err(format!("indices (accessor {}) are not scalars", acc.index()));
            }
            check_format(&acc, UINT, "indices", None)?;
            data.ints(&acc).map_err(|e| format!("indices: {e}"))?.to_vec()
        }
        None => (0..n as u32).collect(),
    };
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(format!("index {bad} is out of range: there are {n} vertices"));
    }
    data.spend(n.saturating_mul(size_of::<Vertex>() + size_of::<SkinVertex>()).saturating_add(indices.len() * 4))?;
    let indices = triangle_list(p.mode(), &indices, warnings);
    if indices.is_empty() {
        return Ok(None);
    }
    if p.morph_targets().len() > 0 {
        warnings.push(format!("primitive {}: morph targets are ignored", p.index()));
    }
    let influences = match joints {
        Some(joints) if p.get(&Semantic::Joints(0)).is_some() => Some(influences(p, n, joints, data, warnings)?),
        _ => None,
    };
    let vertices: Vec<Vertex> = (0..n)
        .map(|i| Vertex {
            position: [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]],
            normal: normals.as_ref().map_or([0.0; 3], |v| [v[3 * i], v[3 * i + 1], v[3 * i + 2]]),
            uv: uvs.as_ref().map_or([0.0; 2], |v| [v[2 * i], v[2 * i + 1]]),
            color: colors.as_ref().map_or([1.0; 4], |(width, v)| {
                let c = &v[width * i..width * i + width];
                [c[0], c[1], c[2], if *width == 4 { c[3] } else { 1.0 }]
            }),
        })
        .collect();
    let mesh = match normals {
        Some(_) => mesh_data(vertices, indices, influences),
        None => {
            data.spend(indices.len() * (size_of::<Vertex>() + size_of::<SkinVertex>()))?;
            flat_shaded(&vertices, &indices, influences.as_deref())
        }
    };
    Ok(Some(Shape { mesh: Arc::new(mesh), material, texture }))
}

/// Texture coordinate sets of `p` that nothing reads (all but `read`) but that break glTF's rules
/// for one: warned of by name, as they are left out of the mesh.
fn warn_of_unread_tex_coords(
    p: &gltf::Primitive<'_>,
    read: Option<u32>,
    n: usize,
    data: &Data<'_>,
    warnings: &mut Vec<String>,
) {
    for (semantic, acc) in p.attributes() {
        if let Semantic::TexCoords(set) = semantic
            && Some(set) != read
            && let Err(e) = check(&acc, &semantic.to_string(), &TEXCOORD, Some(n), data)
        {
            warnings.push(format!("primitive {}: {e}: ignored, as no texture reads it", p.index()));
        }
    }
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
        if j.count() != n || w.count() != n {
            return Err(format!("JOINTS_{set} and WEIGHTS_{set} must hold 4 values for each of the {n} vertices"));
        }
        check(&j, &format!("JOINTS_{set}"), &JOINTS, Some(n), data)?;
        check(&w, &format!("WEIGHTS_{set}"), &WEIGHTS, Some(n), data)?;
        data.spend(n * 4 * size_of::<(u16, f32)>())?;
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
        for &i in t {
            out.push(Vertex { normal, ..vertices[i as usize] });
            out_skin.extend(skin.map(|s| s[i as usize]));
        }
    }
    let indices = (0..out.len() as u32).collect();
    mesh_data(out, indices, skin.map(|_| out_skin))
}

/// Texture coordinates `uv` (pairs) where `transform` moves them, the copy paid from `data`'s budget.
fn moved(uv: Rc<Vec<f32>>, transform: Option<crate::assets::UvTransform>, data: &Data) -> Result<Rc<Vec<f32>>, String> {
    let Some(t) = transform else { return Ok(uv) };
    data.spend(uv.len() * size_of::<f32>())?;
    let pairs = uv.chunks_exact(2).map(|p| t.apply(glam::Vec2::new(p[0], p[1])));
    Ok(Rc::new(pairs.flat_map(|p| [p.x, p.y]).collect()))
}
