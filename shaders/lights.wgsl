// Every light of any kind as seen from a surface point: its direction, how much of it reaches
// the point, its shadow test through the light's layers (a sun's cascades, a spot's one map, a
// cube's six faces) and its cookie.

// The lights a point looks at: its cluster's list (src/light/clusters.rs), or every light for a
// point outside the camera's view (a probe), which has no cluster.
struct LightList {
    first: u32,
    count: u32,
    clustered: bool,
};

// The lights that may reach world point `p` at view depth `depth`: its cluster is the screen tile
// its clip position falls in and the depth slice (spaced evenly in log depth) it lies in, as
// ClusterView::cluster_of finds it on the CPU. Past the last slice no light but a sun reaches, and
// the last slice lists every sun.
fn lights_at(p: vec3<f32>, depth: f32) -> LightList {
    let clip = frame.clip_from_world * vec4<f32>(p, 1.0);
    let ndc = clip.xy / clip.w;
    if (!(clip.w > 0.0) || any(abs(ndc) > vec2<f32>(1.0))) {
        return LightList(0u, frame.light_count, false);
    }
    let tiles = vec2<f32>(f32(CLUSTER_X), f32(CLUSTER_Y));
    let tile = min(vec2<u32>(max((ndc * 0.5 + 0.5) * tiles, vec2<f32>(0.0))), vec2<u32>(CLUSTER_X - 1u, CLUSTER_Y - 1u));
    let t = log(max(depth, frame.cluster_near) / frame.cluster_near) / log(frame.cluster_far / frame.cluster_near);
    let slice = min(u32(max(t * f32(CLUSTER_Z), 0.0)), CLUSTER_Z - 1u);
    let cluster = (slice * CLUSTER_Y + tile.y) * CLUSTER_X + tile.x;
    return LightList(list_word(2u * cluster), list_word(2u * cluster + 1u), true);
}

// Word `i` of the clustered light lists.
fn list_word(i: u32) -> u32 {
    return textureLoad(cluster_lists, vec2<u32>(i % LIST_WIDTH, i / LIST_WIDTH), 0).r;
}

// Entry `k` of `list`: a light's index in the light array.
fn list_light(list: LightList, k: u32) -> u32 {
    if (list.clustered) {
        return list_word(list.first + k);
    }
    return k;
}

// The cascade of light `light` for view depth `depth` (layer_count when beyond them all) and
// how far the point is into the band where that cascade blends into the next (0: not at all,
// 1: fully).
struct CascadePick {
    index: u32,
    next_weight: f32,
};

fn pick_cascade(light: GpuLight, depth: f32) -> CascadePick {
    let count = min(light.layer_count, MAX_CASCADES);
    var pick = CascadePick(count, 0.0);
    for (var i = 0u; i < count; i += 1u) {
        let layer = layers[light.first_layer + i];
        if (depth < layer.far) {
            pick.index = i;
            if (layer.blend > 0.0 && i + 1u < count) {
                pick.next_weight = clamp((depth - (layer.far - layer.blend)) / layer.blend, 0.0, 1.0);
            }
            break;
        }
    }
    return pick;
}

fn light_bias(light: GpuLight) -> Bias {
    return Bias(light.bias_constant, light.bias_slope, light.bias_normal, frame.depth_bias_metres);
}

// World size of a texel of layer `index`, `distance` metres from the light.
fn texel_size(index: u32, distance: f32) -> f32 {
    return layers[index].texel_base + layers[index].texel_per_metre * distance;
}

// The shadow test through layer `index` of the array, `distance` metres from the light.
fn layer_test(light: GpuLight, index: u32, distance: f32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, f: Footprint) -> f32 {
    return ref_test(light, layer_ref(light, index), distance, p, n, l, f);
}

// The shadow test through layer `at` of `light`, `distance` metres from the light.
fn ref_test(light: GpuLight, at: LayerRef, distance: f32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, f: Footprint) -> f32 {
    let texel = at.layer.texel_base + at.layer.texel_per_metre * distance;
    let biased = biased_point(p, n, l, texel, light_bias(light));
    return shadow_lookup(at, biased, light.method, f, light.receiver_plane == 1u, l, texel);
}

