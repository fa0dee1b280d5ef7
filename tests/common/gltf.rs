//! A small skinned glTF model built in code, so tests can break it in every way they need.
//!
//! A 2 m column of two joints: `root` at the origin and `tip` 1 m up. Its vertices sit at
//! heights 0, 1 and 2: the bottom ring follows `root`, the middle ring is shared half and half,
//! the top ring follows `tip`. One clip, "bend", turns `tip` about Z (LINEAR), moves `root`
//! (STEP) and scales `tip` (CUBICSPLINE).

use base64::Engine;
use serde_json::{Value, json};

/// The document and its one binary buffer.
#[derive(Clone)]
pub struct TestModel {
    pub json: Value,
    pub bin: Vec<u8>,
}

fn floats(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|f| f.to_le_bytes()).collect()
}

/// Appends `bytes` (4-byte aligned) and a view and accessor over them; returns the accessor.
fn push(json: &mut Value, bin: &mut Vec<u8>, bytes: Vec<u8>, accessor: Value) -> usize {
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let views = json["bufferViews"].as_array_mut().unwrap();
    views.push(json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len() }));
    let mut accessor = accessor;
    accessor["bufferView"] = json!(views.len() - 1);
    bin.extend(bytes);
    let accessors = json["accessors"].as_array_mut().unwrap();
    accessors.push(accessor);
    accessors.len() - 1
}

/// Heights of the three rings and the corners of each ring (a square 0.2 m across).
pub const RINGS: [f32; 3] = [0.0, 1.0, 2.0];
const CORNERS: [(f32, f32); 4] = [(0.1, 0.1), (-0.1, 0.1), (-0.1, -0.1), (0.1, -0.1)];

/// Joint weights of each ring: (root, tip).
pub const RING_WEIGHTS: [(f32, f32); 3] = [(1.0, 0.0), (0.5, 0.5), (0.0, 1.0)];

/// Key times and values of the clip: tip rotation (LINEAR, about Z), root translation (STEP),
/// tip scale (CUBICSPLINE, in-tangent / value / out-tangent per key).
pub const TIMES: [f32; 3] = [0.0, 1.0, 2.0];
pub const TIP_ANGLES: [f32; 3] = [0.0, 0.8, 0.0];
pub const ROOT_X: [f32; 3] = [0.0, 0.5, 1.0];
pub const TIP_SCALE: [f32; 3] = [1.0, 2.0, 1.0];
pub const TIP_SCALE_OUT_TANGENT: f32 = 1.5;

