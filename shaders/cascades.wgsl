// The sun's cascades: which one a point reads, the blend into the next, the fade at the shadow
// distance, and the debug tint that shows where each one is used.

// The cascade for view depth `depth` (the cascade count when beyond them all) and how far the
// point is into the band where that cascade blends into the next (0: not at all, 1: fully).
struct CascadePick {
    index: u32,
    next_weight: f32,
};

fn pick_cascade(depth: f32) -> CascadePick {
    let count = u32(frame.sun.shadow.y);
    var pick = CascadePick(count, 0.0);
    for (var i = 0u; i < count; i += 1u) {
        if (depth < frame.sun.far[i]) {
            pick.index = i;
            let band = frame.sun.blend[i];
            if (band > 0.0 && i + 1u < count) {
                pick.next_weight = clamp((depth - (frame.sun.far[i] - band)) / band, 0.0, 1.0);
            }
            break;
        }
    }
    return pick;
}

// Visibility of the sun through cascade `c`.
fn cascade_visibility(c: u32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>) -> f32 {
    let bias = Bias(frame.sun.bias.x, frame.sun.bias.y, frame.sun.bias.z);
    let layer = i32(frame.sun.shadow.x) + i32(c);
    return shadow_visibility(frame.sun.view_proj[c], layer, frame.sun.texel[c], p, n, l, bias);
}

// Visibility of the sun at `p` (view depth `depth`): 1 lit, 0 shadowed. Past the last cascade
// everything is lit, and the shadow fades out before it rather than ending in a hard edge.
fn sun_visibility(p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, depth: f32) -> f32 {
    let pick = pick_cascade(depth);
    if (frame.sun.shadow.x < 0.0 || pick.index >= u32(frame.sun.shadow.y)) {
        return 1.0;
    }
    var vis = cascade_visibility(pick.index, p, n, l);
    if (pick.next_weight > 0.0) {
        vis = mix(vis, cascade_visibility(pick.index + 1u, p, n, l), pick.next_weight);
    }
    let fade = smoothstep(frame.shadow.y, frame.camera_forward.w, depth);
    return mix(vis, 1.0, fade);
}

// The debug colour of the cascade used at view depth `depth` (white beyond them all).
fn cascade_tint(depth: f32) -> vec3<f32> {
    var tints = array<vec3<f32>, 4>(
        vec3<f32>(1.0, 0.3, 0.3),
        vec3<f32>(0.3, 1.0, 0.3),
        vec3<f32>(0.35, 0.45, 1.0),
        vec3<f32>(1.0, 0.9, 0.25),
    );
    let pick = pick_cascade(depth);
    if (frame.sun.shadow.x < 0.0 || pick.index >= u32(frame.sun.shadow.y)) {
        return vec3<f32>(1.0);
    }
    return mix(tints[pick.index], tints[min(pick.index + 1u, 3u)], pick.next_weight);
}
