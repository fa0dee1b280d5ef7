//! Materials: base colour, alpha mode, sides, and the base-colour texture, each image decoded once
//! and shared by every texture and primitive that uses it. An image that cannot be read is a
//! warning, and its materials keep their base-colour factor alone.

use super::accessor::Data;
use super::budget::Budget;
use super::container::{Source, read_uri};
use crate::assets::texture::{
    DecodeError, Filter, ImageData, MAX_KEPT_SIZE, Sampling, TextureData, UvTransform, Wrap, decode_image,
    mipmapped_bytes,
};
use crate::components::{AlphaMode, Material};
use glam::{Vec2, Vec3};
use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// The texture coordinates a texture reads: a set, moved by the texture's transform if it has one.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct TexCoords {
    /// `TEXCOORD_n`'s n (the transform's own `texCoord` where it gives one).
    pub(super) set: u32,
    /// KHR_texture_transform's offset, rotation and scale.
    pub(super) transform: Option<UvTransform>,
}

/// What `info` reads, with its KHR_texture_transform; a transform that is not finite is refused.
fn tex_coords(info: &gltf::texture::Info<'_>) -> Result<TexCoords, String> {
    let Some(t) = info.texture_transform() else { return Ok(TexCoords { set: info.tex_coord(), transform: None }) };
    let transform =
        UvTransform { offset: Vec2::from(t.offset()), rotation: t.rotation(), scale: Vec2::from(t.scale()) };
    if !transform.is_finite() {
        return Err(format!(
            "texture {}: its KHR_texture_transform holds a number that is not finite",
            info.texture().index()
        ));
    }
    Ok(TexCoords { set: t.tex_coord().unwrap_or(info.tex_coord()), transform: Some(transform) })
}

/// The materials of one file, with the textures and images read so far.
pub(super) struct Materials<'s, 'd> {
    doc: &'s gltf::Document,
    dir: Option<&'s Path>,
    input: &'s Budget,
    data: &'s Data<'d>,
    textures: HashMap<usize, Option<Arc<TextureData>>>,
    images: HashMap<usize, Option<Arc<ImageData>>>,
    /// The first hard error (the budget ran out), reported when the material is asked for.
    failed: Option<String>,
}

impl<'s, 'd> Materials<'s, 'd> {
    /// The materials of `src`; warns once of what umbra does not draw.
    pub(super) fn new(src: &'s Source<'_>, input: &'s Budget, data: &'s Data<'d>, warnings: &mut Vec<String>) -> Self {
        let doc = &src.doc;
        let ignored = doc.materials().any(|m| {
            m.normal_texture().is_some()
                || m.occlusion_texture().is_some()
                || m.emissive_texture().is_some()
                || m.pbr_metallic_roughness().metallic_roughness_texture().is_some()
        });
        if ignored {
            warnings.push(
                "umbra draws base-colour textures only; its normal, occlusion, emissive and metallic-roughness \
                 textures are ignored"
                    .into(),
            );
        }
        Materials { doc, dir: src.dir, input, data, textures: HashMap::new(), images: HashMap::new(), failed: None }
    }

    /// Material `m` as umbra draws it, its base-colour texture, and the texture coordinates that
    /// texture reads. Fails when an image would exceed the model's budget or the texture's
    /// transform is not finite.
    pub(super) fn get(
        &mut self,
        m: &gltf::Material<'_>,
        warnings: &mut Vec<String>,
    ) -> Result<(Material, Option<Arc<TextureData>>, TexCoords), String> {
        let pbr = m.pbr_metallic_roughness();
        let c = pbr.base_color_factor();
        let alpha_mode = match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask { cutoff: m.alpha_cutoff().unwrap_or(0.5).max(0.0) },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        let material = Material {
            base_color: Vec3::new(c[0], c[1], c[2]),
            opacity: c[3],
            alpha_mode,
            double_sided: m.double_sided(),
            ..Material::color(1.0, 1.0, 1.0)
        };
        let (texture, coords) = match pbr.base_color_texture() {
            Some(info) => (self.texture(&info.texture(), warnings), tex_coords(&info)?),
            None => (None, TexCoords::default()),
        };
        match self.failed.take() {
            Some(e) => Err(e),
            None => Ok((material, texture, coords)),
        }
    }

