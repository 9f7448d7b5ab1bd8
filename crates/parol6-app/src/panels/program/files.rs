//! Program files in the panel: open (typed path, file dialog, recent files, built-ins), save,
//! save as. Opening over unsaved edits asks first; a file that fails to load leaves the
//! program in memory as it is; saving writes atomically and names the file in every message,
//! and asks before it replaces another file or one changed on disk (`file_guard`).

use std::path::{Path, PathBuf};

use eframe::egui;
use parol6_core::program::files::{FormatContext, ProgramFormat, export_notes, write_program};
use parol6_core::program::gcode::AbcChoice;

use super::ProgramPanel;
use crate::panels::PanelContext;

/// What the operator asked to open.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum OpenRequest {
    /// A built-in program, by name.
    Builtin(String),
    /// A program file.
    File(PathBuf),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum DialogKind {
    Open,
    SaveAs,
}

/// The panel's file state between frames.
#[derive(Default)]
pub(super) struct FileState {
    /// The open file dialog, if one is shown.
    dialog: Option<(DialogKind, egui_file::FileDialog)>,
    /// An open that waits for "discard unsaved edits?".
    pending: Option<OpenRequest>,
    /// The folder the dialog last showed (browsed to, opened from, saved to, or left by
    /// Cancel / Esc); `None` until the settings' folder is read at the first frame.
    folder: Option<PathBuf>,
    /// [`Self::folder`] was read from the settings.
    folder_loaded: bool,
    /// A save that waits for "replace it?" / "overwrite it?" (`file_guard`).
    pub(super) question: Option<super::file_guard::SaveQuestion>,
    /// The program's file and what it was on disk when this window last read or wrote it.
    pub(super) disk: Option<(PathBuf, super::file_guard::DiskStamp)>,
}

/// How far into a `.json` file the dialog looks for the program header.
const JSON_SNIFF_BYTES: u64 = 16 * 1024;

/// Files the dialogs list: the formats the program reads and, for `.json`, only files whose
/// beginning names the program format (`"format": "parol6-program"`), so the app's own
/// `settings.json` or another tool's JSON is not offered as a program. The check reads at most
/// [`JSON_SNIFF_BYTES`] once per listing of the folder; a file that cannot be read is listed
/// (opening it then says why).
fn is_program_file(path: &Path) -> bool {
    match ProgramFormat::from_path(path) {
        Ok(ProgramFormat::Json) => json_names_program_format(path).unwrap_or(true),
        Ok(_) => true,
        Err(_) => false,
    }
}

/// `Some(true)` when the file's beginning holds the program format's name.
fn json_names_program_format(path: &Path) -> Option<bool> {
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path).ok()?.take(JSON_SNIFF_BYTES).read_to_end(&mut head).ok()?;
    let marker = format!("\"{}\"", parol6_core::program::json::FORMAT);
    Some(head.windows(marker.len()).any(|w| w == marker.as_bytes()))
}

impl ProgramPanel {
    /// The file rows: typed path + Open, Browse / Save / Save as / Recent, the source line and
    /// the discard question when one is pending.
    pub(super) fn file_row(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.horizontal(|ui| {
            let label = ui.label("Program file");
            let edit = ui
                .add(
                    egui::TextEdit::singleline(&mut self.path_text)
                        .hint_text("program.json / .gcode / .csv / .txt")
                        .desired_width((ui.available_width() - 60.0).max(60.0)),
                )
                .labelled_by(label.id);
            let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if (ui.button("Open").clicked() || enter) && !self.path_text.trim().is_empty() {
                let path = crate::typed_path::typed_path(&self.path_text);
                self.request_open(OpenRequest::File(path), ctx);
            }
        });
        ui.horizontal(|ui| {
            if ui.button("Browse…").on_hover_text(format!("Open a program file ({})", ProgramFormat::list())).clicked()
            {
                self.show_dialog(DialogKind::Open);
            }
            let save = ui.button("Save").on_hover_text("Save to the file it came from (Ctrl+S)");
            if save.clicked() {
                self.save(ctx);
            }
            if ui.button("Save as…").clicked() {
                self.show_dialog(DialogKind::SaveAs);
            }
            let recent = ctx.settings.recent_programs.clone();
            ui.add_enabled_ui(!recent.is_empty(), |ui| {
                ui.menu_button("Recent", |ui| {
                    for path in recent {
                        if ui.button(&path).clicked() {
                            self.request_open(OpenRequest::File(PathBuf::from(&path)), ctx);
                            ui.close();
                        }
                    }
                });
            });
        });
        let mark = if self.editor.is_dirty() { " (unsaved changes)" } else { "" };
        ui.add(
            egui::Label::new(egui::RichText::new(format!("{}: {}{mark}", self.program.name, self.source)).weak())
                .truncate(),
        );
        self.discard_question(ui, ctx);
    }

