//! A small .glb writer: typed arrays become accessors over one binary buffer.

use serde_json::{Value, json};

/// Accessors and buffer views over one growing binary chunk.
#[derive(Default)]
pub(super) struct GlbBuilder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

/// glTF component type codes.
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
/// Buffer view targets for vertex attributes and indices.
pub(super) const ARRAY_BUFFER: u32 = 34962;
pub(super) const ELEMENT_ARRAY_BUFFER: u32 = 34963;

fn type_name(width: usize) -> &'static str {
    match width {
        1 => "SCALAR",
        2 => "VEC2",
        3 => "VEC3",
        4 => "VEC4",
        _ => "MAT4",
    }
}

impl GlbBuilder {
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut view = json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        if let Some(t) = target {
            view["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(view);
        self.views.len() - 1
    }

    /// Floats, `width` per element; `bounds` adds the min and max the spec asks of positions and
    /// key times.
    pub(super) fn floats(&mut self, data: &[f32], width: usize, bounds: bool, target: Option<u32>) -> usize {
        let view = self.view(bytemuck::cast_slice(data), target);
        let mut acc = json!({
            "bufferView": view, "componentType": FLOAT, "count": data.len() / width, "type": type_name(width)
        });
        if bounds {
            let column = |c: usize| data.iter().skip(c).step_by(width).copied();
            acc["min"] = json!((0..width).map(|c| column(c).fold(f32::INFINITY, f32::min)).collect::<Vec<_>>());
            acc["max"] = json!((0..width).map(|c| column(c).fold(f32::NEG_INFINITY, f32::max)).collect::<Vec<_>>());
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    /// Raw bytes (an encoded image) in a buffer view of their own; returns the view.
    pub(super) fn bytes(&mut self, data: &[u8]) -> usize {
        self.view(data, None)
    }

    /// Unsigned shorts, `width` per element.
    pub(super) fn shorts(&mut self, data: &[u16], width: usize, target: Option<u32>) -> usize {
        let view = self.view(bytemuck::cast_slice(data), target);
        self.accessors.push(json!({
            "bufferView": view, "componentType": UNSIGNED_SHORT, "count": data.len() / width, "type": type_name(width)
        }));
        self.accessors.len() - 1
    }

    /// The .glb: `document` (everything but buffers, views and accessors) with the binary chunk.
    pub(super) fn finish(mut self, mut document: Value) -> Vec<u8> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        document["buffers"] = json!([{ "byteLength": self.bin.len() }]);
        document["bufferViews"] = Value::Array(self.views);
        document["accessors"] = Value::Array(self.accessors);
        let mut json = serde_json::to_vec(&document).unwrap_or_default();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let length = 12 + 8 + json.len() + 8 + self.bin.len();
        let mut out = Vec::with_capacity(length);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(length as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        out.extend_from_slice(&(self.bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&self.bin);
        out
    }
}
