//! A tiny SVG writer for log-log scatter plots: one panel per scenario, error against cost.

use std::fmt::Write;

/// One series: a name, a colour and its (cost, error) points, joined in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// CSS colour.
    pub colour: &'static str,
    /// Points (x, y). An x that is not a positive finite number, or a y that is not finite (a
    /// failed run), is left out of the plot and counted in the legend; a y at or below
    /// [`FLOOR`] (an exact answer) is drawn on the floor as a hollow circle.
    pub points: Vec<(f64, f64)>,
}

/// One panel.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    /// Title.
    pub title: String,
    /// y-axis label.
    pub y_label: String,
    /// The series.
    pub series: Vec<Series>,
}

const W: f64 = 460.0;
const H: f64 = 330.0;
const LEFT: f64 = 62.0;
const RIGHT: f64 = 12.0;
const TOP: f64 = 28.0;
const BOTTOM: f64 = 44.0;
/// Errors below this are drawn at it, hollow (an exact answer has error 0).
pub const FLOOR: f64 = 1e-16;

/// Whether a point can be drawn on log-log axes.
fn drawable(&(x, y): &(f64, f64)) -> bool {
    x.is_finite() && x > 0.0 && y.is_finite()
}

fn decades(values: impl Iterator<Item = f64>) -> (i32, i32) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v.log10());
        hi = hi.max(v.log10());
    }
    if !lo.is_finite() {
        return (0, 1);
    }
    let (lo, hi) = (lo.floor() as i32, hi.ceil() as i32);
    (lo, hi.max(lo + 1))
}

fn panel(out: &mut String, p: &Panel, ox: f64, oy: f64) {
    let drawn = || {
        p.series
            .iter()
            .flat_map(|s| s.points.iter().filter(|q| drawable(q)))
    };
    let xs = drawn().map(|q| q.0);
    let ys = drawn().map(|q| q.1.max(FLOOR));
    let ((x0, x1), (y0, y1)) = (decades(xs), decades(ys));
    let (pw, ph) = (W - LEFT - RIGHT, H - TOP - BOTTOM);
    let sx = |x: f64| ox + LEFT + (x.log10() - f64::from(x0)) / f64::from(x1 - x0) * pw;
    let sy = |y: f64| {
        oy + TOP + (1.0 - (y.max(FLOOR).log10() - f64::from(y0)) / f64::from(y1 - y0)) * ph
    };
    let _ = writeln!(
        out,
        r##"<rect x="{}" y="{}" width="{pw}" height="{ph}" fill="white" stroke="#444"/>"##,
        ox + LEFT,
        oy + TOP
    );
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{}" font-size="13" font-weight="bold">{}</text>"#,
        ox + LEFT,
        oy + 18.0,
        p.title
    );
    let ystep = ((y1 - y0) as f64 / 8.0).ceil().max(1.0) as i32;
    for d in (y0..=y1).step_by(ystep as usize) {
        let y = sy(10f64.powi(d));
        let _ = writeln!(
            out,
            r##"<line x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="#ddd"/><text x="{}" y="{}" font-size="10" text-anchor="end">1e{d}</text>"##,
            ox + LEFT,
            ox + LEFT + pw,
            ox + LEFT - 4.0,
            y + 3.0
        );
    }
    for d in x0..=x1 {
        let x = sx(10f64.powi(d));
        let _ = writeln!(
            out,
            r##"<line x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#ddd"/><text x="{x}" y="{}" font-size="10" text-anchor="middle">1e{d}</text>"##,
            oy + TOP,
            oy + TOP + ph,
            oy + TOP + ph + 13.0
        );
    }
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{}" font-size="11" text-anchor="middle">wall seconds per simulated second</text>"#,
        ox + LEFT + pw / 2.0,
        oy + H - 8.0
    );
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{}" font-size="11" transform="rotate(-90 {} {})" text-anchor="middle">{}</text>"#,
        ox + 12.0,
        oy + TOP + ph / 2.0,
        ox + 12.0,
        oy + TOP + ph / 2.0,
        p.y_label
    );
    for (k, s) in p.series.iter().enumerate() {
        // One line through each run of drawable points: a failed point breaks it.
        for run in s.points.split(|q| !drawable(q)).filter(|run| run.len() > 1) {
            let path: Vec<String> = run
                .iter()
                .map(|&(x, y)| format!("{:.1},{:.1}", sx(x), sy(y)))
                .collect();
            let _ = writeln!(
                out,
                r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="1.5"/>"#,
                path.join(" "),
                s.colour
            );
        }
        for &(x, y) in s.points.iter().filter(|q| drawable(q)) {
            let fill = if y > FLOOR { s.colour } else { "white" };
            let _ = writeln!(
                out,
                r#"<circle cx="{:.1}" cy="{:.1}" r="2.5" fill="{fill}" stroke="{}"/>"#,
                sx(x),
                sy(y),
                s.colour
            );
        }
        let failed = s.points.iter().filter(|q| !drawable(q)).count();
        let name = if failed > 0 {
            format!("{} ({failed} failed, not drawn)", s.name)
        } else {
            s.name.clone()
        };
        let (lx, ly) = (ox + LEFT + pw - 110.0, oy + TOP + 12.0 + 12.0 * k as f64);
        let _ = writeln!(
            out,
            r#"<rect x="{lx}" y="{}" width="8" height="8" fill="{}"/><text x="{}" y="{}" font-size="10">{}</text>"#,
            ly - 7.0,
            s.colour,
            lx + 12.0,
            ly,
            name
        );
    }
}

/// The panels on a grid of `columns`, as one SVG document.
pub fn render(panels: &[Panel], columns: usize) -> String {
    let rows = panels.len().div_ceil(columns);
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" font-family="sans-serif">"#,
        W * columns as f64,
        H * rows as f64
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    for (i, p) in panels.iter().enumerate() {
        panel(
            &mut out,
            p,
            W * (i % columns) as f64,
            H * (i / columns) as f64,
        );
    }
    out.push_str("</svg>\n");
    out
}
