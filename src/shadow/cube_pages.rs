//! A point light's cube in pages, as pure math: each of the six faces a perspective map in pages
//! ([`FrustumPages`]), the faces laid out three across and two down on one grid of pages, so that
//! every level lies in one window of the marks with its origin at 0, as a spot's does. A point's
//! face is the largest axis of its direction from the light (as the cube maps pick it), and its
//! page units are that face's matrix over w, the face's place on the grid built into the matrix:
//! the marking and the lookups read them as they read a spot's, given six matrices in place of
//! one.

use super::{
    Aabb, FrustumPages, LightProjection, PAGE_BORDER, PAGE_GRID, PAGE_TEXELS, PageId, PageRange, cube_face,
    cube_face_projection,
};
use glam::{IVec2, Mat4, Vec2, Vec3, Vec4};

/// Faces along a row of the grid (two rows).
pub const CUBE_ACROSS: u32 = 3;

/// Pages a side of each face at the finest level: six faces of them fit a window of
/// [`PAGE_GRID`] pages (three of 32 across, two down), 1,792 texels across a face, a texel about
/// a millimetre a metre from the light.
pub const CUBE_FACE_PAGES: u32 = 32;

const _: () = assert!(CUBE_ACROSS * CUBE_FACE_PAGES <= PAGE_GRID);

/// A point light's cube of maps, paged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubePages {
    /// Where the light is.
    pub position: Vec3,
    /// Where its light fades to nothing: the faces' far plane.
    pub range: f32,
    /// Texels of the finest level each face reaches past its 90° edge.
    pub margin: u32,
    /// Texels of border round each page's square in its tile (as [`FrustumPages::border`]).
    pub border: u32,
}

impl CubePages {
    /// The cube of a light at `position` reaching `range`, each face reaching `margin` texels of
    /// the finest level past its 90° edge (as the cube maps do, for the filters at the seams).
    #[must_use]
    pub fn new(position: Vec3, range: f32, margin: u32) -> CubePages {
        CubePages { position, range, margin, border: PAGE_BORDER }
    }

    /// Face `face` (in [`super::CUBE_FACES`] order): a perspective map of [`CUBE_FACE_PAGES`]
    /// pages a side at level 0.
    #[must_use]
    pub fn face(&self, face: usize) -> FrustumPages {
        let side = CUBE_FACE_PAGES * PAGE_TEXELS;
        let map = cube_face_projection(self.position, self.range, side, self.margin, face);
        FrustumPages { border: self.border, ..FrustumPages::new(map, CUBE_FACE_PAGES) }
    }

    /// Pages a side of each face on `level` (every face's, as [`FrustumPages::pages_across`]).
    fn side(level: u32) -> i32 {
        CUBE_FACE_PAGES.checked_shr(level).unwrap_or(0).max(1) as i32
    }

    /// Pages across and down of level `level`'s grid: its six faces, three across and two down.
    #[must_use]
    pub fn grid(level: u32) -> IVec2 {
        IVec2::new(CUBE_ACROSS as i32, 2) * Self::side(level)
    }

    /// Levels, from level 0 down to faces of a single page.
    #[must_use]
    pub fn levels(&self) -> u32 {
        CUBE_FACE_PAGES.ilog2() + 1
    }

    /// Where face `face`'s first page is on level `level`'s grid.
    #[must_use]
    pub fn face_origin(&self, face: usize, level: u32) -> IVec2 {
        let side = Self::side(level);
        let face = face as i32;
        IVec2::new(face % CUBE_ACROSS as i32, face / CUBE_ACROSS as i32) * side
    }

    /// World to level-0 page units of face `face` on the grid, to be divided by w (the face's
    /// own units, moved to its place in step with w).
    #[must_use]
    pub fn page_from_world(&self, face: usize) -> Mat4 {
        let at = self.face_origin(face, 0).as_vec2();
        let place = Mat4::from_cols(Vec4::X, Vec4::Y, Vec4::Z, Vec4::new(at.x, at.y, 0.0, 1.0));
        place * self.face(face).page_from_world()
    }

    /// log2 of level 0's texel in metres where w is 1 (every face's).
    #[must_use]
    pub fn finest_log2(&self) -> f32 {
        self.face(0).finest_log2()
    }

    /// The face holding `p`, its level-0 page units on the grid and its w; none at the light.
    #[must_use]
    pub fn units(&self, p: Vec3) -> Option<(usize, Vec2, f32)> {
        let d = p - self.position;
        if !(d.is_finite() && d != Vec3::ZERO) {
            return None;
        }
        let face = cube_face(d);
        let u = self.page_from_world(face) * p.extend(1.0);
        (u.w > 0.0).then(|| (face, u.truncate().truncate() / u.w, u.w))
    }

    /// The page of `level` that holds `p`, on the grid; none at the light.
    #[must_use]
    pub fn page_at(&self, level: u32, p: Vec3) -> Option<PageId> {
        let (face, units, _) = self.units(p)?;
        let side = Self::side(level);
        let origin = self.face_origin(face, level);
        let cell = (units / (level as f32).exp2()).floor();
        // Held on its own face (a point on a face's edge rounds onto the next one's first page).
        let local = IVec2::new(cell.x as i32, cell.y as i32) - origin;
        let local = local.clamp(IVec2::ZERO, IVec2::splat(side - 1));
        Some(PageId { level, x: origin.x + local.x, y: origin.y + local.y })
    }

