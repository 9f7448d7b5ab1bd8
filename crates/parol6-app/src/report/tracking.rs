//! The tracking modes side by side (`path-test --compare-tracking`): per path and mode, the
//! ISO 9283 path figures of the run measured and of the simulation beside it, as the LabVIEW GUI
//! compared its control methods.

use std::fmt::Write as _;

use parol6_core::measure::path_figures::PathFigures;

use super::PathReport;

/// Writes the comparison table when the paths ran in more than one tracking mode.
pub(super) fn comparison_table(h: &mut String, paths: &[PathReport]) {
    let mut modes: Vec<_> = paths.iter().filter_map(|p| p.tracking).collect();
    modes.dedup();
    if modes.len() < 2 {
        return;
    }
    let with_sim = paths.iter().any(|p| p.simulation.is_some());
    h.push_str("<h2>Tracking modes compared</h2><table id=\"tracking-modes\"><tr><th rowspan=\"2\">Path</th><th rowspan=\"2\">Tracking</th>");
    let _ = write!(h, "<th colspan=\"6\">measured</th>");
    if with_sim {
        h.push_str("<th colspan=\"6\">simulation</th>");
    }
    h.push_str("</tr><tr>");
    let heads = "<th>AT<sub>p</sub> mm</th><th>RT<sub>p</sub> mm</th><th>max dev. mm</th><th>RMS dev. mm</th><th>CR mm</th><th>CO mm</th>";
    h.push_str(heads);
    if with_sim {
        h.push_str(heads);
    }
    h.push_str("</tr>");
    let cells = |h: &mut String, f: &PathFigures| {
        let _ = write!(
            h,
            "<td>{:.4}</td><td>{:.4}</td><td>{:.4}</td><td>{:.4}</td><td>{}</td><td>{}</td>",
            f.at_p_mm,
            f.rt_p_mm,
            f.max_deviation_mm,
            f.rms_deviation_mm,
            super::corner_cell(f.cr_mm),
            super::corner_cell(f.co_mm)
        );
    };
    for p in paths {
        let mode = p.tracking.map_or("", |m| m.name());
        let _ = write!(h, "<tr><td>{}</td><td>{mode}</td>", p.kind.name());
        cells(h, &p.figures);
        if with_sim {
            match &p.simulation {
                Some((f, _, _)) => cells(h, f),
                None => h.push_str("<td colspan=\"6\">not run</td>"),
            }
        }
        h.push_str("</tr>");
    }
    h.push_str("</table>");
}
