//! Virtual (paged) shadow maps for the sun, as pure math: where the shadow texels of each level
//! of the clipmap lie, and which page holds a point.
//!
//! The sun's virtual map is a stack of levels round the camera, level `l` with texels of
//! `finest · 2^l` metres, each level a window of [`PAGE_GRID`]² pages. Every level's texels lie on
//! one fixed grid in the sun's light space (a page is [`PAGE_TEXELS`] of them a side, numbered from
//! the light space's origin), so a page keeps its texels while the camera moves: the window only
//! decides which pages may be asked for. A page is drawn into a [`PAGE_TILE`]² tile of the atlas,
//! its own texels plus a border of [`PAGE_BORDER`] on each side, so that a filter sampling near
//! its edge finds the texels its neighbour would hold. A visible pixel wants the level whose
//! texel, laid along the light onto the surface, is as large as the pixel's footprint there
//! ([`wanted_texel`], [`Clipmap::level_for`]).

use super::LightProjection;
use super::fit::light_view;
use glam::camera::rh::proj::directx;
use glam::{IVec2, Mat4, Vec2, Vec3};

/// Texels a side of the atlas tile a page is drawn into.
pub const PAGE_TILE: u32 = 64;
/// Texels of border on each side of a page's tile: as far as any filter reaches past the texel
/// it samples ([`crate::components::ShadowMethod::reach`]), as a cube face's margin.
pub const PAGE_BORDER: u32 = 4;
/// Texels a side of a page's own square: the spacing of pages on their level's grid.
pub const PAGE_TEXELS: u32 = PAGE_TILE - 2 * PAGE_BORDER;
/// Pages along a side of a level's window round the camera.
pub const PAGE_GRID: u32 = 128;
/// Most levels a clipmap has.
pub const MAX_PAGE_LEVELS: u32 = 16;
/// log2 of the finest level's texel in metres: about a millimetre.
pub const FINEST_TEXEL_LOG2: i32 = -10;
/// The smallest |n·l| a wanted texel is figured with: a surface the light grazes would otherwise
/// want texels without end (the texel-density view clamps the same way).
pub const MIN_GRAZE: f32 = 0.05;
/// Sharpest pixel the level count plans for at the shadow distance: radians a pixel spans (a
/// 360-pixel-high view with a 90° field of view). Sharper views take the coarsest level there.
const COARSEST_PIXEL_ANGLE: f32 = 1.0 / 180.0;

/// One page: its level and its column and row on that level's grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PageId {
    /// Its level (0: the finest).
    pub level: u32,
    /// Its column: its square spans `x · size ..= (x + 1) · size` along light-space x.
    pub x: i32,
    /// Its row, along light-space y.
    pub y: i32,
}

/// The sun's clipmap: its light space, its levels and the depth range every page shares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clipmap {
    /// World to the sun's light space (a rotation: x and y across the light, z towards it).
    pub light_from_world: Mat4,
    /// log2 of level 0's texel in metres.
    pub finest_log2: i32,
    /// Levels, 1 to [`MAX_PAGE_LEVELS`].
    pub levels: u32,
    /// Light-space z of the near plane (towards the light) and the far plane, shared by every
    /// page so that a page's depths stay good while the camera moves.
    pub depth: (f32, f32),
    /// Texels of border round each page's square in its tile: [`PAGE_BORDER`], or 0 to show
    /// what a filter reading past a page does (the page-seams case).
    pub border: u32,
}

impl Clipmap {
    /// The clipmap of a sun shining along `direction` whose shadow reaches `shadow_distance`
    /// metres from the camera, its pages' depth spanning light-space z `depth` (near, far).
    #[must_use]
    pub fn new(direction: Vec3, shadow_distance: f32, depth: (f32, f32)) -> Clipmap {
        Clipmap {
            light_from_world: light_view(Vec3::ZERO, direction),
            finest_log2: FINEST_TEXEL_LOG2,
            levels: levels_for(shadow_distance, FINEST_TEXEL_LOG2),
            depth,
            border: PAGE_BORDER,
        }
    }

    /// The same clipmap with its grid's origin moved to the point `at`: no longer fixed in light
    /// space, so its texels slide as `at` does (to show what the fixed grid guards against).
    #[must_use]
    pub fn centred_on(self, at: Vec3) -> Clipmap {
        let shift = Mat4::from_translation(-self.across(at).extend(0.0));
        Clipmap { light_from_world: shift * self.light_from_world, ..self }
    }

