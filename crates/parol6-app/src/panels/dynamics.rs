//! Lower panel "Dynamics" (View menu), the two dynamics windows of the original GUI:
//!
//! - inverse dynamics of the program panel's program from the current pose, before it runs:
//!   the torque of every joint vs time (egui_plot) with each joint's limit as dashed lines, the
//!   peaks against the limits, and every stretch over a limit listed (the core's
//!   [`program_torques`]); recomputed on a worker thread when the program or the start pose
//!   changes while the arm stands still (a G-code file of 200 000 steps takes seconds to
//!   plan: the window keeps drawing and says "computing…");
//! - forward dynamics: torque profiles run on the simulation ([`super::torque_form`]);
//! - during replay, instead of both: the joint torques along the recorded motion, with those at
//!   the cursor (`dynamics/replay.rs`), headed REPLAY.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use eframe::egui;
use egui_plot::{HLine, Line, LineStyle, Plot, PlotPoints, VLine};
use parol6_core::RobotModel;
use parol6_core::program::Program;
use parol6_core::program::compile::{CompileOptions, CompileStop, compile_observed};
use parol6_core::program::torques::{ProgramTorques, program_torques, torque_limits_nm};

use super::torque_form::TorqueForm;
use super::{Panel, PanelContext};
use crate::palette;

mod replay;

/// Points drawn per joint at most (min / max per bucket beyond that).
const MAX_POINTS_PER_LINE: usize = 2000;
/// Stretches over a limit listed (the rest are counted).
const WARNINGS_SHOWN: usize = 6;
/// Height of the torque plot, points.
const PLOT_HEIGHT: f32 = 180.0;

/// What was computed, for which program and start pose.
struct Computed {
    program: Arc<Program>,
    start_q: Vec<f64>,
    result: Result<ProgramTorques, String>,
    /// Decimated `[t, τ]` per joint.
    lines: Vec<Vec<[f64; 2]>>,
}

/// An analysis running on a worker thread.
struct Pending {
    program: Arc<Program>,
    start_q: Vec<f64>,
    /// The worker's result (once).
    result: crossbeam_channel::Receiver<Computed>,
    /// Set when a newer analysis supersedes this one: the worker stops at its next step.
    cancel: Arc<AtomicBool>,
}

impl Pending {
    fn is_for(&self, program: &Arc<Program>, start_q: &[f64]) -> bool {
        Arc::ptr_eq(&self.program, program) && self.start_q == start_q
    }
}

/// The dynamics panel.
pub struct DynamicsPanel {
    program: Arc<Program>,
    computed: Option<Computed>,
    /// The analysis being computed, off the UI thread.
    pending: Option<Pending>,
    /// The forward-dynamics form.
    pub form: TorqueForm,
    /// The analysis of the open recording (replay).
    replay: replay::ReplayAnalysis,
    /// The height the last drawn analysis took and the width it was drawn at: while a new one
    /// is computed the section keeps that height, so the forward-dynamics form below it does not
    /// jump away from the pointer each time the arm stops (trial10).
    shown_height: Option<(f32, f32)>,
}

impl DynamicsPanel {
    /// The panel for a robot of `joints` joints.
    pub fn new(joints: usize) -> Self {
        Self {
            program: Arc::new(Program::default()),
            computed: None,
            pending: None,
            form: TorqueForm::new(joints),
            replay: Default::default(),
            shown_height: None,
        }
    }

    /// The program to analyse (the program panel's; cheap, compared by pointer).
    pub fn set_program(&mut self, program: &Arc<Program>) {
        if !Arc::ptr_eq(&self.program, program) {
            self.program = Arc::clone(program);
        }
    }

    /// The torques of the last analysis (tests and the panel).
    pub fn torques(&self) -> Option<&ProgramTorques> {
        self.computed.as_ref().and_then(|c| c.result.as_ref().ok())
    }

