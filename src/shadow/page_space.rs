//! A paged light's virtual map whichever shape it takes: the sun's clipmap round the camera
//! ([`Clipmap`]), a spot's perspective map ([`FrustumPages`]) or a point light's cube of them
//! ([`CubePages`]). Each addresses a point the same way (a `page_from_world` matrix, a cube's
//! face's: level-0 page units over w, a texel of `2^finest_log2 · w` metres; w is 1 for the sun,
//! the distance along the light's axis for a spot or a face), so the marking, the page table and
//! the lookups read them alike; what differs (windows, what a moving box crosses, when old marks
//! still name the same pages, which pages exist) is answered here.

use super::{
    Aabb, CUBE_FACE_PAGES, Clipmap, CubePages, FrustumPages, LightProjection, PAGE_GRID, PageId, PageRange, Window,
};
use glam::{IVec2, Mat3, Mat4, Vec2, Vec3};

/// The pages of a paged light's virtual map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PageSpace {
    /// A sun's levels round the camera.
    Clipmap(Clipmap),
    /// A spot's perspective map, every level over the whole map.
    Frustum(FrustumPages),
    /// A point light's six faces, each as a spot's map, side by side on one grid.
    Cube(CubePages),
}

impl PageSpace {
    /// Its levels.
    #[must_use]
    pub fn levels(&self) -> u32 {
        match self {
            PageSpace::Clipmap(c) => c.levels,
            PageSpace::Frustum(f) => f.levels,
            PageSpace::Cube(c) => c.levels(),
        }
    }

    /// log2 of level 0's texel in metres where w is 1 (see the module's notes).
    #[must_use]
    pub fn finest_log2(&self) -> f32 {
        match self {
            PageSpace::Clipmap(c) => c.finest_log2 as f32,
            PageSpace::Frustum(f) => f.finest_log2(),
            PageSpace::Cube(c) => c.finest_log2(),
        }
    }

    /// World to level-0 page units, to be divided by w (a cube's first face's: see
    /// [`PageSpace::faces`]).
    #[must_use]
    pub fn page_from_world(&self) -> Mat4 {
        match self {
            PageSpace::Clipmap(c) => c.page_from_world(),
            PageSpace::Frustum(f) => f.page_from_world(),
            PageSpace::Cube(c) => c.page_from_world(0),
        }
    }

    /// Its faces: a cube's six, one for the others. Each face has a `page_from_world` of its
    /// own ([`PageSpace::face_matrices`]) and a layer of the coarse map.
    #[must_use]
    pub fn faces(&self) -> usize {
        if matches!(self, PageSpace::Cube(_)) { 6 } else { 1 }
    }

    /// Each face's `page_from_world`, in [`super::CUBE_FACES`] order for a cube (the face holding
    /// a point has the largest w); a map with one face has it six times over.
    #[must_use]
    pub fn face_matrices(&self) -> [Mat4; 6] {
        match self {
            PageSpace::Cube(c) => std::array::from_fn(|face| c.page_from_world(face)),
            _ => [self.page_from_world(); 6],
        }
    }

    /// True when `page` is one of its pages: any of a clipmap's, one on a perspective map or on
    /// a cube's face (marks read back wrong could name others).
    #[must_use]
    pub fn holds(&self, page: PageId) -> bool {
        match self {
            PageSpace::Clipmap(c) => page.level < c.levels,
            PageSpace::Frustum(f) => {
                let side = f.pages_across(page.level) as i32;
                page.level < f.levels && (0..side).contains(&page.x) && (0..side).contains(&page.y)
            }
            PageSpace::Cube(c) => page.level < c.levels() && c.face_of(page).is_some(),
        }
    }

    /// Pages across and down from level `level`'s window origin where its pages may lie: a
    /// clipmap's whole window, a perspective map's level, a cube's six faces (a page table holds
    /// these alone).
    #[must_use]
    pub fn level_grid(&self, level: u32) -> IVec2 {
        match self {
            PageSpace::Clipmap(_) => IVec2::splat(PAGE_GRID as i32),
            PageSpace::Frustum(f) => IVec2::splat(f.pages_across(level) as i32),
            PageSpace::Cube(_) => CubePages::grid(level),
        }
    }

