// A shadow-map layer as both passes see it, and what a colour map stores: the shadow pass
// writes `encode_moments` of each texel's nearest surface, the main pass filters moments and
// reconstructs a visibility from them, or compares with a depth kept in colour
// (shadow_sampling.wgsl).

// One layer of a light's shadow, a tile of the atlas: its projection, the world size of its texels, and how its
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
    // Where its light is (spots and points), from which R16F radial measures distance.
    origin: vec3<f32>,
    // Its tile of the atlas: the page, then the corner and the side's share of the page (as
    // texture coordinates) and the side in texels.
    page: u32,
    tile: vec4<f32>,
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

// How far world point `p` (map depth `z`, already scaled by a multiplicative offset of
// `scale`) is from the light as R16F radial keeps it: from the light itself in a perspective
// layer (seed 004's radial distance), along the light from the layer's near plane in a cascade
// (a sun has no position, and the plane can lie anywhere behind the casters).
fn light_distance(layer: GpuLayer, z: f32, p: vec3<f32>, scale: f32) -> f32 {
    if (layer.perspective == 1u) {
        return distance(p, layer.origin) * (1.0 - max(scale, 0.0));
    }
    return layer_view_distance(layer, z) - layer_view_distance(layer, 0.0);
}

// Non-negative `x` rounded to the nearest half float (11 significant bits, ties to even), as
// an R16Float target stores it; at most the largest half float. (pack2x16float would do it, but
// needs a capability not every backend has.) The spacing of half floats at x is 2^(e - 10) for
// x's exponent e, read from its bits, and 2^-24 below the smallest normal half float (2^-14).
fn round_to_half(x: f32) -> f32 {
    if (!(x > 0.0)) {
        return 0.0;
    }
    let exponent = i32((bitcast<u32>(x) >> 23u) & 0xffu) - 127;
    let step = exp2(f32(max(exponent, -14) - 10));
    return min(round(x / step) * step, 65504.0);
}

// What a colour map stores for the surface at world point `p`, map depth `z`: VSM the depth and
// its square, EVSM each warp and its square (EVSM2 the positive one's), MSM the depth's first four powers; R32F the linear
// depth (seed 001) and R16F radial the distance from the light rounded to a half float (seed
// 004; rounded here, so a wider map shared with another method keeps the format's precision).
// (render/moments.rs clears maps to these values at depth 1.)
fn encode_moments(layer: GpuLayer, z: f32, p: vec3<f32>) -> vec4<f32> {
    let d = linear_depth(layer, z);
    if (layer.method == METHOD_R32F) {
        return vec4<f32>(d, 0.0, 0.0, 0.0);
    }
    if (layer.method == METHOD_R16F_RADIAL) {
        return vec4<f32>(round_to_half(light_distance(layer, z, p, 0.0)), 0.0, 0.0, 0.0);
    }
    if (layer.method == METHOD_EVSM) {
        let w = evsm_warp(layer, d);
        return vec4<f32>(w.x, w.x * w.x, w.y, w.y * w.y);
    }
    if (layer.method == METHOD_EVSM2) {
        let w = evsm_warp(layer, d).x;
        return vec4<f32>(w, w * w, 0.0, 0.0);
    }
    if (layer.method == METHOD_MSM || layer.method == METHOD_MSM_HAUSDORFF) {
        let d2 = d * d;
        return vec4<f32>(d, d2, d2 * d, d2 * d2);
    }
    return vec4<f32>(d, d * d, 0.0, 0.0);
}
