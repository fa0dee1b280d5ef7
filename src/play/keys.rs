//! What the keys do: the settings they change, the window's own switches, and movement.

use crate::Settings;
use crate::components::Key;
use crate::ui::Lab;
use winit::keyboard::KeyCode;

/// Changes the setting a key stands for (F: fit mode, C: cascade tints, 1-4: cascades, P:
/// filter, R: receiver plane, K: caster culling, T: toon shading, G: planar shadows on the
/// ground, L: light volumes, J: contact shadows); false for any other key.
pub fn change_setting(code: KeyCode, settings: &mut Settings) -> bool {
    match code {
        KeyCode::KeyF => settings.cascade.fit_mode = settings.cascade.fit_mode.next(),
        KeyCode::KeyC => settings.view.cascade_debug = !settings.view.cascade_debug,
        KeyCode::KeyP => settings.shadow.method = settings.shadow.method.next(),
        KeyCode::KeyR => settings.shadow.receiver_plane = !settings.shadow.receiver_plane,
        KeyCode::KeyK => settings.maps.caster_culling = settings.maps.caster_culling.next(),
        KeyCode::KeyG => settings.shadow.planar_ground = !settings.shadow.planar_ground,
        KeyCode::KeyL => settings.view.light_volumes = !settings.view.light_volumes,
        KeyCode::KeyJ => settings.shadow.contact_shadows = !settings.shadow.contact_shadows,
        KeyCode::KeyT => {
            settings.view.toon_bands =
                if settings.view.toon_bands == 0 { crate::settings::DEFAULT_TOON_BANDS } else { 0 }
        }
        KeyCode::Digit1 => settings.cascade.cascades = 1,
        KeyCode::Digit2 => settings.cascade.cascades = 2,
        KeyCode::Digit3 => settings.cascade.cascades = 3,
        KeyCode::Digit4 => settings.cascade.cascades = 4,
        _ => return false,
    }
    true
}

/// The shadow settings the keys change, in a few words.
pub fn settings_line(settings: &Settings) -> String {
    let tints = if settings.view.cascade_debug { ", tinted" } else { "" };
    let flat = if settings.shadow.receiver_plane { "" } else { " without receiver plane" };
    let culling = match settings.maps.caster_culling {
        crate::settings::CasterCulling::LightVolume => "",
        crate::settings::CasterCulling::CameraView => ", culling to the camera view",
    };
    let toon =
        if settings.view.toon_bands > 0 { format!(", toon {}", settings.view.toon_bands) } else { String::new() };
    let planar = if settings.shadow.planar_ground { ", planar ground" } else { "" };
    let contact = if settings.shadow.contact_shadows { ", contact shadows" } else { "" };
    format!(
        "{} cascades, {} fit, {} filter{flat}{culling}{tints}{toon}{planar}{contact}",
        settings.cascade.cascades,
        settings.cascade.fit_mode.name(),
        settings.shadow.method.name()
    )
}

/// The sample's key for a physical key, if it has one.
pub fn key_for(code: KeyCode) -> Option<Key> {
    Some(match code {
        KeyCode::KeyW | KeyCode::ArrowUp => Key::Forward,
        KeyCode::KeyS | KeyCode::ArrowDown => Key::Back,
        KeyCode::KeyA | KeyCode::ArrowLeft => Key::Left,
        KeyCode::KeyD | KeyCode::ArrowRight => Key::Right,
        KeyCode::KeyE | KeyCode::Space => Key::Up,
        KeyCode::KeyQ | KeyCode::ControlLeft => Key::Down,
        KeyCode::ShiftLeft | KeyCode::ShiftRight => Key::Fast,
        _ => return None,
    })
}

/// The texel-density view after `current` when B is pressed: off, then each of `lights` in turn,
/// then off again.
pub fn next_texel_view(current: &Option<String>, lights: &[String]) -> Option<String> {
    let next = match current {
        None => 0,
        Some(name) => lights.iter().position(|l| l == name).map_or(lights.len(), |i| i + 1),
    };
    lights.get(next).cloned()
}

