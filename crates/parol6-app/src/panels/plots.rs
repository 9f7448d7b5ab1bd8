//! Lower panel: plots (egui_plot) of the live telemetry (the last ten minutes of the active
//! backend) or of the open recording. Position, velocity, acceleration and drive (torque or
//! step rate) per joint, TCP x / y / z, roll / pitch / yaw, and commanded − measured per joint
//! with its RMS and maximum over the visible window (the hardware-in-the-loop view).
//!
//! Selectable quantities and joints, one time axis for all plots, follow / pause, zoom and
//! pan when paused, units from the Units menu. Every line is decimated by the core's
//! [`SeriesStore`] to one point per pixel (a min / max pair from its pyramid every two pixels), so ten
//! minutes at 250 Hz cost the same per frame as ten seconds, and drawn as unfeathered quads
//! ([`ThinLine`]): cheap on software rasterizers. One quantity at a time by default (a click on
//! a quantity shows it alone, Ctrl+click adds it), so one plot shares the panel's height. CSV
//! and SVG export of what is shown: [`super::plot_export`].

use std::sync::Arc;

use eframe::egui;
use egui_plot::{Plot, VLine};
use parol6_core::telemetry::{DriveKind, LiveView, Quantity, ReplayData, SeriesId, SeriesStore};

use super::plot_axis;
use super::plot_cache::DecimationCache;
use super::plot_export::{self, DrawnGroup, DrawnLine};
use super::plot_line::ThinLine;
use super::plot_stretches::{self, DriveStretches};
use super::{AngleUnit, AppCommand, Panel, PanelContext};
use crate::palette;

/// Time windows offered, s.
pub const WINDOWS_S: [(f64, &str); 6] =
    [(10.0, "10 s"), (30.0, "30 s"), (60.0, "1 min"), (300.0, "5 min"), (600.0, "10 min"), (3600.0, "1 h")];

/// Live history kept for the plots, s (the recorder's live view holds the same).
pub const LIVE_SPAN_S: f64 = 600.0;

/// Newest live history kept at the rate the samples came, s; older samples are kept as 4 ms
/// min/max pairs (the recorder's live view does the same).
pub const LIVE_FULL_RATE_S: f64 = 60.0;

/// Pixels per decimation column: each column gives a min / max pair, so a line has one point
/// per pixel. Finer adds no visible detail to a one-pixel line and, on a software rasterizer,
/// costs a third more of the plots' render time (measured with `bench render --plots`).
const PX_PER_MIN_MAX_PAIR: usize = 2;

/// Smallest plot height, points.
const MIN_PLOT_HEIGHT: f32 = 70.0;

/// Display scale and unit of a quantity (angles converted by [`AngleUnit`]).
pub fn unit_of(q: Quantity, angle: AngleUnit, drive: DriveKind) -> (f64, &'static str) {
    let deg = angle == AngleUnit::Deg;
    let d = angle.from_rad(1.0);
    match q {
        Quantity::Position | Quantity::TrackingError | Quantity::TcpOrientation => (d, if deg { "°" } else { "rad" }),
        Quantity::Velocity => (d, if deg { "°/s" } else { "rad/s" }),
        Quantity::Acceleration => (d, if deg { "°/s²" } else { "rad/s²" }),
        Quantity::Drive => match drive {
            DriveKind::TorqueNm => (1.0, "N·m"),
            DriveKind::StepsPerS => (1.0, "steps/s"),
        },
        Quantity::TcpPosition => (1000.0, "mm"),
    }
}

/// Short name of a quantity on its toggle.
pub fn toggle_label(q: Quantity) -> &'static str {
    match q {
        Quantity::Position => "position",
        Quantity::Velocity => "velocity",
        Quantity::Acceleration => "acceleration",
        Quantity::Drive => "torque",
        Quantity::TrackingError => "cmd - meas",
        Quantity::TcpPosition => "TCP xyz",
        Quantity::TcpOrientation => "TCP rpy",
    }
}

/// Name of a series in legends and files.
pub fn series_name(id: SeriesId) -> String {
    match id.quantity {
        Quantity::TcpPosition => ["x", "y", "z"].get(id.index).copied().unwrap_or("?").to_string(),
        Quantity::TcpOrientation => ["roll", "pitch", "yaw"].get(id.index).copied().unwrap_or("?").to_string(),
        _ => format!("J{}", id.index + 1),
    }
}

