//! Virtual (paged) shadow maps for spot and point lights, as pure math: a light's perspective map
//! (a spot's cone, or one face of a point light's cube) seen as a square of virtual texels at its
//! finest level, each coarser level half as many a side, every level cut into pages of
//! [`PAGE_TEXELS`] as the sun's are and drawn into [`super::PAGE_TILE`]² tiles with the same
//! border. The sun's levels are a clipmap round the camera; a perspective map's levels each cover
//! the whole map, since its texels already grow with distance from the light: a pixel's level
//! follows from its footprint against the texel there, and a light far away or small on screen
//! reads few, coarse pages.

use super::{Aabb, LightProjection, PAGE_BORDER, PAGE_GRID, PAGE_TEXELS, PAGE_TILE, PageId, PageRange};
use glam::{IVec2, Mat4, Vec2, Vec3, Vec4};

/// The most pages a side of a perspective map's finest level: a window of the sun's clipmap,
/// [`PAGE_GRID`] pages of [`PAGE_TEXELS`] (7,680 texels across), so that every level lies in one
/// window with its origin at 0 and the marking and the page table read it as they read the sun's.
pub const MAX_FRUSTUM_PAGES: u32 = PAGE_GRID;

/// A perspective light's map, paged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrustumPages {
    /// The whole map's projection (a spot's, or one cube face's, as the atlas would draw it).
    pub map: LightProjection,
    /// Pages a side of level 0, a power of two; level `l` has `pages >> l` (at least one).
    pub pages: u32,
    /// Levels, from level 0 down to the level of a single page.
    pub levels: u32,
    /// Texels of border round each page's square in its tile (as [`super::Clipmap::border`]).
    pub border: u32,
}

impl FrustumPages {
    /// `map` cut into pages: `pages` a side at level 0, rounded down to a power of two between
    /// 1 and [`MAX_FRUSTUM_PAGES`], halving level by level down to one page.
    #[must_use]
    pub fn new(map: LightProjection, pages: u32) -> FrustumPages {
        let pages = 1u32 << pages.clamp(1, MAX_FRUSTUM_PAGES).ilog2();
        FrustumPages { map, pages, levels: pages.ilog2() + 1, border: PAGE_BORDER }
    }

    /// Pages a side of `level`.
    #[must_use]
    pub fn pages_across(&self, level: u32) -> u32 {
        self.pages.checked_shr(level).unwrap_or(0).max(1)
    }

    /// `1 / tan` of the map's half angle: its projection's x scale.
    fn focal(&self) -> f32 {
        self.map.proj.x_axis.x
    }

    /// World size of a texel of `level`, `distance` metres from the light along its axis.
    #[must_use]
    pub fn texel(&self, level: u32, distance: f32) -> f32 {
        2.0 * distance / (self.focal() * (self.pages_across(level) * PAGE_TEXELS) as f32)
    }

    /// World to level-0 page units, to be divided by w: a point's page on level `l` is the floor
    /// of its units over `2^l`, and w is its distance along the light's axis, so its level-0
    /// texel is `2^finest_log2 · w` (the sun's clipmap reads the same way, with w 1).
    #[must_use]
    pub fn page_from_world(&self) -> Mat4 {
        let half = self.pages as f32 * 0.5;
        // Device x and y from -1..1 to 0..pages, in step with w.
        let units = Mat4::from_cols(
            Vec4::new(half, 0.0, 0.0, 0.0),
            Vec4::new(0.0, half, 0.0, 0.0),
            Vec4::Z,
            Vec4::new(half, half, 0.0, 1.0),
        );
        units * self.map.view_proj
    }

    /// log2 of level 0's texel in metres one metre from the light along its axis.
    #[must_use]
    pub fn finest_log2(&self) -> f32 {
        self.texel(0, 1.0).log2()
    }

    /// Where world point `p` falls on the map: its x and y in normalised device coordinates
    /// (-1..1 across the map); none behind the light.
    #[must_use]
    pub fn ndc(&self, p: Vec3) -> Option<Vec2> {
        let clip = self.map.view_proj * p.extend(1.0);
        (clip.w > 0.0).then(|| clip.truncate().truncate() / clip.w).filter(|n| n.is_finite())
    }

