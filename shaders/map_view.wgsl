// The shadow-map viewer: each layer drawn into its tile of an atlas as distance from the light,
// spread from black (its near plane) to white (its far plane), so cascades, spot maps and cube
// faces all read alike: the depth map's depth turned back into distance, or, for a light whose
// method reads a colour map, what that map keeps of it (the first moment, EVSM's warp undone,
// R32F's linear depth, R16F's metres).

// Per layer, three vectors: (depth terms x, y, near distance, far distance), (1 if perspective,
// its light's METHOD_*, EVSM's positive exponent, 0), (its tile's corner x, y and side as shares
// of the page, its page).
@group(0) @binding(0) var<uniform> view_layers: array<vec4<f32>, 288>;
// The depth atlas, bound as unfilterable floats: GLSL cannot load from a depth texture.
@group(0) @binding(1) var maps: texture_2d_array<f32>;
@group(0) @binding(2) var colours: texture_2d_array<f32>;

struct TileOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) layer: u32,
};

// One triangle over the whole tile (the viewport), instance i drawing layer i.
@vertex
fn vs_tile(@builtin(vertex_index) v: u32, @builtin(instance_index) layer: u32) -> TileOut {
    let uv = vec2<f32>(f32((v << 1u) & 2u), f32(v & 2u));
    return TileOut(vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0), uv, layer);
}

// The texel at `uv` across `tile` (corner and side as shares of the page) of a page of `page`
// texels.
fn tile_texel(tile: vec4<f32>, uv: vec2<f32>, page: vec2<f32>) -> vec2<i32> {
    let side = max(i32(round(tile.z * page.x)), 1);
    let corner = vec2<i32>(round(tile.xy * page));
    return corner + clamp(vec2<i32>(uv * f32(side)), vec2<i32>(0), vec2<i32>(side - 1));
}

@fragment
fn fs_tile(in: TileOut) -> @location(0) vec4<f32> {
    let a = view_layers[3u * in.layer];
    let b = view_layers[3u * in.layer + 1u];
    let tile = view_layers[3u * in.layer + 2u];
    let texel = tile_texel(tile, in.uv, vec2<f32>(textureDimensions(maps)));
    // The colour atlas may be smaller than the depth one (moments resolved at a half or a
    // quarter of its side): the tile is the same share of its page.
    let colour = tile_texel(tile, in.uv, vec2<f32>(textureDimensions(colours)));
    let layer = i32(tile.w);
    let method = u32(b.y);
    var grey: f32;
    switch method {
        case METHOD_VSM, METHOD_MSM, METHOD_MSM_HAUSDORFF, METHOD_R32F: {
            // Linear depth, 0 at the near plane and 1 at the far one, as moments.wgsl keeps it.
            grey = textureLoad(colours, colour, layer, 0).x;
        }
        case METHOD_EVSM, METHOD_EVSM2: {
            // e^(c x) with x = 2d - 1: undone.
            let m = max(textureLoad(colours, colour, layer, 0).x, 1e-30);
            grey = (log(m) / max(b.z, 1e-3) + 1.0) * 0.5;
        }
        case METHOD_R16F_RADIAL: {
            grey = textureLoad(colours, colour, layer, 0).x / max(a.w - a.z, 1e-6);
        }
        default: {
            let z = textureLoad(maps, texel, layer, 0).x;
            let distance = select((a.y - z) / a.x, a.y / (z + a.x), b.x > 0.5);
            grey = (distance - a.z) / max(a.w - a.z, 1e-6);
        }
    }
    return vec4<f32>(vec3<f32>(clamp(grey, 0.0, 1.0)), 1.0);
}