/// The name and colour of the backend the live rows come from after a switch mark.
fn source_mark(robot: bool) -> (&'static str, egui::Color32) {
    if robot {
        ("robot", palette::rgb(palette::SOURCE_ROBOT))
    } else {
        ("simulation", palette::rgb(palette::SOURCE_SIM))
    }
}

fn series_color(index: usize) -> egui::Color32 {
    palette::rgb(palette::PLOT_SERIES[index % palette::PLOT_SERIES.len()])
}

/// The plots panel.
pub struct PlotsPanel {
    live: SeriesStore,
    replay: Option<(Arc<ReplayData>, f64)>,
    /// Quantities shown, in [`Quantity::ALL`] order.
    pub quantities: Vec<Quantity>,
    /// Joints shown (TCP axes are always all three).
    pub joints: Vec<bool>,
    /// Visible time span while following, s.
    pub window_s: f64,
    /// Follow the newest sample (live) or the cursor (replay); off while zoomed or panned.
    pub follow: bool,
    /// Typed path of the export file (CSV or SVG).
    pub export_path: String,
    /// The visible time window of the last frame, s.
    visible_s: Option<(f64, f64)>,
    /// Decimated lines kept while data and window stay the same.
    lines: DecimationCache,
    svg_pending: Option<std::path::PathBuf>,
    /// An export onto an existing file asks first (the same button again replaces it).
    export_ask: super::replace_ask::ReplaceAsk,
    /// Whose live view the live rows come from now (`Some(true)`: the robot's).
    live_on_robot: Option<bool>,
    /// Added to the active backend's times: its clock started elsewhere than the first one's.
    live_shift_s: f64,
    /// Where the live rows switched backend (plot time, s) and to which (`true`: the robot).
    switches: Vec<(f64, bool)>,
    /// Width of the joint toggles' group last frame, points.
    joint_toggles_width: Option<f32>,
    /// What the live drive series held, stretch by stretch (torque or step rates).
    drive_stretches: DriveStretches,
    /// Per plot of the last frame, the first and last time of the points drawn, s.
    drawn_s: Vec<(Quantity, Option<(f64, f64)>)>,
}

/// The joint toggles' width before it is measured, points (six toggles take about 220).
const JOINT_TOGGLES_GUESS_PT: f32 = 240.0;

impl PlotsPanel {
    /// The panel for `joints` joints: the position of every joint.
    pub fn new(joints: usize) -> Self {
        Self {
            live: SeriesStore::live(joints, LIVE_SPAN_S, LIVE_FULL_RATE_S),
            replay: None,
            quantities: vec![Quantity::Position],
            joints: vec![true; joints],
            window_s: 30.0,
            follow: true,
            export_path: String::new(),
            visible_s: None,
            lines: DecimationCache::default(),
            svg_pending: None,
            export_ask: Default::default(),
            live_on_robot: None,
            live_shift_s: 0.0,
            switches: Vec::new(),
            joint_toggles_width: None,
            drive_stretches: DriveStretches::default(),
            drawn_s: Vec::new(),
        }
    }

    /// Shows quantity `q` alone.
    pub fn show_only(&mut self, q: Quantity) {
        self.quantities = vec![q];
    }

    /// Shows or hides quantity `q`, keeping [`Quantity::ALL`] order.
    fn toggle(&mut self, q: Quantity) {
        let on = !self.quantities.contains(&q);
        self.quantities =
            Quantity::ALL.into_iter().filter(|&o| if o == q { on } else { self.quantities.contains(&o) }).collect();
    }

    /// Takes the new samples of the active backend's live view (`on_robot`: the robot's, else
    /// the simulation's). A switch of backend keeps the history: the new backend's rows
    /// continue it from the switch on (its clock shifted onto the plots' own), and the switch
    /// is marked on every plot.
    pub fn feed_live(&mut self, view: &LiveView, on_robot: bool) -> usize {
        let before_s = self.live.time_range_s().map(|(_, last)| last);
        if self.live_on_robot != Some(on_robot) {
            // a backend with no rows yet (a connection's first moments) waits for its first
            let Some(latest) = view.latest_time_s() else { return 0 };
            match (self.live_on_robot, self.live.time_range_s()) {
                (Some(_), Some((_, last))) => {
                    self.live_shift_s = last - latest;
                    self.switches.push((last, on_robot));
                }
                _ => self.live_shift_s = 0.0,
            }
            self.live_on_robot = Some(on_robot);
        }
        let added = self.live.ingest_live_shifted(view, self.live_shift_s);
        if added > 0 {
            self.drive_stretches.note(before_s, view.drive, on_robot);
        }
        added
    }

