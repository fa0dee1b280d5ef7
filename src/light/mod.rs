//! Lights as the renderer, the truth and the tools see them: every light of the world, of any
//! kind, built once a frame into one [`Light`] in one order (suns, then spots, then point lights,
//! each kind in the order its entities were made). The renderer lights with that order, the
//! measuring view reports it, the truth casts rays to it, `tune` tunes it and bias files name it.
//!
//! Each kind lives in a module of its own (`sun.rs`, `spot.rs`, `point.rs`) that owns its shape,
//! its layers' projections, what its size means, where its light reaches, what it tells the GPU
//! ([`KindGpu`]; the renderer packs it, this module never imports the renderer), where the truth's
//! rays go and how it is drawn in the light-volume view. Code outside this module asks a light; it
//! never matches on its kind or on its label's text. Adding a kind touches its own file, this
//! one (the [`LightKind`] variant and [`LightSources`]), its component and the shaders.

pub mod clusters;
pub mod names;
mod point;
mod spot;
mod sun;

pub use point::{POINT_COARSE, Point};
pub use spot::{SPOT_COARSE, Spot};
pub use sun::Sun;

use crate::components::{
    Camera, ContactShadows, Cookie, DirectionalLight, PointLight, ShadowBias, ShadowLayer, ShadowMap, ShadowMethod,
    SpotLight, Transform, VirtualPages,
};
use crate::settings::{CascadeSettings, MapSettings, ShadowSettings};
use crate::shadow::{
    Aabb, CubePages, LightProjection, PAGE_BORDER, PageSpace, VisibleSamples, Window, cube_projections,
};
use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;
use clusters::Reach;
use glam::{Mat4, Vec3, Vec4};

/// Its kind's number on the GPU for a sun (`LIGHT_SUN` in the shaders).
pub const LIGHT_SUN: u32 = 0;
/// Its kind's number on the GPU for a spot light.
pub const LIGHT_SPOT: u32 = 1;
/// Its kind's number on the GPU for a point light.
pub const LIGHT_POINT: u32 = 2;
/// [`ShadowShape::Cascades`] on the GPU.
pub const SHAPE_CASCADES: u32 = 0;
/// [`ShadowShape::Single`] on the GPU.
pub const SHAPE_SINGLE: u32 = 1;
/// [`ShadowShape::Cube`] on the GPU.
pub const SHAPE_CUBE: u32 = 2;
/// [`ShadowShape::Pages`] on the GPU.
pub const SHAPE_PAGES: u32 = 3;

/// What a light's kind tells the shaders of itself: its number, pose and cone. The renderer packs
/// it with what every kind has; a kind leaves what it lacks at its default.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KindGpu {
    /// `LIGHT_SUN`, `LIGHT_SPOT` or `LIGHT_POINT`.
    pub code: u32,
    /// Where it is (spot and point lights).
    pub position: Vec3,
    /// Where its light fades to nothing (spot and point lights).
    pub range: f32,
    /// Unit direction it travels (suns) or shines (spots).
    pub direction: Vec3,
    /// Cosine of a spot's outer half angle.
    pub cos_outer: f32,
    /// Cosine of a spot's inner half angle.
    pub cos_inner: f32,
    /// World to the clip space its cookie is thrown through (spots only).
    pub cookie_from_world: Option<Mat4>,
}

/// How a light's shadow is laid out in layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadowShape {
    /// One orthographic layer per cascade.
    Cascades,
    /// One perspective layer.
    Single,
    /// Six perspective layers, one per cube face.
    Cube,
    /// A virtual map: a coarse layer over all the shadow reaches, then one layer a resident page
    /// (of a sun's clipmap round the camera, or of a spot's perspective map).
    Pages,
}

impl ShadowShape {
    /// Its number on the GPU (`SHAPE_*` in the shaders).
    #[must_use]
    pub fn gpu_id(self) -> u32 {
        match self {
            ShadowShape::Cascades => SHAPE_CASCADES,
            ShadowShape::Single => SHAPE_SINGLE,
            ShadowShape::Cube => SHAPE_CUBE,
            ShadowShape::Pages => SHAPE_PAGES,
        }
    }
}

