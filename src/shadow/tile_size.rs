//! How big each light's shadow tiles are: in proportion to how much of the screen its light
//! covers (a light filling the screen gets the largest tile), kept in a size class until what
//! it shows moves well past the class (so tiles do not thrash as the camera moves), then halved
//! where the atlas cannot hold them all, the lights that show least first. Sizes follow the
//! share of the screen, not its pixels, so a window and a headless frame of the same view draw
//! the same maps.

use super::atlas::MIN_TILE;

/// Octaves (factors of two) what a light shows must move from its class's size before the class
/// changes: past 0.5 it would flip back and forth at a class's edge.
pub const HYSTERESIS: f32 = 0.75;

/// What one shadowed light asks of the atlas.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileNeed {
    /// Its layers (a sun's cascades, a spot's one map, a cube's six faces).
    pub layers: u32,
    /// The side of each layer it would have, in texels.
    pub side: u32,
    /// How much it shows (larger keeps its size longer when memory runs short; infinite for a
    /// sun, whose cascades keep theirs while anything else can shrink).
    pub priority: f32,
}

/// The side in texels (before classes and the budget) of a light's layers when its reach
/// covers a disc whose radius is `coverage` of the screen's half height: `largest` (the
/// settings' map size) for a light filling the screen (coverage 1) with one map (`single`), and
/// half that for a cube's faces, which each see about a quarter of it.
#[must_use]
pub fn texels_for(coverage: f32, single: bool, largest: u32) -> f32 {
    let side = coverage * largest as f32 * if single { 1.0 } else { 0.5 };
    if side.is_finite() { side.max(1.0) } else { 1.0 }
}

/// The size class (log2 of the side) a light keeps: `current` (0: none yet) while `side`
/// (what it needs now) stays within `hysteresis` octaves of it ([`HYSTERESIS`] by default),
/// else the class nearest `side`; always within `MIN_TILE..=largest`.
#[must_use]
pub fn size_class(current: u32, side: f32, largest: u32, hysteresis: f32) -> u32 {
    let want = side.max(1.0).log2();
    let lowest = MIN_TILE.ilog2();
    let highest = largest.max(MIN_TILE).ilog2();
    let keep = current != 0 && (want - current as f32).abs() <= hysteresis;
    let class = if keep { current } else { want.round() as u32 };
    class.clamp(lowest, highest)
}

/// The side each light gets within `capacity` texels: its own, or halved, lowest priority per
/// texel first, until all fit, never below [`MIN_TILE`] (what still does not fit is the
/// atlas's to refuse). Sides are kept as given (they need not be powers of two) until halved.
#[must_use]
pub fn fit_budget(needs: &[TileNeed], capacity: u64) -> Vec<u32> {
    let mut sides: Vec<u32> = needs.iter().map(|n| n.side.max(MIN_TILE)).collect();
    // A tile is the power of two round its side: that is what it takes of the atlas.
    let area = |n: &TileNeed, side: u32| u64::from(n.layers) * u64::from(side.next_power_of_two()).pow(2);
    let mut total: u64 = needs.iter().zip(&sides).map(|(n, &s)| area(n, s)).sum();
    while total > capacity {
        // The light that gives up least per texel it frees: the largest side for its priority.
        let cost = |i: usize| sides[i] as f32 / needs[i].priority.max(1e-12).sqrt();
        let Some(i) = (0..needs.len()).filter(|&i| sides[i] > MIN_TILE).max_by(|&a, &b| cost(a).total_cmp(&cost(b)))
        else {
            break;
        };
        let half = (sides[i].next_power_of_two() / 2).max(MIN_TILE);
        total = total - area(&needs[i], sides[i]) + area(&needs[i], half);
        sides[i] = half;
    }
    sides
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_class_holds_until_what_it_shows_moves_well_past_it() {
        assert_eq!(size_class(0, 700.0, 2048, HYSTERESIS), 9, "log2 700 = 9.45 rounds to 9");
        // Round a class's edge (9.5) nothing flips.
        for side in [600.0, 760.0, 600.0, 820.0, 400.0] {
            assert_eq!(size_class(9, side, 2048, HYSTERESIS), 9, "{side}");
        }
        assert_eq!(size_class(9, 900.0, 2048, HYSTERESIS), 10, "0.81 octaves up");
        assert_eq!(size_class(10, 600.0, 2048, HYSTERESIS), 9, "0.77 octaves down");
        assert_eq!(size_class(9, 1e9, 2048, HYSTERESIS), 11, "never past the largest");
        assert_eq!(size_class(9, 0.0, 2048, HYSTERESIS), MIN_TILE.ilog2(), "never under the smallest");
        assert_eq!(size_class(0, f32::NAN, 2048, HYSTERESIS), MIN_TILE.ilog2());
        assert_eq!(size_class(0, f32::INFINITY, 2048, HYSTERESIS), 11);
        // Without hysteresis a class flips at its edge.
        assert_eq!((size_class(9, 730.0, 2048, 0.0), size_class(10, 720.0, 2048, 0.0)), (10, 9));
    }

    #[test]
    fn texels_follow_the_share_of_the_screen_covered() {
        assert_eq!(texels_for(1.0, true, 2048), 2048.0);
        assert_eq!(texels_for(0.25, true, 2048), 512.0);
        assert_eq!(texels_for(0.25, false, 2048), 256.0);
        assert_eq!(texels_for(f32::NAN, true, 2048), 1.0);
        assert_eq!(texels_for(-5.0, false, 2048), 1.0);
    }

    #[test]
    fn the_budget_halves_the_least_shown_first_and_suns_last() {
        let sun = TileNeed { layers: 4, side: 2048, priority: f32::INFINITY };
        let big = TileNeed { layers: 6, side: 1024, priority: 1000.0 };
        let small = TileNeed { layers: 6, side: 1024, priority: 1.0 };
        let needs = [sun, big, small];
        let room = 4 * 2048 * 2048 + 6 * 1024 * 1024 + 6 * 512 * 512;
        assert_eq!(fit_budget(&needs, room), vec![2048, 1024, 512]);
        assert_eq!(fit_budget(&needs, u64::MAX), vec![2048, 1024, 1024], "room for all: nothing halved");
        // No room at all: everything down to the smallest tile, the sun last.
        let least = fit_budget(&needs, 0);
        assert_eq!(least, vec![MIN_TILE; 3]);
        let tight = fit_budget(&needs, 4 * 1024 * 1024 + 12 * 32 * 32);
        assert_eq!(tight, vec![1024, MIN_TILE, MIN_TILE], "the sun shrinks only once the others cannot");
        assert_eq!(fit_budget(&[], 0), Vec::<u32>::new());
        // A side that is not a power of two takes its power of two's room, and is kept if that fits.
        let odd = TileNeed { layers: 1, side: 1500, priority: 1.0 };
        assert_eq!(fit_budget(&[odd], 2048 * 2048), vec![1500]);
        assert_eq!(fit_budget(&[odd], 2048 * 2048 - 1), vec![1024]);
    }
}