    /// "Unsaved changes: discard them?" before another program opens, while it is asked: a
    /// window over the others that dims them (inline, it pushed the Run buttons and the step
    /// list 46 px down under the pointer: trial 21 m16, trial 22 m1); Esc or a click outside keeps
    /// editing.
    fn discard_question(&mut self, ui: &egui::Ui, ctx: &mut PanelContext<'_>) {
        let Some(request) = self.files.pending.clone() else { return };
        let (mut discard, mut keep) = (false, false);
        let modal = egui::Modal::new(egui::Id::unique("parol6_discard_question")).show(ui.ctx(), |ui| {
            ui.set_max_width(460.0);
            ui.heading("Unsaved changes");
            let text = format!("Unsaved changes to {}. Discard them and open the other program?", self.program.name);
            ui.colored_label(crate::palette::rgb(crate::palette::PATH_WARNING), text);
            ui.add_space(6.0);
            ui.horizontal(|ui| {
                discard = ui.button("Discard").on_hover_text("drop the edits and open the other program").clicked();
                keep = ui.button("Keep editing").on_hover_text("open nothing; save the edits first").clicked();
            });
        });
        if discard {
            self.files.pending = None;
            self.open_now(request, ctx);
        } else if keep || modal.should_close() {
            self.files.pending = None;
        }
    }

    /// True while the "discard unsaved changes?" question is open.
    pub fn discard_question_open(&self) -> bool {
        self.files.pending.is_some()
    }

    /// Closes the discard question, keeping the edits (Esc).
    pub fn cancel_discard_question(&mut self) {
        self.files.pending = None;
    }

    /// Opens `request`, first asking when there are unsaved edits.
    pub(super) fn request_open(&mut self, request: OpenRequest, ctx: &mut PanelContext<'_>) {
        if self.editor.is_dirty() {
            self.files.pending = Some(request);
        } else {
            self.open_now(request, ctx);
        }
    }

    fn open_now(&mut self, request: OpenRequest, ctx: &mut PanelContext<'_>) {
        match request {
            OpenRequest::Builtin(name) => {
                if self.load_builtin(&name) {
                    ctx.settings.last_program = Some(crate::app::remembered::LastProgram::Builtin(name));
                }
            }
            OpenRequest::File(path) => {
                if let Err(e) = self.load_file(&path, ctx) {
                    ctx.error(e);
                }
            }
        }
    }

    /// Starts loading a program file of any format (by extension) from the commanded pose on a
    /// worker, which reads and checks it (the panel shows "checking…" with its progress, then
    /// the program and "loaded …"); on an error the program in memory stays as it is. A newer
    /// open or check supersedes this one. `Err` when the worker cannot start.
    pub fn load_file(&mut self, path: &Path, ctx: &mut PanelContext<'_>) -> Result<(), String> {
        let start_q = ctx.live_robot.commanded.q.clone();
        // the G-code A/B/C setting is a default: a file's `; parol6: abc=…` header wins
        let abc = AbcChoice::default_to(ctx.settings.gcode_abc);
        self.reopening = None;
        self.start_load(ctx.model, path, abc, start_q)
    }

    /// At start: reopens the program file of the last session from `start_q`, read and
    /// checked on the worker as any open (until it arrives the built-in default is shown; if it
    /// cannot be read, a notice names the file and why, and the default stays). `Err`: the
    /// worker could not start (the message names the file).
    pub fn reopen(
        &mut self,
        model: &parol6_core::RobotModel,
        path: PathBuf,
        abc: AbcChoice,
        start_q: Vec<f64>,
    ) -> Result<(), String> {
        self.start_load(model, &path, abc, start_q)
            .map_err(|e| format!("the last program, {}, was not reopened: {e}", path.display()))?;
        self.reopening = Some(path);
        Ok(())
    }

    /// [`Self::load_file`] without a frame's context: G-code `A B C` by `abc`, from `start_q`.
    pub fn start_load(
        &mut self,
        model: &parol6_core::RobotModel,
        path: &Path,
        abc: AbcChoice,
        start_q: Vec<f64>,
    ) -> Result<(), String> {
        let opts = parol6_core::program::check::CheckOptions { speed_override: self.speed_override };
        let job = super::checker::CheckJob::load(model, path, abc, start_q, opts)
            .map_err(|e| format!("cannot start reading {}: {e}", path.display()))?;
        self.job = Some(job);
        Ok(())
    }

