//! Every colour of the UI and the 3D view, in one place (design tokens). Limit-zone / LED
//! colours are not here: they are defined once in `parol6_core::limits` (`LimitZone::rgba`).
//!
//! Colours are sRGB bytes (`[r, g, b]` or `[r, g, b, a]`); helpers turn them into egui colours
//! or linear floats for the GPU.

use eframe::egui;

/// An sRGB colour as an egui colour.
pub const fn rgb(c: [u8; 3]) -> egui::Color32 {
    egui::Color32::from_rgb(c[0], c[1], c[2])
}

// ---------------------------------------------------------------------------------------------
// Window and panels
// ---------------------------------------------------------------------------------------------

/// Panel background (egui's dark theme panel colour); the window is cleared to it.
pub const PANEL_BG: [u8; 3] = [27, 27, 27];

// ---------------------------------------------------------------------------------------------
// Operator UI: text, badges, notices, LEDs that are not limit zones
// ---------------------------------------------------------------------------------------------

// ---------------------------------------------------------------------------------------------
// Plots (reserved for the plots panel)
// ---------------------------------------------------------------------------------------------

// ---------------------------------------------------------------------------------------------
// 3D view: background, grid, robot, ghost, trail, frames, overlays
// ---------------------------------------------------------------------------------------------
