//! From bytes to a validated glTF document and the bytes of every buffer it names: the .glb
//! container, JSON text, data URIs and external .bin files.

use base64::Engine;
use std::path::Path;

/// A validated document with its buffers, each at least as long as it declares.
pub(super) struct Source {
    pub doc: gltf::Document,
    pub buffers: Vec<Vec<u8>>,
}

/// Extensions that may be required without changing what umbra draws: quantized attributes
/// are read like any other accessor; unlit and texture transforms only affect textures and
/// shading umbra does not use.
const TOLERATED_EXTENSIONS: [&str; 3] = ["KHR_mesh_quantization", "KHR_materials_unlit", "KHR_texture_transform"];

/// Parses `bytes` (a .glb or .gltf) and loads its buffers; external files are looked up in `dir`.
pub(super) fn open(bytes: &[u8], dir: Option<&Path>) -> Result<Source, String> {
    let (json, blob) = if bytes.starts_with(b"glTF") {
        split_glb(bytes)?
    } else if bytes.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{') {
        (bytes, None)
    } else {
        let head: Vec<String> = bytes.iter().take(4).map(|b| format!("{b:02x}")).collect();
        return Err(format!(
            "not a glTF file: it starts with bytes [{}], not the .glb magic \"glTF\" or a JSON object",
            head.join(" ")
        ));
    };
    let mut root: gltf::json::Root =
        gltf::json::deserialize::from_slice(json).map_err(|e| format!("the glTF JSON does not parse: {e}"))?;
    if let Some(ext) = root.extensions_required.iter().find(|e| !TOLERATED_EXTENSIONS.contains(&e.as_str())) {
        return Err(format!("it requires the extension {ext}, which umbra does not support"));
    }
    root.extensions_required.clear();
    check_unchecked(&root)?;
    let doc = gltf::Document::from_json(root).map_err(|e| format!("invalid glTF: {e}"))?;
    let buffers = doc.buffers().map(|b| load_buffer(&b, blob, dir)).collect::<Result<_, _>>()?;
    Ok(Source { doc, buffers })
}

/// What the gltf crate's validation leaves unchecked or would index unchecked: animation channel
/// targets, and the POSITION accessor of each primitive.
fn check_unchecked(root: &gltf::json::Root) -> Result<(), String> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive.attributes.get(&gltf::json::validation::Checked::Valid(gltf::Semantic::Positions));
            if let Some(i) = position.map(|i| i.value()).filter(|&i| i >= root.accessors.len()) {
                return Err(format!(
                    "mesh {m} primitive {p}: POSITION is accessor {i}, but there are {} accessors",
                    root.accessors.len()
                ));
            }
        }
    }
    for (a, animation) in root.animations.iter().enumerate() {
        for (c, channel) in animation.channels.iter().enumerate() {
            let at = format!("animation {a} channel {c}");
            if channel.target.node.value() >= root.nodes.len() {
                return Err(format!(
                    "{at} targets node {}, but there are {} nodes",
                    channel.target.node.value(),
                    root.nodes.len()
                ));
            }
            if matches!(channel.target.path, gltf::json::validation::Checked::Invalid) {
                return Err(format!("{at} targets an unknown property"));
            }
        }
    }
    Ok(())
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(bytes.get(at..at.checked_add(4)?)?.try_into().ok()?))
}

/// The JSON chunk and the binary chunk (if any) of a .glb.
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let (Some(version), Some(length)) = (u32_at(bytes, 4), u32_at(bytes, 8)) else {
        return Err(format!("truncated .glb: {} bytes, less than its 12-byte header", bytes.len()));
    };
    if version != 2 {
        return Err(format!(".glb version {version}; umbra reads glTF 2.0"));
    }
    let length = length as usize;
    if length > bytes.len() {
        return Err(format!("truncated .glb: its header says {length} bytes but the file has {}", bytes.len()));
    }
    let (mut json, mut bin, mut at) = (None, None, 12usize);
    while at + 8 <= length {
        let (size, kind) = (u32_at(bytes, at).unwrap_or(0) as usize, &bytes[at + 4..at + 8]);
        let end = (at + 8).saturating_add(size);
        if end > length {
            return Err(format!("truncated .glb: a chunk at byte {at} needs {size} bytes, past the end of the file"));
        }
        match kind {
            b"JSON" if json.is_none() => json = Some(&bytes[at + 8..end]),
            b"BIN\0" if json.is_some() && bin.is_none() => bin = Some(&bytes[at + 8..end]),
            _ if json.is_none() => return Err("the .glb does not start with a JSON chunk".into()),
            _ => {} // Unknown chunks are skipped, as the format asks.
        }
        at = end;
    }
    let json = json.ok_or("the .glb has no JSON chunk")?;
    Ok((json, bin))
}

