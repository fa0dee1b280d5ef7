// The depth reduction of sample distribution shadow maps (Lauritzen, Salvi and Lefohn, "Sample
// Distribution Shadow Maps", I3D 2011). Each visible pixel of the camera's depth buffer is
// carried back to the world: its view depth goes into the frame's nearest and farthest, and its
// position in the sun's light space into the box of its view-depth bin (src/shadow/sdsm.rs reads
// them). Each 8x8 tile reduces into workgroup memory first, then once into the frame's words.
// Floats are compared as order keys (`order_key`, the same as Rust's).

struct Reduce {
    world_from_clip: mat4x4<f32>,
    light_from_world: mat4x4<f32>,
    eye: vec3<f32>,
    near: f32,
    forward: vec3<f32>,
    far: f32,
    size: vec2<u32>,
    _pad: vec2<u32>,
};

@group(0) @binding(0) var<uniform> reduce: Reduce;
// Bound as an unfilterable float texture: GLSL cannot load from a depth texture.
@group(0) @binding(1) var depth: texture_2d<f32>;
@group(0) @binding(2) var<storage, read_write> words: array<atomic<u32>, SDSM_WORDS>;

var<workgroup> tile: array<atomic<u32>, SDSM_WORDS>;

fn order_key(v: f32) -> u32 {
    let b = bitcast<u32>(v);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

// Where a reduction starts: every smallest at the largest key, every largest at zero (word 0
// is the nearest depth, word 1 the farthest, then each bin's 3 smallest and 3 largest).
fn start_word(i: u32) -> u32 {
    if i == 0u || (i >= 2u && (i - 2u) % 6u < 3u) {
        return 0xffffffffu;
    }
    return 0u;
}

fn take(i: u32, v: f32) {
    atomicMin(&tile[i], order_key(v));
}

fn give(i: u32, v: f32) {
    atomicMax(&tile[i], order_key(v));
}

@compute @workgroup_size(8, 8)
fn reduce_depth(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) local: u32) {
    for (var i = local; i < SDSM_WORDS; i += 64u) {
        atomicStore(&tile[i], start_word(i));
    }
    workgroupBarrier();
    if all(id.xy < reduce.size) {
        let d = textureLoad(depth, vec2<i32>(id.xy), 0).r;
        let ndc = vec2<f32>(
            (f32(id.x) + 0.5) / f32(reduce.size.x) * 2.0 - 1.0,
            1.0 - (f32(id.y) + 0.5) / f32(reduce.size.y) * 2.0,
        );
        let w = reduce.world_from_clip * vec4<f32>(ndc, d, 1.0);
        let world = w.xyz / w.w;
        let view_depth = dot(world - reduce.eye, reduce.forward);
        // The sky (depth 1) and anything not finite are not seen.
        if d < 1.0 && abs(view_depth) < 1e30 && all(abs(world) < vec3<f32>(1e30)) {
            take(0u, view_depth);
            give(1u, view_depth);
            if view_depth >= reduce.near && view_depth < reduce.far {
                let t = log(view_depth / reduce.near) / log(reduce.far / reduce.near);
                let bin = min(u32(t * f32(SDSM_BINS)), SDSM_BINS - 1u);
                let l = (reduce.light_from_world * vec4<f32>(world, 1.0)).xyz;
                let at = 2u + 6u * bin;
                take(at, l.x);
                take(at + 1u, l.y);
                take(at + 2u, l.z);
                give(at + 3u, l.x);
                give(at + 4u, l.y);
                give(at + 5u, l.z);
            }
        }
    }
    workgroupBarrier();
    for (var i = local; i < SDSM_WORDS; i += 64u) {
        let v = atomicLoad(&tile[i]);
        if v != start_word(i) {
            if start_word(i) == 0u {
                atomicMax(&words[i], v);
            } else {
                atomicMin(&words[i], v);
            }
        }
    }
}
