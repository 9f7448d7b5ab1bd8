//! The window layout: menu bar, the docked panels (from the registry,
//! [`crate::panels::registry`]), help, the 3D view and the notices over it.
//!
//! The side panels have fixed widths and HOME / STOP sit at the top of the left one, so
//! nothing under the pointer moves when values, warnings or focus change, and the window
//! works from 1024×640 up.

use eframe::egui;

use egui::containers::menu::{MenuButton, MenuConfig};
use std::path::Path;

use super::panel_groups::{GroupRects, PanelGroup, PartialLayout, stand_in};
use super::{Parol6App, WINDOW_TITLE};
use crate::palette;
use crate::panels::registry::{Dock, Panels};
use crate::panels::{AngleUnit, AppCommand, Panel, PanelContext, angle_text, help};
use crate::viewport::{SceneFrame, Viewport};

/// Width of the left (joints) column, points. Fixed: it never follows its contents.
pub const LEFT_PANEL_WIDTH: f32 = 350.0;
/// Width of the right (TCP / Cartesian jog / target) column, points.
pub const RIGHT_PANEL_WIDTH: f32 = 320.0;
/// Where the point table and the file dialogs first open: the top left of the 3D view, below
/// the menu bar, so that none opens over the menu bar or the joints panel's HOME / STOP /
/// E-STOP.
pub const FLOATING_WINDOW_POS: egui::Pos2 = egui::pos2(LEFT_PANEL_WIDTH + 16.0, 40.0);
pub use crate::panels::LOWER_DEFAULT_HEIGHT;
/// Smallest height of that area, points.
pub const LOWER_MIN_HEIGHT: f32 = 120.0;
/// egui id salt of that area.
pub(super) const LOWER_PANEL_ID: &str = "lower";

/// File menu: *Share live* (Foxglove WebSocket) with its address, *Share over ROS 2* with its
/// router and domain, and the remote-control switch.
pub(super) fn live_menu_ui(ui: &mut egui::Ui, pctx: &mut PanelContext<'_>) {
    let mut on = pctx.live.sharing.is_some();
    if ui.checkbox(&mut on, "Share live (Foxglove WebSocket)").changed() {
        pctx.send(AppCommand::ShareLive(on));
    }
    ui.horizontal(|ui| {
        let label = ui.label("Address");
        let edit = egui::TextEdit::singleline(&mut pctx.settings.share_live_address).desired_width(180.0);
        ui.add_enabled(!on, edit)
            .labelled_by(label.id)
            .on_hover_text("IP:PORT; only this PC unless another address is given (0.0.0.0:8765: every interface)");
    });
    // the status rows are always there (greyed while off): toggling inserts no line, so the
    // checkboxes below stay under the pointer
    match &pctx.live.sharing {
        Some(addr) => status_row(ui, egui::RichText::new(format!("sharing at {addr}"))),
        None => status_row(ui, egui::RichText::new("not sharing").weak()),
    }
    ui.separator();
    let mut ros2 = pctx.live.ros2.is_some() || pctx.live.ros2_starting;
    let hover = "a ROS 2 node `parol6` over Zenoh (rmw_zenoh): /joint_states, /tf, /robot_description, and \
                 trajectories on /parol6/joint_trajectory (refused unless remote control is on)";
    if ui.checkbox(&mut ros2, "Share over ROS 2 (Zenoh)").on_hover_text(hover).changed() {
        pctx.send(AppCommand::ShareRos2(ros2));
    }
    ui.horizontal(|ui| {
        let label = ui.label("Router");
        let edit = egui::TextEdit::singleline(&mut pctx.settings.ros2_router).desired_width(180.0);
        ui.add_enabled(!ros2, edit).labelled_by(label.id).on_hover_text(
            "tcp/ADDRESS:PORT of the Zenoh router (`ros2 run rmw_zenoh_cpp rmw_zenohd`: tcp/127.0.0.1:7447)",
        );
        let label = ui.label("Domain");
        let domain = egui::DragValue::new(&mut pctx.settings.ros2_domain).range(0..=232);
        ui.add_enabled(!ros2, domain).labelled_by(label.id).on_hover_text("ROS_DOMAIN_ID of the other nodes, 0–232");
    });
    if pctx.live.ros2_starting {
        status_row(ui, egui::RichText::new("ROS 2 node starting…"));
    } else if let Some(addr) = &pctx.live.ros2 {
        status_row(ui, egui::RichText::new(format!("ROS 2 node parol6: {addr}")));
    } else {
        status_row(ui, egui::RichText::new("ROS 2 node off").weak());
    }
    ui.separator();
    let mut remote = pctx.live.remote_control;
    let hover = "carry out motion commands that come over the network (ROS 2 trajectories), after the same \
                 pre-flight as a program; a banner shows while it is on";
    if ui.checkbox(&mut remote, "Allow remote control").on_hover_text(hover).changed() {
        pctx.send(AppCommand::RemoteControl(remote));
    }
}

