// Making a moment map prefiltered: the resolve that turns a layer's depth map into moments
// (`fs_resolve`), then a separable Gaussian blur (a blurred map gives soft edges from one
// filtered read). One blur pass runs along the rows of a tile of the colour atlas into the same
// place of a scratch page, the other along the scratch's columns back into the tile. Reads past
// the tile's edge take its edge texel, never a neighbour's.

struct Blur {
    // The page of the atlas the tile is on (of the colour atlas and of the depth one).
    layer: u32,
    // Texels each side of the centre it weighs; the Gaussian's sigma is half that.
    radius: i32,
    // The tile's side in texels, and depth texels along a side per moment texel.
    size: u32,
    scale: u32,
    // The tile's first texel on the colour page, and the layer's on the depth page.
    origin: vec2<u32>,
    depth_origin: vec2<u32>,
    // Samples per texel of the multisampled depth (`depth_samples`) a resolve of samples reads.
    samples: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(0) @binding(0) var<uniform> blur: Blur;
@group(1) @binding(0) var moment_layers: texture_2d_array<f32>;
@group(1) @binding(1) var scratch: texture_2d<f32>;
// The depth atlas, bound as unfilterable floats (GLSL cannot load from a depth texture).
@group(1) @binding(2) var depth_pages: texture_2d_array<f32>;
// Or one layer's depth drawn multisampled at the moment map's size, its corner the tile's.
@group(1) @binding(3) var depth_samples: texture_multisampled_2d<f32>;
// The layer being resolved: how its depth becomes moments.
@group(2) @binding(0) var<uniform> resolve_layer: GpuLayer;

// A triangle that covers the whole target (the viewport is the tile).
@vertex
fn vs_blur(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let corner = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(corner * 2.0 - 1.0, 0.0, 1.0);
}

fn weight(i: i32) -> f32 {
    let sigma = 0.5 * f32(max(blur.radius, 1));
    return exp(-f32(i * i) / (2.0 * sigma * sigma));
}

// The tile's first and last texels on the page.
fn tile_first() -> vec2<i32> {
    return vec2<i32>(blur.origin);
}

fn tile_last() -> vec2<i32> {
    return vec2<i32>(blur.origin) + i32(blur.size) - 1;
}

// The moments of texel `q` of the tile, resolved from the layer's depth map: the mean of the
// moments of the scale x scale depth texels it covers. Moments average linearly, so this is
// what filtering a map of full-size moments down would give (and what an MSAA resolve of
// that many samples gives): the mean depth would not be.
fn resolved(q: vec2<i32>) -> vec4<f32> {
    let s = i32(blur.scale);
    let first = vec2<i32>(blur.depth_origin) + (q - tile_first()) * s;
    var sum = vec4<f32>(0.0);
    for (var y = 0; y < s; y += 1) {
        for (var x = 0; x < s; x += 1) {
            let z = textureLoad(depth_pages, first + vec2<i32>(x, y), blur.layer, 0).r;
            sum += encode_moments(resolve_layer, z, vec3<f32>(0.0));
        }
    }
    return sum / f32(s * s);
}

// The same from the multisampled depth: the mean of the moments of texel `q`'s samples, an MSAA
// resolve of moments (MJP's "Shadows" sample makes its moment maps so from an MSAA depth map).
fn resolved_samples(q: vec2<i32>) -> vec4<f32> {
    let at = q - tile_first();
    var sum = vec4<f32>(0.0);
    for (var i = 0u; i < blur.samples; i += 1u) {
        sum += encode_moments(resolve_layer, textureLoad(depth_samples, at, i).r, vec3<f32>(0.0));
    }
    return sum / f32(max(blur.samples, 1u));
}

@fragment
fn fs_blur_rows(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(at.xy);
    var sum = vec4<f32>(0.0);
    var total = 0.0;
    for (var i = -blur.radius; i <= blur.radius; i += 1) {
        let q = clamp(p + vec2<i32>(i, 0), tile_first(), tile_last());
        sum += weight(i) * textureLoad(moment_layers, q, blur.layer, 0);
        total += weight(i);
    }
    return sum / total;
}

// The moments of a layer resolved from its depth map into its tile, before the blur. (Fused
// into the rows pass, each texel's moments would be made once for every tap that reads it.)
@fragment
fn fs_resolve(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    return resolved(vec2<i32>(at.xy));
}

@fragment
fn fs_resolve_samples(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    return resolved_samples(vec2<i32>(at.xy));
}

@fragment
fn fs_blur_columns(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(at.xy);
    var sum = vec4<f32>(0.0);
    var total = 0.0;
    for (var i = -blur.radius; i <= blur.radius; i += 1) {
        let q = clamp(p + vec2<i32>(0, i), tile_first(), tile_last());
        sum += weight(i) * textureLoad(scratch, q, 0);
        total += weight(i);
    }
    return sum / total;
}
