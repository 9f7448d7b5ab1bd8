//! Editing in the program panel: the step list (click to select), the edit toolbar (teach the
//! current pose as a joint or Cartesian step, duplicate, delete, move up / down, undo / redo,
//! the table window), the editor of the selected step's numbers, and the shortcuts
//! (Ctrl+Z, Ctrl+Y / Ctrl+Shift+Z, Ctrl+D, Delete, Alt+↑/↓, Ctrl+S).
//!
//! Teaching takes the pose the arm is at: the simulation's joints, or the robot's measured
//! joints when the hardware drives the state.

use eframe::egui;
use parol6_core::program::runner::RunProgress;
use parol6_core::program::{PoseMm, Step};

use super::ProgramPanel;
use crate::palette;
use crate::panels::PanelContext;
use crate::panels::entry::{self, EntryEvent};
use crate::panels::step_fields::{step_fields, with_field};
use parol6_core::program::check::Severity;

/// A joint step at the arm's pose (degrees, as programs store them).
pub(super) fn taught_joint_step(q_rad: &[f64]) -> Step {
    Step::MoveJoints {
        joints_deg: q_rad.iter().map(|v| v.to_degrees()).collect(),
        speed_fraction: None,
        duration_s: None,
    }
}

/// The pre-flight's view of one planned step, for the step list's tooltip.
fn plan_hover(p: &parol6_core::program::check::PlannedStep) -> String {
    let pose = |t: &PoseMm| {
        format!(
            "({:.1}, {:.1}, {:.1}) mm, ({:.1}, {:.1}, {:.1})°",
            t.position_mm[0], t.position_mm[1], t.position_mm[2], t.rpy_deg[0], t.rpy_deg[1], t.rpy_deg[2]
        )
    };
    let config = p.config.as_deref().unwrap_or("none (numeric IK)");
    format!(
        "{} (line {}), {:.2} s\nconfiguration at its end: {config}\nTCP from {}\n       to {}",
        p.kind,
        p.line,
        p.duration_s,
        pose(&p.start_tcp),
        pose(&p.end_tcp)
    )
}

/// A joint move to the TCP pose of `q_rad`, in the configuration the arm is in there (so the
/// step reaches the taught joints again, whatever the arm's pose before it).
pub(super) fn taught_pose_step(model: &parol6_core::RobotModel, q_rad: &[f64]) -> Step {
    Step::MovePose {
        pose: PoseMm::from_isometry(&model.tcp_isometry(q_rad)),
        config: parol6_core::ik::configuration_of(model, q_rad)
            .filter(|_| !parol6_core::ik::config::on_wrist_border(q_rad)),
        speed_fraction: None,
        duration_s: None,
    }
}

/// A Cartesian (line) step to the TCP pose of `q_rad`.
pub(super) fn taught_line_step(model: &parol6_core::RobotModel, q_rad: &[f64]) -> Step {
    Step::MoveL {
        pose: PoseMm::from_isometry(&model.tcp_isometry(q_rad)),
        speed_mm_s: None,
        blend_mm: None,
        duration_s: None,
    }
}

impl ProgramPanel {
    /// Applies an editor result: on success the program is shared and checked again; an
    /// error is shown.
    fn edited<T>(
        &mut self,
        result: Result<T, parol6_core::program::edit::EditError>,
        ctx: &mut PanelContext<'_>,
    ) -> Option<T> {
        match result {
            Ok(v) => {
                self.program_changed();
                Some(v)
            }
            Err(e) => {
                ctx.error(format!("program: {e}"));
                None
            }
        }
    }

    /// Inserts a taught step after the selection (or at the end) and selects it.
    pub(super) fn teach(&mut self, step: Step, ctx: &mut PanelContext<'_>) {
        let at = self.selected.map_or(self.editor.program().steps.len(), |i| i + 1);
        let r = self.editor.insert(at, step);
        if self.edited(r, ctx).is_some() {
            self.selected = Some(at);
            self.scroll_to = Some(at);
        }
    }