    /// The page of `level` holding the point at `ndc` on the map; none off the map.
    #[must_use]
    pub fn page_at(&self, level: u32, ndc: Vec2) -> Option<PageId> {
        if !(ndc.is_finite() && ndc.abs().max_element() <= 1.0) {
            return None;
        }
        let n = self.pages_across(level) as f32;
        let cell = ((ndc + Vec2::ONE) * 0.5 * n).floor().min(Vec2::splat(n - 1.0));
        Some(PageId { level, x: cell.x as i32, y: cell.y as i32 })
    }

    /// The square (min, max) of normalised device x and y that `page` holds, border included.
    #[must_use]
    pub fn footprint(&self, page: PageId) -> (Vec2, Vec2) {
        let size = 2.0 / self.pages_across(page.level) as f32;
        let border = size * self.border as f32 / PAGE_TEXELS as f32;
        let min = Vec2::new(page.x as f32, page.y as f32) * size - Vec2::ONE;
        (min - Vec2::splat(border), min + Vec2::splat(size + border))
    }

    /// The projection `page` is drawn with: the map's, narrowed to the page's square and border
    /// (an off-axis frustum with the map's near and far planes).
    #[must_use]
    pub fn projection(&self, page: PageId) -> LightProjection {
        let (min, max) = self.footprint(page);
        let (centre, scale) = ((min + max) * 0.5, Vec2::splat(2.0) / (max - min));
        // Applied to clip space before the divide, so it moves x and y in step with w.
        let narrow = Mat4::from_cols(
            Vec4::new(scale.x, 0.0, 0.0, 0.0),
            Vec4::new(0.0, scale.y, 0.0, 0.0),
            Vec4::Z,
            Vec4::new(-centre.x * scale.x, -centre.y * scale.y, 0.0, 1.0),
        );
        let proj = narrow * self.map.proj;
        let per_metre = (max.x - min.x) / (self.focal() * PAGE_TILE as f32);
        LightProjection { view: self.map.view, proj, view_proj: proj * self.map.view, texel: Vec2::new(0.0, per_metre) }
    }

    /// The level a pixel that wants texels of `wanted` metres, `distance` metres from the light
    /// along its axis, reads, `bias` octaves coarser (negative: finer): the nearest in log2,
    /// within the levels. No size at all (NaN, zero, negative) reads the finest.
    #[must_use]
    pub fn level_for(&self, wanted: f32, distance: f32, bias: f32) -> u32 {
        let octaves = (wanted / self.texel(0, distance)).log2() + bias;
        if octaves.is_nan() {
            return 0;
        }
        octaves.round().clamp(0.0, (self.levels - 1) as f32) as u32
    }

    /// The pages of every level whose tiles (border included) `b` lies across, seen from the
    /// light: what a caster moving through `b` dirties. Only the part of `b` between the map's
    /// near plane and its far one counts (what its drawing keeps): a box reaching from behind the
    /// light to before it crosses the pages its part ahead lies across, one off the map, wholly
    /// behind the light, or wholly nearer than the near plane or past the far one, none.
    #[must_use]
    pub fn crossing(&self, b: &Aabb) -> Vec<PageRange> {
        if !b.is_usable() {
            return Vec::new();
        }
        let ahead = ahead_of_near(b.corners().map(|c| self.map.view_proj * c.extend(1.0)));
        if ahead.is_empty() || ahead.iter().all(|c| c.z > c.w) {
            return Vec::new();
        }
        let ndc = ahead.iter().map(|c| c.truncate().truncate() / c.w);
        let min = ndc.clone().fold(Vec2::INFINITY, Vec2::min);
        let max = ndc.fold(Vec2::NEG_INFINITY, Vec2::max);
        if min.cmpgt(Vec2::ONE).any() || max.cmplt(Vec2::splat(-1.0)).any() {
            return Vec::new();
        }
        (0..self.levels)
            .map(|level| {
                let side = self.pages_across(level);
                // A tile's border reaches `border` texels past its page's square.
                let border = 2.0 / side as f32 * self.border as f32 / PAGE_TEXELS as f32;
                let cell = |v: f32| (((v + 1.0) * 0.5 * side as f32).floor() as i32).clamp(0, side as i32 - 1);
                let lo = IVec2::new(cell(min.x - border), cell(min.y - border));
                let hi = IVec2::new(cell(max.x + border), cell(max.y + border));
                PageRange { level, min: lo, max: hi }
            })
            .collect()
    }
}