impl TestModel {
    pub fn new() -> TestModel {
        let mut json = json!({
            "asset": { "version": "2.0" },
            "scene": 0,
            "scenes": [{ "nodes": [0, 2] }],
            "nodes": [
                { "name": "root", "children": [1] },
                { "name": "tip", "translation": [0.0, 1.0, 0.0] },
                { "name": "column", "mesh": 0, "skin": 0 }
            ],
            "buffers": [{ "byteLength": 0 }],
            "bufferViews": [],
            "accessors": [],
            "materials": [{ "pbrMetallicRoughness": { "baseColorFactor": [0.2, 0.4, 0.6, 1.0] } }],
        });
        let mut bin = Vec::new();
        let (mut positions, mut normals, mut joints, mut weights) = (vec![], vec![], vec![], vec![]);
        for (ring, y) in RINGS.iter().enumerate() {
            for (x, z) in CORNERS {
                positions.extend([x, *y, z]);
                normals.extend([x, 0.0, z].map(|c| c / 0.1414214));
                joints.extend([0u16, 1, 0, 0]);
                weights.extend([RING_WEIGHTS[ring].0, RING_WEIGHTS[ring].1, 0.0, 0.0]);
            }
        }
        let mut indices: Vec<u16> = Vec::new();
        for ring in 0..2u16 {
            for k in 0..4u16 {
                let (a, b) = (ring * 4 + k, ring * 4 + (k + 1) % 4);
                indices.extend([a, b + 4, b, a, a + 4, b + 4]);
            }
        }
        let pos = push(
            &mut json,
            &mut bin,
            floats(&positions),
            json!({ "componentType": 5126, "count": 12, "type": "VEC3",
            "min": [-0.1, 0.0, -0.1], "max": [0.1, 2.0, 0.1] }),
        );
        let nor =
            push(&mut json, &mut bin, floats(&normals), json!({ "componentType": 5126, "count": 12, "type": "VEC3" }));
        let jnt = push(
            &mut json,
            &mut bin,
            joints.iter().flat_map(|j| j.to_le_bytes()).collect(),
            json!({ "componentType": 5123, "count": 12, "type": "VEC4" }),
        );
        let wgt =
            push(&mut json, &mut bin, floats(&weights), json!({ "componentType": 5126, "count": 12, "type": "VEC4" }));
        let idx = push(
            &mut json,
            &mut bin,
            indices.iter().flat_map(|i| i.to_le_bytes()).collect(),
            json!({ "componentType": 5123, "count": indices.len(), "type": "SCALAR" }),
        );
        json["meshes"] = json!([{ "primitives": [{
            "attributes": { "POSITION": pos, "NORMAL": nor, "JOINTS_0": jnt, "WEIGHTS_0": wgt },
            "indices": idx, "material": 0 }] }]);
        let ibm: Vec<f32> = [0.0f32, -1.0]
            .iter()
            .flat_map(|ty| {
                let mut m = [0.0f32; 16];
                m[0] = 1.0;
                m[5] = 1.0;
                m[10] = 1.0;
                m[15] = 1.0;
                m[13] = *ty;
                m
            })
            .collect();
        let ibm = push(&mut json, &mut bin, floats(&ibm), json!({ "componentType": 5126, "count": 2, "type": "MAT4" }));
        json["skins"] = json!([{ "joints": [0, 1], "inverseBindMatrices": ibm }]);

        let times = push(
            &mut json,
            &mut bin,
            floats(&TIMES),
            json!({ "componentType": 5126, "count": 3, "type": "SCALAR",
            "min": [0.0], "max": [2.0] }),
        );
        let rotations: Vec<f32> =
            TIP_ANGLES.iter().flat_map(|a| [0.0, 0.0, (a / 2.0).sin(), (a / 2.0).cos()]).collect();
        let rot =
            push(&mut json, &mut bin, floats(&rotations), json!({ "componentType": 5126, "count": 3, "type": "VEC4" }));
        let moves: Vec<f32> = ROOT_X.iter().flat_map(|x| [*x, 0.0, 0.0]).collect();
        let mov =
            push(&mut json, &mut bin, floats(&moves), json!({ "componentType": 5126, "count": 3, "type": "VEC3" }));
        let scales: Vec<f32> = TIP_SCALE
            .iter()
            .enumerate()
            .flat_map(|(k, s)| {
                let out = if k == 0 { TIP_SCALE_OUT_TANGENT } else { 0.0 };
                [0.0, 0.0, 0.0, *s, *s, *s, out, out, out]
            })
            .collect();
        let scl =
            push(&mut json, &mut bin, floats(&scales), json!({ "componentType": 5126, "count": 9, "type": "VEC3" }));
        json["animations"] = json!([{ "name": "bend",
            "samplers": [
                { "input": times, "output": rot, "interpolation": "LINEAR" },
                { "input": times, "output": mov, "interpolation": "STEP" },
                { "input": times, "output": scl, "interpolation": "CUBICSPLINE" }
            ],
            "channels": [
                { "sampler": 0, "target": { "node": 1, "path": "rotation" } },
                { "sampler": 1, "target": { "node": 0, "path": "translation" } },
                { "sampler": 2, "target": { "node": 1, "path": "scale" } }
            ] }]);
        json["buffers"][0]["byteLength"] = json!(bin.len());
        TestModel { json, bin }
    }

    /// A document with no nodes, meshes or data yet (one empty scene, one empty buffer).
    pub fn empty() -> TestModel {
        let json = json!({
            "asset": { "version": "2.0" },
            "scene": 0,
            "scenes": [{ "nodes": [] }],
            "nodes": [],
            "meshes": [],
            "materials": [],
            "buffers": [{ "byteLength": 0 }],
            "bufferViews": [],
            "accessors": [],
        });
        TestModel { json, bin: Vec::new() }
    }

