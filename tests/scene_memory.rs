//! What drawing a large model costs the whole process, GPU driver included (a software one keeps
//! its buffers and each draw's state in the process's memory): a file of 100,000 nodes placed in
//! the sample scene and drawn at each size of `common::MEMORY_FRAMES`, as `umbra render --model`
//! does, stays under 1 GB of resident memory (1.06 GB before each object's placement was shared by
//! its layers). Alone in its binary, so that no other test's memory lands in the count
//! (`tests/primitive_memory.rs` is its twin for a model of many primitives).

mod common;

use common::gltf::TestModel;

#[test]
fn a_model_of_100_000_nodes_is_drawn_in_under_a_gigabyte() {
    let Some(peak) = common::peak_drawing("100,000 nodes", || TestModel::instanced(100_000)) else { return };
    assert!(peak < 1_000_000_000, "peak resident {peak} bytes: over 1 GB");
}
