// Shadow-map lookups, one named function per method, apart from the lighting: everything they
// need comes in as parameters or from their own bindings.

// The shadow atlas: pages of depth, each layer a tile of one page.
@group(0) @binding(1) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;
// The colour atlas, tile for tile with the depth one (only tiles of lights whose method reads
// a colour map hold any), read with bilinear filtering.
@group(0) @binding(6) var moment_maps: texture_2d_array<f32>;
@group(0) @binding(7) var moment_sampler: sampler;

// The methods this pipeline samples with, a bit (1 << METHOD_*) each, fixed when the pipeline is
// built: with one method in use only its code is reached, so no fragment chooses at run time.
override SHADOW_METHODS: u32 = 0xfu;

// Depth biases, in shadow-map texels but for `metres`, a constant one in metres.
struct Bias {
    constant: f32,
    slope: f32,
    normal: f32,
    metres: f32,
};

// What a lookup knows of the receiving surface besides its point: how its world position changes
// to the next pixel right and down (screen-space derivatives, for the receiver plane) and the
// pixel itself (to turn Poisson discs). Where there are no neighbours (probes) both changes are
// zero and no plane is found.
struct Footprint {
    dp_dx: vec3<f32>,
    dp_dy: vec3<f32>,
    pixel: vec2<f32>,
};

// Where a lookup lands in a layer: the position in its tile (0..1 across it), the depth compared
// there, and how the receiver's depth changes across the tile (depth per unit of uv; zero when
// not used); the tile itself (see GpuLayer.tile) and its page.
struct ShadowCoord {
    uv: vec2<f32>,
    layer: u32,
    tile: vec4<f32>,
    // Taps are kept inside the tile (see atlas_uv).
    guard: bool,
    depth: f32,
    plane: vec2<f32>,
    pixel: vec2<f32>,
    // The receiver's distance from the light as R16F radial compares it (see light_distance).
    distance: f32,
};

// The guard against atlas seams: where the point `uv` of the tile (0..1 across it) lies on the
// page, held half a texel inside the tile, so that no filter's 2x2 footprint reaches a
// neighbour's texels; past the edge the edge texels repeat, as a map of its own would clamp.
fn atlas_uv(c: ShadowCoord, uv: vec2<f32>) -> vec2<f32> {
    if (!c.guard) {
        return c.tile.xy + uv * c.tile.z;
    }
    let half = vec2<f32>(0.5 / c.tile.w);
    return c.tile.xy + clamp(uv, half, 1.0 - half) * c.tile.z;
}

// A 2x2 comparison at `at` with the receiver's depth there: on its plane, not at the centre.
fn compare_at(c: ShadowCoord, at: vec2<f32>) -> f32 {
    let depth = c.depth + dot(c.plane, at - c.uv);
    return textureSampleCompareLevel(shadow_maps, shadow_sampler, atlas_uv(c, at), c.layer, depth);
}

// The lookup's tile size in texels, along each side.
fn map_size(c: ShadowCoord) -> vec2<f32> {
    return vec2<f32>(c.tile.w);
}

// One comparison with the texel under `uv`: at a texel centre the bilinear weights are all on
// that texel.
fn shadow_nearest(c: ShadowCoord) -> f32 {
    let centre = (floor(c.uv * map_size(c)) + 0.5) / map_size(c);
    return textureSampleCompareLevel(shadow_maps, shadow_sampler, atlas_uv(c, centre), c.layer, c.depth);
}

// The hardware's 2x2 comparison filter.
fn shadow_bilinear(c: ShadowCoord) -> f32 {
    return compare_at(c, c.uv);
}

