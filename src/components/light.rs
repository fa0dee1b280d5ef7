//! Lights: the three kinds (directional, spot, point), each with its colour, reach and size, and
//! what a light's shadow is made of (its layers, bias and sampling method).

use crate::shadow::{LightPage, PageId, PagePool, PageSpace, Pressure, Residency, Window};
use bevy_ecs::prelude::*;
use glam::{Mat4, Vec2, Vec3};

/// How a spot or point light fades with distance d (metres): by `1 / (1 + LIGHT_FALLOFF·d²)`,
/// times a window that reaches zero at its range. Far from the light this is an inverse square,
/// `1 / (LIGHT_FALLOFF·d²)`; at the light it stays finite.
pub const LIGHT_FALLOFF: f32 = 0.05;

/// The sun: parallel light travelling along `direction`.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Direction the light travels (from the sun towards the ground).
    pub direction: Vec3,
    /// Linear RGB colour.
    pub color: Vec3,
    /// Brightness multiplier.
    pub intensity: f32,
    /// Half the angle its disc covers, in radians (the real sun's is 0.27°): the size soft
    /// shadows and the soft truth take.
    pub angular_radius: f32,
}

impl Default for DirectionalLight {
    fn default() -> Self {
        DirectionalLight {
            direction: Vec3::NEG_Y,
            color: Vec3::ONE,
            intensity: 1.0,
            angular_radius: 0.27f32.to_radians(),
        }
    }
}

/// A spot light at its entity's [`Transform`](super::Transform), shining along the transform's
/// forward axis.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct SpotLight {
    /// Linear RGB colour.
    pub color: Vec3,
    /// Brightness multiplier.
    pub intensity: f32,
    /// Distance in metres at which the light has faded to nothing.
    pub range: f32,
    /// Half angle (radians) inside which the light is at full strength.
    pub inner_angle: f32,
    /// Half angle (radians) outside which the light gives nothing (at most 90°; see
    /// [`crate::shadow::spot_cone`]).
    pub outer_angle: f32,
    /// Radius of the light's disc in metres.
    pub radius: f32,
}

impl Default for SpotLight {
    fn default() -> Self {
        SpotLight {
            color: Vec3::ONE,
            intensity: 1.0,
            range: 10.0,
            inner_angle: 0.3,
            outer_angle: 0.4,
            radius: DEFAULT_LIGHT_RADIUS,
        }
    }
}

/// A point light at its entity's [`Transform`](super::Transform), shining every way.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// Linear RGB colour.
    pub color: Vec3,
    /// Brightness multiplier.
    pub intensity: f32,
    /// Distance in metres at which the light has faded to nothing.
    pub range: f32,
    /// Radius of the light's sphere in metres.
    pub radius: f32,
}

impl Default for PointLight {
    fn default() -> Self {
        PointLight { color: Vec3::ONE, intensity: 1.0, range: 10.0, radius: DEFAULT_LIGHT_RADIUS }
    }
}

/// The size of a spot or point light when none is given: a 10 cm bulb.
pub const DEFAULT_LIGHT_RADIUS: f32 = 0.1;

/// One layer of a light's shadow: a spot light's map, one cascade of the sun's, or one face of a
/// point light's cube. Which slot of the GPU's shadow-map array holds it is the renderer's
/// business.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowLayer {
    /// World to the layer's clip space.
    pub clip_from_world: Mat4,
    /// World size of one texel: `texel.x + texel.y * distance from the light`.
    pub texel: Vec2,
    /// Texels along its side.
    pub resolution: u32,
    /// View depth at which this cascade ends (infinite for other layers).
    pub far: f32,
    /// Width of the band before `far` where this cascade blends into the next.
    pub blend: f32,
    /// How its projection turns distance from the light into depth
    /// ([`crate::shadow::depth_terms`]).
    pub depth: Vec2,
    /// The layer changed in the last update and its map must be drawn again.
    pub dirty: bool,
    /// Identifies the layer's contents: a new number each time it becomes dirty, so a renderer
    /// can tell whether the map it holds is still good, however many updates it missed.
    pub version: u64,
    /// Identifies what the layer's casters at rest draw (see [`crate::systems::CastersAtRest`]):
    /// a new number when one of them starts to move or goes, another comes to rest inside it, or
    /// the layer itself changes. A renderer that keeps their map apart draws it again only then.
    pub static_version: u64,
    /// For a page of a virtual map: which page, and the slot of the pool it holds (its name
    /// across frames); none for every other layer.
    pub page: Option<PagePlace>,
}