    /// Forgets the analysis of the recording (it was closed) and hands back what it held (the
    /// recording and its torques), for the app to free off the UI thread; a running analysis
    /// is cancelled.
    pub fn forget_replay(&mut self) -> impl Send + 'static {
        self.replay.take()
    }

    /// True while an analysis (of the program, or of the open recording) runs on a worker.
    pub fn computing(&self) -> bool {
        self.pending.is_some() || self.replay.computing()
    }

    /// Brings the analysis up to the program and `start_q`: takes a finished worker's result,
    /// or starts a worker (never computes in the frame: a long program takes seconds).
    fn refresh(&mut self, model: &RobotModel, start_q: &[f64]) {
        if self.computed.as_ref().is_some_and(|c| Arc::ptr_eq(&c.program, &self.program) && c.start_q == start_q) {
            return;
        }
        if let Some(p) = self.pending.as_ref().filter(|p| p.is_for(&self.program, start_q)) {
            match p.result.try_recv() {
                Ok(computed) => {
                    self.computed = Some(computed);
                    self.pending = None;
                }
                Err(crossbeam_channel::TryRecvError::Empty) => {}
                Err(crossbeam_channel::TryRecvError::Disconnected) => {
                    let error = Err("the analysis stopped without a result".to_string());
                    self.computed = Some(Computed {
                        program: Arc::clone(&p.program),
                        start_q: p.start_q.clone(),
                        result: error,
                        lines: Vec::new(),
                    });
                    self.pending = None;
                }
            }
            return;
        }
        if let Some(old) = self.pending.take() {
            old.cancel.store(true, Ordering::Relaxed);
        }
        let (tx, rx) = crossbeam_channel::bounded(1);
        let cancel = Arc::new(AtomicBool::new(false));
        let (program, start, stop) = (Arc::clone(&self.program), start_q.to_vec(), Arc::clone(&cancel));
        let model = model.clone();
        let work = move || {
            if let Some(computed) = analyse(&model, program, start, &stop) {
                // the panel may have moved on: nobody waits for this result then
                if tx.send(computed).is_err() {
                    tracing::debug!("a dynamics analysis finished after it was superseded");
                }
            }
        };
        let pending = Pending { program: Arc::clone(&self.program), start_q: start_q.to_vec(), result: rx, cancel };
        match crate::background::spawn("parol6-dynamics", work) {
            Ok(_) => self.pending = Some(pending),
            Err(e) => {
                let result = Err(format!("cannot start the analysis thread: {e}"));
                self.computed =
                    Some(Computed { program: pending.program, start_q: pending.start_q, result, lines: Vec::new() });
            }
        }
    }
}

/// The torques of `program` from `start_q` (on the worker); `None` once `cancel` is set.
fn analyse(model: &RobotModel, program: Arc<Program>, start_q: Vec<f64>, cancel: &AtomicBool) -> Option<Computed> {
    let compiled = compile_observed(model, &program, &start_q, CompileOptions::PREFLIGHT, &mut |_| {
        !cancel.load(Ordering::Relaxed)
    });
    let result = match compiled {
        Err(CompileStop::Cancelled) => return None,
        Err(CompileStop::Error(e)) => Err(e.to_string()),
        Ok(steps) => Ok(program_torques(model, &steps, &start_q, torque_limits_nm(model))),
    };
    let lines = match &result {
        Ok(t) => t.torques_nm.iter().map(|col| decimate(&t.time_s, col, MAX_POINTS_PER_LINE)).collect(),
        Err(_) => Vec::new(),
    };
    Some(Computed { program, start_q, result, lines })
}

