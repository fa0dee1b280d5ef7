//! The sweep's results on disk: a CSV table, a Markdown summary and the charts.

use super::cases::CASES;
use super::chart::{ChartError, Point, cost_axis, cost_chart, distance_chart, line_chart};
use super::config::Config;
use super::metrics::DISTANCE_BANDS;
use super::sweep::{Row, pareto};
use crate::settings::Settings;
use std::fmt::Write;
use std::path::Path;

/// Why the results could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ResultsError {
    /// A file could not be written.
    #[error("could not write {path}: {why}")]
    Write {
        /// Where.
        path: String,
        /// Why.
        why: String,
    },
    /// A chart could not be drawn.
    #[error(transparent)]
    Chart(#[from] ChartError),
}

fn write(path: &Path, text: &str) -> Result<(), ResultsError> {
    std::fs::write(path, text).map_err(|e| ResultsError::Write { path: path.display().to_string(), why: e.to_string() })
}

fn pct(x: f64) -> String {
    format!("{:.4}", 100.0 * x)
}

/// The table: one row per configuration, errors in percent.
pub fn csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "configuration,map_size,cascades,fit,sun_maps,light_maps,filter,bias,faces,depth,bias_scale,texel_bytes,cost_ms,shadow_ms,lookup_ms,min_shadow_ms,max_shadow_ms,\
         misclassified_pct,false_shadow_pct,false_lit_pct,mae_hard,mae_soft,edge_misclassified_pct,\
         texels_per_pixel_median,texels_per_pixel_p99",
    );
    let mut start = 0.0;
    for end in DISTANCE_BANDS {
        let _ = write!(out, ",misclassified_{start}_{end}m_pct");
        start = end;
    }
    for c in &CASES {
        let _ = write!(out, ",{}_pct", c.name);
    }
    out.push('\n');
    for r in rows {
        let (c, all) = (&r.config, r.scene_all());
        let s = c.settings(&Settings::default());
        // A label with a comma (the Bevy-like baseline's) is quoted, as CSV readers expect.
        let label = if c.label().contains(',') { format!("\"{}\"", c.label()) } else { c.label() };
        let _ = write!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{:.3},{:.3},{:.3},{:.3},{:.3},{},{},{},{:.5},{:.5},{}",
            label,
            s.maps.shadow_map_size,
            s.cascade.cascades,
            s.cascade.fit_mode.name(),
            s.maps.sun_maps.name(),
            s.maps.light_maps.name(),
            s.shadow.method.name(),
            s.shadow.depth_bias,
            s.maps.shadow_faces.name(),
            s.maps.shadow_depth.name(),
            s.shadow.bias_scale,
            c.texel_bytes(),
            r.cost.total_ms(),
            r.cost.shadow_ms,
            r.cost.lookup_ms,
            r.cost.range_ms.0,
            r.cost.range_ms.1,
            pct(all.all.misclassified()),
            pct(all.all.false_shadow_rate()),
            pct(all.all.false_lit_rate()),
            all.all.mae_hard(),
            all.all.mae_soft(),
            pct(all.edge.misclassified())
        );
        let quantile = |q| all.texels.quantile(q).map_or("nan".into(), |v| format!("{v:.3}"));
        let _ = write!(out, ",{},{}", quantile(0.5), quantile(0.99));
        for band in &all.bands {
            let _ = write!(out, ",{}", pct(band.misclassified()));
        }
        for s in &r.cases {
            let _ = write!(out, ",{}", s.map_or(String::new(), |s| pct(s.value())));
        }
        out.push('\n');
    }
    out
}

/// Each row's cost against its `error`, where it has one.
fn points(rows: &[Row], error: impl Fn(&Row) -> Option<f64>) -> Vec<Point> {
    let default = Config::default_settings();
    rows.iter()
        .filter_map(|r| error(r).map(|e| (r, e)))
        .map(|(r, error)| Point {
            cost: r.cost.total_ms(),
            error,
            label: r.config.short_label(),
            default: r.config == default,
            family: r.config.family(),
        })
        .collect()
}

fn front(points: &[Point]) -> Vec<usize> {
    pareto(&points.iter().map(|p| (p.cost, p.error.max(super::chart::FLOOR))).collect::<Vec<_>>())
}

