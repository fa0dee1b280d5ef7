//! Components and resources: the data the systems write and the renderer reads.

mod light;

pub use light::*;

use crate::shadow::Aabb;
use bevy_ecs::prelude::*;
use glam::{Mat4, Quat, Vec2, Vec3};

/// Where an entity is: translation, rotation and scale.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// Position in metres.
    pub translation: Vec3,
    /// Orientation.
    pub rotation: Quat,
    /// Per-axis scale.
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Transform { translation: Vec3::ZERO, rotation: Quat::IDENTITY, scale: Vec3::ONE }
    }
}

impl Transform {
    /// A transform at `at` with no rotation or scale.
    pub fn from_translation(at: Vec3) -> Self {
        Transform { translation: at, ..Default::default() }
    }

    /// A transform at `(x, y, z)` with no rotation or scale.
    pub fn from_xyz(x: f32, y: f32, z: f32) -> Self {
        Transform { translation: Vec3::new(x, y, z), ..Default::default() }
    }

    /// This transform with its scale replaced.
    pub fn with_scale(self, scale: Vec3) -> Self {
        Transform { scale, ..self }
    }

    /// This transform with its rotation replaced.
    pub fn with_rotation(self, rotation: Quat) -> Self {
        Transform { rotation, ..self }
    }

    /// This transform turned to look along `dir` (its -Z axis points that way).
    pub fn looking_to(self, dir: Vec3) -> Self {
        let view = crate::shadow::light_view(Vec3::ZERO, dir);
        let rotation = Quat::from_mat4(&view.inverse());
        Transform { rotation, ..self }
    }

    /// Local to world matrix.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }

    /// The direction the entity faces (its local -Z).
    pub fn forward(&self) -> Vec3 {
        self.rotation * Vec3::NEG_Z
    }
}

/// Index of a mesh in the [`crate::assets::MeshLibrary`].
///
/// A mesh entity always has a [`Transform`] and [`WorldBounds`]; they are added if missing.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[require(Transform, WorldBounds)]
pub struct Mesh(pub usize);

/// Index of a texture in the [`crate::assets::TextureLibrary`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Texture(pub usize);

/// How a surface's alpha (base colour × texture × vertex colour) is used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored: the surface is solid.
    Opaque,
    /// Fragments with alpha below `cutoff` are not there at all (leaves, fences), in the
    /// picture, in the shadow maps and in the ray-traced truth alike.
    Mask {
        /// Alpha below which a fragment is cut away.
        cutoff: f32,
    },
    /// The surface is blended over what is behind it, drawn after every opaque surface, back to
    /// front. Shadow maps and the truth cannot be half transparent: there it counts as
    /// [`AlphaMode::Mask`] at [`BLEND_CUTOFF`].
    Blend,
}

/// Where a blended surface counts as solid in shadow maps, the measuring view and the truth.
pub const BLEND_CUTOFF: f32 = 0.5;

impl AlphaMode {
    /// The alpha below which the surface casts no shadow and is not measured: none for opaque.
    #[must_use]
    pub fn cutoff(self) -> Option<f32> {
        match self {
            AlphaMode::Opaque => None,
            AlphaMode::Mask { cutoff } => Some(cutoff),
            AlphaMode::Blend => Some(BLEND_CUTOFF),
        }
    }
}

/// Surface colour, Phong response and how the surface is drawn.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Linear RGB albedo (multiplied by the texture and the vertex colours).
    pub base_color: Vec3,
    /// Alpha factor (multiplied by the texture's and the vertex colours' alpha).
    pub opacity: f32,
    /// Strength of the specular highlight (0 = matte).
    pub specular: f32,
    /// Phong exponent: larger is a tighter highlight.
    pub shininess: f32,
    /// Base-colour texture, if any.
    pub texture: Option<Texture>,
    /// How alpha is used.
    pub alpha_mode: AlphaMode,
    /// Drawn from both sides (the normal flipped on the back); otherwise back faces are culled.
    pub double_sided: bool,
}

impl Default for Material {
    fn default() -> Self {
        Material::color(0.8, 0.8, 0.8)
    }
}

impl Material {
    /// An opaque, one-sided, untextured matte material of the given linear colour with a faint
    /// highlight.
    pub fn color(r: f32, g: f32, b: f32) -> Self {
        Material {
            base_color: Vec3::new(r, g, b),
            opacity: 1.0,
            specular: 0.25,
            shininess: 32.0,
            texture: None,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
        }
    }
}

/// A perspective camera; its pose is the entity's [`Transform`].
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Vertical field of view in radians.
    pub fov_y: f32,
    /// Near plane distance in metres.
    pub near: f32,
    /// Far plane distance in metres.
    pub far: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Camera { fov_y: 60f32.to_radians(), near: 0.1, far: 200.0 }
    }
}