/// Where a page of a virtual shadow map is: the page, and the slot of the pool it holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PagePlace {
    /// The page.
    pub id: PageId,
    /// Its slot: the same for as long as it stays resident.
    pub slot: u32,
}

/// The page pool every paged light shares ([`VirtualPages`]), its pages named by light; kept by
/// the light systems, its size set by the memory budget.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct SharedPool {
    /// The slots and the pages in them.
    pub pages: PagePool<LightPage>,
    /// Octaves coarser (negative: finer) than the settings every paged light's levels are
    /// chosen: one for the pool, so that every light's pixels get about as many texels as the
    /// pool holds for all (see [`Pressure`]).
    pub pressure: Pressure,
    /// The lights (by their entity's bits) marked at this pressure since it last changed, or
    /// since pages began to go missing: it moves again only once every paged light has been, so
    /// that neither a marking made before the last move nor what a light asked for before a
    /// camera cut counts.
    pub heard: std::collections::HashSet<u64>,
    /// Pages went missing at the last update.
    pub short: bool,
}

/// A light's virtual shadow map, kept by the light systems: its pages and the windows of them
/// that may be asked for, what its last marking asked of the pool every paged light shares
/// ([`SharedPool`]), and what its last update did.
#[derive(Clone, Debug, PartialEq)]
pub struct VirtualPages {
    /// Its levels, how they are cut into pages and their depth.
    pub space: PageSpace,
    /// Each level's window round the camera, this update.
    pub windows: Vec<Window>,
    /// The pages its last marking asked for: the pool keeps them while it does not ask again.
    pub needed: Vec<PageId>,
    /// Its pages holding slots of the pool.
    pub resident: u32,
    /// Octaves coarser (negative: finer) every level is chosen: as fine as the pool holds the
    /// view's pages (see [`crate::shadow::Pressure`]).
    pub pressure: Pressure,
    /// The settings' octaves coarser each pixel's page is chosen.
    pub bias: f32,
    /// The number of the last marking given slots.
    pub marks_seen: u64,
    /// What the last update did.
    pub update: PageUpdate,
    /// What the last update that took in a marking did (what the pool lacks, until the next).
    pub marked: PageUpdate,
}

impl VirtualPages {
    /// Octaves coarser than its footprint a pixel's page is chosen, marking and lookup alike.
    #[must_use]
    pub fn lookup_bias(&self) -> f32 {
        self.bias + self.pressure.octaves
    }
}

/// What one update of a virtual map did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PageUpdate {
    /// Pages the last marking asked for.
    pub needed: u32,
    /// Kept, placed, missing, waiting and given up (the pool's account).
    pub residency: Residency,
    /// Resident pages given new contents because a caster moved through them.
    pub invalidated: u32,
    /// Resident pages a caster moved through that the last marking did not need: they gave up
    /// their slots rather than be drawn again out of view.
    pub dropped: u32,
}

impl PageUpdate {
    /// True when the update took no page in and none waits or is missing: every page the last
    /// marking asked for was already resident.
    #[must_use]
    pub fn settled(&self) -> bool {
        let r = self.residency;
        r.placed == 0 && r.waiting == 0 && r.missing == 0
    }
}

