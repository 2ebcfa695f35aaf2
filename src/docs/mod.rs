//! The `documentation/` folder of every FMU and its `model.png` icon, generic over mechanisms:
//! a page ([`page_html`]) in the order a designer reads (what it is, the questions it answers
//! with numbers at the defaults from [`mod@sweep`], the figures, how it is modelled, every variable
//! grouped), each figure a PNG line plot ([`render_png`]).
//!
//! No system library and no system font: plots are drawn with plotters into memory, text in
//! DejaVu Sans embedded in the binary, and PNGs are encoded here. Everything is
//! deterministic (no time, no hash-map order, no machine state), so rebuilding an FMU gives
//! the same bytes.

mod html;
mod map;
mod plot;
pub mod scene;
mod sweep;

pub use html::{Page, Question, anchor, escape, page_html};
pub use map::{Map, render_map_png};
pub use plot::{FIGURE_SIZE, ICON_SIZE, icon_png, render_png, render_svg};
pub use sweep::{Stat, Sweep, defaults, quantity, sweep};

use crate::md::ModelInfo;
use crate::model::{Model, Var, variables_of};

/// An FMU's `documentation/` files (index.html first, then figures) and its `model.png` icon.
pub type Documentation = (Vec<(String, Vec<u8>)>, Vec<u8>);

/// Files by name, e.g. of `documentation/`.
pub type Files = Vec<(String, Vec<u8>)>;

/// `x` for people: at most `sig` significant digits, no trailing zeros, scientific (`2e8`,
/// `1.5e-5`) from 1e6 up and below 1e-4: 31.4159 for 31.41592653589793 at `sig` 6.
pub fn number(x: f64, sig: usize) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if !x.is_finite() {
        return format!("{x}");
    }
    let sig = sig.max(1);
    let trim = |s: &str| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    let e = x.abs().log10().floor() as i32;
    if !(-4..6).contains(&e) {
        let s = format!("{:.*e}", sig - 1, x);
        let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
        format!("{}e{exp}", trim(mantissa))
    } else {
        let decimals = (sig as i32 - 1 - e).max(0) as usize;
        let s = trim(&format!("{x:.decimals$}"));
        if s == "-0" { "0".into() } else { s }
    }
}

/// One line of a figure.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// Legend entry (shown when the figure has more than one series).
    pub label: String,
    /// `(x, y)` in plot units; a non-finite point breaks the line.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.into(),
            points,
        }
    }
}

/// A figure of the documentation: a line plot and its caption.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Figure {
    /// File name in `documentation/`, e.g. `fig2_gamma.png`.
    pub file: String,
    /// Drawn above the plot; also the image's `alt` text.
    pub title: String,
    /// Axis labels, with units, e.g. `shaft angle φ [deg]`.
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Plain text under the figure on the page.
    pub caption: String,
    /// One unit as long on both axes (paths of a point in the plane).
    pub equal_axes: bool,
    /// A marker at every point (few points that each are a measurement, e.g. a ladder of
    /// tolerances); the x axis is then padded too, so no marker sits on an axis.
    pub markers: bool,
}

impl Figure {
    /// A plot of lines: the `series` in the file `file` with its `title`, axis labels and
    /// `caption`; the axes scaled each to its own range, no markers.
    pub fn lines(
        file: &str,
        title: impl Into<String>,
        x_label: &str,
        y_label: &str,
        series: Vec<Series>,
        caption: impl Into<String>,
    ) -> Self {
        Figure {
            file: file.into(),
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series,
            caption: caption.into(),
            equal_axes: false,
            markers: false,
        }
    }
}

/// Every file of a plain `documentation/` (an introduction, the variables, the figures), in
/// order: `index.html`, then each figure's PNG. See [`page_files`].
pub fn documentation(
    info: &ModelInfo,
    vars: &[(u32, &Var)],
    intro_html: &str,
    figures: &[Figure],
) -> Result<Vec<(String, Vec<u8>)>, String> {
    page_files(&Page {
        figures,
        ..Page::plain(info, vars, intro_html)
    })
}

