//! Lower panel: the replay timeline of an open recording. Play / pause, speed, a scrub bar
//! over the whole recording, the events as buttons that jump there, close. The 3D view shows
//! the recorded arm at the cursor and the plots follow it (the app reads
//! [`TimelinePanel::replay`] each frame).

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use eframe::egui;
use parol6_core::telemetry::ReplayData;

use super::{AppCommand, Panel, PanelContext};
use crate::palette;

/// Replay speeds offered.
pub const SPEEDS: [f64; 6] = [0.1, 0.25, 0.5, 1.0, 2.0, 5.0];

/// Events listed in the panel (the rest are counted).
const EVENTS_SHOWN: usize = 40;

/// An open recording and where its cursor is.
#[derive(Debug, Clone)]
pub struct Replay {
    /// The file.
    pub path: PathBuf,
    /// What it holds.
    pub data: Arc<ReplayData>,
    /// Cursor, motion time, s.
    pub cursor_s: f64,
    /// Playing (else paused).
    pub playing: bool,
    /// Playback speed (1 = real time).
    pub speed: f64,
    last_tick: Option<Instant>,
    /// Sizes of the event buttons, points, as last laid out, and the scale they were laid out
    /// at: the events row lays out only the buttons it shows (see [`events_row`]).
    event_sizes_pt: (Vec<egui::Vec2>, f32),
}

impl Replay {
    /// A replay of `data` with the cursor at its start, paused.
    pub fn new(path: PathBuf, data: Arc<ReplayData>) -> Self {
        let cursor_s = data.store.time_range_s().map_or(0.0, |(t0, _)| t0);
        Self { path, data, cursor_s, playing: false, speed: 1.0, last_tick: None, event_sizes_pt: (Vec::new(), 0.0) }
    }

    /// First and last sample time, s (0, 0 when empty).
    pub fn span_s(&self) -> (f64, f64) {
        self.data.store.time_range_s().unwrap_or((0.0, 0.0))
    }

    /// Moves the cursor to `t_s` (clamped to the recording).
    pub fn seek(&mut self, t_s: f64) {
        let (t0, t1) = self.span_s();
        if t_s.is_finite() {
            self.cursor_s = t_s.clamp(t0, t1.max(t0));
        }
    }

    /// Advances the cursor by the wall time since the last call × speed while playing; stops
    /// at the end. Returns true while playing (the window keeps repainting).
    pub fn advance(&mut self, now: Instant) -> bool {
        let last = self.last_tick.replace(now);
        if !self.playing {
            return false;
        }
        let dt_s = last.map_or(0.0, |l| now.duration_since(l).as_secs_f64().min(0.25));
        let (_, t1) = self.span_s();
        self.cursor_s = (self.cursor_s + dt_s * self.speed).min(t1);
        if self.cursor_s >= t1 {
            self.playing = false;
        }
        self.playing
    }

    /// Measured and commanded joint positions at the cursor, rad.
    pub fn joints_at_cursor(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        let store = &self.data.store;
        let (_, row) = store.row_at(self.cursor_s)?;
        let n = store.joints();
        let q: Vec<f64> = row.iter().take(n).map(|&v| f64::from(v)).collect();
        let err_col = 4 * n;
        let cmd = q.iter().enumerate().map(|(j, q)| q + row.get(err_col + j).map_or(0.0, |&e| f64::from(e))).collect();
        Some((q, cmd))
    }

    /// File name for headings.
    pub fn file_name(&self) -> String {
        self.path.file_name().map_or_else(|| self.path.display().to_string(), |n| n.to_string_lossy().into_owned())
    }
}

/// The timeline panel (shown while a recording is open).
#[derive(Default)]
pub struct TimelinePanel {
    /// The open recording.
    pub replay: Option<Replay>,
}

