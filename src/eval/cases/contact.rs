//! The failure case of contact shadows: the halo the march throws behind a thin object that
//! stands in front of a far surface. In the camera's depth the far surface's march passes behind
//! the object on screen; it counts as blocked only when the object is taken to be thicker than
//! the gap between them (the march's thickness), so a thickness too large draws a false shadow
//! along the object's outline on whatever lies behind it.

use super::scenes::{add_box, ground, sun_direction};
use super::{Score, measure_at, misclassified, on_ground};
use crate::eval::measure::{CaseScene, MeasureError, Measurer, SubjectId};
use crate::settings::Settings;
use glam::Vec3;

const CONTACT_HALOS: SubjectId = SubjectId::Case(CaseScene::ContactHalos);

/// A 5 cm bar 1.2 m over the ground, 1.5 m from the camera, across the view of the ground 6 to
/// 12 m away; the sun low behind that ground, so the march from it climbs the screen into the
/// bar's image. The score: the share of truly lit ground rendered dark. Contact shadows are on
/// for every light here, whatever `settings` say: the case is what they would do.
pub fn contact_halos(m: &mut Measurer<'_>, settings: &Settings) -> Result<Score, MeasureError> {
    let settings = settings.clone().with(|s| s.shadow.contact_shadows = true);
    let view = (Vec3::new(0.0, 1.6, 6.0), Vec3::new(0.0, 0.0, -4.0));
    m.subject(CONTACT_HALOS, &settings, |s| {
        let mut app = ground(s, 60.0, false, sun_direction(30.0, 180.0), view)?;
        add_box(&mut app, Vec3::new(0.0, 1.2, 4.5), Vec3::new(2.0, 0.025, 0.025));
        Ok(app)
    })?;
    let measured = measure_at(m, CONTACT_HALOS, "bar", |_| {})?;
    let lit = |i: usize| measured.truth[0][i].is_some_and(|t| t.lit);
    Ok(misclassified(&measured, 0, |i| on_ground(&measured)(i) && lit(i)))
}
