//! The update budget: of the layers whose maps are out of date, which are drawn this frame.
//!
//! A layer's tile is [`TileState::Current`] (it holds the layer as it is), [`TileState::Stale`]
//! (it holds the layer as it was before its light or its casters moved; sampled with the
//! projection it was drawn with, the shadow is where it was, not garbage) or [`TileState::Empty`]
//! (a tile new to the layer, or one drawn for another method: nothing in it to show).
//!
//! Empty tiles are drawn whatever the budget (and count against it). Stale ones wait their turn
//! within what is left, in this order: those stale `max_stale` frames or more ([`MAX_STALE`] by
//! default, the settings' `max_stale`; oldest first),
//! then those whose light shows most on screen (a sun's cascades first, lights wholly behind the
//! camera last), then the oldest.
//!
//! The frame stops at the first overdue layer that does not fit, so nothing passes it: a layer
//! waits at most `max_stale` frames and then as many as the budget takes to draw every layer
//! that is out of date once (the overdue ones ahead of it). An overdue tile larger than the whole
//! budget is drawn alone on a frame of its own (the only frame that goes past the budget), so no
//! size of budget starves it.

/// Frames a layer may wait before it goes ahead of every layer that shows more, by default.
pub const MAX_STALE: u32 = 8;

/// What a layer's tile holds, against what the layer is now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileState {
    /// The layer as it is now: nothing to draw.
    Current,
    /// The layer as it was `age` frames ago (0: it went out of date this frame).
    Stale { age: u32 },
    /// Nothing of the layer's: it must be drawn.
    Empty,
}

/// One layer the planner chooses among.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Update {
    pub state: TileState,
    /// Texels its tile takes to draw.
    pub texels: u64,
    /// How much its light shows on screen (0: none; infinite: a sun).
    pub shows: f32,
}