    pub(super) fn undo(&mut self) {
        if self.editor.undo() {
            self.program_changed();
        }
    }

    pub(super) fn redo(&mut self) {
        if self.editor.redo() {
            self.program_changed();
        }
    }

    pub(super) fn duplicate(&mut self, ctx: &mut PanelContext<'_>) {
        if let Some(i) = self.selected {
            let r = self.editor.duplicate(i);
            if let Some(j) = self.edited(r, ctx) {
                self.selected = Some(j);
            }
        }
    }

    pub(super) fn delete(&mut self, ctx: &mut PanelContext<'_>) {
        if let Some(i) = self.selected {
            let r = self.editor.delete(i);
            self.edited(r, ctx);
        }
    }

    pub(super) fn move_selected(&mut self, up: bool, ctx: &mut PanelContext<'_>) {
        if let Some(i) = self.selected {
            let r = self.editor.move_step(i, up);
            if let Some(j) = self.edited(r, ctx) {
                self.selected = Some(j);
            }
        }
    }

    /// The steps, one line each (cut to the column so the panel never widens); click selects.
    /// Only the rows in view are laid out (a G-code file may hold 200 000 steps).
    pub(super) fn step_list(&mut self, ui: &mut egui::Ui, progress: Option<&RunProgress>) {
        let issues = self.checked.as_ref().map(|r| r.issues.as_slice()).unwrap_or(&[]);
        let plan = self.checked.as_ref().map(|r| r.plan.as_slice()).unwrap_or(&[]);
        let mut clicked = None;
        let row_height = ui
            .spacing()
            .interact_size
            .y
            .max(ui.text_style_height(&egui::TextStyle::Monospace) + 2.0 * ui.spacing().button_padding.y);
        // follows the running step (and shows a newly taught one), never a clicked one: that
        // row is under the pointer and stays there
        let running = progress.filter(|p| !p.state.is_finished()).map(|p| p.step);
        if running.is_some() && running != self.followed_step {
            self.scroll_to = running;
        }
        self.followed_step = running;
        let mut area = egui::ScrollArea::vertical()
            .id_salt("program-steps")
            .max_height(super::STEP_LIST_HEIGHT)
            .min_scrolled_height(super::STEP_LIST_HEIGHT)
            .auto_shrink([false, false]);
        if let Some(row) = self.scroll_to.take() {
            let row_h = row_height + ui.spacing().item_spacing.y;
            let centred = row as f32 * row_h - (super::STEP_LIST_HEIGHT - row_h) / 2.0;
            area = area.vertical_scroll_offset(centred.max(0.0));
        }
        let steps = &self.program.steps;
        area.show_rows(ui, row_height, steps.len(), |ui, rows| {
            for (i, s) in steps.iter().enumerate().skip(rows.start).take(rows.len()) {
                let (mark, strong) = match progress {
                    Some(p) if !p.state.is_finished() && i == p.step => (">", true),
                    Some(p) if i < p.steps_done => ("+", false),
                    _ => (" ", false),
                };
                let worst = issues.iter().filter(|x| x.move_index == i).map(|x| x.severity).max();
                // the pre-flight's plan (in step order): the configuration the step ends in
                let at = plan.partition_point(|p| p.index + p.steps <= i);
                let planned = plan.get(at).filter(|p| (p.index..p.index + p.steps).contains(&i));
                let config = planned.filter(|p| p.end_tcp != p.start_tcp).and_then(|p| p.config.as_deref());
                let row = match config {
                    Some(c) => format!("{mark}{:>3}  [{c}] {}", i + 1, s.step.summary()),
                    None => format!("{mark}{:>3}  {}", i + 1, s.step.summary()),
                };
                let text = egui::RichText::new(row).monospace();
                let text = if strong { text.strong() } else { text };
                let text = match worst {
                    Some(Severity::Error) => text.color(palette::rgb(palette::PATH_ERROR)),
                    Some(Severity::Warning) => text.color(palette::rgb(palette::PATH_WARNING)),
                    None => text,
                };
                let selected = self.selected == Some(i);
                let mut r = ui.add(egui::Button::selectable(selected, text).truncate());
                if let Some(p) = planned {
                    r = r.on_hover_text(plan_hover(p));
                }
                if r.clicked() {
                    clicked = Some(if selected { None } else { Some(i) });
                }
            }
        });
        if let Some(sel) = clicked {
            self.selected = sel;
        }
    }

