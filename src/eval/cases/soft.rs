//! The failure cases of soft and filtered shadows: a wide filter darkening the lit slope it samples
//! (soft acne), a penumbra that stays one width however far its caster is (no contact
//! hardening), light leaking through two stacked casters from a variance map (light
//! bleeding), and light a filter takes from a far surface behind a shadowed receiver's end
//! (ledge bleeding).

use super::scenes::{add_box, ground, pole_scene, set_sun, sun_direction};
use super::{Score, measure_at, on_ground};
use crate::components::ShadowMethod;
use crate::eval::measure::{CaseScene, MeasureError, Measurer, SubjectId};
use crate::eval::metrics::rendered;
use crate::eval::truth;
use crate::settings::Settings;
use glam::Vec3;

const SOFT_ACNE: SubjectId = SubjectId::Case(CaseScene::SoftAcne);
const CONTACT_HARDENING: SubjectId = SubjectId::Case(CaseScene::ContactHardening);
const LIGHT_BLEEDING: SubjectId = SubjectId::Case(CaseScene::LightBleeding);
const LEDGE_BLEEDING: SubjectId = SubjectId::Case(CaseScene::LedgeBleeding);

/// Shares of light are scored in thousandths: `hits / of` is their mean.
const STEPS: f64 = 1000.0;

/// Adds one pixel's share `share` (clamped to 0..1) to a mean kept in thousandths.
fn add_share(score: &mut Score, share: f32) {
    score.of += STEPS as u64;
    score.hits += (share.clamp(0.0, 1.0) as f64 * STEPS).round() as u64;
}

/// A wide filter compares depths up to 2.5 texels from its centre; on a plane the light meets at
/// a slant those depths differ from the centre's by more than the bias, so without the receiver
/// plane a lit surface partly shadows itself. Nothing stands on the plane: every pixel the sun
/// reaches is truly lit, and any darkness is false.
pub fn soft_acne(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let view = (Vec3::new(0.0, 5.0, 10.0), Vec3::new(0.0, 0.0, -2.0));
    let settings = settings.clone().with(|s| s.shadow.method = ShadowMethod::Pcf5);
    m.subject(SOFT_ACNE, &settings, |s| ground(s, 80.0, true, Vec3::NEG_Y, view))?;
    let mut score = Score::default();
    for elevation in [10.0, 20.0, 35.0, 60.0] {
        let measured =
            measure_at(m, SOFT_ACNE, &format!("{elevation}"), |app| set_sun(app, sun_direction(elevation, 30.0)))?;
        for i in (0..measured.frame.position.len()).filter(|&i| on_ground(&measured)(i)) {
            if let Some(r) = rendered(&measured.frame, 0, i) {
                add_share(&mut score, 1.0 - r);
            }
        }
    }
    Ok(score)
}

/// Rays over the spot's disc for this case's own soft truth (the cases' measurer casts none).
const SOFT_RAYS: usize = 64;

/// Partly lit: neither fully lit nor fully dark.
fn partial(v: f32) -> bool {
    (0.05..0.95).contains(&v)
}

/// A 10 cm spot throws a 2.5 m pole's shadow along the ground, its penumbra growing from nothing
/// at the pole's foot to about 20 cm at the tip. Over the ground round the shadow, a pixel is
/// wrong where PCSS draws a penumbra the soft truth does not have, or misses one it has; the
/// score is the share of wrong pixels among those partly lit in either.
pub fn contact_hardening(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let settings = settings.clone().with(|s| s.shadow.method = ShadowMethod::Pcss);
    m.subject(CONTACT_HARDENING, &settings, pole_scene)?;
    let measured = measure_at(m, CONTACT_HARDENING, "pole", |_| {})?;
    let (app, _) = m.parts(CONTACT_HARDENING)?;
    let soft = truth::truth_of(&mut app.world, &measured.frame, truth::SizeOverride::default(), SOFT_RAYS);
    let along_shadow = |i: usize| {
        let p = measured.frame.position[i];
        on_ground(&measured)(i) && (0.15..2.4).contains(&p.x) && p.z.abs() < 0.4
    };
    let mut score = Score::default();
    for i in (0..soft[0].len()).filter(|&i| along_shadow(i)) {
        if let (Some(t), Some(r)) = (soft[0][i], rendered(&measured.frame, 0, i)) {
            let (want, got) = (partial(t.soft), partial(r));
            score.of += (want || got) as u64;
            score.hits += (want != got) as u64;
        }
    }
    Ok(score)
}

/// Visibility above which a pixel the truth has in shadow shows leaked light.
const LEAK: f32 = 0.05;

