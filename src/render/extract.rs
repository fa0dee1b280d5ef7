//! Extraction: the world's components turned into the structs the shaders read.
//!
//! Pure CPU code, so what the GPU is told can be tested without a GPU.

use crate::components::*;
use crate::settings::Settings;
use bevy_ecs::prelude::*;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};

/// Most spot lights the main pass lights with (more are ignored).
pub const MAX_SPOTS: usize = 8;

/// Per-object uniform (matches `Object` in common.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ObjectUniform {
    model: Mat4,
    normal_matrix: Mat4,
    color: Vec4,
    phong: Vec4,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
struct SunUniform {
    direction: Vec4,
    color: Vec4,
    view_proj: Mat4,
    shadow: Vec4,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
struct SpotUniform {
    position: Vec4,
    direction: Vec4,
    color: Vec4,
    view_proj: Mat4,
    shadow: Vec4,
}

/// Per-frame uniform (matches `Frame` in main.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct FrameUniform {
    view_proj: Mat4,
    camera_position: Vec4,
    sun: SunUniform,
    spots: [SpotUniform; MAX_SPOTS],
    counts: [u32; 4],
    shadow: Vec4,
    misc: Vec4,
}

/// One mesh entity to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawItem {
    /// Which mesh of the library.
    pub mesh: Mesh,
    /// Its uniform data.
    pub object: ObjectUniform,
    /// Drawn into shadow maps.
    pub caster: bool,
}

/// Everything one frame needs from the world.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameData {
    /// The main pass's uniform.
    pub frame: FrameUniform,
    /// Objects in draw order.
    pub items: Vec<DrawItem>,
    /// View-projection of each shadow-map layer, by layer index.
    pub layers: Vec<Mat4>,
    /// The camera's view-projection.
    pub camera_view_proj: Mat4,
}

/// Shadow parameters for the shader: layer (or -1 without a map) and texel size terms.
fn shadow_params(map: Option<&ShadowMap>) -> Vec4 {
    map.map_or(Vec4::new(-1.0, 0.0, 0.0, 0.0), |m| Vec4::new(m.layer as f32, m.texel.x, m.texel.y, 0.0))
}

/// Reads the world into the data one frame needs. Without a camera nothing is drawn.
pub fn extract(world: &mut World) -> FrameData {
    let settings = world.resource::<Settings>().clone();
    let aspect = world.resource::<Viewport>().aspect();
    let (camera_view_proj, eye) = world
        .query::<(&Camera, &Transform)>()
        .iter(world)
        .next()
        .map_or((Mat4::ZERO, Vec3::ZERO), |(c, t)| (c.view_proj(t, aspect), t.translation));

    let mut layers = Vec::new();
    let mut put_layer = |m: Option<&ShadowMap>| {
        if let Some(m) = m {
            let i = m.layer as usize;
            if layers.len() <= i {
                layers.resize(i + 1, Mat4::IDENTITY);
            }
            layers[i] = m.view_proj;
        }
    };

    let mut sun = SunUniform::zeroed();
    let mut suns = 0;
    if let Some((light, map)) = world.query::<(&DirectionalLight, Option<&ShadowMap>)>().iter(world).next() {
        put_layer(map);
        sun = SunUniform {
            direction: light.direction.normalize_or(Vec3::NEG_Y).extend(0.0),
            color: (light.color * light.intensity).extend(0.0),
            view_proj: map.map_or(Mat4::IDENTITY, |m| m.view_proj),
            shadow: shadow_params(map),
        };
        suns = 1;
    }

    let mut spots = [SpotUniform::zeroed(); MAX_SPOTS];
    let mut spot_count = 0;
    for (light, t, map) in world.query::<(&SpotLight, &Transform, Option<&ShadowMap>)>().iter(world).take(MAX_SPOTS) {
        put_layer(map);
        let outer = light.outer_angle.clamp(0.0, 1.55);
        let inner = light.inner_angle.clamp(0.0, outer);
        spots[spot_count] = SpotUniform {
            position: t.translation.extend(light.range.max(1e-3)),
            direction: t.forward().extend(outer.cos()),
            color: (light.color * light.intensity).extend(inner.cos().max(outer.cos() + 1e-4)),
            view_proj: map.map_or(Mat4::IDENTITY, |m| m.view_proj),
            shadow: shadow_params(map),
        };
        spot_count += 1;
    }

    let items = world
        .query::<(&Mesh, &Transform, Option<&Material>, Has<ShadowCaster>, Has<ShadowReceiver>)>()
        .iter(world)
        .map(|(mesh, t, material, caster, receiver)| {
            let m = material.copied().unwrap_or(Material::color(0.8, 0.8, 0.8));
            let model = t.matrix();
            let object = ObjectUniform {
                model,
                normal_matrix: model.inverse().transpose(),
                color: m.base_color.extend(receiver as u32 as f32),
                phong: Vec4::new(m.specular, m.shininess.max(1.0), 0.0, 0.0),
            };
            DrawItem { mesh: *mesh, object, caster }
        })
        .collect();

    let frame = FrameUniform {
        view_proj: camera_view_proj,
        camera_position: eye.extend(1.0),
        sun,
        spots,
        counts: [suns, spot_count as u32, 0, 0],
        shadow: Vec4::new(settings.shadow_strength, settings.depth_bias, settings.slope_bias, settings.normal_bias),
        misc: Vec4::new(settings.ambient, settings.shadows as u32 as f32, 0.0, 0.0),
    };
    FrameData { frame, items, layers, camera_view_proj }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_sizes_match_the_wgsl_layout() {
        // WGSL: Object = 2 mat4 + 2 vec4; Frame = mat4 + vec4 + Sun(2 vec4 + mat4 + vec4)
        // + 8 Spot(3 vec4 + mat4 + vec4) + 3 vec4.
        assert_eq!(std::mem::size_of::<ObjectUniform>(), 160);
        assert_eq!(std::mem::size_of::<SunUniform>(), 112);
        assert_eq!(std::mem::size_of::<SpotUniform>(), 128);
        assert_eq!(std::mem::size_of::<FrameUniform>(), 64 + 16 + 112 + 8 * 128 + 48);
    }

    #[test]
    fn receivers_casters_and_layers_are_carried_over() {
        let mut app = crate::App::new(Settings::default()).unwrap();
        app.set_time(0.0);
        let data = extract(&mut app.world);
        let ground = data.items.iter().filter(|i| !i.caster).count();
        assert_eq!(ground, 1, "only the ground is not a caster");
        assert!(data.items.iter().all(|i| i.object.color.w == 1.0), "all sample surfaces receive");
        assert_eq!(data.layers.len(), 2, "one layer for the sun, one for the spot");
        assert_eq!(data.frame.counts[..2], [1, 1]);
        assert_ne!(data.camera_view_proj, Mat4::ZERO);
    }
}