/// Writes `results.csv`, `summary.md` and the charts into `dir`; `heading` says where and how the
/// numbers were taken, and every cost axis names `adapter`. Returns the summary.
pub fn write_all(rows: &[Row], dir: &Path, heading: &str, adapter: &str) -> Result<String, ResultsError> {
    std::fs::create_dir_all(dir)
        .map_err(|e| ResultsError::Write { path: dir.display().to_string(), why: e.to_string() })?;
    write(&dir.join("results.csv"), &csv(rows))?;
    let cost = cost_axis(adapter);
    let scene = points(rows, |r| Some(r.scene_all().all.misclassified()));
    let scene_front = front(&scene);
    cost_chart(
        &dir.join("scene"),
        "Sample scene: shadow cost against error (hard truth)",
        (&cost, "misclassified pixels (log; on the bottom line: none)"),
        &scene,
        &scene_front,
    )?;
    let edge = points(rows, |r| Some(r.scene_all().edge.misclassified()));
    cost_chart(
        &dir.join("scene-edge"),
        "Sample scene: shadow cost against error within 2 pixels of a true shadow edge",
        (&cost, "misclassified edge pixels (log)"),
        &edge,
        &front(&edge),
    )?;
    let soft = points(rows, |r| Some(r.scene_all().all.mae_soft()));
    cost_chart(
        &dir.join("scene-soft"),
        "Sample scene: shadow cost against mean error against the soft truth",
        (&cost, "mean absolute error, as a percentage of full light (log)"),
        &soft,
        &front(&soft),
    )?;
    for (k, case) in CASES.iter().enumerate() {
        let p = points(rows, |r| r.cases[k].map(|s| s.value()));
        if p.is_empty() {
            continue;
        }
        let title = format!("{}: {}", case.name, case.measures);
        cost_chart(
            &dir.join(format!("case-{}", case.name)),
            &title,
            (&cost, "error (log; on the bottom line: none)"),
            &p,
            &front(&p),
        )?;
    }
    // Error against distance for the default and every configuration on the scene's front.
    let default = Config::default_settings();
    let mut shown: Vec<&Row> = scene_front.iter().map(|&i| &rows[i]).collect();
    if let Some(d) = rows.iter().find(|r| r.config == default)
        && !shown.iter().any(|r| r.config == default)
    {
        shown.push(d);
    }
    let lines: Vec<(String, Vec<f64>)> = shown
        .iter()
        .map(|r| (r.config.short_label(), r.scene_all().bands.iter().map(|b| b.misclassified()).collect()))
        .collect();
    distance_chart(
        &dir.join("distance"),
        "Sample scene: error against distance (front and default)",
        &DISTANCE_BANDS,
        &lines,
    )?;
    let fits = fit_points(rows);
    if fits.len() > 1 {
        line_chart(
            &dir.join("fits"),
            "Cascade fits at the default map size: error against shimmer",
            (
                "ground points that flip per frame as the camera creeps (%)",
                "misclassified pixels of the sample scene (%)",
            ),
            &fits,
            &[],
        )?;
    }
    let summary = summary(rows, &scene_front, heading);
    write(&dir.join("summary.md"), &summary)?;
    Ok(summary)
}

/// The configurations that differ from the default only in how cascades are fitted, each as
/// (its fit, [(shimmer %, misclassified %)]): a chart of one point a fit, in the order swept.
fn fit_points(rows: &[Row]) -> Vec<(String, Vec<(f64, f64)>)> {
    let default = Config::default_settings();
    let Some(shimmer) = CASES.iter().position(|c| c.name == "shimmer") else { return Vec::new() };
    rows.iter()
        .filter(|r| r.config == Config { fit: r.config.fit, ..default })
        .filter_map(|r| {
            let at = (100.0 * r.cases[shimmer]?.value(), 100.0 * r.scene_all().all.misclassified());
            Some((r.config.fit.name().to_string(), vec![at]))
        })
        .collect()
}

/// Each method's error against the soft truth light by light, on the rows that differ from the
/// default only in how maps are sampled: where a filter helps (wide penumbrae) and where it blurs
/// more than the light does.
fn by_method(rows: &[Row]) -> String {
    let d = Config::default_settings();
    let same = |c: &Config| c.bevy_like || Config { method: d.method, receiver_plane: d.receiver_plane, ..*c } == d;
    let rows: Vec<&Row> = rows.iter().filter(|r| same(&r.config)).collect();
    let Some(first) = rows.first() else { return String::new() };
    let mut out = String::from(
        "\nMean absolute error against the soft truth light by light, method by method:\n\n| configuration |",
    );
    for name in &first.lights {
        let _ = write!(out, " {name} |");
    }
    out += &format!("\n| --- |{}\n", " --- |".repeat(first.lights.len()));
    for r in rows {
        let _ = write!(out, "| {} |", r.config.label());
        for report in &r.scene {
            let _ = write!(out, " {:.4} |", report.all.mae_soft());
        }
        out.push('\n');
    }
    out
}

