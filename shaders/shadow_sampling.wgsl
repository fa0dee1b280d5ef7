// Shadow-map lookups, one named function per method, apart from the lighting: everything they
// need comes in as parameters or from their own bindings.

@group(0) @binding(1) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;

// The methods this pipeline samples with, a bit (1 << METHOD_*) each, fixed when the pipeline is
// built: with one method in use only its code is reached, so no fragment chooses at run time.
override SHADOW_METHODS: u32 = 0xfu;

// Depth biases, each in shadow-map texels.
struct Bias {
    constant: f32,
    slope: f32,
    normal: f32,
};

// One comparison with the texel under `uv`: at a texel centre the bilinear weights are all on
// that texel.
fn shadow_nearest(uv: vec2<f32>, layer: u32, depth: f32) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_maps));
    let centre = (floor(uv * size) + 0.5) / size;
    return textureSampleCompareLevel(shadow_maps, shadow_sampler, centre, layer, depth);
}

// The hardware's 2x2 comparison filter.
fn shadow_bilinear(uv: vec2<f32>, layer: u32, depth: f32) -> f32 {
    return textureSampleCompareLevel(shadow_maps, shadow_sampler, uv, layer, depth);
}

// Percentage-closer filtering (Reeves, Salesin and Cook 1987): a (2r + 1)² grid of 2x2
// comparisons one texel apart, averaged.
fn shadow_pcf(uv: vec2<f32>, layer: u32, depth: f32, r: i32) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_maps));
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

fn method_used(method: u32) -> bool {
    return (SHADOW_METHODS & (1u << method)) != 0u;
}

// The lookup of `method` (a METHOD_* constant).
fn sample_shadow(method: u32, uv: vec2<f32>, layer: u32, depth: f32) -> f32 {
    let only = countOneBits(SHADOW_METHODS) == 1u;
    if (method_used(METHOD_NEAREST) && (only || method == METHOD_NEAREST)) {
        return shadow_nearest(uv, layer, depth);
    }
    if (method_used(METHOD_BILINEAR) && (only || method == METHOD_BILINEAR)) {
        return shadow_bilinear(uv, layer, depth);
    }
    if (method_used(METHOD_PCF3) && (only || method == METHOD_PCF3)) {
        return shadow_pcf(uv, layer, depth, 1);
    }
    if (method_used(METHOD_PCF5) && (only || method == METHOD_PCF5)) {
        return shadow_pcf(uv, layer, depth, 2);
    }
    return 1.0;
}

// World point `p` (unit normal `n`, unit direction `l` towards the light) pushed along the
// normal and towards the light by amounts measured in texels of world size `texel`, the slope
// term growing with tan(angle) as the depth error across a texel does on a tilted surface.
fn biased_point(p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, texel: f32, bias: Bias) -> vec3<f32> {
    let n_dot_l = clamp(dot(n, l), 0.0, 1.0);
    let sin_t = sqrt(1.0 - n_dot_l * n_dot_l);
    let tan_t = min(sin_t / max(n_dot_l, 1e-3), 10.0);
    return p + n * (bias.normal * texel) + l * ((bias.constant + bias.slope * tan_t) * texel);
}

// Visibility of the (already biased) world point `biased` in shadow-map `layer` seen through
// `clip_from_world`: 1 lit, 0 shadowed. Points outside the map are lit.
fn shadow_lookup(clip_from_world: mat4x4<f32>, layer: u32, biased: vec3<f32>, method: u32) -> f32 {
    let clip = clip_from_world * vec4<f32>(biased, 1.0);
    if (clip.w <= 0.0) {
        return 1.0;
    }
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0) {
        return 1.0;
    }
    return sample_shadow(method, uv, layer, ndc.z);
}
