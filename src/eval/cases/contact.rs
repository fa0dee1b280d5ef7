//! Where contact shadows fail. The failure case: the halo the march throws behind a thin object
//! that stands in front of a far surface. In the camera's depth the far surface's march passes
//! behind the object on screen; it counts as blocked only when the object is taken to be thicker
//! than the gap between them (the march's thickness), so a thickness too large draws a false
//! shadow along the object's outline on whatever lies behind it. And what the march cannot see
//! ([`contact_edge`]): a caster past the screen's edge.

use super::scenes::{add_box, ground, sun_direction};
use super::{Score, measure_at, misclassified, missing_shadow, on_ground};
use crate::eval::measure::{CaseScene, MeasureError, Measurer, SubjectId, place_camera};
use crate::settings::Settings;
use glam::Vec3;

const CONTACT_HALOS: SubjectId = SubjectId::Case(CaseScene::ContactHalos);
const CONTACT_EDGE: SubjectId = SubjectId::Case(CaseScene::ContactEdge);

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

/// What contact shadows miss at the screen's edge. A wall 4 cm thick, 1 m tall and wide, on the
/// ground under a sun 35° up from -x; a depth bias of 0.2 m along the light lifts the map's
/// shadow off the ground behind it for about 12 cm (the map holds the wall's sunlit face, 4 cm
/// in front of the one the ground meets), a gap only contact shadows close. Seen twice, contact
/// shadows on whatever `settings` say: whole (the wall in view), and from a camera whose top
/// edge cuts the ground 5 cm behind the wall, so the wall is off screen and the march from the
/// gap leaves the screen before it reaches it. Each score: the share of the true shadow in the
/// band 5 to 10 cm behind the wall rendered lit.
pub fn contact_edge(m: &mut Measurer<'_>, settings: &Settings) -> Result<[Score; 2], MeasureError> {
    let settings = settings.clone().with(|s| {
        s.shadow.contact_shadows = true;
        s.shadow.depth_bias_metres = s.shadow.depth_bias_metres.max(0.2);
    });
    let whole = (Vec3::new(2.6, 1.5, 0.0), Vec3::new(0.1, 0.3, 0.0));
    m.subject(CONTACT_EDGE, &settings, |s| {
        let mut app = ground(s, 40.0, true, sun_direction(35.0, 270.0), whole)?;
        add_box(&mut app, Vec3::new(0.0, 0.5, 0.0), Vec3::new(0.02, 0.5, 0.5));
        Ok(app)
    })?;
    // 1 m up and 1.5 m out from where its top edge meets the ground (x = 0.07), looking down at
    // that edge's depression (33.7°) plus half the 60° field of view.
    let cut = (Vec3::new(1.57, 1.0, 0.0), Vec3::new(1.57 - 1.0 / 63.7f32.to_radians().tan(), 0.0, 0.0));
    let mut out = [Score::default(); 2];
    for (score, (name, (eye, target))) in out.iter_mut().zip([("whole", whole), ("cut", cut)]) {
        let measured = measure_at(m, CONTACT_EDGE, name, |app| place_camera(&mut app.world, eye, target))?;
        let band = |i: usize| {
            let p = measured.frame.position[i];
            on_ground(&measured)(i) && (0.07..=0.12).contains(&p.x) && p.z.abs() < 0.45
        };
        *score = missing_shadow(&measured, 0, band);
    }
    Ok(out)
}
