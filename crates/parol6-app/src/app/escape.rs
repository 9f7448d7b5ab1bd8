//! What Esc does: STOP, or close the topmost dialog.
//!
//! Esc is STOP (the shortcut table's first row) whenever the arm or a program moves, whenever
//! the pointer is over the 3D view (not covered by a window), and whenever a control of the
//! docked panels (a motion control, a joint entry) has the keyboard. Otherwise, with a dialog,
//! menu or window open, it closes the topmost one instead: the quit question, the torque
//! question, a save's question, an open menu, then the topmost of the file dialog, the point
//! table and the help (a field typed into inside that window first gives up the keyboard,
//! dropping what was typed). With nothing open it is STOP again.

use eframe::egui;
use parol6_core::program::runner::RunState;

use super::Parol6App;

/// The help window's title (its id).
pub(super) const HELP_WINDOW: &str = "Help";

/// What one Esc closes instead of stopping.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Closable {
    /// The "unsaved changes" question on quitting.
    QuitPrompt,
    /// The "torque over the motor limits: run anyway?" question.
    RunConfirmation,
    /// The "replace the file?" / "the file changed on disk" question of a save.
    SaveQuestion,
    /// The "unsaved changes: discard them?" question before another program opens.
    DiscardQuestion,
    /// An open menu or popup.
    Menu,
    /// The program panel's Open / Save-as dialog.
    FileDialog,
    /// The File menu's recording dialog.
    RecordingDialog,
    /// The point-table window.
    PointTable,
    /// The help window.
    Help,
    /// A field typed into inside the topmost window: it gives up the keyboard.
    Field(egui::Id),
}

/// Where [`remember_focus`] keeps the widget that had the keyboard at the end of a frame.
fn focus_memory_id() -> egui::Id {
    egui::Id::unique("parol6-escape-focus-at-frame-end")
}

/// Notes which widget has the keyboard as the frame ends. egui drops the focus when Esc goes
/// down, before the next frame's code runs, so [`Parol6App::escape_closes`] reads the widget that
/// had the keyboard from here: a field typed into inside a window gives up the keyboard on the
/// first Esc, and the window stays open (trial 19 m1: Esc in a point-table cell closed the table).
pub(super) fn remember_focus(ctx: &egui::Context) {
    let focus = ctx.memory(|m| m.focused());
    ctx.data_mut(|d| d.insert_temp(focus_memory_id(), focus));
}

/// The widget that had the keyboard before this frame's input (see [`remember_focus`]).
fn focus_before_input(ctx: &egui::Context) -> Option<egui::Id> {
    ctx.memory(|m| m.focused()).or_else(|| ctx.data(|d| d.get_temp::<Option<egui::Id>>(focus_memory_id())).flatten())
}

/// True when Esc went down this frame (before the STOP shortcut consumes it).
fn esc_pressed(ctx: &egui::Context) -> bool {
    ctx.input(|i| i.events.iter().any(|e| matches!(e, egui::Event::Key { key: egui::Key::Escape, pressed: true, .. })))
}

impl Parol6App {
    /// What this frame's Esc closes, or `None` when it is STOP (see the module's rules).
    /// `arm_moving`: the live arm moves.
    pub(super) fn escape_closes(&self, ctx: &egui::Context, arm_moving: bool) -> Option<Closable> {
        if !esc_pressed(ctx) || arm_moving {
            return None;
        }
        let program_moving =
            self.state.program.as_ref().is_some_and(|p| matches!(p.state, RunState::Preparing | RunState::Running));
        if program_moving || self.pointer_over_view(ctx) {
            return None;
        }
        let focus = focus_before_input(ctx);
        let focus_layer = focus.and_then(|id| ctx.read_response(id)).map(|r| r.layer_id);
        if focus_layer.is_some_and(|l| l.order == egui::Order::Background) {
            return None; // a control of the docked panels has the keyboard
        }
        if self.quit_prompt {
            return Some(Closable::QuitPrompt);
        }
        if self.panels.program.run_confirmation_open() {
            return Some(Closable::RunConfirmation);
        }
        if self.panels.program.save_question_open() {
            return Some(Closable::SaveQuestion);
        }
        if self.panels.program.discard_question_open() {
            return Some(Closable::DiscardQuestion);
        }
        if egui::Popup::is_any_open(ctx) || ctx.any_popup_open() {
            return Some(Closable::Menu);
        }
        let program_shown = !self.program_running();
        let windows = [
            (Closable::FileDialog, self.panels.program.file_dialog_open(), crate::panels::program::FILE_DIALOG_ID),
            (Closable::RecordingDialog, self.files.dialog_open(), super::file_menu::RECORDING_DIALOG_ID),
            (Closable::PointTable, program_shown && self.panels.program.table_open, crate::panels::program::TABLE_ID),
            (Closable::Help, self.show_help, HELP_WINDOW),
        ];
        let layer = |id: &str| egui::LayerId::new(egui::Order::Middle, egui::Id::unique(id));
        let top = ctx.top_layer_id();
        let open = windows.iter().filter(|w| w.1);
        let (what, _, id) = open.clone().find(|w| top == Some(layer(w.2))).or_else(|| open.clone().next())?;
        match focus {
            Some(f) if focus_layer == Some(layer(id)) => Some(Closable::Field(f)),
            _ => Some(*what),
        }
    }

    /// Closes `what` (an Esc that is not STOP).
    pub(super) fn close_on_escape(&mut self, ctx: &egui::Context, what: Closable) {
        match what {
            Closable::QuitPrompt => self.quit_prompt = false,
            Closable::RunConfirmation => self.panels.program.cancel_run_confirmation(),
            Closable::SaveQuestion => self.panels.program.cancel_save_question(),
            Closable::DiscardQuestion => self.panels.program.cancel_discard_question(),
            Closable::Menu => egui::Popup::close_all(ctx),
            Closable::FileDialog => self.panels.program.close_file_dialog(),
            Closable::RecordingDialog => self.files.close_dialog(),
            Closable::PointTable => self.panels.program.table_open = false,
            Closable::Help => self.show_help = false,
            Closable::Field(id) => ctx.memory_mut(|m| m.surrender_focus(id)),
        }
        ctx.request_repaint();
    }

    /// True while the pointer is over the 3D view and no window covers it there.
    pub(super) fn pointer_over_view(&self, ctx: &egui::Context) -> bool {
        let Some(pos) = ctx.pointer_hover_pos() else { return false };
        self.view_rect.is_some_and(|r| r.contains(pos))
            && ctx.layer_id_at(pos).is_none_or(|l| l.order == egui::Order::Background)
    }
}
