//! How far a rendered frame's shadows are from the truth: per light, counts of pixels rendered
//! dark but truly lit (false shadow: acne, over-darkening) and rendered lit but truly dark
//! (false lit: leaks, peter-panning), and the mean error against hard and soft truth; over the
//! whole frame, per band of view distance (cascade seams), and near true shadow edges.

use super::truth::Truth;
use crate::render::DebugFrame;

/// A pixel counts as shadowed when its rendered visibility is below this.
pub const DARK: f32 = 0.5;

/// Pixels either side of a true shadow boundary that count as its edge band.
pub const EDGE_RADIUS: u32 = 2;

/// Upper ends of the view-distance bands, in metres (the last takes everything beyond).
pub const DISTANCE_BANDS: [f32; 6] = [5.0, 10.0, 20.0, 40.0, 60.0, f32::INFINITY];

/// Error counts over a set of pixels for one light.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    /// Pixels compared.
    pub pixels: u64,
    /// Rendered dark, truly lit.
    pub false_shadow: u64,
    /// Rendered lit, truly dark.
    pub false_lit: u64,
    /// Sum of |rendered − hard truth|.
    pub error_hard: f64,
    /// Sum of |rendered − soft truth|.
    pub error_soft: f64,
}

impl Tally {
    /// Adds one pixel: `rendered` visibility against its truth.
    pub fn add(&mut self, rendered: f32, truth: Truth) {
        let rendered = rendered.clamp(0.0, 1.0);
        self.pixels += 1;
        let dark = rendered < DARK;
        self.false_shadow += (dark && truth.lit) as u64;
        self.false_lit += (!dark && !truth.lit) as u64;
        self.error_hard += (rendered - truth.lit as u32 as f32).abs() as f64;
        self.error_soft += (rendered - truth.soft).abs() as f64;
    }

    /// Both tallies together.
    pub fn merge(&mut self, other: &Tally) {
        self.pixels += other.pixels;
        self.false_shadow += other.false_shadow;
        self.false_lit += other.false_lit;
        self.error_hard += other.error_hard;
        self.error_soft += other.error_soft;
    }

    fn rate(&self, n: f64) -> f64 {
        if self.pixels == 0 { 0.0 } else { n / self.pixels as f64 }
    }

    /// Share of pixels rendered dark that are truly lit, of all compared (0..1).
    pub fn false_shadow_rate(&self) -> f64 {
        self.rate(self.false_shadow as f64)
    }

    /// Share of pixels rendered lit that are truly dark, of all compared (0..1).
    pub fn false_lit_rate(&self) -> f64 {
        self.rate(self.false_lit as f64)
    }

    /// Share of pixels on the wrong side of [`DARK`] (0..1).
    pub fn misclassified(&self) -> f64 {
        self.rate((self.false_shadow + self.false_lit) as f64)
    }

    /// Mean absolute error against the hard truth.
    pub fn mae_hard(&self) -> f64 {
        self.rate(self.error_hard)
    }

    /// Mean absolute error against the soft truth.
    pub fn mae_soft(&self) -> f64 {
        self.rate(self.error_soft)
    }
}

/// One light's errors in one or more frames.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightReport {
    /// Every compared pixel.
    pub all: Tally,
    /// By view distance, one per [`DISTANCE_BANDS`] entry.
    pub bands: [Tally; DISTANCE_BANDS.len()],
    /// Pixels within the edge radius of a true shadow boundary.
    pub edge: Tally,
    /// Texels per pixel where the light's lookups were made (see [`super::texels`]); counted by
    /// the sweep, empty where nothing counted them.
    pub texels: super::texels::Density,
}

impl LightReport {
    /// Both reports together.
    pub fn merge(&mut self, other: &LightReport) {
        self.all.merge(&other.all);
        self.edge.merge(&other.edge);
        self.texels.merge(&other.texels);
        for (a, b) in self.bands.iter_mut().zip(&other.bands) {
            a.merge(b);
        }
    }
}

/// The rendered visibility of `light` (in [`crate::light::light_list`] order) at pixel `i`
/// where the renderer made a shadow test there.
pub fn rendered(frame: &DebugFrame, light: usize, i: usize) -> Option<f32> {
    let v = *frame.visibility.get(light)?.get(i)?;
    (frame.covered(i) && v >= 0.0).then_some(v)
}

/// Whether pixel `i` shows `light` yet its visibility is no share of light: NaN, infinite, or
/// outside 0..=1 (-1 marks a pixel the light does not reach). The failure cases count such a
/// pixel as garbage.
#[must_use]
pub fn out_of_range(frame: &DebugFrame, light: usize, i: usize) -> bool {
    let v = frame.visibility[light][i];
    frame.covered(i) && !(v.is_finite() && (v == -1.0 || (0.0..=1.0).contains(&v)))
}

/// The errors of `light` over the pixels `keep` accepts, where both the renderer and the truth
/// have a value.
pub fn tally(frame: &DebugFrame, truth: &[Option<Truth>], light: usize, keep: impl Fn(usize) -> bool) -> Tally {
    let mut t = Tally::default();
    for (i, truth) in truth.iter().enumerate() {
        if let (Some(truth), Some(r)) = (truth, rendered(frame, light, i))
            && keep(i)
        {
            t.add(r, *truth);
        }
    }
    t
}

