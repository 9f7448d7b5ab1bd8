//! The File menu: open a recording for replay (a typed path, or *Browse…*: a file dialog that
//! lists `.mcap` files), the live servers, record to a file, and Quit. Its one-shot actions close
//! it, so their outcome (or error) is seen; a toggle (the sharing switches, Start / Stop
//! recording) keeps it open unless it fails (the app closes any menu over a new error).

use std::path::{Path, PathBuf};

use eframe::egui;

use super::layout::status_row;
use crate::palette;
use crate::panels::{AppCommand, PanelContext};

/// The id of the recording dialog's window (`egui::Id::unique` of it).
pub const RECORDING_DIALOG_ID: &str = "recording-file-dialog";

/// The File menu's state between frames.
#[derive(Default)]
pub struct FileMenu {
    /// Typed path of a recording to open.
    pub open_path: String,
    /// Typed path of a recording to write.
    pub record_path: String,
    /// *Quit* was clicked (taken by the app, which asks first over unsaved edits, as Ctrl+Q).
    pub quit_clicked: bool,
    /// *Start recording* on a path where a file exists asks first: the next click replaces it
    /// (the field still shows the last recording's path, or the one replayed).
    replace_ask: crate::panels::replace_ask::ReplaceAsk,
    /// The *Browse…* dialog for a recording, while it is shown.
    dialog: Option<egui_file::FileDialog>,
    /// The folder that dialog last showed (this session).
    folder: Option<PathBuf>,
}

impl std::fmt::Debug for FileMenu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FileMenu")
            .field("open_path", &self.open_path)
            .field("record_path", &self.record_path)
            .field("dialog_open", &self.dialog.is_some())
            .finish()
    }
}

/// True for a file the recording dialog lists.
fn is_recording(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("mcap"))
}

impl FileMenu {
    /// The menu's contents.
    pub(super) fn ui(&mut self, ui: &mut egui::Ui, pctx: &mut PanelContext<'_>) {
        ui.label("Open recording (.mcap)");
        ui.horizontal(|ui| {
            let label = ui.label("Recording");
            let edit = egui::TextEdit::singleline(&mut self.open_path).desired_width(240.0).hint_text("run.mcap");
            let r = ui.add(edit).labelled_by(label.id);
            let enter = r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if (ui.button("Open recording").clicked() || enter) && !self.open_path.trim().is_empty() {
                pctx.send(AppCommand::OpenRecording(crate::typed_path::typed_path(&self.open_path)));
                ui.close();
            }
            if ui.button("Browse recordings…").on_hover_text("Pick a recording (.mcap) in a file dialog").clicked() {
                self.show_dialog();
                ui.close();
            }
        });
        if pctx.app.replaying() && ui.button("Close recording").clicked() {
            pctx.send(AppCommand::CloseRecording);
            ui.close();
        }
        ui.separator();
        super::layout::live_menu_ui(ui, pctx);
        ui.separator();
        // Start and Stop are one toggle in one place: the rows keep their heights and the menu
        // stays open, as for the sharing toggles (a failure closes it over its error)
        let recording = pctx.app.recording.as_ref().map(|r| r.path.display().to_string());
        let typed = crate::typed_path::typed_path(&self.record_path);
        match (&recording, self.replace_ask.question(&typed, "Start recording again")) {
            (Some(path), _) => status_row(ui, egui::RichText::new(format!("recording to {path}"))),
            (None, Some(text)) => {
                let text = format!("{text} when stopped");
                status_row(ui, egui::RichText::new(text).color(palette::rgb(palette::PATH_WARNING)));
            }
            (None, None) => status_row(ui, egui::RichText::new("Record the active backend (.mcap)")),
        }
        ui.horizontal(|ui| {
            let label = ui.label("Record to");
            match recording {
                Some(mut path) => {
                    let edit = egui::TextEdit::singleline(&mut path).desired_width(240.0);
                    ui.add_enabled(false, edit).labelled_by(label.id);
                    if ui.button("Stop recording").clicked() {
                        pctx.send(AppCommand::Record(None));
                    }
                }
                None => {
                    let edit = egui::TextEdit::singleline(&mut self.record_path).desired_width(240.0);
                    ui.add(edit.hint_text("out.mcap")).labelled_by(label.id);
                    if ui.button("Start recording").clicked() && !self.record_path.trim().is_empty() {
                        // a recording replaces an existing file when it is finished: ask once
                        if self.replace_ask.may_write(&typed) {
                            pctx.send(AppCommand::Record(Some(typed)));
                        }
                    }
                }
            }
        });
        ui.separator();
        if ui.button("Quit (Ctrl+Q)").clicked() {
            self.quit_clicked = true;
            ui.close();
        }
    }

    fn show_dialog(&mut self) {
        // opening changes no file: no Rename, no New Folder
        let mut dialog = egui_file::FileDialog::open_file()
            .title("Open recording (.mcap)")
            .show_rename(false)
            .show_new_folder(false)
            .show_files_filter(Box::new(is_recording))
            .default_pos(super::layout::FLOATING_WINDOW_POS)
            .id(egui::Id::unique(RECORDING_DIALOG_ID));
        // the folder of the typed path (or the typed folder), else the one shown last
        let typed = crate::typed_path::typed_path(&self.open_path);
        let typed_dir =
            if typed.is_dir() { Some(typed) } else { typed.parent().filter(|p| p.is_dir()).map(Path::to_path_buf) };
        if let Some(dir) = typed_dir.filter(|d| !d.as_os_str().is_empty()).or_else(|| self.folder.clone()) {
            dialog = dialog.initial_path(dir);
        }
        dialog.open();
        self.dialog = Some(dialog);
    }

    /// True while the recording dialog is shown.
    pub fn dialog_open(&self) -> bool {
        self.dialog.is_some()
    }

    /// Closes the recording dialog (Esc).
    pub fn close_dialog(&mut self) {
        if let Some(d) = &self.dialog {
            self.folder = Some(d.directory().to_path_buf());
        }
        self.dialog = None;
    }

    /// Shows the recording dialog while it is open (every frame, menu open or not); a picked
    /// file is opened for replay, and its path is kept in the menu's field.
    pub(super) fn dialog_ui(&mut self, ctx: &egui::Context, pctx: &mut PanelContext<'_>) {
        let Some(dialog) = &mut self.dialog else { return };
        let picked = dialog.show(ctx).selected().then(|| dialog.path().map(crate::typed_path::picked_path)).flatten();
        if !dialog.visible() || picked.is_some() {
            self.close_dialog();
        }
        if let Some(path) = picked {
            self.open_path = path.display().to_string();
            pctx.send(AppCommand::OpenRecording(path));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_recording_dialog_lists_mcap_files_only() {
        assert!(is_recording(Path::new("/data/run.mcap")));
        assert!(is_recording(Path::new("RUN.MCAP")));
        assert!(!is_recording(Path::new("settings.json")));
        assert!(!is_recording(Path::new("mcap")));
    }
}
