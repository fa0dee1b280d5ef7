//! A first pass over the glTF JSON that allocates nothing per object: how many objects of each
//! kind the file holds (refused above [`MAX_OBJECTS`] before the real parse builds them), its
//! version, and the animation channels that target no node.

use super::budget::MAX_OBJECTS;
use serde::Deserialize;
use serde::de::{IgnoredAny, SeqAccess, Visitor};

/// An element of a JSON array as the census sees it.
trait Summary: for<'de> Deserialize<'de> {
    /// Objects it holds besides itself (a mesh's primitives).
    fn objects_inside(&self) -> usize {
        0
    }
    /// True when the census must remember where it is.
    fn keep(&self) -> bool {
        false
    }
}

impl Summary for IgnoredAny {}

/// A JSON array visited one element at a time: its length, the objects inside its elements,
/// and the positions of the elements worth keeping.
struct Array<T> {
    len: usize,
    inner: usize,
    kept: Vec<(usize, T)>,
}

impl<T> Default for Array<T> {
    fn default() -> Self {
        Array { len: 0, inner: 0, kept: Vec::new() }
    }
}

impl<'de, T: Summary> Deserialize<'de> for Array<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Walk<T>(std::marker::PhantomData<T>);
        impl<'de, T: Summary> Visitor<'de> for Walk<T> {
            type Value = Array<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an array")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Array<T>, A::Error> {
                let mut out = Array::default();
                while let Some(item) = seq.next_element::<T>()? {
                    out.inner = out.inner.saturating_add(item.objects_inside());
                    if item.keep() {
                        out.kept.push((out.len, item));
                    }
                    out.len += 1;
                }
                Ok(out)
            }
        }
        d.deserialize_seq(Walk(std::marker::PhantomData))
    }
}

#[derive(Deserialize, Default)]
struct Mesh {
    #[serde(default)]
    primitives: Array<IgnoredAny>,
}

impl Summary for Mesh {
    fn objects_inside(&self) -> usize {
        self.primitives.len
    }
}

#[derive(Deserialize, Default)]
struct Target {
    node: Option<IgnoredAny>,
}

#[derive(Deserialize, Default)]
struct Channel {
    #[serde(default)]
    target: Target,
}

impl Summary for Channel {
    fn keep(&self) -> bool {
        self.target.node.is_none()
    }
}

#[derive(Deserialize, Default)]
struct Animation {
    #[serde(default)]
    channels: Array<Channel>,
    #[serde(default)]
    samplers: Array<IgnoredAny>,
}

impl Summary for Animation {
    fn objects_inside(&self) -> usize {
        self.channels.len.saturating_add(self.samplers.len)
    }
    fn keep(&self) -> bool {
        !self.channels.kept.is_empty()
    }
}

#[derive(Deserialize, Default)]
struct Asset {
    version: Option<String>,
    #[serde(rename = "minVersion")]
    min_version: Option<String>,
}

/// What the census found.
#[derive(Deserialize, Default)]
#[serde(default)]
pub(super) struct Census {
    asset: Asset,
    accessors: Array<IgnoredAny>,
    animations: Array<Animation>,
    buffers: Array<IgnoredAny>,
    #[serde(rename = "bufferViews")]
    buffer_views: Array<IgnoredAny>,
    cameras: Array<IgnoredAny>,
    images: Array<IgnoredAny>,
    materials: Array<IgnoredAny>,
    meshes: Array<Mesh>,
    nodes: Array<IgnoredAny>,
    samplers: Array<IgnoredAny>,
    scenes: Array<IgnoredAny>,
    skins: Array<IgnoredAny>,
    textures: Array<IgnoredAny>,
}

impl Census {
    /// Counts the objects of `json` without building them.
    pub(super) fn of(json: &[u8]) -> Result<Census, String> {
        serde_json::from_slice(json).map_err(|e| format!("the glTF JSON does not parse: {e}"))
    }

    /// Every (animation, channel) whose target names no node.
    pub(super) fn untargeted(&self) -> Vec<(usize, usize)> {
        self.animations
            .kept
            .iter()
            .flat_map(|(a, anim)| anim.channels.kept.iter().map(move |(c, _)| (*a, *c)))
            .collect()
    }

