//! Quitting (Ctrl+Q or the window's close button): with unsaved program edits the window asks
//! first, naming the program and its file, and offers "Save and quit", "Discard and quit" and
//! "Cancel" (as opening another program does).

use eframe::egui;

use super::Parol6App;

impl Parol6App {
    /// Closes the window on Ctrl+Q (`ctrl_q`) or when the window was told to close, unless the
    /// program has unsaved edits: then the close is held and the question shown.
    pub(super) fn quit_requests(&mut self, ctx: &egui::Context, ctrl_q: bool) {
        let close_requested = ctx.input(|i| i.viewport().close_requested());
        if !(ctrl_q || close_requested) {
            return;
        }
        if self.quit_closing || !self.panels.program.is_dirty() {
            // sent with the rest of the frame's output (see `quit_prompt_ui`)
            self.close_now |= ctrl_q;
            return;
        }
        if close_requested {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
        }
        self.quit_prompt = true;
    }

    /// True while the "unsaved changes" question is shown.
    pub fn quit_prompt_open(&self) -> bool {
        self.quit_prompt
    }

    /// The question, while it is open: Save (then quit), Discard (quit), Cancel (or a click
    /// outside it: keep working).
    pub(super) fn quit_prompt_ui(&mut self, ctx: &egui::Context) {
        if !self.quit_prompt {
            if std::mem::take(&mut self.close_now) {
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
            return;
        }
        let name = self.panels.program.program().name.clone();
        let place = match self.panels.program.file() {
            Some(f) => format!("file {}", f.display()),
            None => "not saved to a file yet".to_string(),
        };
        let (mut save, mut discard, mut cancel) = (false, false, false);
        let modal = egui::Modal::new(egui::Id::unique("parol6_quit_prompt")).show(ctx, |ui| {
            ui.set_max_width(420.0);
            ui.heading("Unsaved changes");
            ui.label(format!("The program \"{name}\" ({place}) has unsaved edits. Save them before quitting?"));
            ui.add_space(6.0);
            ui.horizontal(|ui| {
                save = ui.button("Save and quit").on_hover_text("save to the file, then quit").clicked();
                discard = ui.button("Discard and quit").on_hover_text("quit without saving the edits").clicked();
                cancel = ui.button("Cancel").on_hover_text("keep working").clicked();
            });
        });
        if cancel || (!save && !discard && modal.should_close()) {
            self.quit_prompt = false;
            return;
        }
        if save {
            let q = self.robot_state().commanded.q.clone();
            match self.panels.program.save_before_quit(&self.model, &q, &mut self.settings) {
                Ok(true) => discard = true,
                Ok(false) => {
                    self.quit_prompt = false;
                    self.notice(format!("choose where to save \"{name}\", then quit again"), false);
                }
                Err(e) => self.notice(format!("not saved, still open: {e}"), true),
            }
        }
        if discard {
            self.quit_prompt = false;
            self.quit_closing = true;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        ctx.request_repaint();
    }
}
