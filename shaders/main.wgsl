// Main pass: Phong lighting by every light, each light's share scaled by its shadow test; the
// measuring view of the same fragments; and probes, the same tests at given points.

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) color: vec4<f32>,
};

// Vertex `v` moved to model-space `position` and `normal`, placed by the object's matrix.
fn place(v: VertexIn, position: vec4<f32>, normal: vec3<f32>) -> VertexOut {
    let world = object.world_from_local * position;
    var out: VertexOut;
    out.clip = frame.clip_from_world * world;
    out.world = world.xyz;
    out.normal = (object.normal_from_local * vec4<f32>(normal, 0.0)).xyz;
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
    return 1.0 - frame.shadow_strength * (1.0 - vis);
}

// How a surface answers light: its albedo, and its highlight's strength and Phong exponent.
struct Response {
    albedo: vec3<f32>,
    specular: f32,
    shininess: f32,
};

// Diffuse plus specular Phong terms for unit vectors normal, to-light and to-eye.
fn phong(n: vec3<f32>, l: vec3<f32>, v: vec3<f32>, r: Response) -> vec3<f32> {
    let n_dot_l = max(dot(n, l), 0.0);
    let spec = r.specular * pow(max(dot(reflect(-l, n), v), 0.0), r.shininess);
    return r.albedo * n_dot_l + vec3<f32>(spec) * step(0.0, dot(n, l));
}

// Toon shading (cel shading, as in seed 003): the light's diffuse strength at the point (its
// angle, falloff and cookie together) falls into frame.toon_bands bands, a shadow takes the
// surface one band down, and the highlight is all or nothing. A shadow counts where its
// visibility is below one half, so filtered and soft edges are cut at one line as the bands are,
// and nothing between bands moves with the camera.
fn toon(n: vec3<f32>, l: vec3<f32>, v: vec3<f32>, r: Response, strength: f32, visibility: f32) -> vec3<f32> {
    let bands = f32(frame.toon_bands);
    let lit = step(0.5, visibility);
    let band = max(ceil(clamp(max(dot(n, l), 0.0) * strength, 0.0, 1.0) * bands) - frame.shadow_strength * (1.0 - lit), 0.0);
    let highlight = step(0.5, r.specular * pow(max(dot(reflect(-l, n), v), 0.0), r.shininess)) * lit;
    return r.albedo * (band / bands) + vec3<f32>(highlight);
}

// What lighting found at a fragment: its colour, and the shadow visibility (0 shadowed .. 1
// lit) the tests of the measured lights gave (frame.first_measured and the three after it); -1
// where a light does not reach the fragment (facing away, outside the cone or range) and no test
// was made.
struct Shaded {
    color: vec3<f32>,
    visibility: vec4<f32>,
};

fn shade(world: vec3<f32>, n: vec3<f32>, f: Footprint, r: Response, test: bool, ground: bool) -> Shaded {
    let v = normalize(frame.camera_position - world);
    let depth = dot(world - frame.camera_position, frame.camera_forward);
    var out = Shaded(r.albedo * frame.ambient, vec4<f32>(-1.0));
    // Only the lights of the point's cluster: its cost follows the lights that reach it.
    let list = lights_at(world, depth);
    for (var k = 0u; k < list.count; k += 1u) {
        let i = list_light(list, k);
        // A light that draws planar shadows onto the ground leaves its maps unread there.
        let planar = ground && lights[i].planar_ground == 1u;
        let s = light_sample(i, world, n, f, depth, test && !planar);
        if (s.reach > 0.0) {
            let m = i - frame.first_measured;
            if (i >= frame.first_measured && m < MEASURED_PER_PASS) {
                out.visibility[m] = s.visibility;
            }
            if (frame.toon_bands > 0u) {
                out.color += lights[i].color * toon(n, s.l, v, r, s.reach * s.cookie, s.visibility);
            } else {
                out.color += lights[i].color * phong(n, s.l, v, r) * (s.reach * strengthen(s.visibility) * s.cookie);
            }
        }
    }
    if (frame.cascade_debug == 1u) {
        out.color *= cascade_tint(depth, list);
    }
    return out;
}

// True where shadows are looked up at all: shadows on and the surface takes them.
fn receives_shadows() -> bool {
    return frame.shadows_on == 1u && object.receives_shadows == 1u;
}

// The object's response with the surface's albedo (on the ground, under its checker).
fn response(s: Surface, world: vec3<f32>, f: Footprint) -> Response {
    var albedo = s.albedo.rgb;
    if (object.ground_grid == 1u) {
        albedo *= 1.0 - GRID_CONTRAST * checker(world.xz, abs(f.dp_dx.xz) + abs(f.dp_dy.xz));
    }
    return Response(albedo, object.specular, object.shininess);
}

// How much darker the ground's dark squares are: enough to see a stair-step against, too
// little to hide a shadow.
const GRID_CONTRAST: f32 = 0.1;