    /// Texture `t` (its image and sampler), read the first time it is asked for.
    fn texture(&mut self, t: &gltf::Texture<'_>, warnings: &mut Vec<String>) -> Option<Arc<TextureData>> {
        if let Some(done) = self.textures.get(&t.index()) {
            return done.clone();
        }
        let image = self.image(t.source().index(), warnings);
        let texture = image.map(|image| Arc::new(TextureData { image, sampling: sampling(&t.sampler()) }));
        self.textures.insert(t.index(), texture.clone());
        texture
    }

    /// Image `i` decoded, or `None` with a warning naming it and why.
    fn image(&mut self, i: usize, warnings: &mut Vec<String>) -> Option<Arc<ImageData>> {
        if let Some(done) = self.images.get(&i) {
            return done.clone();
        }
        let json = self.doc.as_json().images.get(i)?;
        let label = match (&json.name, &json.uri) {
            (Some(name), _) => format!("image {i} ({name})"),
            (None, Some(uri)) if !uri.starts_with("data:") => format!("image {i} ({uri})"),
            _ => format!("image {i}"),
        };
        let bytes: Result<Cow<'_, [u8]>, String> = match (&json.buffer_view, &json.uri) {
            (Some(v), _) => match self.doc.views().nth(v.value()) {
                Some(view) => self.data.view(&view).map(Cow::Borrowed),
                None => Err(format!("buffer view {} does not exist", v.value())),
            },
            (None, Some(uri)) => read_uri(uri, self.dir, self.input).map(Cow::Owned),
            (None, None) => Err("it has neither a buffer view nor a URI".into()),
        };
        let decoded = bytes.map_err(DecodeError::Broken).and_then(|b| {
            let budget = &self.data.budget;
            decode_image(&label, &b, |n| budget.spend(n))
        });
        let image = match decoded {
            Ok(image) => {
                if let Some((w, h)) = image.shrunk_from {
                    warnings.push(format!(
                        "{label} is {w}x{h}; it is drawn at {}x{} (its first mipmap within {MAX_KEPT_SIZE}², the \
                         largest umbra keeps: the whole image would take {} MB, and as much again on a software \
                         adapter)",
                        image.width,
                        image.height,
                        mipmapped_bytes(w, h) / 1_000_000
                    ));
                }
                Some(Arc::new(image))
            }
            Err(DecodeError::Broken(why)) => {
                warnings.push(format!(
                    "{label} cannot be read ({why}); the materials that use it keep their base colour alone"
                ));
                None
            }
            Err(DecodeError::TooLarge(why)) => {
                self.failed = Some(format!("{label}: {why}"));
                None
            }
        };
        self.images.insert(i, image.clone());
        image
    }
}

/// A glTF sampler as umbra samples it (no sampler: repeat, with smooth mipmapped filtering).
fn sampling(s: &gltf::texture::Sampler<'_>) -> Sampling {
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let mag = match s.mag_filter() {
        Some(MagFilter::Nearest) => Filter::Nearest,
        _ => Filter::Linear,
    };
    let (min, mipmap) = match s.min_filter() {
        None | Some(MinFilter::LinearMipmapLinear) => (Filter::Linear, Some(Filter::Linear)),
        Some(MinFilter::Nearest) => (Filter::Nearest, None),
        Some(MinFilter::Linear) => (Filter::Linear, None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, Some(Filter::Nearest)),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, Some(Filter::Nearest)),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, Some(Filter::Linear)),
    };
    let wrap = |w| match w {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
    };
    Sampling { mag, min, mipmap, wrap: [wrap(s.wrap_s()), wrap(s.wrap_t())] }
}