    /// Teach / duplicate / delete / reorder / undo / redo / table.
    pub(super) fn edit_toolbar(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let q = ctx.robot.q.clone();
        let source = if ctx.app.link.is_some() { "measured robot" } else { "simulation" };
        ui.horizontal_wrapped(|ui| {
            if ui
                .button("Teach joints")
                .on_hover_text(format!("Insert a joint move to the arm's pose ({source})"))
                .clicked()
            {
                self.teach(taught_joint_step(&q), ctx);
            }
            if ui
                .button("Teach pose")
                .on_hover_text(format!(
                    "Insert a joint move to the TCP pose in the arm's configuration ({source}): the step reaches \
                     these joints again"
                ))
                .clicked()
            {
                let step = taught_pose_step(ctx.model, &q);
                self.teach(step, ctx);
            }
            if ui.button("Teach line").on_hover_text(format!("Insert a line to the TCP pose ({source})")).clicked() {
                let step = taught_line_step(ctx.model, &q);
                self.teach(step, ctx);
            }
            let has = self.selected.is_some();
            if ui.add_enabled(has, egui::Button::new("Dup")).on_hover_text("Duplicate the step (Ctrl+D)").clicked() {
                self.duplicate(ctx);
            }
            if ui.add_enabled(has, egui::Button::new("Del")).on_hover_text("Delete the step (Delete)").clicked() {
                self.delete(ctx);
            }
            if ui.add_enabled(has, egui::Button::new("Up")).on_hover_text("Move the step up (Alt+Up)").clicked() {
                self.move_selected(true, ctx);
            }
            if ui.add_enabled(has, egui::Button::new("Down")).on_hover_text("Move the step down (Alt+Down)").clicked() {
                self.move_selected(false, ctx);
            }
            if ui.add_enabled(self.editor.can_undo(), egui::Button::new("Undo")).on_hover_text("Ctrl+Z").clicked() {
                self.undo();
            }
            if ui.add_enabled(self.editor.can_redo(), egui::Button::new("Redo")).on_hover_text("Ctrl+Y").clicked() {
                self.redo();
            }
            if ui.selectable_label(self.table_open, "Table").on_hover_text("Every step's numbers in a grid").clicked() {
                self.table_open = !self.table_open;
            }
        });
    }

    /// The selected step's numbers, each committed on Enter or focus loss (one undo entry).
    pub(super) fn step_editor(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let Some(i) = self.selected else {
            ui.weak("Click a step to edit its numbers here.");
            return;
        };
        let Some(step) = self.editor.program().steps.get(i).map(|s| s.step.clone()) else { return };
        let fields = step_fields(&step, ctx.settings, &self.editor.program().speed);
        if fields.is_empty() {
            ui.weak(format!("step {}: {} (edit it in the file)", i + 1, step.kind()));
            return;
        }
        let mut change = None;
        egui::Grid::new("program-step-editor").num_columns(4).spacing([4.0, 2.0]).show(ui, |ui| {
            for (k, f) in fields.iter().enumerate() {
                ui.label(&f.label);
                let name = format!("step {} {}", i + 1, f.label);
                let (_, event) = entry::numeric_entry(ui, &name, f.value, f.decimals, 64.0, f.suffix);
                match event {
                    Some(EntryEvent::Committed(v)) => change = Some((f.slot, v, f.label.clone())),
                    Some(EntryEvent::Invalid(why)) => ctx.error(format!("step {} {}: {why}", i + 1, f.label)),
                    None => {}
                }
                if k % 2 == 1 {
                    ui.end_row();
                }
            }
        });
        if let Some((slot, v, label)) = change {
            match with_field(&step, slot, v, ctx.settings) {
                Ok(new) => {
                    let r = self.editor.set_step(i, new);
                    self.edited(r, ctx);
                }
                Err(why) => ctx.error(format!("step {} {label}: {why}", i + 1)),
            }
        }
    }

