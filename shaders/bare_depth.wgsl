// The bare depth pass: a rigid caster drawn at its placement into one layer, depth only, with
// nothing else (no skinning, no cut-outs, no colour). It measures what drawing the shadow
// casters costs at the least, for `umbra bench --shadow-pass`.

@group(0) @binding(0) var<uniform> clip_from_world: mat4x4<f32>;

@vertex
fn vs_bare(
    @location(0) position: vec3<f32>,
    @location(6) x: vec4<f32>,
    @location(7) y: vec4<f32>,
    @location(8) z: vec4<f32>,
    @location(9) w: vec4<f32>,
) -> @builtin(position) vec4<f32> {
    return clip_from_world * (mat4x4<f32>(x, y, z, w) * vec4<f32>(position, 1.0));
}
