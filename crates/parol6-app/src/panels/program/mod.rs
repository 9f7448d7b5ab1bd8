//! Left panel: the program. Pick a built-in program or open a program file of any format
//! (file dialog, typed path, recent files), edit it (teach the current pose, edit a step's
//! numbers, duplicate, delete, reorder, undo / redo, the point-table window) and save it; see
//! its pre-flight result (also drawn as the planned TCP path in the 3D view, green / amber /
//! red), run it on the active backend with pause, resume, single step and stop, and follow its
//! progress (step n of m, time left).
//!
//! - `edit`: the step list with selection, the edit toolbar, the step editor, shortcuts;
//! - `files`: open / save / save as, the file dialog, recent files;
//! - `table`: the point-table window (every step's numbers in a grid).
//!
//! The runner is the core's `ProgramRunner` on its own thread (the app owns it); this panel
//! only reads its progress and queues commands.

mod confirm;
mod edit;
mod files;
mod table;

use std::path::PathBuf;
use std::sync::Arc;

use parol6_core::program::edit::ProgramEditor;

use eframe::egui;

use parol6_core::RobotModel;
use parol6_core::program::check::{CheckOptions, CheckReport, CheckStatus, Severity, check_program};
use parol6_core::program::compile::{CompileOptions, StepAction, compile};
use parol6_core::program::runner::{RunOptions, RunProgress, RunState, RunnerControl};
use parol6_core::program::{Program, builtin};

use super::shortcuts::{self, Action};
use super::{AppCommand, Panel, PanelContext};
use crate::palette;
use crate::viewport::{PathOverlay, PathPointStatus};

/// Height of the step list, px (fixed so the panel never grows while running).
const STEP_LIST_HEIGHT: f32 = 120.0;
/// Pre-flight problems listed in the panel (the rest are counted).
const ISSUES_SHOWN: usize = 4;

/// The program panel.
pub struct ProgramPanel {
    builtins: Vec<Program>,
    /// The program being edited, with undo / redo.
    editor: ProgramEditor,
    /// The program as last edited, shared with the runner and the pre-flight.
    program: Arc<Program>,
    /// Where the program came from (a file path or "built-in").
    source: String,
    /// The file it was loaded from or saved to ("Save" writes there).
    file: Option<PathBuf>,
    /// The selected step.
    selected: Option<usize>,
    /// File dialog, open action waiting for a discard confirmation, table window.
    files: files::FileState,
    /// The point-table window is open.
    pub table_open: bool,
    /// Typed path of a program file to open.
    pub path_text: String,
    /// Pre-flight of the program from the pose it was checked at.
    report: Option<(Vec<f64>, CheckReport)>,
    /// The planned TCP path for the 3D view.
    overlay: Option<Arc<PathOverlay>>,
    /// Speed override (0, 1].
    pub speed_override: f64,
    /// Start over after the last step.
    pub looping: bool,
    /// A run waits for the torque question (`Some(single_step)`, see `confirm`).
    confirm_run: Option<bool>,
}

impl ProgramPanel {
    /// The panel for `model`, with the first built-in program loaded.
    pub fn new(model: &RobotModel) -> Self {
        let builtins = builtin::programs(model);
        let first = builtins.first().cloned().unwrap_or_default();
        Self {
            builtins,
            program: Arc::new(first.clone()),
            editor: ProgramEditor::new(first),
            source: "built-in".into(),
            file: None,
            selected: None,
            files: files::FileState::default(),
            table_open: false,
            path_text: String::new(),
            report: None,
            overlay: None,
            speed_override: 1.0,
            looping: false,
            confirm_run: None,
        }
    }

    /// The loaded program.
    pub fn program(&self) -> &Arc<Program> {
        &self.program
    }

    /// The planned TCP path of the loaded program (checked from the current pose).
    pub fn overlay(&self) -> Option<Arc<PathOverlay>> {
        self.overlay.clone()
    }

    /// The program's unsaved edits exist.
    pub fn is_dirty(&self) -> bool {
        self.editor.is_dirty()
    }

    /// Loads the built-in program called `name` (case-insensitive); false when none is.
    pub fn load_builtin(&mut self, name: &str) -> bool {
        match self.builtins.iter().find(|p| p.name.eq_ignore_ascii_case(name)) {
            Some(p) => {
                self.set_program(p.clone(), "built-in".into(), None);
                true
            }
            None => false,
        }
    }

    /// The command that runs the loaded program with this panel's settings.
    pub fn run_command(&self, single_step: bool) -> AppCommand {
        AppCommand::RunProgram {
            program: Arc::clone(&self.program),
            opts: RunOptions {
                speed_override: self.speed_override,
                single_step,
                looping: self.looping,
                ..RunOptions::default()
            },
        }
    }