    /// Editing shortcuts (see [`super::super::shortcuts`]: not while a text field has the keyboard).
    pub(super) fn shortcuts(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        use super::super::shortcuts::{Action, pressed};
        let ctx_ui = ui.ctx().clone();
        let pressed = |a: Action| pressed(&ctx_ui, a);
        let redo = pressed(Action::Redo);
        let undo = pressed(Action::Undo);
        let dup = pressed(Action::DuplicateStep);
        let save = pressed(Action::SaveProgram);
        if super::super::shortcuts::pressed_in_text_field(&ctx_ui, Action::SaveProgram) {
            ctx.info("Ctrl+S: nothing saved while a field is being typed in: finish the field (or Esc to drop it), then press Ctrl+S again");
        }
        let del = pressed(Action::DeleteStep);
        let up = pressed(Action::MoveStepUp);
        let down = pressed(Action::MoveStepDown);
        if redo {
            self.redo();
        } else if undo {
            self.undo();
        }
        if dup {
            self.duplicate(ctx);
        }
        if del {
            self.delete(ctx);
        }
        if up || down {
            self.move_selected(up, ctx);
        }
        if save {
            self.save(ctx);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn taught_steps_reach_the_taught_pose() {
        let model = parol6_core::RobotModel::parol6();
        let q = parol6_core::parol6::standby_rad().to_vec();
        let Step::MoveJoints { joints_deg, .. } = taught_joint_step(&q) else { panic!() };
        assert!(joints_deg.iter().zip(&q).all(|(d, r)| (d.to_radians() - r).abs() < 1e-12));
        let Step::MoveL { pose, .. } = taught_line_step(&model, &q) else { panic!() };
        let tcp = model.tcp_isometry(&q);
        assert!((pose.isometry().translation.vector - tcp.translation.vector).norm() < 1e-9);
        assert!(pose.isometry().rotation.angle_to(&tcp.rotation) < 1e-9);
        // standby is on the wrist border: no configuration named there
        let Step::MovePose { config: None, .. } = taught_pose_step(&model, &q) else { panic!() };
    }

    /// Teach pose records the configuration; the step reaches the taught joints from anywhere.
    #[test]
    fn taught_pose_keeps_its_configuration() {
        let model = parol6_core::RobotModel::parol6();
        let taught = [0.4, -1.2, 3.4, 0.6, -0.8, 2.5];
        let step = taught_pose_step(&model, &taught);
        let Step::MovePose { config: Some(config), .. } = &step else { panic!("{step:?}") };
        assert_eq!(Some(*config), parol6_core::ik::configuration_of(&model, &taught));
        let program = parol6_core::program::Program::from_steps("t", vec![step]);
        for start in [parol6_core::parol6::standby_rad().to_vec(), vec![-0.5, -0.8, 2.8, -0.9, 0.9, 4.0]] {
            let compiled = parol6_core::program::compile::compile(
                &model,
                &program,
                &start,
                parol6_core::program::compile::CompileOptions::PREFLIGHT,
            )
            .expect("reachable");
            let end = &compiled[0].end_q;
            assert!(end.iter().zip(&taught).all(|(a, b)| (a - b).abs() < 1e-6), "{end:?}");
        }
    }
}