    /// Saves to `path` (format from the extension); the program stays loaded and now comes
    /// from that file. `Ok`: the message to show ("saved …", and what the format made of the
    /// gripper and output steps, `files::export_notes`).
    pub fn save_to(&mut self, path: &Path, ctx: &mut PanelContext<'_>) -> Result<String, String> {
        let start_q = ctx.live_robot.commanded.q.clone();
        self.save_with(path, ctx.model, &start_q, ctx.settings)?;
        let mut message = format!("saved {}", path.display());
        if let Ok(format) = ProgramFormat::from_path(path) {
            for note in export_notes(self.editor.program(), format) {
                message.push_str("; ");
                message.push_str(&note);
            }
        }
        Ok(message)
    }

    /// [`Self::save_to`] without a frame's context: G-code is written from `start_q`.
    fn save_with(
        &mut self,
        path: &Path,
        model: &parol6_core::RobotModel,
        start_q: &[f64],
        settings: &mut crate::panels::Settings,
    ) -> Result<(), String> {
        let abc = AbcChoice::default_to(settings.gcode_abc);
        let fctx = FormatContext { abc, ..FormatContext::new(model, start_q) };
        write_program(self.editor.program(), path, &fctx).map_err(|e| e.to_string())?;
        self.editor.mark_saved();
        self.stamp_file(path);
        let shown = path.display().to_string();
        self.source = shown.clone();
        self.file = Some(path.to_path_buf());
        self.path_text = shown.clone();
        settings.remember_program(&shown);
        Ok(())
    }

    /// The file the program came from or was last saved to (`None`: built-in or new).
    pub fn file(&self) -> Option<&Path> {
        self.file.as_deref()
    }

    /// Saves before the window closes: `Ok(true)` saved to its file, `Ok(false)` it has no file
    /// yet (the Save-as dialog is opened instead), `Err` the write failed, the file changed on
    /// disk since this window read or wrote it, or it holds comments the save would drop
    /// (`comment_guard`; the message says why; nothing is written).
    pub fn save_before_quit(
        &mut self,
        model: &parol6_core::RobotModel,
        start_q: &[f64],
        settings: &mut crate::panels::Settings,
    ) -> Result<bool, String> {
        match self.file.clone() {
            Some(path) if self.changed_on_disk(&path) => Err(format!(
                "{} changed on disk since this window read or saved it (another window or program wrote it); \
                 Cancel, then Save or Save as… in the Program panel",
                path.display()
            )),
            Some(path) if self.comments_a_save_drops(&path, model, start_q, settings) > 0 => Err(format!(
                "{} has comment lines that Save would not keep; Cancel, then Save (it asks) or Save as… in \
                 the Program panel",
                path.display()
            )),
            Some(path) => self.save_with(&path, model, start_q, settings).map(|()| true),
            None => {
                self.show_dialog(DialogKind::SaveAs);
                Ok(false)
            }
        }
    }

    /// True while the Open / Save-as file dialog is shown.
    pub fn file_dialog_open(&self) -> bool {
        self.files.dialog.is_some()
    }

    /// Opens the Open-program file dialog, as Browse… does.
    pub fn open_file_dialog(&mut self) {
        self.show_dialog(DialogKind::Open);
    }

    /// Closes the file dialog (Esc), choosing nothing; the folder it showed is remembered.
    pub fn close_file_dialog(&mut self) {
        if let Some((_, dialog)) = self.files.dialog.take() {
            self.files.folder = Some(dialog.directory().to_path_buf());
        }
    }

    /// The folder the next file dialog opens in: the one the operator last browsed to (kept
    /// after Cancel too, and across restarts in the settings), else the program file's folder.
    pub fn dialog_folder(&self) -> Option<PathBuf> {
        self.files
            .folder
            .clone()
            .filter(|d| d.is_dir())
            .or_else(|| self.file.as_ref().and_then(|f| f.parent().map(Path::to_path_buf)))
    }

    /// "Save": to the file it came from (asking first when it changed on disk), else "Save as".
    pub(super) fn save(&mut self, ctx: &mut PanelContext<'_>) {
        match self.file.clone() {
            Some(path) => self.save_or_ask(path, ctx),
            None => self.show_dialog(DialogKind::SaveAs),
        }
    }

