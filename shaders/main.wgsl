// Main pass: Phong lighting per light, each light's contribution scaled by its shadow visibility.

const MAX_SPOTS: u32 = 8u;
const MAX_CASCADES: u32 = 4u;

struct Sun {
    // xyz: direction the light travels.
    direction: vec4<f32>,
    // rgb: colour times intensity.
    color: vec4<f32>,
    view_proj: array<mat4x4<f32>, MAX_CASCADES>,
    // View depth where each cascade ends.
    far: vec4<f32>,
    // Width of the band before `far` where each cascade blends into the next.
    blend: vec4<f32>,
    // World size of one texel of each cascade.
    texel: vec4<f32>,
    // x: layer of the first cascade (negative: no shadow), y: number of cascades.
    shadow: vec4<f32>,
    // x: constant, y: slope, z: normal bias, in texels.
    bias: vec4<f32>,
};

struct Spot {
    // xyz: position, w: range.
    position: vec4<f32>,
    // xyz: unit direction, w: cos(outer angle).
    direction: vec4<f32>,
    // rgb: colour times intensity, w: cos(inner angle).
    color: vec4<f32>,
    // The cone's projection: shadow map and cookie alike.
    view_proj: mat4x4<f32>,
    // x: layer (negative: no shadow), y: texel size per metre of distance, z: cookie layer
    // (negative: none).
    shadow: vec4<f32>,
    // x: constant, y: slope, z: normal bias, in texels.
    bias: vec4<f32>,
};

struct Frame {
    view_proj: mat4x4<f32>,
    camera_position: vec4<f32>,
    // xyz: the camera's forward axis, w: shadow distance.
    camera_forward: vec4<f32>,
    sun: Sun,
    spots: array<Spot, MAX_SPOTS>,
    // x: suns (0 or 1), y: spots, z and w: the probe grid's width and height.
    counts: vec4<u32>,
    // x: shadow strength, y: view depth where the sun's shadow starts to fade.
    shadow: vec4<f32>,
    // x: ambient, y: 1 when shadows are on, z: 1 to tint each cascade, w: the shadow filter.
    misc: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;
// Cookie images, COOKIE_SIZE² bytes each, four bytes to a word.
const COOKIE_SIZE: u32 = 64u;
@group(0) @binding(3) var<uniform> cookies: array<vec4<u32>, 512>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) color: vec4<f32>,
};

// Vertex `v` moved to model-space `position` and `normal`, placed by the object's model matrix.
fn place(v: VertexIn, position: vec4<f32>, normal: vec3<f32>) -> VertexOut {
    let world = object.model * position;
    var out: VertexOut;
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.normal = (object.normal_matrix * vec4<f32>(normal, 0.0)).xyz;
    out.uv = v.uv;
    out.color = v.color;
    return out;
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    return place(v, vec4<f32>(v.position, 1.0), v.normal);
}

@vertex
fn vs_main_skinned(v: VertexIn, s: SkinIn) -> VertexOut {
    let m = skin_matrix(s);
    return place(v, m * vec4<f32>(v.position, 1.0), skin_normal(m, v.normal));
}

// True where shadows are looked up at all: shadows on and the surface receives them.
fn receives_shadows() -> bool {
    return frame.misc.y > 0.5 && object.receives_shadows == 1u;
}

// The surface at a fragment, with fragments cut away where a masked pipeline's surface is not
// there. Its normal faces the viewer: a back face (only drawn for double-sided materials) has
// its normal flipped.
struct Surface {
    albedo: vec4<f32>,
    normal: vec3<f32>,
};

fn surface(in: VertexOut, front: bool) -> Surface {
    let albedo = surface_color(in.uv, in.color);
    if (ALPHA_MASK && albedo.a < object.alpha_cutoff) {
        discard;
    }
    return Surface(albedo, normalize(in.normal) * select(-1.0, 1.0, front));
}

