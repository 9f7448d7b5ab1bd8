//! Saving never replaces a file's contents without a word: "Save as" onto another program's
//! existing file asks "Replace it?", and "Save" onto the program's own file asks when that file
//! changed on disk since this window read or wrote it (another window, an editor). Both were
//! silent: a chosen name lost the file it named, and a second window's save lost the first's.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use eframe::egui;

use super::ProgramPanel;
use crate::palette;
use crate::panels::PanelContext;

/// What a file was when this window last read or wrote it: its length and its time of last
/// change. Another stamp later means somebody else wrote it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct DiskStamp {
    len_bytes: u64,
    modified: Option<SystemTime>,
}

impl DiskStamp {
    /// The stamp of `path` now; `None` when it does not exist or cannot be read.
    pub fn of(path: &Path) -> Option<Self> {
        let meta = std::fs::metadata(path).ok()?;
        Some(Self { len_bytes: meta.len(), modified: meta.modified().ok() })
    }
}

/// A save that waits for the operator's answer.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum SaveQuestion {
    /// "Save as" onto a file that exists and is not the program's own.
    Replace(PathBuf),
    /// "Save" onto the program's own file, which changed on disk since this window read or
    /// wrote it.
    ChangedOnDisk(PathBuf),
    /// "Save" onto the program's own file, whose comment lines (this many) the written program
    /// would not hold (`comment_guard`).
    DropsComments(PathBuf, usize),
}

impl ProgramPanel {
    /// Remembers what `path` is on disk now: the program was just read from it or written to it.
    pub(super) fn stamp_file(&mut self, path: &Path) {
        self.files.disk = DiskStamp::of(path).map(|s| (path.to_path_buf(), s));
    }

    /// True when the program's own file `path` was changed on disk by somebody else since this
    /// window read or wrote it. A file that is gone is not "changed": saving writes it again.
    pub(super) fn changed_on_disk(&self, path: &Path) -> bool {
        match &self.files.disk {
            Some((stamped, stamp)) if stamped == path => DiskStamp::of(path).is_some_and(|now| now != *stamp),
            _ => false,
        }
    }

    /// Saves to `path` now, or first asks (the file changed on disk or holds comments the save
    /// would drop, or "Save as" names another existing file).
    pub(super) fn save_or_ask(&mut self, path: PathBuf, ctx: &mut PanelContext<'_>) {
        let own = self.file.as_deref() == Some(path.as_path());
        let dropped = if own {
            self.comments_a_save_drops(&path, ctx.model, &ctx.live_robot.commanded.q, ctx.settings)
        } else {
            0
        };
        if own && self.changed_on_disk(&path) {
            self.files.question = Some(SaveQuestion::ChangedOnDisk(path));
        } else if dropped > 0 {
            self.files.question = Some(SaveQuestion::DropsComments(path, dropped));
        } else if !own && path.exists() {
            self.files.question = Some(SaveQuestion::Replace(path));
        } else {
            self.save_and_say(&path, ctx);
        }
    }

    fn save_and_say(&mut self, path: &Path, ctx: &mut PanelContext<'_>) {
        match self.save_to(path, ctx) {
            Ok(message) => ctx.info(message),
            Err(e) => ctx.error(e),
        }
    }

    /// True while a save waits for the operator's answer.
    pub fn save_question_open(&self) -> bool {
        self.files.question.is_some()
    }

    /// Closes the save question without saving (Esc).
    pub fn cancel_save_question(&mut self) {
        self.files.question = None;
    }

    /// The save question, while it is open: a window over the others that dims them, so that
    /// nothing in the panel moves; Esc or a click outside cancels.
    pub(super) fn save_question(&mut self, ui: &egui::Ui, ctx: &mut PanelContext<'_>) {
        let Some(question) = self.files.question.clone() else { return };
        let (heading, text, yes) = match &question {
            SaveQuestion::Replace(path) => (
                "Replace the file?",
                format!(
                    "{} already exists. Replace it with the program \"{}\"? Its contents will be lost.",
                    path.display(),
                    self.program.name
                ),
                "Replace",
            ),
            SaveQuestion::ChangedOnDisk(path) => (
                "The file changed on disk",
                format!(
                    "{} changed on disk since this window read or saved it (another window or program \
                     wrote it). Overwrite it with the program here, or save this one under another name?",
                    path.display()
                ),
                "Overwrite",
            ),
            SaveQuestion::DropsComments(path, n) => (
                "Comments would be lost",
                format!(
                    "{} has {n} comment line{} that the program does not hold: Save writes the file from \
                     the program's steps, without them. Save anyway, or save under another name and keep \
                     this file as it is?",
                    path.display(),
                    if *n == 1 { "" } else { "s" }
                ),
                "Save anyway",
            ),
        };
        let (mut save, mut save_as, mut cancel) = (false, false, false);
        let modal = egui::Modal::new(egui::Id::unique("parol6_save_question")).show(ui.ctx(), |ui| {
            ui.set_max_width(460.0);
            ui.heading(heading);
            ui.add(egui::Label::new(egui::RichText::new(text).color(palette::rgb(palette::PATH_WARNING))).wrap());
            ui.add_space(6.0);
            ui.horizontal(|ui| {
                save = ui.button(yes).on_hover_text("write the program to this file").clicked();
                save_as = ui.button("Save as…").on_hover_text("choose another file name").clicked();
                cancel = ui.button("Cancel").on_hover_text("keep the file as it is on disk").clicked();
            });
        });
        if save {
            self.files.question = None;
            match question {
                // "Overwrite" agrees to replace the other writer's text, not to lose the file's
                // comments: those are still asked about (trial18: they went without a word)
                SaveQuestion::ChangedOnDisk(path) => {
                    let dropped =
                        self.comments_a_save_drops(&path, ctx.model, &ctx.live_robot.commanded.q, ctx.settings);
                    if dropped > 0 {
                        self.files.question = Some(SaveQuestion::DropsComments(path, dropped));
                    } else {
                        self.save_and_say(&path, ctx);
                    }
                }
                SaveQuestion::Replace(path) | SaveQuestion::DropsComments(path, _) => self.save_and_say(&path, ctx),
            }
        } else if save_as {
            self.files.question = None;
            self.open_save_as_dialog();
        } else if cancel || modal.should_close() {
            self.files.question = None;
        }
    }
}
