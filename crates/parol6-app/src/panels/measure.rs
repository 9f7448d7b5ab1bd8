//! Right panel: ISO 9283 measurement. Set up the test cube (centre, edge, tool orientation),
//! cycles and speed; the cube is pre-flight checked from where the arm is and drawn in the 3D
//! view (green: every pose reachable, red: refused, the refusal named here). Run the pose test
//! on the active backend (simulation or robot) with a progress bar and ABORT, watch the
//! figures grow with every cycle, save the HTML report, and compare the last simulation run
//! with the last robot run in the plot (attained − commanded per pose visit).
//!
//! The measurement runs on the core's driver thread; the app starts, aborts and collects it
//! ([`AppCommand::StartMeasurement`], [`AppCommand::AbortMeasurement`]) and owns it
//! (`AppState::measurement`); this panel reads its progress and finished runs.

use std::sync::Arc;

use eframe::egui;
use egui_plot::{Legend, Line, Plot, PlotPoints};

use parol6_core::RobotModel;
use parol6_core::measure::pose_figures::{self, PoseSample, PoseTestFigures};
use parol6_core::measure::{PoseTestPlan, TestCube};
use parol6_core::motion::StateSource;

use super::entry::{self, EntryEvent};
use super::{AppCommand, Panel, PanelContext};
use crate::app::measurement::FinishedMeasurement;
use crate::palette;
use crate::report::{self, PoseReport, Report, Setup};
use crate::viewport::{PathOverlay, PathPointStatus};

/// The measurement panel.
pub struct MeasurePanel {
    /// The test (cube, cycles, speed, settling).
    pub plan: PoseTestPlan,
    /// Draw the cube in the 3D view.
    pub show_cube: bool,
    /// Where "Save report" writes.
    pub report_path: String,
    preflight: Option<(PoseTestPlan, Vec<f64>, Result<(), String>)>,
    overlay: Option<Arc<PathOverlay>>,
    /// The outcome of "Save report" (text, true when an error or a question), until the next
    /// run starts.
    message: Option<(String, bool)>,
    /// "Save report" onto an existing file asks first (the same button again replaces it).
    replace_ask: super::replace_ask::ReplaceAsk,
}

impl Default for MeasurePanel {
    fn default() -> Self {
        let cube = TestCube::DEFAULT;
        Self {
            plan: PoseTestPlan { cycles: 10, ..PoseTestPlan::new(cube) },
            show_cube: true,
            report_path: "parol6-iso9283.html".into(),
            preflight: None,
            overlay: None,
            message: None,
            replace_ask: Default::default(),
        }
    }
}

impl MeasurePanel {
    /// The cube for the 3D view (coloured by the pre-flight), when shown.
    pub fn overlay(&self) -> Option<Arc<PathOverlay>> {
        if self.show_cube { self.overlay.clone() } else { None }
    }

    /// The joints the cube's pre-flight shown was made from (the live arm's; kept during
    /// replay), once made.
    pub fn preflight_from(&self) -> Option<&[f64]> {
        self.preflight.as_ref().map(|(_, q, _)| q.as_slice())
    }

    fn refresh_preflight(&mut self, model: &RobotModel, start_q: &[f64]) {
        if self.preflight.as_ref().is_some_and(|(p, q, _)| *p == self.plan && q.as_slice() == start_q) {
            return;
        }
        let result = self.plan.preflight(model, start_q).map_err(|e| e.to_string());
        let status = if result.is_ok() { PathPointStatus::Ok } else { PathPointStatus::Error };
        self.overlay = Some(Arc::new(cube_overlay(&self.plan.cube, status)));
        self.preflight = Some((self.plan, start_q.to_vec(), result));
    }

