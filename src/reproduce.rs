//! A window's state as a command line: each light's own settings by its name (`"spot 1=pcss"`),
//! read from and written as the options `--light-method`, `--light-bias`, `--light-size` and
//! `--no-light-shadow`, and [`command_line`], every option that rebuilds what the window shows
//! now, so `umbra render` draws the same picture headless.

use crate::components::{Camera, ContactShadows, ShadowBias, ShadowMap, ShadowMethod, Time, Transform};
use crate::light::{Kind, Light, light_list};
use crate::settings::{MAX_BIAS_SCALE, Settings};
use crate::{App, AppError};
use bevy_ecs::prelude::*;

pub use crate::settings::LightSetting;

/// Splits `"LIGHT=VALUE"` at its last `=`; `form` and `example` say what was wanted.
fn named<'a>(s: &'a str, form: &str, example: &str) -> Result<(String, &'a str), String> {
    let (light, value) = s.rsplit_once('=').ok_or(format!("`{s}` is not {form} (such as \"{example}\")"))?;
    Ok((light.trim().to_string(), value.trim()))
}

/// Reads `"LIGHT=METHOD"`.
pub fn parse_method(s: &str) -> Result<(String, LightSetting), String> {
    let (light, value) = named(s, "LIGHT=METHOD", "spot 1=pcss")?;
    Ok((light, LightSetting::Method(value.parse()?)))
}

/// Reads `"LIGHT=CONSTANT,SLOPE,NORMAL[,SCALE][,flat]"`: texels, then the multiplicative offset
/// (default 0), then `flat` to turn the receiver plane off.
pub fn parse_bias(s: &str) -> Result<(String, LightSetting), String> {
    let (light, value) = named(s, "LIGHT=CONSTANT,SLOPE,NORMAL", "spot 1=0.5,1,0.5")?;
    let why = || {
        let most = (ShadowBias::MAX_TEXELS, MAX_BIAS_SCALE);
        format!("`{value}` is not CONSTANT,SLOPE,NORMAL[,SCALE][,flat] (texels 0..{}, scale 0..{})", most.0, most.1)
    };
    let mut parts: Vec<&str> = value.split(',').map(str::trim).collect();
    let receiver_plane = parts.last() != Some(&"flat");
    if !receiver_plane {
        parts.pop();
    }
    let numbers: Vec<f32> = parts.iter().map(|p| p.parse::<f32>()).collect::<Result<_, _>>().map_err(|_| why())?;
    let bias = match numbers[..] {
        [constant, slope, normal] => ShadowBias { constant, slope, normal, scale: 0.0, receiver_plane },
        [constant, slope, normal, scale] => ShadowBias { constant, slope, normal, scale, receiver_plane },
        _ => return Err(why()),
    };
    if ![bias.constant, bias.slope, bias.normal].into_iter().all(ShadowBias::texels_ok)
        || !(0.0..=MAX_BIAS_SCALE).contains(&bias.scale)
    {
        return Err(why());
    }
    Ok((light, LightSetting::Bias(bias)))
}

/// Reads `"LIGHT=SIZE"`: degrees of disc radius for a sun (0..10), metres of radius for others (0..10).
pub fn parse_size(s: &str) -> Result<(String, LightSetting), String> {
    let (light, value) = named(s, "LIGHT=SIZE", "sun=0.5")?;
    match value.parse::<f32>() {
        Ok(x) if (0.0..=10.0).contains(&x) => Ok((light, LightSetting::Size(x))),
        _ => Err(format!("`{value}` is not a size: degrees for a sun, metres for other lights, 0 to 10")),
    }
}

/// Reads `"LIGHT=on"` or `"LIGHT=off"`: whether the light's shadow test adds contact shadows.
pub fn parse_contact(s: &str) -> Result<(String, LightSetting), String> {
    let (light, value) = named(s, "LIGHT=on|off", "spot 1=on")?;
    match value {
        "on" => Ok((light, LightSetting::Contact(true))),
        "off" => Ok((light, LightSetting::Contact(false))),
        _ => Err(format!("`{value}` is not on or off")),
    }
}