// Layer `index` of `light` as a lookup sees it.
fn layer_ref(light: GpuLight, index: u32) -> LayerRef {
    return LayerRef(layers[index], frame.atlas_guard == 1u, light.size, frame.pcss_search == 1u, light.bias_scale, PCSS_MAX_PENUMBRA, light.nearest_caster);
}

// The shadow test through a light's cube. With seams handled (frame.cube_seams), the face is
// picked for the biased point, so the lookup lands on the face it reads (and the faces reach a
// few texels past their edges for the filters); without, it is picked for the surface point and
// a biased point next to a seam can fall off its face, which reads as lit.
fn cube_test(light: GpuLight, distance: f32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, f: Footprint) -> f32 {
    // Every face has texels of the same size.
    let texel = texel_size(light.first_layer, distance);
    let biased = biased_point(p, n, l, texel, light_bias(light));
    let picked = select(p, biased, frame.cube_seams == 1u);
    let index = light.first_layer + cube_face(picked - light.position);
    return shadow_lookup(layer_ref(light, index), biased, light.method, f, light.receiver_plane == 1u, l, texel);
}

// World size of the shadow-map texel that light `light` looks up at `p` (view depth `depth`,
// unit normal `n`, footprint `f`): its cascade's for a sun, its page's for a paged light, its
// map's (or cube face's) at that distance for others; 0 where it has no map there.
fn texel_at(light: GpuLight, p: vec3<f32>, n: vec3<f32>, f: Footprint, depth: f32) -> f32 {
    if (light.layer_count == 0u) {
        return 0.0;
    }
    if (light.shape == SHAPE_PAGES) {
        if (light.page_fades == 1u && depth >= frame.shadow_distance) {
            return 0.0;
        }
        let to_light = light.position - p;
        let l = select(normalize(to_light), -light.direction, light.kind == LIGHT_SUN);
        let index = page_layer(light, p, page_level(light, p, n, l, f));
        if (index == NO_PAGE) {
            return 0.0;
        }
        return texel_size(index, length(to_light));
    }
    if (light.shape == SHAPE_CASCADES) {
        let pick = pick_cascade(light, depth);
        if (pick.index >= light.layer_count) {
            return 0.0;
        }
        return texel_size(light.first_layer + pick.index, 0.0);
    }
    return texel_size(light.first_layer, length(light.position - p));
}

// Visibility of a sun at `p` (view depth `depth`): past the last cascade everything is lit, and
// the shadow fades out before it rather than ending in a hard edge.
fn sun_visibility(light: GpuLight, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, f: Footprint, depth: f32) -> f32 {
    let pick = pick_cascade(light, depth);
    if (pick.index >= light.layer_count) {
        return 1.0;
    }
    var vis = layer_test(light, light.first_layer + pick.index, 0.0, p, n, l, f);
    if (pick.next_weight > 0.0) {
        vis = mix(vis, layer_test(light, light.first_layer + pick.index + 1u, 0.0, p, n, l, f), pick.next_weight);
    }
    let fade = smoothstep(frame.fade_start, frame.shadow_distance, depth);
    return mix(vis, 1.0, fade);
}

// Visibility of a paged light at `p`, `distance` metres from it: through the page its footprint
// wants (or a coarser one, or the coarse map while none is there). A sun's clipmap ends at the
// shadow distance: past it everything is lit, and the shadow fades out before it as the
// cascades' does.
fn paged_visibility(light: GpuLight, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, f: Footprint, depth: f32, distance: f32) -> f32 {
    let fades = light.page_fades == 1u;
    if (fades && depth >= frame.shadow_distance) {
        return 1.0;
    }
    let coarse = light.first_layer + page_face(light, p);
    let wanted = page_level(light, p, n, l, f);
    var index = page_layer(light, p, wanted);
    let pcss = light.method == METHOD_PCSS && frame.pcss_search == 1u;
    if (pcss) {
        let penumbra = coarse_penumbra(light, coarse, p, n, l, f, distance);
        if (penumbra < 0.0) {
            return 1.0;
        }
        let level = penumbra_level(light, p, coarse, distance, penumbra);
        index = select(coarse, page_layer(light, p, max(level, wanted)), level >= 0);
    }
    if (index == NO_PAGE) {
        return 1.0;
    }
    var at = layer_ref(light, index);
    if (pcss && index != coarse) {
        at.widest = f32(PAGE_BORDER);
    }
    let vis = ref_test(light, at, distance, p, n, l, f);
    return select(vis, mix(vis, 1.0, smoothstep(frame.fade_start, frame.shadow_distance, depth)), fades);
}