    /// World size of a texel of `level`, in metres.
    #[must_use]
    pub fn texel(&self, level: u32) -> f32 {
        (2.0f32).powi(self.finest_log2 + level as i32)
    }

    /// World size of a page's own square on `level`, in metres.
    #[must_use]
    pub fn page_size(&self, level: u32) -> f32 {
        self.texel(level) * PAGE_TEXELS as f32
    }

    /// World size of a page's border on `level`, in metres.
    #[must_use]
    pub fn border_size(&self, level: u32) -> f32 {
        self.texel(level) * self.border as f32
    }

    /// World to level-0 page units across the light: a point's page on level `l` is the floor of
    /// its units over `2^l` (as [`FrustumPages::page_from_world`], whose units are divided by w;
    /// here w is 1).
    ///
    /// [`FrustumPages::page_from_world`]: super::FrustumPages::page_from_world
    #[must_use]
    pub fn page_from_world(&self) -> Mat4 {
        Mat4::from_scale(Vec3::splat(1.0 / self.page_size(0))) * self.light_from_world
    }

    /// Where world point `p` is across the light (light-space x and y).
    #[must_use]
    pub fn across(&self, p: Vec3) -> Vec2 {
        self.light_from_world.transform_point3(p).truncate()
    }

    /// The page of `level` that holds the point `at` across the light (see [`Clipmap::across`]).
    #[must_use]
    pub fn page_at(&self, level: u32, at: Vec2) -> PageId {
        let cell = (at / self.page_size(level)).floor();
        let clamp = |v: f32| v.clamp(i32::MIN as f32 / 2.0, i32::MAX as f32 / 2.0) as i32;
        PageId { level, x: clamp(cell.x), y: clamp(cell.y) }
    }

    /// The window of `level` round the camera at `camera` (across the light): [`PAGE_GRID`]²
    /// pages, the camera's page as near its middle as a whole page allows. Its pages are the
    /// only ones of the level that may be asked for.
    #[must_use]
    pub fn window(&self, level: u32, camera: Vec2) -> Window {
        let page = self.page_at(level, camera);
        Window { level, origin: IVec2::new(page.x, page.y) - IVec2::splat(PAGE_GRID as i32 / 2) }
    }

    /// The windows of every level round the camera at `camera`.
    #[must_use]
    pub fn windows(&self, camera: Vec2) -> Vec<Window> {
        (0..self.levels).map(|l| self.window(l, camera)).collect()
    }

    /// The projection `page` is drawn with: orthographic over its square and its border, the
    /// clipmap's depth range.
    #[must_use]
    pub fn projection(&self, page: PageId) -> LightProjection {
        let (size, border) = (self.page_size(page.level), self.border_size(page.level));
        let min = Vec2::new(page.x as f32, page.y as f32) * size - border;
        let max = min + Vec2::splat(size + 2.0 * border);
        // The level's texel, unless the border is not the default one.
        let texel = (size + 2.0 * border) / PAGE_TILE as f32;
        let (near_z, far_z) = self.depth;
        let proj = directx::orthographic(min.x, max.x, min.y, max.y, -near_z, -far_z);
        let view = self.light_from_world;
        LightProjection { view, proj, view_proj: proj * view, texel: Vec2::new(texel, 0.0) }
    }

    /// The square across the light (min, max) that `page` holds, border included.
    #[must_use]
    pub fn footprint(&self, page: PageId) -> (Vec2, Vec2) {
        let (size, border) = (self.page_size(page.level), self.border_size(page.level));
        let min = Vec2::new(page.x as f32, page.y as f32) * size;
        (min - border, min + Vec2::splat(size + border))
    }

    /// The level a pixel that wants texels of `wanted` metres reads, `bias` octaves coarser
    /// (negative: finer): the nearest in log2, within the clipmap's levels. A pixel that wants no
    /// size at all (NaN, zero, negative) reads the finest.
    #[must_use]
    pub fn level_for(&self, wanted: f32, bias: f32) -> u32 {
        let octaves = wanted.log2() - self.finest_log2 as f32 + bias;
        if octaves.is_nan() {
            return 0;
        }
        octaves.round().clamp(0.0, (self.levels - 1) as f32) as u32
    }
}

