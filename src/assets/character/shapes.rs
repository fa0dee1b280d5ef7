//! Closed low-poly shapes (tubes, spheres, boxes) with joint influences on every vertex.

use glam::Vec3;

/// Up to two (joint, weight) influences of a vertex.
pub(super) type Influence = [(u16, f32); 2];

/// Sides of every tube and segments around every sphere.
const SIDES: usize = 10;

/// A skinned triangle mesh being built, wound counter-clockwise seen from outside.
#[derive(Default)]
pub(super) struct MeshBuilder {
    points: Vec<(Vec3, Vec3, Influence)>,
    pub(super) indices: Vec<u16>,
}

impl MeshBuilder {
    fn vertex(&mut self, p: Vec3, n: Vec3, influence: Influence) -> u16 {
        self.points.push((p, n, influence));
        (self.points.len() - 1) as u16
    }

    /// A triangle, turned so that its face points the way its vertex normals do.
    fn triangle(&mut self, a: u16, b: u16, c: u16) {
        let [pa, pb, pc] = [a, b, c].map(|i| self.points[i as usize].0);
        let face = (pb - pa).cross(pc - pa);
        if face.length_squared() < 1e-14 {
            return;
        }
        let normal: Vec3 = [a, b, c].iter().map(|&i| self.points[i as usize].1).sum();
        self.indices.extend(if face.dot(normal) >= 0.0 { [a, b, c] } else { [a, c, b] });
    }

    /// A capped tube from `a` to `b` with radii `r` at its ends, squashed to `depth` of its width
    /// across; `rings` gives, from 0 at `a` to 1 at `b`, where rings sit and which joints move them.
    pub(super) fn tube(&mut self, a: Vec3, b: Vec3, r: (f32, f32), depth: f32, rings: &[(f32, Influence)]) {
        let axis = (b - a).normalize();
        let u = if axis.y.abs() > 0.9 { Vec3::X } else { Vec3::Y.cross(axis).normalize() };
        let v = axis.cross(u) * depth;
        let ring = |t: f32, k: usize| {
            let angle = k as f32 / SIDES as f32 * std::f32::consts::TAU;
            let radius = r.0 + (r.1 - r.0) * t;
            let out = u * angle.cos() + v * angle.sin();
            (a + (b - a) * t + out * radius, (u * angle.cos() + v.normalize() * angle.sin() / depth).normalize())
        };
        let first = self.points.len() as u16;
        for &(t, influence) in rings {
            for k in 0..SIDES {
                let (p, n) = ring(t, k);
                self.vertex(p, n, influence);
            }
        }
        for ring_index in 0..rings.len() - 1 {
            let (lo, hi) = (first + (ring_index * SIDES) as u16, first + ((ring_index + 1) * SIDES) as u16);
            for k in 0..SIDES as u16 {
                let k1 = (k + 1) % SIDES as u16;
                self.triangle(lo + k, lo + k1, hi + k1);
                self.triangle(lo + k, hi + k1, hi + k);
            }
        }
        for (end, normal) in [(0, -axis), (rings.len() - 1, axis)] {
            let (t, influence) = rings[end];
            let centre = self.vertex(a + (b - a) * t, normal, influence);
            let cap: Vec<u16> = (0..SIDES).map(|k| self.vertex(ring(t, k).0, normal, influence)).collect();
            for k in 0..SIDES {
                self.triangle(centre, cap[k], cap[(k + 1) % SIDES]);
            }
        }
    }

    /// A sphere of radius `r` at `c`.
    pub(super) fn sphere(&mut self, c: Vec3, r: f32, influence: Influence) {
        const BANDS: usize = 6;
        let first = self.points.len() as u16;
        for lat in 0..=BANDS {
            let phi = (lat as f32 / BANDS as f32 - 0.5) * std::f32::consts::PI;
            for k in 0..=SIDES {
                let theta = k as f32 / SIDES as f32 * std::f32::consts::TAU;
                let n = Vec3::new(phi.cos() * theta.cos(), phi.sin(), phi.cos() * theta.sin());
                self.vertex(c + n * r, n, influence);
            }
        }
        let row = (SIDES + 1) as u16;
        for lat in 0..BANDS as u16 {
            for k in 0..SIDES as u16 {
                let (p, q) = (first + lat * row + k, first + (lat + 1) * row + k);
                self.triangle(p, p + 1, q + 1);
                self.triangle(p, q + 1, q);
            }
        }
    }

    /// A box with half extents `half` at `c`, flat-shaded.
    pub(super) fn cuboid(&mut self, c: Vec3, half: Vec3, influence: Influence) {
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            for n in [axis, -axis] {
                let u = if axis == Vec3::Y { Vec3::X } else { Vec3::Y };
                let v = n.cross(u);
                let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .map(|(s, t)| self.vertex(c + (n + u * s + v * t) * half, n, influence));
                self.triangle(corners[0], corners[1], corners[2]);
                self.triangle(corners[0], corners[2], corners[3]);
            }
        }
    }

    /// Positions, three floats per vertex.
    pub(super) fn positions(&self) -> Vec<f32> {
        self.points.iter().flat_map(|p| p.0.to_array()).collect()
    }

    /// Texture coordinates for horizontal stripes: v grows with the bind-pose height,
    /// `per_metre` texture repeats a metre; u is the same everywhere.
    pub(super) fn stripes(&self, per_metre: f32) -> Vec<f32> {
        self.points.iter().flat_map(|p| [0.5, p.0.y * per_metre]).collect()
    }

    /// Unit normals, three floats per vertex.
    pub(super) fn normals(&self) -> Vec<f32> {
        self.points.iter().flat_map(|p| p.1.to_array()).collect()
    }

    /// Joint indices, four per vertex (unused slots name the first joint with weight 0).
    pub(super) fn joints(&self) -> Vec<u16> {
        self.points.iter().flat_map(|p| [p.2[0].0, p.2[1].0, p.2[0].0, p.2[0].0]).collect()
    }

    /// Joint weights, four per vertex, summing to 1.
    pub(super) fn weights(&self) -> Vec<f32> {
        self.points.iter().flat_map(|p| [p.2[0].1, p.2[1].1, 0.0, 0.0]).collect()
    }
}
