//! The structs the shaders read, field for field, and the constants Rust and WGSL share. Each
//! struct lists its fields and their offsets, which a test compares with the WGSL declaration of
//! the same name (reflected by naga), so neither side can change alone.

use crate::components::{Cookie, ShadowMethod};
use glam::{Mat4, Vec4};

/// Declares a `#[repr(C)]` plain-old-data struct with a `FIELDS` table of its field names and
/// byte offsets.
macro_rules! gpu_struct {
    ($(#[$meta:meta])* pub struct $name:ident { $($(#[$fmeta:meta])* $vis:vis $field:ident : $ty:ty),* $(,)? }) => {
        $(#[$meta])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name { $($(#[$fmeta])* $vis $field: $ty),* }

        impl $name {
            /// Each field's name and byte offset, as the WGSL struct of the same name must have them.
            pub const FIELDS: &'static [(&'static str, usize)] =
                &[$((stringify!($field), std::mem::offset_of!($name, $field))),*];
        }
    };
}

gpu_struct! {
    /// One object: its matrices and material (`Object` in common.wgsl, bind group 1).
    pub struct Object {
        /// Local to world.
        pub world_from_local: Mat4,
        /// Inverse-transpose of `world_from_local`, for normals.
        pub normal_from_local: Mat4,
        /// Linear RGBA base colour factor.
        pub base_color: Vec4,
        /// Strength of the specular highlight.
        pub specular: f32,
        /// Phong exponent.
        pub shininess: f32,
        /// Alpha below which a masked surface (and, in shadow maps and the measuring view, a
        /// blended one) is cut away; 0 for opaque.
        pub alpha_cutoff: f32,
        /// 1 if the surface takes shadows.
        pub receives_shadows: u32,
        /// The object's first matrix in the joint palette (skinned objects only).
        pub first_joint: u32,
        /// 1 on the ground when lights draw planar shadows onto it in place of their maps.
        pub planar_receiver: u32,
        /// 1 on the ground when it shows its checker.
        pub ground_grid: u32,
        pub _pad2: u32,
    }
}

gpu_struct! {
    /// The camera and the frame-wide shadow settings (`Frame` in frame.wgsl).
    pub struct Frame {
        /// World to the camera's clip space.
        pub clip_from_world: Mat4,
        /// Where the camera is.
        pub camera_position: [f32; 3],
        /// Beyond this view depth suns cast no shadow.
        pub shadow_distance: f32,
        /// The camera's unit forward axis.
        pub camera_forward: [f32; 3],
        /// View depth where sun shadows start to fade out.
        pub fade_start: f32,
        /// Ambient light level.
        pub ambient: f32,
        /// How dark a full shadow is.
        pub shadow_strength: f32,
        /// 1 when shadows are looked up at all.
        pub shadows_on: u32,
        /// 1 to tint each cascade.
        pub cascade_debug: u32,
        /// Lights in the light array.
        pub light_count: u32,
        /// The first of the lights the measuring view reports.
        pub first_measured: u32,
        /// Width of the probe grid in pixels.
        pub probe_width: u32,
        /// Height of the probe grid in pixels.
        pub probe_height: u32,
        /// 1 when the seams of shadow cubes are handled.
        pub cube_seams: u32,
        /// Depth bias in metres along the light, for every light.
        pub depth_bias_metres: f32,
        /// 1 when PCSS searches for blockers (else it filters with a fixed kernel).
        pub pcss_search: u32,
        /// Bands of toon shading (0: Phong).
        pub toon_bands: u32,
        /// 1 + the index of the light whose texel density is shown (0: the shading).
        pub texel_view: u32,
        /// View depth where the first slice of light clusters starts.
        pub cluster_near: f32,
        /// View depth where the last slice of light clusters ends.
        pub cluster_far: f32,
        /// 1 when lookups keep their taps inside their own tile of the atlas.
        pub atlas_guard: u32,
        /// Steps of a contact-shadow march (0: none this frame).
        pub contact_steps: u32,
        /// How far a contact-shadow march goes towards the light, in metres.
        pub contact_length: f32,
        /// How thick a surface the camera sees is taken to be, in metres.
        pub contact_thickness: f32,
        /// The camera's near plane distance.
        pub camera_near: f32,
        /// The camera's far plane distance.
        pub camera_far: f32,
        /// Radians a pixel of the picture spans (at its middle).
        pub pixel_angle: f32,
        /// 1 when a pixel whose virtual page is missing reads a coarser one (else it is lit).
        pub page_fallback: u32,
        pub _pad2: u32,
    }
}