    fn save_report(&mut self, model: &RobotModel, finished: &[FinishedMeasurement]) {
        let Some(last) = finished.last() else { return };
        let path = crate::typed_path::typed_path(&self.report_path);
        if !self.replace_ask.may_write(&path) {
            self.message = self.replace_ask.question(&path, "Save report again").map(|q| (q, true));
            return;
        }
        let figures = match pose_figures::compute(&last.samples) {
            Ok(f) => f,
            Err(e) => {
                self.message = Some((format!("no report: {e}"), true));
                return;
            }
        };
        // the other backend's run, overlaid (simulation beside the robot)
        let simulation = finished
            .iter()
            .find(|f| f.source == StateSource::Simulation && last.source == StateSource::Robot)
            .and_then(|f| pose_figures::compute(&f.samples).ok().map(|fig| (fig, f.samples.clone())));
        let cycles = last.samples.iter().map(|s| s.cycle).max().unwrap_or(0) as usize;
        let setup = Setup {
            robot: if model.is_parol6 { "PAROL6".into() } else { model.name.clone() },
            tool: report::tool_of_model(model),
            source: last.backend.clone(),
            speed_fraction: self.plan.speed_fraction,
            cycles,
            date_utc: report::now_utc(),
            cube: self.plan.cube,
        };
        let html = report::html(&Report {
            setup,
            pose: Some(PoseReport { figures, samples: last.samples.clone(), simulation }),
            paths: Vec::new(),
        });
        self.message = Some(match parol6_core::fsio::write_atomic_bytes(&path, html.as_bytes()) {
            Ok(()) => (format!("report saved to {}", path.display()), false),
            Err(e) => (e.to_string(), true),
        });
    }
}

/// The cube's edges and its diagonal plane as line strips (m), all in one status colour.
pub fn cube_overlay(cube: &TestCube, status: PathPointStatus) -> PathOverlay {
    let c = cube.corners_mm();
    let m = |p: [f64; 3]| [(p[0] / 1000.0) as f32, (p[1] / 1000.0) as f32, (p[2] / 1000.0) as f32];
    let mut o = PathOverlay::default();
    let edges = [(0, 1), (1, 3), (3, 2), (2, 0), (4, 5), (5, 7), (7, 6), (6, 4), (0, 4), (1, 5), (2, 6), (3, 7)];
    for (a, b) in edges {
        o.break_strip();
        o.push(m(c[a]), status);
        o.push(m(c[b]), status);
    }
    let plane = cube.plane_corners_mm();
    o.break_strip();
    for p in plane.iter().chain(std::iter::once(&plane[0])) {
        o.push(m(*p), status);
    }
    o
}

fn figures_grid(ui: &mut egui::Ui, f: &PoseTestFigures) {
    // scrolls sideways where the column is narrower than the table
    egui::ScrollArea::horizontal().id_salt("iso9283-figures-scroll").show(ui, |ui| figures_table(ui, f));
    let opt = |v: Option<f64>| v.map_or_else(|| "–".into(), |v| format!("{v:.4}"));
    ui.label(format!("P2–P4: AD_p {} mm, RD {} mm", opt(f.ad_p_mm), opt(f.rd_mm)));
}

fn figures_table(ui: &mut egui::Ui, f: &PoseTestFigures) {
    egui::Grid::new("iso9283-figures").striped(true).show(ui, |ui| {
        for h in ["pose", "AP_p mm", "RP_l mm", "AP_a °", "AP_b °", "AP_c °", "n"] {
            ui.strong(h);
        }
        ui.end_row();
        for p in &f.poses {
            ui.label(&p.name);
            for v in [p.ap_p_mm, p.rp_l_mm, p.ap_a_deg, p.ap_b_deg, p.ap_c_deg] {
                ui.monospace(format!("{v:.4}"));
            }
            ui.label(p.cycles.to_string());
            ui.end_row();
        }
    });
}

/// One number field of the set-up, in `unit` (typed units converted to it): a committed value
/// inside `range` (and whole when `whole`) is stored (true); any other, or text that is not a
/// number, leaves the value and adds the reason to `refused` ([`entry::in_range`]).
fn setup_field(
    ui: &mut egui::Ui,
    name: &str,
    value: &mut f64,
    (range, whole): ((f64, f64), bool),
    decimals: usize,
    unit: &str,
    refused: &mut Vec<String>,
) -> bool {
    let (_, event) = entry::ranged_entry(ui, name, *value, (decimals, 64.0), ("", unit), range);
    match event {
        Some(EntryEvent::Committed(v)) => match entry::in_range(name, v, range, unit, whole) {
            Ok(v) => {
                *value = v;
                true
            }
            Err(e) => {
                let u = if unit.is_empty() { String::new() } else { format!(" {unit}") };
                refused.push(format!("{e}; it stays {}{u}", entry::fmt_fixed(*value, decimals)));
                false
            }
        },
        Some(EntryEvent::Invalid(e)) => {
            refused.push(format!("{name}: {e}"));
            false
        }
        None => false,
    }
}

