//! The panel under the 3D view: the replay timeline on top, and the plots and the dynamics below
//! it ([`Dock::Lower`] and [`Dock::LowerShared`]). With both the plots and the dynamics ticked,
//! they stand side by side where the panel is wide enough for two columns of
//! [`SHARED_COLUMN_MIN_WIDTH`], else they share the place as tabs (the tab chosen is
//! remembered in the settings; ticking a panel in the View menu brings its tab forward, while a
//! panel the app shows by itself, as the plots when a recording opens, comes behind the one
//! shown). Neither sits below the
//! other in the panel's scroll area, out of sight (issue 32 minor), and the timeline stays above
//! both.

use eframe::egui;

use super::layout::{LOWER_DEFAULT_HEIGHT, LOWER_MIN_HEIGHT, LOWER_PANEL_ID};
use crate::panels::fixed_box::fixed_height;
use crate::panels::registry::Dock;
use crate::panels::{Panel, PanelContext};

/// Narrowest column of a panel beside another in the lower panel, points (the dynamics' forms
/// and the plots' toolbar fit); narrower, the panels share the place as tabs.
pub const SHARED_COLUMN_MIN_WIDTH: f32 = 440.0;

/// Least height of the shared panels' box, points: under a tall timeline in a low panel they
/// keep that much, and the panel scrolls.
const SHARED_MIN_HEIGHT: f32 = 120.0;

/// The panel under the 3D view (replay timeline, plots, dynamics), resizable by its top edge.
///
/// It keeps the height it was given (default or dragged, saved in the settings): a resizable
/// panel takes its content's height, so the content fills it, and short content (no telemetry
/// yet) does not shrink it. The last panel (the plots) fills the height left, and anything
/// below it would make the panel grow each frame. A window made
/// smaller clamps it, and egui keeps that height: once the wanted height fits again (and no
/// button is held, so a drag is not fought) it goes back to it.
///
/// Returns the panel's outer rectangle.
pub(super) fn lower_dock(
    ui: &mut egui::Ui,
    pctx: &mut PanelContext<'_>,
    docked: &mut [(Dock, &mut dyn Panel)],
) -> egui::Rect {
    let max_h = (ui.available_height() - 120.0).max(LOWER_MIN_HEIGHT);
    let wanted_h = pctx.settings.lower_panel_height_pt;
    let wanted_h = if wanted_h.is_finite() { wanted_h } else { LOWER_DEFAULT_HEIGHT };
    let id = ui.scope_id().with_salt(egui::IdSalt::new(LOWER_PANEL_ID));
    let kept_h = egui::containers::panel::PanelState::load(ui.ctx(), id).map(|s| s.outer_rect.height());
    if kept_h.is_some_and(|h| h < wanted_h.min(max_h) - 0.5) && !ui.input(|i| i.pointer.any_down()) {
        ui.ctx().data_mut(|d| d.remove::<egui::containers::panel::PanelState>(id));
    }
    let shown = egui::Panel::bottom(LOWER_PANEL_ID)
        .resizable(true)
        .default_size(wanted_h.clamp(LOWER_MIN_HEIGHT, max_h))
        .size_range(LOWER_MIN_HEIGHT..=max_h)
        .show(ui, |ui| {
            // in a box of the panel's height, scrolling inside: contents taller than the panel
            // (timeline, plots and dynamics in a small window) are never reported to it, which
            // would hand the 3D view the panel's place (drawn over it)
            let h = ui.available_height();
            fixed_height(ui, LOWER_PANEL_ID, h, |ui| lower_contents(ui, pctx, docked));
        });
    // remembered for the next start; a height the window's size forced is not
    let h = shown.response.rect.height();
    if (h - wanted_h).abs() > 0.5 && (h < max_h - 0.5 || h > wanted_h) {
        pctx.settings.lower_panel_height_pt = h;
    }
    shown.response.rect
}

