// A shadow-map layer as both passes see it, and what a moment map stores: the shadow pass
// writes `encode_moments` of each texel's nearest depth, the main pass filters those moments
// and reconstructs a visibility from them (shadow_sampling.wgsl).

// One layer of the shadow-map array: its projection, the world size of its texels, and how its
// moment map (if its light uses one) is made and read. Checked against the Rust struct of the
// same name (src/render/gpu_types.rs) by a test.
struct GpuLayer {
    clip_from_world: mat4x4<f32>,
    // World size of one texel: texel_base + texel_per_metre * distance from the light.
    texel_base: f32,
    texel_per_metre: f32,
    // View depth where this cascade ends, and the band before it where it blends into the next.
    far: f32,
    blend: f32,
    // How its projection turns distance from the light into depth (see layer_view_distance).
    depth_terms: vec2<f32>,
    // METHOD_* of its light.
    method: u32,
    // 1 for a perspective projection (spots and cube faces), 0 for a sun's cascade.
    perspective: u32,
    // EVSM's positive and negative exponents.
    warp: vec2<f32>,
    // Keeps a moment method's reconstruction stable: the least variance (VSM, in depth units;
    // EVSM, in warped-depth units per unit of depth) or the share of a two-point distribution
    // mixed into the moments (MSM).
    moment_bias: f32,
    // Light-bleeding reduction: the share of the bound cut away.
    bleed: f32,
};

// Distance from the light along the layer's view axis of map depth `z`, as
// `shadow::view_distance` computes it.
fn layer_view_distance(layer: GpuLayer, z: f32) -> f32 {
    let t = layer.depth_terms;
    if (layer.perspective == 1u) {
        return t.y / (z + t.x);
    }
    return (t.y - z) / t.x;
}

// Map depth `z` as moment maps keep it: distance from the light, 0 at the layer's near plane
// and 1 at its far one. A perspective depth crowds most distances next to 1, where their
// squares cancel; linear depth spreads them evenly.
fn linear_depth(layer: GpuLayer, z: f32) -> f32 {
    let near = layer_view_distance(layer, 0.0);
    let far = layer_view_distance(layer, 1.0);
    return clamp((layer_view_distance(layer, z) - near) / max(far - near, 1e-6), 0.0, 1.0);
}

// EVSM's two warps of linear depth `d` (taken to -1..1 first, which spends the exponent's
// range on both sides): e^(c+ x) and -e^(-c- x).
fn evsm_warp(layer: GpuLayer, d: f32) -> vec2<f32> {
    let x = 2.0 * d - 1.0;
    return vec2<f32>(exp(layer.warp.x * x), -exp(-layer.warp.y * x));
}

// What a moment map stores for map depth `z`: VSM the depth and its square, EVSM each warp and
// its square, MSM the depth's first four powers. (render/moments.rs clears maps to these values
// at depth 1.)
fn encode_moments(layer: GpuLayer, z: f32) -> vec4<f32> {
    let d = linear_depth(layer, z);
    if (layer.method == METHOD_EVSM) {
        let w = evsm_warp(layer, d);
        return vec4<f32>(w.x, w.x * w.x, w.y, w.y * w.y);
    }
    if (layer.method == METHOD_MSM) {
        let d2 = d * d;
        return vec4<f32>(d, d2, d2 * d, d2 * d2);
    }
    return vec4<f32>(d, d * d, 0.0, 0.0);
}
