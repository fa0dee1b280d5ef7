//! Texels per pixel where a light's shadow falls: for each pixel a light's lookup is made at,
//! the shadow texel the lookup reads, laid along the light onto the surface, against the pixel's
//! own footprint there (the square root of their areas' ratio: how many texels lie across a
//! pixel). Below one a texel covers several pixels and edges step; far above one, texels are
//! spent where nothing can see them. It explains a configuration's resolution errors: the
//! texel-density view (key B) paints the same measure.
//!
//! The texel is the one the main pass picks (`texel_at` in lights.wgsl): a cascade's by view
//! depth, a page's by the footprint the pixel wants and what is resident (the coarse map where no
//! page is), a spot's or a cube face's at the pixel's distance from the light. The footprint is
//! found from the measured frame's neighbouring pixels, as the page marking finds it.

use crate::light::{Kind, Light, ShadowShape};
use crate::render::DebugFrame;
use crate::shadow::{MIN_GRAZE, PageId, wanted_texel};
use glam::Vec3;
use std::collections::HashSet;

/// Bins per octave of the histogram.
const BINS_PER_OCTAVE: i32 = 16;
/// Octaves the histogram spans either side of one texel a pixel.
const OCTAVES: i32 = 10;

/// Counts of texels per pixel, in sixteenths of an octave from 2^-10 to 2^10 (values beyond
/// are counted in the end bins).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Density {
    bins: Vec<u64>,
}

impl Default for Density {
    fn default() -> Self {
        Density { bins: vec![0; (2 * OCTAVES * BINS_PER_OCTAVE) as usize] }
    }
}

impl Density {
    /// Counts one pixel with `texels` texels across it (not a positive finite number: not counted).
    pub fn add(&mut self, texels: f32) {
        if !(texels.is_finite() && texels > 0.0) {
            return;
        }
        let bin = ((texels.log2() + OCTAVES as f32) * BINS_PER_OCTAVE as f32).floor();
        let bin = bin.clamp(0.0, (self.bins.len() - 1) as f32) as usize;
        self.bins[bin] += 1;
    }

    /// Both counts together.
    pub fn merge(&mut self, other: &Density) {
        self.bins.iter_mut().zip(&other.bins).for_each(|(a, b)| *a += b);
    }

    /// Pixels counted.
    #[must_use]
    pub fn pixels(&self) -> u64 {
        self.bins.iter().sum()
    }

    /// The texels per pixel below which a share `q` (0..1) of the pixels lie, to a sixteenth of
    /// an octave (the middle of its bin); none with no pixels.
    #[must_use]
    pub fn quantile(&self, q: f64) -> Option<f32> {
        let total = self.pixels();
        if total == 0 {
            return None;
        }
        let want = (q.clamp(0.0, 1.0) * total as f64).ceil().max(1.0) as u64;
        let mut seen = 0;
        let bin = self.bins.iter().position(|&n| {
            seen += n;
            seen >= want
        })?;
        Some(((bin as f32 + 0.5) / BINS_PER_OCTAVE as f32 - OCTAVES as f32).exp2())
    }
}

/// What of the camera the footprint needs: where it is, and the radians a pixel spans.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eye {
    /// Where the camera is.
    pub position: Vec3,
    /// Radians a pixel of the measured frame spans at its middle.
    pub pixel_angle: f32,
}

impl Eye {
    /// The camera of `world` for a measured frame `height` pixels high; none without a camera.
    #[must_use]
    pub fn of(world: &mut bevy_ecs::world::World, height: u32) -> Option<Eye> {
        let mut cameras = world.query::<(&crate::components::Camera, &crate::components::Transform)>();
        let (camera, transform) = cameras.iter(world).next()?;
        Some(Eye { position: transform.translation, pixel_angle: camera.pixel_angle(height) })
    }
}

/// The texels per pixel at every pixel of `frame` where `light` (its column `column` of the
/// frame) made a lookup, counted.
#[must_use]
pub fn density(frame: &DebugFrame, column: usize, light: &Light, eye: Eye) -> Density {
    let mut out = Density::default();
    let Some(visibility) = frame.visibility.get(column) else { return out };
    let towards = light.kind.homogeneous();
    let resident: HashSet<PageId> = light.layers.iter().filter_map(|l| l.page.map(|p| p.id)).collect();
    for i in (0..visibility.len()).filter(|&i| frame.covered(i) && visibility[i] >= 0.0) {
        let p = frame.position[i].truncate();
        let n = frame.normal[i].truncate().normalize_or_zero();
        let l = (towards.truncate() - p * towards.w).normalize_or_zero();
        let depth = frame.normal[i].w;
        let Some(texel) = texel_at(light, &resident, (p, n, l, depth), eye) else { continue };
        let area = footprint(frame, i);
        let texel_area = texel * texel / n.dot(l).abs().max(MIN_GRAZE);
        out.add((area / texel_area).sqrt());
    }
    out
}

