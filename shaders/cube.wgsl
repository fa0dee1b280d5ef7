// Shared by the lookups (lights.wgsl) and the marking of pages (page_marks.wgsl), so both pick
// the same face of a point light's cube.

// The cube face (0..6: +X, -X, +Y, -Y, +Z, -Z) that holds direction `d`: its largest axis, as
// `shadow::cube_face` picks it.
fn cube_face(d: vec3<f32>) -> u32 {
    let a = abs(d);
    if (a.x >= a.y && a.x >= a.z) {
        return select(0u, 1u, d.x < 0.0);
    }
    if (a.y >= a.z) {
        return select(2u, 3u, d.y < 0.0);
    }
    return select(4u, 5u, d.z < 0.0);
}
