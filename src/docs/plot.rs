//! Figures and the icon, drawn with plotters into an RGB buffer and encoded to PNG here.
//!
//! Text uses DejaVu Sans embedded by the `dejavu` crate, registered with plotters' `ab_glyph`
//! font table under a private family name: no system font, no fontconfig. The PNG encoder is
//! [`png`] below (plotters' own encoder only writes files), so the bytes depend on nothing but
//! the figure.

use super::Figure;
use plotters::coord::Shift;
use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{FontStyle, register_font};
use std::sync::OnceLock;

/// Width and height of a figure, pixels.
pub const FIGURE_SIZE: (u32, u32) = (800, 500);
/// Width and height of the icon, pixels.
pub const ICON_SIZE: u32 = 128;

/// Most labelled ticks on the x and y axes.
const X_TICKS: usize = 10;
const Y_TICKS: usize = 8;

/// Font family the embedded DejaVu Sans is registered under (private, so that another
/// registration of e.g. `sans-serif` cannot change these images).
const FAMILY: &str = "bindery-dejavu-sans";

/// Line colors (Tableau 10), in series order; the 11th series takes the first again.
const COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

pub(super) fn fonts() -> Result<(), String> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        register_font(FAMILY, FontStyle::Normal, dejavu::sans::regular())
            .map_err(|_| "DejaVu Sans: invalid font".to_string())?;
        register_font(FAMILY, FontStyle::Bold, dejavu::sans::bold())
            .map_err(|_| "DejaVu Sans Bold: invalid font".to_string())
    })
    .clone()
}

pub(super) fn font(size: f64, style: FontStyle) -> TextStyle<'static> {
    TextStyle::from(FontDesc::new(FontFamily::Name(FAMILY), size, style))
        .color(&RGBColor(30, 30, 30))
}

pub(super) fn err<E: std::fmt::Display>(e: E) -> String {
    format!("drawing: {e}")
}

/// Largest font size from `max` down to `min` at which `text` is at most `width` pixels wide.
pub(super) fn fit<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    width: u32,
    max: f64,
    min: f64,
    style: FontStyle,
) -> Result<f64, String> {
    let mut size = max;
    while size > min
        && area
            .estimate_text_size(text, &font(size, style))
            .map_err(err)?
            .0
            > width
    {
        size -= 1.0;
    }
    Ok(size)
}

/// Tick labels at the `n` key points plotters puts on `[lo, hi]` (steps 1, 2 or 5 × 10^k):
/// as many decimals as the step needs; scientific (`2.5e6`) from 1e6 up and for steps
/// below 1e-4; never "-0".
pub(super) fn tick_format(lo: f64, hi: f64, n: usize) -> impl Fn(&f64) -> String {
    let keys = RangedCoordf64::from(lo..hi).key_points(n);
    let step = match keys.as_slice() {
        [a, b, ..] => b - a,
        _ => (hi - lo).abs(),
    }
    .max(f64::MIN_POSITIVE);
    let step_exp = (step.log10() + 1e-9).floor();
    let scientific = lo.abs().max(hi.abs()) >= 1e6 || step < 1e-4;
    let decimals = (-step_exp).clamp(0.0, 12.0) as usize;
    move |&x| {
        if (x / step).abs() < 1e-9 {
            return if scientific {
                "0".into()
            } else {
                format!("{:.decimals$}", 0.0)
            };
        }
        if scientific {
            let digits = ((x.abs().log10() + 1e-9).floor() - step_exp).clamp(0.0, 12.0) as usize;
            format!("{x:.digits$e}")
        } else {
            format!("{x:.decimals$}")
        }
    }
}

/// `[lo, hi]` widened by `pad` of its span on both sides; a span of zero becomes one.
fn padded(lo: f64, hi: f64, pad: f64) -> (f64, f64) {
    let span = hi - lo;
    if span > 0.0 {
        (lo - pad * span, hi + pad * span)
    } else {
        let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        (lo - d, hi + d)
    }
}