gpu_struct! {
    /// One light (`GpuLight` in frame.wgsl).
    pub struct GpuLight {
        /// Colour times intensity.
        pub color: [f32; 3],
        /// [`LIGHT_SUN`], [`LIGHT_SPOT`] or [`LIGHT_POINT`].
        pub kind: u32,
        /// Where it is (spot and point lights).
        pub position: [f32; 3],
        /// Where its light fades to nothing (spot and point lights).
        pub range: f32,
        /// Unit direction it travels (suns) or shines (spots).
        pub direction: [f32; 3],
        /// Cosine of a spot's outer half angle.
        pub cos_outer: f32,
        /// Cosine of a spot's inner half angle.
        pub cos_inner: f32,
        /// Its first layer in the shadow-map array.
        pub first_layer: u32,
        /// Its layers (0: no shadow).
        pub layer_count: u32,
        /// Cookie layer, or -1 for none.
        pub cookie: i32,
        /// Constant bias in texels.
        pub bias_constant: f32,
        /// Slope bias in texels.
        pub bias_slope: f32,
        /// Normal-offset bias in texels.
        pub bias_normal: f32,
        /// `METHOD_*`: how its maps are sampled.
        pub method: u32,
        /// [`SHAPE_CASCADES`], [`SHAPE_SINGLE`] or [`SHAPE_CUBE`].
        pub shape: u32,
        /// Its size for soft shadows: tan of a sun's angular radius, or a spot or point light's
        /// radius in metres.
        pub size: f32,
        /// Multiplicative depth offset: the share of the distance to the light the receiver is
        /// pulled towards it.
        pub bias_scale: f32,
        /// 1 when it draws planar shadows onto the ground in place of its maps there.
        pub planar_ground: u32,
        /// 1 when its filters compare with the receiver's plane.
        pub receiver_plane: u32,
        /// 1 when its shadow test adds a contact-shadow march.
        pub contact: u32,
        /// 1 when a paged light's shadow ends at the shadow distance, fading out before it (a
        /// sun's clipmap); 0 where it reaches as far as its light (a spot's pages).
        pub page_fades: u32,
        /// A paged light's faces: 6 for a point light's cube (each face's `page_from_world` is
        /// in its page table, after the entries), 1 for the others.
        pub page_faces: u32,
        /// World to the cookie's clip space (spots with a cookie).
        pub cookie_from_world: Mat4,
        /// A paged light's world to its level-0 page units across the light (x and y; a page of
        /// level l is `2^l` of them a side).
        pub page_from_world: Mat4,
        /// A paged light's levels (0: it is not paged).
        pub page_levels: u32,
        /// Its page table's first word in the page-table texture: each level's header, a cube's
        /// six face matrices, then each level's entries (see [`super::page_table`]).
        pub page_word: u32,
        /// log2 of its level 0's texel, in metres.
        pub page_finest_log2: f32,
        /// Octaves coarser than its footprint a pixel's page is chosen.
        pub page_bias: f32,
        /// How near to a paged light its casters come along its axis, in metres: PCSS searches
        /// no farther than a blocker that near throws its penumbra (0: as far as one at the
        /// map's near plane; see `nearest_caster` in extract.rs).
        pub nearest_caster: f32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }
}

