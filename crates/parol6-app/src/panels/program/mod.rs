//! Left panel: the program. Pick a built-in program or open a program file of any format
//! (file dialog, typed path, recent files), edit it (teach the current pose, edit a step's
//! numbers, duplicate, delete, reorder, undo / redo, the point-table window) and save it; see
//! its pre-flight result (also drawn as the planned TCP path in the 3D view, green / amber /
//! red), run it on the active backend with pause, resume, single step and stop, and follow its
//! progress (step n of m, time left).
//!
//! - `edit`: the step list with selection, the edit toolbar, the step editor, shortcuts;
//! - `edit_menu`: the menu bar's Edit menu (the same editing actions, with their keys);
//! - `files`: open / save / save as, the file dialog, recent files;
//! - `table`: the point-table window (every step's numbers in a grid).
//!
//! - `checker`: loading, pre-flight and the planned path on a worker thread (progress, a newer
//!   request supersedes an older one).
//!
//! The panel owns the program's one check (`CheckedProgram`: start joints, compiled steps,
//! report), made on a worker from where the arm stands; the 3D view's planned path comes from it
//! and a run gets it (`AppCommand::RunProgram`), so the runner does not check again from the
//! same start. The runner is the core's `ProgramRunner` on its own thread (the app owns it);
//! this panel only reads its progress and queues commands.

mod checker;
mod comment_guard;
mod confirm;
mod edit;
mod edit_menu;
mod file_guard;
mod files;
mod table;

use std::path::PathBuf;
use std::sync::Arc;

use parol6_core::program::edit::ProgramEditor;

use eframe::egui;

use parol6_core::RobotModel;
use parol6_core::plural::count;
use parol6_core::program::check::{CheckOptions, CheckStage, CheckedProgram, Severity};
use parol6_core::program::runner::{RunOptions, RunProgress, RunState, RunnerControl};
use parol6_core::program::{Program, builtin};

pub use checker::{MAX_OVERLAY_POINTS, planned_path};

/// The id of the program's Open / Save-as dialog window (`egui::Id::unique` of it).
pub const FILE_DIALOG_ID: &str = "program-file-dialog";
/// The id of the point-table window (`egui::Id::unique` of it).
pub const TABLE_ID: &str = "program-point-table";

use super::AngleUnit;
use super::angle_text::in_unit;
use super::entry;
use super::fixed_box;
use super::shortcuts::{self, Action};
use super::{AppCommand, Panel, PanelContext};
use crate::palette;
use crate::viewport::PathOverlay;

