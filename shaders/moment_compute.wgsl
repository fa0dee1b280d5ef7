// Moments made from a layer's depth map in one compute dispatch: each workgroup resolves the
// moments of a block of its tile and of the blur's reach around it into shared memory (every
// moment texel once, each the mean of the depth texels it covers: `resolved` in blur.wgsl), blurs
// them along rows and then along columns there, and stores the block. The full-screen passes of
// blur.wgsl do the same in three passes through the moment atlas (resolve, rows into a scratch
// page, columns back); here the atlas is written once. The separable shared-memory blur is the
// classic one of GPU post-processing; the moments-from-depth resolve follows MJP's "Shadows"
// sample (a compute conversion of a depth-only map, blurred on the way).
//
// The storage texture the blocks are stored into (`moments_out`, group 1 binding 4) is
// declared by the renderer after this file, in the moment maps' format, with `resolved_here`:
// `resolved` from the depth atlas, or `resolved_samples` from one layer's multisampled depth.

// Texels of the moment map a workgroup stores along a side (its invocations are one per texel).
const BLOCK: i32 = i32(RESOLVE_BLOCK);
// The block and the widest blur's reach each side: the shared memory's side.
const SPAN: i32 = i32(RESOLVE_BLOCK + 2u * RESOLVE_MAX_RADIUS);
const INVOCATIONS: i32 = BLOCK * BLOCK;

// The moments of the block's span, resolved; then, row by row, the rows' blur of its block's
// columns (a `side` x BLOCK array in the same memory).
var<workgroup> span: array<vec4<f32>, SPAN * SPAN>;

// The rows' blur of texel `x` (counted from the span's first column, which is `r` left of the
// block's) of span row `y`: a weighted mean of the 2r + 1 resolved moments centred on it.
fn blur_row(y: i32, x: i32, side: i32, r: i32) -> vec4<f32> {
    var sum = vec4<f32>(0.0);
    var total = 0.0;
    for (var i = -r; i <= r; i += 1) {
        sum += weight(i) * span[y * side + x + i];
        total += weight(i);
    }
    return sum / total;
}

@compute @workgroup_size(RESOLVE_BLOCK, RESOLVE_BLOCK)
fn cs_resolve(@builtin(local_invocation_id) local: vec3<u32>, @builtin(workgroup_id) group: vec3<u32>) {
    // Radii above RESOLVE_MAX_RADIUS take the full-screen passes (checked on the CPU).
    let r = min(blur.radius, i32(RESOLVE_MAX_RADIUS));
    let side = BLOCK + 2 * r;
    let me = i32(local.y) * BLOCK + i32(local.x);
    // The span's first texel on the page; texels past the tile's edge take its edge texel's moments.
    let corner = tile_first() + vec2<i32>(group.xy) * BLOCK - r;
    for (var k = me; k < side * side; k += INVOCATIONS) {
        let q = clamp(corner + vec2<i32>(k % side, k / side), tile_first(), tile_last());
        span[k] = resolved_here(q);
    }
    workgroupBarrier();
    // Along rows: every row of the span, the block's columns only. At most two texels an
    // invocation (SPAN * BLOCK <= 2 * INVOCATIONS), kept until every row has been read.
    var rows: array<vec4<f32>, 2>;
    for (var n = 0; n < 2; n += 1) {
        let k = me + n * INVOCATIONS;
        if (k < side * BLOCK) {
            rows[n] = blur_row(k / BLOCK, k % BLOCK + r, side, r);
        }
    }
    workgroupBarrier();
    for (var n = 0; n < 2; n += 1) {
        let k = me + n * INVOCATIONS;
        if (k < side * BLOCK) {
            span[k] = rows[n];
        }
    }
    workgroupBarrier();
    // Along columns, one texel an invocation, stored where it lies inside the tile.
    var sum = vec4<f32>(0.0);
    var total = 0.0;
    for (var i = -r; i <= r; i += 1) {
        sum += weight(i) * span[(i32(local.y) + r + i) * BLOCK + i32(local.x)];
        total += weight(i);
    }
    let p = corner + r + vec2<i32>(local.xy);
    if (all(p <= tile_last())) {
        textureStore(moments_out, p, blur.layer, sum / total);
    }
}