/// The runs of finite points of a series (a non-finite point breaks the line).
fn segments(points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    points
        .split(|(x, y)| !(x.is_finite() && y.is_finite()))
        .filter(|s| !s.is_empty())
        .map(<[_]>::to_vec)
        .collect()
}

/// A polyline cut where it turns back on itself (the direction changes by more than 90° in
/// plot units `(sx, sy)` per data unit), the turning point in both pieces. The bitmap backend
/// fills a thick polyline as one polygon, and a path that retraces itself (a saddle going and
/// coming back, a force spike up and down) cancels out to a hollow double line.
fn unfolded(points: &[(f64, f64)], (sx, sy): (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let mut out = vec![];
    let mut piece: Vec<(f64, f64)> = vec![];
    let mut dir = (0.0, 0.0);
    for &p in points {
        if let Some(&q) = piece.last() {
            let d = ((p.0 - q.0) * sx, (p.1 - q.1) * sy);
            if d == (0.0, 0.0) {
                continue;
            }
            if d.0 * dir.0 + d.1 * dir.1 < 0.0 {
                out.push(std::mem::replace(&mut piece, vec![q]));
            }
            dir = d;
        }
        piece.push(p);
    }
    out.push(piece);
    out
}

/// Does the segment `a`–`b` touch the rectangle `[x0, x1] × [y0, y1]`? (Liang–Barsky)
fn segment_hits(a: (f64, f64), b: (f64, f64), (x0, x1, y0, y1): (f64, f64, f64, f64)) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x0),
        (dx, x1 - a.0),
        (-dy, a.1 - y0),
        (dy, y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    t0 <= t1
}

/// Where the legend goes: the first of the upper right, upper left, lower right and lower
/// left corners where a box of `(lw, lh)` (fractions of the plot) meets no line, if any.
fn free_corner(
    fig: &Figure,
    x: (f64, f64),
    y: (f64, f64),
    (lw, lh): (f64, f64),
) -> Option<SeriesLabelPosition> {
    let corners = [
        (
            SeriesLabelPosition::UpperRight,
            (1.0 - lw, 1.0, 1.0 - lh, 1.0),
        ),
        (SeriesLabelPosition::UpperLeft, (0.0, lw, 1.0 - lh, 1.0)),
        (SeriesLabelPosition::LowerRight, (1.0 - lw, 1.0, 0.0, lh)),
        (SeriesLabelPosition::LowerLeft, (0.0, lw, 0.0, lh)),
    ];
    let unit = |p: &(f64, f64)| ((p.0 - x.0) / (x.1 - x.0), (p.1 - y.0) / (y.1 - y.0));
    let hits = |rect| {
        fig.series
            .iter()
            .flat_map(|s| segments(&s.points))
            .any(|seg| match seg.as_slice() {
                [p] => segment_hits(unit(p), unit(p), rect),
                pts => pts
                    .windows(2)
                    .any(|w| segment_hits(unit(&w[0]), unit(&w[1]), rect)),
            })
    };
    corners
        .into_iter()
        .find(|(_, rect)| !hits(*rect))
        .map(|(pos, _)| pos)
}

/// Supersampling of figures: drawn at this multiple of [`FIGURE_SIZE`] and averaged down,
/// so lines are anti-aliased.
pub(super) const SS: u32 = 2;

/// An 800×500 PNG line plot of `fig`: title, light grid, axis labels, one color per series
/// and a legend when there is more than one (in a corner it leaves the lines visible, else
/// above them in extra headroom). Non-finite points break a line. With `equal_axes` one
/// unit is as long on both axes. Deterministic: same figure, same bytes.
pub fn render_png(fig: &Figure) -> Result<Vec<u8>, String> {
    encode_png(FIGURE_SIZE.0, FIGURE_SIZE.1, &draw_figure(fig)?)
}

/// A range of an axis, (low, high).
type Span = (f64, f64);

