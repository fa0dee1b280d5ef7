// Filling a tile of the shadow atlas before its casters are drawn: cleared to the far plane (and
// its colour map to what an empty one keeps), or given back the depth of its casters at rest
// from the static atlas. The viewport and scissor are the tile: a render pass can clear only a
// whole page, so this draws over the tile instead.

struct Fill {
    // What a colour map keeps where nothing was drawn.
    colour: vec4<f32>,
    // The tile's page in the static atlas.
    page: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(0) @binding(0) var<uniform> fill: Fill;
@group(1) @binding(0) var statics: texture_depth_2d_array;

// A triangle over the whole tile, at the far plane.
@vertex
fn vs_fill(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let corner = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(corner * 2.0 - 1.0, 1.0, 1.0);
}

@fragment
fn fs_clear_colour() -> @location(0) vec4<f32> {
    return fill.colour;
}

// The depth the casters at rest left at this texel of the static atlas, unchanged.
@fragment
fn fs_restore(@builtin(position) at: vec4<f32>) -> @builtin(frag_depth) f32 {
    return textureLoad(statics, vec2<i32>(at.xy), i32(fill.page), 0);
}
