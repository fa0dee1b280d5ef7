// The marking of paged lights' pages, a batch of lights at a time: each visible pixel of the
// camera's depth buffer is carried back to the world and the surface there found from its
// neighbours' depths, once for every light; then, for each light of the batch that reaches it,
// the page of the level its footprint wants (page_level in pages.wgsl finds the same level from
// the fragment's derivatives) is marked in a bit of the light's slice of the marks, in its
// level's window (src/shadow/pages.rs reads the bits). Each invocation marks a 4x4 block of
// pixels, skips the lights whose reach misses the block's box, and sets a bit only when it
// differs from the last one it set for that light: neighbouring pixels mostly want the same page.

struct MarkView {
    world_from_clip: mat4x4<f32>,
    eye: vec3<f32>,
    // The lights of this marking.
    count: u32,
    forward: vec3<f32>,
    // Radians a pixel spans.
    pixel_angle: f32,
    size: vec2<u32>,
    _pad0: u32,
    _pad1: u32,
};

struct MarkLight {
    // World to level-0 page units: a cube's six faces', or one map's first.
    page_from_world: array<mat4x4<f32>, 6>,
    // Each level's window origin, two levels a vector.
    origins: array<vec4<i32>, 8>,
    // Where the light is: its position (w 1) or the direction towards it (w 0).
    light: vec4<f32>,
    // The sphere its light reaches: centre and radius (negative: everywhere).
    reach: vec4<f32>,
    shadow_distance: f32,
    // log2 of level 0's texel where w is 1.
    finest_log2: f32,
    levels: u32,
    bias: f32,
    // Level-0 page units a side of a perspective map (0: a clipmap, with no edge).
    extent: f32,
    // 6 for a cube, 1 for others.
    faces: u32,
    // Level-0 page units a side of a cube's face.
    face_side: f32,
    // 1 where the light's lookups read every level coarser than the one a pixel wants (see
    // paged_visibility), so each is marked too; 0 for others.
    coarser: u32,
};

@group(0) @binding(0) var<uniform> view: MarkView;
// Bound as an unfilterable float texture: GLSL cannot load from a depth texture.
@group(0) @binding(1) var depth: texture_2d<f32>;
// Each light's slice: MAX_PAGE_LEVELS levels of MARK_WORDS words.
@group(0) @binding(2) var<storage, read_write> marks: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read> lights: array<MarkLight>;

// The world point at pixel `at` (held inside the buffer) and depth `d`.
fn world_at_depth(at: vec2<i32>, d: f32) -> vec3<f32> {
    let uv = (vec2<f32>(at) + 0.5) / vec2<f32>(view.size);
    let w = view.world_from_clip * vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, d, 1.0);
    return w.xyz / w.w;
}

// The depth buffer at pixel `at`, held inside it.
fn depth_at(at: vec2<i32>) -> f32 {
    return textureLoad(depth, vec2<u32>(clamp(at, vec2<i32>(0), vec2<i32>(view.size) - 1)), 0).r;
}

// The step from `p` (depth `d`, pixel `at`) to the surface at the next pixel along `axis`: the
// shorter of the steps to the neighbours on either side (a step across an edge to another
// surface is the longer one); where neither shows a surface (a pixel-thin part against the sky),
// the step to the next pixel at the same depth, as for a surface facing the camera.
fn step_along(at: vec2<i32>, p: vec3<f32>, d: f32, axis: vec2<i32>) -> vec3<f32> {
    let da = depth_at(at + axis);
    let db = depth_at(at - axis);
    let to_a = world_at_depth(at + axis, da) - p;
    let to_b = p - world_at_depth(at - axis, db);
    let a = da < 1.0 && (db >= 1.0 || dot(to_a, to_a) <= dot(to_b, to_b));
    if (a) {
        return to_a;
    }
    if (db < 1.0) {
        return to_b;
    }
    return world_at_depth(at + axis, d) - p;
}

// What a pixel shows, for every light: where it is, which way it faces (towards the camera),
// the size of its footprint facing the camera, and how squarely it faces the camera. None
// where `size` is negative (the sky).
struct Surface {
    p: vec3<f32>,
    size: f32,
    n: vec3<f32>,
    n_dot_v: f32,
};

fn surface_at(at: vec2<i32>) -> Surface {
    var s = Surface(vec3<f32>(0.0), -1.0, vec3<f32>(0.0), 1.0);
    if (any(at >= vec2<i32>(view.size))) {
        return s;
    }
    let d = depth_at(at);
    if (d >= 1.0) {
        return s;
    }
    s.p = world_at_depth(at, d);
    let c = cross(step_along(at, s.p, d, vec2<i32>(1, 0)), step_along(at, s.p, d, vec2<i32>(0, 1)));
    let area = length(c);
    let to_eye = view.eye - s.p;
    let distance = length(to_eye);
    let v = to_eye / max(distance, 1e-6);
    s.n = select(v, c / area, area > 0.0);
    if (dot(s.n, v) < 0.0) {
        s.n = -s.n;
    }
    s.size = max(distance * view.pixel_angle, 0.0);
    s.n_dot_v = clamp(abs(dot(s.n, v)), MIN_GRAZE, 1.0);
    return s;
}