/// One status line of the File menu: a single row, left-aligned (never justified), cut with
/// "…" when longer than the menu (egui shows the whole text on hover).
pub(super) fn status_row(ui: &mut egui::Ui, text: egui::RichText) {
    ui.add(egui::Label::new(text).truncate());
}

/// What the menu bar and the help window act on.
pub(super) struct MenuTargets<'a> {
    /// The 3D view, for its options in the View menu.
    pub viewport: Option<&'a mut Viewport>,
    /// Where the settings are saved (the help window says so).
    pub settings_path: Option<&'a Path>,
    /// The help window is open.
    pub show_help: &'a mut bool,
    /// The File menu's fields.
    pub files: &'a mut super::file_menu::FileMenu,
}

impl Parol6App {
    /// Draws the menu bar, the docked panels and the help window; with `partial`, only its
    /// groups, the others held by stand-ins (see [`super::panel_groups`]). Returns the
    /// rectangles of the groups laid out.
    pub(super) fn layout(
        ui: &mut egui::Ui,
        pctx: &mut PanelContext<'_>,
        panels: &mut Panels,
        menu: MenuTargets<'_>,
        partial: Option<&PartialLayout>,
    ) -> GroupRects {
        let MenuTargets { viewport, settings_path, show_help, files } = menu;
        let mut rects = GroupRects::default();
        let lays_out = |g| PartialLayout::lays_out(partial, g);
        let stand_in_rect = |g| PartialLayout::stand_in_rect(partial, g);
        if let Some(r) = stand_in_rect(PanelGroup::Menu) {
            stand_in(ui, egui::Panel::top("menu"), r.height());
        }
        let menu = lays_out(PanelGroup::Menu).then(|| {
            egui::Panel::top("menu").show(ui, |ui| {
                egui::MenuBar::new().ui(ui, |ui| {
                    ui.label(egui::RichText::new(WINDOW_TITLE).strong());
                    ui.separator();
                    // Menus of toggles stay open while the operator clicks them.
                    let stay_open = MenuConfig::new().close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside);
                    MenuButton::new("File").config(stay_open.clone()).ui(ui, |ui| files.ui(ui, pctx));
                    // the program editor's actions; each closes the menu (none moves the arm)
                    MenuButton::new("Edit").ui(ui, |ui| panels.program.edit_menu(ui, pctx));
                    MenuButton::new("View").config(stay_open.clone()).ui(ui, |ui| {
                        ui.checkbox(&mut pctx.settings.show_left, "Joints panel");
                        ui.checkbox(&mut pctx.settings.show_right, "TCP / jog / target panel");
                        // a panel ticked comes forward where the lower panel shows them as tabs
                        let lower = [
                            (&mut pctx.settings.show_plots, panels.plots.title()),
                            (&mut pctx.settings.show_dynamics, panels.dynamics.title()),
                        ];
                        let mut forward = None;
                        for (shown, title) in lower {
                            if ui.checkbox(shown, title).changed() && *shown {
                                forward = Some(title);
                            }
                        }
                        if let Some(title) = forward {
                            pctx.settings.lower_tab = title.to_string();
                        }
                        ui.separator();
                        if let Some(v) = viewport {
                            v.options_ui(ui);
                        }
                    });
                    MenuButton::new("Units").config(stay_open).ui(ui, |ui| {
                        ui.radio_value(&mut pctx.settings.unit, AngleUnit::Deg, "Degrees");
                        ui.radio_value(&mut pctx.settings.unit, AngleUnit::Rad, "Radians");
                        ui.separator();
                        ui.label("TCP orientation");
                        for c in crate::panels::AngleConvention::ALL {
                            ui.radio_value(&mut pctx.settings.angle_convention, c, c.describe());
                        }
                        ui.separator();
                        ui.label("G-code A B C")
                            .on_hover_text("Files with a \"; parol6: abc=…\" header line are read as it says");
                        for c in crate::panels::AbcConvention::ALL {
                            ui.radio_value(&mut pctx.settings.gcode_abc, c, c.describe());
                        }
                        ui.separator();
                        ui.label("Tracking").on_hover_text(
                            "Which targets the board is streamed, in the simulation at once and on the robot from \
                             the next connection: official (the plan now, the arm trails ≈ 25 ms), lead (the plan \
                             25 ms ahead), feedforward (as lead, with feed-forward speeds)",
                        );
                        for m in parol6_core::motion::tracking::TrackingMode::ALL {
                            ui.radio_value(&mut pctx.settings.tracking, m, m.name());
                        }
                    });
                    if ui.button("Help (F1)").clicked() {
                        *show_help = !*show_help;
                    }
                    ui.separator();
                    ui.weak(format!("{} · {} joints", pctx.model.name, pctx.model.dof()));
                    if !pctx.settings.show_left {
                        // the joints panel holds STOP and E-STOP: hidden, they come here
                        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                            crate::panels::joints::stop_buttons(ui, pctx, 0.0);
                        });
                    }
                });
            })
        });
        if let Some(r) = menu {
            rects.set(PanelGroup::Menu, r.response.rect);
        }
        let mut docked = panels.docked();
        for (_, panel) in docked.iter_mut().filter(|(dock, _)| *dock == Dock::Bottom) {
            if let Some(r) = stand_in_rect(PanelGroup::Status) {
                stand_in(ui, egui::Panel::bottom(panel.title()), r.height());
            } else if lays_out(PanelGroup::Status) {
                let r = egui::Panel::bottom(panel.title()).show(ui, |ui| panel.ui(ui, pctx));
                rects.set(PanelGroup::Status, r.response.rect);
            }
        }
        let columns = [
            (Dock::Left, PanelGroup::Left, "left", LEFT_PANEL_WIDTH, pctx.settings.show_left),
            (Dock::Right, PanelGroup::Right, "right", RIGHT_PANEL_WIDTH, pctx.settings.show_right),
        ];
        for (dock, group, id, width, shown) in columns {
            let panel = match dock {
                Dock::Left => egui::Panel::left(id),
                _ => egui::Panel::right(id),
            };
            if let Some(r) = stand_in_rect(group) {
                stand_in(ui, panel, r.width());
                continue;
            }
            if !shown || !lays_out(group) {
                continue;
            }
            let r = panel.exact_size(width).resizable(false).show(ui, |ui| {
                // nothing in a column may be wider than it (the ISO figures table scrolls
                // sideways): a panel gives the width taken beyond it to the 3D view and the
                // plots, which then paint over the column's left side
                // first what stays on screen whatever the scroll (STOP and E-STOP)
                for (_, p) in docked.iter_mut().filter(|(d, _)| *d == dock) {
                    p.pinned_ui(ui, pctx);
                }
                egui::ScrollArea::vertical().id_salt(id).auto_shrink([false, false]).show(ui, |ui| {
                    let mut first = true;
                    for (_, p) in docked.iter_mut().filter(|(d, _)| *d == dock) {
                        if !first {
                            ui.separator();
                        }
                        first = false;
                        p.ui(ui, pctx);
                    }
                });
            });
            rects.set(group, r.response.rect);
        }
        let lower_shown = docked.iter().any(|(d, p)| matches!(d, Dock::Lower | Dock::LowerShared) && p.shown(pctx));
        if let Some(r) = stand_in_rect(PanelGroup::Lower) {
            stand_in(ui, egui::Panel::bottom(LOWER_PANEL_ID), r.height());
        } else if lower_shown && lays_out(PanelGroup::Lower) {
            rects.set(PanelGroup::Lower, super::lower_dock::lower_dock(ui, pctx, &mut docked));
        }
        files.dialog_ui(ui.ctx(), pctx);
        if *show_help {
            // in the 3D view (what the panels left), below the menu bar: never over HOME / STOP /
            // E-STOP, a jog button or the menus
            let view = ui.available_rect_before_wrap();
            let (at, width) = help_place(view);
            // room below it in the view for the notices (beside it they would cover a side
            // panel's read-outs in a narrow window)
            let max_h = (view.bottom() - at.y - NOTICES_MIN_HEIGHT - 16.0).max(200.0);
            egui::Window::new(super::escape::HELP_WINDOW)
                // its area's id by its name (egui's own hashes the title's text as an `Option`),
                // so the notices and Esc find it
                .id(egui::Id::unique(super::escape::HELP_WINDOW))
                .open(show_help)
                // drawn at once: a fade redraws the whole window for several frames, each as costly as
                // the first on a software rasterizer
                .fade_in(false)
                .fade_out(false)
                .default_pos(at)
                .default_size([width, max_h.min(720.0)])
                .max_height(max_h)
                .vscroll(true)
                .show(ui.ctx(), |ui| help::help_ui(ui, settings_path));
        }
        rects
    }

    /// Lays out the 3D view in the space the panels left (`partial`: the last full frame's, when
    /// this frame reuses panels; see [`super::frame_reuse`]), in a `Ui` whose id is the same
    /// either way, and tells frame reuse what this frame was (`groups`: where the layout put
    /// the panel groups).
    pub(super) fn central_and_reuse(
        &mut self,
        ui: &mut egui::Ui,
        partial: Option<&PartialLayout>,
        groups: GroupRects,
        scene: &SceneFrame,
    ) {
        let rect = partial.map_or_else(|| ui.available_rect_before_wrap(), |p| p.central);
        let builder =
            egui::UiBuilder::new().scope_id(egui::Id::unique(super::frame_reuse::CENTRAL_SCOPE)).max_rect(rect);
        ui.scope_builder(builder, |ui| self.central(ui, scene));
        if let Some(reuse) = &self.frame_reuse {
            match partial {
                Some(p) => {
                    // the panels' space is still the root's, as in the full frame
                    ui.expand_to_include_rect(ui.max_rect());
                    reuse.check_layout(p, &groups);
                    reuse.register_kept_widgets(ui.ctx(), p);
                }
                None => reuse.full_frame(rect, groups),
            }
        }
    }

    fn central(&mut self, ui: &mut egui::Ui, scene: &SceneFrame) {
        egui::CentralPanel::no_frame().show(ui, |ui| {
            let rect = ui.max_rect();
            self.view_rect = Some(rect);
            match &mut self.viewport {
                Some(v) => {
                    v.ui(ui, scene);
                }
                None => {
                    ui.painter().rect_filled(rect, 0.0, palette::rgb(palette::VIEW_PLACEHOLDER_BG));
                    let msg = self.viewport_error.as_deref().unwrap_or("3D view unavailable");
                    let text = egui::RichText::new(msg).color(palette::rgb(palette::VIEW_PLACEHOLDER_TEXT));
                    ui.put(rect, egui::Label::new(text));
                }
            }
            // beside (or below) the help window, never over its title
            let help = self
                .show_help
                .then(|| ui.ctx().memory(|m| m.area_rect(egui::Id::unique(super::escape::HELP_WINDOW))))
                .flatten();
            let place = notices_place(rect, ui.ctx().content_rect(), help);
            // and clear of the open windows (the point table, a file dialog) and menus
            let place = clear_of_windows(ui.ctx(), place, rect, self.notices.len());
            notices_ui(ui.ctx(), place, &self.notices, self.settings.unit);
        });
    }
}

