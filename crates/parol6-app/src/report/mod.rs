//! The measurement report: one self-contained HTML file (inline CSS and SVG, no scripts, no
//! network) with the test set-up, the table of figures, a 3D snapshot of the cube, scatter
//! plots of the attained positions per pose, path deviation plots, the simulation against the
//! robot when both ran, and the FK matrices of the commanded poses. Written by
//! `parol6 iso9283|path-test --report` and the measurement panel.

pub mod svg;
mod tracking;

use std::fmt::Write as _;

use parol6_core::kinematics::matrix4_rows;
use parol6_core::measure::compare::{self, DiffSample};
use parol6_core::measure::cube::POSE_NAMES;
use parol6_core::measure::driver::PathRecording;
use parol6_core::measure::path_figures::{PathFigureError, PathFigures, nearest_on};
use parol6_core::measure::pose_figures::{PoseSample, PoseTestFigures};
use parol6_core::measure::{PathKind, TestCube};
use parol6_core::motion::tracking::TrackingMode;
use parol6_core::na::Vector3;
use parol6_core::{RobotModel, Tool};

use crate::palette::{
    MEASURE_ATTAINED, MEASURE_COMMANDED, MEASURE_CUBE, MEASURE_JOINTS, MEASURE_PLANE, MEASURE_SIMULATION, REPORT_GRID,
    REPORT_INK, REPORT_PAPER, hex,
};
use svg::{Item3, Series, Style, escape, scene_3d, xy_plot};

/// How the test was set up.
#[derive(Debug, Clone, PartialEq)]
pub struct Setup {
    /// Robot name.
    pub robot: String,
    /// Tool on the flange.
    pub tool: Tool,
    /// What was measured ("simulation", "robot on /dev/ttyACM0", "measurement file …").
    pub source: String,
    /// Speed fraction.
    pub speed_fraction: f64,
    /// Cycles.
    pub cycles: usize,
    /// Date and time, UTC.
    pub date_utc: String,
    /// The cube.
    pub cube: TestCube,
}

/// The pose test's part of a report.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseReport {
    /// Figures of the run measured.
    pub figures: PoseTestFigures,
    /// Its attained poses.
    pub samples: Vec<PoseSample>,
    /// The simulation's figures and poses, when it ran beside the robot.
    pub simulation: Option<(PoseTestFigures, Vec<PoseSample>)>,
}

/// One path test's part of a report.
#[derive(Debug, Clone, PartialEq)]
pub struct PathReport {
    /// Which path.
    pub kind: PathKind,
    /// Its cube.
    pub cube: TestCube,
    /// Figures of the run measured.
    pub figures: PathFigures,
    /// Commanded TCP path, mm.
    pub commanded: Vec<[f64; 3]>,
    /// Attained TCP path per cycle, mm.
    pub attained: Vec<Vec<[f64; 3]>>,
    /// Per cycle: (time, s; distance from the commanded path, mm).
    pub deviation: Vec<Vec<[f64; 2]>>,
    /// The simulation beside the robot: its figures, its first attained cycle, and the
    /// robot − simulation difference over time.
    pub simulation: Option<(PathFigures, Vec<[f64; 3]>, Vec<DiffSample>)>,
    /// The tracking mode the path ran in (`path-test --compare-tracking` runs every one).
    pub tracking: Option<TrackingMode>,
}

impl PathReport {
    /// Names the tracking mode the path ran in.
    pub fn with_tracking(mut self, mode: TrackingMode) -> Self {
        self.tracking = Some(mode);
        self
    }

    /// The path's name, with its tracking mode when it has one ("line, lead").
    fn title(&self) -> String {
        match self.tracking {
            Some(m) => format!("{}, tracking {}", self.kind.name(), m.name()),
            None => self.kind.name().to_string(),
        }
    }

