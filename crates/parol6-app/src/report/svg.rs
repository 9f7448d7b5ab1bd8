//! Hand-written inline SVG for the measurement report: x–y plots (lines or dots, with axes,
//! ticks and a legend) and an orthographic 3D snapshot of the test cube. No scripts, no
//! external references: the SVG is text inside the HTML.

use std::fmt::Write as _;

use crate::palette::{REPORT_GRID, REPORT_INK, hex};

/// Plot size, px.
const W: f64 = 520.0;
const H: f64 = 320.0;
/// Margins: left, right, top, bottom, px.
const ML: f64 = 64.0;
const MR: f64 = 16.0;
const MT: f64 = 28.0;
const MB: f64 = 44.0;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A polyline.
    Line,
    /// A dot per point.
    Dots,
    /// A cross per point (commanded values).
    Crosses,
}

/// One data series.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Colour.
    pub color: [u8; 3],
    /// Points (x, y).
    pub points: Vec<[f64; 2]>,
    /// Style.
    pub style: Style,
}

/// Text escaped for XML / HTML.
pub fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// "Nice" tick step for a span (1, 2 or 5 × 10ⁿ, about five ticks).
fn tick_step(span: f64) -> f64 {
    let raw = span / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * mag).find(|s| *s >= raw).unwrap_or(10.0 * mag)
}

/// The data range of the series with a little room; `equal` gives both axes one scale.
fn bounds(series: &[Series], equal: bool) -> ([f64; 2], [f64; 2]) {
    let pts = series.iter().flat_map(|s| s.points.iter()).filter(|p| p[0].is_finite() && p[1].is_finite());
    let (mut x, mut y) = ([f64::INFINITY, f64::NEG_INFINITY], [f64::INFINITY, f64::NEG_INFINITY]);
    for p in pts {
        x = [x[0].min(p[0]), x[1].max(p[0])];
        y = [y[0].min(p[1]), y[1].max(p[1])];
    }
    if !x[0].is_finite() {
        return ([-1.0, 1.0], [-1.0, 1.0]);
    }
    let pad = |r: [f64; 2]| {
        let span = (r[1] - r[0]).max(1e-6);
        [r[0] - 0.06 * span, r[1] + 0.06 * span]
    };
    let (mut x, mut y) = (pad(x), pad(y));
    if equal {
        // same units per pixel on both axes
        let (pw, ph) = (W - ML - MR, H - MT - MB);
        let per_px = ((x[1] - x[0]) / pw).max((y[1] - y[0]) / ph);
        let (cx, cy) = (0.5 * (x[0] + x[1]), 0.5 * (y[0] + y[1]));
        x = [cx - 0.5 * per_px * pw, cx + 0.5 * per_px * pw];
        y = [cy - 0.5 * per_px * ph, cy + 0.5 * per_px * ph];
    }
    (x, y)
}

/// An x–y plot with a title, axis labels, ticks and a legend.
pub fn xy_plot(title: &str, x_label: &str, y_label: &str, series: &[Series], equal: bool) -> String {
    let (xr, yr) = bounds(series, equal);
    let sx = |v: f64| ML + (v - xr[0]) / (xr[1] - xr[0]) * (W - ML - MR);
    let sy = |v: f64| H - MB - (v - yr[0]) / (yr[1] - yr[0]) * (H - MT - MB);
    let (ink, grid) = (hex(REPORT_INK), hex(REPORT_GRID));
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" class="plot" width="{W}" height="{H}" viewBox="0 0 {W} {H}" role="img" aria-label="{t}"><title>{t}</title>"#,
        t = escape(title)
    );
    let _ =
        write!(s, r#"<text x="{}" y="18" font-size="13" font-weight="bold" fill="{ink}">{}</text>"#, ML, escape(title));
    for (range, vertical) in [(xr, true), (yr, false)] {
        let step = tick_step(range[1] - range[0]);
        let mut v = (range[0] / step).ceil() * step;
        while v <= range[1] {
            // + 0.0: no "-0"
            let label = format!("{}", (v / step).round() * step + 0.0);
            let label = if label.len() > 8 { format!("{v:.3e}") } else { label };
            if vertical {
                let x = sx(v);
                let _ = write!(
                    s,
                    r#"<line x1="{x:.1}" y1="{MT}" x2="{x:.1}" y2="{:.1}" stroke="{grid}"/><text x="{x:.1}" y="{:.1}" font-size="10" text-anchor="middle" fill="{ink}">{label}</text>"#,
                    H - MB,
                    H - MB + 14.0
                );
            } else {
                let y = sy(v);
                let _ = write!(
                    s,
                    r#"<line x1="{ML}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="{grid}"/><text x="{:.1}" y="{:.1}" font-size="10" text-anchor="end" fill="{ink}">{label}</text>"#,
                    W - MR,
                    ML - 4.0,
                    y + 3.0
                );
            }
            v += step;
        }
    }
    let _ = write!(
        s,
        r#"<rect x="{ML}" y="{MT}" width="{:.1}" height="{:.1}" fill="none" stroke="{ink}"/>"#,
        W - ML - MR,
        H - MT - MB
    );
    let _ = write!(
        s,
        r#"<text x="{:.1}" y="{:.1}" font-size="11" text-anchor="middle" fill="{ink}">{}</text>"#,
        ML + 0.5 * (W - ML - MR),
        H - 8.0,
        escape(x_label)
    );
    let _ = write!(
        s,
        r#"<text transform="translate(14 {:.1}) rotate(-90)" font-size="11" text-anchor="middle" fill="{ink}">{}</text>"#,
        MT + 0.5 * (H - MT - MB),
        escape(y_label)
    );
    for (i, ser) in series.iter().enumerate() {
        let c = hex(ser.color);
        let pts = ser.points.iter().filter(|p| p[0].is_finite() && p[1].is_finite());
        match ser.style {
            Style::Line => {
                let d: Vec<String> = pts.map(|p| format!("{:.1},{:.1}", sx(p[0]), sy(p[1]))).collect();
                let _ = write!(
                    s,
                    r#"<polyline class="series" fill="none" stroke="{c}" stroke-width="1.3" points="{}"/>"#,
                    d.join(" ")
                );
            }
            Style::Dots => {
                for p in pts {
                    let _ = write!(
                        s,
                        r#"<circle class="series" cx="{:.1}" cy="{:.1}" r="2.5" fill="{c}" fill-opacity="0.75"/>"#,
                        sx(p[0]),
                        sy(p[1])
                    );
                }
            }
            Style::Crosses => {
                for p in pts {
                    let (x, y) = (sx(p[0]), sy(p[1]));
                    let _ = write!(
                        s,
                        r#"<path class="series" d="M{:.1} {y:.1}H{:.1}M{x:.1} {:.1}V{:.1}" stroke="{c}" stroke-width="2"/>"#,
                        x - 6.0,
                        x + 6.0,
                        y - 6.0,
                        y + 6.0
                    );
                }
            }
        }
        // legend, top right (series without a label share the entry before them)
        if ser.label.is_empty() {
            continue;
        }
        let ly = MT + 14.0 + 14.0 * i as f64;
        let _ = write!(
            s,
            r#"<rect x="{:.1}" y="{:.1}" width="10" height="10" fill="{c}"/><text x="{:.1}" y="{:.1}" font-size="10" fill="{ink}">{}</text>"#,
            W - MR - 150.0,
            ly - 9.0,
            W - MR - 136.0,
            ly,
            escape(&ser.label)
        );
    }
    s.push_str("</svg>");
    s
}