gpu_struct! {
    /// One layer of the shadow-map array (`GpuLayer` in moments.wgsl): the main pass reads them
    /// all, the shadow pass the one it draws.
    pub struct GpuLayer {
        /// World to the layer's clip space.
        pub clip_from_world: Mat4,
        /// World size of one texel at the light.
        pub texel_base: f32,
        /// World size of one texel grows by this per metre from the light.
        pub texel_per_metre: f32,
        /// View depth where this cascade ends (infinite for other layers).
        pub far: f32,
        /// Band before `far` where this cascade blends into the next.
        pub blend: f32,
        /// How its projection turns distance from the light into depth
        /// ([`crate::shadow::depth_terms`]).
        pub depth_terms: [f32; 2],
        /// `METHOD_*` of its light.
        pub method: u32,
        /// 1 for a perspective projection (spots and cube faces).
        pub perspective: u32,
        /// EVSM's positive and negative exponents.
        pub warp: [f32; 2],
        /// A moment method's stabiliser (see `moment_bias` in `render/moments.rs`).
        pub moment_bias: f32,
        /// Light-bleeding reduction of a moment method.
        pub bleed: f32,
        /// Where its light is (spots and points), from which R16F radial measures distance.
        pub origin: [f32; 3],
        /// The atlas page its tile is on.
        pub page: u32,
        /// Its tile: the corner's place on the page and the side's share of it (both as
        /// texture coordinates of the page), then the side in texels.
        pub tile: [f32; 4],
    }
}

gpu_struct! {
    /// One light's planar shadow: how casters are flattened onto the ground and what the ground
    /// loses where they land (`GpuPlanar` in planar.wgsl).
    pub struct GpuPlanar {
        /// World to the flattened point on the plane, homogeneous
        /// ([`crate::shadow::flat_from_world`]).
        pub flat_from_world: Mat4,
        /// The plane: unit normal and offset (`normal · p + d = 0`).
        pub plane: Vec4,
        /// The ground's albedo (rgb) and highlight strength (a).
        pub ground: Vec4,
        /// Which light (index into the light array).
        pub light: u32,
        /// The ground's Phong exponent.
        pub shininess: f32,
        /// How far above the plane flattened casters are drawn.
        pub lift: f32,
        pub _pad0: u32,
    }
}

gpu_struct! {
    /// The tile a moment-blur pass reads and how far it reaches, and where a resolve reads the
    /// depth it makes the tile's moments of (`Blur` in blur.wgsl).
    pub struct Blur {
        /// Layer of the moment array (and of the depth array: they are page for page).
        pub layer: u32,
        /// Texels weighed each side of the centre.
        pub radius: i32,
        /// Texels along the side of the tile it blurs.
        pub size: u32,
        /// Depth texels along a side per moment texel (a resolve's).
        pub scale: u32,
        /// The tile's first texel on the page.
        pub origin: [u32; 2],
        /// The layer's first texel on the depth page (a resolve's).
        pub depth_origin: [u32; 2],
        /// Samples per texel of the multisampled depth a resolve of samples reads (its own
        /// texture, the tile's first texel at its corner).
        pub samples: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }
}

