//! A glTF scene built in code: a ground, a pillar and a box, with whatever lights and camera a
//! test hangs on nodes of its own.

use super::gltf::TestModel;
use glam::Vec3;
use serde_json::{Value, json};
use umbra::assets::{MeshData, cube, plane};
use umbra::components::Transform;

/// Where the scene's casters stand: a 0.6 x 2 x 0.6 m pillar and a 1 m box, on a 30 m ground.
pub const PILLAR: Vec3 = Vec3::new(0.0, 1.0, 0.0);
pub const BOX: Vec3 = Vec3::new(2.0, 0.5, -1.5);

/// The scene being built.
pub struct SceneFile(pub TestModel);

fn push(json: &mut Value, list: &str, item: Value) -> usize {
    if json[list].is_null() {
        json[list] = json!([]);
    }
    let items = json[list].as_array_mut().unwrap();
    items.push(item);
    items.len() - 1
}

/// Adds `mesh` with a material of `color`; returns the mesh's index.
fn add_mesh(model: &mut TestModel, mesh: &MeshData, color: [f32; 3]) -> usize {
    let positions: Vec<f32> = mesh.vertices.iter().flat_map(|v| v.position).collect();
    let normals: Vec<f32> = mesh.vertices.iter().flat_map(|v| v.normal).collect();
    let pos = model.add_floats(&positions, "VEC3");
    model.json["accessors"][pos]["min"] = json!(mesh.bounds.min.to_array());
    model.json["accessors"][pos]["max"] = json!(mesh.bounds.max.to_array());
    let nor = model.add_floats(&normals, "VEC3");
    let indices: Vec<u16> = mesh.indices.iter().map(|&i| i as u16).collect();
    let idx = model.add_shorts(&indices, "SCALAR");
    let material = push(
        &mut model.json,
        "materials",
        json!({ "pbrMetallicRoughness": { "baseColorFactor": [color[0], color[1], color[2], 1.0] } }),
    );
    push(
        &mut model.json,
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": pos, "NORMAL": nor }, "indices": idx, "material": material }] }),
    )
}

impl SceneFile {
    /// The ground, the pillar and the box, without lights or camera.
    pub fn new() -> SceneFile {
        let mut model = TestModel::empty();
        let ground = add_mesh(&mut model, &plane(30.0), [0.55, 0.55, 0.5]);
        let block = add_mesh(&mut model, &cube(Vec3::splat(0.5)), [0.7, 0.6, 0.5]);
        let mut scene = SceneFile(model);
        scene.node(json!({ "name": "ground", "mesh": ground }));
        scene.node(
            json!({ "name": "pillar", "mesh": block, "translation": PILLAR.to_array(), "scale": [0.6, 2.0, 0.6] }),
        );
        scene.node(json!({ "name": "box", "mesh": block, "translation": BOX.to_array() }));
        scene
    }

    /// Adds `node` to the scene; returns its index.
    pub fn node(&mut self, node: Value) -> usize {
        let n = push(&mut self.0.json, "nodes", node);
        self.0.json["scenes"][0]["nodes"].as_array_mut().unwrap().push(json!(n));
        n
    }

    /// A node at `at` whose -Z axis points along `toward`.
    fn aimed(at: Vec3, toward: Vec3) -> Value {
        let rotation = Transform::default().looking_to(toward).rotation;
        json!({ "translation": at.to_array(), "rotation": rotation.to_array() })
    }

    /// Hangs the `KHR_lights_punctual` light `light` on a new node at `at` aimed along `toward`.
    pub fn light(mut self, light: Value, at: Vec3, toward: Vec3) -> SceneFile {
        let json = &mut self.0.json;
        json["extensionsUsed"] = json!(["KHR_lights_punctual"]);
        if json["extensions"]["KHR_lights_punctual"]["lights"].is_null() {
            json["extensions"] = json!({ "KHR_lights_punctual": { "lights": [] } });
        }
        let lights = json["extensions"]["KHR_lights_punctual"]["lights"].as_array_mut().unwrap();
        lights.push(light);
        let index = lights.len() - 1;
        let mut node = SceneFile::aimed(at, toward);
        node["extensions"] = json!({ "KHR_lights_punctual": { "light": index } });
        self.node(node);
        self
    }

    /// Hangs a perspective camera of vertical field of view `fov_y` on a new node at `eye`
    /// looking at `target`.
    pub fn camera(mut self, fov_y: f32, eye: Vec3, target: Vec3) -> SceneFile {
        let camera = json!({ "type": "perspective", "perspective": { "yfov": fov_y, "znear": 0.05, "zfar": 120.0 } });
        let index = push(&mut self.0.json, "cameras", camera);
        let mut node = SceneFile::aimed(eye, target - eye);
        node["camera"] = json!(index);
        self.node(node);
        self
    }

    /// Writes the scene as a .gltf with its data embedded; returns the path.
    pub fn write(&self, dir: &std::path::Path, name: &str) -> std::path::PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, self.0.gltf_embedded()).unwrap();
        path
    }
}
