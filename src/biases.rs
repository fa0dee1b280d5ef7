//! Per-light shadow biases, as `umbra tune` finds them and writes them to a file, and as `play`,
//! `render` and `bench --cache` read them back (`--biases FILE`). The same file may also give
//! lights methods of their own (`"methods": {"spot 1": "pcss"}`). Lights are named as
//! [`crate::light::light_list`] names them ("sun", "spot 1", "point 1").

use crate::components::{ShadowBias, ShadowMethod};
use crate::light::light_list;
use crate::settings::MAX_BIAS_SCALE;
use bevy_ecs::prelude::*;
use serde_json::{Value, json};
use std::path::Path;

pub use crate::settings::LightBiases;

/// A bias file that could not be read, and why.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{path}: {problem}")]
pub struct BiasFileError {
    /// The file.
    pub path: String,
    /// What is wrong with it.
    pub problem: String,
}

fn bias_from(v: &Value, at: &str) -> Result<ShadowBias, String> {
    let field = |name: &str| -> Result<f32, String> {
        let x = v.get(name).and_then(Value::as_f64).ok_or(format!("{at}: `{name}` must be a number"))?;
        if ShadowBias::texels_ok(x as f32) {
            Ok(x as f32)
        } else {
            Err(format!("{at}: `{name}` = {x} must be between 0 and {} texels", ShadowBias::MAX_TEXELS))
        }
    };
    // The multiplicative offset is a share of the distance, not texels, and older files lack it.
    let scale = match v.get("scale") {
        None => 0.0,
        Some(x) => match x.as_f64() {
            Some(x) if (0.0..=MAX_BIAS_SCALE as f64).contains(&x) => x as f32,
            _ => return Err(format!("{at}: `scale` = {x} must be a share between 0 and {MAX_BIAS_SCALE}")),
        },
    };
    // So is the receiver plane, on unless the file says otherwise.
    let receiver_plane = match v.get("receiver_plane") {
        None => true,
        Some(Value::Bool(b)) => *b,
        Some(x) => return Err(format!("{at}: `receiver_plane` = {x} must be true or false")),
    };
    Ok(ShadowBias {
        constant: field("constant")?,
        slope: field("slope")?,
        normal: field("normal")?,
        scale,
        receiver_plane,
    })
}

impl LightBiases {
    /// The biases the lights of `world` have now (their own, or the settings').
    pub fn of(world: &mut World) -> LightBiases {
        LightBiases(light_list(world).into_iter().map(|l| (l.label.to_string(), l.bias)).collect())
    }