/// One layer's projection, with the view depth where it ends and the band before that where it
/// blends into the next (a sun's cascades; infinite and 0 for other layers).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerFit {
    /// World to the layer's clip space, and what it says of texels and depth.
    pub projection: LightProjection,
    /// View depth where the layer stops being used.
    pub far: f32,
    /// Width of the band before `far` where it blends into the next.
    pub blend: f32,
}

impl LayerFit {
    /// A layer used at every depth.
    #[must_use]
    pub fn everywhere(projection: LightProjection) -> LayerFit {
        LayerFit { projection, far: f32::INFINITY, blend: 0.0 }
    }
}

/// The camera a sun's cascades are fitted to: its lens, where it is and its aspect ratio.
#[derive(Clone, Copy, Debug)]
pub struct CameraView<'a> {
    /// Its lens.
    pub camera: &'a Camera,
    /// Where it is and which way it looks.
    pub transform: &'a Transform,
    /// Width over height of the picture.
    pub aspect: f32,
}

/// What a light's layers are fitted to besides the light itself.
#[derive(Clone, Copy, Debug)]
pub struct LayerContext<'a> {
    /// Map size, cube seams, the widest spot one map takes.
    pub maps: &'a MapSettings,
    /// The sun's cascades.
    pub cascade: &'a CascadeSettings,
    /// The camera, if there is one.
    pub view: Option<CameraView<'a>>,
    /// The boxes fitting can use, each with whether it casts a shadow.
    pub scene: &'a [(Aabb, bool)],
    /// What the camera saw (the SDSM fit).
    pub seen: Option<&'a VisibleSamples>,
}

impl LayerContext<'_> {
    /// The six faces of a shadow cube at `at` reaching `range`, `resolution` texels a side,
    /// with the margin the cube seams take when they are handled.
    #[must_use]
    pub fn cube(&self, at: Vec3, range: f32, resolution: u32) -> Vec<LayerFit> {
        let margin = if self.maps.cube_seams { crate::settings::CUBE_MARGIN } else { 0 };
        cube_projections(at, range, resolution, margin).map(LayerFit::everywhere).to_vec()
    }

    /// A shadow cube at `at` reaching `range` in pages ([`CubePages`], with the cube maps' margin
    /// where seams are handled), its coarse map a cube of faces `coarse` texels a side and at
    /// most [`POINT_COARSE`].
    #[must_use]
    pub fn cube_pages(&self, at: Vec3, range: f32, coarse: u32) -> PagedFit {
        let margin = if self.maps.cube_seams { crate::settings::CUBE_MARGIN } else { 0 };
        let coarse_side = coarse.min(POINT_COARSE);
        let camera = self.view.map_or(Vec3::ZERO, |v| v.transform.translation);
        // Without the atlas guard, no border round the pages (as a spot's).
        let border = if self.maps.atlas_guard { PAGE_BORDER } else { 0 };
        let space = PageSpace::Cube(CubePages { border, ..CubePages::new(at, range, margin) });
        PagedFit { space, camera, coarse: self.cube(at, range, coarse_side), coarse_side }
    }
}

/// A light's virtual map as fitted this update: its pages, where the camera is (a clipmap's
/// windows are centred on it), and its coarse map over all its shadow reaches.
#[derive(Clone, Debug, PartialEq)]
pub struct PagedFit {
    /// Its levels, how they are cut into pages and their depth.
    pub space: PageSpace,
    /// Where the camera is.
    pub camera: Vec3,
    /// The map every pixel whose page is not there reads: one layer, or a cube's six faces
    /// ([`PageSpace::faces`]).
    pub coarse: Vec<LayerFit>,
    /// Texels a side of the coarse map.
    pub coarse_side: u32,
}