/// Axis ranges of a figure: its finite points' extent, padded.
fn ranges(fig: &Figure) -> Result<(Span, Span), String> {
    let finite = || {
        fig.series
            .iter()
            .flat_map(|s| &s.points)
            .filter(|(x, y)| x.is_finite() && y.is_finite())
    };
    if finite().next().is_none() {
        return Err(format!("figure {}: no finite point to plot", fig.file));
    }
    let min_max = |f: fn(&(f64, f64)) -> f64| {
        finite()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    };
    let (x_lo, x_hi) = min_max(|p| p.0);
    let (y_lo, y_hi) = min_max(|p| p.1);
    Ok((
        padded(
            x_lo,
            x_hi,
            if fig.equal_axes || fig.markers {
                0.05
            } else {
                0.0
            },
        ),
        padded(y_lo, y_hi, 0.05),
    ))
}

/// The pixels of [`render_png`]: RGB rows, top to bottom.
fn draw_figure(fig: &Figure) -> Result<Vec<u8>, String> {
    fonts()?;
    let (w, h) = (FIGURE_SIZE.0 * SS, FIGURE_SIZE.1 * SS);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        draw_chart(&root, fig, SS)?;
        root.present().map_err(err)?;
    }
    Ok(downsample(
        &buf,
        FIGURE_SIZE.0 as usize,
        FIGURE_SIZE.1 as usize,
        SS as usize,
    ))
}

/// The same figure as [`render_png`], as an SVG document of [`FIGURE_SIZE`] (vector lines,
/// text as text: the font is named "DejaVu Sans" with sans-serif as fallback).
/// Deterministic: same figure, same bytes.
pub fn render_svg(fig: &Figure) -> Result<String, String> {
    fonts()?;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, FIGURE_SIZE).into_drawing_area();
        draw_chart(&root, fig, 1)?;
        root.present().map_err(err)?;
    }
    Ok(out.replace(FAMILY, "DejaVu Sans, sans-serif"))
}

