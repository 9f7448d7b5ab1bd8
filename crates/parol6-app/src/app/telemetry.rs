//! Telemetry in the window: one [`Recorder`] per backend (the simulation's from the start, the
//! serial link's while connected) fed by the backend's sample tap; each frame passes the
//! shown state, the link health and the running program's step to the active one. Its live
//! view (the last ten minutes) feeds the plots; `--record OUT.mcap` and File → Record write
//! the active backend to a file.

use std::path::Path;
use std::sync::Arc;

use parol6_core::RobotModel;
use parol6_core::telemetry::{EventKind, LinkHealth, LiveView, Recorder, RecorderConfig, RecordingInfo};
use parol6_hw::session::Snapshot;

use super::Parol6App;
use crate::panels::RobotState;

/// The link health of a session snapshot, as the recorder keeps it.
pub fn link_health(s: &Snapshot) -> LinkHealth {
    LinkHealth {
        state: format!("{:?}", s.link),
        loop_rate_hz: s.loop_rate_hz,
        missing_replies: s.missing_replies,
        link_losses: s.link_losses,
        estop_pressed: s.estop_pressed,
    }
}

/// Starts a recorder for `model`'s joints.
pub(super) fn start_recorder(model: &RobotModel) -> Option<Recorder> {
    match Recorder::start(model.clone(), RecorderConfig::default()) {
        Ok(r) => Some(r),
        Err(e) => {
            tracing::warn!("telemetry: {e}");
            None
        }
    }
}

impl Parol6App {
    /// The recorder of the active backend.
    pub(super) fn active_recorder(&self) -> Option<&Recorder> {
        match &self.hw {
            Some(link) => link.recorder.as_ref(),
            None => self.sim_recorder.as_ref(),
        }
    }

    /// The live view of the active backend (empty without a recorder).
    pub fn live_view(&self) -> Arc<LiveView> {
        self.active_recorder().map(Recorder::live).unwrap_or_default()
    }

    /// Hands the plots the active backend's rows just before a switch of backend: the plots take
    /// the live view only while shown, and the outgoing backend's view is dropped (the robot's)
    /// or stops keeping rows (the simulation's), so a hidden panel lost that stretch (trial13 D2).
    pub(super) fn plots_take_rows_before_switch(&mut self) {
        let view = self.live_view();
        self.panels.plots.feed_live(&view, self.hw.is_some());
    }

    /// Closes a link that is going away: its recorder takes every sample the session delivered
    /// and the plots get those last rows (the published view was up to 50 ms old, more on a
    /// busy host: the robot's last moments before a disconnect were missing, trial14 m4).
    pub(super) fn plots_take_the_last_rows_of(&mut self, mut link: super::link::HwLink) {
        if let Some(recorder) = link.recorder.take() {
            let (finished, view) = recorder.finish_with_live();
            if let Err(e) = finished {
                tracing::warn!("the robot's telemetry did not close cleanly: {e}");
            }
            self.panels.plots.feed_live(&view, true);
        }
    }

    /// Passes this frame's state, link health and program step to the active recorder.
    pub(super) fn feed_telemetry(&mut self, robot: &Arc<RobotState>) {
        let step = self.program.as_ref().filter(|r| !r.is_finished()).and(self.state.program.as_ref());
        let step = step.map(|p| p.step);
        let link = self.hw.as_ref().map(|l| link_health(&l.session.snapshot()));
        let step_changed = self.last_program_step != Some(step);
        let Some(rec) = self.active_recorder() else { return };
        rec.observe_state(Arc::clone(robot));
        if let Some(h) = link {
            rec.set_link_health(h);
        }
        if step_changed {
            rec.set_program_step(step);
        }
        let error = rec.last_error();
        if step_changed {
            self.last_program_step = Some(step);
        }
        if let Some(e) = error
            && self.state.recording.is_some()
        {
            self.state.recording = None;
            self.notice(e, true);
        }
    }

    /// The program a recording names in its metadata: the one running, else the one loaded in
    /// the program panel ("Draw", or "pick (/path/pick.json)" for a file). A program started
    /// later is logged to `/events` (see [`Self::note_program_start`]).
    fn recorded_program(&self) -> String {
        if let Some(p) = self.state.program.as_ref().filter(|_| self.program_running()) {
            return p.name.clone();
        }
        let panel = &self.panels.program;
        match panel.file() {
            Some(f) => format!("{} ({})", panel.program().name, f.display()),
            None => panel.program().name.clone(),
        }
    }

    /// Logs a program's start to the recording being written, if any: the metadata names only
    /// the program of the recording's start.
    pub(super) fn note_program_start(&self, name: &str) {
        if self.state.recording.is_none() {
            return;
        }
        if let Some(rec) = self.active_recorder() {
            let message = format!("program {name} started");
            rec.event(parol6_core::telemetry::TelemetryEvent { time_s: f64::NAN, kind: EventKind::Note, message });
        }
    }

    /// Starts writing the active backend to `path`.
    pub(super) fn start_file_recording(&mut self, path: &Path) {
        if let Some(r) = &self.state.recording {
            let shown = r.path.display().to_string();
            self.notice(format!("already recording to {shown}: stop it first"), true);
            return;
        }
        let on_robot = self.hw.is_some();
        let Some(rec) = self.active_recorder() else {
            self.notice("cannot record: the telemetry recorder did not start", true);
            return;
        };
        let info = RecordingInfo {
            app_version: env!("CARGO_PKG_VERSION").to_string(),
            program: self.recorded_program(),
            tracking: self.hw.as_ref().map_or(self.sim_tracking, |h| h.tracking).name().to_string(),
            ..self.recording_info.clone()
        };
        match rec.start_recording(path, &info) {
            Ok(()) => {
                self.state.recording = Some(super::state::FileRecording {
                    path: path.to_path_buf(),
                    on_robot,
                    started: std::time::Instant::now(),
                });
                let what = if on_robot { "the robot" } else { "the simulation" };
                self.notice(format!("recording {what} to {}", path.display()), false);
            }
            Err(e) => self.notice(file_error("cannot record to ", path, &e), true),
        }
    }

    /// Stops writing (the file gets its summary and index).
    pub(super) fn stop_file_recording(&mut self) {
        let Some(r) = self.state.recording.take() else { return };
        let rec =
            if r.on_robot { self.hw.as_ref().and_then(|l| l.recorder.as_ref()) } else { self.sim_recorder.as_ref() };
        let result = rec.map(Recorder::stop_recording);
        match result {
            Some(Ok(Some(s))) => self.notice(
                format!("recorded {} samples ({:.1} s) to {}", s.samples, s.duration_s, r.path.display()),
                false,
            ),
            Some(Ok(None)) | None => {}
            Some(Err(e)) => self.notice(file_error("", &r.path, &e), true),
        }
    }

    /// The file being written, if any.
    pub fn recording_path(&self) -> Option<&Path> {
        self.state.recording.as_ref().map(|r| r.path.as_path())
    }
}

/// "`what`PATH: REASON" with the path named once: the telemetry errors begin with their path
/// already ("cannot record to P: P: it is being recorded to now" was the refusal).
pub(super) fn file_error(what: &str, path: &Path, e: &dyn std::fmt::Display) -> String {
    let shown = path.display().to_string();
    let text = e.to_string();
    let reason = text.strip_prefix(&format!("{shown}: ")).unwrap_or(&text);
    format!("{what}{shown}: {reason}")
}