/// `[t, v]` points of a series, at most about `max_points`: beyond that each bucket of samples
/// contributes its minimum and maximum in time order, so no peak is lost.
pub fn decimate(time_s: &[f64], values: &[f64], max_points: usize) -> Vec<[f64; 2]> {
    let n = time_s.len().min(values.len());
    if n <= max_points || max_points < 2 {
        return (0..n).map(|k| [time_s[k], values[k]]).collect();
    }
    let buckets = max_points / 2;
    let mut out = Vec::with_capacity(buckets * 2);
    for b in 0..buckets {
        let (lo, hi) = (b * n / buckets, ((b + 1) * n / buckets).max(b * n / buckets + 1));
        let (mut kmin, mut kmax) = (lo, lo);
        for k in lo..hi.min(n) {
            if values[k] < values[kmin] {
                kmin = k;
            }
            if values[k] > values[kmax] {
                kmax = k;
            }
        }
        let (a, c) = if kmin <= kmax { (kmin, kmax) } else { (kmax, kmin) };
        out.push([time_s[a], values[a]]);
        if c != a {
            out.push([time_s[c], values[c]]);
        }
    }
    out
}

fn joint_color(j: usize) -> egui::Color32 {
    palette::rgb(palette::PLOT_SERIES[j % palette::PLOT_SERIES.len()])
}

impl Panel for DynamicsPanel {
    fn title(&self) -> &'static str {
        "Dynamics"
    }

    fn shown(&self, ctx: &PanelContext<'_>) -> bool {
        ctx.settings.show_dynamics
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        match ctx.app.replay.as_ref() {
            Some(r) => return self.replay_ui(ui, ctx.model, r),
            None => self.replay.clear(),
        }
        let running = ctx.app.program.as_ref().is_some_and(|p| !p.state.is_finished());
        if !running && !ctx.robot.moving {
            let start = ctx.robot.commanded.q.clone();
            self.refresh(ctx.model, &start);
        }
        // wraps: in a tab or column of the lower panel at 1024 px the line was cut
        ui.horizontal_wrapped(|ui| {
            ui.heading(self.title());
            ui.label(format!("— joint torques of \"{}\" from the current pose, before it runs", self.program.name));
        });
        let (top, width) = (ui.cursor().top(), ui.available_width());
        match self.computed.as_ref().map(|c| (&c.result, &c.lines)) {
            _ if self.pending.is_some() => {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.weak("computing the joint torques…");
                });
                ui.ctx().request_repaint_after(std::time::Duration::from_millis(100));
                // the last analysis's height kept: the form below stays where it was
                if let Some((shown_width, shown_height)) = self.shown_height
                    && (shown_width - width).abs() < 0.5
                {
                    ui.add_space((shown_height - (ui.cursor().top() - top)).max(0.0));
                }
            }
            None => {
                ui.weak("computed once the arm stands still");
            }
            Some((Err(e), _)) => {
                ui.colored_label(palette::rgb(palette::ERROR_TEXT), format!("cannot plan the program: {e}"));
            }
            Some((Ok(t), lines)) => {
                torque_view(ui, ctx.model, t, lines, None);
                self.shown_height = Some((width, ui.cursor().top() - top));
            }
        }
        ui.separator();
        self.form.ui(ui, ctx);
        if ctx.robot.moving {
            ui.ctx().request_repaint_after(std::time::Duration::from_millis(100));
        }
    }
}

impl DynamicsPanel {
    /// The panel during replay: the torques along the recording `r`, those at its cursor.
    fn replay_ui(&mut self, ui: &mut egui::Ui, model: &RobotModel, r: &crate::app::state::Replay) {
        self.replay.refresh(model, &r.data);
        ui.horizontal_wrapped(|ui| {
            ui.heading(self.title());
            ui.label(format!(
                "— REPLAY: joint torques along the recording {} (inverse dynamics of the recorded joints, \
                 velocities and accelerations)",
                r.file_name()
            ));
        });
        match self.replay.of(&r.data) {
            None => {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.weak("computing the joint torques along the recording…");
                });
                ui.ctx().request_repaint_after(std::time::Duration::from_millis(100));
            }
            Some(done) => match (&done.result, done.at(r.cursor_s)) {
                (Err(e), _) => {
                    ui.colored_label(palette::rgb(palette::ERROR_TEXT), format!("cannot analyse the recording: {e}"));
                }
                (Ok(t), at_cursor) => {
                    let names = model.joint_names();
                    ui.horizontal_wrapped(|ui| {
                        // times from the recording's start, as the timeline gives them
                        ui.label(format!("at the cursor (t = {:.2} s):", r.cursor_s - r.span_s().0));
                        for (j, tau) in at_cursor.unwrap_or_default().iter().enumerate() {
                            let name = names.get(j).copied().unwrap_or("?");
                            ui.label(egui::RichText::new(format!("{name} {tau:.2} N·m")).color(joint_color(j)));
                        }
                    });
                    torque_view(ui, model, t, &done.lines, Some((r.cursor_s, r.span_s().0)));
                }
            },
        }
        ui.separator();
        ui.weak("forward dynamics: close the recording to run torques on the simulation");
    }
}

