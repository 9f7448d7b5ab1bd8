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

/// The ring around the widget that has the keyboard (Tab): a saturated yellow no widget, text
/// or alarm uses, 12:1 against [`PANEL_BG`].
pub const FOCUS_RING: [u8; 3] = [255, 214, 10];
/// Its line width, points (drawn outside the widget, [`FOCUS_RING_GAP_PT`] away from it).
pub const FOCUS_RING_WIDTH_PT: f32 = 2.0;
/// Gap between the widget and its focus ring, points.
pub const FOCUS_RING_GAP_PT: f32 = 1.0;

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
/// "LIVE ws://…" in the status bar while the window shares live.
pub const LIVE_TEXT: [u8; 3] = [120, 220, 140];
/// The "REMOTE CONTROL ON" banner: commands from the network can move the arm.
pub const REMOTE_CONTROL_BG: [u8; 3] = [200, 40, 40];
/// Its text.
pub const REMOTE_CONTROL_TEXT: [u8; 3] = [255, 255, 255];
/// "moving" in the status bar.
pub const MOVING_TEXT: [u8; 3] = [255, 143, 0];
/// Warning text (a scan that failed, a stale value).
pub const WARN_TEXT: [u8; 3] = [255, 143, 0];
/// Error text (no IK solution, a link error).
pub const ERROR_TEXT: [u8; 3] = [255, 80, 80];
/// Planned program path and pre-flight text: no problem.
pub const PATH_OK: [u8; 3] = [80, 210, 110];
/// Planned program path and pre-flight text: a warning.
pub const PATH_WARNING: [u8; 3] = [255, 176, 0];
/// Planned program path and pre-flight text: an error.
pub const PATH_ERROR: [u8; 3] = [255, 70, 70];

// ---------------------------------------------------------------------------------------------
// Plots
// ---------------------------------------------------------------------------------------------

/// Plot series, one per joint (J1…J6) or axis (x / roll, y / pitch, z / yaw): distinct hues
/// that read on the dark panel background.
pub const PLOT_SERIES: [[u8; 3]; 6] =
    [[86, 180, 233], [230, 159, 0], [0, 200, 140], [240, 228, 66], [213, 94, 200], [255, 110, 90]];
/// The replay cursor on the plots.
pub const PLOT_CURSOR: [u8; 3] = [255, 255, 255];
/// Information events in the replay timeline.
pub const PLOT_EVENT_INFO: [u8; 3] = [140, 200, 255];
/// Frames of the plots in an exported SVG (white background).
pub const PLOT_SVG_FRAME: [u8; 3] = [120, 120, 120];
/// Text in an exported SVG.
pub const PLOT_SVG_TEXT: [u8; 3] = [40, 40, 40];

// ---------------------------------------------------------------------------------------------
// 3D view: background, grid, robot, ghost, trail, frames, overlays
// ---------------------------------------------------------------------------------------------

/// sRGB channel (0…1) → linear light, the exact piecewise sRGB curve.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// sRGB bytes → sRGB floats 0…1 (still sRGB-encoded).
pub fn srgb_unit(c: [u8; 3]) -> [f32; 3] {
    c.map(|v| f32::from(v) / 255.0)
}

/// sRGB bytes → linear RGB floats, for the GPU.
pub fn linear_rgb(c: [u8; 3]) -> [f32; 3] {
    srgb_unit(c).map(srgb_to_linear)
}

/// sRGB bytes + opacity byte → sRGB floats 0…1 (still sRGB-encoded, alpha as 0…1).
pub fn srgb_rgba_unit(c: [u8; 4]) -> [f32; 4] {
    c.map(|v| f32::from(v) / 255.0)
}

/// sRGB bytes + opacity byte → linear RGBA floats (alpha as 0…1, not encoded), for the GPU.
pub fn linear_rgba(c: [u8; 4]) -> [f32; 4] {
    let [r, g, b] = linear_rgb([c[0], c[1], c[2]]);
    [r, g, b, f32::from(c[3]) / 255.0]
}