    /// The bias of the light called `name`, if listed.
    pub fn get(&self, name: &str) -> Option<ShadowBias> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, b)| *b)
    }

    /// Gives each light of `world` named here its bias (the others keep theirs).
    pub fn apply(&self, world: &mut World) {
        for light in light_list(world) {
            if let Some(b) = self.get(&light.label.to_string()) {
                world.entity_mut(light.entity).insert(b);
            }
        }
    }

    /// The biases as JSON text.
    pub fn to_json(&self) -> String {
        let lights: serde_json::Map<String, Value> = self
            .0
            .iter()
            .map(|(name, b)| {
                (
                    name.clone(),
                    json!({
                        "constant": b.constant,
                        "slope": b.slope,
                        "normal": b.normal,
                        "scale": b.scale,
                        "receiver_plane": b.receiver_plane,
                    }),
                )
            })
            .collect();
        let doc = json!({
            "about": "shadow biases per light, written by `umbra tune`: constant, slope and normal in shadow-map texels, scale a share of the distance to the light",
            "lights": lights,
        });
        serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n"
    }

    /// Reads biases from JSON text.
    pub fn from_json(text: &str) -> Result<LightBiases, String> {
        let doc: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
        let keys = doc.as_object().ok_or("a bias file is a JSON object")?.keys();
        if let Some(key) = keys.into_iter().find(|k| !["about", "lights", "methods"].contains(&k.as_str())) {
            return Err(format!(
                "unknown key `{key}`: a bias file lists `lights` (and their `methods`) by name (write it with `umbra tune`)"
            ));
        }
        match doc.get("lights") {
            None => Ok(LightBiases::default()),
            Some(Value::Object(lights)) => lights
                .iter()
                .map(|(name, v)| Ok((name.clone(), bias_from(v, name)?)))
                .collect::<Result<_, _>>()
                .map(LightBiases),
            Some(_) => Err("`lights` must be an object of light names and their biases".into()),
        }
    }

    /// Reads a bias file.
    pub fn load(path: &Path) -> Result<LightBiases, BiasFileError> {
        Ok(LightBiases::load_with_methods(path)?.0)
    }

    /// Reads a bias file with the methods it gives lights (none if it has no `methods`).
    pub fn load_with_methods(path: &Path) -> Result<(LightBiases, Vec<(String, ShadowMethod)>), BiasFileError> {
        let fail = |problem: String| BiasFileError { path: path.display().to_string(), problem };
        let text = std::fs::read_to_string(path).map_err(|e| fail(format!("cannot read it: {e}")))?;
        let biases = LightBiases::from_json(&text).map_err(fail)?;
        Ok((biases, methods_from_json(&text).map_err(fail)?))
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

/// The methods a bias file's `methods` object gives lights by name, in its order.
pub fn methods_from_json(text: &str) -> Result<Vec<(String, ShadowMethod)>, String> {
    let doc: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    match doc.get("methods") {
        None => Ok(Vec::new()),
        Some(Value::Object(methods)) => methods
            .iter()
            .map(|(name, v)| {
                let method = v.as_str().ok_or(format!("methods: `{name}` must be a method's name"))?;
                Ok((name.clone(), method.parse().map_err(|e| format!("methods: {name}: {e}"))?))
            })
            .collect(),
        Some(_) => Err("`methods` must be an object of light names and their methods".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn biases_survive_a_round_trip_and_bad_files_are_named() {
        let b = LightBiases(vec![
            (
                "point 1".into(),
                ShadowBias { constant: 1.0, slope: 0.0, normal: 0.25, scale: 0.0, receiver_plane: true },
            ),
            ("sun".into(), ShadowBias { constant: 0.5, slope: 2.0, normal: 1.0, scale: 0.02, receiver_plane: false }),
        ]);
        assert_eq!(LightBiases::from_json(&b.to_json()), Ok(b));
        assert!(LightBiases::from_json("{").unwrap_err().contains("not JSON"));
        let negative = r#"{"lights": {"sun": {"constant": -1, "slope": 0, "normal": 0}}}"#;
        assert!(LightBiases::from_json(negative).unwrap_err().contains("sun: `constant` = -1"));
        let missing = r#"{"lights": {"spot 1": {"constant": 1, "slope": 1}}}"#;
        assert!(LightBiases::from_json(missing).unwrap_err().contains("spot 1: `normal` must be a number"));
        let scale = r#"{"lights": {"sun": {"constant": 0, "slope": 0, "normal": 0, "scale": 2}}}"#;
        assert!(LightBiases::from_json(scale).unwrap_err().contains("sun: `scale` = 2 must be a share"));
        let plane = r#"{"lights": {"sun": {"constant": 0, "slope": 0, "normal": 0, "receiver_plane": 1}}}"#;
        assert!(LightBiases::from_json(plane).unwrap_err().contains("`receiver_plane` = 1 must be true or false"));
        let old = r#"{"lights": {"sun": {"constant": 0, "slope": 0, "normal": 0}}}"#;
        assert!(LightBiases::from_json(old).unwrap().0[0].1.receiver_plane, "a file without it keeps the plane");
        assert!(LightBiases::from_json(r#"{"lights": [1]}"#).unwrap_err().contains("must be an object"));
        let old = r#"{"sun": {"constant": 1, "slope": 1, "normal": 1}}"#;
        assert!(LightBiases::from_json(old).unwrap_err().contains("unknown key `sun`"));
        let with_methods = r#"{"lights": {}, "methods": {"spot 1": "pcss", "sun": "gauss5"}}"#;
        assert_eq!(LightBiases::from_json(with_methods), Ok(LightBiases::default()));
        assert_eq!(
            methods_from_json(with_methods),
            Ok(vec![("spot 1".into(), ShadowMethod::Pcss), ("sun".into(), ShadowMethod::Gauss5)])
        );
        assert!(methods_from_json(r#"{"methods": {"sun": "blurry"}}"#).unwrap_err().contains("sun: `blurry` is not"));
        assert!(methods_from_json(r#"{"methods": {"sun": 3}}"#).unwrap_err().contains("must be a method's name"));
        assert!(methods_from_json(r#"{"methods": []}"#).unwrap_err().contains("must be an object"));
        assert_eq!(methods_from_json(r#"{"lights": {}}"#), Ok(Vec::new()));
        let err = LightBiases::load(Path::new("no/such/biases.json")).unwrap_err().to_string();
        assert!(err.starts_with("no/such/biases.json: cannot read it"), "{err}");
    }
}