fn torque_view(
    ui: &mut egui::Ui,
    model: &RobotModel,
    t: &ProgramTorques,
    lines: &[Vec<[f64; 2]>],
    replay: Option<(f64, f64)>,
) {
    // a recording's times (its cursor, its stretches, the plot) are shown from its start, as the
    // timeline shows them; a program's from 0
    let (cursor_s, origin_s) = match replay {
        Some((cursor_s, start_s)) => (Some(cursor_s - start_s), start_s),
        None => (None, 0.0),
    };
    let names = model.joint_names();
    ui.horizontal_wrapped(|ui| {
        for (j, peak) in t.peak_abs_nm.iter().enumerate() {
            let name = names.get(j).copied().unwrap_or("?");
            let limit = t.limits_nm.as_ref().and_then(|l| l.get(j));
            let text = match limit {
                Some(limit) => format!("{name} peak {peak:.2} / {limit:.2} N·m"),
                None => format!("{name} peak {peak:.2} N·m"),
            };
            // a peak over its limit stands out: warning colour, bold, on a tinted background
            if limit.is_some_and(|l| peak > l) {
                let warn = palette::rgb(palette::WARN_TEXT);
                let text = egui::RichText::new(format!("{text} OVER")).color(warn).strong();
                ui.label(text.background_color(warn.gamma_multiply(0.2)));
            } else {
                ui.label(egui::RichText::new(text).color(joint_color(j)));
            }
        }
    });
    match &t.limits_nm {
        Some(_) if t.warnings.is_empty() => {
            ui.colored_label(palette::rgb(palette::PATH_OK), "torques within the motor limits");
        }
        Some(_) => {
            for w in t.warnings.iter().take(WARNINGS_SHOWN) {
                ui.colored_label(
                    palette::rgb(palette::WARN_TEXT),
                    format!(
                        "J{} over its limit: {:.2} N·m > {:.2} N·m at t = {:.2} s ({}{}; {:.2}–{:.2} s)",
                        w.joint,
                        w.peak_nm,
                        w.limit_nm,
                        w.peak_s - origin_s,
                        // a recording's stretch has no program line
                        if w.line > 0 { format!("line {}, ", w.line) } else { String::new() },
                        w.step_kind,
                        w.start_s - origin_s,
                        w.end_s - origin_s
                    ),
                );
            }
            let more = t.warnings.len().saturating_sub(WARNINGS_SHOWN) + t.warnings_dropped;
            if more > 0 {
                ui.colored_label(palette::rgb(palette::WARN_TEXT), format!("… {more} more stretches over a limit"));
            }
        }
        None => {
            ui.weak("no documented torque limits for this robot");
        }
    }
    ui.weak("limits: motor holding torque × gear reduction (an upper bound at standstill)");
    // the legend names the six joints only (the dashed limit lines share their joint's colour)
    // the value axis of the plots panel: labelled ticks at every range (egui_plot's own spacer
    // labelled a ±10 N·m axis with "0" alone)
    let plot = Plot::new("program_torques")
        .height(PLOT_HEIGHT)
        .legend(egui_plot::Legend::default())
        .custom_y_axes(vec![super::plot_axis::value_axis("torque (N·m)".into())])
        .y_grid_spacer(super::plot_axis::value_marks)
        // the wheel scrolls the panel, never the plot: it panned the value axis (lines out of
        // sight) while the panel scrolled to the form (trial10); a drag still pans
        .allow_scroll(false)
        .allow_zoom(false);
    plot.x_axis_label("t (s)").show(ui, |pui| {
        if let Some(c) = cursor_s {
            pui.vline(VLine::new("cursor", c).color(palette::rgb(palette::WARN_TEXT)).width(1.0));
        }
        for (j, pts) in lines.iter().enumerate() {
            let name = names.get(j).copied().unwrap_or("?").to_string();
            let shown: Vec<[f64; 2]> = pts.iter().map(|&[t, v]| [t - origin_s, v]).collect();
            pui.line(Line::new(name, PlotPoints::new(shown)).color(joint_color(j)));
            if let Some(limit) = t.limits_nm.as_ref().and_then(|l| l.get(j)) {
                for y in [*limit, -*limit] {
                    pui.hline(HLine::new("", y).color(joint_color(j)).style(LineStyle::dashed_loose()).width(0.8));
                }
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 33 item 1: the panel compiled and analysed the program in the frame (seconds for
    /// a long G-code file, the window frozen). Now a refresh starts a worker and returns; the
    /// result arrives in a later frame, equal to the analysis done in place.
    #[test]
    fn the_dynamics_panel_does_not_compile_a_long_program_in_the_frame() {
        use parol6_core::program::Step;
        use parol6_core::program::compile::compile;
        let model = RobotModel::parol6();
        let start = parol6_core::parol6::standby_rad().to_vec();
        let steps = (0..600)
            .map(|k| Step::MoveJoints {
                joints_deg: start
                    .iter()
                    .enumerate()
                    .map(|(j, v)| v.to_degrees() + if j == k % 6 { 5.0 } else { 0.0 })
                    .collect(),
                speed_fraction: None,
                duration_s: None,
            })
            .collect();
        let program = Arc::new(Program::from_steps("long", steps));
        let mut panel = DynamicsPanel::new(6);
        panel.set_program(&program);
        let t0 = std::time::Instant::now();
        panel.refresh(&model, &start);
        let frame_s = t0.elapsed().as_secs_f64();
        assert!(panel.torques().is_none() && panel.computing(), "the frame only starts the analysis");
        assert!(frame_s < 0.05, "the frame took {frame_s:.3} s");
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
        while panel.computing() && std::time::Instant::now() < deadline {
            std::thread::sleep(std::time::Duration::from_millis(10));
            panel.refresh(&model, &start);
        }
        let done = panel.torques().expect("the worker's result arrives").clone();
        let compiled = compile(&model, &program, &start, CompileOptions::PREFLIGHT).expect("compiles");
        assert_eq!(done, program_torques(&model, &compiled, &start, torque_limits_nm(&model)));
        // a new start pose starts a new analysis, the old result stays until it is done
        let mut other = start.clone();
        other[0] += 0.1;
        panel.refresh(&model, &other);
        assert!(panel.computing());
    }

    #[test]
    fn decimation_keeps_the_peaks_and_bounds_the_points() {
        let t: Vec<f64> = (0..10_000).map(|k| k as f64 * 0.01).collect();
        let mut v: Vec<f64> = t.iter().map(|x| x.sin()).collect();
        v[4321] = 5.0;
        v[7777] = -4.0;
        let d = decimate(&t, &v, 500);
        assert!(d.len() <= 500, "{}", d.len());
        assert!(d.iter().any(|p| p[1] == 5.0) && d.iter().any(|p| p[1] == -4.0));
        assert!(d.windows(2).all(|w| w[0][0] <= w[1][0]), "time order");
        assert_eq!(decimate(&t[..10], &v[..10], 500).len(), 10);
    }
}
