//! From bytes to a validated glTF document and the bytes of every buffer it names: the .glb
//! container, JSON text, data URIs and external .bin files.

use super::budget::{Budget, read_file};
use super::census::Census;
use base64::Engine;
use std::borrow::Cow;
use std::path::Path;

/// A validated document with its buffers, each at least as long as it declares.
pub(super) struct Source<'a> {
    pub doc: gltf::Document,
    /// The bytes of each buffer (the .glb's binary chunk is borrowed, not copied).
    pub buffers: Vec<Cow<'a, [u8]>>,
    /// Every (animation, channel) that targets no node (valid glTF: an extension may name the
    /// target); they are ignored with a warning.
    pub untargeted: Vec<(usize, usize)>,
    /// Where files the model names (buffers, images) are looked up.
    pub dir: Option<&'a Path>,
}

/// Extensions a file may require: quantized attributes are read like any other accessor, unlit
/// materials only change shading, punctual lights become umbra's lights (with `--scene`), and
/// texture transforms move the base-colour texture's coordinates.
const TOLERATED_EXTENSIONS: [&str; 4] =
    ["KHR_mesh_quantization", "KHR_materials_unlit", "KHR_lights_punctual", "KHR_texture_transform"];

/// Parses `bytes` (a .glb or .gltf) and loads its buffers, paid from `input`; external files are
/// looked up in `dir`.
pub(super) fn open<'a>(bytes: &'a [u8], dir: Option<&'a Path>, input: &Budget) -> Result<Source<'a>, String> {
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
    let census = Census::of(json)?;
    census.check_size()?;
    census.check_version()?;
    let untargeted = census.untargeted();
    let mut root = parse_root(json, &untargeted)?;
    if let Some(ext) = root.extensions_required.iter().find(|e| !TOLERATED_EXTENSIONS.contains(&e.as_str())) {
        return Err(format!("it requires the extension {ext}, which umbra does not support"));
    }
    root.extensions_required.clear();
    check_unchecked(&root, &untargeted)?;
    let doc = gltf::Document::from_json(root).map_err(describe)?;
    check_layout(&doc)?;
    let buffers = doc.buffers().map(|b| load_buffer(&b, blob, dir, input)).collect::<Result<_, _>>()?;
    Ok(Source { doc, buffers, untargeted, dir })
}

/// The JSON as the gltf crate's document. A channel without a target node (which the crate's
/// types cannot hold) is pointed at node 0 first; the loader skips it.
fn parse_root(json: &[u8], untargeted: &[(usize, usize)]) -> Result<gltf::json::Root, String> {
    let fail = |e: serde_json::Error| format!("the glTF JSON does not parse: {e}");
    if untargeted.is_empty() {
        return gltf::json::deserialize::from_slice(json).map_err(fail);
    }
    let mut value: serde_json::Value = serde_json::from_slice(json).map_err(fail)?;
    for &(a, c) in untargeted {
        if let Some(target) = value.pointer_mut(&format!("/animations/{a}/channels/{c}/target")) {
            target["node"] = serde_json::json!(0);
        }
    }
    serde_json::from_value(value).map_err(fail)
}

/// The gltf crate's validation errors in plain words, each with where in the JSON it is.
fn describe(e: gltf::Error) -> String {
    let gltf::Error::Validation(errors) = e else { return format!("it is not valid glTF: {e}") };
    let what = |e: &gltf::json::validation::Error| match e {
        gltf::json::validation::Error::IndexOutOfBounds => "names an object that does not exist",
        gltf::json::validation::Error::Invalid => "has a value glTF does not allow",
        gltf::json::validation::Error::Missing => "is missing, and glTF requires it",
        gltf::json::validation::Error::Oversize => "is larger than this machine can hold",
        gltf::json::validation::Error::Unsupported => "uses an extension umbra does not support",
    };
    let listed: Vec<String> = errors.iter().take(3).map(|(path, e)| format!("{path} {}", what(e))).collect();
    let more = if errors.len() > 3 { format!(" (and {} more)", errors.len() - 3) } else { String::new() };
    format!("it breaks the glTF rules: {}{more}", listed.join("; "))
}