    /// The report part of a recording (and of the simulation's recording of the same test).
    pub fn new(
        model: &RobotModel,
        run: &PathRecording,
        simulation: Option<&PathRecording>,
    ) -> Result<Self, PathFigureError> {
        let figures = run.figures(model)?;
        let (commanded, attained) = run.tcp_paths_mm(model);
        let reference: Vec<Vector3<f64>> = commanded.iter().map(|p| Vector3::from(*p)).collect();
        let deviation = run
            .cycles
            .iter()
            .zip(&attained)
            .map(|(c, a)| c.iter().zip(a).map(|(s, p)| [s.t_s, nearest_on(&reference, &Vector3::from(*p)).0]).collect())
            .collect();
        let simulation = match simulation {
            Some(sim) => {
                let f = sim.figures(model)?;
                let first = sim.tcp_paths_mm(model).1.into_iter().next().unwrap_or_default();
                Some((f, first, compare::path_difference(model, run, sim)))
            }
            None => None,
        };
        Ok(Self {
            kind: run.plan.kind,
            cube: run.plan.cube,
            figures,
            commanded,
            attained,
            deviation,
            simulation,
            tracking: None,
        })
    }
}

/// A whole report.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// Set-up.
    pub setup: Setup,
    /// The pose test, if run.
    pub pose: Option<PoseReport>,
    /// The path tests run.
    pub paths: Vec<PathReport>,
}

/// The tool whose TCP offset the model has (none when no tool matches).
pub fn tool_of_model(model: &RobotModel) -> Tool {
    let offset = model.tool.translation.vector;
    Tool::ALL.iter().copied().find(|t| (offset - Vector3::from(t.tcp_offset_m())).norm() < 1e-9).unwrap_or(Tool::None)
}

/// The current date and time, UTC, as `YYYY-MM-DD HH:MM:SS UTC`.
pub fn now_utc() -> String {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    date_from_unix(secs)
}

/// `YYYY-MM-DD HH:MM:SS UTC` of a Unix time (the civil-from-days algorithm).
pub fn date_from_unix(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02} UTC", rem / 3600, rem % 3600 / 60, rem % 60)
}

fn num(v: Option<f64>, decimals: usize) -> String {
    v.map_or_else(|| "–".to_string(), |v| format!("{v:.decimals$}"))
}

/// The report as one HTML document.
pub fn html(report: &Report) -> String {
    let mut h = String::new();
    let s = &report.setup;
    let _ = write!(
        h,
        "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>PAROL6 ISO 9283 measurement</title>\
         <style>body{{font-family:sans-serif;color:{ink};background:{paper};margin:24px;max-width:1120px}}\
         table{{border-collapse:collapse;margin:8px 0}}td,th{{border:1px solid {grid};padding:3px 8px;text-align:right}}\
         th{{background:{grid}}}#setup td{{text-align:left}}td:first-child,th:first-child{{text-align:left}}.plots{{display:flex;flex-wrap:wrap;gap:8px}}\
         h2{{margin-top:28px}}</style></head><body>",
        ink = hex(REPORT_INK),
        paper = hex(REPORT_PAPER),
        grid = hex(REPORT_GRID)
    );
    h.push_str("<h1>PAROL6 ISO 9283 measurement</h1>");
    let c = &s.cube;
    let rows = [
        ("Robot", s.robot.clone()),
        ("Tool", s.tool.name().to_string()),
        ("Measured on", s.source.clone()),
        (
            "Cube",
            format!(
                "centre ({:.1}, {:.1}, {:.1}) mm, edge {:.1} mm, tool roll/pitch/yaw ({:.1}, {:.1}, {:.1})°",
                c.center_mm[0],
                c.center_mm[1],
                c.center_mm[2],
                c.edge_mm,
                c.orientation_rpy_deg[0],
                c.orientation_rpy_deg[1],
                c.orientation_rpy_deg[2]
            ),
        ),
        ("Speed", format!("{:.0} % of the rated speed", 100.0 * s.speed_fraction)),
        ("Cycles", s.cycles.to_string()),
        ("Date", s.date_utc.clone()),
        ("App version", format!("PAROL6 Studio {}", env!("CARGO_PKG_VERSION"))),
    ];
    h.push_str("<h2>Set-up</h2><table id=\"setup\">");
    for (k, v) in rows {
        let _ = write!(h, "<tr><th>{k}</th><td>{}</td></tr>", escape(&v));
    }
    h.push_str("</table>");
    if let Some(pose) = &report.pose {
        pose_section(&mut h, pose);
    }
    h.push_str("<h2>Cube and test poses</h2><div class=\"plots\">");
    h.push_str(&scene_3d("Cube, diagonal plane and test poses (mm)", &cube_items(c, &report.paths)));
    h.push_str("</div>");
    tracking::comparison_table(&mut h, &report.paths);
    for path in &report.paths {
        path_section(&mut h, path);
    }
    fk_section(&mut h, c);
    h.push_str("</body></html>\n");
    h
}

