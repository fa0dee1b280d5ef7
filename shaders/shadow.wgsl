// Shadow pass: depth, and for a light that uses a moment map, the moments of that depth. In a
// depth-only layer opaque casters have no fragment stage (the rasterizer writes depth by
// itself); cut-out casters (masked, or blended ones taken as masked) discard where the surface
// is not there, so they cast cut-out shadows.

@group(0) @binding(0) var<uniform> layer: GpuLayer;

struct ShadowOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) color: vec4<f32>,
    // Where the surface is (R16F radial measures its distance from the light).
    @location(2) world: vec3<f32>,
};

fn shadow_out(world: vec4<f32>, v: VertexIn) -> ShadowOut {
    return ShadowOut(layer.clip_from_world * world, v.uv, v.color, world.xyz);
}

@vertex
fn vs_shadow(v: VertexIn) -> ShadowOut {
    return shadow_out(object.world_from_local * vec4<f32>(v.position, 1.0), v);
}

// The same for a rigid mesh drawn as one of many instances: the instance is the number of its
// object, and an instanced draw, being rigid, has every object's world_from_local bound where a
// skinned draw has its joints (render/instances.rs).
struct Instance {
    @location(6) object: u32,
};

@vertex
fn vs_shadow_instanced(v: VertexIn, i: Instance) -> ShadowOut {
    return shadow_out(joints[i.object] * vec4<f32>(v.position, 1.0), v);
}

// The same for a skinned mesh: the shadow follows the pose.
@vertex
fn vs_shadow_skinned(v: VertexIn, s: SkinIn) -> ShadowOut {
    return shadow_out(object.world_from_local * skin_matrix(s) * vec4<f32>(v.position, 1.0), v);
}

fn cut_out(in: ShadowOut) {
    if (surface_color(in.uv, in.color).a < object.alpha_cutoff) {
        discard;
    }
}

@fragment
fn fs_shadow(in: ShadowOut) {
    cut_out(in);
}

// A layer with a colour map (moments, or depth in colour): the depth test keeps the nearest
// fragment, and so what it stores is the last written.
@fragment
fn fs_moments(in: ShadowOut) -> @location(0) vec4<f32> {
    cut_out(in);
    return encode_moments(layer, in.clip.z, in.world);
}