    /// The projection `page` is drawn with.
    #[must_use]
    pub fn projection(&self, page: PageId) -> LightProjection {
        match self {
            PageSpace::Clipmap(c) => c.projection(page),
            PageSpace::Frustum(f) => f.projection(page),
            // Only pages it holds are drawn; any other is drawn as its first face's first.
            PageSpace::Cube(c) => {
                c.projection(page).unwrap_or_else(|| c.face(0).projection(PageId { x: 0, y: 0, ..page }))
            }
        }
    }

    /// The pages of each level that may be asked for with the camera at `camera`: a clipmap's
    /// windows round it; a perspective map's whole levels, each in a window at the origin.
    #[must_use]
    pub fn windows(&self, camera: Vec3) -> Vec<Window> {
        match self {
            PageSpace::Clipmap(c) => c.windows(c.across(camera)),
            _ => (0..self.levels()).map(|level| Window { level, origin: IVec2::ZERO }).collect(),
        }
    }

    /// True when its shadow ends at the shadow distance, fading out before it (a clipmap's
    /// levels reach that far round the camera); a perspective map reaches as far as its light.
    #[must_use]
    pub fn fades(&self) -> bool {
        matches!(self, PageSpace::Clipmap(_))
    }

    /// Level-0 page units a side of a perspective map: a point whose units lie outside
    /// `0..extent` is off it. None for a clipmap, which has no edge.
    #[must_use]
    pub fn extent(&self) -> Option<f32> {
        match self {
            PageSpace::Clipmap(_) | PageSpace::Cube(_) => None,
            PageSpace::Frustum(f) => Some(f.pages as f32),
        }
    }

    /// Level-0 page units a side of a cube's face: a point's units are held on its face's square
    /// (a point on a face's edge would round onto the next face's first page). None for others.
    #[must_use]
    pub fn face_side(&self) -> Option<f32> {
        match self {
            PageSpace::Cube(_) => Some(CUBE_FACE_PAGES as f32),
            _ => None,
        }
    }

    /// The light-space depth range every page shares (a clipmap's; a perspective map's depth is
    /// its projection's).
    #[must_use]
    pub fn depth(&self) -> Option<(f32, f32)> {
        match self {
            PageSpace::Clipmap(c) => Some(c.depth),
            PageSpace::Frustum(_) | PageSpace::Cube(_) => None,
        }
    }

    /// True when marks made against `marked` name the same pages as `self` has: a clipmap of the
    /// same turn and levels (a new depth range changes what a page holds, not which page it is; a
    /// grid that follows the camera, unsnapped, moves a page by less than itself a frame), or the
    /// same perspective map cut the same way.
    #[must_use]
    pub fn same_pages(&self, marked: &PageSpace) -> bool {
        match (self, marked) {
            (PageSpace::Clipmap(now), PageSpace::Clipmap(then)) => {
                let turn = |c: &Clipmap| Mat3::from_mat4(c.light_from_world);
                (turn(now), now.finest_log2, now.levels) == (turn(then), then.finest_log2, then.levels)
            }
            (PageSpace::Frustum(now), PageSpace::Frustum(then)) => {
                (now.map.view_proj, now.pages) == (then.map.view_proj, then.pages)
            }
            (PageSpace::Cube(now), PageSpace::Cube(then)) => now == then,
            _ => false,
        }
    }

    /// True when `self` is `other` cut the same way, though the light may have moved or turned:
    /// a clipmap naming the same pages ([`Self::same_pages`]), a spot's map of the same pages
    /// and levels, a cube of the same margin. A page of one then lies about where the same page
    /// of the other does, a frame's movement away: what the pixels asked of one, they ask of the
    /// other, and its pages are drawn again where they are.
    #[must_use]
    pub fn same_layout(&self, other: &PageSpace) -> bool {
        match (self, other) {
            (PageSpace::Frustum(a), PageSpace::Frustum(b)) => (a.pages, a.levels) == (b.pages, b.levels),
            (PageSpace::Cube(a), PageSpace::Cube(b)) => a.margin == b.margin,
            _ => self.same_pages(other),
        }
    }

    /// `p`'s level-0 page units (divided by w) and its w; none behind the light.
    #[must_use]
    pub fn units(&self, p: Vec3) -> Option<(Vec2, f32)> {
        if let PageSpace::Cube(c) = self {
            return c.units(p).map(|(_, units, w)| (units, w));
        }
        let u = self.page_from_world() * p.extend(1.0);
        let units = u.truncate().truncate() / u.w;
        (u.w > 0.0 && units.is_finite()).then_some((units, u.w))
    }

