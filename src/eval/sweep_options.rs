//! What a sweep measures besides its configurations ([`super::config`]): the views of the
//! measured scene, how big and how long, the truth's rays, and how many threads measure errors.

use super::cases::CASES;
use super::config::{Config, configs};
use super::measure::TruthSettings;
use crate::App;
use crate::settings::Settings;
use bevy_ecs::prelude::With;
use glam::Vec3;

/// What `--family` takes for the configurations with contact shadows beside their twins
/// without (they belong to their methods' families).
pub const CONTACT_GROUP: &str = "contact shadows";

/// A view of a measured scene: a camera and a time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Its name.
    pub name: &'static str,
    /// Where the camera is.
    pub eye: Vec3,
    /// What it looks at.
    pub target: Vec3,
    /// Scene time in seconds.
    pub time: f64,
}

/// The fixed views of the sample scene that every configuration is measured from.
pub const VIEWS: [View; 4] = [
    View { name: "overview", eye: Vec3::new(2.0, 5.5, 12.5), target: Vec3::new(-0.5, 1.0, 0.0), time: 6.0 },
    View { name: "character", eye: Vec3::new(3.0, 2.5, 7.5), target: Vec3::new(0.0, 0.8, 3.0), time: 3.0 },
    View { name: "far", eye: Vec3::new(-12.0, 1.8, 14.0), target: Vec3::new(4.0, 0.5, -6.0), time: 2.0 },
    View { name: "above", eye: Vec3::new(0.5, 18.0, 6.0), target: Vec3::ZERO, time: 9.0 },
];

/// The views `app`'s scene is measured from: the sample scene's four, or a scene file's own
/// camera (or the one that frames it) at 2 s.
pub fn views(app: &mut App) -> Vec<View> {
    if app.world.resource::<crate::settings::SceneSettings>().file.is_none() {
        return VIEWS.to_vec();
    }
    let mut cameras = app.world.query_filtered::<&crate::components::Transform, With<crate::components::Camera>>();
    cameras
        .iter(&app.world)
        .map(|t| View { name: "scene camera", eye: t.translation, target: t.translation + t.forward(), time: 2.0 })
        .collect()
}

/// What the sweep measures, how big and how long.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepOptions {
    /// The settings every configuration starts from (which scene, its exposure).
    pub base: Settings,
    /// The views of the scene measured.
    pub views: Vec<View>,
    /// Fewer configurations, smaller frames, fewer timed frames.
    pub quick: bool,
    /// Size of the sample-scene frames.
    pub size: (u32, u32),
    /// Size of the failure cases' frames.
    pub case_size: (u32, u32),
    /// Timed frames per view after two untimed ones.
    pub frames: u32,
    /// How the truth is taken.
    pub truth: TruthSettings,
    /// Only the configurations of these families, and the default's (all when empty).
    pub families: Vec<String>,
    /// None of the configurations of these families but the default's.
    pub skipped: Vec<String>,
    /// Configurations whose errors are measured at once, each by a thread with renderers of
    /// its own (the timing is never shared).
    pub workers: usize,
    /// Only the failure cases of these names (every case when `None`): the others are left
    /// unmeasured, and the results say so.
    pub cases: Option<Vec<String>>,
}

/// Threads that measure errors at once on a machine of `cores` cores: one per four cores, one
/// to four (a two-core machine's software rasterizer already takes both).
#[must_use]
pub fn error_workers(cores: usize) -> usize {
    (cores / 4).clamp(1, 4)
}

impl SweepOptions {
    /// True when the sweep measures the failure case `name`.
    #[must_use]
    pub fn measures_case(&self, name: &str) -> bool {
        self.cases.as_ref().is_none_or(|cases| cases.iter().any(|c| c == name))
    }

    /// An error naming the first case asked for that is not a failure case, and listing those
    /// there are.
    pub fn known_cases(&self) -> Result<(), String> {
        match self.cases.iter().flatten().find(|name| !CASES.iter().any(|c| c.name == name.as_str())) {
            Some(unknown) => {
                let known: Vec<&str> = CASES.iter().map(|c| c.name).collect();
                Err(format!("no failure case is named \"{unknown}\"; the cases are: {}", known.join(", ")))
            }
            None => Ok(()),
        }
    }

    /// The full sweep, or the quick one.
    pub fn new(quick: bool) -> SweepOptions {
        let workers = error_workers(std::thread::available_parallelism().map_or(1, |n| n.get()));
        if quick {
            SweepOptions {
                base: Settings::default(),
                views: VIEWS.to_vec(),
                quick,
                size: (320, 180),
                case_size: (192, 192),
                frames: 4,
                truth: TruthSettings { soft_rays: 8, ..Default::default() },
                families: Vec::new(),
                skipped: Vec::new(),
                workers,
                cases: None,
            }
        } else {
            SweepOptions {
                base: Settings::default(),
                views: VIEWS.to_vec(),
                quick,
                size: (640, 360),
                case_size: (256, 256),
                frames: 10,
                truth: TruthSettings::default(),
                families: Vec::new(),
                skipped: Vec::new(),
                workers,
                cases: None,
            }
        }
    }