/// Height of the step list, px (fixed so the panel never grows while running).
const STEP_LIST_HEIGHT: f32 = 120.0;
/// Pre-flight problems listed in the panel (the rest are counted).
const ISSUES_SHOWN: usize = 4;
/// Height of the step editor's box, px: four rows of fields (more scroll inside); the same
/// with no step selected, so the run buttons below it stay where they are.
const STEP_EDITOR_HEIGHT: f32 = 88.0;
/// Height of the pre-flight problems' box, px (longer lists scroll inside).
const ISSUES_HEIGHT: f32 = 64.0;

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
    /// A row the step list scrolls into view next frame (a newly taught step, the running one).
    scroll_to: Option<usize>,
    /// A step the point table scrolls into view next frame (a row just added).
    table_scroll_to: Option<usize>,
    /// The running step the list last followed.
    followed_step: Option<usize>,
    /// Typed path of a program file to open.
    pub path_text: String,
    /// The program checked from the pose it was checked at (its pre-flight report).
    checked: Option<Arc<CheckedProgram>>,
    /// The planned TCP path for the 3D view.
    overlay: Option<Arc<PathOverlay>>,
    /// A load or check running on a worker.
    job: Option<checker::CheckJob>,
    /// Why the last check could not start or finish.
    check_error: Option<String>,
    /// Speed override (0, 1].
    pub speed_override: f64,
    /// Start over after the last step.
    pub looping: bool,
    /// A run waits for the torque question (`Some(single_step)`, see `confirm`).
    confirm_run: Option<bool>,
    /// Another program was opened: the last run's outcome (of the program before) is no longer
    /// shown; `hidden_run` is taken from the app's state on the next frame.
    hide_last_run: bool,
    /// The finished run the progress line no longer shows.
    hidden_run: Option<RunProgress>,
    /// The file of the last session being reopened at start (its failure names it as such).
    reopening: Option<PathBuf>,
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
            scroll_to: None,
            table_scroll_to: None,
            followed_step: None,
            files: files::FileState::default(),
            table_open: false,
            path_text: String::new(),
            checked: None,
            overlay: None,
            job: None,
            check_error: None,
            speed_override: 1.0,
            looping: false,
            confirm_run: None,
            hide_last_run: false,
            hidden_run: None,
            reopening: None,
        }
    }

    /// Selects step `index` (0-based), as a click on its row does (`None`: no step).
    pub fn select_step(&mut self, index: Option<usize>) {
        self.selected = index.filter(|&i| i < self.program.steps.len());
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

    /// The loaded program's check (its report, from the pose it was checked at), once done.
    pub fn checked(&self) -> Option<&Arc<CheckedProgram>> {
        self.checked.as_ref()
    }

    /// True while a file is read or the program checked on a worker.
    pub fn checking(&self) -> bool {
        self.job.is_some()
    }

    /// Waits at most `timeout` for a load or check in flight and takes its answer (headless
    /// rendering wants the planned path in its first frames); true when none is left.
    pub fn wait_for_check(&mut self, timeout: std::time::Duration) -> bool {
        if let Some(answer) = self.job.as_ref().and_then(|j| j.wait(timeout)) {
            self.take_answer(answer, None);
        }
        self.job.is_none()
    }

    /// The command that runs the loaded program with this panel's settings (with its check when
    /// that is of this program at this speed: the runner then does not check it again from the
    /// same start).
    pub fn run_command(&self, single_step: bool) -> AppCommand {
        let opts = CheckOptions { speed_override: self.speed_override };
        let checked =
            self.checked.as_ref().filter(|c| Arc::ptr_eq(&c.program, &self.program) && c.opts == opts).cloned();
        AppCommand::RunProgram {
            program: Arc::clone(&self.program),
            checked,
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
        self.job = None; // a load or check in flight is superseded
        self.reopening = None;
        self.source = source;
        self.file = file;
        self.selected = None;
        self.hide_last_run = true;
        self.program_changed();
    }

    /// After any change of the edited program: share it and plan / check it again.
    fn program_changed(&mut self) {
        self.program = Arc::new(self.editor.program().clone());
        // the last run's outcome and done marks were of the program before the change (trial 23
        // m5: "stopped after 6 of 9 steps" stayed over 10 steps)
        self.hide_last_run = true;
        drop_elsewhere(self.checked.take());
        self.overlay = None;
        self.check_error = None;
        if self.job.as_ref().is_some_and(|j| j.file.is_none()) {
            self.job = None; // a check of the program before the change: superseded
        }
        if self.selected.is_some_and(|i| i >= self.program.steps.len()) {
            self.selected = self.program.steps.len().checked_sub(1);
        }
    }

    /// Pre-flight from `start_q` on a worker (again only when the start pose, the speed or the
    /// program changed; a file being read is checked when it arrives).
    fn refresh_check(&mut self, model: &RobotModel, start_q: &[f64]) {
        let opts = CheckOptions { speed_override: self.speed_override };
        if self.checked.as_ref().is_some_and(|c| c.holds_for(&self.program, start_q, opts))
            || self.check_error.is_some()
        {
            return;
        }
        match &self.job {
            Some(j) if j.file.is_some() || j.is_for(&self.program, start_q, opts) => return,
            _ => {}
        }
        match checker::CheckJob::check(model, Arc::clone(&self.program), start_q.to_vec(), opts) {
            Ok(job) => self.job = Some(job),
            Err(e) => self.check_error = Some(format!("cannot start the pre-flight: {e}")),
        }
    }

    /// Takes a finished load or check: the program read (a load) and its check.
    fn poll_job(&mut self, ctx: &mut PanelContext<'_>) {
        if let Some(answer) = self.job.as_ref().and_then(checker::CheckJob::poll) {
            self.take_answer(answer, Some(ctx));
        }
    }

    fn take_answer(&mut self, answer: Result<checker::Checked, String>, ctx: Option<&mut PanelContext<'_>>) {
        let Some(job) = self.job.take() else { return };
        match (answer, job.file.clone()) {
            (Ok(done), Some(path)) => {
                let Some(program) = done.loaded else { return };
                let shown = path.display().to_string();
                // as set_program, without copying the program on this thread: the editor's
                // program and the checked one are equal, the checked one is shared
                self.editor.replace(program);
                self.program = Arc::clone(&done.checked.program);
                self.source = shown.clone();
                self.file = Some(path.clone());
                self.selected = None;
                self.hide_last_run = true;
                self.check_error = None;
                self.reopening = None;
                self.path_text = shown.clone();
                self.stamp_file(&path);
                if let Some(ctx) = ctx {
                    ctx.settings.remember_program(&shown);
                    ctx.info(format!(
                        "loaded {} ({} steps, read and checked in {:.2} s)",
                        path.display(),
                        self.program.steps.len(),
                        done.seconds
                    ));
                }
                drop_elsewhere(self.checked.replace(done.checked));
                self.overlay = Some(done.overlay);
            }
            (Ok(done), None) => {
                if Arc::ptr_eq(&done.checked.program, &self.program) {
                    drop_elsewhere(self.checked.replace(done.checked));
                    self.overlay = Some(done.overlay);
                }
            }
            (Err(e), Some(path)) => match ctx {
                Some(ctx) if self.reopening.take().is_some_and(|p| p == path) => ctx.error(format!(
                    "the last program, {}, was not reopened: {e}; started with {}",
                    path.display(),
                    self.program.name
                )),
                Some(ctx) => ctx.error(e),
                None => self.check_error = Some(e),
            },
            (Err(e), None) => self.check_error = Some(e),
        }
        drop_elsewhere(Some(job));
    }

    /// "checking…" with its progress while a worker loads or checks.
    fn checking_text(&self) -> Option<String> {
        let job = self.job.as_ref()?;
        let what = match (&job.file, job.stage()) {
            (Some(f), CheckStage::Waiting) => format!("reading {}", f.display()),
            (_, CheckStage::Waiting) => "starting".into(),
            (_, CheckStage::Planning { done, total }) => format!("{done} / {total} steps planned"),
            (_, CheckStage::Checking { done, total }) => format!("{done} / {total} steps checked"),
        };
        Some(format!("pre-flight: checking… {what} ({:.1} s)", job.started.elapsed().as_secs_f64()))
    }
}

/// Drops `value` on a short-lived thread: a large program's check holds millions of samples,
/// whose freeing would stall a frame. When no thread can be started it is dropped here.
fn drop_elsewhere<T: Send + 'static>(value: Option<T>) {
    if let Some(v) = value {
        let spawned = crate::background::spawn("parol6-drop", move || drop(v));
        if let Err(e) = spawned {
            eprintln!("parol6: freeing a program's check on the UI thread ({e})");
        }
    }
}

