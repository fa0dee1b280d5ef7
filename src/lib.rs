//! umbra: a game sample about real-time shadow mapping.
//!
//! The [`App`] owns a bevy_ecs [`World`] and the fixed-step update schedule; the renderer in
//! [`render`] reads the world's components and draws the shadow pass and then the main pass.
//!
//! # Adding a gameplay system
//!
//! A system is a plain function over queries and resources; [`App::add_systems`] puts it into the
//! update schedule after animation and camera control and before the lights' matrices are
//! fitted, so whatever it moves casts its shadow in the same frame:
//!
//! ```no_run
//! use bevy_ecs::prelude::*;
//! use glam::Vec3;
//! use umbra::assets::{MeshLibrary, cube};
//! use umbra::components::{Material, ShadowCaster, Transform};
//! use umbra::{App, Settings};
//!
//! #[derive(Component)]
//! struct Spinner;
//!
//! fn spin(mut q: Query<&mut Transform, With<Spinner>>) {
//!     for mut t in &mut q {
//!         t.rotation *= glam::Quat::from_rotation_y(0.02);
//!     }
//! }
//!
//! let mut app = App::new(Settings::default())?;
//! let mesh = app.world.resource_mut::<MeshLibrary>().add(cube(Vec3::splat(0.5)));
//! app.world.spawn((mesh, Material::color(0.8, 0.3, 0.3), Spinner, ShadowCaster));
//! app.add_systems(spin);
//! # Ok::<(), umbra::AppError>(())
//! ```
//!
//! `examples/gameplay.rs` is the whole program, window included.
//!
//! # Where the pieces live
//!
//! - [`components`]: what the world holds (transforms, meshes, materials, lights and their
//!   shadow settings); [`light`]: one module per light kind, and the typed list the renderer reads.
//! - [`systems`]: the update schedule's systems (animation, bounds, cascades, every light's layers).
//! - [`shadow`]: the CPU math of shadow maps (cascade fits, the atlas, the update budget), apart
//!   from any GPU code; [`render`]: the wgpu passes and their WGSL in `shaders/`.
//! - [`settings`]: every setting, by concern (the scene's, used once when the app is made, then
//!   the shadows', the maps', the cascades' and the view's, each group a resource of its own that
//!   a system reads as `Res<ShadowSettings>` and the like), validated where each group is
//!   defined; [`scene`], [`scene_file`] and
//!   [`assets`]: the sample scene, scene files and glTF models.
//! - [`eval`]: the ray-traced truth, the bench, the failure cases; [`play`] and [`ui`]: the window,
//!   its keys and the panel.
//!
//! The book (`docs/book/` in the repository) tells the rest, in order.

/// `ALL`, `name`, `next` and `FromStr` for a settings enum that the command line and the keys step
/// through by name.
macro_rules! named_choices {
    ($ty:ty, $what:literal, $($variant:ident = $name:literal),+) => {
        impl $ty {
            /// Every choice, in the order the key steps through them.
            pub const ALL: &'static [$ty] = &[$(<$ty>::$variant),+];

            /// The choice's name as the command line spells it.
            pub fn name(self) -> &'static str {
                match self { $(<$ty>::$variant => $name),+ }
            }

            /// The next choice, round again after the last.
            pub fn next(self) -> $ty {
                let i = Self::ALL.iter().position(|c| *c == self).unwrap_or(0);
                Self::ALL[(i + 1) % Self::ALL.len()]
            }
        }

        impl $crate::NamedChoice for $ty {
            fn all() -> &'static [$ty] {
                Self::ALL
            }
            fn choice_name(self) -> &'static str {
                self.name()
            }
        }

        impl std::str::FromStr for $ty {
            type Err = String;
            fn from_str(s: &str) -> Result<$ty, String> {
                Self::ALL.iter().copied().find(|c| c.name() == s).ok_or_else(|| {
                    let names: Vec<&str> = Self::ALL.iter().map(|c| c.name()).collect();
                    format!("`{s}` is not {}: give one of {}", $what, names.join(", "))
                })
            }
        }
    };
}