impl Panel for MeasurePanel {
    fn title(&self) -> &'static str {
        "Measurement (ISO 9283)"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.heading(self.title());
        let measurement = &ctx.app.measurement;
        let running = measurement.running();
        let unit = ctx.settings.unit;
        let refused = ui.add_enabled_ui(!running, |ui| self.setup_ui(ui, unit)).inner;
        for message in refused {
            ctx.error(message);
        }
        // the test runs from the live arm: during replay (the shown state is the recording at
        // the cursor, and motion is refused) the live arm's pre-flight is kept, so neither
        // opening, scrubbing nor closing a recording plans the cube again in the frame
        if !running && !ctx.robot.moving && !ctx.app.replaying() {
            self.refresh_preflight(ctx.model, &ctx.robot.commanded.q.clone());
        }
        match self.preflight.as_ref().map(|p| &p.2) {
            Some(Ok(())) => {
                ui.colored_label(palette::rgb(palette::PATH_OK), "pre-flight: every pose reachable");
            }
            Some(Err(why)) => {
                ui.colored_label(palette::rgb(palette::ERROR_TEXT), why);
            }
            None => {}
        }
        let ok = matches!(self.preflight.as_ref().map(|p| &p.2), Some(Ok(())));
        ui.horizontal(|ui| {
            let refused = ctx.motion_refused();
            let run =
                ui.add_enabled(ok && !running && !ctx.robot.moving && refused.is_none(), egui::Button::new("Run test"));
            let run = match refused {
                Some(why) => run.on_disabled_hover_text(why),
                None => run,
            };
            if run.clicked() {
                self.message = None;
                ctx.send(AppCommand::StartMeasurement(self.plan));
            }
            if ui.add_enabled(running, egui::Button::new("Abort")).clicked() {
                ctx.send(AppCommand::AbortMeasurement);
            }
            let finished = ctx.app.measurement.finished();
            if ui.add_enabled(!running && !finished.is_empty(), egui::Button::new("Save report")).clicked() {
                self.save_report(ctx.model, finished);
            }
        });
        ui.horizontal(|ui| {
            ui.label("Report");
            ui.add(egui::TextEdit::singleline(&mut self.report_path).desired_width(200.0));
        });
        let measurement = &ctx.app.measurement;
        let live = measurement.progress().filter(|_| running);
        // the progress and the outcome in a box of a fixed height: a longer or shorter message
        // (a failed save, then a saved one) moved everything below it under the pointer
        let status_h = 3.0 * ui.spacing().interact_size.y;
        let message = self.message.as_ref().or(measurement.outcome());
        super::fixed_box::fixed_height(ui, "measure-status", status_h, |ui| {
            if let Some(p) = &live {
                let text = format!("{:.0} % {}", 100.0 * p.fraction, p.describe());
                ui.add(crate::theme::bar(p.fraction as f32).text(text));
                ui.ctx().request_repaint_after(std::time::Duration::from_millis(100));
            }
            if let Some((text, error)) = message {
                let color = if *error { palette::ERROR_TEXT } else { palette::PATH_OK };
                ui.add(egui::Label::new(egui::RichText::new(text).color(palette::rgb(color))).wrap());
            }
        });
        let samples: Option<&[PoseSample]> = match &live {
            Some(p) => Some(&p.attained),
            None => measurement.finished().last().map(|f| f.samples.as_slice()),
        };
        if let Some(f) = samples.and_then(|s| pose_figures::compute(s).ok()) {
            figures_grid(ui, &f);
        }
        self.plot(ui, live.as_ref().map(|p| p.attained.as_slice()), measurement.finished());
    }
}

