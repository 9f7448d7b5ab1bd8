//! The window layout: menu bar, side panels, help, the 3D view and the notices over it.

use eframe::egui;

use super::{Parol6App, WINDOW_TITLE};
use crate::panels::cartesian_target::CartesianTargetPanel;
use crate::panels::connection::ConnectionPanel;
use crate::panels::demos::DemosPanel;
use crate::panels::joints::JointsPanel;
use crate::panels::status_bar::StatusBar;
use crate::panels::tcp::TcpPanel;
use crate::panels::{Panel, PanelContext};
use crate::viewport::{SceneFrame, Viewport};

impl Parol6App {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn layout(
        ui: &mut egui::Ui,
        pctx: &mut PanelContext<'_>,
        joints: &mut JointsPanel,
        tcp: &mut TcpPanel,
        target: &mut CartesianTargetPanel,
        demos: &mut DemosPanel,
        connection: &mut ConnectionPanel,
        status: &mut StatusBar,
        viewport: Option<&mut Viewport>,
        viewport_error: Option<&str>,
        show_help: &mut bool,
    ) {
        egui::Panel::top("menu").show(ui, |ui| {
            egui::MenuBar::new().ui(ui, |ui| {
                ui.label(egui::RichText::new(WINDOW_TITLE).strong());
                ui.separator();
                ui.menu_button("View", |ui| {
                    ui.checkbox(&mut pctx.settings.show_left, "Joints panel");
                    ui.checkbox(&mut pctx.settings.show_right, "TCP / target / demos panel");
                    ui.separator();
                    if let Some(v) = viewport {
                        v.options_ui(ui);
                    }
                });
                ui.menu_button("Units", |ui| {
                    ui.radio_value(&mut pctx.settings.unit, crate::panels::AngleUnit::Deg, "Degrees");
                    ui.radio_value(&mut pctx.settings.unit, crate::panels::AngleUnit::Rad, "Radians");
                });
                if ui.button("Help").clicked() {
                    *show_help = !*show_help;
                }
                ui.separator();
                ui.weak(format!("{} · {} joints", pctx.model.name, pctx.model.dof()));
            });
        });
        egui::Panel::bottom("status").show(ui, |ui| status.ui(ui, pctx));
        if pctx.settings.show_left {
            egui::Panel::left("joints").default_size(360.0).min_size(300.0).show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    joints.ui(ui, pctx);
                    ui.separator();
                    egui::CollapsingHeader::new(connection.title())
                        .default_open(pctx.link.is_some())
                        .show(ui, |ui| connection.ui(ui, pctx));
                });
            });
        }
        if pctx.settings.show_right {
            egui::Panel::right("right").default_size(330.0).min_size(280.0).show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    tcp.ui(ui, pctx);
                    ui.separator();
                    target.ui(ui, pctx);
                    ui.separator();
                    demos.ui(ui, pctx);
                });
            });
        }
        if *show_help {
            egui::Window::new("Keyboard").open(show_help).resizable(false).show(ui.ctx(), |ui| {
                egui::Grid::new("keys").show(ui, |ui| {
                    for (k, what) in [
                        ("Esc", "STOP (also cancels a demo)"),
                        ("H, Ctrl+H", "HOME (profiled move to standby)"),
                        ("1–6, PgUp/PgDn", "select joint, jog (robot connected)"),
                        ("drag / wheel", "orbit, zoom the 3D view (right drag: pan)"),
                        ("R, arrows, +/−", "3D view: reset, orbit, zoom (mouse over it)"),
                        ("F1", "this help"),
                        ("Ctrl+Q", "quit"),
                    ] {
                        ui.monospace(k);
                        ui.label(what);
                        ui.end_row();
                    }
                });
            });
        }
        let _ = viewport_error;
    }

    pub(super) fn central(&mut self, ui: &mut egui::Ui, scene: &SceneFrame) {
        egui::CentralPanel::no_frame().show(ui, |ui| {
            let rect = ui.max_rect();
            match &mut self.viewport {
                Some(v) => {
                    v.ui(ui, scene);
                }
                None => {
                    ui.painter().rect_filled(rect, 0.0, egui::Color32::from_gray(30));
                    let msg = self.viewport_error.as_deref().unwrap_or("3D view unavailable");
                    ui.put(rect, egui::Label::new(egui::RichText::new(msg).color(egui::Color32::LIGHT_GRAY)));
                }
            }
            // Notices on top of the view, newest first.
            let mut y = rect.top() + 8.0;
            for n in self.notices.iter().rev().take(4) {
                let color = if n.error { ui.visuals().error_fg_color } else { ui.visuals().selection.bg_fill };
                let galley = ui.painter().layout(
                    n.text.clone(),
                    egui::FontId::proportional(14.0),
                    egui::Color32::WHITE,
                    (rect.width() - 40.0).max(100.0),
                );
                let r = egui::Rect::from_min_size(
                    egui::pos2(rect.left() + 10.0, y),
                    galley.size() + egui::vec2(16.0, 10.0),
                );
                ui.painter().rect_filled(r, 4.0, color.gamma_multiply(0.85));
                ui.painter().galley(r.min + egui::vec2(8.0, 5.0), galley, egui::Color32::WHITE);
                y = r.bottom() + 4.0;
            }
        });
    }
}
