//! The sample's walking character, generated: a low-poly humanoid (hips, spine, chest, head,
//! arms with elbows, legs with knees and feet), its skeleton and a looping walk clip, written as
//! a .glb. `cargo run --example make_character` writes `assets/character.glb`; the game loads
//! that file through the same loader as any other model.

mod glb;
mod shapes;

use glam::{Quat, Vec3};
use glb::{ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER, GlbBuilder};
use serde_json::json;
use shapes::MeshBuilder;

/// Where the generated file lives, relative to the project root.
pub const CHARACTER_PATH: &str = "assets/character.glb";

/// Length of one walk cycle (two steps) in seconds.
pub const WALK_CYCLE: f32 = 1.0;

/// Metres the character moves per second when its feet do not slide.
pub const WALK_SPEED: f32 = 1.35;

/// The joints: name, parent, and where the joint sits in the bind pose (model space, metres,
/// facing +Z, feet on y = 0; the character's left is +X).
const BONES: [(&str, Option<usize>, [f32; 3]); 14] = [
    ("hips", None, [0.0, 0.95, 0.0]),
    ("spine", Some(0), [0.0, 1.08, 0.0]),
    ("chest", Some(1), [0.0, 1.28, 0.0]),
    ("head", Some(2), [0.0, 1.50, 0.0]),
    ("upper_arm.L", Some(2), [0.22, 1.44, 0.0]),
    ("forearm.L", Some(4), [0.25, 1.17, 0.0]),
    ("upper_arm.R", Some(2), [-0.22, 1.44, 0.0]),
    ("forearm.R", Some(6), [-0.25, 1.17, 0.0]),
    ("thigh.L", Some(0), [0.10, 0.92, 0.0]),
    ("shin.L", Some(8), [0.10, 0.50, 0.0]),
    ("foot.L", Some(9), [0.10, 0.08, 0.0]),
    ("thigh.R", Some(0), [-0.10, 0.92, 0.0]),
    ("shin.R", Some(11), [-0.10, 0.50, 0.0]),
    ("foot.R", Some(12), [-0.10, 0.08, 0.0]),
];

const HIPS: u16 = 0;
const SPINE: u16 = 1;
const CHEST: u16 = 2;
const HEAD: u16 = 3;

fn at(bone: u16) -> Vec3 {
    Vec3::from(BONES[bone as usize].2)
}

/// The shirt's stripes: one cream and one navy band per repeat of the texture.
const STRIPE_COLOURS: [[u8; 4]; 2] = [[236, 228, 208, 255], [28, 38, 92, 255]];

/// Stripe pairs per metre of height on the shirt (a band every 8 cm or so).
const STRIPES_PER_METRE: f32 = 6.0;

/// The shirt's texture: 4x16 texels, the top half cream and the bottom half navy, as a PNG.
fn stripes_png() -> Vec<u8> {
    let rgba: Vec<u8> = (0..16).flat_map(|row| [STRIPE_COLOURS[row / 8]; 4]).flatten().collect();
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, 4, 16);
    encoder.set_color(png::ColorType::Rgba);
    if let Ok(mut writer) = encoder.write_header() {
        let _ = writer.write_image_data(&rgba);
    }
    out
}