    /// Per plot of the last frame, the first and last time of the points drawn, s (`None`:
    /// none drawn).
    pub fn drawn_s(&self, q: Quantity) -> Option<(f64, f64)> {
        self.drawn_s.iter().find(|(o, _)| *o == q).and_then(|(_, r)| *r)
    }

    /// Where the live rows switched backend (plot time, s) and to which (`true`: the robot),
    /// those still in the kept history.
    pub fn switches(&self) -> Vec<(f64, bool)> {
        let first = self.live.time_range_s().map_or(f64::INFINITY, |(first, _)| first);
        self.switches.iter().copied().filter(|(t, _)| *t >= first).collect()
    }

    /// Shows the open recording (with its cursor, s) instead of the live data, or live again. A
    /// newly opened recording is followed from its cursor.
    pub fn set_replay(&mut self, replay: Option<(Arc<ReplayData>, f64)>) {
        if let Some((new, _)) = &replay
            && self.replay.as_ref().is_none_or(|(old, _)| !Arc::ptr_eq(old, new))
        {
            self.follow = true;
        }
        self.replay = replay;
    }

    /// The series shown: the recording's while one is open, else the live ones.
    pub fn store(&self) -> &SeriesStore {
        self.replay.as_ref().map_or(&self.live, |(d, _)| &d.store)
    }

    /// The visible time window of the last frame, s.
    pub fn visible_s(&self) -> Option<(f64, f64)> {
        self.visible_s
    }

    /// Selected series of quantity `q`.
    fn selected(&self, q: Quantity) -> Vec<SeriesId> {
        let store = self.store();
        store
            .ids()
            .iter()
            .copied()
            .filter(|id| id.quantity == q && (!q.per_joint() || self.joints.get(id.index).copied().unwrap_or(false)))
            .collect()
    }

    /// The time window to show while following.
    fn follow_window(&self) -> Option<(f64, f64)> {
        let (first, last) = self.store().time_range_s()?;
        Some(match &self.replay {
            Some((_, cursor)) => {
                let x0 = (cursor - 0.75 * self.window_s).max(first);
                (x0, x0 + self.window_s)
            }
            None => ((last - self.window_s).max(first.min(last - self.window_s)), last),
        })
    }

    /// RMS and maximum of commanded − measured of the selected joints over the visible window.
    pub fn tracking_stats(&self, angle: AngleUnit) -> Vec<(String, f64, f64, &'static str)> {
        let Some((t0, t1)) = self.visible_s else { return Vec::new() };
        let store = self.store();
        let (scale, unit) = unit_of(Quantity::TrackingError, angle, store.drive());
        self.selected(Quantity::TrackingError)
            .into_iter()
            .filter_map(|id| {
                let s = store.window_stats(store.column(id)?, t0, t1)?;
                Some((series_name(id), s.rms? * scale, s.max_abs * scale, unit))
            })
            .collect()
    }

