//! The window's look: egui visuals and the background the window is cleared to.
//! (Colours come from [`crate::palette`]; limit-zone / LED colours live in `parol6_core::limits`.)
//!
//! Panels are drawn without a fill, over a window cleared to the panel colour. On a software
//! rasterizer every full-window textured fill costs tens of milliseconds per frame at
//! 1280×800, so this saves most of the frame while looking the same.

use eframe::egui;

/// Panel background, sRGB (from the palette).
pub const PANEL_BG_SRGB: [u8; 3] = crate::palette::PANEL_BG;

/// The app's visuals: egui's dark theme with transparent panel fills.
pub fn visuals() -> egui::Visuals {
    let mut v = egui::Visuals::dark();
    v.panel_fill = egui::Color32::TRANSPARENT;
    v
}

/// Draws a ring ([`crate::palette::FOCUS_RING`]) around the widget that has the keyboard (a
/// button reached by Tab, a field being typed in), over everything, so that where Enter, Space
/// and typing go is plain to see: egui's own hint is a 1-point grey outline. Called once per
/// frame after the layout.
pub fn paint_focus_ring(ctx: &egui::Context) {
    use crate::palette::{FOCUS_RING, FOCUS_RING_GAP_PT, FOCUS_RING_WIDTH_PT};
    let Some(id) = ctx.memory(|m| m.focused()) else { return };
    let Some(widget) = ctx.read_response(id) else { return };
    // the part of the widget that is on screen (a scrolled list cuts it)
    let rect = widget.interact_rect;
    if !rect.is_positive() {
        return;
    }
    let layer = egui::LayerId::new(egui::Order::Foreground, egui::Id::unique("parol6_focus_ring"));
    ctx.layer_painter(layer).rect_stroke(
        rect.expand(FOCUS_RING_GAP_PT),
        3.0,
        egui::Stroke::new(FOCUS_RING_WIDTH_PT, crate::palette::rgb(FOCUS_RING)),
        egui::StrokeKind::Outside,
    );
}

/// The colour under every panel ([`PANEL_BG_SRGB`]).
pub fn panel_background() -> egui::Color32 {
    let [r, g, b] = PANEL_BG_SRGB;
    egui::Color32::from_rgb(r, g, b)
}

/// The clear colour matching [`PANEL_BG_SRGB`], as eframe wants it (normalised, gamma).
pub fn clear_color() -> [f32; 4] {
    let [r, g, b] = PANEL_BG_SRGB;
    egui::Color32::from_rgb(r, g, b).to_normalized_gamma_f32()
}

/// The file dialog's icons (egui_file draws 🗀 🗋 ⟲ ⬆ 💾 and 📁 📂, which egui's default fonts
/// lack, so they showed as boxes): two subsets of fonts egui itself ships, a few kB, used only
/// as the last fallback. See `assets/fonts/README.md` for their source and licences.
const DIALOG_ICON_FONTS: [(&str, &[u8]); 2] = [
    ("parol6-file-dialog-icons", include_bytes!("../../../assets/fonts/file-dialog-icons.ttf")),
    ("parol6-file-dialog-folders", include_bytes!("../../../assets/fonts/file-dialog-folders.ttf")),
];

/// Adds the app's fallback fonts (the file dialog's icons) to `ctx`. Cheap when they are
/// already there, so the app calls it every frame: any host (window, screenshot, UI tests)
/// gets the same glyphs.
pub fn install_fonts(ctx: &egui::Context) {
    for (name, data) in DIALOG_ICON_FONTS {
        let families = [egui::FontFamily::Proportional, egui::FontFamily::Monospace]
            .map(|family| egui::epaint::text::InsertFontFamily {
                family,
                priority: egui::epaint::text::FontPriority::Lowest,
            })
            .to_vec();
        ctx.add_font(egui::epaint::text::FontInsert::new(name, egui::FontData::from_static(data), families));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 32 minor: "The file dialog shows tofu icons".
    #[test]
    fn the_file_dialog_glyphs_have_a_font() {
        let ctx = egui::Context::default();
        install_fonts(&ctx);
        let _ = ctx.run_ui(Default::default(), |_| {});
        for glyph in ['🗀', '🗋', '⟲', '⬆', '💾', '📁', '📂'] {
            let has = ctx.fonts_mut(|f| f.has_glyph(&egui::FontId::proportional(14.0), glyph));
            assert!(has, "no font has {glyph:?} (U+{:04X})", glyph as u32);
        }
    }
}
