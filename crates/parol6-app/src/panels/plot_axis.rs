//! The plots' value axis and hover read-out: ticks on a 1-2-5 series spaced so that every
//! range, from a few µrad of tracking error to metres, gets at least two labelled ticks; tick
//! labels with as many decimals as their step needs (no "-0", no float noise); and the values
//! of each line at the pointer's time.
//!
//! egui_plot's default spacer steps only by powers of ten, so a 100-point plot of a 0.08°
//! tracking error had a single "0" label (issue 32, major 5).

use eframe::egui;
use egui_plot::{GridInput, GridMark};

/// Smallest distance between two labelled ticks, points. With the 1-2-5 series the largest is
/// 2.5 times this, 35 points, so the smallest plot (70 points) always shows two labels.
pub const LABEL_SPACING_PT: f64 = 14.0;

/// Size of the value axis' tick labels, points: their row (about 12 points) fits between two
/// ticks [`LABEL_SPACING_PT`] apart. egui_plot skips every label taller than the spacing, and
/// with its default (body, 12.5 points: a row of about 16) ticks 14–16 points apart, e.g. a
/// ±10 N·m torque plot 150 points tall, had no label at all (trial 7).
pub const LABEL_FONT_PT: f32 = 10.0;

/// The value axis: its title, labels from [`tick_label`] in [`LABEL_FONT_PT`], drawn at full
/// strength from [`LABEL_SPACING_PT`] (egui_plot's default fades them out below 20 points).
pub fn value_axis(title: String) -> egui_plot::AxisHints<'static> {
    egui_plot::AxisHints::new_y()
        .label(title)
        .tick_label_font(egui::FontId::proportional(LABEL_FONT_PT))
        .formatter(|mark, _| tick_label(mark.value, mark.step_size))
        .min_thickness(48.0)
        .label_spacing(12.0..=LABEL_SPACING_PT as f32)
}

/// egui_plot's default `grid_spacing.min`, points: `GridInput::base_step_size` is the value
/// span of this many points.
const EGUI_BASE_SPACING_PT: f64 = 8.0;

/// The smallest of 1, 2, 5 × 10ⁿ that is ≥ `x` (`x` > 0).
pub fn nice_step_at_least(x: f64) -> f64 {
    let p = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * p).find(|s| *s >= x * (1.0 - 1e-12)).unwrap_or(10.0 * p)
}

/// Value-axis marks: a labelled tick and a grid line every `step`, the smallest 1-2-5 step at
/// least [`LABEL_SPACING_PT`] apart. Every mark carries that step, so that the labels all have
/// the same decimals ([`tick_label`]).
pub fn value_marks(input: GridInput) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    let per_pt = input.base_step_size / EGUI_BASE_SPACING_PT;
    if !(per_pt.is_finite() && per_pt > 0.0 && lo.is_finite() && hi.is_finite() && hi > lo) {
        return Vec::new();
    }
    let step = nice_step_at_least(per_pt * LABEL_SPACING_PT);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    if last - first > 1000 {
        return Vec::new();
    }
    (first..=last).map(|k| GridMark { value: k as f64 * step, step_size: step }).collect()
}

/// Decimals that show a tick `step` apart from its neighbours (0 for steps of 1 and more).
pub fn decimals_for_step(step: f64) -> usize {
    if !(step.is_finite() && step > 0.0) {
        return 3;
    }
    (-step.log10() - 1e-9).ceil().clamp(0.0, 12.0) as usize
}