/// The layout rules of buffer views and accessors that the gltf crate leaves unchecked: every
/// view inside the length its buffer declares, strides in whole 4-byte steps, every accessor
/// holding at least one element and starting on a multiple of its component size.
fn check_layout(doc: &gltf::Document) -> Result<(), String> {
    for view in doc.views() {
        let (v, buffer) = (view.index(), view.buffer());
        let end = view.offset().saturating_add(view.length());
        if end > buffer.length() {
            return Err(format!(
                "buffer view {v} reaches byte {end}, past the {} bytes that buffer {} declares (its byteLength)",
                buffer.length(),
                buffer.index()
            ));
        }
        if let Some(stride) = view.stride().filter(|s| !s.is_multiple_of(4)) {
            return Err(format!(
                "buffer view {v}: its byteStride of {stride} bytes is not a multiple of 4, as glTF requires"
            ));
        }
    }
    for animation in doc.animations() {
        for sampler in animation.samplers() {
            if sampler.input().count() == 0 {
                return Err(format!(
                    "animation {} sampler {} has no keys (its input, accessor {}, has count 0)",
                    animation.index(),
                    sampler.index(),
                    sampler.input().index()
                ));
            }
        }
    }
    for acc in doc.accessors() {
        let i = acc.index();
        if acc.count() == 0 {
            return Err(format!("accessor {i} has no elements (count 0); glTF requires at least one"));
        }
        let size = acc.data_type().size();
        if let Some(view) = acc.view() {
            let start = view.offset().saturating_add(acc.offset());
            if !acc.offset().is_multiple_of(size) || !start.is_multiple_of(size) {
                return Err(format!(
                    "accessor {i} starts at byte {start} of buffer {}, not on a multiple of its {size}-byte components",
                    view.buffer().index()
                ));
            }
        }
    }
    Ok(())
}

/// What the gltf crate's validation leaves unchecked or would index unchecked: animation channel
/// targets (but for those that name no node), and the POSITION accessor of each primitive.
fn check_unchecked(root: &gltf::json::Root, untargeted: &[(usize, usize)]) -> Result<(), String> {
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
        for (c, channel) in animation.channels.iter().enumerate().filter(|(c, _)| !untargeted.contains(&(a, *c))) {
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
            b"JSON" if json.is_none() && size == 0 => return Err("the .glb's JSON chunk is empty".into()),
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
fn load_buffer<'a>(
    buffer: &gltf::Buffer<'_>,
    blob: Option<&'a [u8]>,
    dir: Option<&Path>,
    input: &Budget,
) -> Result<Cow<'a, [u8]>, String> {
    let i = buffer.index();
    let data = match buffer.source() {
        gltf::buffer::Source::Bin => {
            Cow::Borrowed(blob.ok_or(format!("buffer {i} is the .glb's binary chunk, but there is none"))?)
        }
        gltf::buffer::Source::Uri(uri) => {
            Cow::Owned(read_uri(uri, dir, input).map_err(|e| format!("buffer {i}: {e}"))?)
        }
    };
    if data.len() < buffer.length() {
        return Err(format!("buffer {i} is short: it declares {} bytes but holds {}", buffer.length(), data.len()));
    }
    Ok(data)
}

/// The bytes a URI names (a data URI, or a file beside the model), paid from `input`.
pub(super) fn read_uri(uri: &str, dir: Option<&Path>, input: &Budget) -> Result<Vec<u8>, String> {
    if uri.starts_with("data:") {
        return data_uri(uri, input);
    }
    let relative = std::path::PathBuf::from(String::from_utf8_lossy(&percent_decode(uri)).into_owned());
    let outside = uri.contains("://")
        || relative.components().any(|c| !matches!(c, std::path::Component::Normal(_) | std::path::Component::CurDir));
    if outside {
        return Err(format!("its file {uri} is not beside the model; umbra reads only files next to it"));
    }
    let path = dir.unwrap_or(Path::new(".")).join(relative);
    read_file(&path, &path.display().to_string(), input)
}

/// The bytes of a `data:[type][;base64],payload` URI.
fn data_uri(uri: &str, input: &Budget) -> Result<Vec<u8>, String> {
    let (head, payload) = uri.split_once(',').ok_or("a data URI without a comma")?;
    input.spend(payload.len() as u64)?;
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
        let b = Budget::input();
        assert_eq!(data_uri("data:application/octet-stream;base64,AAEC", &b).unwrap(), vec![0, 1, 2]);
        assert!(data_uri("data:application/octet-stream;base64,%%%", &b).unwrap_err().contains("base64"));
        assert_eq!(percent_decode("my%20model.bin"), b"my model.bin");
        assert_eq!(percent_decode("100%"), b"100%");
        assert_eq!(data_uri("data:,%00%ff", &b).unwrap(), vec![0, 255], "raw bytes, not text");
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
        let empty_json = b"glTF\x02\0\0\0\x18\0\0\0\0\0\0\0JSON{}  ";
        assert!(split_glb(empty_json).unwrap_err().contains("JSON chunk is empty"));
    }
}