/// The lower panel's contents: the [`Dock::Lower`] panels stacked (the replay timeline), then
/// the [`Dock::LowerShared`] ones shown: one fills the rest, two or more go side by side or in
/// tabs ([`SHARED_COLUMN_MIN_WIDTH`]).
fn lower_contents(ui: &mut egui::Ui, pctx: &mut PanelContext<'_>, docked: &mut [(Dock, &mut dyn Panel)]) {
    let mut stacked = false;
    let top = ui.cursor().top();
    for (_, p) in docked.iter_mut().filter(|(d, _)| *d == Dock::Lower) {
        if p.shown(pctx) {
            if stacked {
                ui.separator();
            }
            stacked = true;
            p.ui(ui, pctx);
        }
    }
    // (the height without the spacing after the last panel, which the place adds again)
    let stacked_pt = stacked.then(|| ui.cursor().top() - top - ui.spacing().item_spacing.y);
    stacked |= hold_vacated_place(ui, stacked_pt);
    let mut shared: Vec<&mut dyn Panel> = Vec::new();
    for (d, p) in docked.iter_mut() {
        if *d == Dock::LowerShared && p.shown(pctx) {
            shared.push(&mut **p);
        }
    }
    if shared.is_empty() {
        return;
    }
    if stacked {
        ui.separator();
    }
    let titles: Vec<&'static str> = shared.iter().map(|p| p.title()).collect();
    if let [only] = shared.as_mut_slice() {
        // the panel shown alone is the one in front: one the app adds (the plots, when a
        // recording opens) comes behind it
        if pctx.settings.lower_tab != only.title() {
            pctx.settings.lower_tab = only.title().to_string();
        }
        only.ui(ui, pctx);
        return;
    }
    let n = shared.len() as f32;
    let gap = ui.spacing().item_spacing.x;
    if ui.available_width() >= n * SHARED_COLUMN_MIN_WIDTH + (n - 1.0) * gap {
        let height = ui.available_height().max(SHARED_MIN_HEIGHT);
        ui.columns(shared.len(), |columns| {
            for (column, p) in columns.iter_mut().zip(shared) {
                // each in a box of its own: the columns scroll apart, and neither's height is
                // reported to the panel
                fixed_height(column, ("lower-column", p.title()), height, |ui| p.ui(ui, pctx));
            }
        });
        return;
    }
    let chosen = titles.iter().position(|t| *t == pctx.settings.lower_tab).unwrap_or(0);
    ui.horizontal(|ui| {
        for (k, title) in titles.iter().enumerate() {
            let tab = ui.selectable_label(k == chosen, egui::RichText::new(*title).strong()).on_hover_text(format!(
                "show {title} here; in a lower panel at least {} pt wide, the panels stand side by side",
                (n * SHARED_COLUMN_MIN_WIDTH + (n - 1.0) * gap).round()
            ));
            if tab.clicked() {
                pctx.settings.lower_tab = (*title).to_string();
            }
        }
    });
    let height = ui.available_height().max(SHARED_MIN_HEIGHT);
    if let Some(p) = shared.get_mut(chosen) {
        let title = p.title();
        fixed_height(ui, ("lower-tab", title), height, |ui| p.ui(ui, pctx));
    }
}

/// Where the stacked panels' height of the last frame is kept, and the place they left.
fn stacked_height_id() -> egui::Id {
    egui::Id::unique("parol6-lower-stacked-height")
}
fn vacated_id() -> egui::Id {
    egui::Id::unique("parol6-lower-vacated")
}

/// Keeps the place the stacked panels (the replay timeline) left, empty but for a line, while
/// the pointer stays in the lower panel: the plots do not slide up under it, so the second click
/// of a double-click on *Close recording* does not land on the plots' toolbar (trial 21 D2: it
/// chose "torque"). `stacked_pt`: the stacked panels' height this frame, if shown. Returns true
/// while the place is held.
fn hold_vacated_place(ui: &mut egui::Ui, stacked_pt: Option<f32>) -> bool {
    let kept = |ui: &egui::Ui, id: egui::Id| ui.data(|d| d.get_temp::<Option<f32>>(id).flatten());
    let (last_frame, vacated) = (kept(ui, stacked_height_id()), kept(ui, vacated_id()));
    ui.data_mut(|d| d.insert_temp(stacked_height_id(), stacked_pt));
    let panel = ui.max_rect().intersect(ui.clip_rect());
    let pointer_in_panel = ui.ctx().pointer_latest_pos().is_some_and(|p| panel.contains(p));
    let held = if stacked_pt.is_some() { None } else { vacated.or(last_frame).filter(|_| pointer_in_panel) };
    ui.data_mut(|d| d.insert_temp(vacated_id(), held));
    let Some(height) = held else { return false };
    let size = egui::vec2(ui.available_width(), height);
    ui.allocate_ui_with_layout(size, egui::Layout::top_down(egui::Align::Min), |ui| {
        ui.set_min_size(size);
        ui.weak("Recording closed (the plots move up once the pointer leaves this panel)");
    });
    true
}
