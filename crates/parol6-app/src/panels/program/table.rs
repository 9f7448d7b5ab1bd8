//! The point-table window: every step's numbers in a grid (joint angles in the chosen unit,
//! positions in mm, orientations in the chosen convention, speeds), each cell committed on
//! Enter or focus loss as one undoable edit. A header row is repeated where the columns
//! change (a joint step after Cartesian ones). Steps without numbers here (arcs, splines,
//! gripper, I/O) show their summary. While a program runs (or is paused) the table stays open,
//! read-only, and says that editing waits for the run to end.

use eframe::egui;

use super::ProgramPanel;
use crate::panels::PanelContext;
use crate::panels::entry::{self, EntryEvent};
use crate::panels::step_fields::{FieldSlot, step_fields, with_field};

/// Width of one number cell, px.
const CELL_WIDTH: f32 = 62.0;
/// What the table says while a program runs (its cells and row buttons are greyed).
pub const READ_ONLY_WHILE_RUNNING: &str = "A program is running: read-only; editing waits for the run to end.";

/// Space between two rows of the table, px.
const TABLE_ROW_SPACING: f32 = 2.0;

/// One line of the table: the columns' names where they change, or a step and its fields.
enum TableRow {
    Header(Vec<String>),
    Step(usize, Vec<crate::panels::step_fields::StepField>),
}

/// The table's lines: a header before the first step with numbers and wherever the columns
/// change.
fn table_rows(program: &parol6_core::program::Program, settings: &crate::panels::Settings) -> Vec<TableRow> {
    let mut rows = Vec::with_capacity(program.steps.len() + 1);
    let mut header: Vec<String> = Vec::new();
    for (i, s) in program.steps.iter().enumerate() {
        let fields = step_fields(&s.step, settings, &program.speed);
        let labels: Vec<String> = fields.iter().map(|f| format!("{} ({})", f.label, f.suffix)).collect();
        if !fields.is_empty() && labels != header {
            rows.push(TableRow::Header(labels.clone()));
            header = labels;
        }
        rows.push(TableRow::Step(i, fields));
    }
    rows
}

/// The names of the columns.
fn header_row(ui: &mut egui::Ui, labels: &[String]) {
    ui.strong("#");
    ui.strong("step");
    for l in labels {
        ui.strong(l);
    }
    ui.end_row();
}