/// Pixels within `radius` pixels (a square) of a true shadow boundary: a pair of neighbouring
/// pixels whose hard truths differ.
pub fn edge_mask(width: u32, height: u32, truth: &[Option<Truth>], radius: u32) -> Vec<bool> {
    let (w, h) = (width as usize, height as usize);
    let lit = |x: usize, y: usize| truth[y * w + x].map(|t| t.lit);
    let mut boundary = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            let here = lit(x, y);
            let right = (x + 1 < w).then(|| lit(x + 1, y)).flatten();
            let below = (y + 1 < h).then(|| lit(x, y + 1)).flatten();
            for (other, at) in [(right, (x + 1, y)), (below, (x, y + 1))] {
                if let (Some(a), Some(b)) = (here, other)
                    && a != b
                {
                    boundary[y * w + x] = true;
                    boundary[at.1 * w + at.0] = true;
                }
            }
        }
    }
    let r = radius as usize;
    let mut mask = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            if boundary[y * w + x] {
                for yy in y.saturating_sub(r)..(y + r + 1).min(h) {
                    mask[yy * w + x.saturating_sub(r)..yy * w + (x + r + 1).min(w)].fill(true);
                }
            }
        }
    }
    mask
}

/// Every light's report for one frame: `truth` holds one column per light, in the frame's
/// order; `edge_radius` sets the edge band in pixels.
pub fn report(frame: &DebugFrame, truth: &[Vec<Option<Truth>>], edge_radius: u32) -> Vec<LightReport> {
    truth
        .iter()
        .enumerate()
        .map(|(light, column)| {
            let edges = edge_mask(frame.width, frame.height, column, edge_radius);
            // A pixel whose depth is not a number is in no band.
            let band_of = |i: usize| DISTANCE_BANDS.iter().position(|&end| frame.normal[i].w < end);
            LightReport {
                all: tally(frame, column, light, |_| true),
                bands: std::array::from_fn(|b| tally(frame, column, light, |i| band_of(i) == Some(b))),
                edge: tally(frame, column, light, |i| edges[i]),
                texels: super::texels::Density::default(),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    fn truth(lit: bool) -> Option<Truth> {
        Some(Truth { lit, soft: lit as u32 as f32 })
    }

    #[test]
    fn false_shadows_and_false_lits_are_counted_apart() {
        let mut t = Tally::default();
        t.add(0.0, truth(true).unwrap()); // acne
        t.add(1.0, truth(false).unwrap()); // leak
        t.add(1.0, truth(true).unwrap());
        t.add(0.2, truth(false).unwrap());
        assert_eq!((t.pixels, t.false_shadow, t.false_lit), (4, 1, 1));
        assert_eq!(t.misclassified(), 0.5);
        assert!((t.mae_hard() - (1.0 + 1.0 + 0.0 + 0.2) / 4.0).abs() < 1e-9);
        assert_eq!(Tally::default().misclassified(), 0.0, "nothing compared, nothing wrong");
    }

    #[test]
    fn edges_are_where_neighbouring_truths_differ_grown_by_the_radius() {
        // A 6x1 strip: lit lit lit dark dark dark; the boundary is between x = 2 and 3.
        let t: Vec<Option<Truth>> = (0..6).map(|x| truth(x < 3)).collect();
        assert_eq!(edge_mask(6, 1, &t, 0), vec![false, false, true, true, false, false]);
        assert_eq!(edge_mask(6, 1, &t, 1), vec![false, true, true, true, true, false]);
        let none: Vec<Option<Truth>> = vec![None, truth(true), None];
        assert_eq!(edge_mask(3, 1, &none, 2), vec![false; 3], "no truth, no edge");
    }

    #[test]
    fn reports_split_by_distance_and_skip_untested_pixels() {
        let frame = DebugFrame {
            width: 3,
            height: 1,
            position: vec![Vec4::W; 3],
            normal: vec![Vec4::new(0.0, 1.0, 0.0, 3.0), Vec4::new(0.0, 1.0, 0.0, 15.0), Vec4::new(0.0, 1.0, 0.0, 15.0)],
            visibility: vec![vec![1.0, 0.0, -1.0]],
        };
        let r = &report(&frame, &[vec![truth(true), truth(true), truth(false)]], 1)[0];
        assert_eq!(r.all.pixels, 2, "the renderer made no test at the third pixel");
        assert_eq!((r.bands[0].pixels, r.bands[0].false_shadow), (1, 0));
        assert_eq!((r.bands[2].pixels, r.bands[2].false_shadow), (1, 1));
    }

    #[test]
    fn a_visibility_that_is_no_share_of_light_is_garbage_only_where_the_pixel_shows_the_light() {
        let odd = [0.0, 1.0, -1.0, 0.5, 1.000_000_1, -0.5, f32::NAN, f32::INFINITY, f32::MAX];
        let expected = [false, false, false, false, true, true, true, true, true];
        let mut frame = DebugFrame {
            width: odd.len() as u32,
            height: 1,
            position: vec![Vec4::W; odd.len()],
            normal: vec![Vec4::Y; odd.len()],
            visibility: vec![odd.to_vec()],
        };
        let seen: Vec<bool> = (0..odd.len()).map(|i| out_of_range(&frame, 0, i)).collect();
        assert_eq!(seen, expected);
        frame.position = vec![Vec4::ZERO; odd.len()];
        assert!((0..odd.len()).all(|i| !out_of_range(&frame, 0, i)), "a pixel showing nothing is never garbage");
    }
}