/// Reads a count of texels: a whole number, or one with K (x1024) or M (x1024²) after it.
pub fn parse_texels(s: &str) -> Result<u32, String> {
    let t = s.trim();
    let (digits, scale) = match t.char_indices().last() {
        Some((i, 'k' | 'K')) => (&t[..i], 1u64 << 10),
        Some((i, 'm' | 'M')) => (&t[..i], 1u64 << 20),
        _ => (t, 1),
    };
    digits
        .trim()
        .parse::<u64>()
        .ok()
        .and_then(|n| u32::try_from(n.checked_mul(scale)?).ok())
        .ok_or(format!("`{s}` is not a count of texels: give a whole number, or one with K or M (such as 4M)"))
}

/// The light called `name`; a name no light has is an error that lists the lights.
pub fn light_named(world: &mut World, name: &str) -> Result<Light, AppError> {
    let lights = light_list(world);
    lights.iter().find(|l| l.label.to_string() == name).cloned().ok_or_else(|| {
        let known: Vec<String> = lights.iter().map(|l| format!("`{}`", l.label)).collect();
        AppError::UnknownLight { name: name.to_string(), known: known.join(", ") }
    })
}

/// Gives each light named in `settings` its own setting, in order (a later one wins); a name no
/// light has is an error that lists the lights.
pub fn apply(world: &mut World, settings: &[(String, LightSetting)]) -> Result<(), AppError> {
    for (name, setting) in settings {
        let light = &light_named(world, name)?;
        let e = light.entity;
        match *setting {
            LightSetting::Method(m) => {
                world.entity_mut(e).insert(m);
            }
            LightSetting::Bias(b) => {
                world.entity_mut(e).insert(b);
            }
            LightSetting::NoShadow => {
                world.entity_mut(e).remove::<ShadowMap>();
            }
            LightSetting::Size(x) => light.kind.set_size(world, e, x),
            LightSetting::Contact(on) => {
                world.entity_mut(e).insert(ContactShadows(on));
            }
        }
    }
    Ok(())
}

/// A light's size as [`LightSetting::Size`] gives it (its kind's own units).
#[must_use]
pub fn size_of(light: &Light) -> f32 {
    light.kind.size_control().value
}

/// `args` as one line a shell reads back as them, each quoted where it needs it.
#[must_use]
pub fn shell_line(args: &[String]) -> String {
    args.iter().map(|a| quoted(a)).collect::<Vec<_>>().join(" ")
}

/// Quotes `s` for a shell when it needs it.
fn quoted(s: &str) -> String {
    if s.chars().all(|c| c.is_ascii_alphanumeric() || "-_.,/:=".contains(c)) {
        s.to_string()
    } else {
        format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
    }
}