/// Widest the help window opens, pt.
const HELP_WIDTH: f32 = 600.0;
/// Narrowest the help window opens, pt (in a 3D view narrower than this it covers part of a
/// side panel's lower half rather than becoming unreadable).
const HELP_MIN_WIDTH: f32 = 300.0;

/// Where the help window first opens and its width: the top left of the 3D view (`view`),
/// 16 pt in, as wide as the view leaves (at most [`HELP_WIDTH`]).
fn help_place(view: egui::Rect) -> (egui::Pos2, f32) {
    let width = (view.width() - 32.0).clamp(HELP_MIN_WIDTH, HELP_WIDTH);
    (view.left_top() + egui::vec2(16.0, 16.0), width)
}

/// The notices' area (tests find their rectangle by it).
const NOTICES_AREA: &str = "parol6-notices";

/// Narrowest column of notices beside the help window; narrower, they go below it.
const NOTICES_MIN_WIDTH: f32 = 240.0;

/// Least room below the help window for the notices there, pt.
const NOTICES_MIN_HEIGHT: f32 = 120.0;

/// Where the notices go: the top left of the 3D view (`view`), or, while the help window
/// (`help`) covers that, the wider free side beside it in the view, or below it in the view,
/// and only then beside or below it in the window (`screen`), over the panels' read-outs.
/// Returns the top left corner and the width of the column.
pub(super) fn notices_place(view: egui::Rect, screen: egui::Rect, help: Option<egui::Rect>) -> (egui::Pos2, f32) {
    let top = view.top() + 8.0;
    let home = (egui::pos2(view.left() + 10.0, top), (view.width() - 40.0).max(100.0));
    let Some(help) = help.filter(|h| h.intersects(view)) else { return home };
    // the free side in `within`, the wider one first: (left x, width)
    let sides = |within: egui::Rect| {
        let right = (help.right() + 10.0, within.right() - help.right() - 20.0);
        let left = (within.left() + 10.0, help.left() - within.left() - 20.0);
        if right.1 >= left.1 { [right, left] } else { [left, right] }
    };
    let beside = |within| sides(within).into_iter().find(|s| s.1 >= NOTICES_MIN_WIDTH);
    if let Some((x, width)) = beside(view) {
        return (egui::pos2(x, top), width);
    }
    if view.bottom() - help.bottom() >= NOTICES_MIN_HEIGHT {
        return (egui::pos2(home.0.x, help.bottom() + 8.0), home.1);
    }
    if let Some((x, width)) = beside(screen) {
        return (egui::pos2(x, top), width);
    }
    if screen.bottom() - help.bottom() >= NOTICES_MIN_HEIGHT {
        return (egui::pos2(home.0.x, help.bottom() + 8.0), home.1);
    }
    // a help window as large as the window: the wider side, however narrow
    let (x, width) = sides(screen)[0];
    (egui::pos2(x, top), width.max(60.0))
}

