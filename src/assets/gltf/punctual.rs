//! The lights (`KHR_lights_punctual`) and the first camera of the scene's nodes, checked.
//!
//! The gltf crate has already checked that every index is in range and every type is known; this
//! checks the numbers. A light whose colour or intensity is not a finite, non-negative number is
//! left out with a warning; a nonsense range or cone is mended with one.

use super::accessor::Data;
use crate::assets::model::{FileLightKind, ModelCamera, ModelLight};
use glam::Vec3;
use gltf::camera::Projection;
use gltf::khr_lights_punctual::Kind;

/// The lights of the nodes in `scene`, in node order.
pub(super) fn lights(
    nodes: &[gltf::Node<'_>],
    scene: &[usize],
    data: &Data<'_>,
    warnings: &mut Vec<String>,
) -> Result<Vec<ModelLight>, String> {
    let mut out = Vec::new();
    for node in scene.iter().map(|&n| &nodes[n]) {
        let Some(light) = node.light() else { continue };
        let at = format!("light {} (on node {})", light.index(), node.index());
        let color = Vec3::from(light.color());
        if !color.is_finite() || color.min_element() < 0.0 {
            warnings.push(format!("{at} has colour {color}, not finite and non-negative: left out"));
            continue;
        }
        let intensity = light.intensity();
        if !intensity.is_finite() || intensity < 0.0 {
            warnings.push(format!("{at} has intensity {intensity}, not finite and non-negative: left out"));
            continue;
        }
        let range = light.range().filter(|r| {
            let good = r.is_finite() && *r > 0.0;
            if !good {
                warnings.push(format!("{at} has range {r}, not a positive distance: taken as unbounded"));
            }
            good
        });
        let kind = match light.kind() {
            Kind::Directional => FileLightKind::Directional,
            Kind::Point => FileLightKind::Point,
            Kind::Spot { inner_cone_angle: inner, outer_cone_angle: outer } => {
                let right = std::f32::consts::FRAC_PI_2;
                if !(0.0 <= inner && inner < outer && outer <= right) {
                    warnings.push(format!(
                        "{at}: its cone angles {inner} and {outer} are not 0 ≤ inner < outer ≤ π/2: clamped"
                    ));
                }
                FileLightKind::Spot { inner, outer }
            }
        };
        data.spend(size_of::<ModelLight>())?;
        out.push(ModelLight { node: node.index(), kind, color, intensity, range });
    }
    Ok(out)
}

/// The camera of the first node in `scene` that has one; its numbers are checked, and one that
/// makes no sense is replaced by umbra's default with a warning.
pub(super) fn camera(nodes: &[gltf::Node<'_>], scene: &[usize], warnings: &mut Vec<String>) -> Option<ModelCamera> {
    let node = scene.iter().map(|&n| &nodes[n]).find(|n| n.camera().is_some())?;
    let camera = node.camera()?;
    let at = format!("camera {} (on node {})", camera.index(), node.index());
    let (fov_y, near, far) = match camera.projection() {
        Projection::Perspective(p) => (Some(p.yfov()), p.znear(), p.zfar()),
        Projection::Orthographic(o) => {
            warnings.push(format!("{at} is orthographic; umbra shows its view in perspective"));
            (None, o.znear(), Some(o.zfar()))
        }
    };
    let fov_y = fov_y.filter(|f| {
        let good = f.is_finite() && *f > 1e-3 && *f < std::f32::consts::PI - 1e-3;
        if !good {
            warnings.push(format!("{at} has a vertical field of view of {f} radians: umbra's default taken"));
        }
        good
    });
    let near = Some(near).filter(|n| n.is_finite() && *n > 0.0);
    if near.is_none() {
        warnings.push(format!("{at} has no positive near plane: umbra's default taken"));
    }
    let far = far.filter(|f| f.is_finite() && *f > near.unwrap_or(0.0));
    Some(ModelCamera { node: node.index(), fov_y, near, far })
}
