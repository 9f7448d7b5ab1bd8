//! The window's look: egui visuals and the background the window is cleared to.
//! (Colours come from [`crate::palette`]; limit-zone / LED colours live in `parol6_core::limits`.)
//!
//! Panels are drawn without a fill, over a window cleared to the panel colour. On a software
//! rasterizer every full-window textured fill costs tens of milliseconds per frame at
//! 1280×800, so this saves most of the frame while looking the same.

use eframe::egui;

/// Panel background, sRGB (from the palette).
pub const PANEL_BG_SRGB: [u8; 3] = crate::palette::PANEL_BG;

/// The app's visuals: egui's dark theme with transparent panel fills, and windows and menus
/// set off by their border instead of a drop shadow. A shadow is a soft rectangle as large as
/// its window, drawn under it: on a software rasterizer it was a fifth of the time a window
/// (the point table) took to appear.
pub fn visuals() -> egui::Visuals {
    let mut v = egui::Visuals::dark();
    v.panel_fill = egui::Color32::TRANSPARENT;
    v.window_shadow = egui::Shadow::NONE;
    v.popup_shadow = egui::Shadow::NONE;
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

/// Corner radius of a progress or level bar, pt. egui rounds a bar's ends by half its height by
/// default and then fills at least a full circle, so a bar at or near 0 showed a grey disc over
/// the start of its text (the Manipulability bar at a singular pose); with this radius the
/// least fill is a 4 pt sliver.
pub const BAR_CORNER_RADIUS: u8 = 2;

/// A progress or level bar at `fraction` (0…1) in the app's style ([`BAR_CORNER_RADIUS`]).
pub fn bar(fraction: f32) -> egui::ProgressBar {
    egui::ProgressBar::new(fraction).corner_radius(BAR_CORNER_RADIUS)
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

    /// The fill of each bar [`bar`] paints at `fraction`, as (width, height), pt.
    fn bar_fill(fraction: f32) -> (f32, f32) {
        let ctx = egui::Context::default();
        ctx.set_visuals(visuals());
        let out = ctx.run_ui(Default::default(), |ui| {
            ui.add(bar(fraction).fill(egui::Color32::RED).desired_width(200.0));
        });
        let fills: Vec<egui::Rect> = out
            .shapes
            .iter()
            .filter_map(|c| match &c.shape {
                egui::Shape::Rect(r) if r.fill == egui::Color32::RED => Some(r.rect),
                _ => None,
            })
            .collect();
        assert_eq!(fills.len(), 1, "one fill: {fills:?}");
        (fills[0].width(), fills[0].height())
    }

    /// Hand trial, 1024×700 on the fake robot at standby (J5 = 0, a singular wrist): the
    /// Manipulability bar at 0 drew a full grey disc over "wrist singular".
    #[test]
    fn a_bar_at_zero_fills_a_sliver_not_a_disc() {
        let (w0, h) = bar_fill(0.0);
        assert!(w0 <= 2.0 * f32::from(BAR_CORNER_RADIUS) + 1e-3 && w0 < h / 2.0, "fill {w0} of a {h} pt bar");
        let (w_half, _) = bar_fill(0.5);
        assert!((w_half - 100.0).abs() < 1.0, "half of 200 pt: {w_half}");
    }

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