/// Two plates, one 1.5 m and one 0.5 m up, throw their shadows onto the same strip of ground
/// under a sun 45° up; the high one covers only half of it, so in the map its edge lies over the
/// low plate. A variance map blurred across that edge holds a mix of the two plates' depths whose
/// variance is large next to the ground's distance behind them, and Chebyshev's bound lets up to
/// a quarter of the light through where the truth has shadow. The score is the share of the
/// shadowed ground across that edge showing any light, under the settings' method where it is a
/// moment method and VSM otherwise.
pub fn light_bleeding(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let method = if settings.shadow.method.moments() { settings.shadow.method } else { ShadowMethod::Vsm };
    let settings = settings.clone().with(|s| s.shadow.method = method);
    let view = (Vec3::new(0.0, 3.0, 0.6), Vec3::new(0.0, 0.0, 0.5));
    m.subject(LIGHT_BLEEDING, &settings, |s| {
        let mut app = ground(s, 40.0, false, Vec3::new(0.0, -1.0, 1.0).normalize(), view)?;
        add_box(&mut app, Vec3::new(-0.75, 1.5, -1.0), Vec3::new(0.75, 0.01, 0.25));
        add_box(&mut app, Vec3::new(0.0, 0.5, 0.0), Vec3::new(1.0, 0.01, 0.25));
        Ok(app)
    })?;
    let measured = measure_at(m, LIGHT_BLEEDING, "stacked", |_| {})?;
    let across_edge = |i: usize| {
        let p = measured.frame.position[i];
        on_ground(&measured)(i) && p.x.abs() < 0.15 && (0.32..0.68).contains(&p.z)
    };
    let mut score = Score::default();
    for (i, t) in measured.truth[0].iter().enumerate() {
        if let (Some(t), Some(r), true) = (t, rendered(&measured.frame, 0, i), across_edge(i))
            && !t.lit
        {
            score.of += 1;
            score.hits += (r > LEAK) as u64;
        }
    }
    Ok(score)
}

/// The ledge-bleeding case's sun: 20° up, shining along +Z.
const LEDGE_SUN_ELEVATION: f32 = 20.0;
/// Height of the plate's top face, whose edge at z = 0 throws the shadow's edge.
const PLATE_TOP: f32 = 1.31;
/// Height of the ledge's top face.
const LEDGE_TOP: f32 = 1.0;

/// How far along +Z the plate's shadow edge falls on the ledge, and so where the ledge ends.
fn ledge_end() -> f32 {
    (PLATE_TOP - LEDGE_TOP) / LEDGE_SUN_ELEVATION.to_radians().tan()
}

/// A ledge 1 m up ends exactly where a plate 31 cm above it throws its shadow's edge, under a sun
/// 20° up; the ground lies a metre below. In the map, the plate's edge borders the ground, far
/// behind the ledge: a filter at the ledge's shadowed end mixes the plate's depth with the
/// ground's. Filtering the comparisons lets in the ground's share of light (PCF); Chebyshev's
/// bound on plain depths more; a positive exponential warp alone (EVSM2) all of it, since the far
/// ground's huge warped depth outweighs the plate's in the mean, while EVSM's negative warp,
/// dominated by the plate, keeps it near the ground's share. The score is the mean false light
/// on the ledge's truly shadowed top within 10 cm of its end, under the settings' own method.
pub fn ledge_bleeding(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let end = ledge_end();
    let view = (Vec3::new(0.0, 1.5, end + 0.5), Vec3::new(0.0, LEDGE_TOP, end - 0.1));
    m.subject(LEDGE_BLEEDING, settings, |s| {
        let mut app = ground(s, 40.0, false, sun_direction(LEDGE_SUN_ELEVATION, 180.0), view)?;
        add_box(&mut app, Vec3::new(0.0, PLATE_TOP - 0.01, -0.5), Vec3::new(0.5, 0.01, 0.5));
        add_box(&mut app, Vec3::new(0.0, LEDGE_TOP - 0.01, (end - 1.5) / 2.0), Vec3::new(0.5, 0.01, (end + 1.5) / 2.0));
        Ok(app)
    })?;
    let measured = measure_at(m, LEDGE_BLEEDING, "ledge", |_| {})?;
    let on_ledge_end = |i: usize| {
        let p = measured.frame.position[i];
        measured.frame.covered(i)
            && (p.y - LEDGE_TOP).abs() < 1e-3
            && measured.frame.normal[i].y > 0.99
            && p.x.abs() < 0.3
            && (end - 0.1..end).contains(&p.z)
    };
    let mut score = Score::default();
    for (i, t) in measured.truth[0].iter().enumerate() {
        if let (Some(t), Some(r), true) = (t, rendered(&measured.frame, 0, i), on_ledge_end(i))
            && !t.lit
        {
            add_share(&mut score, r);
        }
    }
    Ok(score)
}