/// A setting chosen by name from one table (each written by `named_choices!`): what the command
/// line lists in its help and parses, and the keys step through.
pub trait NamedChoice: Copy + Send + Sync + 'static {
    /// Every choice, in the table's order.
    fn all() -> &'static [Self];
    /// The choice's name as the command line spells it.
    fn choice_name(self) -> &'static str;
}

pub mod assets;
pub mod biases;
pub mod components;
pub mod eval;
pub mod figures;
pub mod lanterns;
pub mod light;
pub mod play;
pub mod render;
pub mod reproduce;
pub mod scene;
pub mod scene_file;
pub mod settings;
pub mod shadow;
pub mod systems;
pub mod ui;

use assets::MeshLibrary;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::{ScheduleConfigs, ScheduleLabel};
use bevy_ecs::system::ScheduleSystem;
use components::{Input, Time, Viewport};
pub use settings::{Settings, SettingsError};

/// Why the sample could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// A setting is out of range.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// A model file could not be loaded.
    #[error(transparent)]
    Model(#[from] assets::ModelError),
    /// A per-light setting names a light the scene does not have.
    #[error("no light is called `{name}`: the scene's lights are {known}")]
    UnknownLight {
        /// The name given.
        name: String,
        /// The lights there are, listed.
        known: String,
    },
}

/// The fixed-step update schedule.
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct Update;

/// The ordered stages of one update; gameplay systems go in [`Stage::Gameplay`].
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Scripted animation: cubes, walkers and model clips.
    Animate,
    /// Camera control from input.
    Camera,
    /// User systems: they see the animated scene and may move anything before lights are fitted.
    Gameplay,
    /// Model parts posed, world bounds, light matrices and shadow-map dirty flags.
    Lights,
}

/// The sample: a world, its update schedule and a fixed clock.
pub struct App {
    /// All entities, components and resources.
    pub world: World,
    update: Schedule,
}

impl App {
    /// An app holding the sample scene (and the user's model, if the settings name one), or the
    /// scene of the glTF file the settings name.
    pub fn new(settings: Settings) -> Result<App, AppError> {
        let texel_density = settings.view.texel_density.clone();
        let scene = settings.scene.clone();
        let mut app = App::empty(settings)?;
        match scene.file {
            Some(_) => scene_file::spawn_file_scene(&mut app.world, &scene)?,
            None => scene::spawn_sample_scene(&mut app.world, &scene)?,
        }
        if let Some(biases) = &scene.biases {
            biases.apply(&mut app.world);
        }
        reproduce::apply(&mut app.world, &scene.light_settings)?;
        if let Some(name) = &texel_density {
            reproduce::light_named(&mut app.world, name)?;
        }
        if let Some((eye, target)) = scene.camera {
            scene::place_camera(&mut app.world, eye, target);
        }
        Ok(app)
    }

    /// An app with umbra's resources and systems but no entities, for custom scenes and tests.
    pub fn empty(settings: Settings) -> Result<App, SettingsError> {
        settings.validate()?;
        let mut world = World::new();
        world.insert_resource(Time { dt: settings.scene.dt, ..Default::default() });
        let caps = systems::ShadowCaps::default();
        let atlas = systems::ShadowAtlas::for_settings(&settings.maps, caps, [settings.shadow.method].into_iter());
        world.insert_resource(atlas);
        settings.put(&mut world)?;
        world.insert_resource(Input::default());
        world.insert_resource(Viewport { width: 1280, height: 720 });
        world.insert_resource(MeshLibrary::default());
        world.insert_resource(assets::TextureLibrary::default());
        world.insert_resource(components::Notices::default());
        world.insert_resource(systems::CasterChanges::default());
        world.insert_resource(components::SharedPool::default());
        world.insert_resource(systems::CastersAtRest::default());
        let mut update = Schedule::new(Update);
        update.configure_sets((Stage::Animate, Stage::Camera, Stage::Gameplay, Stage::Lights).chain());
        update
            .add_systems((systems::spin, systems::bob, systems::walk, systems::animate_models).in_set(Stage::Animate));
        update.add_systems((systems::fly_camera, systems::orbit_camera).in_set(Stage::Camera));
        let lights = (
            (systems::pose_parts, systems::follow_nodes),
            systems::update_bounds,
            systems::track_casters,
            systems::size_shadow_maps,
            systems::update_light_matrices,
        );
        update.add_systems(lights.chain().in_set(Stage::Lights));
        Ok(App { world, update })
    }

