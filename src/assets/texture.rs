//! Base-colour textures in CPU memory: decoded images with their mipmaps, how they are sampled,
//! the library that owns them, and the alpha lookup the ray-traced truth makes at a ray's hit.

use bevy_ecs::prelude::*;
use glam::Vec2;
use std::sync::{Arc, OnceLock};

/// Widest and tallest image umbra decodes.
pub const MAX_TEXTURE_SIZE: u32 = 8192;

/// Widest and tallest image umbra keeps: a larger one is kept from its first mipmap that fits. An
/// 8192² image with its mipmaps is 358 MB, and a software adapter's texture holds as much again
/// in the same process (`tests/texture_memory.rs`); at 4096² each is a quarter of that.
pub const MAX_KEPT_SIZE: u32 = 4096;

/// An RGBA image with its mipmaps: colour in sRGB, alpha linear, 4 bytes a texel, rows top first.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageData {
    /// Where it came from, for messages.
    pub name: String,
    /// Width of level 0 in texels.
    pub width: u32,
    /// Height of level 0 in texels.
    pub height: u32,
    /// Level 0 (the image itself, or its first mipmap within [`MAX_KEPT_SIZE`]), then each level
    /// half the size of the one before, down to 1x1.
    pub levels: Vec<Vec<u8>>,
    /// The size it was decoded at, where that was larger than umbra keeps.
    pub shrunk_from: Option<(u32, u32)>,
}

/// How texels are blended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Filter {
    /// The nearest texel.
    Nearest,
    /// A weighted blend of the nearest four.
    Linear,
}

/// What happens outside 0..1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Wrap {
    /// The image repeats.
    Repeat,
    /// The image repeats, every other copy mirrored.
    MirroredRepeat,
    /// The edge texels stretch on.
    ClampToEdge,
}

/// A glTF sampler: filters and wrapping.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Sampling {
    /// Filter when a texel covers more than a pixel.
    pub mag: Filter,
    /// Filter when a pixel covers more than a texel.
    pub min: Filter,
    /// Filter between mipmap levels; none uses level 0 only.
    pub mipmap: Option<Filter>,
    /// Wrapping across (u) and down (v).
    pub wrap: [Wrap; 2],
}

impl Default for Sampling {
    /// What glTF asks for without a sampler: repeat, and smooth filtering with mipmaps.
    fn default() -> Self {
        Sampling { mag: Filter::Linear, min: Filter::Linear, mipmap: Some(Filter::Linear), wrap: [Wrap::Repeat; 2] }
    }
}

/// Where a texture sits on its surface (glTF's KHR_texture_transform): the texture coordinates
/// scaled, then turned by `rotation` radians, then offset, as the extension's own matrix
/// (translation × rotation × scale, the rotation's columns (cos, sin) and (−sin, cos)) does. Applied
/// to a primitive's coordinates once, when it is loaded, so the picture and the casters' alpha
/// read the same place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Added last.
    pub offset: Vec2,
    /// Radians, turning u towards v.
    pub rotation: f32,
    /// Applied first.
    pub scale: Vec2,
}

impl UvTransform {
    /// `uv` where the texture is read once transformed.
    #[must_use]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let (sin, cos) = self.rotation.sin_cos();
        let s = uv * self.scale;
        Vec2::new(cos * s.x - sin * s.y, sin * s.x + cos * s.y) + self.offset
    }

    /// Every number is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.offset.is_finite() && self.rotation.is_finite() && self.scale.is_finite()
    }
}

/// A base-colour texture: an image (shared by every texture that uses it) and its sampler.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureData {
    /// The image.
    pub image: Arc<ImageData>,
    /// How it is sampled.
    pub sampling: Sampling,
}

/// All textures of the scene; a material's [`crate::components::Texture`] is an index into it.
#[derive(Resource, Default, Debug)]
pub struct TextureLibrary {
    textures: Vec<Arc<TextureData>>,
}

impl TextureLibrary {
    /// Adds a texture (once: adding the same one again gives the same index).
    pub fn add(&mut self, texture: Arc<TextureData>) -> crate::components::Texture {
        let i = match self.textures.iter().position(|t| Arc::ptr_eq(t, &texture)) {
            Some(i) => i,
            None => {
                self.textures.push(texture);
                self.textures.len() - 1
            }
        };
        crate::components::Texture(i)
    }