    fn toolbar(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            let mut picked = None;
            for q in Quantity::ALL {
                let on = self.quantities.contains(&q);
                let r = ui.selectable_label(on, toggle_label(q)).on_hover_text("Ctrl+click: add to the plots shown");
                if r.clicked() {
                    picked = Some((q, ui.input(|i| i.modifiers.command || i.modifiers.shift)));
                }
            }
            match picked {
                Some((q, true)) => self.toggle(q),
                Some((q, false)) => self.show_only(q),
                None => {}
            }
            // the joint toggles wrap as one group: J1 never stays behind at the end of a row
            // (its width is last frame's, or a generous guess on the first)
            let group_width = self.joint_toggles_width.unwrap_or(JOINT_TOGGLES_GUESS_PT);
            if ui.available_size_before_wrap().x < group_width + ui.spacing().item_spacing.x * 2.0 {
                ui.end_row();
            } else {
                ui.separator();
            }
            let group = ui.horizontal(|ui| {
                for (i, on) in self.joints.iter_mut().enumerate() {
                    let text = egui::RichText::new(format!("J{}", i + 1)).color(series_color(i));
                    ui.toggle_value(on, text);
                }
            });
            self.joint_toggles_width = Some(group.response.rect.width());
            ui.separator();
            let shown = WINDOWS_S.iter().find(|(s, _)| *s == self.window_s).map_or("?", |(_, l)| *l);
            egui::ComboBox::from_id_salt("plot_window").selected_text(shown).width(64.0).show_ui(ui, |ui| {
                for (s, label) in WINDOWS_S {
                    ui.selectable_value(&mut self.window_s, s, label);
                }
            });
            let follow_label = if self.replay.is_some() { "Follow cursor" } else { "Follow live" };
            if ui.selectable_label(self.follow, follow_label).on_hover_text("off: zoom and pan freely").clicked() {
                self.follow = !self.follow;
            }
        });
    }

    fn export_row(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        // wrapped: at 1024 px the row ran under the right panel ("SVG of the plots" out of reach)
        ui.horizontal_wrapped(|ui| {
            let label = ui.label("Export to");
            ui.add(
                egui::TextEdit::singleline(&mut self.export_path)
                    .desired_width(220.0)
                    .hint_text("file name, e.g. plots.csv"),
            )
            .labelled_by(label.id);
            let path = crate::typed_path::typed_path(&self.export_path);
            let has_path = !self.export_path.trim().is_empty();
            // greyed without a file name, saying so (trial 22 m3: they did nothing and said nothing)
            const NO_PATH: &str = "type a file name into Export to first";
            let csv = ui.add_enabled(has_path, egui::Button::new("CSV of the visible window"));
            let csv = csv.on_disabled_hover_text(NO_PATH);
            if csv.clicked() && !self.export_ask.may_write(&path) {
                let again = "clicking CSV of the visible window or SVG of the plots again";
                ctx.info(self.export_ask.question(&path, again).unwrap_or_default());
            } else if csv.clicked() {
                // a replay's store has one drive quantity; the live history's stretches say which
                // rows hold which
                let replay_stretches = DriveStretches::default();
                let stretches = if self.replay.is_some() { &replay_stretches } else { &self.drive_stretches };
                match self.visible_s {
                    Some((t0, t1)) => match plot_export::write_csv(&path, self.store(), stretches, t0, t1) {
                        Ok(rows) => ctx.info(format!("wrote {rows} rows to {}", path.display())),
                        Err(e) => ctx.error(e),
                    },
                    None => ctx.error("nothing is plotted yet"),
                }
            }
            let svg = ui.add_enabled(has_path, egui::Button::new("SVG of the plots")).on_disabled_hover_text(NO_PATH);
            if svg.clicked() {
                if self.export_ask.may_write(&path) {
                    self.svg_pending = Some(path);
                } else {
                    let again = "clicking SVG of the plots or CSV of the visible window again";
                    ctx.info(self.export_ask.question(&path, again).unwrap_or_default());
                }
            }
        });
    }
}