impl ProgramPanel {
    /// Shows the window while [`ProgramPanel::table_open`]; read-only while `running` (the run
    /// steps through the program it started with: an edit now would not reach it).
    pub(super) fn table_window(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, running: bool) {
        let mut open = true;
        let mut change: Option<(usize, FieldSlot, f64, String)> = None;
        let mut select = None;
        let (mut add_row, mut remove_row) = (false, false);
        let program = std::sync::Arc::clone(&self.program);
        egui::Window::new(format!("Point table: {}", program.name))
            .id(egui::Id::unique(super::TABLE_ID))
            .open(&mut open)
            // drawn at once: a fade redraws the whole window for several frames, each as costly as
            // the first on a software rasterizer
            .fade_in(false)
            .fade_out(false)
            .default_pos(crate::app::FLOATING_WINDOW_POS)
            .default_size([640.0, 360.0])
            .resizable(true)
            .show(ui.ctx(), |ui| {
                // one line in either case: the rows below do not move when a run starts or ends
                if running {
                    ui.colored_label(crate::palette::rgb(crate::palette::WARN_TEXT), READ_ONLY_WHILE_RUNNING);
                } else {
                    ui.weak(format!(
                        "{} steps. Type a value, then Enter or Tab; Ctrl+Z undoes. Angles: {}, {}.",
                        program.steps.len(),
                        ctx.settings.unit.suffix().trim(),
                        ctx.settings.angle_convention.describe()
                    ));
                }
                ui.horizontal(|ui| {
                    // greyed while a program runs; the rows still scroll
                    if running {
                        ui.disable();
                    }
                    add_row = ui
                        .button("Add row")
                        .on_hover_text("a copy of the selected row (or the last one), after it; edit its numbers")
                        .clicked();
                    let selected = self.selected.filter(|&i| i < program.steps.len());
                    let remove = ui.add_enabled(selected.is_some(), egui::Button::new("Remove row"));
                    remove_row = remove
                        .on_hover_text("remove the selected row (Ctrl+Z undoes)")
                        .on_disabled_hover_text("click a row's number to select it")
                        .clicked();
                });
                // only the rows in view are laid out (a 1 000-step program took 170 ms a frame)
                let rows = table_rows(&program, ctx.settings);
                let row_h = ui.spacing().interact_size.y + TABLE_ROW_SPACING;
                let mut scroll = egui::ScrollArea::both().auto_shrink([false, false]);
                // a row just added: in the middle of the view (it is selected)
                if let Some(step) = self.table_scroll_to.take()
                    && let Some(k) = rows.iter().position(|r| matches!(r, TableRow::Step(i, _) if *i == step))
                {
                    let view_h = ui.available_height();
                    scroll = scroll.vertical_scroll_offset((k as f32 * row_h - 0.5 * (view_h - row_h)).max(0.0));
                }
                scroll.show_rows(ui, row_h, rows.len(), |ui, range| {
                    if running {
                        ui.disable();
                    }
                    egui::Grid::new("program-point-table-grid").striped(true).spacing([4.0, TABLE_ROW_SPACING]).show(
                        ui,
                        |ui| {
                            // the columns' names stay in view: the header of the first row shown
                            let first_header = rows[..=range.start.min(rows.len().saturating_sub(1))]
                                .iter()
                                .rev()
                                .find_map(|r| match r {
                                    TableRow::Header(labels) => Some(labels),
                                    TableRow::Step(..) => None,
                                });
                            if let (Some(labels), Some(TableRow::Step(..))) = (first_header, rows.get(range.start)) {
                                header_row(ui, labels);
                            }
                            for row in &rows[range] {
                                let (i, fields) = match row {
                                    TableRow::Header(labels) => {
                                        header_row(ui, labels);
                                        continue;
                                    }
                                    TableRow::Step(i, fields) => (*i, fields),
                                };
                                let Some(s) = program.steps.get(i) else { continue };
                                let selected = self.selected == Some(i);
                                if ui.selectable_label(selected, format!("{}", i + 1)).clicked() {
                                    select = Some(i);
                                }
                                ui.label(s.step.kind());
                                if fields.is_empty() {
                                    ui.add(egui::Label::new(egui::RichText::new(s.step.summary()).weak()).truncate());
                                }
                                for f in fields {
                                    let name = format!("table {} {}", i + 1, f.label);
                                    let (_, event) =
                                        entry::unit_entry(ui, &name, f.value, f.decimals, CELL_WIDTH, "", f.suffix);
                                    match event {
                                        Some(EntryEvent::Committed(v)) => {
                                            change = Some((i, f.slot, v, f.label.clone()))
                                        }
                                        Some(EntryEvent::Invalid(why)) => {
                                            ctx.error(format!("table row {}, {}: {why}", i + 1, f.label))
                                        }
                                        None => {}
                                    }
                                }
                                ui.end_row();
                            }
                        },
                    );
                });
            });
        if !open {
            self.table_open = false;
        }
        if let Some(i) = select {
            self.selected = Some(i);
        }
        if add_row {
            if self.selected.is_none() {
                self.selected = program.steps.len().checked_sub(1);
            }
            if self.selected.is_some() {
                self.duplicate(ctx);
                // the new row (selected by the copy) comes into view next frame
                self.table_scroll_to = self.selected;
            } else {
                ctx.error("the program has no row to copy: teach a step first");
            }
        }
        if remove_row {
            self.delete(ctx);
        }
        if let Some((i, slot, v, label)) = change
            && let Some(step) = self.editor.program().steps.get(i).map(|s| s.step.clone())
        {
            match with_field(&step, slot, v, ctx.settings) {
                Ok(new) => {
                    let r = self.editor.set_step(i, new);
                    if let Err(e) = r {
                        ctx.error(format!("table row {}: {e}", i + 1));
                    } else {
                        self.program_changed();
                    }
                }
                Err(why) => ctx.error(format!("table row {}, {label}: {why}", i + 1)),
            }
        }
    }
}