/// A light's shadow maps, written by the light-matrix system and read by the renderer: one per
/// sun cascade, one for a spot light, six (cube faces +X, -X, +Y, -Y, +Z, -Z) for a point light
/// or a spot too wide for one map. A light without this component casts no shadow.
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct ShadowMap {
    /// The light's layers, nearest cascade first.
    pub layers: Vec<ShadowLayer>,
    /// Texels along a side of each of its layers, as [`crate::systems::size_shadow_maps`] sizes
    /// them for the atlas (0 until it has: then the settings' size).
    pub resolution: u32,
    /// The size class (log2 of the side) its light keeps with hysteresis, before the memory
    /// budget halves it (0: none yet).
    pub wanted: u32,
    /// How much its light shows on screen (the radius of the disc its reach covers, as a share
    /// of the screen's half height; infinite for a sun): what the update budget ranks it by.
    pub shows: f32,
    /// Its virtual map, when its shadow is paged (its layers are then the coarse map, then one
    /// layer a resident page).
    pub pages: Option<VirtualPages>,
}

impl ShadowMap {
    /// True when any of the light's layers must be drawn again (its dirty flag).
    pub fn dirty(&self) -> bool {
        self.layers.iter().any(|l| l.dirty)
    }
}

/// Whether a light's shadow test adds screen-space contact shadows (a march through the camera's
/// depth towards the light, see contact.wgsl). A light without one takes the settings'.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ContactShadows(pub bool);

/// How far a light's shadow test pushes the surface before looking it up, in shadow-map texels.
/// A light without one takes the settings' bias.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ShadowBias {
    /// Towards the light, always.
    pub constant: f32,
    /// Towards the light, times tan of the angle between normal and light.
    pub slope: f32,
    /// Along the surface normal.
    pub normal: f32,
    /// Multiplicative offset (seed 001's depth offset): the share of the receiver's distance
    /// from the light (along the layer's axis; for a sun's cascade, from its near plane) it is
    /// pulled towards the light before the test, so the bias grows with distance as a depth
    /// format's rounding does. 0.05 is the source's `depth × 0.95`; not in texels, and 0 by
    /// default.
    pub scale: f32,
    /// Filters compare each tap with the depth the receiver's plane has there (receiver-plane
    /// depth bias, Isidoro 2006), not with the depth at the lookup's centre.
    pub receiver_plane: bool,
}

impl ShadowBias {
    /// The largest constant, slope or normal term accepted, in texels: settings, bias files and
    /// the panel's command lines all refuse more.
    pub const MAX_TEXELS: f32 = 100.0;

    /// Whether `x` is a term in texels this bias accepts (0 to [`ShadowBias::MAX_TEXELS`]).
    #[must_use]
    pub fn texels_ok(x: f32) -> bool {
        x.is_finite() && (0.0..=ShadowBias::MAX_TEXELS).contains(&x)
    }
}

impl Default for ShadowBias {
    /// Half a texel each: of the uniform biases `umbra bench` swept (0, 0.5, 1, 2, 4), the one
    /// with the fewest wrong pixels on the sample scene that still keeps every failure case in
    /// bounds (no bias at all brings back acne).
    fn default() -> Self {
        ShadowBias { constant: 0.5, slope: 0.5, normal: 0.5, scale: 0.0, receiver_plane: true }
    }
}