    /// The texture an index refers to, if it exists.
    pub fn get(&self, texture: crate::components::Texture) -> Option<&Arc<TextureData>> {
        self.textures.get(texture.0)
    }

    /// All textures in index order.
    pub fn all(&self) -> &[Arc<TextureData>] {
        &self.textures
    }
}

/// Bytes of an image of this size with all its mipmaps (a third more than level 0).
#[must_use]
pub fn mipmapped_bytes(width: u32, height: u32) -> u64 {
    (width as u64 * height as u64 * 4).saturating_mul(4) / 3 + 4
}

/// Decodes a PNG or JPEG image of at most [`MAX_TEXTURE_SIZE`] on a side whose decoded size with
/// mipmaps `pay` accepts (it is told the bytes before anything is decoded).
pub fn decode_image(
    name: &str,
    bytes: &[u8],
    pay: impl FnOnce(u64) -> Result<(), String>,
) -> Result<ImageData, DecodeError> {
    let header = super::decode::header(bytes, MAX_TEXTURE_SIZE).map_err(DecodeError::Broken)?;
    let (width, height) = header.size();
    pay(mipmapped_bytes(width, height)).map_err(DecodeError::TooLarge)?;
    let rgba = header.decode().map_err(DecodeError::Broken)?;
    Ok(ImageData::new(name, width, height, rgba))
}

/// Why an image could not be decoded.
#[derive(Clone, Debug, PartialEq)]
pub enum DecodeError {
    /// It is not a PNG or JPEG umbra can read (the model loads without it).
    Broken(String),
    /// It would exceed the model's budget (the model is refused).
    TooLarge(String),
}

impl ImageData {
    /// An image from RGBA bytes (sRGB colour, linear alpha), with its mipmaps made; one larger
    /// than [`MAX_KEPT_SIZE`] keeps its first mipmap that fits, and the levels after it.
    #[must_use]
    pub fn new(name: &str, width: u32, height: u32, rgba: Vec<u8>) -> ImageData {
        let decoded = (width.max(1), height.max(1));
        let mut rgba = rgba;
        rgba.resize(decoded.0 as usize * decoded.1 as usize * 4, 255);
        let mut levels = vec![rgba];
        let (mut w, mut h) = decoded;
        let mut kept = decoded;
        while w > 1 || h > 1 {
            let (next, nw, nh) = half(levels.last().map_or(&[][..], |l| l), w, h);
            // A level larger than umbra keeps gives way to the one made from it.
            if w.max(h) > MAX_KEPT_SIZE {
                levels.clear();
                kept = (nw, nh);
            }
            levels.push(next);
            (w, h) = (nw, nh);
        }
        let shrunk_from = (kept != decoded).then_some(decoded);
        ImageData { name: name.to_string(), width: kept.0, height: kept.1, levels, shrunk_from }
    }

    /// The width and height of mipmap level `level`.
    #[must_use]
    pub fn level_size(&self, level: usize) -> (u32, u32) {
        ((self.width >> level).max(1), (self.height >> level).max(1))
    }

    /// Alpha (0..1) of texel (x, y) of level 0.
    fn alpha_at(&self, x: u32, y: u32) -> f32 {
        let i = (y as usize * self.width as usize + x as usize) * 4 + 3;
        self.levels[0].get(i).map_or(1.0, |&a| a as f32 / 255.0)
    }
}

impl TextureData {
    /// Alpha at `uv` from level 0 with the sampler's magnification filter and wrapping: what a
    /// ray that hits the surface there sees, for the ray-traced truth.
    #[must_use]
    pub fn alpha(&self, uv: Vec2) -> f32 {
        let image = &self.image;
        let (w, h) = (image.width, image.height);
        if !uv.is_finite() {
            return image.alpha_at(0, 0);
        }
        let at = uv * Vec2::new(w as f32, h as f32);
        let [wrap_u, wrap_v] = self.sampling.wrap;
        match self.sampling.mag {
            Filter::Nearest => image.alpha_at(wrap(at.x.floor(), w, wrap_u), wrap(at.y.floor(), h, wrap_v)),
            Filter::Linear => {
                let at = at - 0.5;
                let (base, f) = (at.floor(), at - at.floor());
                let x = [wrap(base.x, w, wrap_u), wrap(base.x + 1.0, w, wrap_u)];
                let y = [wrap(base.y, h, wrap_v), wrap(base.y + 1.0, h, wrap_v)];
                let row = |y| image.alpha_at(x[0], y) * (1.0 - f.x) + image.alpha_at(x[1], y) * f.x;
                row(y[0]) * (1.0 - f.y) + row(y[1]) * f.y
            }
        }
    }
}