/// The corners of a box in clip space (`clips`, in [`Aabb::corners`] order) on or past the near
/// plane (clip depth 0), and where its twelve edges cross it: the points whose bounds bound the
/// part of the box a map's drawing keeps, however much of it lies behind.
fn ahead_of_near(clips: [Vec4; 8]) -> Vec<Vec4> {
    let mut ahead: Vec<Vec4> = clips.iter().copied().filter(|c| c.z >= 0.0).collect();
    for (i, bit) in (0..8).flat_map(|i| [1, 2, 4].map(|bit| (i, bit))).filter(|(i, bit)| i & bit == 0) {
        let (p, q) = (clips[i], clips[i | bit]);
        if (p.z >= 0.0) != (q.z >= 0.0) {
            ahead.push(p.lerp(q, p.z / (p.z - q.z)));
        }
    }
    ahead
}

/// Pages a side of the finest level a perspective map needs (`focal`: its projection's x scale)
/// for a texel of `finest` metres at `nearest` metres from the light: the sharpest any visible
/// pixel of it asks for, where it is nearest the light. A power of two, 1 to
/// [`MAX_FRUSTUM_PAGES`]; one page for odd input.
#[must_use]
pub fn pages_for(focal: f32, nearest: f32, finest: f32) -> u32 {
    let texels = 2.0 * nearest / (focal * finest);
    if !(texels.is_finite() && texels > 0.0) {
        return 1;
    }
    let pages = (texels / PAGE_TEXELS as f32).ceil().min(MAX_FRUSTUM_PAGES as f32) as u32;
    pages.max(1).next_power_of_two().min(MAX_FRUSTUM_PAGES)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::spot_projection;

    /// A 60° spot at (1, 4, -2) pointing down and a little along +X, 16 pages across level 0.
    fn spot() -> FrustumPages {
        let map = spot_projection(Vec3::new(1.0, 4.0, -2.0), Vec3::new(0.2, -1.0, 0.0), 30f32.to_radians(), 20.0, 1);
        FrustumPages::new(map, 16)
    }

    /// The world point `distance` metres along the spot's axis whose map position is `ndc`.
    fn at(p: &FrustumPages, ndc: Vec2, distance: f32) -> Vec3 {
        let view = Vec3::new(ndc.x * distance / p.focal(), ndc.y * distance / p.map.proj.y_axis.y, -distance);
        p.map.view.inverse().transform_point3(view)
    }

    #[test]
    fn levels_halve_the_pages_down_to_one_and_odd_counts_round_down() {
        let p = spot();
        assert_eq!((p.pages, p.levels), (16, 5));
        assert_eq!((0..6).map(|l| p.pages_across(l)).collect::<Vec<_>>(), [16, 8, 4, 2, 1, 1]);
        assert_eq!(p.pages_across(u32::MAX), 1);
        for (asked, got) in [(0, 1), (1, 1), (3, 2), (100, 64), (128, 128), (u32::MAX, MAX_FRUSTUM_PAGES)] {
            assert_eq!(FrustumPages::new(p.map, asked).pages, got, "{asked}");
        }
        assert!((p.texel(1, 5.0) - 2.0 * p.texel(0, 5.0)).abs() < 1e-7);
        assert!((p.texel(0, 10.0) - 2.0 * p.texel(0, 5.0)).abs() < 1e-7, "texels grow with distance");
    }

    #[test]
    fn a_point_lies_in_the_page_that_holds_it_and_off_the_map_in_none() {
        let p = spot();
        for level in 0..p.levels {
            for ndc in [Vec2::ZERO, Vec2::new(-1.0, -1.0), Vec2::new(1.0, 1.0), Vec2::new(0.37, -0.81)] {
                let world = at(&p, ndc, 6.0);
                let seen = p.ndc(world).unwrap();
                assert!((seen - ndc).length() < 1e-4, "{ndc} came back as {seen}");
                let page = p.page_at(level, ndc).unwrap();
                let (min, max) = p.footprint(page);
                assert!(ndc.cmpge(min).all() && ndc.cmple(max).all(), "{ndc} in {page:?}");
                let n = p.pages_across(level) as i32;
                assert!((0..n).contains(&page.x) && (0..n).contains(&page.y));
            }
        }
        assert_eq!(p.page_at(0, Vec2::new(1.01, 0.0)), None);
        assert_eq!(p.page_at(0, Vec2::NAN), None);
        let behind = p.map.view.inverse().transform_point3(Vec3::new(0.0, 0.0, 3.0));
        assert_eq!(p.ndc(behind), None, "behind the light");
    }

    #[test]
    fn a_page_projection_fills_its_tile_with_its_square_and_border() {
        let p = spot();
        let page = PageId { level: 1, x: 5, y: 2 };
        let projection = p.projection(page);
        let (min, max) = p.footprint(page);
        let inset = p.border as f32 / PAGE_TILE as f32 * 2.0;
        for distance in [0.5, 6.0, 19.0] {
            for (corner, expected) in [(min, Vec2::splat(-1.0)), (max, Vec2::ONE)] {
                let clip = projection.view_proj * at(&p, corner, distance).extend(1.0);
                let got = clip.truncate().truncate() / clip.w;
                assert!((got - expected).length() < 1e-3, "{corner} at {distance} m: {got}");
            }
            // The page's own square starts `border` texels inside the tile.
            let inner = min + (max - min) * (p.border as f32 / PAGE_TILE as f32);
            let clip = projection.view_proj * at(&p, inner, distance).extend(1.0);
            assert!((clip.x / clip.w + 1.0 - inset).abs() < 1e-3);
            // Depth is the map's own.
            let whole = p.map.view_proj * at(&p, inner, distance).extend(1.0);
            assert!((clip.z / clip.w - whole.z / whole.w).abs() < 1e-5);
        }
        // A tile texel is a texel of the page's level.
        assert!((projection.texel.y * 6.0 - p.texel(1, 6.0)).abs() < 1e-6);
    }

    #[test]
    fn page_units_over_w_name_the_page_and_w_scales_the_finest_texel() {
        let p = spot();
        let to_units = p.page_from_world();
        for (ndc, distance) in [(Vec2::ZERO, 1.0), (Vec2::new(0.9, -0.3), 4.0), (Vec2::new(-0.99, 0.99), 15.0)] {
            let world = at(&p, ndc, distance);
            let u = to_units * world.extend(1.0);
            assert!((u.w - distance).abs() < 1e-3, "w is the distance along the axis: {}", u.w);
            for level in 0..p.levels {
                let cell = (u.truncate().truncate() / u.w / 2f32.powi(level as i32)).floor();
                let page = p.page_at(level, ndc).unwrap();
                assert_eq!((cell.x as i32, cell.y as i32), (page.x, page.y), "{ndc} on level {level}");
            }
            let texel = 2f32.powf(p.finest_log2()) * u.w;
            assert!((texel - p.texel(0, distance)).abs() < 1e-6 * distance);
        }
    }

    #[test]
    fn the_level_is_the_one_whose_texel_is_nearest_the_wanted_size() {
        let p = spot();
        for level in 0..p.levels {
            assert_eq!(p.level_for(p.texel(level, 7.0), 7.0, 0.0), level);
            assert_eq!(p.level_for(p.texel(level, 7.0) * 1.3, 7.0, 0.0), level);
        }
        assert_eq!(p.level_for(p.texel(2, 7.0), 7.0, 1.0), 3, "a bias of one octave coarser");
        for odd in [f32::NAN, 0.0, -1.0] {
            assert_eq!(p.level_for(odd, 7.0, 0.0), 0, "{odd}");
        }
        assert_eq!(p.level_for(1e9, 7.0, 0.0), p.levels - 1);
        assert_eq!(p.level_for(0.01, 0.0, 0.0), p.levels - 1, "at the light every texel is a point");
    }

    #[test]
    fn a_map_takes_the_pages_its_nearest_sharpest_pixel_asks_for() {
        let focal = 1.0 / 30f32.to_radians().tan();
        // 2 m from the light, 1 mm texels: 2 · 2 · tan 30° / 0.001 = 2,309 texels, 42 pages, 64.
        assert_eq!(pages_for(focal, 2.0, 0.001), 64);
        assert_eq!(pages_for(focal, 2.0, 1.0), 1, "a far, coarse light takes one page");
        assert_eq!(pages_for(focal, 2.0, 1e-9), MAX_FRUSTUM_PAGES);
        for odd in [f32::NAN, 0.0, -3.0, f32::INFINITY] {
            assert_eq!(pages_for(focal, odd, 0.001), 1, "{odd}");
            assert_eq!(pages_for(focal, 2.0, odd), 1, "{odd}");
        }
    }
}