// Percentage-closer filtering (Reeves, Salesin and Cook 1987): a (2r + 1)² grid of 2x2
// comparisons one texel apart, averaged.
fn shadow_pcf(c: ShadowCoord, r: i32) -> f32 {
    var sum = 0.0;
    for (var y = -r; y <= r; y += 1) {
        for (var x = -r; x <= r; x += 1) {
            sum += compare_at(c, c.uv + vec2<f32>(f32(x), f32(y)) / map_size(c));
        }
    }
    let n = f32((2 * r + 1) * (2 * r + 1));
    return sum / n;
}

// The optimised Gaussian PCF of Castaño (2013, "Shadow Mapping Summary, part 1"; shipped by The
// Witness, Bevy and Filament): a 5x5-texel kernel with tent-like weights, taken as 3x3 bilinear
// comparisons placed between texels so that their bilinear weights add up to the kernel's. Along
// each axis, with s the point's place between two texel centres, the three taps weigh 4 - 3s, 7
// and 1 + 3s (12 in all) and sit where those weights split between their texels.
fn shadow_gauss5(c: ShadowCoord) -> f32 {
    let t = c.uv * map_size(c) + 0.5;
    let base = floor(t) - 0.5;
    let s = t - floor(t);
    let w = array<vec2<f32>, 3>(4.0 - 3.0 * s, vec2<f32>(7.0), 1.0 + 3.0 * s);
    let o = array<vec2<f32>, 3>((3.0 - 2.0 * s) / w[0] - 2.0, (3.0 + s) / 7.0, s / w[2] + 2.0);
    var sum = 0.0;
    for (var j = 0; j < 3; j += 1) {
        for (var i = 0; i < 3; i += 1) {
            let at = (base + vec2<f32>(o[i].x, o[j].y)) / map_size(c);
            sum += w[i].x * w[j].y * compare_at(c, at);
        }
    }
    // The weights add up to 144 only up to rounding: clamped, a lit point never reads above 1.
    return clamp(sum / 144.0, 0.0, 1.0);
}

// Interleaved gradient noise (Jimenez 2014, "Next generation post processing in Call of Duty:
// Advanced Warfare"): a value in 0..1 per pixel whose neighbours differ as much as they can.
fn interleaved_gradient_noise(pixel: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(floor(pixel), vec2<f32>(0.06711056, 0.00583715))));
}

// The rotation (cos, sin) a pixel turns its Poisson disc by.
fn disc_turn(pixel: vec2<f32>) -> vec2<f32> {
    let a = 6.2831853 * interleaved_gradient_noise(pixel);
    return vec2<f32>(cos(a), sin(a));
}

// Point `d` of a unit disc turned by `turn` and scaled to `radius` texels of `c`'s tile, as a
// uv offset.
fn disc_offset(c: ShadowCoord, d: vec2<f32>, turn: vec2<f32>, radius: f32) -> vec2<f32> {
    let r = vec2<f32>(d.x * turn.x - d.y * turn.y, d.x * turn.y + d.y * turn.x);
    return r * radius / map_size(c);
}

// Poisson-disc PCF: comparisons spread evenly over a disc (points no two of which are close,
// src/shadow/poisson.rs), the disc turned per pixel so the pattern's banding becomes fine noise.
fn shadow_poisson16(c: ShadowCoord, radius: f32) -> f32 {
    let turn = disc_turn(c.pixel);
    var sum = 0.0;
    for (var i = 0; i < 16; i += 1) {
        sum += compare_at(c, c.uv + disc_offset(c, POISSON_16[i], turn, radius));
    }
    return sum / 16.0;
}

fn shadow_poisson32(c: ShadowCoord, radius: f32) -> f32 {
    let turn = disc_turn(c.pixel);
    var sum = 0.0;
    for (var i = 0; i < 32; i += 1) {
        sum += compare_at(c, c.uv + disc_offset(c, POISSON_32[i], turn, radius));
    }
    return sum / 32.0;
}