    /// Opens the Save-as file dialog, as Save as… does.
    pub(super) fn open_save_as_dialog(&mut self) {
        self.show_dialog(DialogKind::SaveAs);
    }

    fn show_dialog(&mut self, kind: DialogKind) {
        self.show_dialog_named(kind, None);
    }

    /// [`Self::show_dialog`]; Save as proposes `name` where given (else the file's name).
    fn show_dialog_named(&mut self, kind: DialogKind, name: Option<String>) {
        let start = self.dialog_folder();
        let mut dialog = match kind {
            // opening changes no file: no Rename, no New Folder
            DialogKind::Open => {
                egui_file::FileDialog::open_file().title("Open program").show_rename(false).show_new_folder(false)
            }
            DialogKind::SaveAs => {
                let name = name.or_else(|| {
                    self.file.as_ref().and_then(|f| f.file_name()).map(|n| n.to_string_lossy().into_owned())
                });
                egui_file::FileDialog::save_file()
                    .title("Save program as (.json, .gcode, .csv, .txt)")
                    .default_filename(name.unwrap_or_else(|| format!("{}.json", file_stem(&self.program.name))))
            }
        };
        dialog = dialog
            .show_files_filter(Box::new(|p: &Path| is_program_file(p)))
            .default_pos(crate::app::FLOATING_WINDOW_POS)
            .id(egui::Id::unique(super::FILE_DIALOG_ID));
        if let Some(dir) = start {
            dialog = dialog.initial_path(dir);
        }
        dialog.open();
        self.files.dialog = Some((kind, dialog));
    }

    /// Shows the file dialog if open; opens or saves what the operator picked.
    /// The folder it showed is remembered, whether a file was picked or not.
    pub(super) fn dialogs(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        self.sync_dialog_folder(ctx.settings);
        let Some((kind, dialog)) = &mut self.files.dialog else { return };
        let kind = *kind;
        let picked =
            dialog.show(ui.ctx()).selected().then(|| dialog.path().map(crate::typed_path::picked_path)).flatten();
        if !dialog.visible() {
            self.files.folder = Some(dialog.directory().to_path_buf());
            self.files.dialog = None;
            self.sync_dialog_folder(ctx.settings);
        }
        let Some(path) = picked else { return };
        self.files.dialog = None;
        match kind {
            DialogKind::Open => self.request_open(OpenRequest::File(path), ctx),
            DialogKind::SaveAs => {
                let path = if path.extension().is_none() { path.with_extension("json") } else { path };
                // a name the formats refuse: say why and ask again, with the name typed (trial 22
                // m14: the dialog closed, and the operator had to open it and find the folder again)
                if let Err(e) = ProgramFormat::from_path(&path) {
                    ctx.error(e.to_string());
                    let typed = path.file_name().map(|n| n.to_string_lossy().into_owned());
                    self.show_dialog_named(DialogKind::SaveAs, typed);
                    return;
                }
                self.save_or_ask(path, ctx);
            }
        }
    }
}

impl ProgramPanel {
    /// Reads the remembered dialog folder from the settings once, then keeps the settings'
    /// copy equal to the panel's (so it is saved with the other settings).
    fn sync_dialog_folder(&mut self, settings: &mut crate::panels::Settings) {
        if !self.files.folder_loaded {
            self.files.folder_loaded = true;
            if self.files.folder.is_none() {
                self.files.folder = settings.program_folder.as_ref().map(PathBuf::from);
            }
        }
        let shown = self.files.folder.as_ref().map(|d| d.display().to_string());
        if shown.is_some() && settings.program_folder != shown {
            settings.program_folder = shown;
        }
    }
}

/// A readable file name from a program name: letters, digits and `-` kept, `&` read as
/// "and", any other run of characters one `_`, none at either end ("Pick & place" →
/// "Pick_and_place", not "Pick___place").
fn file_stem(name: &str) -> String {
    let mut s = String::new();
    for c in name.replace('&', " and ").chars() {
        if c.is_ascii_alphanumeric() || c == '-' {
            s.push(c);
        } else if !s.is_empty() && !s.ends_with('_') {
            s.push('_');
        }
    }
    let s = s.trim_matches('_');
    if s.is_empty() { "program".into() } else { s.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_stems_are_safe_and_readable() {
        assert_eq!(file_stem("Pick & place"), "Pick_and_place");
        assert_eq!(file_stem(""), "program");
        assert_eq!(file_stem("../etc"), "etc");
        assert_eq!(file_stem("  a -- b  "), "a_--_b");
        assert_eq!(file_stem("&"), "and");
    }
}
