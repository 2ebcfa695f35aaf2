//! A map: a quantity over a grid of two parameters, each cell filled with the color of its value
//! (perceptually uniform, dark to light: viridis), the line where the value crosses zero, a color bar with its scale beside it, and
//! cells without a value (a run refused) grey. Drawn like the line plots (embedded DejaVu Sans,
//! supersampled, PNG through the `png` crate), deterministic.

use super::plot::{FIGURE_SIZE, SS, downsample, encode_png, err, font, fonts, tick_format};
use plotters::prelude::*;
use plotters::style::FontStyle;

/// A quantity `z` over the grid `xs` × `ys`: `z[j][i]` at `(xs[i], ys[j])`; a non-finite value
/// is a cell without one.
pub struct Map {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub z_label: String,
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    pub z: Vec<Vec<f64>>,
}

/// A chart on `area` with its margins left, right, top and bottom.
fn chart_on<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, plotters::coord::Shift>,
    [left, right, top, bottom]: [u32; 4],
) -> ChartBuilder<'a, 'a, DB> {
    let mut b = ChartBuilder::on(area);
    b.margin_left(left)
        .margin_right(right)
        .margin_top(top)
        .margin_bottom(bottom);
    b
}

/// Viridis at 9 stops (matplotlib's table), linear between them.
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 44, 122),
    (59, 81, 139),
    (44, 113, 142),
    (33, 144, 141),
    (39, 173, 129),
    (92, 200, 99),
    (170, 220, 50),
    (253, 231, 37),
];