// One layer as a lookup sees it: its data (its tile with it), the size of its light (see
// GpuLight.size), whether PCSS searches it for blockers (else PCSS filters with a fixed
// kernel), and whether its taps are kept inside its tile.
struct LayerRef {
    layer: GpuLayer,
    guard: bool,
    light_size: f32,
    pcss_search: bool,
    // The light's multiplicative depth offset (see scaled_depth).
    bias_scale: f32,
    // The widest penumbra PCSS searches for and draws, in texels: PCSS_MAX_PENUMBRA, or a page's
    // border on a page (see paged_visibility).
    widest: f32,
    // How near to the light its casters come along its axis, in metres, where that is known
    // (GpuLight.nearest_caster; 0 where not): no blocker is nearer.
    nearest: f32,
};

fn view_distance(at: LayerRef, z: f32) -> f32 {
    return layer_view_distance(at.layer, z);
}

// The moments of the lookup's layer around its point, bilinearly filtered from the blurred map.
// The moment map may be smaller than the depth map (resolved at a half or a quarter of its
// side): the tile is the same share of its page, and the seams' guard is half of its own texel.
fn filtered_moments(c: ShadowCoord) -> vec4<f32> {
    var m = c;
    m.tile.w = c.tile.z * f32(textureDimensions(moment_maps).x);
    return textureSampleLevel(moment_maps, moment_sampler, atlas_uv(m, c.uv), c.layer, 0.0);
}

// Chebyshev's one-sided inequality: of a distribution with this mean and mean square (its
// variance held to at least `least`), at most this share lies beyond `d`, so at least the rest
// of the light gets through. Exact for one flat occluder over a flat receiver.
fn chebyshev(mean: f32, square: f32, d: f32, least: f32) -> f32 {
    let variance = max(square - mean * mean, least);
    let beyond = d - mean;
    if (beyond <= 0.0) {
        return 1.0;
    }
    return variance / (variance + beyond * beyond);
}

// Light-bleeding reduction (Lauritzen 2007): where two occluders overlap, the bound stays
// well above zero in the shadow of the lower one; cutting the lowest `amount` of it away and
// stretching the rest darkens those regions, at the price of slightly harder edges.
fn reduce_bleeding(p: f32, amount: f32) -> f32 {
    return clamp((p - amount) / (1.0 - amount), 0.0, 1.0);
}

// Variance shadow maps (Donnelly and Lauritzen 2006, "Variance shadow maps").
fn shadow_vsm(c: ShadowCoord, at: LayerRef) -> f32 {
    let m = filtered_moments(c);
    let d = linear_depth(at.layer, c.depth);
    return reduce_bleeding(chebyshev(m.x, m.y, d, at.layer.moment_bias), at.layer.bleed);
}

// Exponential variance shadow maps (Lauritzen and McCool 2008, "Layered variance shadow maps";
// four moments as in Lauritzen's "Summed-area variance shadow maps" notes): Chebyshev's bound on
// a positive and a negative exponential warp of the depth, the tighter of the two. The warp
// squeezes the occluders' spread relative to the receiver's distance from them, so much less
// light bleeds. The least variance grows with the warp's slope at the point.
fn shadow_evsm(c: ShadowCoord, at: LayerRef) -> f32 {
    let m = filtered_moments(c);
    let w = evsm_warp(at.layer, linear_depth(at.layer, c.depth));
    let slope = 2.0 * at.layer.warp * abs(w) * at.layer.moment_bias;
    let positive = chebyshev(m.x, m.y, w.x, slope.x * slope.x);
    let negative = chebyshev(m.z, m.w, w.y, slope.y * slope.y);
    return reduce_bleeding(min(positive, negative), at.layer.bleed);
}

// EVSM with the positive warp alone (two moments, in a map half EVSM's size): the bound of
// shadow_evsm's first half. Where a receiver lies close behind an occluder over a far one, the
// positive warp leaves light the negative warp would have cut.
fn shadow_evsm2(c: ShadowCoord, at: LayerRef) -> f32 {
    let m = filtered_moments(c);
    let w = evsm_warp(at.layer, linear_depth(at.layer, c.depth)).x;
    let slope = 2.0 * at.layer.warp.x * w * at.layer.moment_bias;
    return reduce_bleeding(chebyshev(m.x, m.y, w, slope * slope), at.layer.bleed);
}