/// Height of a window's title bar that the notices keep clear of when they cannot clear the
/// whole window, pt.
const TITLE_BAR_HEIGHT: f32 = 30.0;

/// Height of one notice of one line, pt (the column's height before it was first laid out).
const NOTICE_HEIGHT: f32 = 31.0;

/// What the notices keep clear of: the open windows (the point table, the file dialogs, the help,
/// a question) and the open menus and pop-ups, as (whole rectangle, the part that must stay
/// clear when nothing else is: a window's title bar, a menu's whole rectangle).
fn open_windows_and_menus(ctx: &egui::Context) -> Vec<(egui::Rect, egui::Rect)> {
    ctx.memory(|m| {
        m.areas()
            .visible_layer_ids()
            .into_iter()
            .filter_map(|layer| {
                let r = m.area_rect(layer.id)?;
                match layer.order {
                    egui::Order::Middle => {
                        let title = egui::Rect::from_min_max(r.min, egui::pos2(r.right(), r.top() + TITLE_BAR_HEIGHT));
                        Some((r, title))
                    }
                    egui::Order::Foreground => Some((r, r)),
                    _ => None,
                }
            })
            .filter(|(r, _)| r.is_positive())
            .collect()
    })
}

/// `place` (from [`notices_place`]) moved clear of the open windows and menus
/// ([`open_windows_and_menus`]): trial 9 and 10 saw notices over the title of the save dialog and
/// the point table, and over the File menu's "Browse recordings…". The column (its size of the
/// last frame, or `count` one-line notices) slides down below what it meets, within the 3D view
/// (`view`) and then within the window (over the plots under a short 3D view), or else goes right
/// of it in the view; when none of these clears the whole windows, the same with their title
/// bars only (a notice may cover a window's content, never its title or a menu).
fn clear_of_windows(
    ctx: &egui::Context,
    place: (egui::Pos2, f32),
    view: egui::Rect,
    count: usize,
) -> (egui::Pos2, f32) {
    if count == 0 {
        return place;
    }
    let obstacles = open_windows_and_menus(ctx);
    if obstacles.is_empty() {
        return place;
    }
    let screen = ctx.content_rect();
    let last = ctx.memory(|m| m.area_rect(egui::Id::unique(NOTICES_AREA)));
    let shown = count.min(4) as f32;
    let size = |width: f32| {
        let w = last.map_or(width.min(400.0), |r| r.width()).min(width);
        let h = last.map_or(0.0, |r| r.height()).max(NOTICE_HEIGHT * shown);
        egui::vec2(w, h)
    };
    let (start, width) = place;
    for whole in [true, false] {
        let rects: Vec<egui::Rect> = obstacles.iter().map(|(w, t)| if whole { *w } else { *t }).collect();
        let clear = |column: egui::Rect| !rects.iter().any(|r| r.intersects(column));
        // down, past each window or menu in the way: within the view, then within the window
        for bounds in [view, screen] {
            let mut at = start;
            for _ in 0..=rects.len() {
                let column = egui::Rect::from_min_size(at, size(width));
                if !bounds.contains_rect(column) {
                    break;
                }
                match rects.iter().filter(|r| r.intersects(column)).map(|r| r.bottom()).reduce(f32::max) {
                    None => return (at, width),
                    Some(bottom) => at.y = bottom + 8.0,
                }
            }
        }
        // right of what lies in the column's band at the top
        let band = egui::Rect::from_min_size(start, egui::vec2(view.right() - start.x, size(width).y));
        if let Some(right) = rects.iter().filter(|r| r.intersects(band)).map(|r| r.right()).reduce(f32::max) {
            let at = egui::pos2(right + 10.0, start.y);
            let w = view.right() - at.x - 10.0;
            if w >= NOTICES_MIN_WIDTH && clear(egui::Rect::from_min_size(at, size(w))) {
                return (at, w);
            }
        }
    }
    place
}