impl Panel for TimelinePanel {
    fn title(&self) -> &'static str {
        "Replay"
    }

    fn shown(&self, _settings: &super::Settings) -> bool {
        self.replay.is_some()
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let Some(r) = self.replay.as_mut() else { return };
        let (t0, t1) = r.span_s();
        ui.horizontal(|ui| {
            ui.strong(format!("Replay: {}", r.file_name()));
            let d = &r.data;
            ui.weak(format!(
                "{} · {} samples in the file · {:.1} s{}",
                d.robot,
                d.samples_in_file,
                t1 - t0,
                if d.program.is_empty() { String::new() } else { format!(" · program {}", d.program) }
            ));
            if d.truncated {
                ui.colored_label(palette::rgb(palette::WARN_TEXT), "cut short: showing what could be read");
            }
            if ui.button("Close recording").clicked() {
                ctx.send(AppCommand::CloseRecording);
            }
        });
        ui.horizontal(|ui| {
            let label = if r.playing { "Pause" } else { "Play" };
            if ui.button(label).clicked() {
                if !r.playing && r.cursor_s >= t1 {
                    r.cursor_s = t0;
                }
                r.playing = !r.playing;
            }
            egui::ComboBox::from_id_salt("replay_speed").selected_text(format!("{}×", r.speed)).width(64.0).show_ui(
                ui,
                |ui| {
                    for s in SPEEDS {
                        ui.selectable_value(&mut r.speed, s, format!("{s}×"));
                    }
                },
            );
            ui.label(format!("{:.2} s", r.cursor_s - t0));
            let mut at = r.cursor_s;
            let width = (ui.available_width() - 80.0).max(100.0);
            ui.spacing_mut().slider_width = width;
            let slider = egui::Slider::new(&mut at, t0..=t1.max(t0 + 1e-3)).show_value(false).text("time");
            if ui.add(slider).changed() {
                r.seek(at);
            }
        });
        if let Some(t) = events_row(ui, r, t0) {
            r.seek(t);
            r.playing = false;
        }
    }
}

/// The events as buttons that jump to their time, in a row that scrolls sideways; the time
/// clicked, if any. Only the buttons that show are laid out: the others take the size they
/// had when last laid out (all of them the first time, and again at a new scale). Laying out
/// the hidden ones cost a text layout each on every frame that draws the panels, and with
/// frame reuse (`app/frame_reuse`) each of those frames laid them out anew.
fn events_row(ui: &mut egui::Ui, r: &mut Replay, t0: f64) -> Option<f64> {
    let events = &r.data.events;
    if events.is_empty() {
        return None;
    }
    let shown = events.len().min(EVENTS_SHOWN);
    let ppp = ui.ctx().pixels_per_point();
    let (sizes, sizes_ppp) = &mut r.event_sizes_pt;
    if *sizes_ppp != ppp || sizes.len() != shown {
        sizes.clear();
        *sizes_ppp = ppp;
    }
    let mut jump = None;
    ui.scope(|ui| {
        // a solid scroll bar, under the buttons: a floating one lies over their lower half while
        // the pointer is on them and takes the clicks there
        ui.spacing_mut().scroll = egui::style::ScrollStyle::solid();
        egui::ScrollArea::horizontal().id_salt("replay_events").show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.label("Events:");
                let known = sizes.len() == shown;
                for (i, e) in events.iter().take(shown).enumerate() {
                    if known {
                        let size = sizes[i];
                        if !ui.is_rect_visible(egui::Rect::from_min_size(ui.cursor().min, size)) {
                            ui.allocate_space(size);
                            continue;
                        }
                    }
                    let color = palette::rgb(match e.level {
                        0..=2 => palette::PLOT_EVENT_INFO,
                        3 => palette::WARN_TEXT,
                        _ => palette::ERROR_TEXT,
                    });
                    let text = egui::RichText::new(format!("{:.1} s {}", e.time_s - t0, e.message)).color(color);
                    let button = ui.small_button(text).on_hover_text("jump here");
                    if button.clicked() {
                        jump = Some(e.time_s);
                    }
                    if !known {
                        sizes.push(button.rect.size());
                    }
                }
                if events.len() > shown {
                    ui.weak(format!("… {} more", events.len() - shown));
                }
            });
        });
    });
    jump
}