/// Draws `fig` on `root` (of [`FIGURE_SIZE`] times `scale` pixels): title, light grid, axis
/// labels, one color per series and a legend when there is more than one.
fn draw_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    scale: u32,
) -> Result<(), String> {
    let (mut xr, mut yr) = ranges(fig)?;
    let s = |v: u32| v * scale;
    let sf = |v: f64| v * f64::from(scale);
    let w = s(FIGURE_SIZE.0);
    root.fill(&WHITE).map_err(err)?;
    let root_m = root.margin(s(6), 0, 0, 0);
    let title_size = fit(
        &root_m,
        &fig.title,
        w - s(40),
        sf(20.0),
        sf(11.0),
        FontStyle::Bold,
    )?;
    let area = root_m
        .titled(&fig.title, font(title_size, FontStyle::Bold))
        .map_err(err)?;
    let builder = || {
        let mut b = ChartBuilder::on(&area);
        b.margin_left(s(12))
            .margin_right(s(28))
            .margin_top(s(4))
            .margin_bottom(s(10))
            .x_label_area_size(s(52))
            .y_label_area_size(s(84));
        b
    };
    let (pw, ph) = builder()
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(err)?
        .plotting_area()
        .dim_in_pixel();
    let (pw, ph) = (f64::from(pw.max(1)), f64::from(ph.max(1)));
    if fig.equal_axes {
        // Same data units per pixel on both axes: widen the range that has more pixels
        // per unit, about its center.
        let upp = ((xr.1 - xr.0) / pw).max((yr.1 - yr.0) / ph);
        let widen = |r: (f64, f64), px: f64| {
            let c = 0.5 * (r.0 + r.1);
            (c - 0.5 * upp * px, c + 0.5 * upp * px)
        };
        xr = widen(xr, pw);
        yr = widen(yr, ph);
    }

    let legend_font = font(sf(14.0), FontStyle::Normal);
    let (lmargin, lsym) = (s(8), s(34));
    let legend = if fig.series.len() > 1 {
        let mut text = MultiLineText::<(i32, i32), &str>::new((0, 0), &legend_font);
        for sr in &fig.series {
            text.push_line(sr.label.as_str());
        }
        let (tw, th) = text.estimate_dimension().map_err(err)?;
        // Box plus its 5 px offset from the plot's edge plus clearance, as fractions.
        let (lw, lh) = (
            f64::from(tw) + f64::from(lsym + 2 * lmargin) + sf(12.0),
            f64::from(th) + f64::from(2 * lmargin) + sf(12.0),
        );
        let (fw, fh) = ((lw / pw).min(0.9), (lh / ph).min(0.9));
        Some(match free_corner(fig, xr, yr, (fw, fh)) {
            Some(pos) => pos,
            None => {
                // Headroom above the data for the legend; keeps equal axes equal.
                let grow = 1.0 / (1.0 - fh);
                yr.1 = yr.0 + (yr.1 - yr.0) * grow;
                if fig.equal_axes {
                    let (c, half) = (0.5 * (xr.0 + xr.1), 0.5 * (xr.1 - xr.0) * grow);
                    xr = (c - half, c + half);
                }
                SeriesLabelPosition::UpperRight
            }
        })
    } else {
        None
    };

    let mut chart = builder()
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(err)?;
    let fx = tick_format(xr.0, xr.1, X_TICKS);
    let fy = tick_format(yr.0, yr.1, Y_TICKS);
    chart
        .configure_mesh()
        .bold_line_style(RGBColor(222, 222, 222).stroke_width(s(1)))
        .light_line_style(RGBColor(244, 244, 244).stroke_width(s(1)))
        .max_light_lines(4)
        .axis_style(RGBColor(90, 90, 90).stroke_width(s(1)))
        .set_all_tick_mark_size(s(5))
        .x_labels(X_TICKS)
        .y_labels(Y_TICKS)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style(font(sf(14.0), FontStyle::Normal))
        .axis_desc_style(font(sf(16.0), FontStyle::Normal))
        .x_desc(fig.x_label.as_str())
        .y_desc(fig.y_label.as_str())
        .draw()
        .map_err(err)?;
    // pixels per data unit, to find where a line turns back
    let (pw, ph) = chart.plotting_area().dim_in_pixel();
    let per_unit = (f64::from(pw) / (xr.1 - xr.0), f64::from(ph) / (yr.1 - yr.0));
    let radius = s(4) as i32;
    for (i, sr) in fig.series.iter().enumerate() {
        let color = COLORS[i % COLORS.len()];
        let len = (lsym - s(10)) as i32;
        let mut labelled = legend.is_none();
        for seg in segments(&sr.points) {
            if seg.len() > 1 {
                for piece in unfolded(&seg, per_unit) {
                    let drawn = chart
                        .draw_series(LineSeries::new(piece, color.stroke_width(s(2))))
                        .map_err(err)?;
                    if !labelled {
                        labelled = true;
                        let label = drawn.label(sr.label.as_str());
                        let line = move |(x, y): (i32, i32)| {
                            PathElement::new(vec![(x, y), (x + len, y)], color.stroke_width(s(3)))
                        };
                        if fig.markers {
                            label.legend(move |(x, y)| {
                                EmptyElement::at((x, y))
                                    + line((0, 0))
                                    + Circle::new((len / 2, 0), radius, color.filled())
                            });
                        } else {
                            label.legend(line);
                        }
                    }
                }
            }
            if seg.len() == 1 || fig.markers {
                let drawn = chart
                    .draw_series(seg.iter().map(|&p| Circle::new(p, radius, color.filled())))
                    .map_err(err)?;
                if !labelled {
                    labelled = true;
                    drawn.label(sr.label.as_str()).legend(move |(x, y)| {
                        Circle::new((x + len / 2, y), radius, color.filled())
                    });
                }
            }
        }
    }
    if let Some(pos) = legend {
        chart
            .configure_series_labels()
            .position(pos)
            .margin(lmargin)
            .legend_area_size(lsym)
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(170, 170, 170).stroke_width(s(1)))
            .label_font(legend_font.clone())
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

/// A 128×128 PNG icon (`model.png`): a Geneva wheel with its drive pin above `title`
/// (shrunk, then cut with an ellipsis, to fit). Drawn at 4× and averaged down, so edges
/// are smooth. Deterministic.
pub fn icon_png(title: &str) -> Result<Vec<u8>, String> {
    encode_png(ICON_SIZE, ICON_SIZE, &draw_icon(title)?)
}

/// The pixels of [`icon_png`]: RGB rows, top to bottom.
fn draw_icon(title: &str) -> Result<Vec<u8>, String> {
    fonts()?;
    const S: u32 = 4;
    let n = ICON_SIZE * S;
    let mut buf = vec![0u8; (n * n * 3) as usize];
    let px = |v: f64| (v * f64::from(S)).round() as i32;
    {
        let root = BitMapBackend::with_buffer(&mut buf, (n, n)).into_drawing_area();
        let paper = RGBColor(241, 244, 248);
        let steel = RGBColor(52, 101, 164);
        let dark = RGBColor(36, 48, 66);
        root.fill(&RGBColor(120, 132, 150)).map_err(err)?;
        root.draw(&Rectangle::new(
            [(px(2.0), px(2.0)), (px(126.0), px(126.0))],
            paper.filled(),
        ))
        .map_err(err)?;

        let (cx, cy, r) = (64.0, 52.0, 38.0);
        let disk = |x: f64, y: f64, rad: f64, c: RGBColor| {
            Circle::new((px(x), px(y)), px(rad), c.filled())
        };
        root.draw(&disk(cx, cy, r, steel)).map_err(err)?;
        // Four radial slots (axis-aligned) and four concave locking arcs between them.
        let (sw, s0) = (0.11 * r, 0.42 * r);
        for (dx, dy) in [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)] {
            let (a, b) = (
                (cx + dx * s0 - dy * sw, cy + dy * s0 - dx * sw),
                (cx + dx * (r + 1.0) + dy * sw, cy + dy * (r + 1.0) + dx * sw),
            );
            root.draw(&Rectangle::new(
                [(px(a.0), px(a.1)), (px(b.0), px(b.1))],
                paper.filled(),
            ))
            .map_err(err)?;
            // Round slot bottom.
            root.draw(&disk(cx + dx * s0, cy + dy * s0, sw, paper))
                .map_err(err)?;
        }
        let d = std::f64::consts::FRAC_1_SQRT_2 * 1.04 * r;
        for (sx, sy) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
            root.draw(&disk(cx + sx * d, cy + sy * d, 0.40 * r, paper))
                .map_err(err)?;
        }
        // Hub, and the drive pin engaged in the right slot.
        root.draw(&disk(cx, cy, 0.2 * r, dark)).map_err(err)?;
        root.draw(&disk(cx, cy, 0.08 * r, paper)).map_err(err)?;
        root.draw(&disk(cx + 0.72 * r, cy, 0.095 * r, RGBColor(230, 126, 34)))
            .map_err(err)?;

        let text = fit_title(&root, title, px(118.0) as u32, f64::from(S))?;
        let style = font(f64::from(px(text.1)), FontStyle::Bold)
            .color(&dark)
            .pos(Pos::new(HPos::Center, VPos::Center));
        root.draw_text(&text.0, &style, (px(64.0), px(111.0)))
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(downsample(
        &buf,
        ICON_SIZE as usize,
        ICON_SIZE as usize,
        S as usize,
    ))
}