    /// The page of `level` that holds `p`; none behind the light or off a perspective map.
    #[must_use]
    pub fn page_at(&self, level: u32, p: Vec3) -> Option<PageId> {
        match self {
            PageSpace::Clipmap(c) => Some(c.page_at(level, c.across(p))),
            PageSpace::Frustum(f) => f.page_at(level, f.ndc(p)?),
            PageSpace::Cube(c) => c.page_at(level, p),
        }
    }

    /// World size of a texel of `level` at `p` (metres); infinite behind the light.
    #[must_use]
    pub fn texel(&self, level: u32, p: Vec3) -> f32 {
        self.units(p).map_or(f32::INFINITY, |(_, w)| (self.finest_log2() + level as f32).exp2() * w)
    }

    /// The level a pixel at `p` that wants texels of `wanted` metres reads, `bias` octaves
    /// coarser (negative: finer): the nearest in log2, within the levels; the finest for a pixel
    /// that wants no size at all (NaN, zero, negative) and the coarsest behind the light.
    #[must_use]
    pub fn level_for(&self, wanted: f32, p: Vec3, bias: f32) -> u32 {
        // Behind the light w is 0: every texel there is a point, and the coarsest is chosen.
        let w = self.units(p).map_or(0.0, |(_, w)| w);
        let octaves = wanted.log2() - self.finest_log2() - w.log2() + bias;
        if octaves.is_nan() {
            return 0;
        }
        octaves.round().clamp(0.0, (self.levels() - 1) as f32) as u32
    }