/// The options that rebuild what `world` shows now: every setting that differs from the
/// defaults, each light's own settings where they differ from what those options alone would
/// build, the camera (`--eye`, `--target`) and the scene's time (`--time`). Read by `umbra
/// render` and `umbra play`; the per-light options need the same scene, so a scene that cannot
/// be built again (a file gone since) gives them without comparing.
pub fn command_line(world: &mut World) -> Vec<String> {
    let settings = Settings::from_world(world);
    let mut out = settings_options(&settings);
    let base = settings.clone().with(|s| {
        s.scene.light_settings = Vec::new();
        s.scene.biases = None;
    });
    let mut fresh = App::new(base).ok();
    let lights = light_list(world);
    let before = fresh.as_mut().map(|f| light_list(&f.world)).unwrap_or_default();
    let mut push = |flag: &str, value: String| out.extend([flag.to_string(), value]);
    for light in &lights {
        let was = before.iter().find(|b| b.label == light.label);
        let name = light.label.to_string();
        let own_method = world.get::<ShadowMethod>(light.entity).copied();
        if own_method.is_some() && own_method != was.map(|w| w.method) {
            push("--light-method", format!("{name}={}", light.method.name()));
        }
        if was.is_none_or(|w| w.bias != light.bias) {
            let b = light.bias;
            let flat = if b.receiver_plane { "" } else { ",flat" };
            push("--light-bias", format!("{name}={},{},{},{}{flat}", b.constant, b.slope, b.normal, b.scale));
        }
        if was.is_none_or(|w| size_of(w) != size_of(light)) {
            push("--light-size", format!("{name}={}", size_of(light)));
        }
        if was.is_none_or(|w| w.contact != light.contact) {
            push("--light-contact", format!("{name}={}", if light.contact { "on" } else { "off" }));
        }
        if !light.shadowed && was.is_none_or(|w| w.shadowed) {
            push("--no-light-shadow", name);
        }
    }
    let camera = world.query_filtered::<&Transform, With<Camera>>().iter(world).next().copied();
    if let Some(t) = camera {
        // A target far along the view keeps the direction's rounding far below a pixel.
        let (eye, target) = (t.translation, t.translation + t.forward() * 100.0);
        push("--eye", format!("{},{},{}", eye.x, eye.y, eye.z));
        push("--target", format!("{},{},{}", target.x, target.y, target.z));
    }
    push("--time", world.resource::<Time>().t.to_string());
    out
}