fn figure_row(h: &mut String, label: &str, f: &parol6_core::measure::pose_figures::PoseFigures) {
    let _ = write!(h, "<tr><td>{label}</td>");
    for v in [f.ap_p_mm, f.ap_x_mm, f.ap_y_mm, f.ap_z_mm, f.rp_l_mm] {
        let _ = write!(h, "<td>{v:.4}</td>");
    }
    for v in [f.ap_a_deg, f.ap_b_deg, f.ap_c_deg, f.rp_a_deg, f.rp_b_deg, f.rp_c_deg] {
        let _ = write!(h, "<td>{v:.4}</td>");
    }
    let _ = write!(h, "<td>{}</td></tr>", f.cycles);
}

fn pose_section(h: &mut String, pose: &PoseReport) {
    h.push_str(
        "<h2>Pose accuracy and repeatability</h2><table id=\"figures\"><tr><th>Pose</th><th>AP<sub>p</sub> mm</th>\
         <th>AP<sub>x</sub> mm</th><th>AP<sub>y</sub> mm</th><th>AP<sub>z</sub> mm</th><th>RP<sub>l</sub> mm</th>\
         <th>AP<sub>a</sub> °</th><th>AP<sub>b</sub> °</th><th>AP<sub>c</sub> °</th><th>RP<sub>a</sub> °</th>\
         <th>RP<sub>b</sub> °</th><th>RP<sub>c</sub> °</th><th>n</th></tr>",
    );
    for f in &pose.figures.poses {
        figure_row(h, &f.name, f);
    }
    if let Some((sim, _)) = &pose.simulation {
        for f in &sim.poses {
            figure_row(h, &format!("{} (simulation)", f.name), f);
        }
    }
    h.push_str("</table>");
    let _ = write!(
        h,
        "<table id=\"distance\"><tr><th>Distance P2–P4</th><th>AD<sub>p</sub> mm</th><th>RD mm</th></tr>\
         <tr><td>measured</td><td>{}</td><td>{}</td></tr>",
        num(pose.figures.ad_p_mm, 4),
        num(pose.figures.rd_mm, 4)
    );
    if let Some((sim, _)) = &pose.simulation {
        let _ = write!(h, "<tr><td>simulation</td><td>{}</td><td>{}</td></tr>", num(sim.ad_p_mm, 4), num(sim.rd_mm, 4));
    }
    h.push_str(
        "</table><p>AP: mean attained minus commanded; RP<sub>l</sub> = l̄ + 3·S<sub>l</sub>, RP<sub>a/b/c</sub> = \
         3·S (S with n − 1); a, b, c are the rotations about x, y, z (roll, pitch, yaw).</p>",
    );
    h.push_str("<h2>Attained positions per pose</h2><p>Attained minus commanded position, mm; the cross is the commanded pose.</p><div class=\"plots\">");
    for (i, name) in POSE_NAMES.iter().enumerate() {
        for (a, b, axes) in [(0, 1, "x–y"), (0, 2, "x–z")] {
            let series = |samples: &[PoseSample], label: &str, color| Series {
                label: label.into(),
                color,
                points: samples
                    .iter()
                    .filter(|s| s.pose == i)
                    .map(|s| {
                        let d = |k: usize| s.attained.position_mm[k] - s.commanded.position_mm[k];
                        [d(a), d(b)]
                    })
                    .collect(),
                style: Style::Dots,
            };
            let mut all = vec![
                Series {
                    label: "commanded".into(),
                    color: MEASURE_COMMANDED,
                    points: vec![[0.0, 0.0]],
                    style: Style::Crosses,
                },
                series(&pose.samples, "attained", MEASURE_ATTAINED),
            ];
            if let Some((_, sim)) = &pose.simulation {
                all.push(series(sim, "simulation", MEASURE_SIMULATION));
            }
            if all[1].points.is_empty() {
                continue;
            }
            let (la, lb) = (["Δx", "Δy", "Δz"][a], ["Δx", "Δy", "Δz"][b]);
            h.push_str(&xy_plot(&format!("{name}: {axes}"), &format!("{la}, mm"), &format!("{lb}, mm"), &all, true));
        }
    }
    h.push_str("</div>");
}