// Moment shadow maps (Peters and Klein 2015, "Moment shadow mapping"). Of every distribution
// of depths with the four filtered moments, the reconstruction finds the one that puts the most
// of its weight in front of the receiver's depth `d`; that weight bounds the shadow. The
// moments are first mixed with a little of a distribution half at 0 and half at 1 (moments 0.5
// each), which keeps the solve invertible under rounding.
struct MsmSolve {
    // The biased moments, and the receiver's depth.
    b: vec4<f32>,
    d: f32,
    // Hamburger's other two points, z2 <= z3.
    z2: f32,
    z3: f32,
};

// Hamburger's three points: d and the two roots z2, z3 of a quadratic found through a
// Cholesky solve of the moments' Hankel matrix [[1, b1, b2], [b1, b2, b3], [b2, b3, b4]].
fn msm_solve(c: ShadowCoord, at: LayerRef) -> MsmSolve {
    let b = mix(filtered_moments(c), vec4<f32>(0.5), at.layer.moment_bias);
    let d = linear_depth(at.layer, c.depth);
    // Cholesky factor L of the Hankel matrix.
    let l22 = sqrt(max(b.y - b.x * b.x, 1e-12));
    let l32 = (b.z - b.x * b.y) / l22;
    let l33 = sqrt(max(b.w - b.y * b.y - l32 * l32, 1e-12));
    // Solve L y = (1, d, d²), then L^T q = y: q are the quadratic's coefficients.
    let y2 = (d - b.x) / l22;
    let y3 = (d * d - b.y - l32 * y2) / l33;
    let q2 = y3 / l33;
    let q1 = (y2 - l32 * q2) / l22;
    let q0 = 1.0 - b.x * q1 - b.y * q2;
    // The roots of q2 z² + q1 z + q0.
    let root = sqrt(max(q1 * q1 - 4.0 * q2 * q0, 0.0));
    let r = vec2<f32>(-q1 - root, -q1 + root) / (2.0 * q2);
    return MsmSolve(b, d, min(r.x, r.y), max(r.x, r.y));
}

// The weight of Hamburger's three points in front of d.
fn hamburger_shadow(s: MsmSolve) -> f32 {
    let b = s.b;
    if (s.d <= s.z2) {
        return 0.0;
    }
    if (s.d <= s.z3) {
        return (s.d * s.z3 - b.x * (s.d + s.z3) + b.y) / ((s.z3 - s.z2) * (s.d - s.z2));
    }
    return 1.0 - (s.z2 * s.z3 - b.x * (s.z2 + s.z3) + b.y) / ((s.d - s.z2) * (s.d - s.z3));
}

// The Hausdorff bound where Hamburger's points leave 0..1: four points at 0, d, a free one f
// and 1. The moments of x^k (1 - x), k = 1..3, vanish at 0 and 1, so they weigh d and f alone;
// the three of them give f, then each point's weight, and the shadow is the weight at 0 with
// f's where f lies in front of d.
fn hausdorff_shadow(s: MsmSolve) -> f32 {
    let b = s.b;
    let d = s.d;
    let e = vec3<f32>(b.x - b.y, b.y - b.z, b.z - b.w);
    let f = (e.z - d * e.y) / (e.y - d * e.x);
    // u = w (x (1 - x)) at f and at d.
    let u_f = (e.y - d * e.x) / (f - d);
    let w_f = u_f / (f * (1.0 - f));
    let w_d = (e.x - u_f) / (d * (1.0 - d));
    let w_1 = b.x - w_d * d - w_f * f;
    let w_0 = 1.0 - w_d - w_f - w_1;
    return w_0 + select(0.0, w_f, f < d);
}