/// The bytes of one buffer: the .glb's binary chunk, a data URI, or a file next to the model.
fn load_buffer(buffer: &gltf::Buffer<'_>, blob: Option<&[u8]>, dir: Option<&Path>) -> Result<Vec<u8>, String> {
    let i = buffer.index();
    let data = match buffer.source() {
        gltf::buffer::Source::Bin => {
            blob.ok_or(format!("buffer {i} is the .glb's binary chunk, but there is none"))?.to_vec()
        }
        gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
            data_uri(uri).map_err(|e| format!("buffer {i}: {e}"))?
        }
        gltf::buffer::Source::Uri(uri) => {
            read_beside(dir, uri, buffer.length()).map_err(|e| format!("buffer {i}: {e}"))?
        }
    };
    if data.len() < buffer.length() {
        return Err(format!("buffer {i} is short: it declares {} bytes but holds {}", buffer.length(), data.len()));
    }
    Ok(data)
}

/// At most `length` bytes of the file `uri` names, which must lie next to the model (or below it):
/// not a web address, not an absolute path, no `..`, and a plain file (never a device or pipe
/// that could hang the read).
fn read_beside(dir: Option<&Path>, uri: &str, length: usize) -> Result<Vec<u8>, String> {
    use std::io::Read;
    let relative = std::path::PathBuf::from(String::from_utf8_lossy(&percent_decode(uri)).into_owned());
    let outside = uri.contains("://")
        || relative.components().any(|c| !matches!(c, std::path::Component::Normal(_) | std::path::Component::CurDir));
    if outside {
        return Err(format!("its file {uri} is not beside the model; umbra reads only files next to it"));
    }
    let path = dir.unwrap_or(Path::new(".")).join(relative);
    let fail = |e: std::io::Error| format!("cannot read {}: {e}", path.display());
    if !std::fs::metadata(&path).map_err(fail)?.is_file() {
        return Err(format!("{} is not a plain file", path.display()));
    }
    let mut data = Vec::new();
    std::fs::File::open(&path).and_then(|f| f.take(length as u64).read_to_end(&mut data)).map_err(fail)?;
    Ok(data)
}

/// The bytes of a `data:[type][;base64],payload` URI.
fn data_uri(uri: &str) -> Result<Vec<u8>, String> {
    let (head, payload) = uri.split_once(',').ok_or("a data URI without a comma")?;
    if head.ends_with(";base64") {
        base64::engine::general_purpose::STANDARD
            .decode(payload.trim())
            .map_err(|e| format!("its data URI is not valid base64: {e}"))
    } else {
        Ok(percent_decode(payload))
    }
}

/// `%20`-style escapes of a URI turned back into bytes (invalid escapes stay as they are).
fn percent_decode(s: &str) -> Vec<u8> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(b)) => {
                out.push(b);
                i += 3;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_uris_and_escapes_decode() {
        assert_eq!(data_uri("data:application/octet-stream;base64,AAEC").unwrap(), vec![0, 1, 2]);
        assert!(data_uri("data:application/octet-stream;base64,%%%").unwrap_err().contains("base64"));
        assert_eq!(percent_decode("my%20model.bin"), b"my model.bin");
        assert_eq!(percent_decode("100%"), b"100%");
        assert_eq!(data_uri("data:,%00%ff").unwrap(), vec![0, 255], "raw bytes, not text");
    }

    #[test]
    fn glb_headers_are_checked() {
        assert!(split_glb(b"glTF\x02\0\0").unwrap_err().contains("12-byte header"));
        assert!(split_glb(b"glTF\x01\0\0\0\x0c\0\0\0").unwrap_err().contains("version 1"));
        assert!(split_glb(b"glTF\x02\0\0\0\xff\0\0\0").unwrap_err().contains("header says 255 bytes"));
        let chunk_past_end = b"glTF\x02\0\0\0\x18\0\0\0\x10\0\0\0JSON{}  ";
        assert!(split_glb(chunk_past_end).unwrap_err().contains("past the end"));
        let ok = b"glTF\x02\0\0\0\x18\0\0\0\x04\0\0\0JSON{}  ";
        assert_eq!(split_glb(ok).unwrap(), (&b"{}  "[..], None));
    }
}