    /// A new program (loaded): history cleared, nothing selected.
    fn set_program(&mut self, program: Program, source: String, file: Option<PathBuf>) {
        self.editor.replace(program);
        self.source = source;
        self.file = file;
        self.selected = None;
        self.program_changed();
    }

    /// After any change of the edited program: share it and plan / check it again.
    fn program_changed(&mut self) {
        self.program = Arc::new(self.editor.program().clone());
        self.report = None;
        self.overlay = None;
        if self.selected.is_some_and(|i| i >= self.program.steps.len()) {
            self.selected = self.program.steps.len().checked_sub(1);
        }
    }

    /// Pre-flight from `start_q` (again only when the start pose or the program changed).
    fn refresh_check(&mut self, model: &RobotModel, start_q: &[f64]) {
        if self.report.as_ref().is_some_and(|(q, _)| q == start_q) {
            return;
        }
        let opts = CheckOptions { speed_override: self.speed_override };
        let report = check_program(model, &self.program, start_q, opts);
        self.overlay = Some(Arc::new(planned_path(model, &self.program, start_q, &report)));
        self.report = Some((start_q.to_vec(), report));
    }
}

/// The planned TCP path: every pre-flight sample of every motion step, coloured by the status
/// of the pre-flight's last checked point at or before it in the same step (an error in a
/// step without checked points, e.g. an unreachable one, colours the whole step).
pub fn planned_path(model: &RobotModel, program: &Program, start_q: &[f64], report: &CheckReport) -> PathOverlay {
    let mut overlay = PathOverlay::default();
    let Ok(compiled) = compile(model, program, start_q, CompileOptions::PREFLIGHT) else {
        return overlay;
    };
    let to_path = |s: CheckStatus| match s {
        CheckStatus::Ok => PathPointStatus::Ok,
        CheckStatus::Warning => PathPointStatus::Warning,
        CheckStatus::Error => PathPointStatus::Error,
    };
    for c in &compiled {
        let StepAction::Motion(traj) = &c.action else { continue };
        let checked: Vec<_> = report.path.iter().filter(|p| p.move_index == c.steps.start).collect();
        let step_worst = report.issues.iter().filter(|i| c.steps.contains(&i.move_index)).map(|i| i.severity).max();
        overlay.break_strip();
        for (k, q) in traj.samples().iter().enumerate() {
            let t = k as f64 * traj.dt_s();
            let status = match checked.iter().rev().find(|p| p.t_s <= t + 1e-9) {
                Some(p) => to_path(p.status),
                None => step_worst.map_or(PathPointStatus::Ok, |s| to_path(s.into())),
            };
            let p = model.tcp_isometry(q).translation.vector;
            overlay.push([p.x as f32, p.y as f32, p.z as f32], status);
        }
    }
    overlay
}

impl Panel for ProgramPanel {
    fn title(&self) -> &'static str {
        "Program"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.heading(self.title());
        let progress = ctx.program.cloned();
        let running = progress.as_ref().is_some_and(|p| !p.state.is_finished());
        ui.add_enabled_ui(!running, |ui| {
            self.picker(ui, ctx);
            self.file_row(ui, ctx);
        });
        if !running && !ctx.robot.moving {
            self.refresh_check(ctx.model, &ctx.robot.commanded.q.clone());
        }
        self.summary_line(ui);
        self.step_list(ui, progress.as_ref());
        ui.add_enabled_ui(!running, |ui| {
            self.edit_toolbar(ui, ctx);
            self.step_editor(ui, ctx);
        });
        if !running {
            self.shortcuts(ui, ctx);
        }
        self.controls(ui, ctx, progress.as_ref());
        progress_line(ui, progress.as_ref());
        self.issue_lines(ui);
        if running {
            ui.ctx().request_repaint_after(std::time::Duration::from_millis(100));
        }
        self.dialogs(ui, ctx);
        self.run_confirmation(ui, ctx);
        if self.table_open && !running {
            self.table_window(ui, ctx);
        }
    }
}

impl ProgramPanel {
    fn picker(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let mut pick = None;
        ui.horizontal_wrapped(|ui| {
            for p in &self.builtins {
                let selected = p.name == self.program.name && self.source == "built-in";
                if ui.selectable_label(selected, &p.name).on_hover_text(&p.description).clicked() {
                    pick = Some(p.name.clone());
                }
            }
        });
        if let Some(name) = pick {
            self.request_open(files::OpenRequest::Builtin(name), ctx);
        }
    }