    /// The configurations it sweeps: [`configs`], only those of its families (and the
    /// default's) when it names any, less those of the families it skips (but the default).
    /// [`CONTACT_GROUP`] names every configuration with contact shadows and each one's twin
    /// without them, whatever their families. A name no configuration has is an error that lists
    /// those there are, as is a failure case unknown ([`SweepOptions::known_cases`]).
    pub fn configs(&self) -> Result<Vec<Config>, String> {
        self.known_cases()?;
        let all = configs(self.quick);
        let mut known: Vec<&str> = all.iter().fold(Vec::new(), |mut names, c| {
            if !names.contains(&c.family()) {
                names.push(c.family());
            }
            names
        });
        if all.iter().any(|c| c.contact) {
            known.push(CONTACT_GROUP);
        }
        if let Some(unknown) = self.families.iter().chain(&self.skipped).find(|f| !known.contains(&f.as_str())) {
            return Err(format!(
                "no configuration is of the family \"{unknown}\"; the families are: {}",
                known.join(", ")
            ));
        }
        let d = Config::default_settings();
        let contact = self.families.iter().any(|f| f == CONTACT_GROUP);
        let has_contact_twin = |c: &Config| all.contains(&Config { contact: true, ..*c });
        let wanted = |c: &Config| {
            self.families.is_empty()
                || *c == d
                || self.families.iter().any(|f| f == c.family())
                || (contact && has_contact_twin(c))
        };
        let skipped = |c: &Config| *c != d && self.skipped.iter().any(|f| f == c.family());
        Ok(all.iter().copied().filter(|c| wanted(c) && !skipped(c)).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_family_chosen_takes_its_configurations_and_the_defaults_and_nothing_else() {
        let mut options = SweepOptions::new(false);
        options.families = vec!["moment maps".into()];
        let some = options.configs().unwrap();
        assert!(some.contains(&Config::default_settings()));
        assert!(some.iter().all(|c| *c == Config::default_settings() || c.method.moments()));
        assert_eq!(some.len(), 1 + configs(false).iter().filter(|c| c.family() == "moment maps").count());
        options.families = vec!["moments".into()];
        let err = options.configs().unwrap_err();
        assert!(err.contains("\"moments\"") && err.contains("moment maps") && err.contains("Bevy-like"), "{err}");
    }

    #[test]
    fn the_contact_group_takes_each_configuration_with_contact_shadows_beside_its_twin_without() {
        let mut options = SweepOptions::new(false);
        options.families = vec![CONTACT_GROUP.into()];
        let some = options.configs().unwrap();
        let with: Vec<&Config> = some.iter().filter(|c| c.contact).collect();
        assert_eq!(with.len(), configs(false).iter().filter(|c| c.contact).count());
        assert!(with.len() >= 8, "{}", with.len());
        for c in &with {
            assert!(some.contains(&Config { contact: false, ..**c }), "{}", c.label());
        }
        assert_eq!(some.len(), 2 * with.len(), "each twin once, the default among them");
        options.quick = true;
        let err = options.configs().unwrap_err();
        assert!(
            err.starts_with(&format!("no configuration is of the family \"{CONTACT_GROUP}\"")),
            "the quick sweep has none: {err}"
        );
    }

    #[test]
    fn an_unknown_case_is_refused_with_the_list() {
        let mut options = SweepOptions::new(true);
        options.cases = Some(vec!["acne".into(), "shimmer".into()]);
        assert!(options.configs().is_ok());
        assert!(options.measures_case("shimmer") && !options.measures_case("thin-casters"));
        options.cases = Some(vec!["acne".into(), "spots".into()]);
        let err = options.configs().unwrap_err();
        assert!(err.starts_with("no failure case is named \"spots\"") && err.contains("peter-panning"), "{err}");
    }

    #[test]
    fn a_family_skipped_leaves_out_its_configurations_but_the_defaults() {
        let mut options = SweepOptions::new(true);
        options.skipped = vec!["moment maps".into()];
        let some = options.configs().unwrap();
        assert!(some.contains(&Config::default_settings()));
        assert!(some.iter().all(|c| !c.method.moments()), "no moment map left");
        let moments = configs(true).iter().filter(|c| c.family() == "moment maps").count();
        assert!(moments > 0);
        assert_eq!(some.len() + moments, configs(true).len());
        options.skipped = vec!["moments".into()];
        assert!(options.configs().unwrap_err().contains("\"moments\""));
    }

    #[test]
    fn errors_are_measured_one_thread_per_four_cores() {
        assert_eq!([0, 1, 2, 3, 4, 8, 16, 64].map(error_workers), [1, 1, 1, 1, 1, 2, 4, 4]);
    }
}