/// The levels a clipmap needs so that its coarsest texel is as large as a pixel of the coarsest
/// view it plans for (a 360-pixel-high view with a 90° field of view) at the shadow distance, from a finest texel of
/// `2^finest_log2` metres: 1 to [`MAX_PAGE_LEVELS`].
#[must_use]
pub fn levels_for(shadow_distance: f32, finest_log2: i32) -> u32 {
    let coarsest = shadow_distance * COARSEST_PIXEL_ANGLE;
    let octaves = coarsest.log2() - finest_log2 as f32;
    if !octaves.is_finite() {
        return if octaves == f32::INFINITY { MAX_PAGE_LEVELS } else { 1 };
    }
    (octaves.ceil() as i64 + 1).clamp(1, i64::from(MAX_PAGE_LEVELS)) as u32
}

/// The texel size (metres) a pixel wants: one whose square, laid along the light onto the
/// surface (it stretches by 1 / |n·l|), covers as much of it as the pixel does. The pixel spans
/// `pixel_angle` radians at `distance` metres from the eye, and its footprint stretches by
/// 1 / |n·v| on a surface seen aslant; both cosines are held at [`MIN_GRAZE`] or more. The marking
/// and the lookups find the same size for the same surface (the WGSL twin is `wanted_texel` in
/// pages.wgsl, page_marks.wgsl has its own copy).
#[must_use]
pub fn wanted_texel(distance: f32, pixel_angle: f32, n_dot_v: f32, n_dot_l: f32) -> f32 {
    let cosine = |c: f32| if c.is_nan() { 1.0 } else { c.abs().clamp(MIN_GRAZE, 1.0) };
    let size = (distance * pixel_angle).max(0.0);
    if size.is_nan() {
        return 0.0;
    }
    size * (cosine(n_dot_l) / cosine(n_dot_v)).sqrt()
}

/// One level's window: the pages of it that may be asked for, [`PAGE_GRID`] a side from
/// `origin`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Window {
    /// Its level.
    pub level: u32,
    /// Its first page's column and row.
    pub origin: IVec2,
}

impl Window {
    /// Where `page` is in the window, as an index 0..PAGE_GRID² (row by row), if it is in it.
    #[must_use]
    pub fn index(&self, page: PageId) -> Option<usize> {
        self.index_in(page, IVec2::splat(PAGE_GRID as i32))
    }

    /// Where `page` is in the first `grid` columns and rows of the window, as an index (row by
    /// row, `grid.x` a row), if it is in them.
    #[must_use]
    pub fn index_in(&self, page: PageId, grid: IVec2) -> Option<usize> {
        let (x, y) = (i64::from(page.x) - i64::from(self.origin.x), i64::from(page.y) - i64::from(self.origin.y));
        let (columns, rows) = (i64::from(grid.x), i64::from(grid.y));
        let inside = page.level == self.level && (0..columns).contains(&x) && (0..rows).contains(&y);
        inside.then(|| (y * columns + x) as usize)
    }

    /// The page at `index` (row by row) of the window.
    #[must_use]
    pub fn page(&self, index: usize) -> PageId {
        let grid = PAGE_GRID as usize;
        let (x, y) = ((index % grid) as i32, (index / grid) as i32);
        PageId { level: self.level, x: self.origin.x.saturating_add(x), y: self.origin.y.saturating_add(y) }
    }
}

/// The pages of one level whose tiles meet a square across the light: columns and rows
/// `min..=max` (empty when a component of `min` exceeds `max`'s).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PageRange {
    /// Their level.
    pub level: u32,
    /// The first column and row.
    pub min: IVec2,
    /// The last column and row.
    pub max: IVec2,
}

impl PageRange {
    /// True when `page` is one of them.
    #[must_use]
    pub fn contains(&self, page: PageId) -> bool {
        page.level == self.level
            && (self.min.x..=self.max.x).contains(&page.x)
            && (self.min.y..=self.max.y).contains(&page.y)
    }

    /// How many pages it holds.
    #[must_use]
    pub fn count(&self) -> u64 {
        let side = |a: i32, b: i32| (i64::from(b) - i64::from(a) + 1).max(0) as u64;
        side(self.min.x, self.max.x) * side(self.min.y, self.max.y)
    }

    /// Its pages, row by row.
    pub fn pages(&self) -> impl Iterator<Item = PageId> {
        let (level, min, max) = (self.level, self.min, self.max);
        (min.y..=max.y).flat_map(move |y| (min.x..=max.x).map(move |x| PageId { level, x, y }))
    }
}