    /// The face a page of the grid lies on, and the page on that face; none between the faces.
    #[must_use]
    pub fn face_of(&self, page: PageId) -> Option<(usize, PageId)> {
        let side = Self::side(page.level);
        let (column, row) = (page.x.div_euclid(side), page.y.div_euclid(side));
        if !((0..CUBE_ACROSS as i32).contains(&column) && (0..2).contains(&row)) {
            return None;
        }
        let face = (row * CUBE_ACROSS as i32 + column) as usize;
        Some((face, PageId { level: page.level, x: page.x - column * side, y: page.y - row * side }))
    }

    /// The projection a page of the grid is drawn with (its face's, narrowed to it).
    #[must_use]
    pub fn projection(&self, page: PageId) -> Option<LightProjection> {
        let (face, local) = self.face_of(page)?;
        Some(self.face(face).projection(local))
    }

    /// The pages of every level, on the grid, whose tiles `b` lies across on any face.
    #[must_use]
    pub fn crossing(&self, b: &Aabb) -> Vec<PageRange> {
        (0..6)
            .flat_map(|face| {
                self.face(face).crossing(b).into_iter().map(move |r| {
                    let origin = self.face_origin(face, r.level);
                    PageRange { level: r.level, min: r.min + origin, max: r.max + origin }
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::test_rng::Rng;

    fn cube() -> CubePages {
        CubePages::new(Vec3::new(1.0, 2.0, -1.5), 8.0, 4)
    }

    #[test]
    fn the_faces_lie_side_by_side_in_one_window_at_every_level() {
        let c = cube();
        assert_eq!(c.levels(), 6);
        for level in 0..c.levels() {
            let side = c.face(0).pages_across(level) as i32;
            let mut seen = std::collections::HashMap::new();
            for face in 0..6 {
                let origin = c.face_origin(face, level);
                for (x, y) in [(0, 0), (side - 1, 0), (0, side - 1), (side - 1, side - 1)] {
                    let page = PageId { level, x: origin.x + x, y: origin.y + y };
                    assert!(page.x < PAGE_GRID as i32 && page.y < PAGE_GRID as i32);
                    assert_eq!(c.face_of(page), Some((face, PageId { level, x, y })));
                    assert_eq!(*seen.entry(page).or_insert(face), face, "{page:?} on two faces");
                }
            }
        }
        assert_eq!(c.face_of(PageId { level: 0, x: 3 * CUBE_FACE_PAGES as i32, y: 0 }), None, "past the third face");
        assert_eq!(c.face_of(PageId { level: 0, x: 0, y: -1 }), None);
    }

    #[test]
    fn a_point_lies_in_the_page_its_face_holds_it_in_and_its_units_name_it() {
        let c = cube();
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for _ in 0..500 {
            let p = c.position + rng.point(6.0);
            let Some((face, units, w)) = c.units(p) else { continue };
            assert_eq!(face, cube_face(p - c.position));
            for level in 0..c.levels() {
                let page = c.page_at(level, p).unwrap();
                let (on, local) = c.face_of(page).unwrap();
                assert_eq!(on, face, "{p} on level {level}");
                // The page's own projection sees the point inside its tile.
                let clip = c.projection(page).unwrap().view_proj * p.extend(1.0);
                let ndc = clip.truncate().truncate() / clip.w;
                assert!(ndc.abs().max_element() <= 1.0 + 1e-4, "{p} at {ndc} in {page:?}");
                let cell = (units / (level as f32).exp2()).floor();
                let inside = local.x < c.face(face).pages_across(level) as i32 - 1;
                if inside {
                    assert_eq!(cell.x as i32, page.x, "{p} on level {level}");
                }
            }
            let texel = (c.finest_log2()).exp2() * w;
            let along = (p - c.position).abs().max_element();
            assert!((w - along).abs() < 1e-3 * along.max(1.0), "w is the distance along the face's axis");
            assert!((texel - c.face(face).texel(0, along)).abs() < 1e-5 * along.max(1.0));
        }
        assert_eq!(c.units(c.position), None, "at the light");
        assert_eq!(c.page_at(0, Vec3::NAN), None);
    }

    #[test]
    fn a_moving_box_dirties_its_pages_on_the_faces_it_crosses() {
        let c = cube();
        let p = c.position + Vec3::new(3.0, 0.2, -0.4);
        let ranges = c.crossing(&Aabb::new(p - 0.01, p + 0.01));
        assert!(!ranges.is_empty());
        for level in 0..c.levels() {
            let page = c.page_at(level, p).unwrap();
            assert!(ranges.iter().any(|r| r.contains(page)), "{page:?}");
        }
        // Every range lies on the face it was found on.
        for r in &ranges {
            assert_eq!(c.face_of(PageId { level: r.level, x: r.min.x, y: r.min.y }).map(|f| f.0), Some(0));
            assert_eq!(c.face_of(PageId { level: r.level, x: r.max.x, y: r.max.y }).map(|f| f.0), Some(0));
        }
        assert!(c.crossing(&Aabb::new(Vec3::NAN, Vec3::NAN)).is_empty());
        // Past the light's reach (8 m) or inside its near plane it casts nothing on the faces.
        let far = c.position + Vec3::new(9.0, 0.2, -0.4);
        assert!(c.crossing(&Aabb::new(far - 0.5, far + 0.5)).is_empty(), "out of reach");
        let near = c.position + Vec3::new(1e-4, 0.0, 0.0);
        assert!(c.crossing(&Aabb::new(near - 1e-5, near + 1e-5)).is_empty(), "inside the near plane");
        // Reaching across the far plane it still crosses.
        assert!(!c.crossing(&Aabb::new(far - 1.5, far + 1.5)).is_empty(), "into its reach");
    }
}