/// A light's size as a person sets it: the number, what it is and the largest a slider offers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeControl {
    /// The size in the units `label` names.
    pub value: f32,
    /// What the number is ("disc radius (°)").
    pub label: &'static str,
    /// The largest value the panel's slider offers.
    pub max: f32,
}

/// Where a light's rays come from, as the ray-traced truth casts them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Emitter {
    /// Parallel light from a disc infinitely far away.
    Distant {
        /// Unit direction towards the light.
        towards: Vec3,
        /// Half the angle its disc covers, in radians.
        angular_radius: f32,
    },
    /// Light from a disc at a point, out to a range, inside a cone.
    Local {
        /// Where the light is.
        position: Vec3,
        /// Distance at which it gives nothing.
        range: f32,
        /// Radius of its disc (or sphere) in metres.
        radius: f32,
        /// The way its disc faces, or none for a sphere (which always faces the receiver).
        facing: Option<Vec3>,
        /// Cosine of the cone's half angle around `facing`, outside which it gives nothing
        /// (-1: every way).
        cos_cone: f32,
    },
}

/// What every light kind answers. Each kind implements it in its own module.
pub trait Kind {
    /// Its name's first word ("sun", "spot", "point").
    fn word(&self) -> &'static str;
    /// The first light of this kind is named by the word alone ("sun", not "sun 1"): kinds a
    /// scene usually has one of.
    fn first_unnumbered(&self) -> bool {
        false
    }
    /// How its shadow is laid out in layers.
    fn shape(&self, settings: &MapSettings, method: ShadowMethod) -> ShadowShape;
    /// Its shadow's layers, `resolution` texels a side: their projections, in layer order.
    fn layers(&self, context: &LayerContext, resolution: u32) -> Vec<LayerFit>;
    /// Its virtual map round the camera, its coarse map `coarse` texels a side, its depth range
    /// kept from `depth` (last update's) while it holds the scene; none for a kind that is not
    /// paged, or without a camera.
    fn pages(&self, context: &LayerContext, coarse: u32, depth: Option<(f32, f32)>) -> Option<PagedFit>;
    /// Its coarse map where it is paged, at most `coarse` texels a side: its layers and their
    /// side, what the atlas keeps for it besides the pages (as [`Kind::pages`] fits it).
    fn coarse_map(&self, settings: &MapSettings, coarse: u32) -> (u32, u32);
    /// Its size as soft shadows take it: tan of a distant light's angular radius (a blocker's
    /// distance times it is the penumbra's half width), or a local light's radius in metres.
    fn penumbra_size(&self) -> f32;
    /// Its size as a person sets it.
    fn size_control(&self) -> SizeControl;
    /// Sets the size of `entity`'s light of this kind, in [`Kind::size_control`]'s units.
    fn set_size(&self, world: &mut World, entity: Entity, size: f32);
    /// Where its light can arrive (the clusters list it there).
    fn reach(&self) -> Reach;
    /// Its kind, pose and cone as the shaders read them (the rest is the same for every kind).
    fn gpu(&self) -> KindGpu;
    /// Where the truth's rays to it go.
    fn emitter(&self) -> Emitter;
    /// Where it is as a homogeneous point: w = 1 for a light at a point, w = 0 for a direction
    /// towards a light infinitely far away.
    fn homogeneous(&self) -> Vec4;
    /// The colour of its layer `layer`'s volume in the light-volume view.
    fn volume_colour(&self, layer: usize) -> [f32; 4];
}

/// What a light is, where it is and how big: everything that shapes its light and its shadow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Parallel light from far away.
    Sun(Sun),
    /// Light from a point inside a cone.
    Spot(Spot),
    /// Light from a point every way.
    Point(Point),
}

/// `$body` with `$k` bound to whichever kind `$kind` holds.
macro_rules! each_kind {
    ($kind:expr, $k:ident => $body:expr) => {
        match $kind {
            LightKind::Sun($k) => $body,
            LightKind::Spot($k) => $body,
            LightKind::Point($k) => $body,
        }
    };
}

