// Per-object data shared by the shadow pass and the main pass (bind group 1, dynamic offset).
struct Object {
    world_from_local: mat4x4<f32>,
    // Inverse-transpose of world_from_local, for normals under non-uniform scale.
    normal_from_local: mat4x4<f32>,
    // Linear RGBA base colour factor.
    base_color: vec4<f32>,
    // Strength of the specular highlight.
    specular: f32,
    // Phong exponent.
    shininess: f32,
    // Alpha below which a masked surface is cut away (blended ones too, in shadow maps and the
    // measuring view).
    alpha_cutoff: f32,
    // 1 if the surface takes shadows.
    receives_shadows: u32,
    // First matrix of this object's joints in the palette (skinned objects only).
    first_joint: u32,
    // 1 on the ground when lights that keep their maps draw planar shadows onto it instead
    // (settings' planar_ground): those lights' maps are not looked up here.
    planar_receiver: u32,
    // 1 on the ground when it shows its checker (settings' ground_grid): a faint 1 m checker
    // that makes stair-steps, acne and shimmer easy to see. Colour only: the measuring view
    // never reads it.
    ground_grid: u32,
    _pad2: u32,
};

@group(1) @binding(0) var<uniform> object: Object;

// The base-colour texture of the object's material, white when it has none (bind group 2).
@group(2) @binding(0) var base_color_texture: texture_2d<f32>;
@group(2) @binding(1) var base_color_sampler: sampler;

// What this pipeline does, fixed when it is built: sample the base-colour texture (objects
// without one skip the lookup), cut away fragments below the object's alpha cutoff, blend.
override TEXTURED: bool = true;
override ALPHA_MASK: bool = false;
override ALPHA_BLEND: bool = false;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(4) uv: vec2<f32>,
    @location(5) color: vec4<f32>,
};

// The surface's colour and alpha: base colour factor x texture x vertex colour (fragment
// stages only: the texture is sampled with derivatives).
fn surface_color(uv: vec2<f32>, vertex_color: vec4<f32>) -> vec4<f32> {
    var color = object.base_color * vertex_color;
    if (TEXTURED) {
        color *= textureSample(base_color_texture, base_color_sampler, uv);
    }
    return color;
}