/// The notices (newest first) at `place` (from [`notices_place`]), on a layer in front of every
/// window and menu: an error raised from the point table or the File menu is never hidden
/// behind them.
fn notices_ui(ctx: &egui::Context, place: (egui::Pos2, f32), notices: &[super::Notice], unit: AngleUnit) {
    if notices.is_empty() {
        return;
    }
    let (at, width) = place;
    // in front of everything but never in the way: a click on a notice reaches what it covers
    let area = egui::Area::new(egui::Id::unique(NOTICES_AREA)).order(egui::Order::Tooltip).interactable(false);
    area.fixed_pos(at).show(ctx, |ui| {
        ui.set_max_width(width);
        ui.spacing_mut().item_spacing.y = 4.0;
        for n in notices.iter().rev().take(4) {
            let color = palette::rgba(if n.error { palette::NOTICE_ERROR_BG } else { palette::NOTICE_INFO_BG });
            egui::Frame::new().fill(color).corner_radius(4.0).inner_margin(egui::vec2(8.0, 5.0)).show(ui, |ui| {
                let text = egui::RichText::new(angle_text::in_unit(&n.text, unit))
                    .size(14.0)
                    .color(palette::rgb(palette::NOTICE_TEXT));
                ui.add(egui::Label::new(text).wrap());
            });
        }
    });
}
