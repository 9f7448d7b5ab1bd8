//! Export from the plots panel: the visible window as CSV (every kept row, every series, SI
//! units in the column names, and each row's `resolution`: `sample`, or `min_max_4ms` for the
//! live summary of samples older than a minute) and the shown plots as SVG (the decimated lines as drawn).
//!
//! The live history is kept over a switch between the simulation and the robot, whose drive
//! series hold different quantities (torque in N·m, step rates in steps/s). A window with both
//! has a set of drive columns per quantity, each row's value under its own unit and the other
//! set empty, and a `backend` column (`simulation` or `robot`) names each live row's source.

use std::fmt::Write as _;
use std::path::Path;

use eframe::egui;
use parol6_core::telemetry::{DriveKind, Quantity, SeriesStore};

use super::plot_stretches::DriveStretches;
use super::plots::series_name;

/// A line as drawn: name, colour, points in display units.
#[derive(Debug, Clone)]
pub struct DrawnLine {
    /// Series name (`J1`, `x` …).
    pub name: String,
    /// Its colour.
    pub color: egui::Color32,
    /// `[t_s, value]` in the plot's unit.
    pub points: Vec<[f64; 2]>,
}

/// One plot as drawn: its title (with unit) and lines.
#[derive(Debug, Clone)]
pub struct DrawnGroup {
    /// Title with unit.
    pub title: String,
    /// Lines.
    pub lines: Vec<DrawnLine>,
}

/// CSV column name of a series, SI unit in the name (a drive series in the store's current
/// quantity).
pub fn csv_column(store: &SeriesStore, col: usize) -> String {
    csv_column_as(store, col, store.drive())
}

/// CSV column name of a series, a drive series holding `drive`.
fn csv_column_as(store: &SeriesStore, col: usize, drive: DriveKind) -> String {
    let Some(&id) = store.ids().get(col) else { return format!("col{col}") };
    let name = series_name(id).to_lowercase();
    match id.quantity {
        Quantity::Position => format!("{name}_q_rad"),
        Quantity::Velocity => format!("{name}_qd_rad_s"),
        Quantity::Acceleration => format!("{name}_qdd_rad_s2"),
        Quantity::Drive => match drive {
            DriveKind::TorqueNm => format!("{name}_torque_nm"),
            DriveKind::StepsPerS => format!("{name}_steps_s"),
        },
        Quantity::TrackingError => format!("{name}_cmd_minus_meas_rad"),
        Quantity::TcpPosition => format!("tcp_{name}_m"),
        Quantity::TcpOrientation => format!("tcp_{name}_rad"),
    }
}

/// A sample time, s, to the microsecond (the samples' times are sums of 1 ms steps, whose
/// binary noise wrote `377.40000000000003`), without trailing zeros and never "-0".
pub fn time_text(t_s: f64) -> String {
    let text = format!("{:.6}", t_s + 0.0);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" { "0".into() } else { text.into() }
}

/// One column of the CSV: a series of the store, a drive series only in rows of its quantity.
#[derive(Clone, Copy, PartialEq)]
enum Column {
    Plain(usize),
    Drive(usize, DriveKind),
}