/// Texel column (or row) `i` of `size` wrapped by `mode`.
fn wrap(i: f32, size: u32, mode: Wrap) -> u32 {
    let n = size.max(1) as i64;
    let i = i.clamp(-1e9, 1e9) as i64;
    let k = match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            let k = i.rem_euclid(2 * n);
            if k < n { k } else { 2 * n - 1 - k }
        }
    };
    k as u32
}

/// sRGB byte to linear, by table.
fn to_linear(c: u8) -> f32 {
    static TABLE: OnceLock<[f32; 256]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|i| {
            let c = i as f32 / 255.0;
            if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
        })
    })[c as usize]
}

/// Linear 0..1 to an sRGB byte.
fn to_srgb(l: f32) -> u8 {
    let l = l.clamp(0.0, 1.0);
    let c = if l <= 0.003_130_8 { l * 12.92 } else { 1.055 * l.powf(1.0 / 2.4) - 0.055 };
    (c * 255.0 + 0.5) as u8
}

/// The next mipmap level of a `w` x `h` level: each texel the mean of (up to) four, colour
/// averaged in linear light so that mipmaps do not darken.
fn half(level: &[u8], w: u32, h: u32) -> (Vec<u8>, u32, u32) {
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let mut out = Vec::with_capacity(nw as usize * nh as usize * 4);
    let texel = |x: u32, y: u32| {
        let i = ((y.min(h - 1) * w + x.min(w - 1)) * 4) as usize;
        level.get(i..i + 4).map_or([0; 4], |t| [t[0], t[1], t[2], t[3]])
    };
    for y in 0..nh {
        for x in 0..nw {
            let four =
                [texel(2 * x, 2 * y), texel(2 * x + 1, 2 * y), texel(2 * x, 2 * y + 1), texel(2 * x + 1, 2 * y + 1)];
            for c in 0..3 {
                out.push(to_srgb(four.iter().map(|t| to_linear(t[c])).sum::<f32>() / 4.0));
            }
            out.push(((four.iter().map(|t| t[3] as u32).sum::<u32>() + 2) / 4) as u8);
        }
    }
    (out, nw, nh)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker(n: u32) -> ImageData {
        let rgba =
            (0..n * n).flat_map(|i| if (i % n + i / n).is_multiple_of(2) { [255, 0, 0, 255] } else { [0, 0, 255, 0] });
        ImageData::new("checker", n, n, rgba.collect())
    }

    #[test]
    fn an_image_wider_than_umbra_keeps_keeps_its_first_mipmap_that_fits() {
        let wide = MAX_KEPT_SIZE * 2;
        let rgba: Vec<u8> = (0..wide * 2).flat_map(|i| [(i % 256) as u8, 0, 0, 255]).collect();
        let (first, ..) = half(&rgba, wide, 2);
        let image = ImageData::new("wide", wide, 2, rgba);
        assert_eq!((image.width, image.height, image.shrunk_from), (MAX_KEPT_SIZE, 1, Some((wide, 2))));
        assert_eq!(image.levels[0], first, "level 0 is the first mipmap");
        assert_eq!(image.levels.len(), MAX_KEPT_SIZE.ilog2() as usize + 1, "down to 1x1");
        let fits = ImageData::new("fits", MAX_KEPT_SIZE, 1, vec![9; MAX_KEPT_SIZE as usize * 4]);
        assert_eq!((fits.width, fits.shrunk_from), (MAX_KEPT_SIZE, None));
    }

    #[test]
    fn mipmaps_halve_down_to_one_texel_and_average_in_linear_light() {
        let image = checker(8);
        let sizes: Vec<usize> = image.levels.iter().map(Vec::len).collect();
        assert_eq!(sizes, vec![256, 64, 16, 4]);
        // Half red, half blue averaged in linear light: 0.5 linear is 188 in sRGB, not 128.
        assert_eq!(&image.levels[3][..], &[188, 0, 188, 128]);
        let odd = ImageData::new("odd", 3, 1, vec![255; 12]);
        assert_eq!(odd.levels.len(), 2);
        assert_eq!(odd.level_size(1), (1, 1));
    }

    #[test]
    fn alpha_follows_the_sampler() {
        let nearest = Sampling { mag: Filter::Nearest, ..Sampling::default() };
        let t = TextureData { image: Arc::new(checker(4)), sampling: nearest };
        assert_eq!(t.alpha(Vec2::new(0.1, 0.1)), 1.0);
        assert_eq!(t.alpha(Vec2::new(0.3, 0.1)), 0.0);
        assert_eq!(t.alpha(Vec2::new(1.1, 0.1)), 1.0, "repeats");
        let clamped = TextureData { sampling: Sampling { wrap: [Wrap::ClampToEdge; 2], ..nearest }, ..t.clone() };
        assert_eq!(clamped.alpha(Vec2::new(1.1, 0.1)), 0.0, "the last column stretches on");
        let mirrored = TextureData { sampling: Sampling { wrap: [Wrap::MirroredRepeat; 2], ..nearest }, ..t.clone() };
        assert_eq!(mirrored.alpha(Vec2::new(-0.1, 0.1)), 1.0);
        let linear = TextureData { sampling: Sampling::default(), ..t.clone() };
        assert!((linear.alpha(Vec2::new(0.25, 0.125)) - 0.5).abs() < 1e-6, "between two texels");
        assert_eq!(t.alpha(Vec2::NAN), 1.0, "a NaN coordinate reads a texel, never panics");
    }

    #[test]
    fn decoding_refuses_what_is_not_png_or_jpeg_and_asks_before_allocating() {
        assert!(matches!(decode_image("x", b"GIF89a....", |_| Ok(())), Err(DecodeError::Broken(_))));
        let mut png = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut png, 2, 2);
            encoder.set_color(png::ColorType::Rgba);
            encoder.write_header().unwrap().write_image_data(&[9; 16]).unwrap();
        }
        let image = decode_image("ok", &png, |_| Ok(())).unwrap();
        assert_eq!((image.width, image.height, image.levels[0].clone()), (2, 2, vec![9; 16]));
        let refused = decode_image("big", &png, |n| Err(format!("{n} bytes")));
        assert_eq!(refused, Err(DecodeError::TooLarge(format!("{} bytes", mipmapped_bytes(2, 2)))));
        assert!(matches!(decode_image("cut", &png[..png.len() / 2], |_| Ok(())), Err(DecodeError::Broken(_))));
    }

    #[test]
    fn a_texture_transform_scales_then_turns_then_offsets() {
        let t = |offset: [f32; 2], rotation: f32, scale: [f32; 2]| UvTransform {
            offset: Vec2::from(offset),
            rotation,
            scale: Vec2::from(scale),
        };
        let uv = Vec2::new(0.25, 0.5);
        assert_eq!(t([0.0, 0.0], 0.0, [1.0, 1.0]).apply(uv), uv);
        assert_eq!(t([0.5, -1.0], 0.0, [2.0, 4.0]).apply(uv), Vec2::new(1.0, 1.0));
        // A quarter turn takes u to v.
        let turned = t([0.0, 0.0], std::f32::consts::FRAC_PI_2, [1.0, 1.0]).apply(Vec2::X);
        assert!((turned - Vec2::Y).length() < 1e-6, "{turned}");
        // Scale comes before the turn, the offset after it.
        let all = t([0.1, 0.2], std::f32::consts::FRAC_PI_2, [2.0, 1.0]).apply(Vec2::X);
        assert!((all - Vec2::new(0.1, 2.2)).length() < 1e-6, "{all}");
        assert!(!t([f32::NAN, 0.0], 0.0, [1.0, 1.0]).is_finite());
        assert!(!t([0.0, 0.0], f32::INFINITY, [1.0, 1.0]).is_finite());
        assert!(t([1e30, 0.0], 0.0, [0.0, 0.0]).is_finite());
    }
}