/// `title` at a size (icon pixels) from 15 down to 9 that fits `width` (drawing pixels,
/// `scale` per icon pixel), cut with an ellipsis if even the smallest does not.
fn fit_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    width: u32,
    scale: f64,
) -> Result<(String, f64), String> {
    let wide = |t: &str, size: f64| -> Result<bool, String> {
        Ok(area
            .estimate_text_size(t, &font(scale * size, FontStyle::Bold))
            .map_err(err)?
            .0
            > width)
    };
    let mut size = 15.0;
    while size > 9.0 && wide(title, size)? {
        size -= 1.0;
    }
    let mut chars: Vec<char> = title.trim().chars().collect();
    let mut text: String = chars.iter().collect();
    while !chars.is_empty() && wide(&text, size)? {
        chars.pop();
        text = chars.iter().collect::<String>().trim_end().to_string() + "…";
    }
    Ok((text, size))
}

/// Averages `s`×`s` blocks of an RGB image `w*s` by `h*s` pixels into one pixel each.
pub(super) fn downsample(buf: &[u8], w: usize, h: usize, s: usize) -> Vec<u8> {
    let row = w * s * 3;
    let n = (s * s) as u32;
    let mut acc = vec![0u32; w * 3];
    let mut out = Vec::with_capacity(w * h * 3);
    for band in buf.chunks_exact(row * s) {
        acc.fill(0);
        for r in band.chunks_exact(row) {
            for (a, block) in acc.chunks_exact_mut(3).zip(r.chunks_exact(3 * s)) {
                for p in block.chunks_exact(3) {
                    a[0] += u32::from(p[0]);
                    a[1] += u32::from(p[1]);
                    a[2] += u32::from(p[2]);
                }
            }
        }
        out.extend(acc.iter().map(|&v| ((v + n / 2) / n) as u8));
    }
    out
}

