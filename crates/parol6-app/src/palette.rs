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

/// An sRGB colour with alpha (unmultiplied) as an egui colour.
pub fn rgba(c: [u8; 4]) -> egui::Color32 {
    egui::Color32::from_rgba_unmultiplied(c[0], c[1], c[2], c[3])
}

/// STOP button fill.
pub const STOP_FILL: [u8; 3] = [170, 30, 30];
/// STOP button text.
pub const STOP_TEXT: [u8; 3] = [255, 255, 255];
/// An LED that is off.
pub const LED_OFF: [u8; 3] = [70, 70, 70];
/// The dark rim around every LED.
pub const LED_RIM: [u8; 4] = [0, 0, 0, 160];
/// Error notices over the 3D view (background).
pub const NOTICE_ERROR_BG: [u8; 4] = [200, 60, 60, 220];
/// Information notices over the 3D view (background).
pub const NOTICE_INFO_BG: [u8; 4] = [0, 92, 128, 220];
/// Notice text.
pub const NOTICE_TEXT: [u8; 3] = [255, 255, 255];
/// Placeholder drawn where the 3D view would be when it is unavailable.
pub const VIEW_PLACEHOLDER_BG: [u8; 3] = [30, 30, 30];
/// Text of that placeholder.
pub const VIEW_PLACEHOLDER_TEXT: [u8; 3] = [190, 190, 190];
/// Manipulability bar, well conditioned.
pub const CONDITION_GOOD: [u8; 3] = [0, 92, 128];
/// Manipulability bar at or near a singularity: information, not an alarm (a neutral slate,
/// deliberately neither amber nor red: those mean risk).
pub const CONDITION_SINGULAR: [u8; 3] = [96, 104, 120];
/// "ROBOT" source badge in the status bar (the arm shown is the real one).
pub const SOURCE_ROBOT: [u8; 3] = [255, 143, 0];
/// "SIMULATION" source badge in the status bar.
pub const SOURCE_SIM: [u8; 3] = [140, 200, 255];
/// "moving" in the status bar.
pub const MOVING_TEXT: [u8; 3] = [255, 143, 0];
/// Warning text (a scan that failed, a stale value).
pub const WARN_TEXT: [u8; 3] = [255, 143, 0];
/// Error text (no IK solution, a link error).
pub const ERROR_TEXT: [u8; 3] = [255, 80, 80];

// ---------------------------------------------------------------------------------------------
// Plots (reserved for the plots panel)
// ---------------------------------------------------------------------------------------------

// ---------------------------------------------------------------------------------------------
// 3D view: background, grid, robot, ghost, trail, frames, overlays
// ---------------------------------------------------------------------------------------------