// PCSS on pages. A search as wide as a penumbra runs past a page's border, and one cut at
// PCSS_MAX_PENUMBRA texels of a fine page is narrower in the world than the penumbra. So the
// blockers are first searched for in the light's coarse map, which holds the whole light with
// no page edges; the lookup then searches again, at most PAGE_BORDER texels wide, and filters on
// the level where the penumbra found fits in that (see penumbra_level). A bound on the mean
// penumbra at `p` (metres; see penumbra_bound), -1 where the coarse search finds no blocker (the
// point is lit, as PCSS has it where its search finds none).
fn coarse_penumbra(light: GpuLight, coarse: u32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, f: Footprint, distance: f32) -> f32 {
    let at = layer_ref(light, coarse);
    let texel = texel_size(coarse, distance);
    let biased = biased_point(p, n, l, texel, light_bias(light));
    let found = shadow_coord(at, biased, METHOD_PCSS, f, light.receiver_plane == 1u, l, texel);
    if (!found.inside) {
        return -1.0;
    }
    return penumbra_bound(found.c, at) * receiver_texel(at, found.c);
}

// The finest level of `light` at `p` whose texels are wide enough that a penumbra `penumbra`
// metres wide spans at most PAGE_BORDER of them, so that PCSS reads no texel past its page's
// border; -1 where that level's texels are wider than the coarse map's (layer `coarse`, whose
// own search is PCSS_MAX_PENUMBRA wide): the coarse map is read. A level's texel is
// 2^(page_finest_log2 + level) · w (see pages.wgsl).
fn penumbra_level(light: GpuLight, p: vec3<f32>, coarse: u32, distance: f32, penumbra: f32) -> i32 {
    let w = log2(max(page_units(light, p).z, 1e-6));
    let level = ceil(log2(penumbra / f32(PAGE_BORDER)) - light.page_finest_log2 - w);
    let coarse_level = log2(texel_size(coarse, distance)) - light.page_finest_log2 - w;
    if (level > min(coarse_level, f32(light.page_levels - 1u))) {
        return -1;
    }
    // No penumbra (log2 of 0 is minus infinity): the finest.
    return i32(max(level, 0.0));
}

// Visibility of light `light` at `p`, `distance` metres from it (1 where it casts no shadow).
fn light_visibility(light: GpuLight, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, f: Footprint, depth: f32, distance: f32) -> f32 {
    if (light.layer_count == 0u) {
        return 1.0;
    }
    switch light.shape {
        case SHAPE_CASCADES: {
            return sun_visibility(light, p, n, l, f, depth);
        }
        case SHAPE_SINGLE: {
            return layer_test(light, light.first_layer, distance, p, n, l, f);
        }
        case SHAPE_PAGES: {
            return paged_visibility(light, p, n, l, f, depth, distance);
        }
        default: {
            return cube_test(light, distance, p, n, l, f);
        }
    }
}

// Texel (x, y) of cookie `layer`, 0..1.
fn cookie_texel(layer: u32, x: u32, y: u32) -> f32 {
    let i = (layer * COOKIE_SIZE + y) * COOKIE_SIZE + x;
    let word = cookies[i / 16u][(i / 4u) % 4u];
    return f32((word >> (8u * (i % 4u))) & 0xffu) / 255.0;
}