// A visibility weakened by the shadow strength setting.
fn strengthen(vis: f32) -> f32 {
    return 1.0 - frame.shadow.x * (1.0 - vis);
}

// Visibility of spot light `s` at distance `distance` (1 where it casts no shadow).
fn spot_visibility(s: Spot, distance: f32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>) -> f32 {
    if (s.shadow.x < 0.0) {
        return 1.0;
    }
    let bias = Bias(s.bias.x, s.bias.y, s.bias.z);
    return shadow_visibility(s.view_proj, i32(s.shadow.x), s.shadow.y * distance, p, n, l, bias);
}

// One light as seen from a surface point: the unit direction towards it, how much of it reaches
// (0 where it does not: facing away, outside the cone or range), and its shadow test (1 where
// none is made).
struct LightSample {
    l: vec3<f32>,
    reach: f32,
    visibility: f32,
};

// The sun at `p` (unit normal `n`, view depth `depth`); `test` says whether to look up its shadow.
fn sun_sample(p: vec3<f32>, n: vec3<f32>, depth: f32, test: bool) -> LightSample {
    let l = -normalize(frame.sun.direction.xyz);
    var s = LightSample(l, 0.0, 1.0);
    if (frame.counts.x > 0u && dot(n, l) > 0.0) {
        s.reach = 1.0;
        if (test) {
            s.visibility = sun_visibility(p, n, l, depth);
        }
    }
    return s;
}

// Spot light `i` at `p` (unit normal `n`); `test` says whether to look up its shadow.
fn spot_sample(i: u32, p: vec3<f32>, n: vec3<f32>, test: bool) -> LightSample {
    let spot = frame.spots[i];
    let to_light = spot.position.xyz - p;
    let d = length(to_light);
    let l = to_light / max(d, 1e-4);
    // The cone: full inside the inner angle, a smooth edge, nothing outside the outer angle;
    // behind the light the cosine is negative, so the back projection is cut here too.
    let cone = smoothstep(spot.direction.w, spot.color.w, dot(-l, spot.direction.xyz));
    // Inverse-square-like falloff, windowed to reach exactly zero at the range.
    let x = d / spot.position.w;
    let window = clamp(1.0 - x * x * x * x, 0.0, 1.0);
    let attenuation = window * window / (1.0 + 0.05 * d * d);
    var s = LightSample(l, 0.0, 1.0);
    if (cone * attenuation > 0.0 && dot(n, l) > 0.0) {
        s.reach = cone * attenuation;
        if (test) {
            s.visibility = spot_visibility(spot, d, p, n, l);
        }
    }
    return s;
}

// The spot's cookie at `p`: the image projected through the cone (1 without a cookie).
fn cookie(s: Spot, p: vec3<f32>) -> f32 {
    if (s.shadow.z < 0.0) {
        return 1.0;
    }
    let clip = s.view_proj * vec4<f32>(p, 1.0);
    if (clip.w <= 0.0) {
        return 0.0;
    }
    let ndc = clip.xy / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0))) {
        return 0.0;
    }
    return cookie_bilinear(uv, u32(s.shadow.z));
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

// Diffuse plus specular Phong terms for unit vectors normal, to-light and to-eye.
fn phong(n: vec3<f32>, l: vec3<f32>, v: vec3<f32>, albedo: vec3<f32>) -> vec3<f32> {
    let n_dot_l = max(dot(n, l), 0.0);
    let r = reflect(-l, n);
    let spec = object.specular * pow(max(dot(r, v), 0.0), object.shininess);
    return albedo * n_dot_l + vec3<f32>(spec) * step(0.0, dot(n, l));
}

// What lighting found at a fragment: its colour, and the shadow visibility (0 shadowed .. 1
// lit) each light's test gave: x the sun, y z w the first three spots; -1 where a light does not
// reach the fragment (facing away, outside the cone or range) and no test was made.
struct Shaded {
    color: vec3<f32>,
    visibility: vec4<f32>,
};