impl Panel for ProgramPanel {
    fn title(&self) -> &'static str {
        "Program"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        if std::mem::take(&mut self.hide_last_run) {
            self.hidden_run = ctx.app.program.clone().filter(|p| p.state.is_finished());
        }
        // the run status of a program opened since is not shown
        let progress = ctx.app.program.clone().filter(|p| self.hidden_run.as_ref() != Some(p));
        let running = progress.as_ref().is_some_and(|p| !p.state.is_finished());
        // the heading shares its row with the built-in programs: one row less above the run
        // buttons, which stay in view at 1024x700
        self.picker(ui, ctx, running);
        ui.add_enabled_ui(!running, |ui| {
            self.file_row(ui, ctx);
        });
        self.poll_job(ctx);
        // from the live arm, also during replay: the recording at the cursor is not where a run
        // would start, and checking again at every cursor move would take the CPU from frames
        if !running && !ctx.live_robot.moving {
            self.refresh_check(ctx.model, &ctx.live_robot.commanded.q.clone());
        }
        if self.job.is_some() {
            // the progress line moves while a worker loads or checks
            ui.ctx().request_repaint_after(std::time::Duration::from_millis(50));
        }
        // each part that changes has a fixed height: nothing below it moves under the pointer
        let line_h = ui.spacing().interact_size.y;
        let unit = ctx.settings.unit;
        fixed_box::fixed_height(ui, "program-summary", line_h, |ui| self.summary_line(ui, unit));
        // Run / Pause / Step / Stop right under the verdict, above the step list and the editor:
        // below them they were under the fold of the left panel at 1024x700, 1280x800 and
        // 1600x1000 (hand trial), reachable only by scrolling
        self.controls(ui, ctx, progress.as_ref());
        fixed_box::fixed_height(ui, "program-progress", line_h, |ui| progress_line(ui, progress.as_ref(), unit));
        self.step_list(ui, progress.as_ref());
        ui.add_enabled_ui(!running, |ui| {
            self.edit_toolbar(ui, ctx);
            fixed_box::fixed_height(ui, "program-step-editor-box", STEP_EDITOR_HEIGHT, |ui| self.step_editor(ui, ctx));
        });
        if !running {
            self.shortcuts(ui, ctx);
        }
        fixed_box::fixed_height(ui, "program-issues", ISSUES_HEIGHT, |ui| self.issue_lines(ui, unit));
        if running {
            ui.ctx().request_repaint_after(std::time::Duration::from_millis(100));
        }
        self.dialogs(ui, ctx);
        self.save_question(ui, ctx);
        self.run_confirmation(ui, ctx);
        // open during a run too, read-only (it vanished without a word: trial10 n1)
        if self.table_open {
            self.table_window(ui, ctx, running);
        }
    }
}