/// The world size of the texel `light`'s lookup reads at `p` (unit normal `n`, unit direction
/// `l` towards the light, view depth `depth`); none where it has no map there.
fn texel_at(
    light: &Light,
    resident: &HashSet<PageId>,
    (p, n, l, depth): (Vec3, Vec3, Vec3, f32),
    eye: Eye,
) -> Option<f32> {
    let first = light.layers.first()?;
    let distance = || light.kind.homogeneous().truncate().distance(p);
    match light.shape {
        ShadowShape::Cascades => light.layers.iter().find(|layer| depth < layer.far).map(|layer| layer.texel.x),
        ShadowShape::Single | ShadowShape::Cube => Some(first.texel.x + first.texel.y * distance()),
        ShadowShape::Pages => {
            let view = light.pages.as_ref()?;
            let space = &view.space;
            let to_eye = eye.position - p;
            let wanted = wanted_texel(to_eye.length(), eye.pixel_angle, n.dot(to_eye.normalize_or_zero()), n.dot(l));
            let from = space.level_for(wanted, p, view.bias);
            let held = |level: &u32| space.page_at(*level, p).is_some_and(|page| resident.contains(&page));
            let level = (from..space.levels()).find(held);
            Some(level.map_or(first.texel.x + first.texel.y * distance(), |level| space.texel(level, p)))
        }
    }
}

/// The area of the surface pixel `i` of `frame` shows: the cross product of the steps to its
/// neighbours across and down (the shorter of the steps to either side: a step over an edge to
/// another surface is the longer), or 0 where it has no neighbour on the surface.
fn footprint(frame: &DebugFrame, i: usize) -> f32 {
    let (w, h) = (frame.width as usize, frame.height as usize);
    let (x, y) = (i % w, i / w);
    let p = frame.position[i].truncate();
    let at = |x: usize, y: usize| {
        let j = y * w + x;
        frame.covered(j).then(|| frame.position[j].truncate())
    };
    let step = |a: Option<Vec3>, b: Option<Vec3>| match (a.map(|a| a - p), b.map(|b| p - b)) {
        (Some(a), Some(b)) => Some(if a.length_squared() <= b.length_squared() { a } else { b }),
        (a, b) => a.or(b),
    };
    let across = step((x + 1 < w).then(|| at(x + 1, y)).flatten(), (x > 0).then(|| at(x - 1, y)).flatten());
    let down = step((y + 1 < h).then(|| at(x, y + 1)).flatten(), (y > 0).then(|| at(x, y - 1)).flatten());
    match (across, down) {
        (Some(a), Some(b)) => a.cross(b).length(),
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_come_from_the_octave_bins() {
        let mut d = Density::default();
        assert_eq!(d.quantile(0.5), None);
        for _ in 0..99 {
            d.add(1.0);
        }
        d.add(8.0);
        let median = d.quantile(0.5).unwrap();
        assert!((median / 1.0 - 1.0).abs() < 0.05, "{median}");
        let top = d.quantile(0.995).unwrap();
        assert!((top / 8.0 - 1.0).abs() < 0.05, "{top}");
        assert!((d.quantile(0.99).unwrap() - median).abs() < 1e-6, "99 of 100 at one");
        for odd in [f32::NAN, 0.0, -1.0, f32::INFINITY] {
            d.add(odd);
        }
        assert_eq!(d.pixels(), 100, "odd values are not counted");
        d.add(1e9);
        d.add(1e-9);
        assert_eq!(d.pixels(), 102, "extremes land in the end bins");
        let mut both = Density::default();
        both.merge(&d);
        both.merge(&d);
        assert_eq!(both.pixels(), 204);
    }

    #[test]
    fn a_flat_frame_facing_the_camera_has_the_footprint_of_its_pixels() {
        // A 3x3 frame of points 1 cm apart on a plane: the middle pixel covers 1 cm².
        let position: Vec<glam::Vec4> =
            (0..9).map(|i| glam::Vec4::new((i % 3) as f32 * 0.01, (i / 3) as f32 * 0.01, 0.0, 1.0)).collect();
        let frame = DebugFrame {
            width: 3,
            height: 3,
            position,
            normal: vec![glam::Vec4::new(0.0, 0.0, 1.0, 2.0); 9],
            visibility: vec![vec![1.0; 9]],
        };
        assert!((footprint(&frame, 4) - 1e-4).abs() < 1e-9);
        assert!((footprint(&frame, 0) - 1e-4).abs() < 1e-9, "a corner has one neighbour each way");
        let mut lone = frame.clone();
        lone.position[1].w = 0.0;
        lone.position[3].w = 0.0;
        assert_eq!(footprint(&lone, 0), 0.0, "no neighbour down or across: no footprint");
    }
}