impl Kind for LightKind {
    fn word(&self) -> &'static str {
        each_kind!(self, k => k.word())
    }
    fn first_unnumbered(&self) -> bool {
        each_kind!(self, k => k.first_unnumbered())
    }
    fn shape(&self, settings: &MapSettings, method: ShadowMethod) -> ShadowShape {
        each_kind!(self, k => k.shape(settings, method))
    }
    fn layers(&self, context: &LayerContext, resolution: u32) -> Vec<LayerFit> {
        each_kind!(self, k => k.layers(context, resolution))
    }
    fn pages(&self, context: &LayerContext, coarse: u32, depth: Option<(f32, f32)>) -> Option<PagedFit> {
        each_kind!(self, k => k.pages(context, coarse, depth))
    }
    fn coarse_map(&self, settings: &MapSettings, coarse: u32) -> (u32, u32) {
        each_kind!(self, k => k.coarse_map(settings, coarse))
    }
    fn penumbra_size(&self) -> f32 {
        each_kind!(self, k => k.penumbra_size())
    }
    fn size_control(&self) -> SizeControl {
        each_kind!(self, k => k.size_control())
    }
    fn set_size(&self, world: &mut World, entity: Entity, size: f32) {
        each_kind!(self, k => k.set_size(world, entity, size))
    }
    fn reach(&self) -> Reach {
        each_kind!(self, k => k.reach())
    }
    fn gpu(&self) -> KindGpu {
        each_kind!(self, k => k.gpu())
    }
    fn emitter(&self) -> Emitter {
        each_kind!(self, k => k.emitter())
    }
    fn homogeneous(&self) -> Vec4 {
        each_kind!(self, k => k.homogeneous())
    }
    fn volume_colour(&self, layer: usize) -> [f32; 4] {
        each_kind!(self, k => k.volume_colour(layer))
    }
}

/// A light's name: its kind's word and its number among the lights of that kind ("sun", "sun
/// 2", "spot 1", "point 1"). Bias files and reports use it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LightLabel {
    /// Its kind's word.
    pub word: &'static str,
    /// 1 for the first light of its kind.
    pub number: usize,
    /// Written as the word alone (the first of a kind named so).
    pub bare: bool,
}

impl std::fmt::Display for LightLabel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.bare { write!(f, "{}", self.word) } else { write!(f, "{} {}", self.word, self.number) }
    }
}

/// One light as the renderer, the truth and the tools see it, built once a frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Its entity.
    pub entity: Entity,
    /// Its name.
    pub label: LightLabel,
    /// Its kind, pose and size.
    pub kind: LightKind,
    /// How its shadow is laid out.
    pub shape: ShadowShape,
    /// Linear RGB colour times intensity.
    pub color: Vec3,
    /// It casts a shadow (it has a [`ShadowMap`]).
    pub shadowed: bool,
    /// Its shadow bias (its own, or the settings').
    pub bias: ShadowBias,
    /// How its shadow map is sampled (its own, or the settings').
    pub method: ShadowMethod,
    /// Its shadow test adds contact shadows (its own choice, or the settings').
    pub contact: bool,
    /// The image its light is thrown through (spot lights only).
    pub cookie: Option<Cookie>,
    /// Its shadow's layers as the update fitted them (none when it casts no shadow).
    pub layers: Vec<ShadowLayer>,
    /// How much it shows on screen (see [`ShadowMap::shows`]).
    pub shows: f32,
    /// Its virtual map as a lookup reads it, when its shadow is paged.
    pub pages: Option<PageView>,
}

/// A virtual map as the lookups (and the marking) read it: its pages, the windows its page
/// table covers and the octaves coarser a pixel's page is chosen.
#[derive(Clone, Debug, PartialEq)]
pub struct PageView {
    /// Its levels, how they are cut into pages and their depth.
    pub space: PageSpace,
    /// Each level's window round the camera.
    pub windows: Vec<Window>,
    /// Octaves coarser than its footprint a pixel's page is chosen.
    pub bias: f32,
}