// The bit (word, mask) of light `i`'s page of `level` that holds `units` (level-0 page units),
// or a mask of 0 where it is outside the level's window.
fn page_bit(i: u32, units: vec2<f32>, level: u32) -> vec2<u32> {
    let pair = lights[i].origins[level / 2u];
    let origin = select(pair.xy, pair.zw, level % 2u == 1u);
    let cell = vec2<i32>(floor(units / exp2(f32(level)))) - origin;
    if (any(cell < vec2<i32>(0)) || any(cell >= vec2<i32>(i32(PAGE_GRID)))) {
        return vec2<u32>(0u);
    }
    let index = u32(cell.y) * PAGE_GRID + u32(cell.x);
    let word = (i * MAX_PAGE_LEVELS + level) * MARK_WORDS + index / 32u;
    return vec2<u32>(word, 1u << (index % 32u));
}

// True where light `i` reaches some point of the box from `lo` to `hi`.
fn reaches_box(i: u32, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    let reach = lights[i].reach;
    return reach.w < 0.0 || distance(clamp(reach.xyz, lo, hi), reach.xyz) <= reach.w;
}

// The pages of light `i` that surface `s` wants: where it is (level-0 page units) and its level
// (as page_level in pages.wgsl finds it), and the next level too where the pixel lies within a
// tenth of an octave of the two's border, so a lookup whose footprint rounds the other way finds
// its page (`other`, `level` where there is none). None where it wants no page.
struct Wanted {
    some: bool,
    units: vec2<f32>,
    level: u32,
    other: u32,
};

fn wanted_pages(i: u32, s: Surface) -> Wanted {
    let none = Wanted(false, vec2<f32>(0.0), 0u, 0u);
    let p = s.p;
    if (s.size < 0.0 || dot(p - view.eye, view.forward) >= lights[i].shadow_distance) {
        return none;
    }
    // Only where the light reaches, and on its map (page units over w, as page_layer reads them).
    let reach = lights[i].reach;
    if (reach.w >= 0.0 && distance(p, reach.xyz) > reach.w) {
        return none;
    }
    // A cube's face holding `p` looks along its largest axis from the light (as the lookups
    // pick it: page_face in pages.wgsl).
    let face = select(0u, cube_face(p - lights[i].light.xyz), lights[i].faces == 6u);
    let u = lights[i].page_from_world[face] * vec4<f32>(p, 1.0);
    var units = u.xy / u.w;
    let face_side = lights[i].face_side;
    if (face_side > 0.0) {
        // Held on its face's square (its edge would round onto the next face's first page).
        let origin = vec2<f32>(f32(face % CUBE_ACROSS), f32(face / CUBE_ACROSS)) * face_side;
        units = clamp(units, origin, origin + vec2<f32>(face_side - 1e-3));
    }
    let extent = lights[i].extent;
    let off_map = extent > 0.0 && (any(units < vec2<f32>(0.0)) || any(units >= vec2<f32>(extent)));
    if (u.w <= 0.0 || off_map) {
        return none;
    }
    let light = lights[i].light;
    let n_dot_l = dot(s.n, normalize(light.xyz - p * light.w));
    // A surface turned away from the light makes no lookup (a little slack for shading normals).
    if (n_dot_l < -0.1) {
        return none;
    }
    let wanted = s.size * sqrt(clamp(abs(n_dot_l), MIN_GRAZE, 1.0) / s.n_dot_v);
    // A texel of level 0 here is 2^finest_log2 · w (w is 1 for a sun).
    let octaves = log2(wanted) - lights[i].finest_log2 - log2(u.w) + lights[i].bias;
    let top = f32(lights[i].levels - 1u);
    let level = clamp(round(octaves), 0.0, top);
    let other = clamp(select(level - 1.0, level + 1.0, octaves > level), 0.0, top);
    let near_border = abs(abs(octaves - level) - 0.5) < 0.1;
    return Wanted(true, units, u32(level), u32(select(level, other, near_border)));
}

// Sets bit `bit` (word, mask) of the marks; none for a mask of 0.
fn mark(bit: vec2<u32>) {
    if (bit.y != 0u) {
        atomicOr(&marks[bit.x], bit.y);
    }
}

@compute @workgroup_size(8, 8)
fn mark_pages(@builtin(global_invocation_id) id: vec3<u32>) {
    let corner = vec2<i32>(id.xy * 4u);
    var surfaces: array<Surface, 16>;
    var lo = vec3<f32>(3.4e38);
    var hi = vec3<f32>(-3.4e38);
    for (var k = 0; k < 16; k += 1) {
        surfaces[k] = surface_at(corner + vec2<i32>(k % 4, k / 4));
        if (surfaces[k].size >= 0.0) {
            lo = min(lo, surfaces[k].p);
            hi = max(hi, surfaces[k].p);
        }
    }
    if (any(lo > hi)) {
        return;
    }
    for (var i = 0u; i < view.count; i += 1u) {
        if (!reaches_box(i, lo, hi)) {
            continue;
        }
        var last = vec2<u32>(0u);
        for (var k = 0; k < 16; k += 1) {
            let wanted = wanted_pages(i, surfaces[k]);
            if (!wanted.some) {
                continue;
            }
            let bit = page_bit(i, wanted.units, wanted.level);
            if (any(bit != last)) {
                mark(bit);
                last = bit;
                // Every coarser level's page over it as well, for a light whose lookups read them
                // (PCSS on pages: where its penumbra fits a page's border).
                for (var l = wanted.level + 1u; l < lights[i].levels * lights[i].coarser; l += 1u) {
                    mark(page_bit(i, wanted.units, l));
                }
            }
            if (wanted.other != wanted.level) {
                mark(page_bit(i, wanted.units, wanted.other));
            }
        }
    }
}