impl Camera {
    /// Projection for a viewport of the given aspect ratio (depth 0..1).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        glam::camera::rh::proj::directx::perspective(self.fov_y, aspect.max(1e-3), self.near, self.far)
    }

    /// World to clip space for a camera at `transform`.
    pub fn view_proj(&self, transform: &Transform, aspect: f32) -> Mat4 {
        let view = Mat4::from_rotation_translation(transform.rotation, transform.translation).inverse();
        self.projection(aspect) * view
    }

    /// Radians a pixel spans at the middle of a picture `height` pixels high (0 for none).
    #[must_use]
    pub fn pixel_angle(&self, height: u32) -> f32 {
        if height == 0 { 0.0 } else { 2.0 * (self.fov_y * 0.5).tan() / height as f32 }
    }

    /// The view depth the shadows reach: `shadow_distance`, no farther than the far plane and no
    /// nearer than twice the near one. The cascades split up to it and the SDSM reduction bins
    /// up to it, so both read it from here.
    #[must_use]
    pub fn shadow_far(&self, shadow_distance: f32) -> f32 {
        shadow_distance.min(self.far).max(self.near * 2.0)
    }
}

/// Fly-camera state: the camera looks along yaw/pitch and moves at `speed` m/s.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct FlyCamera {
    /// Turn about world Y in radians (0 looks along -Z).
    pub yaw: f32,
    /// Turn above the horizon in radians.
    pub pitch: f32,
    /// Walking speed in metres per second.
    pub speed: f32,
    /// Radians turned per pixel of mouse motion.
    pub sensitivity: f32,
}

impl FlyCamera {
    /// A fly camera looking along yaw/pitch at the default speed.
    pub fn new(yaw: f32, pitch: f32) -> Self {
        FlyCamera { yaw, pitch, speed: 6.0, sensitivity: 0.003 }
    }

    /// The rotation the yaw and pitch describe.
    pub fn rotation(&self) -> Quat {
        Quat::from_rotation_y(self.yaw) * Quat::from_rotation_x(self.pitch)
    }
}

/// Orbit-camera state: while `active`, the camera circles `focus` at `distance`, turned by
/// dragging and pulled in or out by the wheel; otherwise the fly camera steers it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// It steers the camera (the fly camera waits).
    pub active: bool,
    /// What it circles.
    pub focus: OrbitFocus,
    /// Metres from the focus.
    pub distance: f32,
    /// Turn about world Y in radians (0 looks along -Z, as [`FlyCamera::yaw`]).
    pub yaw: f32,
    /// Turn above the horizon in radians (negative looks down).
    pub pitch: f32,
    /// Radians turned per pixel dragged.
    pub sensitivity: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        OrbitCamera {
            active: false,
            focus: OrbitFocus::Point(Vec3::new(0.0, 1.0, 0.0)),
            distance: 12.0,
            yaw: 0.0,
            pitch: -0.4,
            sensitivity: 0.005,
        }
    }
}

/// What an orbit camera circles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OrbitFocus {
    /// A fixed point (the scene's centre).
    Point(Vec3),
    /// An entity, this far above its origin (the walking character's chest).
    Entity(Entity, f32),
}

/// Marks an entity that is drawn into shadow maps.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct ShadowCaster;

/// Marks an entity whose surface takes shadows.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct ShadowReceiver;

/// Turns an entity about `axis` at `rate` radians per second from `base` at t = 0.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Spin {
    /// Unit axis.
    pub axis: Vec3,
    /// Radians per second.
    pub rate: f32,
    /// Rotation at t = 0.
    pub base: Quat,
}

/// Moves an entity up and down: `y = base_y + amplitude * sin(frequency * t + phase)`.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Bob {
    /// Height of the centre of motion.
    pub base_y: f32,
    /// Metres above and below the centre.
    pub amplitude: f32,
    /// Radians per second.
    pub frequency: f32,
    /// Radians at t = 0.
    pub phase: f32,
}

/// Plays one of a model's clips, looping, at `speed` times real time.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Animator {
    /// The clip, or none for the rest pose.
    pub clip: Option<usize>,
    /// Playback rate (1 = as authored).
    pub speed: f32,
}

/// Model-space matrices of every node of a model, as its clip has them now.
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct Pose(pub Vec<Mat4>);

/// One mesh of a model: which model entity and which of its parts.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ModelPart {
    /// The entity holding the [`crate::assets::ModelInstance`].
    pub root: Entity,
    /// Index into the model's parts.
    pub part: usize,
}

/// An entity hung on a node of a model (a file's light): it goes where the model's pose puts
/// the node, turning with it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct AtNode {
    /// The entity holding the [`crate::assets::ModelInstance`].
    pub root: Entity,
    /// Index into the model's nodes.
    pub node: usize,
}

/// The joint matrices that skin this entity's mesh (model space: `global joint × inverse bind`);
/// the vertex shader blends them, and the entity's bounds follow them.
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct Joints(pub Vec<Mat4>);