/// How depth is kept: the default, the 16-bit depth map, depth in colour targets and the
/// multiplicative offset, with each one's memory, cost and error, and the precision case.
fn by_format(rows: &[Row]) -> String {
    let d = Config::default_settings();
    let precision = CASES.iter().position(|c| c.name == "precision");
    let about_depth = |c: &Config| {
        let method = if c.method.colour_depth_bits() > 0 { d.method } else { c.method };
        let changes_depth = *c == d || c.depth != d.depth || c.bias_scale != d.bias_scale || method != c.method;
        let rest = Config { depth: d.depth, bias_scale: d.bias_scale, bias: d.bias, method, ..*c };
        !c.bevy_like && changes_depth && rest == d
    };
    let mut out = String::from(
        "\nHow depth is kept: bytes a texel takes (depth map and colour map together), memory of \
         one layer, cost and error on the sample scene, and the precision case (worst wall):\n\n\
         | configuration | bytes per texel | MiB per layer | shadow cost ms | misclassified % | precision % |\n\
         | --- | --- | --- | --- | --- | --- |\n",
    );
    for r in rows.iter().filter(|r| about_depth(&r.config)) {
        let texels = (r.config.map_size as f64).powi(2);
        let _ = writeln!(
            out,
            "| {} | {} | {:.1} | {:.2} | {} | {} |",
            r.config.label(),
            r.config.texel_bytes(),
            r.config.texel_bytes() as f64 * texels / (1024.0 * 1024.0),
            r.cost.total_ms(),
            pct(r.scene_all().all.misclassified()),
            precision.and_then(|k| r.cases.get(k).copied().flatten()).map_or("-".into(), |s| pct(s.value()))
        );
    }
    out
}

/// Umbra's default against the Bevy-like baseline, measured in the same run.
fn against_bevy(rows: &[Row]) -> String {
    let default = Config::default_settings();
    let (Some(d), Some(b)) = (rows.iter().find(|r| r.config == default), rows.iter().find(|r| r.config.bevy_like))
    else {
        return String::new();
    };
    let (da, ba) = (d.scene_all(), b.scene_all());
    format!(
        "\nUmbra's default against the Bevy-like baseline (same views, same truth): shadow cost {:.2} ms \
         against {:.2} ms (x{:.2}); misclassified {} % against {} % (x{:.2}); within 2 pixels of a \
         true edge {} % against {} %; mean error against the soft truth {:.4} against {:.4} (x{:.2}).\n",
        d.cost.total_ms(),
        b.cost.total_ms(),
        d.cost.total_ms() / b.cost.total_ms(),
        pct(da.all.misclassified()),
        pct(ba.all.misclassified()),
        da.all.misclassified() / ba.all.misclassified(),
        pct(da.edge.misclassified()),
        pct(ba.edge.misclassified()),
        da.all.mae_soft(),
        ba.all.mae_soft(),
        da.all.mae_soft() / ba.all.mae_soft()
    )
}

/// `row`'s errors and texels per pixel light by light, headed `what`.
fn light_by_light(row: &Row, what: &str) -> String {
    let mut out = format!(
        "\n{what} light by light:\n\n| light | pixels it reaches | misclassified % | false shadow % | false lit % | \
         MAE hard | MAE soft | texels/pixel (median · p99) |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n"
    );
    for (name, report) in row.lights.iter().zip(&row.scene) {
        let t = report.all;
        let _ = writeln!(
            out,
            "| {name} | {} | {} | {} | {} | {:.4} | {:.4} | {} |",
            t.pixels,
            pct(t.misclassified()),
            pct(t.false_shadow_rate()),
            pct(t.false_lit_rate()),
            t.mae_hard(),
            t.mae_soft(),
            density(&report.texels)
        );
    }
    out
}

/// Texels per pixel as a table cell: the median and the 99th percentile, or a dash where none
/// were counted.
fn density(d: &super::texels::Density) -> String {
    match (d.quantile(0.5), d.quantile(0.99)) {
        (Some(median), Some(p99)) => format!("{median:.2} · {p99:.2}"),
        _ => "–".into(),
    }
}