    /// The pages of every level whose tiles (border included) `b` lies across, seen from the
    /// light: what a caster moving through `b` dirties. A box reaching behind a spot crosses its
    /// whole map; one off its map crosses none.
    #[must_use]
    pub fn crossing(&self, b: &Aabb) -> Vec<PageRange> {
        if !b.is_usable() {
            return Vec::new();
        }
        match self {
            PageSpace::Clipmap(c) => {
                let across = b.transformed(&c.light_from_world);
                let square = (across.min.truncate(), across.max.truncate());
                (0..c.levels).map(|level| c.pages_meeting(level, square)).collect()
            }
            PageSpace::Frustum(f) => f.crossing(b),
            PageSpace::Cube(c) => c.crossing(b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::spot_projection;

    fn spot() -> PageSpace {
        let map = spot_projection(Vec3::new(1.0, 4.0, -2.0), Vec3::new(0.2, -1.0, 0.0), 30f32.to_radians(), 20.0, 1);
        PageSpace::Frustum(FrustumPages::new(map, 16))
    }

    fn sun() -> PageSpace {
        PageSpace::Clipmap(Clipmap::new(Vec3::new(0.2, -1.0, 0.3), 60.0, (20.0, -20.0)))
    }

    #[test]
    fn both_shapes_find_a_points_page_from_its_units_over_w() {
        let ground = [Vec3::new(1.3, 0.0, -2.2), Vec3::new(2.5, 0.2, -1.0), Vec3::new(0.0, 0.5, -3.5)];
        for space in [spot(), sun()] {
            for p in ground {
                let (units, _) = space.units(p).unwrap();
                for level in 0..space.levels() {
                    let cell = (units / (level as f32).exp2()).floor();
                    let page = space.page_at(level, p).unwrap();
                    assert_eq!((page.x, page.y), (cell.x as i32, cell.y as i32), "{space:?} {p} {level}");
                }
            }
        }
    }

    #[test]
    fn the_level_matches_each_shapes_own_and_odd_sizes_read_the_finest() {
        let p = Vec3::new(1.3, 0.0, -2.2);
        let (PageSpace::Frustum(f), PageSpace::Clipmap(c)) = (spot(), sun()) else { unreachable!() };
        let w = spot().units(p).unwrap().1;
        for wanted in [1e-4, 3e-3, 0.02, 0.5, 40.0] {
            assert_eq!(spot().level_for(wanted, p, 0.5), f.level_for(wanted, w, 0.5), "{wanted}");
            assert_eq!(sun().level_for(wanted, p, -1.0), c.level_for(wanted, -1.0), "{wanted}");
            let level = spot().level_for(wanted, p, 0.0);
            assert!((spot().texel(level, p) - f.texel(level, w)).abs() < 1e-6 * f.texel(level, w));
        }
        for space in [spot(), sun()] {
            for odd in [f32::NAN, 0.0, -1.0] {
                assert_eq!(space.level_for(odd, p, 0.0), 0, "{odd}");
            }
        }
        let behind = Vec3::new(1.0, 9.0, -2.0);
        assert_eq!(spot().page_at(0, behind), None);
        assert_eq!(spot().level_for(0.01, behind, 0.0), spot().levels() - 1);
        assert_eq!(spot().texel(0, behind), f32::INFINITY);
    }

    #[test]
    fn a_spots_windows_hold_each_whole_level_at_the_origin() {
        let PageSpace::Frustum(f) = spot() else { unreachable!() };
        let windows = spot().windows(Vec3::new(50.0, 3.0, 9.0));
        assert_eq!(windows.len(), f.levels as usize);
        for w in &windows {
            let side = f.pages_across(w.level) as i32;
            let last = PageId { level: w.level, x: side - 1, y: side - 1 };
            assert!(w.index(PageId { level: w.level, x: 0, y: 0 }).is_some() && w.index(last).is_some());
        }
        assert_eq!(sun().windows(Vec3::ZERO).len(), sun().levels() as usize);
    }

    #[test]
    fn a_moving_box_dirties_the_pages_it_lies_across_and_no_others() {
        let space = spot();
        let p = Vec3::new(1.3, 0.0, -2.2);
        let ranges = space.crossing(&Aabb::new(p - 0.01, p + 0.01));
        assert_eq!(ranges.len(), space.levels() as usize);
        for r in &ranges {
            assert!(r.contains(space.page_at(r.level, p).unwrap()), "{r:?}");
            assert!(r.count() <= 4, "a small box is in one page, or beside a border: {r:?}");
        }
        let off = Vec3::new(30.0, 0.0, -2.0);
        assert!(space.crossing(&Aabb::new(off - 0.5, off + 0.5)).is_empty(), "off the map");
        let around = space.crossing(&Aabb::new(Vec3::new(-1.0, 3.0, -4.0), Vec3::new(3.0, 5.0, 0.0)));
        let PageSpace::Frustum(f) = space else { unreachable!() };
        assert_eq!(around[0].count(), u64::from(f.pages * f.pages), "round the light: the whole map");
        assert!(space.crossing(&Aabb::new(Vec3::NAN, Vec3::ONE)).is_empty());
        let behind = Vec3::new(1.0, 9.0, -2.0);
        assert!(space.crossing(&Aabb::new(behind - 0.5, behind + 0.5)).is_empty(), "wholly behind the light");
        // The sun's, as its clipmap finds them.
        let PageSpace::Clipmap(c) = sun() else { unreachable!() };
        let b = Aabb::new(p - 0.3, p + 0.3);
        let across = b.transformed(&c.light_from_world);
        assert_eq!(sun().crossing(&b)[2], c.pages_meeting(2, (across.min.truncate(), across.max.truncate())));
    }

    #[test]
    fn old_marks_name_the_same_pages_until_the_light_turns_or_moves() {
        let PageSpace::Clipmap(c) = sun() else { unreachable!() };
        let deeper = PageSpace::Clipmap(Clipmap { depth: (40.0, -40.0), ..c });
        assert!(sun().same_pages(&deeper), "a new depth range keeps the pages");
        assert!(!sun().same_pages(&spot()) && !spot().same_pages(&sun()));
        assert!(spot().same_pages(&spot()));
        let moved = spot_projection(Vec3::new(1.0, 4.1, -2.0), Vec3::new(0.2, -1.0, 0.0), 30f32.to_radians(), 20.0, 1);
        let map = moved;
        let moved = PageSpace::Frustum(FrustumPages::new(moved, 16));
        assert!(!spot().same_pages(&moved));
        assert!(spot().same_layout(&moved) && !spot().same_layout(&PageSpace::Frustum(FrustumPages::new(map, 8))));
        assert!(sun().same_layout(&deeper) && !sun().same_layout(&spot()) && !spot().same_layout(&sun()));
        let lamp = |x: f32, margin| PageSpace::Cube(CubePages::new(Vec3::new(x, 2.0, 0.0), 8.0, margin));
        assert!(lamp(0.0, 4).same_layout(&lamp(0.1, 4)) && !lamp(0.0, 4).same_pages(&lamp(0.1, 4)));
        assert!(!lamp(0.0, 4).same_layout(&lamp(0.0, 2)) && !lamp(0.0, 4).same_layout(&spot()));
        assert_eq!((spot().depth(), sun().depth()), (None, Some((20.0, -20.0))));
    }
}