fn shade(in: VertexOut, n: vec3<f32>, albedo: vec3<f32>) -> Shaded {
    let p = in.world;
    let v = normalize(frame.camera_position.xyz - p);
    let depth = dot(p - frame.camera_position.xyz, frame.camera_forward.xyz);
    var out = Shaded(albedo * frame.misc.x, vec4<f32>(-1.0));

    let sun = sun_sample(p, n, depth, receives_shadows());
    if (sun.reach > 0.0) {
        out.visibility.x = sun.visibility;
        out.color += frame.sun.color.rgb * phong(n, sun.l, v, albedo) * strengthen(sun.visibility);
    }
    for (var i = 0u; i < min(frame.counts.y, MAX_SPOTS); i += 1u) {
        let spot = spot_sample(i, p, n, receives_shadows());
        if (spot.reach > 0.0) {
            if (i < 3u) {
                out.visibility[i + 1u] = spot.visibility;
            }
            let light = frame.spots[i];
            out.color += light.color.rgb * phong(n, spot.l, v, albedo) * (spot.reach * strengthen(spot.visibility) * cookie(light, p));
        }
    }
    if (frame.misc.z > 0.5) {
        out.color *= cascade_tint(depth);
    }
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let s = surface(in, front);
    return vec4<f32>(shade(in, s.normal, s.albedo.rgb).color, select(1.0, s.albedo.a, ALPHA_BLEND));
}

// The measuring view of the same fragment (never used for play): where the visible surface is,
// which way it faces and what each light's shadow test gave. The floats travel as their bits in
// integer targets, which every backend can render to.
struct DebugOut {
    // xyz: world position, w: 1 (the sky stays 0).
    @location(0) position: vec4<u32>,
    // xyz: unit world normal, w: view depth.
    @location(1) normal: vec4<u32>,
    @location(2) visibility: vec4<u32>,
};

@fragment
fn fs_debug(in: VertexOut, @builtin(front_facing) front: bool) -> DebugOut {
    let s = surface(in, front);
    let shaded = shade(in, s.normal, s.albedo.rgb);
    let depth = dot(in.world - frame.camera_position.xyz, frame.camera_forward.xyz);
    return DebugOut(
        bitcast<vec4<u32>>(vec4<f32>(in.world, 1.0)),
        bitcast<vec4<u32>>(vec4<f32>(s.normal, depth)),
        bitcast<vec4<u32>>(shaded.visibility),
    );
}

// Probes: single points whose shadow tests are wanted (fixed world points, watched as the camera
// moves). Probe i is drawn as one point into pixel (i % width, i / width) of an integer target,
// width in frame.counts.z.
struct ProbeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) world: vec3<f32>,
    @location(1) @interpolate(flat) normal: vec3<f32>,
};

struct ProbeIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

@vertex
fn vs_probe(@builtin(vertex_index) i: u32, v: ProbeIn) -> ProbeOut {
    let width = max(frame.counts.z, 1u);
    let height = max(frame.counts.w, 1u);
    let pixel = vec2<f32>(f32(i % width) + 0.5, f32(i / width) + 0.5);
    let size = vec2<f32>(f32(width), f32(height));
    let ndc = vec2<f32>(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0);
    return ProbeOut(vec4<f32>(ndc, 0.5, 1.0), v.position, v.normal);
}

@fragment
fn fs_probe(in: ProbeOut) -> @location(0) vec4<u32> {
    let n = normalize(in.normal);
    let depth = dot(in.world - frame.camera_position.xyz, frame.camera_forward.xyz);
    var out = vec4<f32>(-1.0);
    let sun = sun_sample(in.world, n, depth, true);
    if (sun.reach > 0.0) {
        out.x = sun.visibility;
    }
    for (var i = 0u; i < min(frame.counts.y, 3u); i += 1u) {
        let spot = spot_sample(i, in.world, n, true);
        if (spot.reach > 0.0) {
            out[i + 1u] = spot.visibility;
        }
    }
    return bitcast<vec4<u32>>(out);
}