// Light through a reconstruction's `shadow`, with the light-bleeding reduction. Rounding can
// leave a degenerate solve: read as lit rather than as a black speck.
fn msm_lit(shadow: f32, at: LayerRef) -> f32 {
    let lit = 1.0 - clamp(shadow, 0.0, 1.0);
    return reduce_bleeding(select(1.0, lit, lit == lit), at.layer.bleed);
}

// The Hamburger reconstruction: depths may lie anywhere.
fn shadow_msm(c: ShadowCoord, at: LayerRef) -> f32 {
    return msm_lit(hamburger_shadow(msm_solve(c, at)), at);
}

// The Hausdorff reconstruction: depths lie in 0..1, so a bound with points outside that range
// is replaced by the four-point one inside it.
fn shadow_msm_hausdorff(c: ShadowCoord, at: LayerRef) -> f32 {
    let s = msm_solve(c, at);
    if (s.z2 >= 0.0 && s.z3 <= 1.0) {
        return msm_lit(hamburger_shadow(s), at);
    }
    return msm_lit(hausdorff_shadow(s), at);
}

// Depth kept in a colour target (seeds 001 and 004): the values of the 2x2 texels around the
// point, each compared by hand with the receiver's `value` (lit where it is no farther) and
// weighted bilinearly, as the hardware's comparison filter weighs a depth map's texels.
fn compare_stored(c: ShadowCoord, value: f32) -> f32 {
    let size = vec2<i32>(map_size(c));
    // The tile's first texel on the page; its texels are kept inside it (the seams' guard).
    let origin = vec2<i32>(round(c.tile.xy * vec2<f32>(textureDimensions(moment_maps))));
    let at = c.uv * vec2<f32>(size) - 0.5;
    let base = floor(at);
    let f = at - base;
    var lit = vec4<f32>(0.0);
    // Without the guard only the page's edge holds the texels in.
    let low = select(-origin, vec2<i32>(0), c.guard);
    let high = select(vec2<i32>(textureDimensions(moment_maps)) - 1 - origin, size - 1, c.guard);
    for (var k = 0; k < 4; k += 1) {
        let texel = origin + clamp(vec2<i32>(base) + vec2<i32>(k % 2, k / 2), low, high);
        lit[k] = select(0.0, 1.0, value <= textureLoad(moment_maps, texel, c.layer, 0).r);
    }
    return mix(mix(lit.x, lit.y, f.x), mix(lit.z, lit.w, f.x), f.y);
}

// Linear depth in an R32Float target, as seed 001 kept it (with its multiplicative offset, a
// light's bias_scale, applied to the receiver's depth before the lookup).
fn shadow_r32f(c: ShadowCoord, at: LayerRef) -> f32 {
    return compare_stored(c, linear_depth(at.layer, c.depth));
}

// The distance from the light in an R16Float target, as seed 004 kept it.
fn shadow_r16f_radial(c: ShadowCoord) -> f32 {
    return compare_stored(c, c.distance);
}

fn method_used(method: u32) -> bool {
    return (SHADOW_METHODS & (1u << method)) != 0u;
}

// True for methods that compare away from the lookup's own point (SPREADING_METHODS, a bit each,
// from `ShadowMethod::spreads`).
fn method_spreads(method: u32) -> bool {
    return (SPREADING_METHODS & (1u << method)) != 0u;
}

