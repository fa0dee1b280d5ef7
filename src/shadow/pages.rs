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
pub const PAGE_TILE: u32 = 128;
/// Texels of border on each side of a page's tile: as far as any filter reaches past the texel
/// it samples ([`crate::components::ShadowMethod::reach`]), as a cube face's margin.
pub const PAGE_BORDER: u32 = 4;
/// Texels a side of a page's own square: the spacing of pages on their level's grid.
pub const PAGE_TEXELS: u32 = PAGE_TILE - 2 * PAGE_BORDER;
/// Pages along a side of a level's window round the camera.
pub const PAGE_GRID: u32 = 64;
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
        }
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
        let (size, texel) = (self.page_size(page.level), self.texel(page.level));
        let border = PAGE_BORDER as f32 * texel;
        let min = Vec2::new(page.x as f32, page.y as f32) * size - border;
        let max = min + Vec2::splat(size + 2.0 * border);
        let (near_z, far_z) = self.depth;
        let proj = directx::orthographic(min.x, max.x, min.y, max.y, -near_z, -far_z);
        let view = self.light_from_world;
        LightProjection { view, proj, view_proj: proj * view, texel: Vec2::new(texel, 0.0) }
    }

    /// The square across the light (min, max) that `page` holds, border included.
    #[must_use]
    pub fn footprint(&self, page: PageId) -> (Vec2, Vec2) {
        let (size, border) = (self.page_size(page.level), PAGE_BORDER as f32 * self.texel(page.level));
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
/// view it plans for ([`COARSEST_PIXEL_ANGLE`]) at the shadow distance, from a finest texel of
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
/// surface (it stretches by 1 / |n·l|), covers as much of it as the pixel does (`pixel_area`,
/// square metres). `n_dot_l` is held at [`MIN_GRAZE`] or more. The WGSL twin is `wanted_texel`
/// in pages.wgsl.
#[must_use]
pub fn wanted_texel(pixel_area: f32, n_dot_l: f32) -> f32 {
    let graze = if n_dot_l.is_nan() { 1.0 } else { n_dot_l.abs().clamp(MIN_GRAZE, 1.0) };
    (pixel_area.max(0.0) * graze).sqrt()
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
        let (x, y) = (i64::from(page.x) - i64::from(self.origin.x), i64::from(page.y) - i64::from(self.origin.y));
        let grid = i64::from(PAGE_GRID);
        (page.level == self.level && (0..grid).contains(&x) && (0..grid).contains(&y)).then(|| (y * grid + x) as usize)
    }

    /// The page at `index` (row by row) of the window.
    #[must_use]
    pub fn page(&self, index: usize) -> PageId {
        let grid = PAGE_GRID as usize;
        let (x, y) = ((index % grid) as i32, (index / grid) as i32);
        PageId { level: self.level, x: self.origin.x.saturating_add(x), y: self.origin.y.saturating_add(y) }
    }

    /// The pages of the window that meet the square `min..max` across the light, on a clipmap
    /// whose pages on this level are `size` metres a side (and whose border is `border` metres).
    pub fn pages_meeting(&self, (min, max): (Vec2, Vec2), size: f32, border: f32) -> impl Iterator<Item = PageId> {
        // A page's tile reaches `border` past its square, so a box that far outside still meets it.
        let cell = |v: f32| (v / size).floor().clamp(i32::MIN as f32 / 2.0, i32::MAX as f32 / 2.0) as i32;
        let grid = PAGE_GRID as i32;
        let lo = |v: f32, o: i32| cell(v - border).clamp(o, o + grid);
        let hi = |v: f32, o: i32| cell(v + border).clamp(o - 1, o + grid - 1);
        let usable = min.is_finite() && max.is_finite() && size > 0.0;
        let (x0, x1) = if usable { (lo(min.x, self.origin.x), hi(max.x, self.origin.x)) } else { (1, 0) };
        let (y0, y1) = if usable { (lo(min.y, self.origin.y), hi(max.y, self.origin.y)) } else { (1, 0) };
        let level = self.level;
        (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| PageId { level, x, y }))
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
    fn a_pixel_wants_its_footprint_shrunk_where_the_light_grazes() {
        assert_eq!(wanted_texel(4e-6, 1.0), 2e-3);
        assert!((wanted_texel(4e-6, 0.25) - 1e-3).abs() < 1e-9);
        assert_eq!(wanted_texel(4e-6, -1.0), 2e-3, "either side");
        assert_eq!(wanted_texel(4e-6, 0.0), wanted_texel(4e-6, MIN_GRAZE));
        assert_eq!(wanted_texel(-1.0, 1.0), 0.0);
        assert_eq!(wanted_texel(4e-6, f32::NAN), 2e-3);
        assert_eq!(wanted_texel(f32::NAN, 1.0), 0.0, "no footprint: the finest level");
    }

    #[test]
    fn a_box_meets_the_pages_its_square_and_their_borders_reach() {
        let c = clipmap();
        let w = c.window(0, Vec2::ZERO);
        let (size, border) = (c.page_size(0), PAGE_BORDER as f32 * c.texel(0));
        let inside = (Vec2::splat(0.01), Vec2::splat(0.02));
        assert_eq!(w.pages_meeting(inside, size, border).collect::<Vec<_>>(), vec![PageId { level: 0, x: 0, y: 0 }]);
        // Just past a page's square, but within its border: both pages.
        let edge = (Vec2::new(size + border * 0.5, 0.01), Vec2::new(size + border * 0.6, 0.02));
        assert_eq!(w.pages_meeting(edge, size, border).count(), 2);
        // A box larger than the window meets every page of it, no more.
        let huge = (Vec2::splat(-1e9), Vec2::splat(1e9));
        assert_eq!(w.pages_meeting(huge, size, border).count(), (PAGE_GRID * PAGE_GRID) as usize);
        let nan = (Vec2::NAN, Vec2::ONE);
        assert_eq!(w.pages_meeting(nan, size, border).count(), 0);
        let outside = (Vec2::splat(1e6), Vec2::splat(1e6 + 1.0));
        assert_eq!(w.pages_meeting(outside, size, border).count(), 0);
    }
}