/// The time axis of a recording's plots counted from its start `origin_s`, as the timeline and
/// the Dynamics panel count: marks at round times from the start (egui_plot's own powers of ten,
/// moved), labelled from it. A live plot keeps the simulation's clock.
pub fn time_from(plot: egui_plot::Plot<'_>, origin_s: f64) -> egui_plot::Plot<'_> {
    let spacer = egui_plot::log_grid_spacer(10);
    plot.x_grid_spacer(move |input: GridInput| {
        let from_start = GridInput { bounds: (input.bounds.0 - origin_s, input.bounds.1 - origin_s), ..input };
        spacer(from_start).into_iter().map(|m| GridMark { value: m.value + origin_s, ..m }).collect()
    })
    .x_axis_formatter(move |mark, _| tick_label(mark.value - origin_s, mark.step_size))
}

/// A tick label: the value with the decimals its step needs, never "-0".
pub fn tick_label(value: f64, step: f64) -> String {
    let decimals = decimals_for_step(step);
    let v = if value.abs() < 0.5 * 10f64.powi(-(decimals as i32)) { 0.0 } else { value };
    format!("{v:.decimals$}")
}

/// The point of `line` (sorted by time) nearest to `t_s`, if the line has any.
pub fn value_at(line: &[[f64; 2]], t_s: f64) -> Option<f64> {
    if line.is_empty() || !t_s.is_finite() {
        return None;
    }
    let i = line.partition_point(|p| p[0] < t_s);
    let candidates = [i.checked_sub(1), (i < line.len()).then_some(i)];
    candidates
        .into_iter()
        .flatten()
        .min_by(|a, b| (line[*a][0] - t_s).abs().total_cmp(&(line[*b][0] - t_s).abs()))
        .map(|k| line[k][1])
}

/// The hover read-out: the time and each line's value with its unit, one per row.
pub fn hover_text(t_s: f64, values: &[(String, f64)], unit: &str, value_step: f64) -> String {
    let decimals = decimals_for_step(value_step) + 1;
    let mut out = format!("t = {t_s:.3} s");
    for (name, v) in values {
        let v = if v.abs() < 0.5 * 10f64.powi(-(decimals as i32)) { 0.0 } else { *v };
        out.push_str(&format!("\n{name}: {v:.decimals$} {unit}"));
    }
    out
}

/// Shows the read-out beside the pointer, inside `plot` and never under the pointer: a
/// non-interactive layer (a tooltip would wait for the pointer to rest, and a widget over
/// the plot would take its hover away).
pub fn show_readout(ctx: &egui::Context, id: egui::Id, pointer: egui::Pos2, plot: egui::Rect, text: String) {
    let offset = egui::vec2(16.0, 16.0);
    // right of the pointer in the plot's left half, left of it in the right half
    let (pos, pivot) = if pointer.x < plot.center().x {
        (pointer + offset, egui::Align2::LEFT_TOP)
    } else {
        (pointer + egui::vec2(-offset.x, offset.y), egui::Align2::RIGHT_TOP)
    };
    egui::Area::new(id)
        .order(egui::Order::Tooltip)
        .interactable(false)
        .pivot(pivot)
        .fixed_pos(pos)
        .constrain_to(plot)
        .show(ctx, |ui| {
            let frame = egui::Frame::popup(ui.style());
            // the rows that fit in the plot: a short plot (1024×700) cut the box at J3
            let row_pt = ui.text_style_height(&egui::TextStyle::Monospace);
            let rows = ((plot.height() - frame.total_margin().sum().y) / row_pt).floor().max(0.0) as usize;
            frame.show(ui, |ui| {
                ui.label(egui::RichText::new(fit_rows(&text, rows)).monospace());
            });
        });
}

/// The read-out `text` (the time, then one value per line) in at most `rows` rows: where its
/// lines do not fit, the values stand side by side in columns under the time (two rows at
/// least: the time and the values).
pub fn fit_rows(text: &str, rows: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let rows = rows.max(2);
    let Some((time, values)) = lines.split_first().filter(|_| lines.len() > rows) else {
        return text.to_string();
    };
    let per_row = values.len().div_ceil(rows - 1);
    let width = values.iter().map(|v| v.chars().count()).max().unwrap_or(0);
    let mut out = time.to_string();
    for row in values.chunks(per_row) {
        let cells: Vec<String> = row.iter().map(|v| format!("{v:<width$}")).collect();
        out.push('\n');
        out.push_str(cells.join("  ").trim_end());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_readout_too_tall_for_its_plot_puts_its_values_side_by_side() {
        let text = "t = 1.000 s\nJ1: 1.0 °\nJ2: -22.5 °\nJ3: 3.0 °\nJ4: 4.0 °\nJ5: 5.0 °\nJ6: 6.0 °";
        assert_eq!(fit_rows(text, 7), text, "it fits: as it was");
        assert_eq!(
            fit_rows(text, 4),
            "t = 1.000 s\nJ1: 1.0 °    J2: -22.5 °\nJ3: 3.0 °    J4: 4.0 °\nJ5: 5.0 °    J6: 6.0 °"
        );
        assert_eq!(fit_rows(text, 3).lines().count(), 3);
        assert_eq!(fit_rows(text, 0).lines().count(), 2, "the time and one row of values at least");
        assert_eq!(fit_rows("t = 1.000 s", 1), "t = 1.000 s");
    }

    fn marks(lo: f64, hi: f64, height_pt: f64) -> Vec<GridMark> {
        let base_step_size = (hi - lo) / height_pt * EGUI_BASE_SPACING_PT;
        value_marks(GridInput { bounds: (lo, hi), base_step_size })
    }

    #[test]
    fn every_range_and_plot_height_gets_two_labelled_ticks_at_least_14_points_apart() {
        for exp in -7..=4 {
            for mant in [1.0, 1.3, 2.2, 4.9, 7.7] {
                let span = mant * 10f64.powi(exp);
                for height in [70.0, 100.0, 155.0, 300.0, 900.0] {
                    for centre in [0.0, span * 0.37, -span * 3.1] {
                        let (lo, hi) = (centre - span / 2.0, centre + span / 2.0);
                        let m = marks(lo, hi, height);
                        assert!(m.len() >= 2, "{lo}..{hi} in {height} pt: {} ticks", m.len());
                        let step = m[0].step_size;
                        assert!(m.iter().all(|k| k.step_size == step), "one step for all marks");
                        let spacing_pt = step / (hi - lo) * height;
                        assert!(spacing_pt >= LABEL_SPACING_PT - 1e-9, "{lo}..{hi}: {spacing_pt} pt");
                        let labels: Vec<String> = m.iter().map(|k| tick_label(k.value, step)).collect();
                        let mut uniq = labels.clone();
                        uniq.dedup();
                        assert_eq!(uniq, labels, "distinct labels for {lo}..{hi}");
                        let negative_zero = |l: &String| l.starts_with('-') && l.chars().all(|c| "-0.".contains(c));
                        assert!(!labels.iter().any(negative_zero), "{labels:?}");
                        assert!(labels.iter().all(|l| l.len() <= 12 && !l.contains('e')), "{labels:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_tracking_error_plot_of_a_tenth_of_a_degree_had_one_label() {
        // the case: 0–0.08° in a 100-point plot; powers of ten gave only "0"
        let m = marks(-0.01, 0.09, 100.0);
        let step = m[0].step_size;
        let labels: Vec<String> = m.iter().map(|k| tick_label(k.value, step)).collect();
        assert!(labels.len() >= 3, "{labels:?}");
        assert!(labels.contains(&"0.00".to_string()) && labels.contains(&"0.02".to_string()), "{labels:?}");
    }

    #[test]
    fn a_position_plot_of_whole_degrees_has_no_decimals() {
        let m = marks(-107.3, 206.1, 270.0);
        let labels: Vec<String> = m.iter().map(|k| tick_label(k.value, k.step_size)).collect();
        assert_eq!(labels.first().map(String::as_str), Some("-100"), "{labels:?}");
        assert!(labels.iter().all(|l| !l.contains('.')), "{labels:?}");
    }

    #[test]
    fn tick_labels_have_no_float_noise_or_negative_zero() {
        assert_eq!(tick_label(0.30000000000000004, 0.1), "0.3");
        assert_eq!(tick_label(-1e-17, 0.02), "0.00");
        assert_eq!(tick_label(377.40000000000003, 0.2), "377.4");
        assert_eq!(tick_label(2e-5, 1e-5), "0.00002");
        assert_eq!(tick_label(1500.0, 500.0), "1500");
    }

    #[test]
    fn the_hover_readout_takes_each_lines_nearest_sample() {
        let line = [[0.0, 1.0], [0.5, 2.0], [1.0, 3.0]];
        assert_eq!(value_at(&line, 0.7), Some(2.0));
        assert_eq!(value_at(&line, 0.8), Some(3.0));
        assert_eq!(value_at(&line, -5.0), Some(1.0));
        assert_eq!(value_at(&[], 0.0), None);
        let text = hover_text(1.23456, &[("J1".into(), 0.012345), ("J2".into(), -0.0)], "°", 0.01);
        assert_eq!(text, "t = 1.235 s\nJ1: 0.012 °\nJ2: 0.000 °");
    }
}