/// Walks an entity round a circle on the ground at a steady pace, facing the way it goes.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Walker {
    /// Centre of the circle (its y is the ground height).
    pub center: Vec3,
    /// Radius in metres.
    pub radius: f32,
    /// Metres per second along the circle (negative walks the other way).
    pub speed: f32,
    /// Angle on the circle at t = 0, radians.
    pub phase: f32,
}

/// World-space bounds of a mesh entity, kept up to date by [`crate::systems::update_bounds`].
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct WorldBounds(pub Aabb);

impl Default for WorldBounds {
    fn default() -> Self {
        WorldBounds(Aabb::EMPTY)
    }
}

/// Simulation time on a fixed step: the scene at `t` is a pure function of `t`.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct Time {
    /// Seconds since the start.
    pub t: f64,
    /// The fixed step in seconds.
    pub dt: f32,
    /// Steps taken.
    pub frame: u64,
    /// Updates run, with the clock held or not: a frame of the world, however many pictures
    /// are rendered of it (the shadow update budget is spent once per update).
    pub updates: u64,
}

impl Default for Time {
    fn default() -> Self {
        Time { t: 0.0, dt: 1.0 / 60.0, frame: 0, updates: 0 }
    }
}

/// Keys the sample reacts to, independent of the window library.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Key {
    /// Move forward.
    Forward,
    /// Move back.
    Back,
    /// Move left.
    Left,
    /// Move right.
    Right,
    /// Move up.
    Up,
    /// Move down.
    Down,
    /// Move faster while held.
    Fast,
}

/// Input for this step: held keys, mouse motion while looking or dragging, and the wheel.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct Input {
    /// Keys held down.
    pub held: Vec<Key>,
    /// Mouse motion in pixels since the last step (only while looking).
    pub look_delta: Vec2,
    /// Mouse motion in pixels since the last step while dragging (the orbit camera's turn).
    pub drag_delta: Vec2,
    /// Wheel steps since the last step (positive: towards the scene).
    pub zoom: f32,
}

impl Input {
    /// True while `key` is held.
    pub fn pressed(&self, key: Key) -> bool {
        self.held.contains(&key)
    }

    /// Starts or stops holding `key`.
    pub fn set(&mut self, key: Key, down: bool) {
        self.held.retain(|k| *k != key);
        if down {
            self.held.push(key);
        }
    }
}

/// Messages for the user that systems raise while the scene runs (a broken object left out of
/// light fitting, say); the front end prints and clears them.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct Notices(pub Vec<String>);

/// What the camera saw in the last frame the renderer read back (sample distribution shadow
/// maps: the renderer writes it, the light matrices read it at the next update).
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct SeenByCamera(pub crate::shadow::VisibleSamples);

/// The pages the camera's pixels asked each paged light for, in the last marking the renderer
/// read back (virtual shadow maps: the renderer writes it, the light matrices read it at the next
/// update and give the pages slots).
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct MarkedPages(pub Vec<crate::shadow::PageMarks>);

/// Size of the image being rendered, in pixels.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Viewport {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl Viewport {
    /// Width over height (1 for an empty viewport).
    pub fn aspect(&self) -> f32 {
        if self.width == 0 || self.height == 0 { 1.0 } else { self.width as f32 / self.height as f32 }
    }

    /// Pixel coordinates (x right, y down) of world point `p` seen through `view_proj`, or `None`
    /// when the point is behind the camera.
    pub fn project(&self, view_proj: &Mat4, p: Vec3) -> Option<Vec2> {
        let clip = *view_proj * p.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some(Vec2::new((ndc.x * 0.5 + 0.5) * self.width as f32, (0.5 - ndc.y * 0.5) * self.height as f32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shadows_reach_the_shadow_distance_within_the_camera_planes() {
        let c = Camera { near: 0.5, far: 100.0, ..Camera::default() };
        assert_eq!(c.shadow_far(60.0), 60.0);
        assert_eq!(c.shadow_far(500.0), 100.0);
        assert_eq!(c.shadow_far(0.0), 1.0);
        assert_eq!(c.shadow_far(f32::NAN), 100.0);
        assert_eq!(c.shadow_far(f32::INFINITY), 100.0);
    }

    #[test]
    fn project_puts_the_look_target_in_the_middle() {
        let cam = Camera::default();
        let t = Transform::from_xyz(0.0, 2.0, 5.0).looking_to(Vec3::new(0.0, -2.0, -5.0));
        let vp = Viewport { width: 200, height: 100 };
        let m = cam.view_proj(&t, vp.aspect());
        let c = vp.project(&m, Vec3::ZERO).unwrap();
        assert!((c - Vec2::new(100.0, 50.0)).length() < 1e-3, "{c:?}");
        // Up in the world is up on screen, which is a smaller y.
        assert!(vp.project(&m, Vec3::Y * 0.5).unwrap().y < 50.0);
        assert!(vp.project(&m, Vec3::new(0.0, 2.0, 10.0)).is_none());
    }
}