    /// Adds a float accessor (with its view) over new bytes; returns its index.
    pub fn add_floats(&mut self, values: &[f32], kind: &str) -> usize {
        let width = match kind {
            "SCALAR" => 1,
            "VEC3" => 3,
            "MAT4" => 16,
            _ => 4,
        };
        let count = values.len() / width;
        let i = push(
            &mut self.json,
            &mut self.bin,
            floats(values),
            json!({ "componentType": 5126, "count": count, "type": kind }),
        );
        self.json["buffers"][0]["byteLength"] = json!(self.bin.len());
        i
    }

    /// Adds an unsigned-short accessor (with its view) over new bytes; returns its index.
    pub fn add_shorts(&mut self, values: &[u16], kind: &str) -> usize {
        let width = match kind {
            "SCALAR" => 1,
            "VEC3" => 3,
            _ => 4,
        };
        let bytes = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let i = push(
            &mut self.json,
            &mut self.bin,
            bytes,
            json!({ "componentType": 5123, "count": values.len() / width, "type": kind }),
        );
        self.json["buffers"][0]["byteLength"] = json!(self.bin.len());
        i
    }

    /// The model as one .glb.
    pub fn glb(&self) -> Vec<u8> {
        let mut json = serde_json::to_vec(&self.json).unwrap();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend(((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
        out.extend((json.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(json);
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(bin);
        out
    }

    /// The model as .gltf text with its buffer in a base64 data URI.
    pub fn gltf_embedded(&self) -> Vec<u8> {
        let mut json = self.json.clone();
        let data = base64::engine::general_purpose::STANDARD.encode(&self.bin);
        json["buffers"][0]["uri"] = json!(format!("data:application/octet-stream;base64,{data}"));
        serde_json::to_vec_pretty(&json).unwrap()
    }

    /// The test column drawn rigid by `n` more nodes, each placed apart on a grid 300 wide.
    pub fn instanced(n: usize) -> TestModel {
        let mut model = TestModel::new();
        model.json["nodes"][2].as_object_mut().unwrap().remove("skin");
        let nodes = model.json["nodes"].as_array_mut().unwrap();
        nodes.extend((0..n).map(|i| json!({ "mesh": 0, "translation": [(i % 300) as f32, 0.0, (i / 300) as f32] })));
        model.json["scenes"][0]["nodes"] = json!((0..3 + n).filter(|&k| k != 1).collect::<Vec<_>>());
        model
    }

    /// The test column drawn rigid, its mesh of `n` primitives, each the column again (each a
    /// mesh of its own to umbra, drawn with a call of its own).
    pub fn primitives(n: usize) -> TestModel {
        let mut model = TestModel::new();
        model.json["nodes"][2].as_object_mut().unwrap().remove("skin");
        let column = model.json["meshes"][0]["primitives"][0].clone();
        model.json["meshes"][0]["primitives"] = json!(vec![column; n]);
        model
    }

    /// The model as .gltf text naming `bin_name`, whose bytes are returned beside it.
    pub fn gltf_external(&self, bin_name: &str) -> (Vec<u8>, Vec<u8>) {
        let mut json = self.json.clone();
        json["buffers"][0]["uri"] = json!(bin_name);
        (serde_json::to_vec_pretty(&json).unwrap(), self.bin.clone())
    }
}

/// The model as the loader reads it from a .glb; any error fails the test.
pub fn load(model: &TestModel) -> umbra::assets::Model {
    umbra::assets::parse_model(&model.glb(), None, "test.glb").unwrap_or_else(|e| panic!("{e}"))
}

/// The error text for a changed copy of the test model, which must be refused.
pub fn refused(change: impl FnOnce(&mut TestModel)) -> String {
    let mut model = TestModel::new();
    change(&mut model);
    match umbra::assets::parse_model(&model.glb(), None, "broken.glb") {
        Ok(_) => panic!("a broken model loaded"),
        Err(e) => e.to_string(),
    }
}

/// An RGBA PNG of `width` x `height` texels.
pub fn png_rgba(width: u32, height: u32, rgba: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.write_header().unwrap().write_image_data(rgba).unwrap();
    out
}

/// A `n` x `n` checker of two RGBA colours, `a` at texel (0, 0).
pub fn checker(n: u32, a: [u8; 4], b: [u8; 4]) -> Vec<u8> {
    (0..n * n).flat_map(|i| if (i % n + i / n).is_multiple_of(2) { a } else { b }).collect()
}

impl TestModel {
    /// Gives the column texture coordinates (u round the column, v up it) and a base-colour
    /// texture whose image is `png` (stored in the buffer), sampled by `sampler` (JSON, or none).
    pub fn with_texture(mut self, png: &[u8], sampler: Option<Value>) -> TestModel {
        let uv: Vec<f32> = (0..12).flat_map(|i| [(i % 4) as f32 / 4.0, (i / 4) as f32 / 2.0]).collect();
        let uv = push(
            &mut self.json,
            &mut self.bin,
            floats(&uv),
            json!({ "componentType": 5126, "count": 12, "type": "VEC2" }),
        );
        self.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(uv);
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let views = self.json["bufferViews"].as_array_mut().unwrap();
        views.push(json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": png.len() }));
        let view = views.len() - 1;
        self.bin.extend_from_slice(png);
        self.json["buffers"][0]["byteLength"] = json!(self.bin.len());
        self.json["images"] = json!([{ "bufferView": view, "mimeType": "image/png", "name": "checker" }]);
        let mut texture = json!({ "source": 0 });
        if let Some(sampler) = sampler {
            self.json["samplers"] = json!([sampler]);
            texture["sampler"] = json!(0);
        }
        self.json["textures"] = json!([texture]);
        self.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({ "index": 0 });
        self
    }
}

/// A 2 m square in the XY plane facing +Z (corners at ±1), with texture coordinates u = (x + 1)
/// / 2 and v = (1 - y) / 2, drawn with `material` (JSON); `image` (JSON, its data from `png` if
/// given, stored in the buffer) is its base-colour texture when given, sampled nearest.
pub fn quad_glb(material: Value, image: Option<(Value, Option<&[u8]>)>) -> Vec<u8> {
    let mut bin = Vec::new();
    let mut json = json!({
        "asset": { "version": "2.0" },
        "scene": 0, "scenes": [{ "nodes": [0] }], "nodes": [{ "mesh": 0 }],
        "buffers": [{ "byteLength": 0 }], "bufferViews": [], "accessors": [],
        "materials": [material],
    });
    let corners = [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let positions: Vec<f32> = corners.iter().flat_map(|&(x, y)| [x, y, 0.0]).collect();
    let normals: Vec<f32> = corners.iter().flat_map(|_| [0.0, 0.0, 1.0]).collect();
    let uvs: Vec<f32> = corners.iter().flat_map(|&(x, y)| [(x + 1.0) / 2.0, (1.0 - y) / 2.0]).collect();
    let pos = push(
        &mut json,
        &mut bin,
        floats(&positions),
        json!({ "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 0.0] }),
    );
    let nor = push(&mut json, &mut bin, floats(&normals), json!({ "componentType": 5126, "count": 4, "type": "VEC3" }));
    let uv = push(&mut json, &mut bin, floats(&uvs), json!({ "componentType": 5126, "count": 4, "type": "VEC2" }));
    let indices: Vec<u8> = [0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()).collect();
    let idx = push(&mut json, &mut bin, indices, json!({ "componentType": 5123, "count": 6, "type": "SCALAR" }));
    json["meshes"] = json!([{ "primitives": [{
        "attributes": { "POSITION": pos, "NORMAL": nor, "TEXCOORD_0": uv }, "indices": idx, "material": 0 }] }]);
    if let Some((mut image, png)) = image {
        if let Some(png) = png {
            while !bin.len().is_multiple_of(4) {
                bin.push(0);
            }
            let views = json["bufferViews"].as_array_mut().unwrap();
            views.push(json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": png.len() }));
            image["bufferView"] = json!(views.len() - 1);
            image["mimeType"] = json!("image/png");
            bin.extend_from_slice(png);
        }
        json["images"] = json!([image]);
        json["samplers"] = json!([{ "magFilter": 9728, "minFilter": 9728 }]);
        json["textures"] = json!([{ "source": 0, "sampler": 0 }]);
        json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({ "index": 0 });
    }
    json["buffers"][0]["byteLength"] = json!(bin.len());
    TestModel { json, bin }.glb()
}
