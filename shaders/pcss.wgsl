// Percentage-closer soft shadows: the blocker searches and the filter they size, on a map of a
// light's own (shadow_pcss) and on pages (penumbra_bound, read by coarse_penumbra in
// lights.wgsl). The lookup's coordinates and LayerRef are shadow_sampling.wgsl's.

// Widest penumbra PCSS draws (and so the widest it searches for blockers), in texels, on a map
// of its own, and the depth levels its blocker search compares with.
const PCSS_MAX_PENUMBRA: f32 = 24.0;
const PCSS_LEVELS: i32 = 6;

// How far, in texels at the receiver `receiver` metres from the light, a blocker `blocker`
// metres from it shifts its shadow for each side of the light: for a sun, (receiver - blocker)
// times tan of its angular radius; for a light of radius R, R (receiver - blocker) / blocker
// at the receiver (similar triangles); over the texel's size there.
fn penumbra_texels(at: LayerRef, receiver: f32, blocker: f32) -> f32 {
    let gap = max(receiver - blocker, 0.0);
    let texel = at.layer.texel_base + at.layer.texel_per_metre * receiver;
    if (at.layer.perspective == 1u) {
        return at.light_size * gap / max(blocker, 1e-4) / max(texel, 1e-9);
    }
    return at.light_size * gap / max(texel, 1e-9);
}

// The depth of a blocker whose penumbra at the receiver is `w` texels wide: penumbra_texels
// turned round, then view_distance turned round.
fn depth_for_penumbra(at: LayerRef, receiver: f32, w: f32) -> f32 {
    let texel = at.layer.texel_base + at.layer.texel_per_metre * receiver;
    let shift = w * texel / max(at.light_size, 1e-9);
    let t = at.layer.depth_terms;
    if (at.layer.perspective == 1u) {
        return t.y * (1.0 + shift) / receiver - t.x;
    }
    return t.y - t.x * (receiver - shift);
}

// Percentage-closer soft shadows (Fernando 2005, "Percentage-closer soft shadows"): search the
// part of the map through which the light's disc sees the receiver for blockers, estimate how
// wide a penumbra they throw, and filter with a Poisson disc that wide. No blocker: lit.
//
// The search reads the maps only through comparisons (GL cannot read a depth map's raw values),
// so it finds the blockers' mean penumbra, not their mean depth: for each tap it compares with
// the depths whose blockers would throw penumbrae of w_1 < w_2 < ... texels. The share of
// blockers throwing more than w is the share of taps nearer than that depth over the share
// nearer than the receiver, and the mean penumbra is the integral of that share over w.
fn shadow_pcss(c: ShadowCoord, at: LayerRef) -> f32 {
    if (!at.pcss_search) {
        return shadow_poisson32(c, POISSON32_RADIUS);
    }
    let search = pcss_search(c, at);
    if (!search.found) {
        return 1.0;
    }
    return shadow_poisson32(c, clamp(search.mean, 0.5, at.widest));
}

// What PCSS's blocker search finds: whether any blocker is nearer than the receiver, and the
// mean penumbra of those it finds, in texels at the receiver, to within `step` (the widths it
// compares with are `step` apart).
struct BlockerSearch {
    found: bool,
    mean: f32,
    step: f32,
};

// PCSS's blocker search round `c`, at most `at.widest` texels wide.
fn pcss_search(c: ShadowCoord, at: LayerRef) -> BlockerSearch {
    let widest = search_radius(c, at);
    let step = widest / f32(PCSS_LEVELS);
    var widths: array<f32, PCSS_LEVELS>;
    for (var k = 0; k < PCSS_LEVELS; k += 1) {
        widths[k] = (f32(k) + 0.5) * step;
    }
    let b = find_blockers(c, at, widest, widths);
    var mean = 0.0;
    for (var k = 0; k < PCSS_LEVELS; k += 1) {
        mean += step * b.beyond[k];
    }
    return BlockerSearch(b.found, mean, step);
}

// How far round `c` PCSS searches, in texels: as far as the nearest blocker there may be (at the
// map's near plane, or the nearest caster where that is known) throws its penumbra, at most
// `at.widest`.
fn search_radius(c: ShadowCoord, at: LayerRef) -> f32 {
    let receiver = view_distance(at, c.depth);
    let nearest = max(max(view_distance(at, 0.0), at.nearest), 1e-3);
    return clamp(penumbra_texels(at, receiver, nearest), 0.5, at.widest);
}

// The blockers round `c`, searched within `radius` texels: whether any is nearer than the
// receiver, and the share of those whose penumbrae at the receiver are wider than each of
// `widths` (texels).
struct Blockers {
    found: bool,
    beyond: array<f32, PCSS_LEVELS>,
};

fn find_blockers(c: ShadowCoord, at: LayerRef, radius: f32, widths: array<f32, PCSS_LEVELS>) -> Blockers {
    let receiver = view_distance(at, c.depth);
    var levels: array<f32, PCSS_LEVELS>;
    for (var k = 0; k < PCSS_LEVELS; k += 1) {
        levels[k] = depth_for_penumbra(at, receiver, widths[k]);
    }
    let turn = disc_turn(c.pixel);
    var blocked = 0.0;
    var beyond: array<f32, PCSS_LEVELS>;
    for (var i = 0; i < 16; i += 1) {
        let tap = c.uv + disc_offset(c, POISSON_16[i], turn, radius);
        let along = dot(c.plane, tap - c.uv);
        let at = atlas_uv(c, tap);
        blocked += 1.0 - textureSampleCompareLevel(shadow_maps, shadow_sampler, at, c.layer, c.depth + along);
        for (var k = 0; k < PCSS_LEVELS; k += 1) {
            beyond[k] += 1.0 - textureSampleCompareLevel(shadow_maps, shadow_sampler, at, c.layer, levels[k] + along);
        }
    }
    let found = blocked >= 1e-3;
    for (var k = 0; k < PCSS_LEVELS; k += 1) {
        beyond[k] = select(0.0, beyond[k] / blocked, found);
    }
    return Blockers(found, beyond);
}

// An upper bound on the mean penumbra (texels at the receiver) of the blockers round `c`, -1
// where there is none: a search as PCSS's, but comparing with widths an octave apart (the widest
// over 32 up to the widest), so it is as close at a narrow penumbra as at a wide one. A blocker
// counted between two widths is taken at the wider; one past the widest at twice it.
fn penumbra_bound(c: ShadowCoord, at: LayerRef) -> f32 {
    let widest = search_radius(c, at);
    var widths: array<f32, PCSS_LEVELS>;
    for (var k = 0; k < PCSS_LEVELS; k += 1) {
        widths[k] = widest * exp2(f32(k + 1 - PCSS_LEVELS));
    }
    let b = find_blockers(c, at, widest, widths);
    // Every blocker's penumbra is at most the first width, plus, for the share past each width,
    // the step to the next.
    var bound = widths[0];
    for (var k = 0; k + 1 < PCSS_LEVELS; k += 1) {
        bound += b.beyond[k] * (widths[k + 1] - widths[k]);
    }
    bound += b.beyond[PCSS_LEVELS - 1] * widest;
    return select(-1.0, bound, b.found);
}

// The world size of a texel of `at` at the receiver of `c`.
fn receiver_texel(at: LayerRef, c: ShadowCoord) -> f32 {
    return at.layer.texel_base + at.layer.texel_per_metre * view_distance(at, c.depth);
}
