//! `umbra gallery`: the same view under each kind of shadow the README shows, one picture each,
//! and a Markdown grid that labels every picture with its cost and error from a bench run's
//! `results.csv` (learners look before they read).

use super::config::Config;
use crate::components::ShadowMethod;
use crate::settings::{DEFAULT_TOON_BANDS, Settings};
use glam::Vec3;
use std::fmt::Write as _;

/// Where every picture is seen from (eye, target) and when: close enough to see an edge's
/// texels, with the sun's, both spots' and the lantern's shadows in view.
pub const VIEW: (Vec3, Vec3, f64) = (Vec3::new(3.0, 3.4, 6.4), Vec3::new(0.0, 0.0, 1.0), 5.0);

/// One picture of the gallery.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// Its caption's name.
    pub name: &'static str,
    /// Its file name, without `.png`.
    pub slug: &'static str,
    /// The bench configuration whose cost and error it is labelled with.
    pub config: Config,
    /// Toon bands (0: Phong).
    pub toon: u32,
}

impl Entry {
    /// `base` drawn as this entry draws it.
    #[must_use]
    pub fn settings(&self, base: &Settings) -> Settings {
        self.config.settings(base).with(|s| s.view.toon_bands = self.toon)
    }
}

/// Every picture, in the grid's order: the hard comparisons, the filters, the moment maps, the
/// source articles' own methods and toon shading.
#[must_use]
pub fn entries() -> Vec<Entry> {
    let d = Config::default_settings();
    let method = |name, slug, method| Entry { name, slug, config: Config { method, ..d }, toon: 0 };
    vec![
        method("hard (nearest texel)", "nearest", ShadowMethod::Nearest),
        method("bilinear (umbra's default)", "bilinear", ShadowMethod::Bilinear),
        method("PCF 5x5", "pcf5", ShadowMethod::Pcf5),
        method("Poisson PCF, 32 taps", "poisson32", ShadowMethod::Poisson32),
        method("PCSS", "pcss", ShadowMethod::Pcss),
        method("VSM", "vsm", ShadowMethod::Vsm),
        method("EVSM", "evsm", ShadowMethod::Evsm),
        method("EVSM2 (positive warp only)", "evsm2", ShadowMethod::Evsm2),
        method("MSM", "msm", ShadowMethod::Msm),
        method("MSM Hausdorff", "msm-hausdorff", ShadowMethod::MsmHausdorff),
        method("planar (stencil)", "planar", ShadowMethod::Planar),
        method("R16F radial distance", "r16f-radial", ShadowMethod::RadialR16f),
        Entry { name: "toon shading, 4 bands (bilinear)", slug: "toon", config: d, toon: DEFAULT_TOON_BANDS },
    ]
}

/// What a bench run measured of one configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// Shadow cost (maps and lookups), ms.
    pub cost_ms: f64,
    /// Misclassified pixels against the hard truth, percent.
    pub misclassified_pct: f64,
    /// Mean absolute error against the soft truth.
    pub mae_soft: f64,
}

/// The fields of one CSV line (a field in double quotes may hold commas).
fn fields(line: &str) -> Vec<String> {
    let (mut out, mut field, mut quoted) = (Vec::new(), String::new(), false);
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut field)),
            c => field.push(c),
        }
    }
    out.push(field);
    out
}

/// Each configuration's measurements in a bench's `results.csv` text, by its label; an error
/// names a missing column.
pub fn read_results(csv: &str) -> Result<Vec<(String, Measured)>, String> {
    let mut lines = csv.lines();
    let header = fields(lines.next().ok_or("the results file is empty")?);
    let column = |name: &str| header.iter().position(|h| h == name).ok_or(format!("no `{name}` column"));
    let (label, cost, wrong, soft) =
        (column("configuration")?, column("cost_ms")?, column("misclassified_pct")?, column("mae_soft")?);
    let number = |f: &[String], i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok()).unwrap_or(f64::NAN);
    Ok(lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f = fields(l);
            let m = Measured {
                cost_ms: number(&f, cost),
                misclassified_pct: number(&f, wrong),
                mae_soft: number(&f, soft),
            };
            (f.get(label).cloned().unwrap_or_default(), m)
        })
        .collect())
}

/// The Markdown grid: `columns` pictures a row, each captioned with its name and, where the
/// bench measured its configuration, its cost and errors; `dir` is put before each picture's file
/// name: where the pictures are as the Markdown's reader finds them (`""` beside it,
/// `"docs/gallery/"` from the README).
#[must_use]
pub fn markdown(entries: &[Entry], results: &[(String, Measured)], dir: &str, columns: usize) -> String {
    let columns = columns.max(1);
    let mut out = format!("|{}\n|{}\n", " |".repeat(columns), " --- |".repeat(columns));
    for row in entries.chunks(columns) {
        out.push('|');
        for e in row {
            let measured = results.iter().find(|(label, _)| *label == e.config.label()).map(|(_, m)| m);
            let numbers = measured.map_or("not in this bench run".to_string(), |m| {
                format!("{:.1} ms, {:.3} % wrong, soft error {:.4}", m.cost_ms, m.misclassified_pct, m.mae_soft)
            });
            let _ = write!(out, " ![{}]({dir}{}.png)<br>**{}**: {numbers} |", e.name, e.slug, e.name);
        }
        out += &" |".repeat(columns - row.len());
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_are_read_by_their_columns_and_quoted_labels_keep_their_commas() {
        let csv = "configuration,cost_ms,x,misclassified_pct,mae_soft\n\
                   2048 x4 stable pcss b0.5,706.6,1,0.071,0.0013\n\
                   \"bevy-like (2048 x4 gauss5, 0.02 m)\",163.1,2,0.121,0.0054\n";
        let r = read_results(csv).unwrap();
        assert_eq!(r.len(), 2);
        assert_eq!(
            r[0],
            (
                "2048 x4 stable pcss b0.5".into(),
                Measured { cost_ms: 706.6, misclassified_pct: 0.071, mae_soft: 0.0013 }
            )
        );
        assert_eq!(r[1].0, "bevy-like (2048 x4 gauss5, 0.02 m)");
        assert!(read_results("configuration,cost_ms\n").unwrap_err().contains("misclassified_pct"));
        assert!(read_results("").is_err());
    }

    #[test]
    fn the_grid_captions_every_picture_and_says_when_the_bench_lacks_one() {
        let e = entries();
        assert_eq!(e.len(), 13);
        let pcss = e.iter().find(|e| e.slug == "pcss").unwrap();
        let results =
            vec![(pcss.config.label(), Measured { cost_ms: 706.62, misclassified_pct: 0.0712, mae_soft: 0.00131 })];
        let md = markdown(&e, &results, "docs/gallery/", 4);
        assert_eq!(md.lines().count(), 2 + 4, "a header, a rule and four rows of four (the last one short)");
        assert!(md.contains("![PCSS](docs/gallery/pcss.png)<br>**PCSS**: 706.6 ms, 0.071 % wrong, soft error 0.0013"));
        assert_eq!(md.matches("not in this bench run").count(), 12);
        assert!(e.iter().all(|e| e.settings(&Settings::default()).validate().is_ok()));
        assert_eq!(e.iter().find(|e| e.slug == "toon").unwrap().settings(&Settings::default()).view.toon_bands, 4);
    }
}