impl Panel for PlotsPanel {
    fn title(&self) -> &'static str {
        "Plots"
    }

    fn shown(&self, ctx: &PanelContext<'_>) -> bool {
        ctx.settings.show_plots
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        self.lines.begin_frame();
        self.toolbar(ui);
        let stats = if self.quantities.contains(&Quantity::TrackingError) {
            self.tracking_stats(ctx.settings.unit)
        } else {
            Vec::new()
        };
        if !stats.is_empty() {
            ui.horizontal_wrapped(|ui| {
                // the mode the simulation streams in now (the robot's: chosen at connection)
                ui.label(format!("cmd - meas over the visible window (tracking {}):", ctx.settings.tracking.name()));
                for (name, rms, max, unit) in &stats {
                    ui.label(format!("{name} RMS {rms:.3} {unit}, max {max:.3} {unit}"));
                }
            });
        }
        self.export_row(ui, ctx);
        let shown = self.quantities.clone();
        if self.store().is_empty() {
            ui.weak("no telemetry yet: move the arm, run a program or open a recording");
            return;
        }
        if shown.is_empty() {
            ui.weak("pick a quantity to plot");
            return;
        }
        let gaps = 6.0 * shown.len() as f32;
        let height = ((ui.available_height() - gaps) / shown.len() as f32).max(MIN_PLOT_HEIGHT);
        let follow_window = if self.follow { self.follow_window() } else { None };
        let link = ui.make_persistent_id("plots_time_axis");
        let mut svg_groups: Vec<DrawnGroup> = Vec::new();
        let collect_svg = self.svg_pending.is_some();
        let mut visible = None;
        let mut interacted = false;
        let mut seek = None;
        let cursor = self.replay.as_ref().map(|(_, c)| *c);
        // a recording's times are shown from its start (the timeline's clock); live, the simulation's
        let origin_s = self.replay.as_ref().and_then(|(d, _)| d.store.time_range_s()).map_or(0.0, |(t0, _)| t0);
        let switches = if self.replay.is_some() { Vec::new() } else { self.switches() };
        let id_lists: Vec<Vec<SeriesId>> = shown.iter().map(|q| self.selected(*q)).collect();
        let mut drawn_s = Vec::new();
        egui::ScrollArea::vertical().id_salt("plots_scroll").auto_shrink([false, false]).show(ui, |ui| {
            for (k, (q, ids)) in shown.iter().zip(&id_lists).enumerate() {
                let store = self.replay.as_ref().map_or(&self.live, |(d, _)| &d.store);
                let (scale, unit) = unit_of(*q, ctx.settings.unit, store.drive());
                // the live history's stretches of the other drive quantity (the other
                // backend's) are not drawn under this axis's unit
                let hidden = if *q == Quantity::Drive && self.replay.is_none() {
                    self.drive_stretches.hidden(store.drive())
                } else {
                    Vec::new()
                };
                let lines = &mut self.lines;
                let mut plot = Plot::new(("plot", k))
                    .height(height)
                    .link_axis(link, [true, false])
                    .link_cursor(link, [true, false])
                    .custom_y_axes(vec![plot_axis::value_axis(format!("{} ({unit})", q.label()))])
                    .y_grid_spacer(plot_axis::value_marks)
                    // the read-out below names every line's value at the pointer's time
                    .label_formatter(|_| None)
                    .show_x(true)
                    // the panel's own colour behind the lines: a filled plot area is the
                    // largest thing egui shades in the window (~0.4 Mpx at 1280×800)
                    .show_background(false)
                    .allow_scroll(false);
                if k + 1 == shown.len() {
                    plot = plot.x_axis_label(if origin_s == 0.0 { "time (s)" } else { "time from the start (s)" });
                }
                if origin_s != 0.0 {
                    plot = plot_axis::time_from(plot, origin_s);
                }
                let resp = plot.show(ui, |pui| {
                    let b = pui.plot_bounds();
                    let (x0, x1) = match follow_window {
                        Some(w) => {
                            pui.set_plot_bounds_x(w.0..=w.1);
                            pui.set_auto_bounds([false, true]);
                            w
                        }
                        None => (b.min()[0], b.max()[0]),
                    };
                    let width_px = (pui.transform().frame().width() * pui.ctx().pixels_per_point()).max(1.0) as usize;
                    // one min / max pair per two pixels: one point per pixel
                    let columns = width_px.div_ceil(PX_PER_MIN_MAX_PAIR);
                    let mut group = DrawnGroup { title: format!("{} ({unit})", q.label()), lines: Vec::new() };
                    let hover_t = pui.response().hovered().then(|| pui.pointer_coordinate()).flatten().map(|p| p.x);
                    let mut hover_values = Vec::new();
                    let mut drawn: Option<(f64, f64)> = None;
                    let pad_s = (x1 - x0) / columns.max(1) as f64;
                    for id in ids {
                        let Some(col) = store.column(*id) else { continue };
                        let points = lines.line(store, col, x0, x1, columns);
                        let scaled: Vec<[f64; 2]> = points.iter().map(|p| [p[0], p[1] * scale]).collect();
                        let runs = if hidden.is_empty() {
                            vec![scaled]
                        } else {
                            plot_stretches::split_shown(&scaled, &hidden, pad_s)
                        };
                        for run in runs.iter().filter(|r| !r.is_empty()) {
                            let (a, b) = (run[0][0], run[run.len() - 1][0]);
                            drawn = Some(drawn.map_or((a, b), |(lo, hi)| (lo.min(a), hi.max(b))));
                            // a value only within the line's time span (a column's width of
                            // slack at its ends): none before its first sample or past its last
                            let at_t = hover_t.filter(|t| (a - pad_s..=b + pad_s).contains(t));
                            if let Some(v) = at_t.and_then(|t| plot_axis::value_at(run, t)) {
                                hover_values.push((series_name(*id), v));
                            }
                            let color = series_color(id.index);
                            if collect_svg {
                                group.lines.push(DrawnLine { name: series_name(*id), color, points: run.clone() });
                            }
                            pui.add(ThinLine::new(series_name(*id), run).color(color).width(1.0));
                        }
                    }
                    drawn_s.push((*q, drawn));
                    if let Some(c) = cursor {
                        pui.vline(VLine::new("cursor", c).color(palette::rgb(palette::PLOT_CURSOR)).width(1.5));
                    }
                    for &(t, robot) in switches.iter().filter(|(t, _)| (x0..=x1).contains(t)) {
                        let (name, color) = source_mark(robot);
                        pui.vline(VLine::new(name, t).color(color).width(1.5));
                    }
                    let clicked_at = pui.response().clicked().then(|| pui.pointer_coordinate()).flatten();
                    let b = pui.plot_bounds();
                    let value_step = (b.max()[1] - b.min()[1]) / f64::from(pui.transform().frame().height().max(1.0))
                        * plot_axis::LABEL_SPACING_PT;
                    // no read-out where no line has a sample (it gave the nearest sample's values)
                    let hover = hover_t
                        .filter(|_| !hover_values.is_empty())
                        .map(|t| plot_axis::hover_text(t - origin_s, &hover_values, unit, value_step));
                    ((x0, x1), group, clicked_at.map(|p| p.x), hover)
                });
                let ((x0, x1), group, clicked_at, hover) = resp.inner;
                // the switches' names over the plot (a text item would widen its auto bounds)
                let frame = *resp.transform.frame();
                for &(t, robot) in switches.iter().filter(|(t, _)| (x0..=x1).contains(t)) {
                    let (name, color) = source_mark(robot);
                    let at = egui::pos2(resp.transform.position_from_point_x(t) + 3.0, frame.top() + 1.0);
                    let font = egui::TextStyle::Small.resolve(ui.style());
                    ui.painter_at(frame).text(at, egui::Align2::LEFT_TOP, name, font, color);
                }
                if let Some(note) = plot_stretches::hidden_note(&hidden, x0, x1, store.drive()) {
                    // a label over the plot's lower left corner: it takes no room from the plots
                    let r = egui::Rect::from_min_max(egui::pos2(frame.left() + 4.0, frame.bottom() - 18.0), frame.max);
                    let mut child = ui.new_child(egui::UiBuilder::new().max_rect(r));
                    child.set_clip_rect(r.intersect(ui.clip_rect()));
                    child.label(egui::RichText::new(note).small().color(palette::rgb(palette::PATH_WARNING)));
                }
                if let (Some(text), Some(pointer)) = (hover, resp.response.hover_pos()) {
                    let id = ui.make_persistent_id(("plot_readout", k));
                    plot_axis::show_readout(ui.ctx(), id, pointer, resp.response.rect, text);
                }
                visible.get_or_insert((x0, x1));
                if collect_svg {
                    svg_groups.push(group);
                }
                let r = &resp.response;
                let wheel =
                    r.hovered() && ui.input(|i| i.smooth_scroll_delta != egui::Vec2::ZERO || i.zoom_delta() != 1.0);
                if r.dragged() || wheel {
                    interacted = true;
                }
                if cursor.is_some() && clicked_at.is_some() {
                    seek = clicked_at;
                }
            }
        });
        self.visible_s = visible;
        self.drawn_s = drawn_s;
        if interacted {
            self.follow = false;
        }
        if let Some(t) = seek {
            ctx.send(AppCommand::SeekReplay(t));
        }
        if let Some(path) = self.svg_pending.take() {
            let (t0, t1) = visible.unwrap_or((0.0, 1.0));
            match plot_export::write_svg(&path, &svg_groups, t0, t1) {
                Ok(()) => ctx.info(format!("wrote {}", path.display())),
                Err(e) => ctx.error(e),
            }
        }
    }
}