// The lookup of `method` (a METHOD_* constant) in layer `at`.
fn sample_shadow(method: u32, c: ShadowCoord, at: LayerRef) -> f32 {
    let only = countOneBits(SHADOW_METHODS) == 1u;
    if (method_used(METHOD_NEAREST) && (only || method == METHOD_NEAREST)) {
        return shadow_nearest(c);
    }
    if (method_used(METHOD_BILINEAR) && (only || method == METHOD_BILINEAR)) {
        return shadow_bilinear(c);
    }
    if (method_used(METHOD_PCF3) && (only || method == METHOD_PCF3)) {
        return shadow_pcf(c, 1);
    }
    if (method_used(METHOD_PCF5) && (only || method == METHOD_PCF5)) {
        return shadow_pcf(c, 2);
    }
    if (method_used(METHOD_GAUSS5) && (only || method == METHOD_GAUSS5)) {
        return shadow_gauss5(c);
    }
    if (method_used(METHOD_POISSON16) && (only || method == METHOD_POISSON16)) {
        return shadow_poisson16(c, POISSON16_RADIUS);
    }
    if (method_used(METHOD_POISSON32) && (only || method == METHOD_POISSON32)) {
        return shadow_poisson32(c, POISSON32_RADIUS);
    }
    if (method_used(METHOD_PCSS) && (only || method == METHOD_PCSS)) {
        return shadow_pcss(c, at);
    }
    if (method_used(METHOD_VSM) && (only || method == METHOD_VSM)) {
        return shadow_vsm(c, at);
    }
    if (method_used(METHOD_EVSM) && (only || method == METHOD_EVSM)) {
        return shadow_evsm(c, at);
    }
    if (method_used(METHOD_EVSM2) && (only || method == METHOD_EVSM2)) {
        return shadow_evsm2(c, at);
    }
    if (method_used(METHOD_MSM) && (only || method == METHOD_MSM)) {
        return shadow_msm(c, at);
    }
    if (method_used(METHOD_MSM_HAUSDORFF) && (only || method == METHOD_MSM_HAUSDORFF)) {
        return shadow_msm_hausdorff(c, at);
    }
    if (method_used(METHOD_R32F) && (only || method == METHOD_R32F)) {
        return shadow_r32f(c, at);
    }
    if (method_used(METHOD_R16F_RADIAL) && (only || method == METHOD_R16F_RADIAL)) {
        return shadow_r16f_radial(c);
    }
    return 1.0;
}

// World point `p` (unit normal `n`, unit direction `l` towards the light) pushed along the
// normal and towards the light by amounts measured in texels of world size `texel`, the slope
// term growing with tan(angle) as the depth error across a texel does on a tilted surface; and
// `bias.metres` further towards the light.
fn biased_point(p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, texel: f32, bias: Bias) -> vec3<f32> {
    let n_dot_l = clamp(dot(n, l), 0.0, 1.0);
    let sin_t = sqrt(1.0 - n_dot_l * n_dot_l);
    let tan_t = min(sin_t / max(n_dot_l, 1e-3), 10.0);
    return p + n * (bias.normal * texel) + l * ((bias.constant + bias.slope * tan_t) * texel + bias.metres);
}

// How ndc = clip.xyz / clip.w of a layer changes when the world point moves by `dp`.
fn ndc_change(clip_from_world: mat4x4<f32>, clip: vec4<f32>, dp: vec3<f32>) -> vec3<f32> {
    let d = clip_from_world * vec4<f32>(dp, 0.0);
    return (d.xyz * clip.w - clip.xyz * d.w) / (clip.w * clip.w);
}

// Steepest receiver plane used, as the tangent of the surface's angle to the map (84°): beyond
// it derivatives say more about the pixel grid than about the surface.
const MAX_PLANE_SLOPE: f32 = 10.0;

