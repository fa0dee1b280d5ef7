// Per-object data shared by the shadow pass and the main pass (bind group 1, dynamic offset).
struct Object {
    model: mat4x4<f32>,
    // Inverse-transpose of the model matrix, for normals under non-uniform scale.
    normal_matrix: mat4x4<f32>,
    // rgb: linear albedo; w: 1 if the surface receives shadows.
    color: vec4<f32>,
    // x: specular strength, y: Phong exponent.
    phong: vec4<f32>,
    // x: first matrix of this object's joints in the palette (skinned objects only).
    skin: vec4<u32>,
};

@group(1) @binding(0) var<uniform> object: Object;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
};