impl ProgramPanel {
    /// The panel's heading and the built-in programs (off while a program runs).
    fn picker(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, running: bool) {
        let mut pick = None;
        ui.horizontal_wrapped(|ui| {
            ui.heading(self.title());
            for p in &self.builtins {
                let selected = p.name == self.program.name && self.source == "built-in";
                let label = egui::Button::selectable(selected, &p.name);
                if ui.add_enabled(!running, label).on_hover_text(&p.description).clicked() {
                    pick = Some(p.name.clone());
                }
            }
        });
        if let Some(name) = pick {
            self.request_open(files::OpenRequest::Builtin(name), ctx);
        }
    }

    fn summary_line(&self, ui: &mut egui::Ui, unit: AngleUnit) {
        if let Some(text) = self.checking_text() {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label(text);
            });
            return;
        }
        if let Some(e) = &self.check_error {
            ui.colored_label(palette::rgb(palette::PATH_ERROR), format!("pre-flight: {}", in_unit(e, unit)));
            return;
        }
        ui.horizontal(|ui| match &self.checked {
            Some(r) => {
                let errors = r.issues.iter().filter(|i| i.severity == Severity::Error).count();
                let warnings = r.issues.len() - errors;
                let (text, color) = if errors > 0 {
                    (
                        format!("pre-flight: {}, {}", count(errors, "error"), count(warnings, "warning")),
                        palette::PATH_ERROR,
                    )
                } else if warnings > 0 {
                    (format!("pre-flight: ok, {}", count(warnings, "warning")), palette::PATH_WARNING)
                } else {
                    ("pre-flight: ok".to_string(), palette::PATH_OK)
                };
                ui.colored_label(palette::rgb(color), text);
                ui.label(format!("· {} · {:.1} s", count(r.moves, "step"), r.duration_s));
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
        let checking = self.job.is_some();
        let clean = !checking && self.checked.as_ref().is_some_and(|r| r.ok);
        ui.horizontal(|ui| {
            let run_label = if paused { "Resume (F5)" } else { "Run (F5)" };
            // nothing starts while the E-stop is latched, a recording is replayed or an ISO
            // test drives the arm: Run is greyed, with the reason
            let refused = ctx
                .motion_refused()
                .or_else(|| ctx.app.measurement.running().then_some(crate::app::state::MEASUREMENT_RUNNING));
            let can_run = ((clean && !running) || paused) && refused.is_none();
            // tighter than elsewhere: the four buttons fit the column with "Resume (F5)"
            ui.spacing_mut().button_padding.x = 1.0;
            ui.spacing_mut().item_spacing.x = 3.0;
            // as wide as its longest label: "Resume (F5)" does not widen the row
            let widest = egui::WidgetText::from("Resume (F5)").into_galley(
                ui,
                Some(egui::TextWrapMode::Extend),
                f32::INFINITY,
                egui::TextStyle::Button,
            );
            let run_w = widest.size().x + 2.0 * ui.spacing().button_padding.x;
            let run_button = egui::Button::new(run_label).min_size(egui::vec2(run_w, 0.0));
            let run = ui.add_enabled(can_run, run_button).on_disabled_hover_text(if let Some(why) = refused {
                why
            } else if running {
                "running"
            } else if checking {
                "the pre-flight is still checking"
            } else {
                "the pre-flight must be clean"
            });
            let f5 = shortcuts::pressed(ui.ctx(), Action::RunProgram);
            if f5 && checking && !running {
                // never an unchecked program: F5 waits for the operator to press it again
                ctx.error(format!(
                    "{} is still being checked: Run (F5) starts it once the pre-flight is done",
                    self.program.name
                ));
            }
            if f5 && !checking && !running && !paused && refused.is_none() && !clean {
                let why =
                    checker::run_refusal(&self.program.name, self.checked.as_deref(), self.check_error.as_deref());
                ctx.error(in_unit(&why, ctx.settings.unit));
            }
            if run.clicked() || (f5 && can_run) {
                if paused {
                    ctx.send(AppCommand::Program(RunnerControl::Resume));
                } else {
                    self.start_run(ctx, false);
                }
            }
            let idle = if running { "" } else { NO_RUN };
            let pause = ui.add_enabled(running && !paused, egui::Button::new("Pause (F6)"));
            let pause = pause.on_disabled_hover_text(if paused { "paused: Resume (F5) or Stop program" } else { idle });
            if pause.clicked() || (running && !paused && shortcuts::pressed(ui.ctx(), Action::PauseProgram)) {
                ctx.send(AppCommand::Program(RunnerControl::Pause));
            }
            let can_step = (paused || (!running && clean)) && refused.is_none();
            let step = ui.add_enabled(can_step, egui::Button::new("Step (F10)"));
            if step.clicked() || (can_step && shortcuts::pressed(ui.ctx(), Action::SingleStep)) {
                self.step_once(ctx, progress.filter(|_| paused).map(|p| p.step));
            }
            if ui.add_enabled(running, egui::Button::new("Stop program")).on_disabled_hover_text(idle).clicked() {
                ctx.send(AppCommand::Program(RunnerControl::Stop));
            }
        });
        ui.add_enabled_ui(!running, |ui| {
            ui.horizontal(|ui| {
                ui.checkbox(&mut self.looping, "Loop");
                ui.label("Speed ×");
                let (r, refused) =
                    entry::typed_slider(ui, "Speed ×", &mut self.speed_override, 0.05..=1.0, ("", ""), 2);
                if r.changed() {
                    drop_elsewhere(self.checked.take()); // planned again at the new speed
                }
                if let Some(message) = refused {
                    ctx.error(message);
                }
            });
        });
    }

    fn issue_lines(&self, ui: &mut egui::Ui, unit: AngleUnit) {
        let Some(r) = &self.checked else { return };
        for i in r.issues.iter().take(ISSUES_SHOWN) {
            let color = if i.severity == Severity::Error { palette::PATH_ERROR } else { palette::PATH_WARNING };
            let line = if i.line > 0 { format!("line {}, ", i.line) } else { String::new() };
            let text = egui::RichText::new(format!("{line}step {}: {}", i.move_index + 1, in_unit(&i.message, unit)))
                .color(palette::rgb(color));
            ui.add(egui::Label::new(text).wrap());
        }
        if r.issues.len() > ISSUES_SHOWN {
            ui.weak(format!("… and {} more (parol6 program check FILE lists all)", r.issues.len() - ISSUES_SHOWN));
        }
    }
}

/// Why Pause and Stop program are greyed: nothing runs (also under the E-stop and in replay).
const NO_RUN: &str = "no program is running";

/// One line, always present, so nothing below moves when a run starts or ends.
fn progress_line(ui: &mut egui::Ui, progress: Option<&RunProgress>, unit: AngleUnit) {
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
                // a looping run names its passes: "after 0 of 12 steps" read as if nothing ran (trial17)
                RunState::Stopped if p.passes > 0 => format!(
                    "{}: stopped after {} and {} of {} steps",
                    p.name,
                    parol6_core::plural::count(p.passes as usize, "pass"),
                    p.steps_done,
                    p.steps
                ),
                RunState::Stopped => format!("{}: stopped after {} of {} steps", p.name, p.steps_done, p.steps),
                RunState::Failed(why) => format!("{}: {}", p.name, in_unit(why, unit)),
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
