//! Fixed-height boxes: a section or a message line whose height does not follow its contents,
//! so that nothing below it moves under the pointer when its contents change (a pre-flight
//! count, a step editor opening, a run stopping, a message growing). What does not fit
//! scrolls inside the box.

use eframe::egui;

/// Lays out `add` in a box of exactly `height_pt` points and the available width, scrolling
/// inside when the contents are taller. `id_salt` names the box's scroll state. A box wholly
/// out of view (scrolled away) takes its place but lays nothing out: `None`.
pub fn fixed_height<R>(
    ui: &mut egui::Ui,
    id_salt: impl egui::AsIdSalt,
    height_pt: f32,
    add: impl FnOnce(&mut egui::Ui) -> R,
) -> Option<R> {
    let size = egui::vec2(ui.available_width(), height_pt);
    let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
    let clip = rect.intersect(ui.clip_rect());
    if !clip.is_positive() {
        return None;
    }
    let builder = egui::UiBuilder::new().max_rect(rect).layout(egui::Layout::top_down(egui::Align::Min));
    let mut child = ui.new_child(builder);
    child.set_clip_rect(clip);
    let area = egui::ScrollArea::vertical().id_salt(id_salt).max_height(height_pt).auto_shrink([false, false]);
    Some(area.show(&mut child, add).inner)
}

/// A message line of exactly `lines` text rows: longer text is cut with "…" (the whole text
/// shows on hover), shorter text leaves the rest empty.
pub fn message_lines(ui: &mut egui::Ui, text: egui::RichText, lines: usize) -> egui::Response {
    let row_h = ui.text_style_height(&egui::TextStyle::Body);
    let height = row_h * lines as f32 + ui.spacing().item_spacing.y * (lines.saturating_sub(1)) as f32;
    let size = egui::vec2(ui.available_width(), height);
    let (rect, resp) = ui.allocate_exact_size(size, egui::Sense::hover());
    let full = text.text().to_string();
    let clip = rect.intersect(ui.clip_rect());
    if !clip.is_positive() {
        return resp;
    }
    let builder = egui::UiBuilder::new().max_rect(rect).layout(egui::Layout::top_down(egui::Align::Min));
    let mut child = ui.new_child(builder);
    child.set_clip_rect(clip);
    let mut job = egui::text::LayoutJob::default();
    text.append_to(&mut job, child.style(), egui::FontSelection::Default, egui::Align::Min);
    job.wrap = egui::text::TextWrapping { max_rows: lines, break_anywhere: false, ..Default::default() };
    job.wrap.max_width = rect.width();
    child.add(egui::Label::new(job));
    if full.is_empty() { resp } else { resp.on_hover_text(full) }
}