    fn summary_line(&self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| match &self.report {
            Some((_, r)) => {
                let errors = r.issues.iter().filter(|i| i.severity == Severity::Error).count();
                let warnings = r.issues.len() - errors;
                let (text, color) = if errors > 0 {
                    (format!("pre-flight: {errors} error(s), {warnings} warning(s)"), palette::PATH_ERROR)
                } else if warnings > 0 {
                    (format!("pre-flight: ok, {warnings} warning(s)"), palette::PATH_WARNING)
                } else {
                    ("pre-flight: ok".to_string(), palette::PATH_OK)
                };
                ui.colored_label(palette::rgb(color), text);
                ui.label(format!("· {} steps · {:.1} s", r.moves, r.duration_s));
            }
            None => {
                ui.weak("pre-flight: when the arm stands still");
            }
        });
    }

    fn controls(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, progress: Option<&RunProgress>) {
        let state = progress.map(|p| &p.state);
        let running = state.is_some_and(|s| !s.is_finished());
        let paused = state == Some(&RunState::Paused);
        let clean = self.report.as_ref().is_some_and(|(_, r)| r.ok);
        ui.horizontal(|ui| {
            let run_label = if paused { "Resume (F5)" } else { "Run (F5)" };
            let can_run = (clean && !running) || paused;
            let run = ui.add_enabled(can_run, egui::Button::new(run_label)).on_disabled_hover_text(if running {
                "running"
            } else {
                "the pre-flight must be clean"
            });
            let f5 = shortcuts::pressed(ui.ctx(), Action::RunProgram);
            if run.clicked() || (f5 && can_run) {
                if paused {
                    ctx.send(AppCommand::Program(RunnerControl::Resume));
                } else {
                    self.start_run(ctx, false);
                }
            }
            let pause = ui.add_enabled(running && !paused, egui::Button::new("Pause (F6)"));
            if pause.clicked() || (running && !paused && shortcuts::pressed(ui.ctx(), Action::PauseProgram)) {
                ctx.send(AppCommand::Program(RunnerControl::Pause));
            }
            let can_step = paused || (!running && clean);
            let step = ui.add_enabled(can_step, egui::Button::new("Step (F10)"));
            if step.clicked() || (can_step && shortcuts::pressed(ui.ctx(), Action::SingleStep)) {
                if paused {
                    ctx.send(AppCommand::Program(RunnerControl::Step));
                } else {
                    self.start_run(ctx, true);
                }
            }
            if ui.add_enabled(running, egui::Button::new("Stop program")).clicked() {
                ctx.send(AppCommand::Program(RunnerControl::Stop));
            }
        });
        ui.add_enabled_ui(!running, |ui| {
            ui.horizontal(|ui| {
                ui.checkbox(&mut self.looping, "Loop");
                ui.label("Speed ×");
                let r = ui.add(egui::Slider::new(&mut self.speed_override, 0.05..=1.0).max_decimals(2));
                if r.changed() {
                    self.report = None; // planned again at the new speed
                }
            });
        });
    }

    fn issue_lines(&self, ui: &mut egui::Ui) {
        let Some((_, r)) = &self.report else { return };
        for i in r.issues.iter().take(ISSUES_SHOWN) {
            let color = if i.severity == Severity::Error { palette::PATH_ERROR } else { palette::PATH_WARNING };
            let line = if i.line > 0 { format!("line {}, ", i.line) } else { String::new() };
            let text = egui::RichText::new(format!("{line}step {}: {}", i.move_index + 1, i.message))
                .color(palette::rgb(color));
            ui.add(egui::Label::new(text).wrap());
        }
        if r.issues.len() > ISSUES_SHOWN {
            ui.weak(format!("… and {} more (parol6 program check FILE lists all)", r.issues.len() - ISSUES_SHOWN));
        }
    }
}

/// One line, always present, so nothing below moves when a run starts or ends.
fn progress_line(ui: &mut egui::Ui, progress: Option<&RunProgress>) {
    ui.horizontal(|ui| match progress {
        Some(p) => {
            let text = match &p.state {
                RunState::Preparing => format!("{}: checking and planning…", p.name),
                RunState::Running => match &p.waiting_for {
                    Some(w) => format!("{}: step {} of {}, waiting for {w}", p.name, p.step + 1, p.steps),
                    None => format!("{}: step {} of {}, {:.1} s left", p.name, p.step + 1, p.steps, p.time_left_s),
                },
                RunState::Paused => format!("{}: paused at step {} of {}", p.name, p.step + 1, p.steps),
                RunState::Done => format!("{}: done ({:.1} s)", p.name, p.clock_s.1 - p.clock_s.0),
                RunState::Stopped => format!("{}: stopped after {} of {} steps", p.name, p.steps_done, p.steps),
                RunState::Failed(why) => format!("{}: {why}", p.name),
            };
            if matches!(p.state, RunState::Failed(_)) {
                ui.colored_label(palette::rgb(palette::ERROR_TEXT), text);
            } else {
                ui.label(text);
            }
        }
        None => {
            ui.weak("Idle. STOP (Esc) halts a running program.");
        }
    });
}
