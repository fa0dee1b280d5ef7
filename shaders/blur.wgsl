// The separable Gaussian blur of a moment map (what makes it "prefiltered": a blurred map
// gives soft edges from one filtered read). One pass runs along the rows of a tile of the
// colour atlas into the same place of a scratch page, the other along the scratch's columns
// back into the tile. Reads past the tile's edge take its edge texel, never a neighbour's.

struct Blur {
    // The page of the atlas the tile is on.
    layer: u32,
    // Texels each side of the centre it weighs; the Gaussian's sigma is half that.
    radius: i32,
    // The tile's side in texels, and its first texel on the page.
    size: u32,
    _pad0: u32,
    origin: vec2<u32>,
    _pad1: vec2<u32>,
};

@group(0) @binding(0) var<uniform> blur: Blur;
@group(1) @binding(0) var moment_layers: texture_2d_array<f32>;
@group(1) @binding(1) var scratch: texture_2d<f32>;

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