/// The character's four surfaces: shirt (striped by a texture, so white itself), skin,
/// trousers, shoes, each with its linear colour.
fn surfaces() -> [(&'static str, [f32; 3], MeshBuilder); 4] {
    let mut shirt = MeshBuilder::default();
    let mut skin = MeshBuilder::default();
    let mut trousers = MeshBuilder::default();
    let mut shoes = MeshBuilder::default();
    let one = |j: u16| [(j, 1.0), (j, 0.0)];
    let half = |a: u16, b: u16| [(a, 0.5), (b, 0.5)];
    // Torso: hips to the base of the neck, a flattened tube that bends at the spine and chest.
    let torso =
        [(0.0, one(HIPS)), (0.25, half(HIPS, SPINE)), (0.45, one(SPINE)), (0.7, half(SPINE, CHEST)), (1.0, one(CHEST))];
    shirt.tube(Vec3::new(0.0, 0.86, 0.0), Vec3::new(0.0, 1.48, 0.0), (0.16, 0.19), 0.62, &torso);
    skin.tube(
        Vec3::new(0.0, 1.44, 0.0),
        Vec3::new(0.0, 1.58, 0.0),
        (0.05, 0.05),
        1.0,
        &[(0.0, one(CHEST)), (1.0, one(HEAD))],
    );
    skin.sphere(Vec3::new(0.0, 1.66, 0.01), 0.11, one(HEAD));
    for (upper, fore) in [(4u16, 5u16), (6, 7)] {
        let (shoulder, elbow) = (at(upper), at(fore));
        let wrist = elbow + (elbow - shoulder).normalize() * 0.25;
        let arm = [(0.0, half(CHEST, upper)), (0.2, one(upper)), (0.85, one(upper)), (1.0, half(upper, fore))];
        shirt.tube(shoulder, elbow, (0.06, 0.05), 1.0, &arm);
        skin.tube(elbow, wrist, (0.045, 0.035), 1.0, &[(0.0, half(upper, fore)), (0.2, one(fore)), (1.0, one(fore))]);
        skin.sphere(wrist + (wrist - elbow).normalize() * 0.04, 0.045, one(fore));
    }
    for (thigh, shin, foot) in [(8u16, 9u16, 10u16), (11, 12, 13)] {
        let leg = [(0.0, half(HIPS, thigh)), (0.15, one(thigh)), (0.9, one(thigh)), (1.0, half(thigh, shin))];
        trousers.tube(at(thigh), at(shin), (0.085, 0.06), 1.0, &leg);
        let calf = [(0.0, half(thigh, shin)), (0.15, one(shin)), (1.0, one(shin))];
        trousers.tube(at(shin), at(foot) + Vec3::Y * 0.02, (0.06, 0.045), 1.0, &calf);
        let centre = at(foot) * Vec3::new(1.0, 0.0, 1.0) + Vec3::new(0.0, 0.045, 0.06);
        shoes.cuboid(centre, Vec3::new(0.05, 0.045, 0.13), one(foot));
    }
    [
        ("shirt", [1.0, 1.0, 1.0], shirt),
        ("skin", [0.80, 0.56, 0.42], skin),
        ("trousers", [0.16, 0.15, 0.17], trousers),
        ("shoes", [0.35, 0.18, 0.09], shoes),
    ]
}

/// Joint rotations of the walk at phase `p` (radians, one cycle = 2π), as (bone, rotation).
fn walk_pose(p: f32) -> Vec<(usize, Quat)> {
    let deg = |d: f32| d.to_radians();
    let s = p.sin();
    let mut pose = vec![
        (0, Quat::from_rotation_y(deg(4.0) * s)),
        (1, Quat::from_rotation_y(deg(-3.0) * s) * Quat::from_rotation_x(deg(3.0))),
        (2, Quat::from_rotation_y(deg(-4.0) * s)),
        (3, Quat::from_rotation_y(deg(3.0) * s)),
    ];
    // Each leg: a swing about X (negative is forward), a knee that bends while the leg swings
    // forward and an ankle that keeps the foot nearly level; the right leg runs half a cycle later.
    for (side, thigh, arm) in [(0.0f32, 8usize, 4usize), (std::f32::consts::PI, 11, 6)] {
        let q = p + side;
        let swing = deg(-26.0) * q.sin();
        let knee = deg(6.0) + deg(48.0) * (q + 0.6).cos().max(0.0).powf(1.5);
        let ankle = -0.8 * (swing + knee);
        pose.push((thigh, Quat::from_rotation_x(swing)));
        pose.push((thigh + 1, Quat::from_rotation_x(knee)));
        pose.push((thigh + 2, Quat::from_rotation_x(ankle)));
        // Arms swing against the leg of their side and bend more at the elbow when forward.
        let arm_swing = deg(20.0) * q.sin();
        pose.push((
            arm,
            Quat::from_rotation_x(arm_swing) * Quat::from_rotation_z(deg(if side == 0.0 { 6.0 } else { -6.0 })),
        ));
        pose.push((arm + 1, Quat::from_rotation_x(-deg(12.0) - deg(14.0) * (-q.sin()).max(0.0))));
    }
    pose
}

/// Height of the hips above their bind height at phase `p`: highest as the legs pass each other.
fn hip_lift(p: f32) -> f32 {
    0.022 * (2.0 * p).cos() - 0.018
}

/// The character as .glb bytes. The same code always writes the same file.
pub fn character_glb() -> Vec<u8> {
    let mut glb = GlbBuilder::default();
    let (mut meshes, mut materials) = (Vec::new(), Vec::new());
    let mut primitives = Vec::new();
    for (i, (name, color, mesh)) in surfaces().into_iter().enumerate() {
        let mut attributes = json!({
            "POSITION": glb.floats(&mesh.positions(), 3, true, Some(ARRAY_BUFFER)),
            "NORMAL": glb.floats(&mesh.normals(), 3, false, Some(ARRAY_BUFFER)),
            "JOINTS_0": glb.shorts(&mesh.joints(), 4, Some(ARRAY_BUFFER)),
            "WEIGHTS_0": glb.floats(&mesh.weights(), 4, false, Some(ARRAY_BUFFER)),
        });
        let indices = glb.shorts(&mesh.indices, 1, Some(ELEMENT_ARRAY_BUFFER));
        let mut pbr = json!({ "baseColorFactor": [color[0], color[1], color[2], 1.0], "metallicFactor": 0.0,
            "roughnessFactor": 0.8 });
        if name == "shirt" {
            attributes["TEXCOORD_0"] =
                json!(glb.floats(&mesh.stripes(STRIPES_PER_METRE), 2, false, Some(ARRAY_BUFFER)));
            pbr["baseColorTexture"] = json!({ "index": 0 });
        }
        primitives.push(json!({ "attributes": attributes, "indices": indices, "material": i }));
        materials.push(json!({ "name": name, "pbrMetallicRoughness": pbr }));
    }
    let stripes = glb.bytes(&stripes_png());
    meshes.push(json!({ "name": "body", "primitives": primitives }));

    let mut nodes: Vec<_> = BONES
        .iter()
        .enumerate()
        .map(|(i, (name, parent, head))| {
            let local = Vec3::from(*head) - parent.map_or(Vec3::ZERO, |p| Vec3::from(BONES[p].2));
            let children: Vec<usize> = (0..BONES.len()).filter(|&c| BONES[c].1 == Some(i)).collect();
            let mut node = json!({ "name": name, "translation": local.to_array() });
            if !children.is_empty() {
                node["children"] = json!(children);
            }
            node
        })
        .collect();
    nodes.push(json!({ "name": "body", "mesh": 0, "skin": 0 }));
    let inverse_bind: Vec<f32> =
        BONES.iter().flat_map(|b| glam::Mat4::from_translation(-Vec3::from(b.2)).to_cols_array()).collect();
    let skin = json!({ "joints": (0..BONES.len()).collect::<Vec<_>>(), "skeleton": 0,
        "inverseBindMatrices": glb.floats(&inverse_bind, 16, false, None) });

    // The walk: 16 linear keys a cycle, the last equal to the first so the loop is seamless.
    const KEYS: usize = 16;
    let phases: Vec<f32> = (0..=KEYS).map(|k| k as f32 / KEYS as f32 * std::f32::consts::TAU).collect();
    let times: Vec<f32> = (0..=KEYS).map(|k| k as f32 / KEYS as f32 * WALK_CYCLE).collect();
    let input = glb.floats(&times, 1, true, None);
    let (mut samplers, mut channels) = (Vec::new(), Vec::new());
    let mut channel = |glb: &mut GlbBuilder, node: usize, path: &str, values: Vec<f32>, width: usize| {
        samplers.push(
            json!({ "input": input, "output": glb.floats(&values, width, false, None), "interpolation": "LINEAR" }),
        );
        channels.push(json!({ "sampler": samplers.len() - 1, "target": { "node": node, "path": path } }));
    };
    let hips: Vec<f32> = phases.iter().flat_map(|&p| (at(HIPS) + Vec3::Y * hip_lift(p)).to_array()).collect();
    channel(&mut glb, 0, "translation", hips, 3);
    let poses: Vec<Vec<(usize, Quat)>> = phases.iter().map(|&p| walk_pose(p)).collect();
    for k in 0..poses[0].len() {
        let bone = poses[0][k].0;
        let values = poses.iter().flat_map(|pose| pose[k].1.normalize().to_array()).collect();
        channel(&mut glb, bone, "rotation", values, 4);
    }
    let document = json!({
        "asset": { "version": "2.0", "generator": "umbra make_character" },
        "scene": 0,
        "scenes": [{ "nodes": [0, BONES.len()] }],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "images": [{ "name": "stripes", "bufferView": stripes, "mimeType": "image/png" }],
        "samplers": [{ "magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497 }],
        "textures": [{ "sampler": 0, "source": 0 }],
        "skins": [skin],
        "animations": [{ "name": "walk", "samplers": samplers, "channels": channels }],
    });
    glb.finish(document)
}