impl MeasurePanel {
    /// The cube and the run settings. Fixed-width fields in a grid: the panel keeps its width
    /// whatever the values (a wider panel would slide under the 3D view's pointer area). Typed
    /// like every number field (units converted, `,` as decimal mark); a value outside its range
    /// or not a number is refused with a message naming the field and the range (they were drag
    /// values, which clamped what was typed without a word). Returns those messages.
    fn setup_ui(&mut self, ui: &mut egui::Ui, unit: super::AngleUnit) -> Vec<String> {
        let mut refused = Vec::new();
        let c = &mut self.plan.cube;
        ui.spacing_mut().slider_width = 110.0;
        let angle = unit.suffix().trim();
        egui::Grid::new("iso9283-setup").num_columns(4).spacing([4.0, 2.0]).show(ui, |ui| {
            ui.label("");
            for h in ["x / roll", "y / pitch", "z / yaw"] {
                ui.weak(h);
            }
            ui.end_row();
            ui.label("Centre mm");
            for (v, axis) in c.center_mm.iter_mut().zip(["centre x", "centre y", "centre z"]) {
                setup_field(ui, axis, v, ((-1000.0, 1000.0), false), 2, "mm", &mut refused);
            }
            ui.end_row();
            // the tool orientation in the chosen angle unit, kept in degrees
            ui.label(format!("Tool RPY {angle}"));
            let half_turn = unit.from_rad(std::f64::consts::PI);
            for (v, axis) in c.orientation_rpy_deg.iter_mut().zip(["tool roll", "tool pitch", "tool yaw"]) {
                let mut shown = unit.from_rad(v.to_radians());
                if setup_field(
                    ui,
                    axis,
                    &mut shown,
                    ((-half_turn, half_turn), false),
                    unit.decimals(),
                    angle,
                    &mut refused,
                ) {
                    *v = unit.to_rad(shown).to_degrees();
                }
            }
            ui.end_row();
            ui.label("Edge mm");
            setup_field(ui, "edge", &mut c.edge_mm, ((1.0, 500.0), false), 2, "mm", &mut refused);
            ui.label("Cycles");
            let mut cycles = self.plan.cycles as f64;
            if setup_field(ui, "cycles", &mut cycles, ((2.0, 1000.0), true), 0, "", &mut refused) {
                self.plan.cycles = cycles as usize;
            }
            ui.end_row();
        });
        ui.horizontal(|ui| {
            ui.label("Speed");
            let (_, speed_refused) =
                entry::typed_slider(ui, "test speed", &mut self.plan.speed_fraction, 0.01..=1.0, ("", ""), 2);
            refused.extend(speed_refused);
            ui.checkbox(&mut self.show_cube, "Cube in 3D");
        });
        refused
    }

    /// Attained − commanded position per pose visit, mm: the live run, and the last finished
    /// run on each backend (simulation and robot overlaid).
    fn plot(&self, ui: &mut egui::Ui, live: Option<&[PoseSample]>, finished: &[FinishedMeasurement]) {
        let series = |s: &[PoseSample]| -> Vec<[f64; 2]> {
            s.iter()
                .enumerate()
                .map(|(i, p)| {
                    let d: f64 = (0..3).map(|k| (p.attained.position_mm[k] - p.commanded.position_mm[k]).powi(2)).sum();
                    [i as f64 + 1.0, d.sqrt()]
                })
                .collect()
        };
        if live.is_none() && finished.is_empty() {
            return;
        }
        Plot::new("iso9283-plot")
            .height(140.0)
            .legend(Legend::default())
            .custom_y_axes(vec![super::plot_axis::value_axis("error (mm)".into())])
            .y_grid_spacer(super::plot_axis::value_marks)
            .show(ui, |plot| {
                for f in finished {
                    let (name, color) = match f.source {
                        StateSource::Simulation => ("simulation", palette::MEASURE_SIMULATION),
                        StateSource::Robot => ("robot", palette::MEASURE_ATTAINED),
                    };
                    plot.line(Line::new(name, PlotPoints::from(series(&f.samples))).color(palette::rgb(color)));
                }
                if let Some(s) = live {
                    plot.line(Line::new("running", PlotPoints::from(series(s))).color(palette::rgb(palette::PATH_OK)));
                }
            });
        ui.small("attained − commanded position per pose visit, mm");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cube_overlay_has_twelve_edges_and_the_plane() {
        let o = cube_overlay(&MeasurePanel::default().plan.cube, PathPointStatus::Error);
        assert_eq!(o.len(), 12 * 2 + 5);
        assert_eq!(o.worst(), Some(PathPointStatus::Error));
    }
}