// A 1 m checker at `p` (0 on light squares, 1 on dark ones), box-filtered over the pixel's
// footprint `w` so that it fades to its mean far away instead of aliasing itself (the analytic
// filter of a square wave: the integral of its steps over the footprint).
fn checker(p: vec2<f32>, w: vec2<f32>) -> f32 {
    let width = max(w, vec2<f32>(1e-4));
    let steps = 2.0 * (abs(fract((p - 0.5 * width) * 0.5) - 0.5) - abs(fract((p + 0.5 * width) * 0.5) - 0.5)) / width;
    return 0.5 - 0.5 * steps.x * steps.y;
}

// Texel density (Lloyd et al. 2006, the aliasing measure): shadow-map texels of light `i` per
// screen pixel along a side, where the surface at `world` (unit normal `n`, footprint `f`) sees
// it. Red: a texel covers several pixels (stair-steps); green: about one each; blue: many texels
// a pixel (resolution spent where it cannot be seen). Grey where the light has no map there.
fn texel_density(i: u32, world: vec3<f32>, n: vec3<f32>, f: Footprint, depth: f32) -> vec3<f32> {
    let light = lights[i];
    let texel = texel_at(light, world, n, f, depth);
    if (texel <= 0.0) {
        return vec3<f32>(0.35);
    }
    var l = -light.direction;
    if (light.kind != LIGHT_SUN) {
        l = normalize(light.position - world);
    }
    // A texel's square laid along the light onto the surface, against the pixel's footprint.
    let texel_area = texel * texel / max(abs(dot(n, l)), 0.05);
    let pixel_area = max(length(cross(f.dp_dx, f.dp_dy)), 1e-12);
    let t = clamp(log2(pixel_area / texel_area) * 0.5 / 3.0, -1.0, 1.0);
    let red = vec3<f32>(0.9, 0.15, 0.1);
    let green = vec3<f32>(0.2, 0.8, 0.2);
    let blue = vec3<f32>(0.15, 0.35, 0.95);
    return select(mix(green, blue, t), mix(green, red, -t), t < 0.0);
}

// The fragment's footprint; taken before anything can branch, as derivatives must be.
fn footprint(in: VertexOut) -> Footprint {
    return Footprint(dpdx(in.world), dpdy(in.world), in.clip.xy);
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let f = footprint(in);
    let s = surface(in, front);
    var color = shade(in.world, s.normal, f, response(s, in.world, f), receives_shadows(), object.planar_receiver == 1u).color;
    if (frame.texel_view > 0u) {
        let depth = dot(in.world - frame.camera_position, frame.camera_forward);
        color = texel_density(frame.texel_view - 1u, in.world, s.normal, f, depth) * (0.35 + 0.65 * max(dot(s.normal, normalize(frame.camera_position - in.world)), 0.0));
    }
    return vec4<f32>(color, select(1.0, s.albedo.a, ALPHA_BLEND));
}

// The measuring view of the same fragment (never used for play): where the visible surface is,
// which way it faces and what the measured lights' shadow tests gave. The floats travel as their
// bits in integer targets, which every backend can render to.
struct DebugOut {
    // xyz: world position, w: 1 (the sky stays 0).
    @location(0) position: vec4<u32>,
    // xyz: unit world normal, w: view depth.
    @location(1) normal: vec4<u32>,
    @location(2) visibility: vec4<u32>,
};

@fragment
fn fs_debug(in: VertexOut, @builtin(front_facing) front: bool) -> DebugOut {
    let f = footprint(in);
    let s = surface(in, front);
    let shaded = shade(in.world, s.normal, f, response(s, in.world, f), receives_shadows(), object.planar_receiver == 1u);
    let depth = dot(in.world - frame.camera_position, frame.camera_forward);
    return DebugOut(
        bitcast<vec4<u32>>(vec4<f32>(in.world, 1.0)),
        bitcast<vec4<u32>>(vec4<f32>(s.normal, depth)),
        bitcast<vec4<u32>>(shaded.visibility),
    );
}

// Probes: single points whose shadow tests are wanted (fixed world points, watched as the camera
// moves). Probe i is drawn as one point into pixel (i % width, i / width) of an integer target.
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
    let width = max(frame.probe_width, 1u);
    let height = max(frame.probe_height, 1u);
    let pixel = vec2<f32>(f32(i % width) + 0.5, f32(i / width) + 0.5);
    let size = vec2<f32>(f32(width), f32(height));
    let ndc = vec2<f32>(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0);
    return ProbeOut(vec4<f32>(ndc, 0.5, 1.0), v.position, v.normal);
}

@fragment
fn fs_probe(in: ProbeOut) -> @location(0) vec4<u32> {
    let white = Response(vec3<f32>(1.0), 0.0, 1.0);
    let f = Footprint(vec3<f32>(0.0), vec3<f32>(0.0), in.clip.xy);
    return bitcast<vec4<u32>>(shade(in.world, normalize(in.normal), f, white, true, false).visibility);
}
