// Shadow pass: depth only. No fragment stage: the rasterizer writes depth by itself.

struct Layer {
    view_proj: mat4x4<f32>,
};

@group(0) @binding(0) var<uniform> layer: Layer;

@vertex
fn vs_shadow(v: VertexIn) -> @builtin(position) vec4<f32> {
    return layer.view_proj * object.model * vec4<f32>(v.position, 1.0);
}

// The same for a skinned mesh: the shadow follows the pose.
@vertex
fn vs_shadow_skinned(v: VertexIn, s: SkinIn) -> @builtin(position) vec4<f32> {
    return layer.view_proj * object.model * skin_matrix(s) * vec4<f32>(v.position, 1.0);
}