    /// Refuses a file with more objects than umbra reads, naming the most numerous kind.
    pub(super) fn check_size(&self) -> Result<(), String> {
        let kinds = [
            ("accessors", self.accessors.len),
            ("animations", self.animations.len),
            ("animation channels and samplers", self.animations.inner),
            ("buffers", self.buffers.len),
            ("buffer views", self.buffer_views.len),
            ("cameras", self.cameras.len),
            ("images", self.images.len),
            ("materials", self.materials.len),
            ("meshes", self.meshes.len),
            ("mesh primitives", self.meshes.inner),
            ("nodes", self.nodes.len),
            ("samplers", self.samplers.len),
            ("scenes", self.scenes.len),
            ("skins", self.skins.len),
            ("textures", self.textures.len),
        ];
        let total = kinds.iter().fold(0usize, |a, (_, n)| a.saturating_add(*n));
        if total <= MAX_OBJECTS {
            return Ok(());
        }
        let (kind, most) = kinds.iter().max_by_key(|(_, n)| *n).copied().unwrap_or(("objects", total));
        Err(format!(
            "it holds {total} objects ({most} of them {kind}); umbra reads files of at most {MAX_OBJECTS} \
             objects (nodes, meshes and their primitives, accessors, materials and the rest together)"
        ))
    }

    /// Refuses a file that is not glTF 2.0, by its `asset.version` and `asset.minVersion`.
    pub(super) fn check_version(&self) -> Result<(), String> {
        if let Some(v) = &self.asset.version {
            match version(v) {
                Some((2, _)) => {}
                Some(_) => return Err(format!("asset.version is \"{v}\"; umbra reads glTF 2.0 (version 2.x)")),
                None => return Err(format!("asset.version \"{v}\" is not a version like \"2.0\"")),
            }
        }
        if let Some(v) = &self.asset.min_version {
            match version(v) {
                Some(found) if found <= (2, 0) => {}
                Some(_) => {
                    return Err(format!(
                        "asset.minVersion is \"{v}\": the file needs a glTF newer than 2.0, which umbra reads"
                    ));
                }
                None => return Err(format!("asset.minVersion \"{v}\" is not a version like \"2.0\"")),
            }
        }
        Ok(())
    }
}

/// "2.0" as (2, 0).
fn version(s: &str) -> Option<(u32, u32)> {
    let (major, minor) = s.split_once('.')?;
    Some((major.parse().ok()?, minor.parse().ok()?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn objects_are_counted_and_untargeted_channels_found() {
        let json = br#"{ "asset": { "version": "2.0" }, "nodes": [{}, {}, {"mesh": 0}],
            "meshes": [{ "primitives": [{}, {}] }, { "primitives": [{}] }],
            "animations": [{ "channels": [{ "target": { "node": 1 } }] },
                           { "channels": [{ "target": { "node": 0 } }, { "target": { "path": "pointer" } }] }],
            "extras": 1 }"#;
        let census = Census::of(json).unwrap();
        assert_eq!((census.nodes.len, census.meshes.len, census.meshes.inner), (3, 2, 3));
        assert_eq!(census.untargeted(), vec![(1, 1)]);
        census.check_size().unwrap();
        census.check_version().unwrap();
    }

    #[test]
    fn too_many_objects_are_refused_by_their_kind() {
        let json = format!("{{ \"nodes\": [{}{{}}] }}", "{},".repeat(MAX_OBJECTS));
        let err = Census::of(json.as_bytes()).unwrap().check_size().unwrap_err();
        assert!(err.contains(&format!("{} of them nodes", MAX_OBJECTS + 1)), "{err}");
    }

    #[test]
    fn versions_other_than_two_are_refused() {
        let check = |asset: &str| Census::of(format!("{{ \"asset\": {asset} }}").as_bytes()).unwrap().check_version();
        assert!(check(r#"{ "version": "2.0" }"#).is_ok());
        assert!(check(r#"{ "version": "2.1", "minVersion": "2.0" }"#).is_ok());
        assert!(check(r#"{ "version": "1.0" }"#).unwrap_err().contains("asset.version is \"1.0\""));
        assert!(check(r#"{ "version": "3.0" }"#).unwrap_err().contains("umbra reads glTF 2.0"));
        assert!(check(r#"{ "version": "2.0", "minVersion": "2.1" }"#).unwrap_err().contains("minVersion"));
        assert!(check(r#"{ "version": "two" }"#).unwrap_err().contains("not a version"));
    }
}