// Receiver-plane depth bias (Isidoro 2006, "Shadow mapping: GPU-based tips and techniques"):
// from how the map position (u, v) and the depth z change per pixel right (x) and down (y),
// solve for how z changes per unit of u and of v across the map, so a filter compares each tap
// with the depth of the receiver's plane there. The surface moves `toward` (world units towards
// the light) by `depth_per_metre` of depth a metre and spans `texel` metres a texel.
//
// Safe where derivatives are not: a surface seen edge-on in the map (the two pixel steps land
// on one line of it) or not finite gives no plane (the centre depth for every tap), and a plane
// steeper than MAX_PLANE_SLOPE is laid down to it.
fn receiver_plane(dx: vec3<f32>, dy: vec3<f32>, depth_per_metre: f32, texel: f32, size: f32) -> vec2<f32> {
    let du = vec2<f32>(dx.x, dy.x) * 0.5;
    let dv = vec2<f32>(dx.y, dy.y) * -0.5;
    let det = du.x * dv.y - du.y * dv.x;
    let scale = length(vec2<f32>(dx.x, dx.y)) * length(vec2<f32>(dy.x, dy.y)) * 0.25;
    if (!(abs(det) > 1e-4 * scale) || !(scale > 0.0)) {
        return vec2<f32>(0.0);
    }
    let plane = vec2<f32>(dx.z * dv.y - dy.z * dv.x, dy.z * du.x - dx.z * du.y) / det;
    let steepest = MAX_PLANE_SLOPE * abs(depth_per_metre) * texel * size;
    let len = length(plane);
    if (!(len <= 3.0e38)) {
        return vec2<f32>(0.0);
    }
    return plane * min(1.0, steepest / max(len, 1e-30));
}

// The multiplicative depth offset of the source articles (seed 001 compares the stored depth
// with the receiver's times 0.95): map depth `z` of a point whose distance from the light, along
// the layer's axis, is `1 - scale` of the receiver's (layer_view_distance turned round); in a
// cascade, whose depth is linear and whose sun has no position, distance from the near plane.
// The bias grows with distance, as the rounding of a depth format does.
fn scaled_depth(layer: GpuLayer, z: f32, scale: f32) -> f32 {
    if (scale <= 0.0) {
        return z;
    }
    if (layer.perspective == 0u) {
        return z * (1.0 - scale);
    }
    let d = layer_view_distance(layer, z) * (1.0 - scale);
    let t = layer.depth_terms;
    return t.y / max(d, 1e-6) - t.x;
}

// Where the (already biased) world point `biased` falls in layer `at`, if it falls in it at all
// (behind the map, off its sides or past its far plane it does not). With `plane_on`, a
// spreading filter compares with the receiver's plane; `l` is the unit direction towards the
// light and `texel` the texel's world size at the point.
struct CoordIn {
    inside: bool,
    c: ShadowCoord,
};

fn shadow_coord(at: LayerRef, biased: vec3<f32>, method: u32, f: Footprint, plane_on: bool, l: vec3<f32>, texel: f32) -> CoordIn {
    let clip_from_world = at.layer.clip_from_world;
    let clip = clip_from_world * vec4<f32>(biased, 1.0);
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    let depth = scaled_depth(at.layer, ndc.z, at.bias_scale);
    let distance = light_distance(at.layer, depth, biased, at.bias_scale);
    var c = ShadowCoord(uv, at.layer.page, at.layer.tile, at.guard, depth, vec2<f32>(0.0), f.pixel, distance);
    let inside = clip.w > 0.0 && all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0)) && ndc.z <= 1.0;
    if (inside && plane_on && method_spreads(method)) {
        let dx = ndc_change(clip_from_world, clip, f.dp_dx);
        let dy = ndc_change(clip_from_world, clip, f.dp_dy);
        c.plane = receiver_plane(dx, dy, ndc_change(clip_from_world, clip, l).z, texel, at.layer.tile.w);
    }
    return CoordIn(inside, c);
}

// Visibility of the (already biased) world point `biased` in layer `at` (see shadow_coord): 1
// lit, 0 shadowed. Points outside the map are lit.
fn shadow_lookup(at: LayerRef, biased: vec3<f32>, method: u32, f: Footprint, plane_on: bool, l: vec3<f32>, texel: f32) -> f32 {
    let found = shadow_coord(at, biased, method, f, plane_on, l, texel);
    if (!found.inside) {
        return 1.0;
    }
    return sample_shadow(method, found.c, at);
}