/// A labelled 3D point or polyline for [`scene_3d`].
#[derive(Debug, Clone, PartialEq)]
pub struct Item3 {
    /// Label (points only; empty: none).
    pub label: String,
    /// Colour.
    pub color: [u8; 3],
    /// Points, mm; one point: a marker, more: a polyline.
    pub points: Vec<[f64; 3]>,
    /// Closed polyline (a polygon outline).
    pub closed: bool,
}

/// An orthographic snapshot from the front-right, above (azimuth 35°, elevation 25°), z up.
pub fn scene_3d(title: &str, items: &[Item3]) -> String {
    let (az, el) = (35f64.to_radians(), 25f64.to_radians());
    let project = |p: &[f64; 3]| {
        let x = p[0] * az.cos() - p[1] * az.sin();
        let depth = p[0] * az.sin() + p[1] * az.cos();
        let y = p[2] * el.cos() - depth * el.sin();
        [x, y]
    };
    let flat: Vec<Series> = items
        .iter()
        .map(|it| Series {
            label: String::new(),
            color: it.color,
            points: it.points.iter().map(project).collect(),
            style: Style::Line,
        })
        .collect();
    let (xr, yr) = bounds(&flat, true);
    let sx = |v: f64| ML + (v - xr[0]) / (xr[1] - xr[0]) * (W - ML - MR);
    let sy = |v: f64| H - MB - (v - yr[0]) / (yr[1] - yr[0]) * (H - MT - MB);
    let ink = hex(REPORT_INK);
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" class="plot" width="{W}" height="{H}" viewBox="0 0 {W} {H}" role="img" aria-label="{t}"><title>{t}</title><text x="{ML}" y="18" font-size="13" font-weight="bold" fill="{ink}">{t}</text>"#,
        t = escape(title)
    );
    for (it, f) in items.iter().zip(&flat) {
        let c = hex(it.color);
        if f.points.len() == 1 {
            let (x, y) = (sx(f.points[0][0]), sy(f.points[0][1]));
            let _ = write!(
                s,
                r#"<circle cx="{x:.1}" cy="{y:.1}" r="3.5" fill="{c}"/><text x="{:.1}" y="{:.1}" font-size="11" fill="{ink}">{}</text>"#,
                x + 6.0,
                y - 5.0,
                escape(&it.label)
            );
        } else {
            let d: Vec<String> = f.points.iter().map(|p| format!("{:.1},{:.1}", sx(p[0]), sy(p[1]))).collect();
            let tag = if it.closed { "polygon" } else { "polyline" };
            let _ = write!(s, r#"<{tag} fill="none" stroke="{c}" stroke-width="1.2" points="{}"/>"#, d.join(" "));
        }
    }
    s.push_str("</svg>");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_numbers() {
        assert_eq!(tick_step(10.0), 2.0);
        assert_eq!(tick_step(0.9), 0.2);
        assert_eq!(tick_step(100.0), 20.0);
        assert_eq!(tick_step(3.0), 1.0);
    }

    #[test]
    fn a_plot_is_one_svg_element_with_its_series_and_escaped_text() {
        let s = xy_plot(
            "a < b",
            "t, s",
            "d, mm",
            &[Series {
                label: "robot".into(),
                color: [1, 2, 3],
                points: vec![[0.0, 0.0], [1.0, 2.0]],
                style: Style::Line,
            }],
            false,
        );
        assert!(s.starts_with("<svg") && s.ends_with("</svg>"));
        assert!(s.contains("a &lt; b") && !s.contains("a < b"));
        assert!(s.contains("#010203") && s.contains("<polyline class=\"series\""));
        let empty = xy_plot("empty", "x", "y", &[], true);
        assert!(empty.contains("</svg>"));
        let cube =
            scene_3d("cube", &[Item3 { label: "P1".into(), color: [0; 3], points: vec![[0.0; 3]], closed: false }]);
        assert!(cube.contains(">P1</text>"));
    }
}