/// Changes the window's own state a key stands for (Tab: panel, M: measure, N: measure when
/// still, X: overlay, H: hold the clock, O: next camera, V: shadow-map viewer, F12: screenshot);
/// false for any other key.
pub fn change_lab(code: KeyCode, lab: &mut Lab) -> bool {
    match code {
        KeyCode::Tab => lab.panel = !lab.panel,
        KeyCode::KeyM => lab.asked.measure = true,
        KeyCode::KeyN => lab.auto_measure = !lab.auto_measure,
        KeyCode::KeyX => lab.overlay = !lab.overlay,
        KeyCode::KeyH => lab.hold = !lab.hold,
        KeyCode::KeyO => lab.asked.camera = true,
        KeyCode::KeyV => lab.map_viewer = !lab.map_viewer,
        KeyCode::F12 => lab.asked.screenshot = true,
        _ => return false,
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::ShadowMethod;
    use crate::settings::CasterCulling;
    use crate::shadow::FitMode;

    #[test]
    fn setting_keys_toggle_and_choose_and_others_do_nothing() {
        let mut s = Settings::default();
        assert!(change_setting(KeyCode::KeyF, &mut s));
        assert_eq!(s.cascade.fit_mode, FitMode::Unsnapped);
        assert!(change_setting(KeyCode::KeyC, &mut s) && s.view.cascade_debug);
        assert!(change_setting(KeyCode::Digit2, &mut s));
        assert_eq!(s.cascade.cascades, 2);
        assert!(change_setting(KeyCode::KeyP, &mut s));
        assert_eq!(s.shadow.method, ShadowMethod::Pcf3);
        assert!(change_setting(KeyCode::KeyK, &mut s));
        assert_eq!(s.maps.caster_culling, CasterCulling::CameraView);
        assert_eq!(settings_line(&s), "2 cascades, unsnapped fit, pcf3 filter, culling to the camera view, tinted");
        assert!(change_setting(KeyCode::KeyR, &mut s) && !s.shadow.receiver_plane);
        assert!(change_setting(KeyCode::KeyT, &mut s) && s.view.toon_bands == crate::settings::DEFAULT_TOON_BANDS);
        assert!(change_setting(KeyCode::KeyT, &mut s) && s.view.toon_bands == 0);
        assert!(change_setting(KeyCode::KeyG, &mut s) && s.shadow.planar_ground);
        assert!(change_setting(KeyCode::KeyJ, &mut s) && s.shadow.contact_shadows);
        assert!(settings_line(&s).ends_with(", planar ground, contact shadows"));
        assert!(settings_line(&s).contains("pcf3 filter without receiver plane"));
        let before = s.clone();
        assert!(!change_setting(KeyCode::KeyW, &mut s));
        assert_eq!(s, before);
    }

    #[test]
    fn the_texel_view_steps_through_the_lights_and_back_to_the_shading() {
        let lights = ["sun".to_string(), "spot 1".to_string()];
        let mut view = None;
        let mut seen = Vec::new();
        for _ in 0..3 {
            view = next_texel_view(&view, &lights);
            seen.push(view.clone());
        }
        assert_eq!(seen, [Some("sun".into()), Some("spot 1".into()), None]);
        assert_eq!(next_texel_view(&Some("gone".into()), &lights), None, "a light no longer there: off");
        assert_eq!(next_texel_view(&None, &[]), None);
    }

    #[test]
    fn lab_keys_switch_and_ask_and_leave_the_settings_keys_alone() {
        let mut lab = Lab::default();
        assert!(change_lab(KeyCode::Tab, &mut lab) && lab.panel);
        assert!(change_lab(KeyCode::KeyM, &mut lab) && lab.asked.measure);
        assert!(change_lab(KeyCode::KeyH, &mut lab) && lab.hold);
        assert!(change_lab(KeyCode::F12, &mut lab) && lab.asked.screenshot);
        for code in [KeyCode::KeyP, KeyCode::KeyW, KeyCode::Digit1] {
            assert!(!change_lab(code, &mut lab), "{code:?} is not the window's");
        }
        let mut s = Settings::default();
        for code in [
            KeyCode::Tab,
            KeyCode::KeyM,
            KeyCode::KeyN,
            KeyCode::KeyX,
            KeyCode::KeyH,
            KeyCode::KeyO,
            KeyCode::KeyV,
            KeyCode::F12,
            KeyCode::KeyB,
        ] {
            assert!(!change_setting(code, &mut s), "{code:?} is taken twice");
            assert!(key_for(code).is_none(), "{code:?} moves the camera too");
        }
    }
}