// Bilinear lookup in cookie `layer` at `uv`, clamped at the edges.
fn cookie_bilinear(uv: vec2<f32>, layer: u32) -> f32 {
    let at = uv * f32(COOKIE_SIZE) - 0.5;
    let base = floor(at);
    let f = at - base;
    let hi = i32(COOKIE_SIZE) - 1;
    let x0 = u32(clamp(i32(base.x), 0, hi));
    let y0 = u32(clamp(i32(base.y), 0, hi));
    let x1 = u32(clamp(i32(base.x) + 1, 0, hi));
    let y1 = u32(clamp(i32(base.y) + 1, 0, hi));
    let top = mix(cookie_texel(layer, x0, y0), cookie_texel(layer, x1, y0), f.x);
    let bottom = mix(cookie_texel(layer, x0, y1), cookie_texel(layer, x1, y1), f.x);
    return mix(top, bottom, f.y);
}

// The light's cookie at `p`: its image projected through the cone (1 without a cookie).
fn cookie(light: GpuLight, p: vec3<f32>) -> f32 {
    if (light.cookie < 0) {
        return 1.0;
    }
    let clip = light.cookie_from_world * vec4<f32>(p, 1.0);
    if (clip.w <= 0.0) {
        return 0.0;
    }
    let ndc = clip.xy / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0))) {
        return 0.0;
    }
    return cookie_bilinear(uv, u32(light.cookie));
}

// One light as seen from a surface point: the unit direction towards it, how much of it reaches
// (0 where it does not: facing away, outside the cone or range), its shadow test (1 where none
// is made) and its cookie.
struct LightSample {
    l: vec3<f32>,
    reach: f32,
    visibility: f32,
    cookie: f32,
};

// Light `i` at `p` (unit normal `n`, footprint `f`, view depth `depth`); `test` says whether to
// look up its shadow.
fn light_sample(i: u32, p: vec3<f32>, n: vec3<f32>, f: Footprint, depth: f32, test: bool) -> LightSample {
    let light = lights[i];
    var s = LightSample(-light.direction, 1.0, 1.0, 1.0);
    var distance = 0.0;
    if (light.kind != LIGHT_SUN) {
        let to_light = light.position - p;
        distance = length(to_light);
        s.l = to_light / max(distance, 1e-4);
        // Inverse-square-like falloff, windowed to reach exactly zero at the range.
        let x = distance / light.range;
        let window = clamp(1.0 - x * x * x * x, 0.0, 1.0);
        s.reach = window * window / (1.0 + LIGHT_FALLOFF * distance * distance);
        if (light.kind == LIGHT_SPOT) {
            // Full inside the inner angle, a smooth edge, nothing outside the outer angle; behind
            // the light the cosine is negative, so the back projection is cut here too.
            s.reach *= smoothstep(light.cos_outer, light.cos_inner, dot(-s.l, light.direction));
        }
    }
    if (dot(n, s.l) <= 0.0) {
        s.reach = 0.0;
    }
    if (s.reach > 0.0) {
        if (test) {
            s.visibility = light_visibility(light, p, n, s.l, f, depth, distance);
            if (light.contact == 1u && frame.contact_steps > 0u && s.visibility > 0.0) {
                let reach = select(distance, 1e30, light.kind == LIGHT_SUN);
                s.visibility = min(s.visibility, contact_visibility(p, s.l, reach, f));
            }
        }
        s.cookie = cookie(light, p);
    }
    return s;
}

// The debug colour of the first sun's cascade at view depth `depth` (white beyond them all, or
// without a sun); `list` holds every sun.
fn cascade_tint(depth: f32, list: LightList) -> vec3<f32> {
    var tints = array<vec3<f32>, 4>(
        vec3<f32>(1.0, 0.3, 0.3),
        vec3<f32>(0.3, 1.0, 0.3),
        vec3<f32>(0.35, 0.45, 1.0),
        vec3<f32>(1.0, 0.9, 0.25),
    );
    for (var k = 0u; k < list.count; k += 1u) {
        let light = lights[list_light(list, k)];
        if (light.kind == LIGHT_SUN && light.layer_count > 0u) {
            let pick = pick_cascade(light, depth);
            if (pick.index >= light.layer_count) {
                return vec3<f32>(1.0);
            }
            return mix(tints[pick.index], tints[min(pick.index + 1u, 3u)], pick.next_weight);
        }
    }
    return vec3<f32>(1.0);
}