/// The results in Markdown: every configuration, family by family and each by cost, the front (of
/// misclassified pixels against cost) marked, then each case.
pub fn summary(rows: &[Row], front: &[usize], heading: &str) -> String {
    let default = Config::default_settings();
    let mut out = format!("{heading}\n\n");
    out += "| family | configuration | shadow cost ms (maps + lookup) | misclassified % | edge misclassified % | false shadow % | false lit % | MAE hard | MAE soft | texels/pixel (median · p99) | front |\n";
    out += "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    // Grouped by family (in the order the families first appear), each by cost.
    let mut families: Vec<&str> = Vec::new();
    for r in rows {
        if !families.contains(&r.config.family()) {
            families.push(r.config.family());
        }
    }
    let family_rank = |i: usize| families.iter().position(|f| *f == rows[i].config.family()).unwrap_or(0);
    let mut order: Vec<usize> = (0..rows.len()).collect();
    order.sort_by(|&a, &b| {
        family_rank(a).cmp(&family_rank(b)).then(rows[a].cost.total_ms().total_cmp(&rows[b].cost.total_ms()))
    });
    for i in order {
        let (r, report) = (&rows[i], rows[i].scene_all());
        let all = report.all;
        let name = if r.config == default { format!("**{}** (default)", r.config.label()) } else { r.config.label() };
        let _ = writeln!(
            out,
            "| {} | {name} | {:.2} ({:.2} + {:.2}) | {} | {} | {} | {} | {:.4} | {:.4} | {} | {} |",
            r.config.family(),
            r.cost.total_ms(),
            r.cost.shadow_ms,
            r.cost.lookup_ms,
            pct(all.misclassified()),
            pct(report.edge.misclassified()),
            pct(all.false_shadow_rate()),
            pct(all.false_lit_rate()),
            all.mae_hard(),
            all.mae_soft(),
            density(&report.texels),
            if front.contains(&i) { "yes" } else { "" }
        );
    }
    out += &against_bevy(rows);
    // The default, and the default with virtual sun maps, then with every light's maps virtual,
    // light by light.
    let paged = Config { sun_maps: crate::settings::SunMaps::Virtual, ..default };
    let every = Config { light_maps: crate::settings::LightMaps::Virtual, ..paged };
    let each = [
        (default, "The default configuration"),
        (paged, "With the sun's maps virtual"),
        (every, "With every light's maps virtual"),
    ];
    for (config, what) in each {
        if let Some(d) = rows.iter().find(|r| r.config == config) {
            out += &light_by_light(d, what);
        }
    }
    out += &by_method(rows);
    out += &by_format(rows);
    out += "\n| case | what it counts | threshold % | default % | best % (configuration) |\n| --- | --- | --- | --- | --- |\n";
    for (k, case) in CASES.iter().enumerate() {
        let measured: Vec<(&Row, f64)> = rows.iter().filter_map(|r| Some((r, r.cases[k]?.value()))).collect();
        if measured.is_empty() {
            continue;
        }
        let at_default = measured.iter().find(|(r, _)| r.config == default).map_or(f64::NAN, |(_, v)| *v);
        let best = measured.iter().min_by(|a, b| a.1.total_cmp(&b.1));
        let best = best.map_or(String::new(), |(r, v)| format!("{} ({})", pct(*v), r.config.label()));
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {best} |",
            case.name,
            case.measures,
            pct(case.threshold),
            pct(at_default)
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::ShadowMethod;
    use crate::eval::cases::Score;
    use crate::shadow::FitMode;

    fn row(config: Config, shimmer_hits: u64) -> Row {
        let mut cases = vec![Some(Score::default()); CASES.len()];
        let k = CASES.iter().position(|c| c.name == "shimmer").unwrap();
        cases[k] = Some(Score { hits: shimmer_hits, of: 1000, garbage: 0 });
        Row { config, cost: Default::default(), scene: Vec::new(), lights: Vec::new(), cases }
    }

    #[test]
    fn the_fit_chart_takes_the_rows_that_differ_from_the_default_only_in_their_fit() {
        let d = Config::default_settings();
        let rows = [
            row(d, 0),
            row(Config { fit: FitMode::Tight, ..d }, 3),
            row(Config { method: ShadowMethod::Pcf3, ..d }, 7),
            row(Config { fit: FitMode::Tight, map_size: d.map_size * 2, ..d }, 9),
            row(Config { fit: FitMode::Sdsm, ..d }, 1),
        ];
        let fits = fit_points(&rows);
        let names: Vec<&str> = fits.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["stable", "tight", "sdsm"]);
        let shimmer: Vec<f64> = fits.iter().map(|(_, p)| p[0].0).collect();
        assert_eq!(shimmer, [0.0, 0.3, 0.1]);
        assert!(fit_points(&rows[2..4]).is_empty());
    }

    #[test]
    fn a_case_the_sweep_left_out_is_blank_in_the_table_and_missing_from_the_summary() {
        let d = Config::default_settings();
        let mut rows = [row(d, 2), row(Config { fit: FitMode::Tight, ..d }, 5)];
        let acne = CASES.iter().position(|c| c.name == "acne").unwrap();
        for r in &mut rows {
            r.cases[acne] = None;
        }
        let table = csv(&rows);
        let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
        let column = header.iter().position(|h| *h == "acne_pct").unwrap();
        let shimmer = header.iter().position(|h| *h == "shimmer_pct").unwrap();
        for line in table.lines().skip(1) {
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!((fields.len(), fields[column]), (header.len(), ""), "{line}");
            assert_ne!(fields[shimmer], "", "{line}");
        }
        let summary = summary(&rows, &[], "heading");
        assert!(!summary.contains("| acne |"), "a case nobody measured has no line");
        assert!(summary.contains("| shimmer |"));
        assert!(fit_points(&rows).iter().all(|(_, p)| p.len() == 1));
    }
}
