// Planar projected shadows (Blinn 1988, "Me and my (fake) shadow"; drawn with the stencil buffer
// as seed 004 draws them): a caster flattened onto the ground along the rays from one light, and
// drawn over the ground after the scene, taking away what that light gave it there. The stencil
// test (render/planar.rs) lets each pixel lose a light once however many casters overlap it.

// One light's planar shadow, bound by dynamic offset. Checked against the Rust struct of the
// same name (src/render/gpu_types.rs) by a test.
struct GpuPlanar {
    // World to the flattened point, homogeneous (shadow::flat_from_world).
    flat_from_world: mat4x4<f32>,
    // The plane: unit normal and offset (normal . p + d = 0).
    plane: vec4<f32>,
    // The ground's albedo (rgb) and highlight strength (a).
    ground: vec4<f32>,
    // Which light (index into lights).
    light: u32,
    shininess: f32,
    // How far above the plane flattened casters are drawn.
    lift: f32,
    _pad0: u32,
};

@group(0) @binding(8) var<uniform> planar: GpuPlanar;

// The flattened point stays homogeneous all the way to the rasterizer, which clips it as it
// clips any point: a caster that reaches above a lamp has a shadow that runs to the horizon, and
// dividing by w in the vertex stage would fold it back across the ground. Its w is positive
// where the caster's point lies below the lamp; the rest (a point above it casts nothing down)
// is discarded per fragment, where the interpolated homogeneous point is still exact.
struct PlanarOut {
    @builtin(position) clip: vec4<f32>,
    // The flattened point, on (just above) the plane, homogeneous.
    @location(0) flat: vec4<f32>,
    // How high the caster's point is above the plane.
    @location(1) height: f32,
};

fn flatten(world: vec4<f32>) -> PlanarOut {
    var flat = planar.flat_from_world * world;
    flat = vec4<f32>(flat.xyz + planar.plane.xyz * (planar.lift * flat.w), flat.w);
    return PlanarOut(frame.clip_from_world * flat, flat, dot(planar.plane, world));
}

@vertex
fn vs_planar(v: VertexIn) -> PlanarOut {
    return flatten(object.world_from_local * vec4<f32>(v.position, 1.0));
}

// A skinned caster flattens in its pose.
@vertex
fn vs_planar_skinned(v: VertexIn, s: SkinIn) -> PlanarOut {
    return flatten(object.world_from_local * skin_matrix(s) * vec4<f32>(v.position, 1.0));
}

// What the light gives the ground at the flattened point (Phong with the ground's response,
// scaled by the shadow strength): the share the shadow takes away. Nothing where the caster's
// point lies below the plane or above a lamp, or where the light does not reach the ground
// (outside a spot's cone, which also leaves out casters behind the spot).
fn planar_share(in: PlanarOut) -> vec3<f32> {
    if (in.height < 0.0 || in.flat.w <= 0.0) {
        discard;
    }
    // The ground's own point, below the lifted one: lit as the main pass lit it.
    let n = planar.plane.xyz;
    let world = in.flat.xyz / in.flat.w - n * planar.lift;
    let f = Footprint(vec3<f32>(0.0), vec3<f32>(0.0), in.clip.xy);
    let depth = dot(world - frame.camera_position, frame.camera_forward);
    let s = light_sample(planar.light, world, n, f, depth, false);
    if (s.reach <= 0.0) {
        discard;
    }
    let v = normalize(frame.camera_position - world);
    let ground = Response(planar.ground.rgb, planar.ground.a, planar.shininess);
    return lights[planar.light].color * phong(n, s.l, v, ground) * (s.reach * s.cookie * frame.shadow_strength);
}

// Over the picture: subtracted from what is drawn (the blend is destination minus source).
@fragment
fn fs_planar(in: PlanarOut) -> @location(0) vec4<f32> {
    return vec4<f32>(planar_share(in), 0.0);
}

// In the measuring view: visibility 0, written only into the light's channel of the third
// target (the pipeline's write masks keep the rest).
@fragment
fn fs_planar_measure(in: PlanarOut) -> DebugOut {
    _ = planar_share(in);
    return DebugOut(vec4<u32>(0u), vec4<u32>(0u), vec4<u32>(0u));
}