    /// Adds gameplay systems; they run after animation and camera and before the light matrices.
    pub fn add_systems<M>(&mut self, systems: impl IntoScheduleConfigs<ScheduleSystem, M>) -> &mut Self {
        let configs: ScheduleConfigs<ScheduleSystem> = systems.into_configs();
        self.update.add_systems(configs.in_set(Stage::Gameplay));
        self
    }

    /// Advances the clock by one fixed step and runs the update schedule.
    pub fn step(&mut self) {
        let mut time = self.world.resource_mut::<Time>();
        time.frame += 1;
        time.t = time.frame as f64 * time.dt as f64;
        self.run_update();
    }

    /// Runs the update schedule with the clock held where it is: the camera and anything else
    /// driven by input moves, the animation does not.
    pub fn step_held(&mut self) {
        self.run_update();
    }

    /// Sets the clock to `t` seconds and runs the update schedule: the scene as it is at `t`.
    pub fn set_time(&mut self, t: f64) {
        let mut time = self.world.resource_mut::<Time>();
        time.frame = (t / time.dt as f64).round() as u64;
        time.t = t;
        self.run_update();
    }

    /// Tells the app the size of the image it is rendered into.
    pub fn resize(&mut self, width: u32, height: u32) {
        *self.world.resource_mut::<Viewport>() = Viewport { width, height };
    }

    /// The messages systems raised for the user since the last call (see [`components::Notices`]).
    pub fn take_notices(&mut self) -> Vec<String> {
        self.world.get_resource_mut::<components::Notices>().map(|mut n| std::mem::take(&mut n.0)).unwrap_or_default()
    }

    /// Takes in what the renderer learned ([`render::Renderer::news`]): what this device keeps
    /// of shadows (a world that updated before it heard has its tiles sized again, and its lights
    /// fitted again, for this device), the last frame's [`render::ShadowStats`], what the camera
    /// saw for the SDSM fit, the pages paged lights' pixels asked for, and messages for the user. The renderer reads the world only; this
    /// is the one way what it learns gets in.
    pub fn hear(&mut self, news: render::RenderNews) {
        let before = self.world.get_resource::<systems::ShadowCaps>().copied().unwrap_or_default();
        self.world.insert_resource(news.caps);
        if before != news.caps && self.world.resource::<Time>().updates > 0 {
            use bevy_ecs::system::RunSystemOnce;
            let _ = self.world.run_system_once(systems::size_shadow_maps);
            let _ = self.world.run_system_once(systems::update_light_matrices);
        }
        if let Some(stats) = news.stats {
            self.world.insert_resource(stats);
        }
        if let Some(seen) = news.seen {
            self.world.insert_resource(components::SeenByCamera(seen));
        }
        if !news.marks.is_empty() {
            let mut marked = self.world.get_resource_or_init::<components::MarkedPages>();
            for marks in news.marks {
                marked.0.retain(|m| m.light != marks.light);
                marked.0.push(marks);
            }
        }
        self.world.get_resource_or_init::<components::Notices>().0.extend(news.notices);
    }

    /// A copy of the settings in force, every group of them (systems read the group they need
    /// as a resource: [`settings::ShadowSettings`], [`settings::MapSettings`] and the others).
    pub fn settings(&self) -> Settings {
        Settings::from_world(&self.world)
    }

    /// Puts `settings` in force from the next update: each group that differs from the one in
    /// force replaces it (the scene's are kept, for what they say about how the app was made,
    /// but change nothing now). Refused, with nothing changed, if one is out of range.
    pub fn set_settings(&mut self, settings: &Settings) -> Result<(), SettingsError> {
        settings.put(&mut self.world)
    }

    fn run_update(&mut self) {
        self.world.resource_mut::<Time>().updates += 1;
        self.update.run(&mut self.world);
        // Mouse motion and the wheel are consumed by the step that saw them.
        let mut input = self.world.resource_mut::<Input>();
        (input.look_delta, input.drag_delta, input.zoom) = (glam::Vec2::ZERO, glam::Vec2::ZERO, 0.0);
    }
}
