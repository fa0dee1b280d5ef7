// Virtual (paged) shadow maps: which layer a lookup of a paged light reads. A sun's clipmap is a
// stack of levels round the camera, each a window of PAGE_GRID² pages; a spot's levels, and a
// point light's cube faces side by side, each cover the whole map from one window at the origin.
// A point's level-0 page units are its page_from_world (its cube face's) over w, and a texel of
// level 0 there is 2^page_finest_log2 · w (w is 1 for a sun, the distance along a spot's or a
// face's axis). Its page table (src/render/page_table.rs) gives each level's window (its origin,
// the pages across and down it holds, where its entries start) and, for each page a level can
// hold, the layer its resident page is in. The math mirrors
// src/shadow/pages.rs, src/shadow/page_space.rs and src/shadow/cube_pages.rs.

// The face of `light` that holds `p`: a point light's cube face (as cube_face picks it), 0 for
// a map with one.
fn page_face(light: GpuLight, p: vec3<f32>) -> u32 {
    return select(0u, cube_face(p - light.position), light.page_faces == 6u);
}

// `light`'s world to level-0 page units on face `face`: its own, or a cube face's from its page
// table (after the levels' headers, 16 words a face, column by column).
fn page_matrix(light: GpuLight, face: u32) -> mat4x4<f32> {
    if (light.page_faces != 6u) {
        return light.page_from_world;
    }
    let at = light.page_word + light.page_levels * PAGE_LEVEL_WORDS + 16u * face;
    var columns: array<vec4<f32>, 4>;
    for (var c = 0u; c < 4u; c += 1u) {
        let w = at + 4u * c;
        columns[c] = bitcast<vec4<f32>>(vec4<u32>(table_word(w), table_word(w + 1u), table_word(w + 2u), table_word(w + 3u)));
    }
    return mat4x4<f32>(columns[0], columns[1], columns[2], columns[3]);
}

// `p`'s level-0 page units of `light` (xy) and its w (z); w <= 0 behind the light. A cube's
// units are held on their face's square.
fn page_units(light: GpuLight, p: vec3<f32>) -> vec3<f32> {
    let face = page_face(light, p);
    let u = page_matrix(light, face) * vec4<f32>(p, 1.0);
    var units = u.xy / u.w;
    if (light.page_faces == 6u) {
        let side = f32(CUBE_FACE_PAGES);
        let origin = vec2<f32>(f32(face % CUBE_ACROSS), f32(face / CUBE_ACROSS)) * side;
        units = clamp(units, origin, origin + vec2<f32>(side - 1e-3));
    }
    return vec3<f32>(units, u.w);
}

// Word `i` of the page tables.
fn table_word(i: u32) -> u32 {
    return textureLoad(page_tables, vec2<u32>(i % LIST_WIDTH, i / LIST_WIDTH), 0).r;
}

// The texel size (metres) a pixel wants: one whose square, laid along the light onto the surface,
// covers as much of it as the pixel does; the pixel spans `pixel_angle` radians `distance` metres
// from the eye (`wanted_texel` in src/shadow/pages.rs).
fn wanted_texel(distance: f32, pixel_angle: f32, n_dot_v: f32, n_dot_l: f32) -> f32 {
    let size = max(distance * pixel_angle, 0.0);
    return size * sqrt(clamp(abs(n_dot_l), MIN_GRAZE, 1.0) / clamp(abs(n_dot_v), MIN_GRAZE, 1.0));
}

// The level of `light` a pixel at `p` wants (`l` towards the light): the surface it shows faces
// the way its footprint `f` does (the triangle's face, as the marking pass sees it in the depth
// buffer; `n` where the footprint has no size, as a probe's). The marking pass
// (page_marks.wgsl) finds the same level for the same surface.
fn page_level(light: GpuLight, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>, f: Footprint) -> i32 {
    let c = cross(f.dp_dx, f.dp_dy);
    let area = length(c);
    let facing = select(n, c / area, area > 0.0);
    let to_eye = frame.camera_position - p;
    let distance = length(to_eye);
    let wanted = wanted_texel(distance, frame.pixel_angle, dot(facing, to_eye / max(distance, 1e-6)), dot(facing, l));
    let w = page_units(light, p).z;
    let octaves = log2(wanted) - light.page_finest_log2 - log2(max(w, 1e-6)) + light.page_bias;
    // No footprint (log2 of 0 is minus infinity): the finest.
    return i32(clamp(round(octaves), 0.0, f32(light.page_levels - 1u)));
}

// One level's window as its page table holds it.
struct PageWindow {
    // Its first page's column and row.
    origin: vec2<i32>,
    // The pages across and down it holds.
    size: vec2<i32>,
    // Its first entry's word in the page tables.
    entries: u32,
}

// Level `level`'s window of `light` (its header: PAGE_LEVEL_WORDS words).
fn page_window(light: GpuLight, level: u32) -> PageWindow {
    let at = light.page_word + PAGE_LEVEL_WORDS * level;
    let size = table_word(at + 2u);
    return PageWindow(
        vec2<i32>(bitcast<i32>(table_word(at)), bitcast<i32>(table_word(at + 1u))),
        vec2<i32>(i32(size & 0xffffu), i32(size >> 16u)),
        light.page_word + table_word(at + 3u)
    );
}

// What page_layer gives where no page is resident and the fallback is off.
const NO_PAGE: u32 = 0xffffffffu;

// The layer `light`'s lookup at `p` reads: the page holding `p` of the finest level resident
// from `level` on, or the coarse map (its layer, or the cube face holding `p`) where none is.
// Without the fallback (frame.page_fallback 0) only level `level` is read, and NO_PAGE where its
// page is missing.
fn page_layer(light: GpuLight, p: vec3<f32>, level: i32) -> u32 {
    let at_p = page_units(light, p);
    let units = at_p.xy;
    // Behind the light nothing is paged: the coarse map.
    let behind = !(at_p.z > 0.0);
    let first = u32(max(level, 0));
    let last = select(first + 1u, light.page_levels, frame.page_fallback == 1u);
    for (var l = first; l < select(min(last, light.page_levels), 0u, behind); l += 1u) {
        let window = page_window(light, l);
        let at = vec2<i32>(floor(units / exp2(f32(l)))) - window.origin;
        if (all(at >= vec2<i32>(0)) && all(at < window.size)) {
            let entry = table_word(window.entries + u32(at.y * window.size.x + at.x));
            if (entry > 0u) {
                return entry - 1u;
            }
        }
    }
    // The coarse map: its one layer, or the cube face that holds `p`.
    return select(NO_PAGE, light.first_layer + page_face(light, p), frame.page_fallback == 1u);
}
