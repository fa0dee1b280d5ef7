// Screen-space contact shadows (as Bevy, Filament, Unreal and Godot ship them; the march of
// Sousa, Kasyan and Schulz, "Secrets of CryENGINE 3 graphics technology", 2011): from a surface
// point, step a short way towards the light through the camera's depth, drawn before the main
// pass (src/render/camera_depth.rs). A step that lands behind what the camera sees there, by no
// more than the thickness surfaces are taken to have, is blocked. It finds what a shadow map is
// too coarse for (thin casters, the gap a bias opens at contact), and it cannot know what the
// camera does not see: what is off screen, or hidden behind something nearer.

@group(0) @binding(10) var camera_depth: texture_2d<f32>;

// View depth (along the camera's forward axis) of camera depth `z`: the camera's perspective
// projection takes view depth d to z = f (d - n) / (d (f - n)), 0 at its near plane, 1 at its far.
fn view_depth_of(z: f32) -> f32 {
    let n = frame.camera_near;
    let f = frame.camera_far;
    return n * f / max(f - z * (f - n), 1e-6);
}

// A number in 0..1 that changes from pixel to pixel without a pattern the eye picks up
// (interleaved gradient noise, Jimenez 2014): where the march starts, so its steps band as noise.
fn pixel_noise(pixel: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(floor(pixel), vec2<f32>(0.06711056, 0.00583715))));
}

// Visibility of the light along unit direction `l` from world point `p` (footprint `f`), `reach`
// metres from the light (a sun's is unbounded): 0 where a step of the march is hidden, 1 where
// none is or the march leaves the screen first. A step counts as hidden only when it lies behind
// the camera's surface by more than the depth the receiver itself spans across a pixel (which
// the depth buffer cannot resolve: a flat receiver seen at a grazing angle would shadow itself)
// and less than the thickness.
fn contact_visibility(p: vec3<f32>, l: vec3<f32>, reach: f32, f: Footprint) -> f32 {
    let steps = frame.contact_steps;
    let size = vec2<f32>(textureDimensions(camera_depth));
    let step = min(frame.contact_length, reach) / f32(max(steps, 1u));
    let own = abs(dot(f.dp_dx, frame.camera_forward)) + abs(dot(f.dp_dy, frame.camera_forward));
    let start = pixel_noise(f.pixel);
    for (var i = 0u; i < steps; i += 1u) {
        let q = p + l * (step * (f32(i) + start));
        let clip = frame.clip_from_world * vec4<f32>(q, 1.0);
        if (clip.w <= 0.0) {
            break;
        }
        let ndc = clip.xy / clip.w;
        if (any(abs(ndc) >= vec2<f32>(1.0))) {
            break;
        }
        let texel = vec2<i32>(vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * size);
        let scene = view_depth_of(textureLoad(camera_depth, texel, 0).r);
        let behind = dot(q - frame.camera_position, frame.camera_forward) - scene;
        if (behind > own && behind < frame.contact_thickness) {
            return 0.0;
        }
    }
    return 1.0;
}
