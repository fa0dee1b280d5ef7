// Shadow-map lookups, kept apart from the lighting so filters can be swapped in one place.

@group(0) @binding(1) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;

// Depth biases, each in shadow-map texels.
struct Bias {
    constant: f32,
    slope: f32,
    normal: f32,
};

// Visibility of world point `p` (unit normal `n`, unit direction `l` towards the light) in the
// shadow map `layer` seen through `view_proj`: 1 lit, 0 shadowed. `texel` is the world size of one
// shadow-map texel at p. The point is pushed along the normal and towards the light by amounts
// measured in texels, the slope term growing with tan(angle) as the depth error across a texel
// does on a tilted surface. Points outside the map are lit.
fn shadow_visibility(view_proj: mat4x4<f32>, layer: i32, texel: f32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, bias: Bias) -> f32 {
    let n_dot_l = clamp(dot(n, l), 0.0, 1.0);
    let sin_t = sqrt(1.0 - n_dot_l * n_dot_l);
    let tan_t = min(sin_t / max(n_dot_l, 1e-3), 10.0);
    let biased = p + n * (bias.normal * texel) + l * ((bias.constant + bias.slope * tan_t) * texel);
    let clip = view_proj * vec4<f32>(biased, 1.0);
    if (clip.w <= 0.0) {
        return 1.0;
    }
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0) {
        return 1.0;
    }
    return filtered(uv, layer, ndc.z);
}

// The filter setting (frame.misc.w): 0 nearest, 1 bilinear, 2 a 3x3 and 3 a 5x5 grid of
// bilinear comparisons one texel apart, averaged (percentage-closer filtering).
fn filtered(uv: vec2<f32>, layer: i32, depth: f32) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_maps));
    let mode = i32(frame.misc.w);
    if (mode == 0) {
        // At a texel centre the bilinear weights are all on that texel: a plain comparison.
        let centre = (floor(uv * size) + 0.5) / size;
        return textureSampleCompareLevel(shadow_maps, shadow_sampler, centre, layer, depth);
    }
    let r = max(mode - 1, 0);
    var sum = 0.0;
    for (var y = -r; y <= r; y += 1) {
        for (var x = -r; x <= r; x += 1) {
            let at = uv + vec2<f32>(f32(x), f32(y)) / size;
            sum += textureSampleCompareLevel(shadow_maps, shadow_sampler, at, layer, depth);
        }
    }
    let n = f32((2 * r + 1) * (2 * r + 1));
    return sum / n;
}