impl PageView {
    /// What the lookups read of `pages`.
    #[must_use]
    pub fn of(pages: &VirtualPages) -> PageView {
        PageView { space: pages.space, windows: pages.windows.clone(), bias: pages.lookup_bias() }
    }
}

impl Light {
    /// Its size as soft shadows take it (see [`Kind::penumbra_size`]).
    #[must_use]
    pub fn size(&self) -> f32 {
        self.kind.penumbra_size()
    }

    /// Its lookups may read any of its pages' levels coarser than a pixel wants, so each is
    /// marked with the one it wants: PCSS with its blocker search reads the level where the
    /// penumbra fits a page's border (`paged_visibility` in lights.wgsl).
    #[must_use]
    pub fn reads_coarser_pages(&self, pcss_search: bool) -> bool {
        self.pages.is_some() && self.method == ShadowMethod::Pcss && pcss_search
    }
}

/// One light of the world before its settings are looked up: its entity, kind and colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Source {
    /// Its entity.
    pub entity: Entity,
    /// Its kind, pose and size.
    pub kind: LightKind,
    /// Linear RGB colour times intensity.
    pub color: Vec3,
}

/// Reads the lights of every kind from the world: the one place that queries each kind's
/// component.
#[derive(SystemParam)]
pub struct LightSources<'w, 's> {
    suns: Query<'w, 's, (Entity, &'static DirectionalLight)>,
    spots: Query<'w, 's, (Entity, &'static SpotLight, &'static Transform)>,
    points: Query<'w, 's, (Entity, &'static PointLight, &'static Transform)>,
}

impl LightSources<'_, '_> {
    /// Every light, in light order.
    #[must_use]
    pub fn all(&self) -> Vec<Source> {
        in_light_order([
            self.suns.iter().map(|(e, l)| Sun::source(e, l)).collect(),
            self.spots.iter().map(|(e, l, t)| Spot::source(e, l, t)).collect(),
            self.points.iter().map(|(e, l, t)| Point::source(e, l, t)).collect(),
        ])
    }
}

/// Light order: suns, then spots, then points, each kind in the order its entities were made.
fn in_light_order(kinds: [Vec<Source>; 3]) -> Vec<Source> {
    kinds
        .into_iter()
        .flat_map(|mut found| {
            found.sort_by_key(|s| s.entity.index());
            found
        })
        .collect()
}

/// The lights of `world` in light order, every one of them (read only: a kind never spawned
/// has none).
pub fn light_list(world: &World) -> Vec<Light> {
    let maps = world.get_resource::<MapSettings>().copied().unwrap_or_default();
    let settings = world.get_resource::<ShadowSettings>().copied().unwrap_or_default();
    let sources = in_light_order([
        world
            .try_query::<(Entity, &DirectionalLight)>()
            .map_or_else(Vec::new, |mut q| q.iter(world).map(|(e, l)| Sun::source(e, l)).collect()),
        world
            .try_query::<(Entity, &SpotLight, &Transform)>()
            .map_or_else(Vec::new, |mut q| q.iter(world).map(|(e, l, t)| Spot::source(e, l, t)).collect()),
        world
            .try_query::<(Entity, &PointLight, &Transform)>()
            .map_or_else(Vec::new, |mut q| q.iter(world).map(|(e, l, t)| Point::source(e, l, t)).collect()),
    ]);
    let mut counts = std::collections::HashMap::new();
    sources
        .into_iter()
        .map(|Source { entity, kind, color }| {
            let number = *counts.entry(kind.word()).and_modify(|n| *n += 1).or_insert(1);
            let map = world.get::<ShadowMap>(entity);
            let method = world.get::<ShadowMethod>(entity).copied().unwrap_or(settings.method);
            let pages = map.and_then(|m| m.pages.as_ref()).map(PageView::of);
            // What the last update laid out, until it lays it out anew.
            let shape = match (kind.shape(&maps, method), &pages) {
                (_, Some(_)) => ShadowShape::Pages,
                (ShadowShape::Pages, None) => kind.shape(&maps.unpaged(), method),
                (shape, None) => shape,
            };
            Light {
                entity,
                label: LightLabel { word: kind.word(), number, bare: number == 1 && kind.first_unnumbered() },
                kind,
                shape,
                color,
                shadowed: map.is_some(),
                bias: world.get::<ShadowBias>(entity).copied().unwrap_or_else(|| settings.shadow_bias()),
                method,
                contact: world.get::<ContactShadows>(entity).map_or(settings.contact_shadows, |c| c.0),
                cookie: world.get::<Cookie>(entity).copied(),
                layers: map.map(|m| m.layers.clone()).unwrap_or_default(),
                shows: map.map_or(0.0, |m| m.shows),
                pages,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::Settings;

    #[test]
    fn lights_come_suns_first_with_their_own_names_and_defaults() {
        let mut world = World::new();
        Settings::default().put(&mut world).unwrap();
        let spot = world.spawn((SpotLight::default(), Transform::default(), ShadowMap::default())).id();
        let point = world.spawn((PointLight::default(), Transform::from_xyz(0.0, 3.0, 0.0))).id();
        let sun = world.spawn((DirectionalLight::default(), ShadowMap::default(), ShadowMethod::Pcf5)).id();
        let wide = SpotLight { outer_angle: 1.2, ..Default::default() };
        let bias = ShadowBias { constant: 2.0, slope: 0.0, normal: 1.0, scale: 0.0, receiver_plane: true };
        let second = world.spawn((wide, Transform::default(), ShadowMap::default(), bias)).id();
        world.spawn(DirectionalLight::default());
        let lights = light_list(&world);
        let order: Vec<Entity> = lights.iter().map(|l| l.entity).collect();
        assert_eq!(order[..4], [sun, order[1], spot, second]);
        assert_eq!(order[4], point);
        let names: Vec<String> = lights.iter().map(|l| l.label.to_string()).collect();
        assert_eq!(names, vec!["sun", "sun 2", "spot 1", "spot 2", "point 1"]);
        assert_eq!(lights[0].method, ShadowMethod::Pcf5);
        assert_eq!(lights[2].method, ShadowSettings::default().method, "the settings' method by default");
        assert_eq!((lights[2].bias, lights[3].bias), (ShadowSettings::default().shadow_bias(), bias));
        assert!(!lights[4].shadowed && !lights[1].shadowed && lights[0].shadowed);
        let shapes: Vec<ShadowShape> = lights.iter().map(|l| l.shape).collect();
        use ShadowShape::*;
        assert_eq!(shapes, vec![Cascades, Cascades, Single, Cube, Cube]);
    }

    #[test]
    fn every_light_is_listed_however_many() {
        let mut world = World::new();
        for _ in 0..1100 {
            world.spawn((PointLight::default(), Transform::default()));
        }
        let lights = light_list(&world);
        assert_eq!(lights.len(), 1100);
        assert_eq!(lights[1099].label.to_string(), "point 1100");
    }

    #[test]
    fn sizes_set_through_the_kind_land_on_its_component() {
        let mut world = World::new();
        Settings::default().put(&mut world).unwrap();
        let sun = world.spawn(DirectionalLight::default()).id();
        let spot = world.spawn((SpotLight::default(), Transform::default())).id();
        let point = world.spawn((PointLight::default(), Transform::default())).id();
        for light in light_list(&world) {
            light.kind.set_size(&mut world, light.entity, 0.75);
        }
        assert!((world.get::<DirectionalLight>(sun).unwrap().angular_radius - 0.75f32.to_radians()).abs() < 1e-7);
        assert_eq!(world.get::<SpotLight>(spot).unwrap().radius, 0.75);
        assert_eq!(world.get::<PointLight>(point).unwrap().radius, 0.75);
        let sizes: Vec<f32> = light_list(&world).iter().map(|l| l.kind.size_control().value).collect();
        assert!(sizes.iter().all(|s| (s - 0.75).abs() < 1e-5), "{sizes:?}");
    }
}