/// The color of `t` in [0, 1].
fn viridis(t: f64) -> RGBColor {
    let t = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (t.floor() as usize).min(VIRIDIS.len() - 2);
    let f = t - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |p: u8, q: u8| (f64::from(p) + f * (f64::from(q) - f64::from(p))).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Cell edges of grid values: midway between neighbours, half a spacing beyond the ends.
fn edges(v: &[f64]) -> Vec<f64> {
    if v.len() == 1 {
        let d = if v[0] == 0.0 { 0.5 } else { 0.05 * v[0].abs() };
        return vec![v[0] - d, v[0] + d];
    }
    let mut e = vec![v[0] - 0.5 * (v[1] - v[0])];
    e.extend(v.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    e.push(v[v.len() - 1] + 0.5 * (v[v.len() - 1] - v[v.len() - 2]));
    e
}

/// The segments of the line z = 0 through the grid (marching squares, linear along the cell
/// edges between the grid points; a cell with a non-finite corner has none).
pub fn zero_contour(xs: &[f64], ys: &[f64], z: &[Vec<f64>]) -> Vec<[(f64, f64); 2]> {
    let mut out = Vec::new();
    for j in 0..ys.len().saturating_sub(1) {
        for i in 0..xs.len().saturating_sub(1) {
            // corners counter-clockwise from (i, j)
            let c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let v: Vec<f64> = c.iter().map(|&(a, b)| z[b][a]).collect();
            if v.iter().any(|x| !x.is_finite()) {
                continue;
            }
            let mut pts = Vec::new();
            for e in 0..4 {
                let (p, q) = (e, (e + 1) % 4);
                if (v[p] < 0.0) != (v[q] < 0.0) {
                    let t = v[p] / (v[p] - v[q]);
                    let (a, b) = ((xs[c[p].0], ys[c[p].1]), (xs[c[q].0], ys[c[q].1]));
                    pts.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
                }
            }
            for pair in pts.chunks_exact(2) {
                out.push([pair[0], pair[1]]);
            }
        }
    }
    out
}

/// The map as an 800×500 PNG.
pub fn render_map_png(m: &Map) -> Result<Vec<u8>, String> {
    fonts()?;
    let (w, h) = (FIGURE_SIZE.0 * SS, FIGURE_SIZE.1 * SS);
    let s = |v: u32| v * SS;
    let sf = |v: f64| v * f64::from(SS);
    let finite: Vec<f64> =
        m.z.iter()
            .flatten()
            .copied()
            .filter(|z| z.is_finite())
            .collect();
    if finite.is_empty() {
        return Err(format!("map {}: no value to draw", m.title));
    }
    let lo = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let mut hi = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if hi <= lo {
        hi = lo + if lo == 0.0 { 1.0 } else { lo.abs() * 1e-3 };
    }
    let (xe, ye) = (edges(&m.xs), edges(&m.ys));
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = root.margin(s(6), 0, 0, 0);
        let area = root
            .titled(&m.title, font(sf(18.0), FontStyle::Bold))
            .map_err(err)?;
        let (main, bar) = area.split_horizontally(s(640));
        let (x0, x1) = (xe[0].min(xe[xe.len() - 1]), xe[0].max(xe[xe.len() - 1]));
        let (y0, y1) = (ye[0].min(ye[ye.len() - 1]), ye[0].max(ye[ye.len() - 1]));
        let mut chart = chart_on(&main, [s(12), s(12), s(4), s(10)])
            .x_label_area_size(s(52))
            .y_label_area_size(s(84))
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        let (xf, yf) = (tick_format(x0, x1, 10), tick_format(y0, y1, 8));
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(m.x_label.as_str())
            .y_desc(m.y_label.as_str())
            .label_style(font(sf(14.0), FontStyle::Normal))
            .axis_desc_style(font(sf(15.0), FontStyle::Normal))
            .x_label_formatter(&xf)
            .y_label_formatter(&yf)
            .draw()
            .map_err(err)?;
        for (j, row) in m.z.iter().enumerate() {
            for (i, &z) in row.iter().enumerate() {
                let color = if z.is_finite() {
                    viridis((z - lo) / (hi - lo))
                } else {
                    RGBColor(200, 200, 200)
                };
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(xe[i], ye[j]), (xe[i + 1], ye[j + 1])],
                        color.filled(),
                    )))
                    .map_err(err)?;
            }
        }
        // where z crosses 0 (a lift-off boundary, a sign change of a force): a white line
        if lo < 0.0 && hi > 0.0 {
            for seg in zero_contour(&m.xs, &m.ys, &m.z) {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        seg.to_vec(),
                        WHITE.stroke_width(s(2)),
                    )))
                    .map_err(err)?;
            }
        }
        // the color bar: the scale of z
        let mut cb = chart_on(&bar, [s(4), s(20), s(4), s(62)])
            .y_label_area_size(s(96))
            .build_cartesian_2d(0.0..1.0, lo..hi)
            .map_err(err)?;
        let zf = tick_format(lo, hi, 8);
        cb.configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_desc(m.z_label.as_str())
            .label_style(font(sf(13.0), FontStyle::Normal))
            .axis_desc_style(font(sf(14.0), FontStyle::Normal))
            .y_label_formatter(&zf)
            .draw()
            .map_err(err)?;
        let n = 200;
        cb.draw_series((0..n).map(|k| {
            let a = lo + (hi - lo) * k as f64 / n as f64;
            let b = lo + (hi - lo) * (k + 1) as f64 / n as f64;
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                viridis((k as f64 + 0.5) / n as f64).filled(),
            )
        }))
        .map_err(err)?;
        if lo < 0.0 && hi > 0.0 {
            cb.draw_series(std::iter::once(PathElement::new(
                vec![(0.0, 0.0), (1.0, 0.0)],
                WHITE.stroke_width(s(2)),
            )))
            .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    encode_png(
        FIGURE_SIZE.0,
        FIGURE_SIZE.1,
        &downsample(
            &buf,
            FIGURE_SIZE.0 as usize,
            FIGURE_SIZE.1 as usize,
            SS as usize,
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_zero_line_of_a_plane_is_where_the_plane_is_zero() {
        // z = x + y - 1 on a 5 x 4 grid: every segment's ends lie on x + y = 1
        let xs: Vec<f64> = (0..5).map(|i| i as f64 * 0.25).collect();
        let ys: Vec<f64> = (0..4).map(|j| j as f64 / 3.0).collect();
        let z: Vec<Vec<f64>> = ys
            .iter()
            .map(|y| xs.iter().map(|x| x + y - 1.0).collect())
            .collect();
        let segs = zero_contour(&xs, &ys, &z);
        assert!(segs.len() >= 3, "{segs:?}");
        for s in &segs {
            for p in s {
                assert!((p.0 + p.1 - 1.0).abs() < 1e-12, "{p:?}");
            }
        }
        // no sign change, no line; a missing corner, no segment in its cells
        let pos: Vec<Vec<f64>> = z
            .iter()
            .map(|r| r.iter().map(|v| v + 10.0).collect())
            .collect();
        assert!(zero_contour(&xs, &ys, &pos).is_empty());
        let mut holed = z.clone();
        for r in &mut holed {
            for v in r.iter_mut() {
                *v = f64::NAN;
            }
        }
        assert!(zero_contour(&xs, &ys, &holed).is_empty());
        let png = render_map_png(&Map {
            title: "plane".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            z_label: "z".into(),
            xs,
            ys,
            z,
        })
        .expect("drawn");
        assert_eq!(&png[1..4], b"PNG");
    }
}
