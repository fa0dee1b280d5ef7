//! Poisson-disc sample patterns for the filters that spread their comparisons over a disc: points
//! no two of which are close, made once here and written into the shaders' prelude.

use glam::Vec2;

/// Candidates tried for each point: the one farthest from every point already placed wins
/// (Mitchell's best-candidate algorithm, 1991), which gives a Poisson-disc-like spread.
const CANDIDATES: usize = 32;

/// `count` points in the unit disc, evenly spread, the same on every call.
#[must_use]
pub fn poisson_disc(count: usize) -> Vec<Vec2> {
    let mut rng = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        // xorshift64*: small, fixed and good enough to place points.
        rng ^= rng >> 12;
        rng ^= rng << 25;
        rng ^= rng >> 27;
        (rng.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut points: Vec<Vec2> = Vec::with_capacity(count);
    for _ in 0..count {
        let mut best = (Vec2::ZERO, -1.0f32);
        for _ in 0..CANDIDATES {
            // Uniform over the disc's area.
            let (r, a) = (next().sqrt(), next() * std::f32::consts::TAU);
            let c = Vec2::new(r * a.cos(), r * a.sin());
            let gap = points.iter().map(|p| p.distance_squared(c)).fold(f32::INFINITY, f32::min);
            if gap > best.1 {
                best = (c, gap);
            }
        }
        points.push(best.0);
    }
    points
}

/// `points` as a WGSL constant array named `name`.
#[must_use]
pub fn wgsl_array(name: &str, points: &[Vec2]) -> String {
    let items: Vec<String> = points.iter().map(|p| format!("vec2<f32>({:?}, {:?})", p.x, p.y)).collect();
    format!(
        "const {name}: array<vec2<f32>, {}> = array<vec2<f32>, {}>({});\n",
        points.len(),
        points.len(),
        items.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_lie_in_the_disc_far_apart_and_centred() {
        for n in [1, 16, 32, 64] {
            let p = poisson_disc(n);
            assert_eq!(p.len(), n);
            assert!(p.iter().all(|q| q.is_finite() && q.length() <= 1.0), "{n}: outside the disc");
            // n points in a disc of area π: a perfect packing spaces them about sqrt(π / n)
            // apart; a random set would have pairs far closer.
            let min = (0..n)
                .flat_map(|i| (0..i).map(move |j| (i, j)))
                .map(|(i, j)| p[i].distance(p[j]))
                .fold(f32::INFINITY, f32::min);
            if n > 1 {
                assert!(min > 0.5 * (std::f32::consts::PI / n as f32).sqrt(), "{n}: two points {min} apart");
            }
            if n >= 16 {
                let mean = p.iter().copied().sum::<Vec2>() / n as f32;
                assert!(mean.length() < 0.15, "{n}: mean {mean}");
            }
        }
    }

    #[test]
    fn the_pattern_is_the_same_every_time_and_empty_for_zero() {
        assert_eq!(poisson_disc(16), poisson_disc(16));
        assert!(poisson_disc(0).is_empty());
    }

    #[test]
    fn the_wgsl_array_names_every_point() {
        let text = wgsl_array("DISC", &[Vec2::new(0.5, -0.25), Vec2::ZERO]);
        assert_eq!(
            text,
            "const DISC: array<vec2<f32>, 2> = array<vec2<f32>, 2>(vec2<f32>(0.5, -0.25), vec2<f32>(0.0, 0.0));\n"
        );
    }
}
