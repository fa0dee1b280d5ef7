// Main pass: Phong lighting per light, each light's contribution scaled by its shadow visibility.

const MAX_SPOTS: u32 = 8u;

struct Sun {
    // xyz: direction the light travels.
    direction: vec4<f32>,
    // rgb: colour times intensity.
    color: vec4<f32>,
    view_proj: mat4x4<f32>,
    // x: layer (negative: no shadow), y/z: texel size = y + z * distance.
    shadow: vec4<f32>,
};

struct Spot {
    // xyz: position, w: range.
    position: vec4<f32>,
    // xyz: unit direction, w: cos(outer angle).
    direction: vec4<f32>,
    // rgb: colour times intensity, w: cos(inner angle).
    color: vec4<f32>,
    view_proj: mat4x4<f32>,
    shadow: vec4<f32>,
};

struct Frame {
    view_proj: mat4x4<f32>,
    camera_position: vec4<f32>,
    sun: Sun,
    spots: array<Spot, MAX_SPOTS>,
    // x: suns (0 or 1), y: spots.
    counts: vec4<u32>,
    // x: shadow strength, y: constant bias, z: slope bias, w: normal bias.
    shadow: vec4<f32>,
    // x: ambient, y: 1 when shadows are on.
    misc: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let world = object.model * vec4<f32>(v.position, 1.0);
    var out: VertexOut;
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.normal = (object.normal_matrix * vec4<f32>(v.normal, 0.0)).xyz;
    return out;
}

// Visibility of a light with shadow parameters `s`, or 1 where there is no shadow to look up.
fn visibility(view_proj: mat4x4<f32>, s: vec4<f32>, distance: f32, p: vec3<f32>, n: vec3<f32>, l: vec3<f32>) -> f32 {
    if (s.x < 0.0 || frame.misc.y < 0.5 || object.color.w < 0.5) {
        return 1.0;
    }
    let bias = Bias(frame.shadow.y, frame.shadow.z, frame.shadow.w);
    let vis = shadow_visibility(view_proj, i32(s.x), s.y + s.z * distance, p, n, l, bias);
    return 1.0 - frame.shadow.x * (1.0 - vis);
}

// Diffuse plus specular Phong terms for unit vectors normal, to-light and to-eye.
fn phong(n: vec3<f32>, l: vec3<f32>, v: vec3<f32>, albedo: vec3<f32>) -> vec3<f32> {
    let n_dot_l = max(dot(n, l), 0.0);
    let r = reflect(-l, n);
    let spec = object.phong.x * pow(max(dot(r, v), 0.0), object.phong.y);
    return albedo * n_dot_l + vec3<f32>(spec) * step(0.0, dot(n, l));
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let p = in.world;
    let v = normalize(frame.camera_position.xyz - p);
    let albedo = object.color.rgb;
    var color = albedo * frame.misc.x;

    if (frame.counts.x > 0u) {
        let l = -normalize(frame.sun.direction.xyz);
        if (dot(n, l) > 0.0) {
            let vis = visibility(frame.sun.view_proj, frame.sun.shadow, 0.0, p, n, l);
            color += frame.sun.color.rgb * phong(n, l, v, albedo) * vis;
        }
    }

    for (var i = 0u; i < min(frame.counts.y, MAX_SPOTS); i += 1u) {
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
        if (cone * attenuation > 0.0 && dot(n, l) > 0.0) {
            let vis = visibility(spot.view_proj, spot.shadow, d, p, n, l);
            color += spot.color.rgb * phong(n, l, v, albedo) * (cone * attenuation * vis);
        }
    }
    return vec4<f32>(color, 1.0);
}