impl Clipmap {
    /// The pages of `level` whose tiles (border included) meet the square `min..max` across the
    /// light; none for a square that is not finite.
    #[must_use]
    pub fn pages_meeting(&self, level: u32, (min, max): (Vec2, Vec2)) -> PageRange {
        let (size, border) = (self.page_size(level), self.border_size(level));
        let cell = |v: f32| (v / size).floor().clamp(i32::MIN as f32 / 2.0, i32::MAX as f32 / 2.0) as i32;
        if !(min.is_finite() && max.is_finite()) {
            return PageRange { level, min: IVec2::ONE, max: IVec2::ZERO };
        }
        // A tile reaches `border` past its page's square, so a square that far outside still meets it.
        let lo = IVec2::new(cell(min.x - border), cell(min.y - border));
        let hi = IVec2::new(cell(max.x + border), cell(max.y + border));
        PageRange { level, min: lo, max: hi }
    }
}

/// The light-space depth range (near, far; z grows towards the light) a clipmap keeps for a scene
/// that `needed` (the top of its casters, the bottom of everything): the `previous` one while it
/// holds the scene and is not more than twice as deep as it needs, else one with room round the
/// scene, in whole metres. A page's depths are good only for the range it was drawn with, so the
/// range must not follow every caster that bobs.
#[must_use]
pub fn depth_range(previous: Option<(f32, f32)>, (top, bottom): (f32, f32)) -> (f32, f32) {
    let usable = top.is_finite() && bottom.is_finite() && top >= bottom;
    let Some((top, bottom)) = usable.then_some((top, bottom)) else {
        return previous.unwrap_or((1.0, -1.0));
    };
    let depth = top - bottom;
    if let Some((near, far)) = previous
        && near >= top
        && far <= bottom
        && near - far <= 2.0 * depth + 4.0
    {
        return (near, far);
    }
    let pad = 0.25 * depth + 1.0;
    ((top + pad).ceil(), (bottom - pad).floor())
}

/// Words of marks a level takes: one bit a page of its window.
pub const MARK_WORDS: usize = (PAGE_GRID * PAGE_GRID / 32) as usize;

/// The pages the camera's pixels asked a paged light for, as the marking pass left them: a bit
/// per page of each level's window, level after level (see `page_marks.wgsl`).
#[derive(Clone, Debug, PartialEq)]
pub struct PageMarks {
    /// The light's entity, as bits.
    pub light: u64,
    /// The marking's number: each marking the renderer reads back has a new one.
    pub seq: u64,
    /// The pages the pixels were marked against.
    pub space: super::PageSpace,
    /// Its windows then, one a level.
    pub windows: Vec<Window>,
    /// Octaves coarser than its footprint each pixel's page was chosen (the settings' bias and
    /// the pool's pressure then).
    pub bias: f32,
    /// [`MARK_WORDS`] words a level.
    pub bits: Vec<u32>,
}