/// Writes every kept row between `t0_s` and `t1_s` to `path` as CSV (atomically: a failed
/// write leaves the old file), each with its resolution (see the module docs); returns the rows.
/// `stretches` are the live history's (empty for a replay's store, whose drive quantity is one).
pub fn write_csv(
    path: &Path,
    store: &SeriesStore,
    stretches: &DriveStretches,
    t0_s: f64,
    t1_s: f64,
) -> Result<usize, String> {
    // each row's drive quantity and backend (a replay's rows: the store's quantity)
    let row_of = |t: f64| stretches.at(t).map_or((store.drive(), None), |s| (s.drive, Some(s.robot)));
    let mut drives: Vec<DriveKind> = Vec::new();
    for (t, _) in store.raw_window(t0_s, t1_s) {
        let d = row_of(t).0;
        if !drives.contains(&d) {
            drives.push(d);
        }
    }
    drives.sort_by_key(|d| *d != DriveKind::TorqueNm);
    if drives.is_empty() {
        drives.push(store.drive());
    }
    let ids = store.ids();
    let mut columns = Vec::new();
    for (c, id) in ids.iter().enumerate() {
        if id.quantity != Quantity::Drive {
            columns.push(Column::Plain(c));
        } else if ids.get(c.wrapping_sub(1)).is_none_or(|p| p.quantity != Quantity::Drive) {
            // the block of drive series, once per quantity in the window
            let block: Vec<usize> = (c..ids.len()).take_while(|&k| ids[k].quantity == Quantity::Drive).collect();
            columns.extend(drives.iter().flat_map(|&d| block.iter().map(move |&k| Column::Drive(k, d))));
        }
    }
    let backend_column = !stretches.is_empty();
    let mut rows = 0;
    parol6_core::fsio::write_atomic(path, |out| {
        let mut header = String::from("t_s");
        for col in &columns {
            header.push(',');
            header.push_str(&match *col {
                Column::Plain(c) => csv_column(store, c),
                Column::Drive(c, d) => csv_column_as(store, c, d),
            });
        }
        if backend_column {
            header.push_str(",backend");
        }
        header.push_str(",resolution");
        writeln!(out, "{header}")?;
        let summary_before_s = store.summary_before_s();
        let mut line = String::new();
        for (t, values) in store.raw_window(t0_s, t1_s) {
            let (drive, robot) = row_of(t);
            line.clear();
            line.push_str(&time_text(t));
            for col in &columns {
                line.push(',');
                let v = match *col {
                    Column::Plain(c) => values.get(c),
                    Column::Drive(c, d) => values.get(c).filter(|_| d == drive),
                };
                if let Some(v) = v.filter(|v| v.is_finite()) {
                    // the shortest text that reads back as the same f64
                    line.push_str(&(v + 0.0).to_string());
                }
            }
            if backend_column {
                line.push_str(match robot {
                    Some(true) => ",robot",
                    Some(false) => ",simulation",
                    None => ",",
                });
            }
            line.push_str(match summary_before_s {
                Some(before) if t < before => ",min_max_4ms",
                _ => ",sample",
            });
            writeln!(out, "{line}")?;
            rows += 1;
        }
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    Ok(rows)
}

/// Size of one plot in the SVG, px.
const SVG_W: f64 = 900.0;
const SVG_PLOT_H: f64 = 180.0;
const SVG_MARGIN: f64 = 60.0;

fn css(c: egui::Color32) -> String {
    format!("#{:02x}{:02x}{:02x}", c.r(), c.g(), c.b())
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// The SVG text of `groups` over the time window `t0_s`..`t1_s`: one plot per group, stacked,
/// with its frame, title, value range and legend.
pub fn svg_text(groups: &[DrawnGroup], t0_s: f64, t1_s: f64) -> String {
    let frame = crate::palette::rgb(crate::palette::PLOT_SVG_FRAME);
    let text = crate::palette::rgb(crate::palette::PLOT_SVG_TEXT);
    let height = SVG_MARGIN + groups.len() as f64 * (SVG_PLOT_H + SVG_MARGIN);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{height}\" font-family=\"sans-serif\" font-size=\"12\">\n",
        SVG_W + 2.0 * SVG_MARGIN
    );
    let dt = (t1_s - t0_s).max(1e-9);
    for (k, g) in groups.iter().enumerate() {
        let top = SVG_MARGIN + k as f64 * (SVG_PLOT_H + SVG_MARGIN);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in g.lines.iter().flat_map(|l| &l.points) {
            lo = lo.min(p[1]);
            hi = hi.max(p[1]);
        }
        if !(lo.is_finite() && hi.is_finite()) {
            (lo, hi) = (0.0, 1.0);
        }
        if hi - lo < 1e-12 {
            (lo, hi) = (lo - 0.5, hi + 0.5);
        }
        let x = |t: f64| SVG_MARGIN + (t - t0_s) / dt * SVG_W;
        let y = |v: f64| top + SVG_PLOT_H - (v - lo) / (hi - lo) * SVG_PLOT_H;
        let _ = writeln!(
            s,
            "<rect x=\"{SVG_MARGIN}\" y=\"{top}\" width=\"{SVG_W}\" height=\"{SVG_PLOT_H}\" fill=\"none\" stroke=\"{}\"/>",
            css(frame)
        );
        let _ = writeln!(
            s,
            "<text x=\"{SVG_MARGIN}\" y=\"{}\" fill=\"{}\">{}</text>",
            top - 6.0,
            css(text),
            escape(&g.title)
        );
        let _ = writeln!(s, "<text x=\"4\" y=\"{}\" fill=\"{}\">{hi:.4}</text>", top + 12.0, css(text));
        let _ = writeln!(s, "<text x=\"4\" y=\"{}\" fill=\"{}\">{lo:.4}</text>", top + SVG_PLOT_H, css(text));
        for (i, l) in g.lines.iter().enumerate() {
            let mut pts = String::new();
            for p in l.points.iter().filter(|p| p[0] >= t0_s && p[0] <= t1_s) {
                pts.push_str(&format!("{:.1},{:.1} ", x(p[0]), y(p[1])));
            }
            let c = css(l.color);
            let _ = writeln!(
                s,
                "<polyline fill=\"none\" stroke=\"{c}\" stroke-width=\"1\" points=\"{}\"/>",
                pts.trim_end()
            );
            let lx = SVG_MARGIN + SVG_W - 60.0 * (g.lines.len() - i) as f64;
            let _ = writeln!(s, "<text x=\"{lx}\" y=\"{}\" fill=\"{c}\">{}</text>", top - 6.0, escape(&l.name));
        }
    }
    let bottom = height - SVG_MARGIN / 2.0;
    let _ = writeln!(s, "<text x=\"{SVG_MARGIN}\" y=\"{bottom}\" fill=\"{}\">{t0_s:.2} s</text>", css(text));
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{bottom}\" text-anchor=\"end\" fill=\"{}\">{t1_s:.2} s</text>",
        SVG_MARGIN + SVG_W,
        css(text)
    );
    s.push_str("</svg>\n");
    s
}

/// Writes [`svg_text`] to `path`.
pub fn write_svg(path: &Path, groups: &[DrawnGroup], t0_s: f64, t1_s: f64) -> Result<(), String> {
    if groups.is_empty() {
        return Err("no plot is shown: nothing to write".into());
    }
    parol6_core::fsio::write_atomic_bytes(path, svg_text(groups, t0_s, t1_s).as_bytes()).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (issue 32): the plot CSV had times such as `377.40000000000003`.
    #[test]
    fn sample_times_are_written_to_the_microsecond_without_noise() {
        assert_eq!(time_text(377.40000000000003), "377.4");
        assert_eq!(time_text(0.001 * 3.0), "0.003");
        assert_eq!(time_text(-0.0), "0");
        assert_eq!(time_text(-1e-9), "0");
        assert_eq!(time_text(12.0), "12");
        assert_eq!(time_text(0.0000016), "0.000002");
    }

    #[test]
    fn svg_has_a_polyline_per_line_and_escapes_titles() {
        let g = DrawnGroup {
            title: "a < b".into(),
            lines: vec![DrawnLine {
                name: "J1".into(),
                color: egui::Color32::RED,
                points: vec![[0.0, 1.0], [1.0, 2.0]],
            }],
        };
        let s = svg_text(&[g.clone(), g], 0.0, 1.0);
        assert_eq!(s.matches("<polyline").count(), 2);
        assert!(s.contains("a &lt; b") && s.contains("#ff0000"));
        assert!(s.starts_with("<svg") && s.trim_end().ends_with("</svg>"));
    }

    #[test]
    fn csv_columns_name_their_units() {
        let st = SeriesStore::new(6, 10.0);
        assert_eq!(csv_column(&st, 0), "j1_q_rad");
        assert_eq!(csv_column(&st, 24), "j1_cmd_minus_meas_rad");
        assert_eq!(csv_column(&st, 30), "tcp_x_m");
        assert_eq!(csv_column(&st, 35), "tcp_yaw_rad");
    }
}