/// The options for every setting of `s` that differs from the defaults (per-light ones aside).
fn settings_options(s: &Settings) -> Vec<String> {
    let d = Settings::default();
    let mut out = Vec::new();
    let mut flag = |on: bool, name: &str| {
        if on {
            out.push(format!("--{name}"));
        }
    };
    flag(!s.shadow.enabled, "no-shadows");
    flag(s.view.cascade_debug, "cascade-debug");
    flag(s.shadow.planar_ground, "planar-ground");
    flag(!s.shadow.receiver_plane, "no-receiver-plane");
    flag(!s.maps.reuse_shadow_maps, "redraw-shadows");
    flag(!s.maps.instancing, "no-instancing");
    flag(s.maps.static_cache, "static-cache");
    flag(!s.maps.atlas_guard, "no-atlas-guard");
    flag(!s.maps.page_fallback, "no-page-fallback");
    flag(!s.maps.old_bounds, "no-old-bounds");
    flag(!s.scene.character, "no-character");
    flag(!s.view.ground_grid, "no-ground-grid");
    flag(s.view.light_volumes, "light-volumes");
    flag(s.shadow.contact_shadows, "contact-shadows");
    let mut value = |differs: bool, name: &str, v: String| {
        if differs {
            out.extend([format!("--{name}"), v]);
        }
    };
    value(s.maps.shadow_map_size != d.maps.shadow_map_size, "shadow-map-size", s.maps.shadow_map_size.to_string());
    value(s.maps.shadow_memory != d.maps.shadow_memory, "shadow-memory", s.maps.shadow_memory.to_string());
    value(s.maps.shadow_updates != d.maps.shadow_updates, "shadow-updates", s.maps.shadow_updates.to_string());
    value(s.maps.max_stale != d.maps.max_stale, "max-stale", s.maps.max_stale.to_string());
    value(s.maps.tile_hysteresis != d.maps.tile_hysteresis, "tile-hysteresis", s.maps.tile_hysteresis.to_string());
    value(
        s.shadow.shadow_strength != d.shadow.shadow_strength,
        "shadow-strength",
        s.shadow.shadow_strength.to_string(),
    );
    value(s.shadow.depth_bias != d.shadow.depth_bias, "depth-bias", s.shadow.depth_bias.to_string());
    value(s.shadow.slope_bias != d.shadow.slope_bias, "slope-bias", s.shadow.slope_bias.to_string());
    value(s.shadow.normal_bias != d.shadow.normal_bias, "normal-bias", s.shadow.normal_bias.to_string());
    value(s.shadow.bias_scale != d.shadow.bias_scale, "bias-scale", s.shadow.bias_scale.to_string());
    value(s.scene.cubes != d.scene.cubes, "cubes", s.scene.cubes.to_string());
    value(s.scene.lanterns != d.scene.lanterns, "lanterns", s.scene.lanterns.to_string());
    value(s.cascade.cascades != d.cascade.cascades, "cascades", s.cascade.cascades.to_string());
    value(s.cascade.split_lambda != d.cascade.split_lambda, "split-lambda", s.cascade.split_lambda.to_string());
    value(s.cascade.cascade_blend != d.cascade.cascade_blend, "cascade-blend", s.cascade.cascade_blend.to_string());
    value(
        s.cascade.shadow_distance != d.cascade.shadow_distance,
        "shadow-distance",
        s.cascade.shadow_distance.to_string(),
    );
    value(s.cascade.fit_mode != d.cascade.fit_mode, "fit", s.cascade.fit_mode.name().into());
    value(s.maps.sun_maps != d.maps.sun_maps, "sun-maps", s.maps.sun_maps.name().into());
    value(s.maps.light_maps != d.maps.light_maps, "light-maps", s.maps.light_maps.name().into());
    value(s.maps.page_bias != d.maps.page_bias, "page-bias", s.maps.page_bias.to_string());
    value(s.maps.page_memory != d.maps.page_memory, "page-memory", s.maps.page_memory.to_string());
    value(s.shadow.method != d.shadow.method, "method", s.shadow.method.name().into());
    value(s.maps.moment_blur != d.maps.moment_blur, "moment-blur", s.maps.moment_blur.to_string());
    value(s.shadow.light_bleeding != d.shadow.light_bleeding, "light-bleeding", s.shadow.light_bleeding.to_string());
    value(s.maps.moment_bits != d.maps.moment_bits, "moment-bits", s.maps.moment_bits.name().into());
    value(s.maps.moments_from != d.maps.moments_from, "moments-from", s.maps.moments_from.name().into());
    value(s.maps.moment_resolve != d.maps.moment_resolve, "moment-resolve", s.maps.moment_resolve.name().into());
    value(s.maps.moment_samples != d.maps.moment_samples, "moment-samples", s.maps.moment_samples.to_string());
    value(s.shadow.contact_steps != d.shadow.contact_steps, "contact-steps", s.shadow.contact_steps.to_string());
    value(s.shadow.contact_length != d.shadow.contact_length, "contact-length", s.shadow.contact_length.to_string());
    value(
        s.shadow.contact_thickness != d.shadow.contact_thickness,
        "contact-thickness",
        s.shadow.contact_thickness.to_string(),
    );
    value(s.maps.shadow_depth != d.maps.shadow_depth, "shadow-depth", s.maps.shadow_depth.name().into());
    value(s.view.toon_bands != d.view.toon_bands, "toon", s.view.toon_bands.to_string());
    value(s.maps.caster_culling != d.maps.caster_culling, "culling", s.maps.caster_culling.name().into());
    value(s.maps.shadow_faces != d.maps.shadow_faces, "shadow-faces", s.maps.shadow_faces.name().into());
    value(s.maps.tile_sizes != d.maps.tile_sizes, "tile-sizes", s.maps.tile_sizes.name().into());
    value(s.scene.exposure != d.scene.exposure, "exposure", s.scene.exposure.to_string());
    if let Some(light) = &s.view.texel_density {
        value(true, "texel-density", light.clone());
    }
    if let Some(p) = &s.scene.model {
        value(true, "model", p.display().to_string());
    }
    if let Some(p) = &s.scene.file {
        value(true, "scene", p.display().to_string());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texel_counts_take_k_and_m_and_refuse_the_rest() {
        assert_eq!(parse_texels("4096"), Ok(4096));
        assert_eq!(parse_texels("4M"), Ok(4 << 20));
        assert_eq!(parse_texels(" 16k "), Ok(16 << 10));
        assert_eq!(parse_texels("0"), Ok(0));
        for bad in ["", "M", "-1", "1.5M", "4G", "5000M", "nan"] {
            assert!(parse_texels(bad).unwrap_err().contains("count of texels"), "{bad}");
        }
    }

    #[test]
    fn light_options_read_what_they_write_and_name_what_is_wrong() {
        assert_eq!(parse_method("spot 1=pcss"), Ok(("spot 1".into(), LightSetting::Method(ShadowMethod::Pcss))));
        let bias = ShadowBias { constant: 1.5, slope: 0.0, normal: 2.0, scale: 0.05, receiver_plane: false };
        assert_eq!(parse_bias("sun=1.5,0,2,0.05,flat"), Ok(("sun".into(), LightSetting::Bias(bias))));
        let plain = ShadowBias { scale: 0.0, receiver_plane: true, ..bias };
        assert_eq!(parse_bias(" sun = 1.5, 0, 2 "), Ok(("sun".into(), LightSetting::Bias(plain))));
        assert_eq!(parse_size("point 1=0.25"), Ok(("point 1".into(), LightSetting::Size(0.25))));
        for bad in [
            "sun",
            "sun=1,2",
            "sun=1,2,3,4,5",
            "sun=a,b,c",
            "sun=1,2,-3",
            "sun=1,2,3,0.9",
            "sun=NaN,1,1",
            "sun=1,1,1,flat,flat",
        ] {
            assert!(parse_bias(bad).is_err(), "{bad}");
        }
        for bad in ["sun=-1", "sun=11", "sun=inf", "sun=NaN", "sun="] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
        assert!(parse_method("sun=blur").unwrap_err().contains("not a shadow method"));
        assert_eq!(quoted("spot 1=pcss"), "\"spot 1=pcss\"");
        assert_eq!(quoted("1.5,2,3"), "1.5,2,3");
    }

    #[test]
    fn the_default_scene_needs_only_its_camera_and_time() {
        let mut app = App::new(Settings::default()).unwrap();
        app.set_time(2.0);
        let line = command_line(&mut app.world);
        assert_eq!(line.iter().filter(|a| a.starts_with("--")).collect::<Vec<_>>(), ["--eye", "--target", "--time"]);
        assert_eq!(line.last().map(String::as_str), Some("2"));
    }

    #[test]
    fn changed_lights_and_settings_are_written() {
        let mut app = App::new(Settings::default().with(|s| {
            s.cascade.cascades = 2;
            s.shadow.method = ShadowMethod::Pcf5;
        }))
        .unwrap();
        let lights = light_list(&app.world);
        let own = [
            ("spot 1".to_string(), LightSetting::Method(ShadowMethod::Vsm)),
            ("sun".to_string(), LightSetting::Bias(ShadowBias { constant: 2.0, ..Default::default() })),
            ("point 1".to_string(), LightSetting::Size(0.3)),
            ("spot 2".to_string(), LightSetting::NoShadow),
        ];
        apply(&mut app.world, &own).unwrap();
        assert!(app.world.get::<ShadowMap>(lights[2].entity).is_none());
        let line = shell_line(&command_line(&mut app.world));
        for part in [
            "--cascades 2",
            "--method pcf5",
            "--light-method \"spot 1=vsm\"",
            "--light-bias sun=2,0.5,0.5,0",
            "--light-size \"point 1=0.3\"",
            "--no-light-shadow \"spot 2\"",
        ] {
            assert!(line.contains(part), "{part} in {line}");
        }
        assert!(!line.contains("spot 1=0.1"), "unchanged sizes are not written: {line}");
        let unknown = apply(&mut app.world, &[("moon".into(), LightSetting::NoShadow)]).unwrap_err();
        assert!(unknown.to_string().contains("moon") && unknown.to_string().contains("`spot 1`"));
    }
}
