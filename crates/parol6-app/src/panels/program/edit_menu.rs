//! The menu bar's Edit menu: the program editor's undo / redo, teach, duplicate, delete, move
//! up / down and the point table, each with its keys from the shortcut table
//! ([`crate::panels::shortcuts`]) and greyed, with the reason on hover, when it cannot act. No
//! entry moves the arm: teaching reads where the arm stands.

use eframe::egui;

use super::ProgramPanel;
use super::edit::{taught_joint_step, taught_line_step, taught_pose_step};
use crate::panels::PanelContext;
use crate::panels::shortcuts::{Action, chords};

/// Why an entry that needs a selected step is greyed.
const NO_STEP: &str = "no step selected: click one in the program's step list";

/// One entry: its label, its keys (when the table binds some), greyed with `why` when set;
/// true when clicked.
fn entry(ui: &mut egui::Ui, label: &str, action: Option<Action>, why: Option<&str>) -> bool {
    let mut button = egui::Button::new(label);
    if let Some(a) = action {
        button = button.shortcut_text(chords(a));
    }
    let r = ui.add_enabled(why.is_none(), button);
    match why {
        Some(why) => r.on_disabled_hover_text(why).clicked(),
        None => r.clicked(),
    }
}

impl ProgramPanel {
    /// The Edit menu's entries (the menu bar draws the menu).
    pub fn edit_menu(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let running = ctx.app.program.as_ref().is_some_and(|p| !p.state.is_finished());
        let busy = running.then_some("a program is running: stop it to edit the program");
        let why = |ok: bool, reason: &'static str| busy.or((!ok).then_some(reason));
        let steps = self.program.steps.len();
        let selected = self.selected.filter(|&i| i < steps);
        let mut acted = false;
        if entry(ui, "Undo", Some(Action::Undo), why(self.editor.can_undo(), "nothing to undo")) {
            self.undo();
            acted = true;
        }
        if entry(ui, "Redo", Some(Action::Redo), why(self.editor.can_redo(), "nothing to redo")) {
            self.redo();
            acted = true;
        }
        ui.separator();
        let q = ctx.robot.q.clone();
        let teach_why = busy;
        if entry(ui, "Teach joints", None, teach_why) {
            self.teach(taught_joint_step(&q), ctx);
            acted = true;
        }
        if entry(ui, "Teach pose", None, teach_why) {
            let step = taught_pose_step(ctx.model, &q);
            self.teach(step, ctx);
            acted = true;
        }
        if entry(ui, "Teach line", None, teach_why) {
            let step = taught_line_step(ctx.model, &q);
            self.teach(step, ctx);
            acted = true;
        }
        ui.separator();
        if entry(ui, "Duplicate step", Some(Action::DuplicateStep), why(selected.is_some(), NO_STEP)) {
            self.duplicate(ctx);
            acted = true;
        }
        if entry(ui, "Delete step", Some(Action::DeleteStep), why(selected.is_some(), NO_STEP)) {
            self.delete(ctx);
            acted = true;
        }
        let up_why = if selected == Some(0) { why(false, "the selected step is the first") } else { None };
        if entry(ui, "Move step up", Some(Action::MoveStepUp), up_why.or(why(selected.is_some(), NO_STEP))) {
            self.move_selected(true, ctx);
            acted = true;
        }
        let last = selected.is_some_and(|i| i + 1 == steps);
        let down_why = if last { why(false, "the selected step is the last") } else { None };
        if entry(ui, "Move step down", Some(Action::MoveStepDown), down_why.or(why(selected.is_some(), NO_STEP))) {
            self.move_selected(false, ctx);
            acted = true;
        }
        ui.separator();
        let table = if self.table_open { "Close point table" } else { "Point table" };
        // the table opens during a run too, read-only
        if entry(ui, table, None, None) {
            self.table_open = !self.table_open;
            acted = true;
        }
        if acted {
            ui.close();
        }
    }
}