/// How a light's shadow map is sampled: how many comparisons are averaged for one visibility. A
/// light without one takes the settings' method.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowMethod {
    /// One comparison with the nearest texel: hard, blocky edges.
    Nearest = 0,
    /// The hardware's 2x2 comparison filter: edges one texel soft.
    #[default]
    Bilinear = 1,
    /// A 3x3 grid of 2x2 comparisons, one texel apart (percentage-closer filtering; Reeves,
    /// Salesin and Cook 1987).
    Pcf3 = 2,
    /// A 5x5 grid of 2x2 comparisons.
    Pcf5 = 3,
    /// A 5x5-texel kernel with tent-like weights taken as nine 2x2 comparisons (Castaño 2013,
    /// the one Bevy and Filament ship).
    Gauss5 = 4,
    /// 16 comparisons over a disc 1.5 texels in radius, turned per pixel (Poisson-disc PCF).
    Poisson16 = 5,
    /// 32 comparisons over a disc 2.5 texels in radius, turned per pixel.
    Poisson32 = 6,
    /// Percentage-closer soft shadows (Fernando 2005): a blocker search, then a Poisson filter
    /// as wide as the penumbra the light's size and the blocker's distance give.
    Pcss = 7,
    /// Variance shadow maps (Donnelly and Lauritzen 2006): the depth and its square, blurred,
    /// and Chebyshev's inequality as the visibility.
    Vsm = 8,
    /// Exponential variance shadow maps (Lauritzen and McCool 2008): VSM of a positive and a
    /// negative exponential warp of the depth (four moments), which bleeds far less light.
    Evsm = 9,
    /// Moment shadow maps (Peters and Klein 2015): four powers of the depth, blurred, and the
    /// Hamburger reconstruction of the sharpest shadow they allow.
    Msm = 10,
    /// Depth in an `R32Float` colour target (seed 001): the shadow pass's fragment stage writes
    /// each texel's linear depth (0 at the layer's near plane, 1 at its far one), and the lookup
    /// compares the 2x2 texels around its point by hand, weighted as the hardware's bilinear
    /// comparison weighs them.
    DepthR32f = 11,
    /// The distance from the light in metres in an `R16Float` colour target (seed 004): radial
    /// for spots and cube faces, along the light for a sun's cascades; compared as
    /// [`ShadowMethod::DepthR32f`] compares. Half floats keep 11 significant bits, so a step
    /// grows with the distance (8 mm at 10 m).
    RadialR16f = 12,
    /// Planar projected shadows (seed 004): no shadow map; every caster is flattened onto the
    /// ground along the light's rays and drawn over it, once per pixel through the stencil
    /// buffer. Exact on the ground; every other surface gets no shadow from the light.
    Planar = 13,
    /// EVSM with the positive warp alone (two moments, as VSM keeps): half of EVSM's map and
    /// blur, and more light bleeding, where the negative warp would have caught what the
    /// positive one lets through.
    Evsm2 = 14,
    /// Moment shadow maps with the Hausdorff reconstruction (Peters and Klein 2015): the same
    /// four moments as [`ShadowMethod::Msm`], but every depth is known to lie in 0..1, so
    /// where Hamburger's three points would fall outside that range, four points inside it
    /// (at 0, 1, the receiver and one more) bound the shadow instead: less light bleeding
    /// behind casters close to the range's ends.
    MsmHausdorff = 15,
}

impl ShadowMethod {
    /// Texels a sample reaches past its own on each side (the shadow map must hold them: cube
    /// faces reach this far past their edges).
    pub fn reach(self) -> u32 {
        match self {
            ShadowMethod::Nearest => 0,
            ShadowMethod::Bilinear => 1,
            ShadowMethod::Pcf3 => 2,
            ShadowMethod::Pcf5 | ShadowMethod::Gauss5 | ShadowMethod::Poisson16 => 3,
            // PCSS reaches as far as its penumbra; on a cube face it may read past the face's
            // margin, where the edge texels repeat.
            ShadowMethod::Poisson32 | ShadowMethod::Pcss => 4,
            // One filtered read of a map blurred beforehand (the blur clamps at the map's edge).
            ShadowMethod::Vsm
            | ShadowMethod::Evsm
            | ShadowMethod::Evsm2
            | ShadowMethod::Msm
            | ShadowMethod::MsmHausdorff => 1,
            ShadowMethod::DepthR32f | ShadowMethod::RadialR16f => 1,
            ShadowMethod::Planar => 0,
        }
    }

    /// Radius in texels of the disc a Poisson filter spreads its comparisons over (0 for the
    /// others).
    pub fn disc_radius(self) -> f32 {
        match self {
            ShadowMethod::Poisson16 => 1.5,
            ShadowMethod::Poisson32 => 2.5,
            _ => 0.0,
        }
    }

