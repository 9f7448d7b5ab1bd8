//! Lower panel: the replay timeline of an open recording. Play / pause, speed, a scrub bar
//! over the whole recording, the events as buttons that jump there, close. The 3D view shows
//! the recorded arm at the cursor and the read-outs and plots follow it. The recording and its
//! cursor are the app's ([`crate::app::state::AppState::replay`]); the panel reads them and
//! changes them only through [`AppCommand::Replay`].

use eframe::egui;

use super::{AppCommand, Panel, PanelContext};
pub use crate::app::state::Replay;
use crate::palette;

/// Replay speeds offered.
pub const SPEEDS: [f64; 6] = [0.1, 0.25, 0.5, 1.0, 2.0, 5.0];

/// Events listed in the panel (the rest are counted).
const EVENTS_SHOWN: usize = 40;

/// What the timeline panel asks of the open recording (carried out by the app).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ReplayControl {
    /// Play (from the start when the cursor is at the end) or pause.
    Play(bool),
    /// Playback speed (1 = real time).
    Speed(f64),
    /// Move the cursor to this motion time, s, playing on (the scrub bar; an event or a plot
    /// click pauses: [`AppCommand::SeekReplay`]).
    Scrub(f64),
}

/// The timeline panel (shown while a recording is open).
#[derive(Default)]
pub struct TimelinePanel {
    /// Sizes of the event buttons, points, as last laid out, and the scale they were laid out
    /// at: the events row lays out only the buttons it shows (see [`events_row`]).
    event_sizes_pt: (Vec<egui::Vec2>, f32, super::AngleUnit),
}

impl Panel for TimelinePanel {
    fn title(&self) -> &'static str {
        "Replay"
    }

    fn shown(&self, ctx: &PanelContext<'_>) -> bool {
        ctx.app.replay.is_some()
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let app = ctx.app;
        let Some(r) = app.replay.as_ref() else { return };
        let mut commands = Vec::new();
        let (t0, t1) = r.span_s();
        // Close at the row's right end and the rest cut to the width left: a long program path
        // in the metadata made this row wider than the panel, which put Close, the scrub bar's
        // end and the plots' controls below it past the panel's edge (1024 px window)
        ui.horizontal(|ui| {
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                if ui.button("Close recording").clicked() {
                    ctx.send(AppCommand::CloseRecording);
                }
                ui.with_layout(egui::Layout::left_to_right(egui::Align::Center), |ui| {
                    let d = &r.data;
                    let title = egui::RichText::new(format!("Replay: {}", r.file_name())).strong();
                    ui.add(egui::Label::new(title).truncate());
                    if d.truncated {
                        let text = egui::RichText::new("cut short: showing what could be read")
                            .color(palette::rgb(palette::WARN_TEXT));
                        ui.add(egui::Label::new(text).truncate());
                    }
                    let info = format!(
                        "{} · {} samples in the file · {:.1} s{}",
                        d.robot,
                        d.samples_in_file,
                        t1 - t0,
                        if d.program.is_empty() { String::new() } else { format!(" · program {}", d.program) }
                    );
                    ui.add(egui::Label::new(egui::RichText::new(&info).weak()).truncate()).on_hover_text(info);
                });
            });
        });
        ui.horizontal(|ui| {
            let label = if r.playing { "Pause" } else { "Play" };
            if ui.button(label).clicked() {
                commands.push(AppCommand::Replay(ReplayControl::Play(!r.playing)));
            }
            egui::ComboBox::from_id_salt("replay_speed").selected_text(format!("{}×", r.speed)).width(64.0).show_ui(
                ui,
                |ui| {
                    for s in SPEEDS {
                        if ui.selectable_label(r.speed == s, format!("{s}×")).clicked() {
                            commands.push(AppCommand::Replay(ReplayControl::Speed(s)));
                        }
                    }
                },
            );
            ui.label(format!("{:.2} s", r.cursor_s - t0));
            let mut at = r.cursor_s;
            let width = (ui.available_width() - 80.0).max(100.0);
            ui.spacing_mut().slider_width = width;
            let slider = egui::Slider::new(&mut at, t0..=t1.max(t0 + 1e-3)).show_value(false).text("time");
            if ui.add(slider).changed() {
                commands.push(AppCommand::Replay(ReplayControl::Scrub(at)));
            }
        });
        if let Some(t) = events_row(ui, r, &mut self.event_sizes_pt, t0, ctx.settings.unit) {
            commands.push(AppCommand::SeekReplay(t));
        }
        ctx.commands.append(&mut commands);
    }
}

/// The events as buttons that jump to their time, in a row that scrolls sideways; the time
/// clicked, if any. Only the buttons that show are laid out: the others take the size they
/// had when last laid out (all of them the first time, and again at a new scale). Laying out
/// the hidden ones cost a text layout each on every frame that draws the panels, and with
/// frame reuse (`app/frame_reuse`) each of those frames laid them out anew.
fn events_row(
    ui: &mut egui::Ui,
    r: &Replay,
    event_sizes_pt: &mut (Vec<egui::Vec2>, f32, super::AngleUnit),
    t0: f64,
    unit: super::AngleUnit,
) -> Option<f64> {
    let events = &r.data.events;
    if events.is_empty() {
        return None;
    }
    let shown = events.len().min(EVENTS_SHOWN);
    let ppp = ui.ctx().pixels_per_point();
    let (sizes, sizes_ppp, sizes_unit) = event_sizes_pt;
    // the texts' angles are in the chosen unit: another unit, other widths
    if *sizes_ppp != ppp || *sizes_unit != unit || sizes.len() != shown {
        sizes.clear();
        *sizes_ppp = ppp;
        *sizes_unit = unit;
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
                    let message = super::angle_text::in_unit(&e.message, unit);
                    let text = egui::RichText::new(format!("{:.1} s {message}", e.time_s - t0)).color(color);
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
