// GPU skinning, shared by the shadow pass and the main pass: each vertex is moved by the
// weighted sum of up to four joint matrices (the same sums as `assets::skin` on the CPU).

struct SkinIn {
    @location(2) joints: vec4<u32>,
    @location(3) weights: vec4<f32>,
};

// Every skinned object's joint matrices (model space), one after another (bind group 3).
@group(3) @binding(0) var<storage, read> joints: array<mat4x4<f32>>;

// The blend of joint matrices that moves this vertex.
fn skin_matrix(s: SkinIn) -> mat4x4<f32> {
    let base = object.first_joint;
    return joints[base + s.joints.x] * s.weights.x
        + joints[base + s.joints.y] * s.weights.y
        + joints[base + s.joints.z] * s.weights.z
        + joints[base + s.joints.w] * s.weights.w;
}

// A normal carried through `m`: the cofactor matrix is the inverse transpose times the
// determinant, so with the determinant's sign it needs no inverse. A joint scaled to nothing
// (a common way to hide a part) gives no normal rather than a NaN, as on the CPU.
fn skin_normal(m: mat4x4<f32>, n: vec3<f32>) -> vec3<f32> {
    let a = m[0].xyz;
    let b = m[1].xyz;
    let c = m[2].xyz;
    let cofactor = mat3x3<f32>(cross(b, c), cross(c, a), cross(a, b));
    let turned = cofactor * n * select(1.0, -1.0, dot(a, cross(b, c)) < 0.0);
    let len = length(turned);
    return select(vec3<f32>(0.0), turned / len, len > 1e-20);
}