fn cube_items(c: &TestCube, paths: &[PathReport]) -> Vec<Item3> {
    let corners = c.corners_mm();
    let mut items: Vec<Item3> =
        [(0, 1), (1, 3), (3, 2), (2, 0), (4, 5), (5, 7), (7, 6), (6, 4), (0, 4), (1, 5), (2, 6), (3, 7)]
            .iter()
            .map(|&(a, b)| Item3 {
                label: String::new(),
                color: MEASURE_CUBE,
                points: vec![corners[a], corners[b]],
                closed: false,
            })
            .collect();
    items.push(Item3 {
        label: String::new(),
        color: MEASURE_PLANE,
        points: c.plane_corners_mm().to_vec(),
        closed: true,
    });
    for p in paths {
        items.push(Item3 {
            label: String::new(),
            color: MEASURE_COMMANDED,
            points: p.commanded.clone(),
            closed: false,
        });
    }
    for (name, p) in POSE_NAMES.iter().zip(c.pose_positions_mm()) {
        items.push(Item3 { label: (*name).to_string(), color: MEASURE_ATTAINED, points: vec![p], closed: false });
    }
    items
}

/// Coordinates of a point in the cube's diagonal plane (u along x, v along (0, 1, 1)/√2), mm.
fn in_plane(c: &TestCube, p: &[f64; 3]) -> [f64; 2] {
    let [u, v, _] = TestCube::plane_axes();
    let d = Vector3::from(*p) - Vector3::from(c.center_mm);
    [d.dot(&u), d.dot(&v)]
}

/// A cornering deviation, mm, or a dash for a path without corners.
pub(crate) fn corner_cell(v: Option<f64>) -> String {
    v.map_or_else(|| "—".to_string(), |v| format!("{v:.4}"))
}

