// Shadow pass: depth only. Opaque casters have no fragment stage (the rasterizer writes depth
// by itself); cut-out casters (masked, or blended ones taken as masked) discard where the
// surface is not there, so they cast cut-out shadows.

struct Layer {
    clip_from_world: mat4x4<f32>,
};

@group(0) @binding(0) var<uniform> layer: Layer;

struct ShadowOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) color: vec4<f32>,
};

@vertex
fn vs_shadow(v: VertexIn) -> ShadowOut {
    return ShadowOut(layer.clip_from_world * object.world_from_local * vec4<f32>(v.position, 1.0), v.uv, v.color);
}

// The same for a skinned mesh: the shadow follows the pose.
@vertex
fn vs_shadow_skinned(v: VertexIn, s: SkinIn) -> ShadowOut {
    return ShadowOut(layer.clip_from_world * object.world_from_local * skin_matrix(s) * vec4<f32>(v.position, 1.0), v.uv, v.color);
}

@fragment
fn fs_shadow(in: ShadowOut) {
    if (surface_color(in.uv, in.color).a < object.alpha_cutoff) {
        discard;
    }
}