/// The PNG file of a `w`×`h` image given as RGB rows top to bottom (8-bit RGB, the `png`
/// crate's adaptive row filter and best compression: plots are mostly flat color).
pub(super) fn encode_png(w: u32, h: u32, rgb: &[u8]) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Best);
    enc.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
    let mut writer = enc.write_header().map_err(|e| format!("PNG: {e}"))?;
    writer
        .write_image_data(rgb)
        .map_err(|e| format!("PNG: {e}"))?;
    writer.finish().map_err(|e| format!("PNG: {e}"))?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::docs::Series;

    /// Decodes a PNG that should show `expected` (RGB rows) with the `png` crate's decoder
    /// (which checks the chunk CRCs and the zlib stream) and compares the pixels. Returns
    /// (width, height).
    fn decode(bytes: &[u8], expected: &[u8]) -> (u32, u32) {
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .expect("a PNG header");
        let mut rgb = vec![0u8; reader.output_buffer_size()];
        let info = reader.next_frame(&mut rgb).expect("PNG image data");
        assert_eq!(
            (info.color_type, info.bit_depth),
            (png::ColorType::Rgb, png::BitDepth::Eight)
        );
        rgb.truncate(info.buffer_size());
        assert_eq!(rgb, expected, "pixels");
        (info.width, info.height)
    }

    fn sample() -> Figure {
        let pts = |f: fn(f64) -> f64| {
            (0..=360)
                .map(|i| (f64::from(i), f(f64::from(i).to_radians())))
                .collect()
        };
        Figure {
            file: "fig1_test.png".into(),
            title: "Knife motion over one shaft turn".into(),
            x_label: "shaft angle φ [deg]".into(),
            y_label: "knife stroke s [mm]".into(),
            series: vec![
                Series::new("s", pts(|a| 40.0 * (1.0 - a.cos()))),
                Series::new("v·10", pts(|a| 30.0 * a.sin())),
            ],
            caption: "A test figure.".into(),
            equal_axes: false,
            markers: false,
        }
    }

    #[test]
    fn figure_svg_is_deterministic_vector_and_names_a_real_font() {
        let fig = sample();
        let a = render_svg(&fig).unwrap();
        assert_eq!(a, render_svg(&fig).unwrap(), "same figure, same text");
        assert!(a.starts_with("<svg") && a.trim_end().ends_with("</svg>"));
        assert!(a.contains(&format!(
            "width=\"{}\" height=\"{}\"",
            FIGURE_SIZE.0, FIGURE_SIZE.1
        )));
        // both series as lines in their colors, text as text, no private font name left
        for c in [COLORS[0], COLORS[1]] {
            let hex = format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2);
            assert!(a.contains(&hex), "color {hex} missing");
        }
        assert!(a.contains("<polyline"));
        assert!(a.contains("Knife motion over one shaft turn"));
        assert!(a.contains("DejaVu Sans, sans-serif") && !a.contains(FAMILY));
    }

    #[test]
    fn figure_png_decodes_and_is_deterministic() {
        let fig = sample();
        let a = render_png(&fig).unwrap();
        let b = render_png(&fig).unwrap();
        assert!(a == b, "same figure, same bytes");
        let rgb = draw_figure(&fig).unwrap();
        assert_eq!(decode(&a, &rgb), FIGURE_SIZE);
        assert!(a.len() < 150_000, "{} bytes", a.len());
        // Both series colors are drawn.
        for c in [COLORS[0], COLORS[1]] {
            assert!(
                rgb.chunks_exact(3).any(|p| p == [c.0, c.1, c.2]),
                "color {c:?} missing"
            );
        }
        // Text is drawn (anti-aliased grey pixels exist).
        assert!(
            rgb.chunks_exact(3)
                .any(|p| p[0] == p[1] && p[1] == p[2] && p[0] > 40 && p[0] < 200)
        );
    }

    #[test]
    fn equal_axes_and_degenerate_figures_render() {
        let circle: Vec<(f64, f64)> = (0..=100)
            .map(|i| f64::from(i) * std::f64::consts::TAU / 100.0)
            .map(|a| (3.0 * a.cos(), a.sin()))
            .collect();
        let mut fig = Figure {
            file: "p.png".into(),
            title: "Path".into(),
            x_label: "x [mm]".into(),
            y_label: "y [mm]".into(),
            equal_axes: true,
            markers: false,
            ..Default::default()
        };
        fig.series.push(Series::new("path", circle));
        assert_eq!(
            decode(&render_png(&fig).unwrap(), &draw_figure(&fig).unwrap()),
            FIGURE_SIZE
        );
        // A constant, a single point, gaps.
        fig.equal_axes = false;
        fig.series = vec![
            Series::new(
                "c",
                vec![(0.0, 2.0), (1.0, 2.0), (f64::NAN, 0.0), (2.0, 2.0)],
            ),
            Series::new("one", vec![(0.5, 2.0)]),
        ];
        render_png(&fig).unwrap();
        fig.series = vec![Series::new("none", vec![(f64::NAN, 1.0)])];
        assert!(render_png(&fig).is_err());
    }

    #[test]
    fn icon_decodes_and_is_deterministic() {
        for title in [
            "Geneva knife drive",
            "A very long mechanism name that cannot possibly fit",
            "",
        ] {
            let a = icon_png(title).unwrap();
            assert!(a == icon_png(title).unwrap(), "same title, same bytes");
            assert_eq!(
                decode(&a, &draw_icon(title).unwrap()),
                (ICON_SIZE, ICON_SIZE)
            );
            assert!(a.len() < 30_000, "{} bytes", a.len());
        }
    }

    /// Pixels of a figure within 60 of `c` in every channel (the line and its anti-aliasing).
    fn pixels_like(rgb: &[u8], c: RGBColor) -> usize {
        rgb.chunks_exact(3)
            .filter(|p| {
                (p[0] as i32 - c.0 as i32).abs() < 60
                    && (p[1] as i32 - c.1 as i32).abs() < 60
                    && (p[2] as i32 - c.2 as i32).abs() < 60
            })
            .count()
    }

    #[test]
    fn a_path_that_turns_back_is_drawn_as_a_line_not_hollow() {
        assert_eq!(
            unfolded(&[(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)], (1.0, 1.0)).len(),
            1
        );
        let out_and_back = [(0.0, 0.0), (1.0, 1.0), (2.0, 2.0), (1.0, 1.0), (0.0, 0.0)];
        let pieces = unfolded(&out_and_back, (1.0, 1.0));
        assert_eq!(
            pieces,
            vec![
                vec![(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)],
                vec![(2.0, 2.0), (1.0, 1.0), (0.0, 0.0)]
            ]
        );
        // drawn: as many line pixels as the one-way path (the filled polygon of a retraced
        // polyline cancelled to a hollow outline)
        let fig = |pts: &[(f64, f64)]| Figure {
            series: vec![Series::new("s", pts.to_vec())],
            ..Default::default()
        };
        let once = pixels_like(&draw_figure(&fig(&out_and_back[..3])).unwrap(), COLORS[0]);
        let twice = pixels_like(&draw_figure(&fig(&out_and_back)).unwrap(), COLORS[0]);
        assert!(
            once > 500 && twice as f64 > 0.95 * once as f64,
            "{once} {twice}"
        );
    }

    #[test]
    fn markers_sit_inside_the_axes() {
        let mut fig = Figure {
            series: vec![
                Series::new("a", vec![(0.0, 1.0), (1.0, 2.0), (2.0, 1.5)]),
                Series::new("b", vec![(0.5, 1.0), (1.5, 1.2)]),
            ],
            ..Default::default()
        };
        let ((x0, x1), _) = ranges(&fig).unwrap();
        assert_eq!((x0, x1), (0.0, 2.0), "lines over a turn end at the axes");
        fig.markers = true;
        let ((x0, x1), _) = ranges(&fig).unwrap();
        assert!(x0 < -0.09 && x1 > 2.09, "{x0} {x1}");
        let plain = pixels_like(
            &draw_figure(&Figure {
                markers: false,
                ..fig.clone()
            })
            .unwrap(),
            COLORS[0],
        );
        let marked = pixels_like(&draw_figure(&fig).unwrap(), COLORS[0]);
        assert!(marked > plain + 100, "markers drawn: {plain} {marked}");
    }

    #[test]
    fn legend_corner() {
        let r = (0.6, 1.0, 0.8, 1.0);
        assert!(segment_hits((0.0, 0.9), (1.0, 0.9), r));
        assert!(!segment_hits((0.0, 0.5), (1.0, 0.5), r));
        assert!(
            segment_hits((0.7, 0.0), (0.7, 1.0), r),
            "crosses without a point inside"
        );
        assert!(!segment_hits((0.0, 0.0), (0.5, 1.0), r));
        let fig = |pts: Vec<(f64, f64)>| Figure {
            series: vec![Series::new("a", pts)],
            ..Default::default()
        };
        let rising = fig(vec![(0.0, 0.0), (1.0, 1.0)]);
        let size = (0.3, 0.2);
        assert!(matches!(
            free_corner(&rising, (0.0, 1.0), (0.0, 1.0), size),
            Some(SeriesLabelPosition::UpperLeft)
        ));
        let full = fig(vec![
            (0.0, 0.0),
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (0.0, 0.0),
        ]);
        assert!(free_corner(&full, (0.0, 1.0), (0.0, 1.0), size).is_none());
    }

    #[test]
    fn tick_labels() {
        let f = tick_format(0.0, 360.0, 10);
        assert_eq!(f(&90.0), "90");
        let f = tick_format(-0.5, 0.5, 8);
        assert_eq!(f(&-0.0), "0.0");
        assert_eq!(f(&-1e-17), "0.0");
        assert_eq!(f(&0.2), "0.2");
        let f = tick_format(0.0, 0.25, 10);
        assert_eq!(f(&0.05), "0.05");
        let f = tick_format(0.0, 2e9, 10);
        assert_eq!(f(&1.6e9), "1.6e9");
        assert_eq!(f(&2e9), "2.0e9");
        assert_eq!(f(&8e8), "8e8");
        assert_eq!(f(&0.0), "0");
        assert_eq!(f(&-4e8), "-4e8");
    }
}