    /// The family it belongs to, as the charts colour it.
    pub fn family(self) -> &'static str {
        match self {
            ShadowMethod::Nearest | ShadowMethod::Bilinear => "hard",
            ShadowMethod::Pcf3 | ShadowMethod::Pcf5 => "grid PCF",
            ShadowMethod::Gauss5 => "Gaussian PCF",
            ShadowMethod::Poisson16 | ShadowMethod::Poisson32 => "Poisson PCF",
            ShadowMethod::Pcss => "PCSS",
            ShadowMethod::Vsm
            | ShadowMethod::Evsm
            | ShadowMethod::Evsm2
            | ShadowMethod::Msm
            | ShadowMethod::MsmHausdorff => "moment maps",
            ShadowMethod::DepthR32f | ShadowMethod::RadialR16f => "depth in colour",
            ShadowMethod::Planar => "planar",
        }
    }

    /// Bits per moment a moment method does best with, from `umbra bench`'s 16- against 32-bit
    /// rows on the sample scene (misclassified %, 32 against 16): VSM 0.058 against 0.069, EVSM
    /// 0.055 against 0.054 (so half floats, half the memory), MSM 0.053 against 1.61 (plain
    /// powers of the depth in half floats lose the fourth moment). 0 for the other methods.
    pub fn moment_bits(self) -> u32 {
        match self {
            ShadowMethod::Vsm | ShadowMethod::Msm | ShadowMethod::MsmHausdorff => 32,
            ShadowMethod::Evsm | ShadowMethod::Evsm2 => 16,
            _ => 0,
        }
    }

    /// Moments it keeps per texel: two (VSM, EVSM2), four (EVSM, MSM), or none.
    pub fn moment_count(self) -> u32 {
        match self {
            ShadowMethod::Vsm | ShadowMethod::Evsm2 => 2,
            ShadowMethod::Evsm | ShadowMethod::Msm | ShadowMethod::MsmHausdorff => 4,
            _ => 0,
        }
    }

    /// It reads a prefiltered moment map, not the depth map.
    pub fn moments(self) -> bool {
        self.moment_count() > 0
    }

    /// Bits of float a depth-in-colour method stores its one value in (0 for the others).
    pub fn colour_depth_bits(self) -> u32 {
        match self {
            ShadowMethod::DepthR32f => 32,
            ShadowMethod::RadialR16f => 16,
            _ => 0,
        }
    }

    /// It reads a colour map the shadow pass writes beside the depth map (moments, or depth in
    /// colour), not the depth map itself.
    pub fn colour_map(self) -> bool {
        self.moments() || self.colour_depth_bits() > 0
    }

    /// Its maps can be virtual pages of depth (see [`crate::settings::SunMaps`]): every method
    /// but those that read a colour map and planar shadows, which draw none.
    pub fn pages(self) -> bool {
        !self.colour_map() && self != ShadowMethod::Planar
    }

    /// It compares with depths away from the lookup's own point, so the receiver plane matters.
    pub fn spreads(self) -> bool {
        !matches!(self, ShadowMethod::Nearest | ShadowMethod::Bilinear | ShadowMethod::Planar) && !self.colour_map()
    }
}

/// An image projected through a spot light's cone that shapes its light (seed 004's projected
/// texture): the light is multiplied by the image where the cone meets a surface.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cookie {
    /// A four-pane window: a frame and a cross of dark bars.
    Window,
    /// Dappled light through leaves: soft round spots.
    Leaves,
}

impl Cookie {
    /// Every cookie, in texture-layer order.
    pub const ALL: [Cookie; 2] = [Cookie::Window, Cookie::Leaves];

    /// Layer of the cookie texture array holding this image.
    pub fn layer(self) -> u32 {
        Cookie::ALL.iter().position(|c| *c == self).unwrap_or(0) as u32
    }
}
