//! The figure of each metric a sweep asks for, the one a person wants: a map when two
//! parameters span a grid, a histogram when parameters are drawn at random (Monte Carlo, Latin
//! hypercube), lines over the first varied parameter otherwise (one per value of the others).

use super::Row;
use super::file::Plan;
use super::sample::Axis;
use crate::docs::{Figure, Map, Series, render_map_png, render_png};
use crate::model::units::display_of;

/// Most lines in one figure; more combinations of the other parameters are left out (said in
/// the title).
const MAX_LINES: usize = 10;

fn label(name: &str, unit: &'static str) -> String {
    let unit = display_of(unit).0;
    if unit.is_empty() {
        name.to_string()
    } else {
        format!("{name} [{unit}]")
    }
}

/// The figures of the sweep's metrics, as (file name, PNG bytes); none for a single run.
pub fn figures(plan: &Plan, rows: &[Row]) -> Result<Vec<(String, Vec<u8>)>, String> {
    let mut by_run: Vec<Option<&Row>> = vec![None; plan.runs()];
    for r in rows {
        if let Some(slot) = by_run.get_mut(r.run) {
            *slot = Some(r);
        }
    }
    let random = plan
        .design
        .axes
        .iter()
        .any(|a| matches!(a, Axis::Random(_)));
    let varied: Vec<usize> = (plan.design.axes.iter().enumerate())
        .filter(|(_, a)| matches!(a, Axis::Values(v) if v.len() > 1))
        .map(|(i, _)| i)
        .collect();
    let metric = |r: Option<&Row>, k: usize| {
        r.and_then(|r| r.metrics.get(k).copied())
            .unwrap_or(f64::NAN)
    };
    let mut out = Vec::new();
    for (k, m) in plan.metrics.iter().enumerate() {
        let file = format!(
            "{}.png",
            m.name.replace(
                |c: char| !c.is_ascii_alphanumeric() && c != '_' && c != '-',
                "_"
            )
        );
        let m_label = label(&m.name, m.unit);
        let mf = display_of(m.unit).1;
        let metric = |r: Option<&Row>, k: usize| metric(r, k) * mf;
        if random {
            let values: Vec<f64> = by_run
                .iter()
                .map(|r| metric(*r, k))
                .filter(|x| x.is_finite())
                .collect();
            if values.is_empty() {
                continue;
            }
            out.push((
                file,
                render_png(&histogram(plan, &m_label, display_of(m.unit).0, &values))?,
            ));
        } else if varied.len() == 2 {
            let (a, b) = (varied[0], varied[1]);
            let (Axis::Values(xs), Axis::Values(ys)) = (&plan.design.axes[a], &plan.design.axes[b])
            else {
                unreachable!("varied axes have values")
            };
            // runs: the earlier axis slower; the others have one value
            let z = (0..ys.len())
                .map(|j| {
                    (0..xs.len())
                        .map(|i| metric(by_run[i * ys.len() + j], k))
                        .collect()
                })
                .collect();
            let map = Map {
                title: format!(
                    "{}: {} over {} and {}",
                    plan.model, m.name, plan.swept[a].name, plan.swept[b].name
                ),
                x_label: label(&plan.swept[a].name, plan.swept[a].unit),
                y_label: label(&plan.swept[b].name, plan.swept[b].unit),
                z_label: m_label,
                xs: xs
                    .iter()
                    .map(|x| x * display_of(plan.swept[a].unit).1)
                    .collect(),
                ys: ys
                    .iter()
                    .map(|y| y * display_of(plan.swept[b].unit).1)
                    .collect(),
                z,
            };
            if map.z.iter().flatten().any(|z: &f64| z.is_finite()) {
                out.push((file, render_map_png(&map)?));
            }
        } else if let Some(&a) = varied.first() {
            // lines over axis a, one per combination of the other varied axes
            let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
            for (run, row) in by_run.iter().enumerate() {
                let p = plan.design.point(run);
                let key: Vec<String> = (varied.iter().filter(|&&i| i != a))
                    .map(|&i| {
                        let (u, f) = display_of(plan.swept[i].unit);
                        format!(
                            "{} = {} {u}",
                            plan.swept[i].name,
                            crate::docs::number(p[i] * f, 4)
                        )
                        .trim_end()
                        .to_string()
                    })
                    .collect();
                let key = key.join(", ");
                let pt = (p[a] * display_of(plan.swept[a].unit).1, metric(*row, k));
                match series.iter_mut().find(|s| s.0 == key) {
                    Some(s) => s.1.push(pt),
                    None => series.push((key, vec![pt])),
                }
            }
            let total = series.len();
            series.truncate(MAX_LINES);
            let title = if total > MAX_LINES {
                format!(
                    "{}: {} over {} (the first {MAX_LINES} of {total} lines)",
                    plan.model, m.name, plan.swept[a].name
                )
            } else {
                format!("{}: {} over {}", plan.model, m.name, plan.swept[a].name)
            };
            let mut fig = Figure::lines(
                &file,
                title,
                &label(&plan.swept[a].name, plan.swept[a].unit),
                &m_label,
                series.into_iter().map(|(l, p)| Series::new(l, p)).collect(),
                "",
            );
            fig.markers = true;
            if fig
                .series
                .iter()
                .flat_map(|s| &s.points)
                .any(|p| p.1.is_finite())
            {
                out.push((file, render_png(&fig)?));
            }
        }
    }
    Ok(out)
}

/// A histogram of `values` (in `unit`) as a step line: 2·∛n bins (Rice's rule; 10 to 50),
/// counts per bin.
fn histogram(plan: &Plan, m_label: &str, unit: &str, values: &[f64]) -> Figure {
    let n = values.len();
    let bins = ((2.0 * (n as f64).cbrt()).round() as usize).clamp(10, 50);
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let mut hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if hi <= lo {
        hi = lo + if lo == 0.0 { 1.0 } else { lo.abs() * 1e-6 };
    }
    let width = (hi - lo) / bins as f64;
    let mut count = vec![0usize; bins];
    for &x in values {
        count[(((x - lo) / width) as usize).min(bins - 1)] += 1;
    }
    let mut pts = vec![(lo, 0.0)];
    for (i, &c) in count.iter().enumerate() {
        let (a, b) = (lo + i as f64 * width, lo + (i + 1) as f64 * width);
        pts.push((a, c as f64));
        pts.push((b, c as f64));
    }
    pts.push((hi, 0.0));
    let mean = values.iter().sum::<f64>() / n as f64;
    let sd =
        (values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n.max(2) - 1) as f64).sqrt();
    let mut series = vec![Series::new(m_label, pts)];
    let mut title = format!(
        "{}: {} runs, mean {} {unit}, standard deviation {} {unit}",
        plan.model,
        n,
        crate::docs::number(mean, 6),
        crate::docs::number(sd, 3)
    )
    .replace(" , ", ", ");
    if lo < 0.0 && hi > 0.0 {
        // a sign change matters (a force that must stay positive): the share below zero
        let below = values.iter().filter(|&&x| x < 0.0).count();
        title += &format!(
            ", {} % below 0",
            crate::docs::number(100.0 * below as f64 / n as f64, 3)
        );
        let top = count.iter().copied().max().unwrap_or(0) as f64;
        series.push(Series::new("0", vec![(0.0, 0.0), (0.0, top)]));
    }
    Figure::lines("histogram.png", title, m_label, "runs", series, "")
}
