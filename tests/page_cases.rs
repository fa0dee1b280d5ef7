//! The virtual-page failure cases (`src/eval/cases/pages.rs`), each held under its threshold with
//! the sun's maps virtual and shown crossing it when its guard is taken away: no border round the
//! pages (the atlas guard off), no fallback to a coarser level for a missing page (twice: a camera
//! cut and a pool too small), no stale mark on the pages a caster moved out of, and a page grid
//! that follows the camera (unsnapped). With every light paged, PCSS's contact hardening, a
//! point light's cube seams (no border, no margin) and spots starved of updates (no limit on how
//! long a page waits) likewise. Where the device runs no compute shaders no page is marked, and
//! the tests say SKIPPED.

mod common;

use umbra::eval::cases::{Score, case};
use umbra::eval::measure::{Measurer, TruthSettings};
use umbra::settings::{LightMaps, Settings, SunMaps};
use umbra::shadow::FitMode;

const SIZE: (u32, u32) = (192, 192);

/// The default settings with virtual sun maps and `change` made.
fn paged(change: impl FnOnce(&mut Settings)) -> Settings {
    Settings::default().with(|s| {
        s.maps.sun_maps = SunMaps::Virtual;
        change(s);
    })
}

/// Runs case `name` with virtual sun maps and with `broken` made to them too; the first must stay
/// under the case's threshold, the second go over it. None (SKIPPED said) where pages cannot be
/// marked.
fn holds_and_breaks(name: &str, broken: impl FnOnce(&mut Settings)) -> Option<(Score, Score)> {
    holds_and_breaks_with(name, paged(|_| ()), paged(broken))
}

/// [`holds_and_breaks`] with every light paged.
fn holds_and_breaks_all_paged(name: &str, broken: impl FnOnce(&mut Settings)) -> Option<(Score, Score)> {
    let all = |s: &mut Settings| s.maps.light_maps = LightMaps::Virtual;
    holds_and_breaks_with(
        name,
        paged(all),
        paged(|s| {
            all(s);
            broken(s);
        }),
    )
}

/// Runs case `name` with `good` and `bad` settings: the first must stay under its threshold, the
/// second go over it.
fn holds_and_breaks_with(name: &str, good: Settings, bad: Settings) -> Option<(Score, Score)> {
    let gpu = common::gpu();
    if !gpu.computes() {
        eprintln!("SKIPPED: {name}: this device runs no compute shaders, so no page is marked");
        return None;
    }
    let case = case(name).unwrap();
    let measurer = || Measurer::new(&gpu, SIZE, TruthSettings { soft_rays: 0, ..TruthSettings::default() });
    let good = (case.run)(&mut measurer(), &good).unwrap();
    let bad = (case.run)(&mut measurer(), &bad).unwrap();
    eprintln!("{name}: {:.5} with virtual maps ({good:?}), {:.5} broken ({bad:?})", good.value(), bad.value());
    assert!(good.of > 100, "{name}: too few samples to judge ({good:?})");
    assert!(good.value() <= case.threshold, "{name}: {:.5} > {}", good.value(), case.threshold);
    assert!(bad.value() > case.threshold, "{name} broken: {:.5} <= {}", bad.value(), case.threshold);
    Some((good, bad))
}

#[test]
fn filters_near_a_page_border_read_its_border_but_read_a_stranger_without_one() {
    holds_and_breaks("page-seams", |s| s.maps.atlas_guard = false);
}

#[test]
fn a_camera_cut_reads_coarser_pages_until_its_own_come_but_shows_holes_without_the_fallback() {
    if let Some((good, _)) = holds_and_breaks("camera-cut", |s| s.maps.page_fallback = false) {
        assert_eq!(good.garbage, 0, "its pages come within the frames the case allows");
    }
}

#[test]
fn a_moving_box_leaves_no_shadow_behind_unless_the_pages_it_left_are_kept() {
    holds_and_breaks("moving-caster", |s| s.maps.old_bounds = false);
}

#[test]
fn a_pool_too_small_shadows_through_coarser_pages_but_not_without_the_fallback() {
    holds_and_breaks("pool-too-small", |s| s.maps.page_fallback = false);
}

#[test]
fn a_camera_creeping_across_a_level_boundary_flips_few_shadows_unless_the_grid_follows_it() {
    holds_and_breaks("level-creep", |s| s.cascade.fit_mode = FitMode::Unsnapped);
}

/// PCSS with every light paged: its blockers are found in the coarse map, searched no farther
/// than the nearest caster throws a penumbra, and filtered on the level where the penumbra fits a
/// page's border. A search of 24 texels of the finer pages the pool chose cut the pole's penumbra
/// short (42.7 % before).
#[test]
fn pcss_with_every_light_paged_keeps_its_contact_hardening() {
    let gpu = common::gpu();
    if !gpu.computes() {
        eprintln!("SKIPPED: this device runs no compute shaders, so no page is marked");
        return;
    }
    let case = case("contact-hardening").unwrap();
    let mut measurer = Measurer::new(&gpu, SIZE, TruthSettings { soft_rays: 0, ..TruthSettings::default() });
    let score = (case.run)(&mut measurer, &paged(|s| s.maps.light_maps = LightMaps::Virtual)).unwrap();
    eprintln!("contact-hardening, every light paged: {:.5} ({score:?})", score.value());
    assert!(score.of > 100, "too few samples to judge ({score:?})");
    assert!(score.value() <= case.threshold, "{:.5} > {}", score.value(), case.threshold);
}

/// On pages a filter or a biased point past a face's edge reads the page's border (drawn with
/// the face's margin): without both it reads a stranger's tile (1.4 % with the border alone
/// taken away, 2.4 % with both).
#[test]
fn a_paged_point_lights_shadow_holds_across_its_cube_seams_but_not_without_its_pages_borders() {
    holds_and_breaks_all_paged("cube-seams", |s| {
        s.maps.cube_seams = false;
        s.maps.atlas_guard = false;
    });
}

#[test]
fn paged_spots_starved_of_updates_keep_their_old_pages_until_their_turn_but_not_past_it() {
    holds_and_breaks_all_paged("starved-budget", |s| s.maps.max_stale = 1000);
}
