//! The question before a run whose pre-flight warns of joint torque over the motor limits
//! (`CheckReport::torque_warnings`): the arm may lose steps, so Run / F5 / Step ask first.

use eframe::egui;

use parol6_core::program::check::CheckReport;

use super::ProgramPanel;
use crate::palette;
use crate::panels::PanelContext;

/// Text of the question: how many torque warnings, and the first one with its step and line.
pub(super) fn torque_question(report: &CheckReport, unit: crate::panels::AngleUnit) -> String {
    let first = report
        .issues
        .iter()
        .find(|i| i.message.contains("exceeds its motor limit"))
        .map(|i| {
            format!(
                "Step {} (line {}): {}",
                i.move_index + 1,
                i.line,
                crate::panels::angle_text::in_unit(&i.message, unit)
            )
        })
        .unwrap_or_default();
    format!(
        "Pre-flight found {} where a joint needs more torque than its motor gives. \
         The arm may lose steps or sag. {first}",
        parol6_core::plural::count(report.torque_warnings, "stretch")
    )
}

impl ProgramPanel {
    /// Starts a run (`single_step`: one step, then pause), or first asks when the pre-flight
    /// warns of torque over the motor limits.
    pub(super) fn start_run(&mut self, ctx: &mut PanelContext<'_>, single_step: bool) {
        let torque = self.checked.as_ref().is_some_and(|c| c.report.torque_warnings > 0);
        if torque {
            self.confirm_run = Some(single_step);
        } else {
            ctx.send(self.run_command(single_step));
        }
    }

    /// Step (F10): one step of a paused run (`paused_at`: its step), or a run of the first step
    /// that then pauses. Steps blended into one path run together, and the notice says which
    /// (trial 23 D1: one F10 ran steps 3–6 of Draw without a word).
    pub(super) fn step_once(&mut self, ctx: &mut PanelContext<'_>, paused_at: Option<usize>) {
        let from = paused_at.unwrap_or(0);
        let end = parol6_core::program::compile::blended_chain_end(&self.program, from);
        if end > from {
            ctx.info(format!(
                "Step runs steps {}–{} together: they are blended into one path (blend); set their blend \
                 to 0 to step through them one by one",
                from + 1,
                end + 1
            ));
        }
        match paused_at {
            Some(_) => ctx.send(crate::panels::AppCommand::Program(parol6_core::program::runner::RunnerControl::Step)),
            None => self.start_run(ctx, true),
        }
    }

    /// True while the torque question is open.
    pub fn run_confirmation_open(&self) -> bool {
        self.confirm_run.is_some()
    }

    /// Closes the torque question without running (Esc).
    pub fn cancel_run_confirmation(&mut self) {
        self.confirm_run = None;
    }

    /// The torque question, while it is open: "Run anyway" starts the run, "Cancel" (or a
    /// click outside) does not.
    pub(super) fn run_confirmation(&mut self, ui: &egui::Ui, ctx: &mut PanelContext<'_>) {
        let Some(single_step) = self.confirm_run else { return };
        let Some(checked) = &self.checked else {
            self.confirm_run = None;
            return;
        };
        let text = torque_question(&checked.report, ctx.settings.unit);
        let (mut run, mut cancel) = (false, false);
        let modal = egui::Modal::new(egui::Id::unique("parol6_torque_confirm")).show(ui.ctx(), |ui| {
            ui.set_max_width(460.0);
            ui.heading("Joint torque over the motor limits");
            ui.add(egui::Label::new(egui::RichText::new(text).color(palette::rgb(palette::PATH_WARNING))).wrap());
            ui.add_space(6.0);
            ui.horizontal(|ui| {
                run = ui.button("Run anyway").on_hover_text("start the program as planned").clicked();
                cancel =
                    ui.button("Cancel").on_hover_text("do not run; slow the steps down or lighten the load").clicked();
            });
        });
        if run {
            self.confirm_run = None;
            ctx.send(self.run_command(single_step));
        } else if cancel || modal.should_close() {
            self.confirm_run = None;
        }
    }
}