impl PageMarks {
    /// The pages marked, level after level, coarsest last.
    pub fn pages(&self) -> impl Iterator<Item = PageId> + '_ {
        self.windows.iter().enumerate().flat_map(move |(l, window)| {
            let words = self.bits.get(l * MARK_WORDS..(l + 1) * MARK_WORDS).unwrap_or(&[]);
            words.iter().enumerate().flat_map(move |(w, &word)| {
                (0..32).filter(move |b| word & (1 << b) != 0).map(move |b| window.page(w * 32 + b))
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clipmap() -> Clipmap {
        Clipmap::new(Vec3::new(0.3, -1.0, 0.2), 60.0, (40.0, -40.0))
    }

    #[test]
    fn levels_double_their_texels_and_reach_the_shadow_distance() {
        let c = clipmap();
        assert_eq!(c.levels, 10, "1 mm to half a metre for 60 m");
        for l in 1..c.levels {
            assert_eq!(c.texel(l), 2.0 * c.texel(l - 1));
        }
        assert!((c.texel(0) - 1.0 / 1024.0).abs() < 1e-9);
        assert!(c.texel(c.levels - 1) >= 60.0 * COARSEST_PIXEL_ANGLE);
        // Each level's window is twice as wide as the one before, round the camera.
        let w = |l| c.page_size(l) * PAGE_GRID as f32;
        assert_eq!(w(3), 2.0 * w(2));
        for odd in [f32::NAN, 0.0, -5.0, 1e-9] {
            assert_eq!(levels_for(odd, FINEST_TEXEL_LOG2), 1, "{odd}");
        }
        assert_eq!(levels_for(f32::INFINITY, FINEST_TEXEL_LOG2), MAX_PAGE_LEVELS);
        assert_eq!(levels_for(1e30, FINEST_TEXEL_LOG2), MAX_PAGE_LEVELS);
    }

    #[test]
    fn without_a_border_a_page_is_drawn_over_its_own_square_alone() {
        let page = PageId { level: 2, x: 3, y: -2 };
        let mut c = clipmap();
        let with = c.projection(page);
        assert!((with.texel.x - c.texel(2)).abs() < 1e-9, "the border keeps the level's texel");
        c.border = 0;
        let (min, max) = c.footprint(page);
        assert_eq!(max - min, Vec2::splat(c.page_size(2)));
        let without = c.projection(page);
        assert!((without.texel.x * PAGE_TILE as f32 - c.page_size(2)).abs() < 1e-6, "128 texels over 120's square");
        let corner = c.light_from_world.inverse().transform_point3(min.extend(0.0));
        let clip = without.view_proj.project_point3(corner);
        assert!((clip.truncate() - Vec2::new(-1.0, -1.0)).length() < 1e-4, "its square fills the tile: {clip}");
    }

    #[test]
    fn page_units_name_the_page_a_point_lies_in_on_every_level() {
        let c = clipmap();
        for p in [Vec3::ZERO, Vec3::new(3.3, 0.2, -7.9), Vec3::new(-250.0, 4.0, 90.0)] {
            let u = c.page_from_world() * p.extend(1.0);
            assert!((u.w - 1.0).abs() < 1e-6);
            for level in [0, 4, 9] {
                let cell = (u.truncate().truncate() / 2f32.powi(level as i32)).floor();
                let page = c.page_at(level, c.across(p));
                assert_eq!((cell.x as i32, cell.y as i32), (page.x, page.y), "{p} on level {level}");
            }
        }
    }

    #[test]
    fn a_grid_centred_on_a_point_puts_it_at_the_origin_and_keeps_the_turn() {
        let c = clipmap();
        let at = Vec3::new(12.3, 4.0, -7.7);
        let moved = c.centred_on(at);
        assert!(moved.across(at).length() < 1e-4);
        assert_eq!(glam::Mat3::from_mat4(moved.light_from_world), glam::Mat3::from_mat4(c.light_from_world));
        let nan = c.centred_on(Vec3::NAN);
        assert!(nan.across(Vec3::ZERO).is_nan(), "a NaN point gives a NaN grid, not a panic");
    }

    #[test]
    fn a_point_lies_in_the_page_that_holds_it_and_a_page_centre_round_trips() {
        let c = clipmap();
        for level in [0, 3, 9] {
            for at in [Vec2::ZERO, Vec2::new(-0.001, 0.0), Vec2::new(13.7, -42.25), Vec2::new(-1e4, 3e3)] {
                let page = c.page_at(level, at);
                let (min, max) = c.footprint(page);
                let border = PAGE_BORDER as f32 * c.texel(level);
                assert!(at.cmpge(min + border - 1e-3).all() && at.cmple(max - border + 1e-3).all(), "{at} in {page:?}");
                let centre = (min + max) * 0.5;
                assert_eq!(c.page_at(level, centre), page);
            }
        }
        assert_eq!(c.page_at(0, Vec2::new(-0.001, 0.0)).x, -1, "pages below the origin count down");
        // Odd points give some page, never a panic.
        let _ = c.page_at(0, Vec2::NAN);
        let _ = c.page_at(9, Vec2::splat(f32::INFINITY));
    }

    #[test]
    fn a_page_projection_puts_its_square_inside_the_border_and_its_neighbour_texel_for_texel() {
        let c = clipmap();
        let page = PageId { level: 2, x: 5, y: -3 };
        let p = c.projection(page);
        assert_eq!(p.texel, Vec2::new(c.texel(2), 0.0));
        let (min, max) = c.footprint(page);
        let world = |xy: Vec2| c.light_from_world.inverse().transform_point3(xy.extend(0.0));
        let uv = |xy: Vec2| {
            let n = p.view_proj.project_point3(world(xy));
            Vec2::new(n.x * 0.5 + 0.5, 0.5 - n.y * 0.5)
        };
        let b = PAGE_BORDER as f32 / PAGE_TILE as f32;
        let border = PAGE_BORDER as f32 * c.texel(2);
        let inner = uv(min + border);
        assert!((inner.x - b).abs() < 1e-4 && (inner.y - (1.0 - b)).abs() < 1e-4, "{inner}");
        let outer = uv(max - border);
        assert!((outer.x - (1.0 - b)).abs() < 1e-4 && (outer.y - b).abs() < 1e-4, "{outer}");
        // A texel centre of this page's border is a texel centre of its neighbour's square.
        let next = c.projection(PageId { x: 6, ..page });
        let shared = max - Vec2::splat(border) + Vec2::new(0.5, 0.5) * c.texel(2);
        let texel_of = |p: &LightProjection| {
            let n = p.view_proj.project_point3(world(shared));
            ((n.x * 0.5 + 0.5) * PAGE_TILE as f32 - 0.5).round()
        };
        assert_eq!(texel_of(&p) - texel_of(&next), PAGE_TEXELS as f32);
        // The depth range is the clipmap's.
        let top = p
            .view_proj
            .project_point3(world((min + max) * 0.5) + c.light_from_world.inverse().z_axis.truncate() * 40.0);
        assert!(top.z.abs() < 1e-4, "{top}");
    }

    #[test]
    fn windows_are_snapped_to_whole_pages_and_keep_their_pages_as_the_camera_creeps() {
        let c = clipmap();
        let w = c.window(1, Vec2::new(3.0, -2.0));
        let still = c.window(1, Vec2::new(3.0 + c.texel(1) * 0.5, -2.0));
        assert_eq!(w, still, "half a texel moves no window");
        let camera_page = c.page_at(1, Vec2::new(3.0, -2.0));
        assert_eq!(w.index(camera_page), Some((PAGE_GRID as usize / 2) * (PAGE_GRID as usize + 1)));
        // One page on, the window moves one page and its pages are the same pages.
        let moved = c.window(1, Vec2::new(3.0 + c.page_size(1), -2.0));
        assert_eq!(moved.origin, w.origin + IVec2::X);
        for i in [0, 100, PAGE_GRID as usize * PAGE_GRID as usize - 1] {
            let page = w.page(i);
            assert_eq!(w.index(page), Some(i), "round trip");
            if page.x > w.origin.x {
                assert_eq!(moved.page(moved.index(page).unwrap()), page);
            }
        }
        assert_eq!(w.index(PageId { level: 2, ..camera_page }), None, "another level's page");
        assert_eq!(w.index(PageId { level: 1, x: w.origin.x - 1, y: w.origin.y }), None);
        assert_eq!(w.index(PageId { level: 1, x: i32::MAX, y: i32::MIN }), None);
    }

    #[test]
    fn the_level_is_the_one_whose_texel_is_nearest_the_wanted_size() {
        let c = clipmap();
        assert_eq!(c.level_for(c.texel(3), 0.0), 3);
        assert_eq!(c.level_for(c.texel(3) * 1.4, 0.0), 3);
        assert_eq!(c.level_for(c.texel(3) * 1.42, 0.0), 4);
        assert_eq!(c.level_for(c.texel(3), 1.0), 4, "a bias of an octave is one level coarser");
        assert_eq!(c.level_for(c.texel(3), -2.0), 1);
        for (odd, level) in [(f32::NAN, 0), (0.0, 0), (-1.0, 0), (1e-30, 0), (1e30, 9), (f32::INFINITY, 9)] {
            assert_eq!(c.level_for(odd, 0.0), level, "{odd}");
        }
        assert_eq!(c.level_for(1.0, f32::NAN), 0);
    }

    #[test]
    fn a_pixel_wants_its_footprint_shrunk_where_the_light_grazes_and_grown_where_it_is_seen_aslant() {
        assert_eq!(wanted_texel(2.0, 1e-3, 1.0, 1.0), 2e-3);
        assert!((wanted_texel(2.0, 1e-3, 1.0, 0.25) - 1e-3).abs() < 1e-9);
        assert!((wanted_texel(2.0, 1e-3, 0.25, 1.0) - 4e-3).abs() < 1e-9);
        assert_eq!(wanted_texel(2.0, 1e-3, -1.0, -1.0), 2e-3, "either side");
        assert_eq!(wanted_texel(2.0, 1e-3, 1.0, 0.0), wanted_texel(2.0, 1e-3, 1.0, MIN_GRAZE));
        assert_eq!(wanted_texel(2.0, 1e-3, 0.0, 1.0), wanted_texel(2.0, 1e-3, MIN_GRAZE, 1.0));
        assert_eq!(wanted_texel(-1.0, 1e-3, 1.0, 1.0), 0.0);
        assert_eq!(wanted_texel(2.0, 1e-3, f32::NAN, f32::NAN), 2e-3);
        assert_eq!(wanted_texel(f32::NAN, 1e-3, 1.0, 1.0), 0.0, "no footprint: the finest level");
        assert_eq!(wanted_texel(f32::INFINITY, 0.0, 1.0, 1.0), 0.0);
    }

    #[test]
    fn a_square_meets_the_pages_its_square_and_their_borders_reach() {
        let c = clipmap();
        let (size, border) = (c.page_size(0), PAGE_BORDER as f32 * c.texel(0));
        let inside = c.pages_meeting(0, (Vec2::splat(0.01), Vec2::splat(0.02)));
        assert_eq!(inside.pages().collect::<Vec<_>>(), vec![PageId { level: 0, x: 0, y: 0 }]);
        assert_eq!(inside.count(), 1);
        // Just past a page's square, but within its border: both pages.
        let edge = c.pages_meeting(0, (Vec2::new(size + border * 0.5, 0.01), Vec2::new(size + border * 0.6, 0.02)));
        assert_eq!(edge.count(), 2);
        assert!(edge.contains(PageId { level: 0, x: 0, y: 0 }) && edge.contains(PageId { level: 0, x: 1, y: 0 }));
        assert!(!edge.contains(PageId { level: 1, x: 0, y: 0 }), "another level");
        let huge = c.pages_meeting(0, (Vec2::splat(-1e12), Vec2::splat(1e12)));
        assert!(huge.count() > u64::from(u32::MAX), "counted without overflow");
        let nan = c.pages_meeting(0, (Vec2::NAN, Vec2::ONE));
        assert_eq!((nan.count(), nan.pages().count()), (0, 0));
        assert!(!nan.contains(PageId { level: 0, x: 0, y: 0 }));
    }

    #[test]
    fn the_depth_range_holds_the_scene_and_keeps_still_while_it_can() {
        let first = depth_range(None, (10.0, -30.0));
        assert!(first.0 >= 10.0 && first.1 <= -30.0 && first.0.fract() == 0.0, "{first:?}");
        assert_eq!(depth_range(Some(first), (11.0, -29.0)), first, "a caster bobbing inside keeps it");
        let higher = depth_range(Some(first), (first.0 + 5.0, -30.0));
        assert!(higher.0 >= first.0 + 5.0);
        let shallow = depth_range(Some(first), (1.0, -1.0));
        assert!(shallow.0 - shallow.1 < first.0 - first.1, "a scene far shallower takes a tighter range");
        for odd in [(f32::NAN, 0.0), (0.0, f32::INFINITY), (-1.0, 1.0)] {
            assert_eq!(depth_range(Some(first), odd), first, "{odd:?}");
            assert_eq!(depth_range(None, odd), (1.0, -1.0), "{odd:?}");
        }
    }

    #[test]
    fn marks_read_back_as_the_pages_of_their_windows() {
        let c = clipmap();
        let windows = vec![c.window(0, Vec2::ZERO), c.window(1, Vec2::new(5.0, 5.0))];
        let mut bits = vec![0u32; 2 * MARK_WORDS];
        bits[0] = 1 << 3;
        bits[MARK_WORDS + 2] = 1 << 31;
        let marks = PageMarks {
            light: 7,
            seq: 1,
            space: crate::shadow::PageSpace::Clipmap(c),
            windows: windows.clone(),
            bias: 0.0,
            bits,
        };
        let pages: Vec<PageId> = marks.pages().collect();
        assert_eq!(pages, vec![windows[0].page(3), windows[1].page(2 * 32 + 31)]);
        // Too few words (a broken readback) read as no marks, not a panic.
        let short = PageMarks { bits: vec![u32::MAX; 3], ..marks };
        assert_eq!(short.pages().count(), 0);
    }
}