fn path_section(h: &mut String, p: &PathReport) {
    let f = &p.figures;
    let name = p.title();
    let id = match p.tracking {
        Some(m) => format!("{}-{}", p.kind.name(), m.name()),
        None => p.kind.name().to_string(),
    };
    let _ = write!(
        h,
        "<h2>Path: {name}</h2><table class=\"path-figures\" id=\"path-{id}\"><tr><th>Run</th><th>AT<sub>p</sub> mm</th><th>RT<sub>p</sub> mm</th>\
         <th>max deviation mm</th><th>RMS deviation mm</th><th>CR mm</th><th>CO mm</th><th>points</th><th>cycles</th></tr>"
    );
    let row = |h: &mut String, label: &str, f: &PathFigures| {
        let _ = write!(
            h,
            "<tr><td>{label}</td><td>{:.4}</td><td>{:.4}</td><td>{:.4}</td><td>{:.4}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            f.at_p_mm,
            f.rt_p_mm,
            f.max_deviation_mm,
            f.rms_deviation_mm,
            corner_cell(f.cr_mm),
            corner_cell(f.co_mm),
            f.points,
            f.cycles
        );
    };
    row(h, "measured", f);
    if let Some((sf, _, _)) = &p.simulation {
        row(h, "simulation", sf);
    }
    h.push_str("</table><div class=\"plots\">");
    // the paths in the diagonal plane, and the deviation over time
    let c = p.cube;
    let mut plane = vec![Series {
        label: "commanded".into(),
        color: MEASURE_COMMANDED,
        points: p.commanded.iter().map(|q| in_plane(&c, q)).collect(),
        style: Style::Line,
    }];
    if let Some(first) = p.attained.first() {
        plane.push(Series {
            label: "attained (cycle 1)".into(),
            color: MEASURE_ATTAINED,
            points: first.iter().map(|q| in_plane(&c, q)).collect(),
            style: Style::Line,
        });
    }
    if let Some((_, sim, _)) = &p.simulation {
        plane.push(Series {
            label: "simulation (cycle 1)".into(),
            color: MEASURE_SIMULATION,
            points: sim.iter().map(|q| in_plane(&c, q)).collect(),
            style: Style::Line,
        });
    }
    h.push_str(&xy_plot(&format!("{name}: path in the diagonal plane"), "u (along x), mm", "v, mm", &plane, true));
    let dev: Vec<Series> = p
        .deviation
        .iter()
        .enumerate()
        .map(|(i, d)| Series {
            label: if i == 0 { "attained, every cycle".into() } else { String::new() },
            color: MEASURE_ATTAINED,
            points: d.clone(),
            style: Style::Line,
        })
        .collect();
    h.push_str(&xy_plot(
        &format!("{name}: deviation from the commanded path"),
        "time since the cycle's start, s",
        "deviation, mm",
        &dev,
        false,
    ));
    if let Some((_, _, diff)) = &p.simulation {
        let first: Vec<&DiffSample> = diff.iter().filter(|d| d.cycle == 1).collect();
        let tcp = Series {
            label: "TCP distance".into(),
            color: MEASURE_ATTAINED,
            points: first.iter().map(|d| [d.t_s, d.tcp_mm]).collect(),
            style: Style::Line,
        };
        h.push_str(&xy_plot(&format!("{name}: robot − simulation, TCP (cycle 1)"), "time, s", "mm", &[tcp], false));
        let joints: Vec<Series> = (0..first.first().map_or(0, |d| d.joint_deg.len()))
            .map(|j| Series {
                label: format!("J{}", j + 1),
                color: MEASURE_JOINTS[j % MEASURE_JOINTS.len()],
                points: first.iter().map(|d| [d.t_s, d.joint_deg[j]]).collect(),
                style: Style::Line,
            })
            .collect();
        h.push_str(&xy_plot(
            &format!("{name}: robot − simulation per joint (cycle 1)"),
            "time, s",
            "deg",
            &joints,
            false,
        ));
    }
    h.push_str("</div>");
}

fn fk_section(h: &mut String, c: &TestCube) {
    h.push_str("<h2>Commanded poses (4×4, base frame, mm)</h2><div class=\"plots\">");
    for (name, pose) in POSE_NAMES.iter().zip(c.poses()) {
        let m = matrix4_rows(&pose.isometry());
        let _ = write!(h, "<table class=\"fk\"><tr><th colspan=\"4\">{name}</th></tr>");
        for (r, row) in m.iter().enumerate() {
            h.push_str("<tr>");
            for (k, v) in row.iter().enumerate() {
                // the translation column in mm
                let v = if k == 3 && r < 3 { v * 1000.0 } else { *v };
                let _ = write!(h, "<td>{:.4}</td>", if v.abs() < 5e-13 { 0.0 } else { v });
            }
            h.push_str("</tr>");
        }
        h.push_str("</table>");
    }
    h.push_str("</div>");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_follow_the_civil_calendar() {
        assert_eq!(date_from_unix(0), "1970-01-01 00:00:00 UTC");
        assert_eq!(date_from_unix(951_782_400), "2000-02-29 00:00:00 UTC");
        assert_eq!(date_from_unix(1_700_000_000), "2023-11-14 22:13:20 UTC");
    }
}
