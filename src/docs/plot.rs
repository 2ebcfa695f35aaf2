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

fn fonts() -> Result<(), String> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        register_font(FAMILY, FontStyle::Normal, dejavu::sans::regular())
            .map_err(|_| "DejaVu Sans: invalid font".to_string())?;
        register_font(FAMILY, FontStyle::Bold, dejavu::sans::bold())
            .map_err(|_| "DejaVu Sans Bold: invalid font".to_string())
    })
    .clone()
}

fn font(size: f64, style: FontStyle) -> TextStyle<'static> {
    TextStyle::from(FontDesc::new(FontFamily::Name(FAMILY), size, style))
        .color(&RGBColor(30, 30, 30))
}

fn err<E: std::fmt::Display>(e: E) -> String {
    format!("drawing: {e}")
}

/// Largest font size from `max` down to `min` at which `text` is at most `width` pixels wide.
fn fit<DB: DrawingBackend>(
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
fn tick_format(lo: f64, hi: f64, n: usize) -> impl Fn(&f64) -> String {
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
const SS: u32 = 2;

/// An 800×500 PNG line plot of `fig`: title, light grid, axis labels, one color per series
/// and a legend when there is more than one (in a corner it leaves the lines visible, else
/// above them in extra headroom). Non-finite points break a line. With `equal_axes` one
/// unit is as long on both axes. Deterministic: same figure, same bytes.
pub fn render_png(fig: &Figure) -> Result<Vec<u8>, String> {
    Ok(png::encode_rgb(
        FIGURE_SIZE.0,
        FIGURE_SIZE.1,
        &draw_figure(fig)?,
    ))
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
    Ok(png::encode_rgb(ICON_SIZE, ICON_SIZE, &draw_icon(title)?))
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
fn downsample(buf: &[u8], w: usize, h: usize, s: usize) -> Vec<u8> {
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

/// A small PNG encoder: 8-bit RGB, adaptive per-row filter, zlib stream of one deflate block
/// with fixed Huffman codes after greedy LZ77 (hash chains, 32 KiB window). Plots are mostly
/// flat color, which this compresses well.
pub(crate) mod png {
    /// The PNG file of a `w`×`h` image given as RGB rows top to bottom.
    pub fn encode_rgb(w: u32, h: u32, rgb: &[u8]) -> Vec<u8> {
        assert_eq!(rgb.len(), w as usize * h as usize * 3, "RGB buffer size");
        let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
        let mut ihdr = Vec::with_capacity(13);
        ihdr.extend_from_slice(&w.to_be_bytes());
        ihdr.extend_from_slice(&h.to_be_bytes());
        ihdr.extend_from_slice(&[8, 2, 0, 0, 0]); // depth 8, RGB, deflate, adaptive filter, no interlace
        chunk(&mut out, b"IHDR", &ihdr);
        chunk(&mut out, b"IDAT", &zlib(&filter(w as usize * 3, rgb)));
        chunk(&mut out, b"IEND", &[]);
        out
    }

    fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let start = out.len();
        out.extend_from_slice(kind);
        out.extend_from_slice(data);
        let crc = crc32(&out[start..]);
        out.extend_from_slice(&crc.to_be_bytes());
    }

    /// Each row prefixed by the filter type (0..=4) whose output has the least sum of
    /// absolute values (as signed bytes); ties go to the lower type.
    pub(crate) fn filter(stride: usize, rgb: &[u8]) -> Vec<u8> {
        const BPP: usize = 3;
        let zero = vec![0u8; stride];
        let mut out = Vec::with_capacity(rgb.len() + rgb.len() / stride.max(1));
        let mut up = &zero[..];
        for row in rgb.chunks_exact(stride) {
            let predict = |f: u8, i: usize| -> u8 {
                let a = if i >= BPP { row[i - BPP] } else { 0 };
                match f {
                    0 => 0,
                    1 => a,
                    2 => up[i],
                    3 => ((u16::from(a) + u16::from(up[i])) / 2) as u8,
                    _ => paeth(a, up[i], if i >= BPP { up[i - BPP] } else { 0 }),
                }
            };
            let mut cost = [0u64; 5];
            for (i, &x) in row.iter().enumerate() {
                for (f, c) in cost.iter_mut().enumerate() {
                    *c += u64::from((x.wrapping_sub(predict(f as u8, i)) as i8).unsigned_abs());
                }
            }
            let best = (0..5u8)
                .min_by_key(|&f| (cost[f as usize], f))
                .expect("five filters");
            out.push(best);
            out.extend(
                row.iter()
                    .enumerate()
                    .map(|(i, &x)| x.wrapping_sub(predict(best, i))),
            );
            up = row;
        }
        out
    }

    fn paeth(a: u8, b: u8, c: u8) -> u8 {
        let p = a as i16 + b as i16 - c as i16;
        let (pa, pb, pc) = (
            (p - a as i16).abs(),
            (p - b as i16).abs(),
            (p - c as i16).abs(),
        );
        if pa <= pb && pa <= pc {
            a
        } else if pb <= pc {
            b
        } else {
            c
        }
    }

    /// A zlib stream (RFC 1950) of `data`.
    pub(crate) fn zlib(data: &[u8]) -> Vec<u8> {
        let mut out = vec![0x78, 0x9c];
        out.extend_from_slice(&deflate(data));
        out.extend_from_slice(&adler32(data).to_be_bytes());
        out
    }

    pub(crate) fn adler32(data: &[u8]) -> u32 {
        let (mut a, mut b) = (1u32, 0u32);
        for block in data.chunks(5552) {
            for &x in block {
                a += x as u32;
                b += a;
            }
            a %= 65521;
            b %= 65521;
        }
        (b << 16) | a
    }

    const CRC_TABLE: [u32; 256] = {
        let mut t = [0u32; 256];
        let mut n = 0;
        while n < 256 {
            let mut c = n as u32;
            let mut k = 0;
            while k < 8 {
                c = if c & 1 != 0 {
                    0xedb8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
                k += 1;
            }
            t[n] = c;
            n += 1;
        }
        t
    };

    /// CRC-32 (ISO 3309, as in PNG and zip).
    pub(crate) fn crc32(data: &[u8]) -> u32 {
        !data.iter().fold(!0u32, |c, &b| {
            CRC_TABLE[((c ^ b as u32) & 0xff) as usize] ^ (c >> 8)
        })
    }

    const LEN_BASE: [u16; 29] = [
        3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115,
        131, 163, 195, 227, 258,
    ];
    const LEN_EXTRA: [u8; 29] = [
        0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0,
    ];
    const DIST_BASE: [u16; 30] = [
        1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769, 1025, 1537,
        2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577,
    ];
    const DIST_EXTRA: [u8; 30] = [
        0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12,
        13, 13,
    ];

    const WINDOW: usize = 32768;
    const MAX_MATCH: usize = 258;
    const MAX_CHAIN: usize = 96;
    const HASH_BITS: u32 = 15;
    const NONE: u32 = u32::MAX;

    struct Bits {
        out: Vec<u8>,
        acc: u64,
        n: u32,
    }

    impl Bits {
        /// Appends the `n` low bits of `v`, least significant first.
        fn put(&mut self, v: u32, n: u32) {
            self.acc |= u64::from(v) << self.n;
            self.n += n;
            while self.n >= 8 {
                self.out.push(self.acc as u8);
                self.acc >>= 8;
                self.n -= 8;
            }
        }
        /// Appends a Huffman code (most significant bit first).
        fn code(&mut self, code: u32, len: u32) {
            self.put(code.reverse_bits() >> (32 - len), len);
        }
        /// A literal/length symbol in the fixed code of RFC 1951, 3.2.6.
        fn sym(&mut self, s: u32) {
            match s {
                0..=143 => self.code(0x30 + s, 8),
                144..=255 => self.code(0x190 + s - 144, 9),
                256..=279 => self.code(s - 256, 7),
                _ => self.code(0xc0 + s - 280, 8),
            }
        }
        fn matched(&mut self, len: usize, dist: usize) {
            let i = LEN_BASE
                .iter()
                .rposition(|&b| b as usize <= len)
                .expect("length >= 3");
            self.sym(257 + i as u32);
            self.put((len - LEN_BASE[i] as usize) as u32, LEN_EXTRA[i] as u32);
            let j = DIST_BASE
                .iter()
                .rposition(|&b| b as usize <= dist)
                .expect("distance >= 1");
            self.code(j as u32, 5);
            self.put((dist - DIST_BASE[j] as usize) as u32, DIST_EXTRA[j] as u32);
        }
        fn finish(mut self) -> Vec<u8> {
            if self.n > 0 {
                self.out.push(self.acc as u8);
            }
            self.out
        }
    }

    /// A raw deflate stream (RFC 1951) of `data`: one final block, fixed Huffman codes.
    pub(crate) fn deflate(data: &[u8]) -> Vec<u8> {
        let n = data.len();
        let mut bits = Bits {
            out: Vec::with_capacity(n / 8 + 16),
            acc: 0,
            n: 0,
        };
        bits.put(1, 1); // BFINAL
        bits.put(1, 2); // BTYPE = fixed Huffman
        let mut head = vec![NONE; 1 << HASH_BITS];
        let mut prev = vec![NONE; WINDOW];
        let hash = |i: usize| -> usize {
            let v = (data[i] as u32) << 16 | (data[i + 1] as u32) << 8 | data[i + 2] as u32;
            (v.wrapping_mul(0x9e37_79b1) >> (32 - HASH_BITS)) as usize
        };
        let insert = |i: usize, head: &mut [u32], prev: &mut [u32]| {
            if i + 3 <= n {
                let h = hash(i);
                prev[i % WINDOW] = head[h];
                head[h] = i as u32;
            }
        };
        let mut i = 0;
        while i < n {
            let (mut best_len, mut best_dist) = (0, 0);
            if i + 3 <= n {
                let max = MAX_MATCH.min(n - i);
                let mut cand = head[hash(i)];
                let mut chain = MAX_CHAIN;
                while cand != NONE && chain > 0 {
                    let c = cand as usize;
                    if c >= i || i - c > WINDOW {
                        break;
                    }
                    if data[c + best_len.min(max - 1)] == data[i + best_len.min(max - 1)] {
                        let l = data[c..c + max]
                            .iter()
                            .zip(&data[i..i + max])
                            .take_while(|(a, b)| a == b)
                            .count();
                        if l > best_len {
                            (best_len, best_dist) = (l, i - c);
                            if l == max {
                                break;
                            }
                        }
                    }
                    cand = prev[c % WINDOW];
                    chain -= 1;
                }
            }
            if best_len >= 3 {
                bits.matched(best_len, best_dist);
                for k in i..i + best_len {
                    insert(k, &mut head, &mut prev);
                }
                i += best_len;
            } else {
                bits.sym(data[i] as u32);
                insert(i, &mut head, &mut prev);
                i += 1;
            }
        }
        bits.sym(256);
        bits.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::png::{crc32, deflate};
    use super::*;
    use crate::docs::Series;
    use std::io::{Cursor, Read};

    /// Inflates a raw deflate stream with an independent decoder: the zip crate's (flate2),
    /// fed a one-entry archive built around the stream; it checks the CRC too.
    fn inflate(raw: &[u8], plain_len: usize, crc: u32) -> Vec<u8> {
        let name = b"d";
        let mut z = Vec::new();
        let u16le = |z: &mut Vec<u8>, v: u16| z.extend_from_slice(&v.to_le_bytes());
        let u32le = |z: &mut Vec<u8>, v: u32| z.extend_from_slice(&v.to_le_bytes());
        let common = |z: &mut Vec<u8>| {
            for v in [20u16, 0, 8, 0, 0x21] {
                u16le(z, v); // version needed, flags, method deflate, time, date 1980-01-01
            }
            u32le(z, crc);
            u32le(z, raw.len() as u32);
            u32le(z, plain_len as u32);
            u16le(z, name.len() as u16);
            u16le(z, 0);
        };
        u32le(&mut z, 0x0403_4b50);
        common(&mut z);
        z.extend_from_slice(name);
        z.extend_from_slice(raw);
        let cd = z.len();
        u32le(&mut z, 0x0201_4b50);
        u16le(&mut z, 20); // version made by
        common(&mut z);
        for v in [0u16, 0, 0] {
            u16le(&mut z, v); // comment length, disk, internal attributes
        }
        u32le(&mut z, 0); // external attributes
        u32le(&mut z, 0); // local header offset
        z.extend_from_slice(name);
        let cd_len = z.len() - cd;
        u32le(&mut z, 0x0605_4b50);
        for v in [0u16, 0, 1, 1] {
            u16le(&mut z, v);
        }
        u32le(&mut z, cd_len as u32);
        u32le(&mut z, cd as u32);
        u16le(&mut z, 0);
        let mut archive = zip::ZipArchive::new(Cursor::new(z)).expect("archive");
        let mut out = Vec::new();
        archive
            .by_index(0)
            .expect("entry")
            .read_to_end(&mut out)
            .expect("inflates with a good CRC");
        out
    }

    /// Decodes a PNG written by [`png::encode_rgb`] that should show `expected` (RGB rows):
    /// checks signature, chunk CRCs, IHDR, zlib header and Adler-32, inflates with the zip
    /// crate, undoes the row filters and compares. Returns (width, height).
    fn decode(png: &[u8], expected: &[u8]) -> (u32, u32) {
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let mut at = 8;
        let (mut w, mut h, mut idat) = (0, 0, Vec::new());
        loop {
            let len = u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
            let kind = &png[at + 4..at + 8];
            let body = &png[at + 8..at + 8 + len];
            let crc = u32::from_be_bytes(png[at + 8 + len..at + 12 + len].try_into().unwrap());
            assert_eq!(crc, crc32(&png[at + 4..at + 8 + len]), "chunk CRC");
            match kind {
                b"IHDR" => {
                    w = u32::from_be_bytes(body[0..4].try_into().unwrap());
                    h = u32::from_be_bytes(body[4..8].try_into().unwrap());
                    assert_eq!(&body[8..], &[8, 2, 0, 0, 0]);
                }
                b"IDAT" => idat.extend_from_slice(body),
                b"IEND" => break,
                _ => panic!("unexpected chunk"),
            }
            at += 12 + len;
        }
        assert_eq!(at + 12, png.len(), "nothing after IEND");
        assert_eq!(
            (idat[0] as u16 * 256 + idat[1] as u16) % 31,
            0,
            "zlib header"
        );
        let stride = w as usize * 3;
        assert_eq!(expected.len(), stride * h as usize);
        let want = png::filter(stride, expected);
        let filtered = inflate(&idat[2..idat.len() - 4], want.len(), crc32(&want));
        assert_eq!(
            png::adler32(&filtered),
            u32::from_be_bytes(idat[idat.len() - 4..].try_into().unwrap()),
            "adler32"
        );
        let mut rgb = vec![0u8; stride * h as usize];
        for r in 0..h as usize {
            let f = filtered[r * (stride + 1)];
            for i in 0..stride {
                let x = filtered[r * (stride + 1) + 1 + i];
                let a = if i >= 3 { rgb[r * stride + i - 3] } else { 0 };
                let b = if r > 0 { rgb[(r - 1) * stride + i] } else { 0 };
                let c = if r > 0 && i >= 3 {
                    rgb[(r - 1) * stride + i - 3]
                } else {
                    0
                };
                let p = a as i16 + b as i16 - c as i16;
                let pred = match f {
                    0 => 0,
                    1 => a,
                    2 => b,
                    3 => ((a as u16 + b as u16) / 2) as u8,
                    4 => {
                        let (pa, pb, pc) = (
                            (p - a as i16).abs(),
                            (p - b as i16).abs(),
                            (p - c as i16).abs(),
                        );
                        if pa <= pb && pa <= pc {
                            a
                        } else if pb <= pc {
                            b
                        } else {
                            c
                        }
                    }
                    _ => panic!("filter type {f}"),
                };
                rgb[r * stride + i] = x.wrapping_add(pred);
            }
        }
        assert!(rgb == expected, "decoded image differs");
        (w, h)
    }

    #[test]
    fn deflate_round_trips() {
        let mut data = Vec::new();
        for i in 0..70_000u32 {
            data.push((i.wrapping_mul(2_654_435_761) >> 29) as u8);
            if i % 1000 < 400 {
                data.push(7);
            }
        }
        data.extend(std::iter::repeat_n(0u8, 100_000));
        for d in [&data[..], &[][..], &[1u8][..], &[5, 5, 5, 5, 5][..]] {
            assert_eq!(inflate(&deflate(d), d.len(), crc32(d)), d);
        }
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
