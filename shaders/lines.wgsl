// Lines in the world drawn over the picture (the light volumes): no depth test, so a volume
// half under the ground still shows whole.

struct LineCamera {
    clip_from_world: mat4x4<f32>,
};

@group(0) @binding(0) var<uniform> camera: LineCamera;

struct LineIn {
    @location(0) position: vec3<f32>,
    @location(1) color: vec4<f32>,
};

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_line(v: LineIn) -> LineOut {
    return LineOut(camera.clip_from_world * vec4<f32>(v.position, 1.0), v.color);
}

@fragment
fn fs_line(in: LineOut) -> @location(0) vec4<f32> {
    return in.color;
}
