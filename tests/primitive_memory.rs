//! A model of 20,000 primitives, each a mesh of its own to umbra and so a draw call of its own in
//! every shadow layer that sees it, placed in the sample scene and drawn at each size of
//! `common::MEMORY_FRAMES` as `umbra render --model` does, stays under 1 GB of resident memory. It
//! took 1.26 GB on lavapipe before the shadow pass was submitted in parts (`src/render/parts.rs`),
//! and overflowed a test thread's stack before obvhs's debug checks were turned off (`Cargo.toml`):
//! its 20,000 coincident boxes make a hierarchy 20,000 levels deep. Alone in its binary, so that no
//! other test's memory lands in the count.

mod common;

use common::gltf::TestModel;

#[test]
fn a_model_of_20_000_primitives_is_drawn_in_under_a_gigabyte() {
    let Some(peak) = common::peak_drawing("20,000 primitives", || TestModel::primitives(20_000)) else { return };
    assert!(peak < 1_000_000_000, "peak resident {peak} bytes: over 1 GB");
}
