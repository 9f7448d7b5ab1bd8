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