/// Which of `layers` are drawn this frame within `budget` texels (`None`: no limit), those that
/// have waited `max_stale` frames first; empty tiles are always drawn, and spend the budget
/// first.
#[must_use]
pub fn plan_updates(layers: &[Update], budget: Option<u64>, max_stale: u32) -> Vec<bool> {
    let mut draw: Vec<bool> = layers.iter().map(|l| l.state == TileState::Empty).collect();
    let mut stale: Vec<(usize, u32)> = layers
        .iter()
        .enumerate()
        .filter_map(|(i, l)| match l.state {
            TileState::Stale { age } => Some((i, age)),
            _ => None,
        })
        .collect();
    let Some(budget) = budget else {
        for (i, _) in stale {
            draw[i] = true;
        }
        return draw;
    };
    let shows = |i: usize| if layers[i].shows.is_nan() { 0.0 } else { layers[i].shows.max(0.0) };
    stale.sort_by(|&(a, age_a), &(b, age_b)| {
        let overdue = |age: u32| age >= max_stale;
        overdue(age_b)
            .cmp(&overdue(age_a))
            .then_with(|| if overdue(age_a) { age_b.cmp(&age_a) } else { std::cmp::Ordering::Equal })
            .then_with(|| shows(b).total_cmp(&shows(a)))
            .then_with(|| age_b.cmp(&age_a))
            .then_with(|| a.cmp(&b))
    });
    let mut spent = layers.iter().filter(|l| l.state == TileState::Empty).fold(0u64, |s, l| s.saturating_add(l.texels));
    for (i, age) in stale {
        let texels = layers[i].texels;
        let overdue = age >= max_stale;
        if spent.saturating_add(texels) <= budget {
            draw[i] = true;
            spent += texels;
        } else if overdue {
            // Alone on a frame of its own if it is larger than the whole budget.
            draw[i] = spent == 0;
            break;
        }
    }
    draw
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stale(age: u32, texels: u64, shows: f32) -> Update {
        Update { state: TileState::Stale { age }, texels, shows }
    }

    #[test]
    fn with_no_limit_every_stale_and_empty_tile_is_drawn_and_current_ones_kept() {
        let current = Update { state: TileState::Current, texels: 64, shows: 1.0 };
        let empty = Update { state: TileState::Empty, texels: 1 << 22, shows: 0.0 };
        let layers = [current, stale(0, 1 << 20, 0.5), empty];
        assert_eq!(plan_updates(&layers, None, MAX_STALE), [false, true, true]);
        // Empty tiles do not count against the budget and are drawn past it.
        assert_eq!(plan_updates(&layers, Some(1024), MAX_STALE), [false, false, true]);
    }

    #[test]
    fn the_budget_goes_to_what_shows_most_then_to_the_oldest() {
        let layers = [stale(3, 100, 0.1), stale(0, 100, 0.9), stale(5, 100, 0.1), stale(1, 100, f32::INFINITY)];
        assert_eq!(plan_updates(&layers, Some(250), MAX_STALE), [false, true, false, true]);
        assert_eq!(plan_updates(&layers, Some(300), MAX_STALE), [false, true, true, true], "the older of two equals");
        // A layer that does not fit lets a smaller one after it through.
        let layers = [stale(0, 400, 1.0), stale(0, 100, 0.5)];
        assert_eq!(plan_updates(&layers, Some(300), MAX_STALE), [false, true]);
    }

    #[test]
    fn an_overdue_layer_goes_first_and_nothing_passes_it() {
        let layers = [stale(0, 100, f32::INFINITY), stale(MAX_STALE, 200, 0.0), stale(MAX_STALE + 2, 100, 0.0)];
        assert_eq!(
            plan_updates(&layers, Some(250), MAX_STALE),
            [false, false, true],
            "the oldest first, then it waits"
        );
        assert_eq!(plan_updates(&layers, Some(300), MAX_STALE), [false, true, true]);
    }

    #[test]
    fn a_tile_larger_than_the_budget_is_drawn_alone_once_overdue() {
        let layers = [stale(0, 1 << 22, 1.0), stale(0, 100, 0.5)];
        assert_eq!(plan_updates(&layers, Some(1024), MAX_STALE), [false, true]);
        let layers = [stale(MAX_STALE, 1 << 22, 1.0), stale(0, 100, 0.5)];
        assert_eq!(plan_updates(&layers, Some(1024), MAX_STALE), [true, false]);
        let empty = Update { state: TileState::Empty, texels: 100, shows: 0.0 };
        assert_eq!(
            plan_updates(&[layers[0], empty], Some(1024), MAX_STALE),
            [false, true],
            "not past an empty tile's cost"
        );
    }

    #[test]
    fn no_layer_waits_longer_than_max_stale_and_a_turn_of_the_budget() {
        // Twelve layers of 100 texels, all moving every frame, with a budget for two a frame:
        // whatever each shows, none waits more than MAX_STALE frames and then the six frames
        // the budget takes to draw all twelve.
        let shows = [0.0, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, f32::INFINITY];
        let mut ages: Vec<Option<u32>> = vec![None; shows.len()];
        let mut worst = 0;
        for _ in 0..100 {
            let layers: Vec<Update> =
                ages.iter().zip(shows).map(|(age, shows)| stale(age.map_or(0, |a| a + 1), 100, shows)).collect();
            let draw = plan_updates(&layers, Some(200), MAX_STALE);
            assert_eq!(draw.iter().filter(|&&d| d).count(), 2);
            for (age, (drawn, layer)) in ages.iter_mut().zip(draw.iter().zip(&layers)) {
                let TileState::Stale { age: now } = layer.state else { unreachable!() };
                worst = worst.max(now);
                *age = (!drawn).then_some(now);
            }
        }
        assert!((MAX_STALE..=MAX_STALE + 6).contains(&worst), "a layer waited {worst} frames");
    }

    #[test]
    fn odd_sizes_and_shows_are_ranked_without_panicking() {
        let layers = [stale(0, u64::MAX, f32::NAN), stale(0, 0, -1.0), stale(u32::MAX, 5, f32::INFINITY)];
        let draw = plan_updates(&layers, Some(10), MAX_STALE);
        assert_eq!(draw, [false, true, true]);
        let huge = Update { state: TileState::Empty, texels: u64::MAX, shows: 0.0 };
        assert_eq!(plan_updates(&[huge, huge, layers[1]], Some(10), MAX_STALE), [true, true, false]);
        assert_eq!(plan_updates(&[], Some(0), MAX_STALE), Vec::<bool>::new());
    }
}