gpu_struct! {
    /// The camera a marking of virtual pages reads its pixels with (`MarkView` in
    /// page_marks.wgsl).
    pub struct MarkView {
        /// The camera's clip space back to the world.
        pub world_from_clip: Mat4,
        /// The camera's position.
        pub eye: [f32; 3],
        /// The lights of this marking: the first entries of the `MarkLight` array.
        pub count: u32,
        /// The camera's forward direction.
        pub forward: [f32; 3],
        /// Radians a pixel of the picture spans (at its middle).
        pub pixel_angle: f32,
        /// The depth buffer's width and height.
        pub size: [u32; 2],
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

gpu_struct! {
    /// One paged light of a marking: its pages and where it reaches (`MarkLight` in
    /// page_marks.wgsl; an array of them, each marking its own slice of the marks).
    pub struct MarkLight {
        /// The light's world to level-0 page units (see [`GpuLight::page_from_world`]): a cube's
        /// six faces', or one map's first.
        pub page_from_world: [Mat4; 6],
        /// Each level's window origin, two levels a vector (x, y, x, y).
        pub origins: [[i32; 4]; (crate::shadow::MAX_PAGE_LEVELS / 2) as usize],
        /// Where the light is as a homogeneous point: its position with w 1, or the direction
        /// towards it with w 0.
        pub light: [f32; 4],
        /// The sphere its light reaches (centre, radius; a negative radius: everywhere).
        pub reach: [f32; 4],
        /// View depth past which nothing takes the light's shadow.
        pub shadow_distance: f32,
        /// log2 of level 0's texel where w is 1, in metres.
        pub finest_log2: f32,
        /// The light's levels.
        pub levels: u32,
        /// Octaves coarser than its footprint a pixel's page is chosen.
        pub bias: f32,
        /// Level-0 page units a side of the map, past which a point is off it (0: no edge).
        pub extent: f32,
        /// Faces in `page_from_world`: 6 for a cube, 1 for others.
        pub faces: u32,
        /// Level-0 page units a side of a cube's face, on whose square a point is held.
        pub face_side: f32,
        /// 1 where the light's lookups may read any level coarser than the one a pixel wants,
        /// so that every coarser level's page is marked with it (PCSS on pages; see
        /// `paged_visibility` in lights.wgsl).
        pub coarser: u32,
    }
}

gpu_struct! {
    /// How an atlas tile is filled before its casters are drawn (`Fill` in tile.wgsl).
    pub struct Fill {
        /// What its colour map keeps where nothing was drawn.
        pub colour: [f32; 4],
        /// Its page in the static atlas.
        pub page: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }
}

gpu_struct! {
    /// What the depth reduction of sample distribution shadow maps reads (`Reduce` in sdsm.wgsl).
    pub struct Reduce {
        /// The camera's clip space back to the world.
        pub world_from_clip: Mat4,
        /// The world to the sun's light space, which the bins' boxes are in.
        pub light_from_world: Mat4,
        /// The camera's position.
        pub eye: [f32; 3],
        /// The view depth the bins start at.
        pub near: f32,
        /// The camera's forward direction.
        pub forward: [f32; 3],
        /// The view depth the bins end at.
        pub far: f32,
        /// The depth buffer's width and height.
        pub size: [u32; 2],
        pub _pad: [u32; 2],
    }
}

/// Most shadow-map layers the array holds (sixteen cubes); the lights whose layers do not fit
/// are lit without a shadow, and said so.
pub const MAX_LAYERS: usize = 96;
/// Side of the block of moment texels one workgroup of `cs_resolve` makes (moment_compute.wgsl).
pub const RESOLVE_BLOCK: u32 = 16;
/// The widest moment blur (texels each way) `cs_resolve` makes (its shared memory then fits the
/// 16,352 bytes every device that computes gives); wider ones take the full-screen passes.
pub const RESOLVE_MAX_RADIUS: u32 = 7;

/// Words in a row of the texture that holds the clustered light lists.
pub const LIST_WIDTH: u32 = 4096;

/// Words of each level's header in a paged light's page table (`render/page_table.rs`): its
/// window's origin (x, y), its pages across (low 16 bits) and down (high 16 bits), and its first
/// entry's word counted from the table's first.
pub const PAGE_LEVEL_WORDS: usize = 4;

/// Lights the measuring view reports in one pass (a vec4 target of visibilities).
pub const MEASURED_PER_PASS: usize = 4;

pub use crate::light::{LIGHT_POINT, LIGHT_SPOT, LIGHT_SUN, SHAPE_CASCADES, SHAPE_CUBE, SHAPE_PAGES, SHAPE_SINGLE};

/// The constants both languages use, written here once, as WGSL declarations that come before
/// every shader file.
pub fn prelude() -> String {
    let cookie_vectors = Cookie::ALL.len() * (crate::assets::COOKIE_SIZE * crate::assets::COOKIE_SIZE) as usize / 16;
    let mut out = String::from("// Constants shared with Rust (src/render/gpu_types.rs), written there.\n");
    let mut constant = |name: &str, value: u64| out.push_str(&format!("const {name}: u32 = {value}u;\n"));
    constant("MAX_LAYERS", MAX_LAYERS as u64);
    constant("CLUSTER_X", crate::light::clusters::CLUSTER_X as u64);
    constant("CLUSTER_Y", crate::light::clusters::CLUSTER_Y as u64);
    constant("CLUSTER_Z", crate::light::clusters::CLUSTER_Z as u64);
    constant("LIST_WIDTH", LIST_WIDTH as u64);
    constant("MAX_CASCADES", crate::shadow::MAX_CASCADES as u64);
    constant("MEASURED_PER_PASS", MEASURED_PER_PASS as u64);
    constant("COOKIE_SIZE", crate::assets::COOKIE_SIZE as u64);
    constant("COOKIE_VECTORS", cookie_vectors as u64);
    constant("LIGHT_SUN", LIGHT_SUN as u64);
    constant("LIGHT_SPOT", LIGHT_SPOT as u64);
    constant("LIGHT_POINT", LIGHT_POINT as u64);
    constant("SHAPE_CASCADES", SHAPE_CASCADES as u64);
    constant("SHAPE_SINGLE", SHAPE_SINGLE as u64);
    constant("SHAPE_CUBE", SHAPE_CUBE as u64);
    constant("SHAPE_PAGES", SHAPE_PAGES as u64);
    constant("PAGE_GRID", crate::shadow::PAGE_GRID as u64);
    constant("PAGE_LEVEL_WORDS", PAGE_LEVEL_WORDS as u64);
    constant("PAGE_BORDER", crate::shadow::PAGE_BORDER as u64);
    constant("MARK_WORDS", crate::shadow::MARK_WORDS as u64);
    constant("MAX_PAGE_LEVELS", crate::shadow::MAX_PAGE_LEVELS as u64);
    constant("CUBE_FACE_PAGES", crate::shadow::CUBE_FACE_PAGES as u64);
    constant("CUBE_ACROSS", crate::shadow::CUBE_ACROSS as u64);
    constant("SDSM_BINS", crate::shadow::SDSM_BINS as u64);
    constant("SDSM_WORDS", crate::shadow::SDSM_WORDS as u64);
    constant("RESOLVE_BLOCK", RESOLVE_BLOCK as u64);
    constant("RESOLVE_MAX_RADIUS", RESOLVE_MAX_RADIUS as u64);
    for method in ShadowMethod::ALL {
        constant(&format!("METHOD_{}", method.name().to_uppercase().replace('-', "_")), *method as u64);
    }
    let spreading = ShadowMethod::ALL.iter().filter(|m| m.spreads()).fold(0u64, |mask, &m| mask | 1 << m as u64);
    constant("SPREADING_METHODS", spreading);
    out.push_str(&format!("const LIGHT_FALLOFF: f32 = {:?};\n", crate::components::LIGHT_FALLOFF));
    out.push_str(&format!("const MIN_GRAZE: f32 = {:?};\n", crate::shadow::MIN_GRAZE));
    out.push_str(&format!("const POISSON16_RADIUS: f32 = {:?};\n", ShadowMethod::Poisson16.disc_radius()));
    out.push_str(&format!("const POISSON32_RADIUS: f32 = {:?};\n", ShadowMethod::Poisson32.disc_radius()));
    out.push_str(&crate::shadow::wgsl_array("POISSON_16", &crate::shadow::poisson_disc(16)));
    out.push_str(&crate::shadow::wgsl_array("POISSON_32", &crate::shadow::poisson_disc(32)));
    out
}