/// Every file of `documentation/` for a page, in order: `index.html`, then the picture's and
/// each figure's PNG. Fails on a figure that cannot be drawn, a file name that is not a plain,
/// unique `*.png` name, or a question naming an output the model does not have.
pub fn page_files(page: &Page) -> Result<Vec<(String, Vec<u8>)>, String> {
    for q in page.questions {
        if let Some(o) = q
            .outputs
            .iter()
            .find(|o| !page.vars.iter().any(|(_, v)| v.name == **o))
        {
            return Err(format!("question {:?}: no variable {o}", q.ask));
        }
    }
    let mut files = vec![("index.html".to_string(), page_html(page).into_bytes())];
    for fig in page.picture.into_iter().chain(page.figures) {
        let plain = fig.file.len() > 4
            && fig.file.ends_with(".png")
            && !fig.file.starts_with('.')
            && fig
                .file
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
        if !plain {
            return Err(format!(
                "figure file name {:?}: want a plain name like fig1_motion.png",
                fig.file
            ));
        }
        if files.iter().any(|(f, _)| *f == fig.file) {
            return Err(format!("figure file name {:?} used twice", fig.file));
        }
        files.push((fig.file.clone(), render_png(fig)?));
    }
    Ok(files)
}

/// A mechanism's documentation and icon: the page of `M`'s variables ([`page_files`]) with the
/// introduction `what`, the first of `figures` as the picture next to it and the others below,
/// the `questions` answered at the defaults, the `notes` and the table of the sweep `s`; the
/// icon labelled `icon`.
pub fn model_page<M: Model>(
    what: &str,
    mut figures: Vec<Figure>,
    questions: &[Question],
    notes: &str,
    s: &Sweep,
    icon: &str,
) -> Result<Documentation, String> {
    let picture = (!figures.is_empty()).then(|| figures.remove(0));
    let files = page_files(&Page {
        info: &ModelInfo::of::<M>(),
        vars: &variables_of::<M>(),
        what,
        picture: picture.as_ref(),
        questions,
        figures: &figures,
        notes,
        sweep: Some(s),
    })?;
    Ok((files, icon_png(icon)?))
}

/// `f(φ)` sampled at `n + 1` points over one turn, φ from 0 to 2π, as `(φ in degrees, f(φ))`:
/// the points of a figure over a shaft turn.
pub fn over_turn(n: usize, f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|k| {
            let phi = std::f64::consts::TAU * k as f64 / n as f64;
            (phi.to_degrees(), f(phi))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Experiment;

    #[test]
    fn numbers_for_people() {
        assert_eq!(number(std::f64::consts::PI * 10.0, 6), "31.4159");
        assert_eq!(number(0.10471975511965978, 6), "0.10472");
        assert_eq!(number(15000.0, 6), "15000");
        assert_eq!(number(300.00000000001, 6), "300");
        assert_eq!(number(2e8, 6), "2e8");
        assert_eq!(number(1.5e-5, 6), "1.5e-5");
        assert_eq!(number(0.0035, 6), "0.0035");
        assert_eq!(number(-0.0, 6), "0");
        assert_eq!(number(-113.6512, 5), "-113.65");
        assert_eq!(number(1.0 / 15.0, 4), "0.06667");
    }

    #[test]
    fn documentation_files() {
        let info = ModelInfo {
            identifier: "t",
            model_name: "T",
            description: "d",
            experiment: Experiment {
                start: 0.0,
                stop: 1.0,
                step: 1e-3,
                tolerance: None,
            },
            event_indicators: 0,
            can_interpolate_inputs: false,
            terminals: &[],
            variables: 0,
            partials: false,
        };
        let v = Var::output("y", "m", "out");
        let fig = |f: &str| Figure {
            file: f.into(),
            series: vec![Series::new("a", vec![(0.0, 0.0), (1.0, 1.0)])],
            ..Default::default()
        };
        let files = documentation(
            &info,
            &[(0, &v)],
            "",
            &[fig("fig1_a.png"), fig("fig2_b.png")],
        )
        .unwrap();
        let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["index.html", "fig1_a.png", "fig2_b.png"]);
        for bad in ["../x.png", "x.svg", "index.html", "a b.png", ".png"] {
            assert!(documentation(&info, &[], "", &[fig(bad)]).is_err(), "{bad}");
        }
        assert!(documentation(&info, &[], "", &[fig("a.png"), fig("a.png")]).is_err());
    }
}