/// Background of the 3D view (also the clear colour of offscreen renders).
pub const VIEW_BACKGROUND: [u8; 3] = [38, 42, 50];
/// Thin grid lines (every 0.1 m), with their opacity.
pub const VIEW_GRID_MINOR: [u8; 4] = [107, 115, 128, 115];
/// Bold grid lines (every 0.5 m), with their opacity.
pub const VIEW_GRID_MAJOR: [u8; 4] = [158, 166, 179, 191];
/// Grid line along the world +X axis.
pub const VIEW_GRID_AXIS_X: [u8; 4] = [242, 64, 51, 255];
/// Grid line along the world +Y axis.
pub const VIEW_GRID_AXIS_Y: [u8; 4] = [77, 230, 77, 255];
/// Robot links whose URDF gives no material colour.
pub const VIEW_ROBOT_DEFAULT: [u8; 4] = [191, 191, 191, 255];
/// Placeholder cube shown where a mesh file could not be loaded (loud on purpose).
pub const VIEW_MESH_PLACEHOLDER: [u8; 4] = [255, 0, 217, 255];
/// Ghost (target pose) tint; drawn translucent, see [`VIEW_GHOST_OPACITY`].
pub const VIEW_GHOST: [u8; 3] = [115, 204, 255];
/// How much of the ghost's own colour the ghost tint replaces (0…1).
pub const VIEW_GHOST_TINT_STRENGTH: f32 = 0.85;
/// Opacity of the ghost links (0…1).
pub const VIEW_GHOST_OPACITY: f32 = 0.33;
/// Collision-geometry overlay.
pub const VIEW_COLLISION: [u8; 3] = [255, 140, 26];
/// Opacity of the collision overlay (0…1).
pub const VIEW_COLLISION_OPACITY: f32 = 0.4;
/// TCP trail; the newest point has [`VIEW_TRAIL_OPACITY`], older ones fade out.
pub const VIEW_TRAIL: [u8; 3] = [255, 217, 51];
/// Opacity of the newest trail point (0…1).
pub const VIEW_TRAIL_OPACITY: f32 = 0.95;
/// TCP trail coloured by speed or tracking error: low, middle and top of the scale (blue → green
/// → red, interpolated in linear light).
pub const VIEW_TRAIL_SCALE: [[u8; 3]; 3] = [[60, 120, 255], [80, 220, 110], [255, 60, 50]];
/// Frame axes (TCP and link frames): X arrow.
pub const VIEW_FRAME_AXIS_X: [u8; 3] = [230, 26, 26];
/// Frame axes: Y arrow.
pub const VIEW_FRAME_AXIS_Y: [u8; 3] = [26, 204, 38];
/// Frame axes: Z arrow.
pub const VIEW_FRAME_AXIS_Z: [u8; 3] = [38, 77, 255];
/// Dot marking a link origin when link names are shown.
pub const VIEW_LINK_LABEL_DOT: [u8; 3] = [255, 220, 80];
/// Link name labels.
pub const VIEW_LINK_LABEL_TEXT: [u8; 3] = [255, 235, 150];
/// Hint text drawn over the 3D view (grid legend).
pub const VIEW_HINT_TEXT: [u8; 3] = [170, 170, 170];
/// Warning text drawn over the 3D view (mesh problems).
pub const VIEW_WARNING_TEXT: [u8; 3] = [255, 176, 0];

// ---------------------------------------------------------------------------------------------
// Measurement: the cube overlay in the 3D view, the panel's plots and the HTML report
// ---------------------------------------------------------------------------------------------

/// The test cube's edges in the 3D view and the report.
pub const MEASURE_CUBE: [u8; 3] = [150, 160, 175];
/// The cube's diagonal plane (the test poses and paths lie on it).
pub const MEASURE_PLANE: [u8; 3] = [115, 204, 255];
/// Commanded poses and paths.
pub const MEASURE_COMMANDED: [u8; 3] = [40, 40, 40];
/// Attained poses and paths of the run measured (the robot, or the simulation alone).
pub const MEASURE_ATTAINED: [u8; 3] = [214, 96, 0];
/// The simulation's attained poses and paths, overlaid on the robot's.
pub const MEASURE_SIMULATION: [u8; 3] = [0, 114, 178];
/// Report text and axes.
pub const REPORT_INK: [u8; 3] = [30, 30, 30];
/// Report plot grid lines.
pub const REPORT_GRID: [u8; 3] = [220, 220, 220];
/// Report page background.
pub const REPORT_PAPER: [u8; 3] = [255, 255, 255];
/// One line per joint in the per-joint plots (J1…J6).
pub const MEASURE_JOINTS: [[u8; 3]; 6] =
    [[230, 26, 26], [26, 160, 38], [38, 77, 255], [200, 120, 0], [150, 40, 180], [0, 150, 150]];

/// A colour as CSS / SVG hex (`#rrggbb`).
pub fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

#[cfg(test)]
mod view_colour_tests {
    use super::*;

    /// WCAG 2 relative luminance of an sRGB colour.
    fn luminance(c: [u8; 3]) -> f32 {
        let [r, g, b] = linear_rgb(c);
        0.2126 * r + 0.7152 * g + 0.0722 * b
    }

    /// Issue 32 minor: "The Tab focus highlight is nearly invisible". WCAG 2.2 asks 3:1 of a
    /// focus indicator against what is beside it; the ring has far more.
    #[test]
    fn the_focus_ring_stands_out_of_the_panels() {
        let ratio = (luminance(FOCUS_RING) + 0.05) / (luminance(PANEL_BG) + 0.05);
        assert!(ratio > 7.0, "focus ring contrast {ratio:.1}:1");
        const { assert!(FOCUS_RING_WIDTH_PT >= 2.0) };
    }

    #[test]
    fn srgb_conversion_end_points_and_mid_grey() {
        assert_eq!(linear_rgb([0, 0, 0]), [0.0; 3]);
        assert!(linear_rgb([255, 255, 255]).iter().all(|v| (v - 1.0).abs() < 1e-6));
        // sRGB 188 is about 50 % linear light
        assert!((linear_rgb([188, 188, 188])[0] - 0.5029).abs() < 1e-3);
        assert!((linear_rgba([0, 0, 0, 51])[3] - 0.2).abs() < 1e-6);
    }
}
