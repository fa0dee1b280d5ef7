//! Per-light shadow biases, as `umbra tune` finds them and writes them to a file, and as `play`,
//! `render` and `bench --cache` read them back (`--biases FILE`).

use crate::components::ShadowBias;
use crate::systems::light_order;
use bevy_ecs::prelude::*;
use serde_json::{Value, json};
use std::path::Path;

/// One bias per light, in the order the renderer uses the lights: the sun, then the spots.
#[derive(Clone, Debug, PartialEq)]
pub struct LightBiases {
    /// The sun's.
    pub sun: Option<ShadowBias>,
    /// Each spot light's.
    pub spots: Vec<ShadowBias>,
}

/// A bias file that could not be read, and why.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{path}: {problem}")]
pub struct BiasFileError {
    /// The file.
    pub path: String,
    /// What is wrong with it.
    pub problem: String,
}

fn bias_json(b: &ShadowBias) -> Value {
    json!({ "constant": b.constant, "slope": b.slope, "normal": b.normal })
}

fn bias_from(v: &Value, at: &str) -> Result<ShadowBias, String> {
    let field = |name: &str| -> Result<f32, String> {
        let x = v.get(name).and_then(Value::as_f64).ok_or(format!("{at}: `{name}` must be a number"))?;
        if (0.0..=100.0).contains(&x) {
            Ok(x as f32)
        } else {
            Err(format!("{at}: `{name}` = {x} must be between 0 and 100 texels"))
        }
    };
    Ok(ShadowBias { constant: field("constant")?, slope: field("slope")?, normal: field("normal")? })
}

impl LightBiases {
    /// The biases the lights of `world` have now.
    pub fn of(world: &mut World) -> LightBiases {
        let (sun, spots) = light_order(world);
        let bias = |e: Entity| world.get::<ShadowBias>(e).copied().unwrap_or_default();
        LightBiases { sun: sun.map(bias), spots: spots.into_iter().map(bias).collect() }
    }

    /// Gives each light of `world` its bias (lights beyond those listed keep theirs).
    pub fn apply(&self, world: &mut World) {
        let (sun, spots) = light_order(world);
        let pairs = sun.zip(self.sun).into_iter().chain(spots.into_iter().zip(self.spots.iter().copied()));
        for (e, b) in pairs.collect::<Vec<_>>() {
            world.entity_mut(e).insert(b);
        }
    }

    /// The biases as JSON text.
    pub fn to_json(&self) -> String {
        let doc = json!({
            "about": "shadow biases in shadow-map texels per light, written by `umbra tune`",
            "sun": self.sun.as_ref().map(bias_json),
            "spots": self.spots.iter().map(bias_json).collect::<Vec<_>>(),
        });
        serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n"
    }

    /// Reads biases from JSON text.
    pub fn from_json(text: &str) -> Result<LightBiases, String> {
        let doc: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
        let sun = match doc.get("sun") {
            None | Some(Value::Null) => None,
            Some(v) => Some(bias_from(v, "sun")?),
        };
        let spots = match doc.get("spots") {
            None => Vec::new(),
            Some(Value::Array(list)) => list
                .iter()
                .enumerate()
                .map(|(i, v)| bias_from(v, &format!("spot {}", i + 1)))
                .collect::<Result<_, _>>()?,
            Some(_) => return Err("`spots` must be a list".into()),
        };
        Ok(LightBiases { sun, spots })
    }

    /// Reads a bias file.
    pub fn load(path: &Path) -> Result<LightBiases, BiasFileError> {
        let fail = |problem: String| BiasFileError { path: path.display().to_string(), problem };
        let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read it: {e}")))?;
        LightBiases::from_json(&text).map_err(fail)
    }

    /// Writes a bias file, whole or not at all.
    pub fn save(&self, path: &Path) -> Result<(), BiasFileError> {
        let fail = |problem: String| BiasFileError { path: path.display().to_string(), problem };
        let tmp = path.with_extension("json.partial");
        std::fs::write(&tmp, self.to_json()).map_err(|e| fail(e.to_string()))?;
        std::fs::rename(&tmp, path).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            fail(e.to_string())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn biases_survive_a_round_trip_and_bad_files_are_named() {
        let b = LightBiases {
            sun: Some(ShadowBias { constant: 0.5, slope: 2.0, normal: 1.0 }),
            spots: vec![ShadowBias { constant: 1.0, slope: 0.0, normal: 0.25 }],
        };
        assert_eq!(LightBiases::from_json(&b.to_json()), Ok(b));
        assert!(LightBiases::from_json("{").unwrap_err().contains("not JSON"));
        let negative = r#"{"sun": {"constant": -1, "slope": 0, "normal": 0}}"#;
        assert!(LightBiases::from_json(negative).unwrap_err().contains("sun: `constant` = -1"));
        let missing = r#"{"spots": [{"constant": 1, "slope": 1}]}"#;
        assert!(LightBiases::from_json(missing).unwrap_err().contains("spot 1: `normal` must be a number"));
        let err = LightBiases::load(Path::new("no/such/biases.json")).unwrap_err().to_string();
        assert!(err.starts_with("no/such/biases.json: cannot read it"), "{err}");
    }
}
