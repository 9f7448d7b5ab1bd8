//! Replay in the window: opening a recording off the UI thread (File → Open recording,
//! `parol6 replay FILE.mcap`), moving its cursor each frame while it plays, and handing the
//! recording and cursor to the plots. While a recording is open the 3D view shows the
//! recorded arm at the cursor (the commanded pose as the ghost).

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use crossbeam_channel::{Receiver, TryRecvError, bounded};
use parol6_core::telemetry::{ReplayData, ReplayError, read_replay_file};

use super::Parol6App;
use super::state::Replay;
use crate::panels::timeline::ReplayControl;

/// A recording being read: its path and where the result (and the seconds it took) arrives.
pub(super) type ReplayLoading = (PathBuf, Receiver<Result<(ReplayData, f64), String>>);

/// Reads `path` and loads it for replay with `model`: a clear message for a file that cannot
/// be read, is empty, is not a recording of ours or is of another robot.
pub fn read_replay(path: &std::path::Path, model: &parol6_core::RobotModel) -> Result<ReplayData, String> {
    read_replay_file(path, model).map_err(|e| match e {
        ReplayError::Io { .. } => e.to_string(),
        ReplayError::Recording(e) => format!("cannot replay {}: {e}", path.display()),
    })
}

impl Parol6App {
    /// Starts reading `path` on a thread; the replay opens when it is read.
    pub(super) fn open_recording(&mut self, path: PathBuf) {
        let (tx, rx) = bounded(1);
        let model = self.model.clone();
        let p = path.clone();
        let spawned = std::thread::Builder::new().name("parol6-replay-load".into()).spawn(move || {
            let t0 = Instant::now();
            let _ = tx.send(read_replay(&p, &model).map(|d| (d, t0.elapsed().as_secs_f64())));
        });
        match spawned {
            Ok(_) => {
                self.notice(format!("opening {}", path.display()), false);
                self.replay_loading = Some((path, rx));
            }
            Err(e) => self.notice(format!("cannot start reading {}: {e}", path.display()), true),
        }
    }

    /// Opens `data`, already read from `path` in `read_s` seconds (`parol6 replay FILE` reads it
    /// before the window opens).
    pub(super) fn open_loaded_recording(&mut self, path: PathBuf, data: ReplayData, read_s: f64) {
        let (tx, rx) = bounded(1);
        let _ = tx.send(Ok((data, read_s)));
        self.replay_loading = Some((path, rx));
    }

    /// Takes the loaded recording (or its error) when it has arrived.
    pub(super) fn poll_replay_loading(&mut self) {
        let Some((path, rx)) = &self.replay_loading else { return };
        let result = match rx.try_recv() {
            Ok(r) => r,
            Err(TryRecvError::Empty) => return,
            Err(TryRecvError::Disconnected) => Err(format!("reading {} stopped", path.display())),
        };
        let path = path.clone();
        self.replay_loading = None;
        match result {
            Ok((data, read_s)) => {
                for w in &data.warnings {
                    self.notice(format!("{}: {w}", path.display()), true);
                }
                let samples = data.store.len();
                let replay = Replay::new(path.clone(), Arc::new(data));
                let (t0, t1) = replay.span_s();
                self.notice(
                    format!(
                        "replaying {} ({:.1} s, {samples} samples, read in {read_s:.2} s): the 3D view shows the recording",
                        path.display(),
                        t1 - t0
                    ),
                    false,
                );
                self.state.replay = Some(replay);
                self.release_memory_at = Some(Instant::now() + super::RELEASE_MEMORY_AFTER);
                self.settings.show_plots = true;
                if let Some(v) = &mut self.viewport {
                    v.clear_trail();
                }
            }
            Err(e) => self.notice(e, true),
        }
    }

    /// Closes the open recording: the 3D view and the plots show the live robot again.
    pub(super) fn close_recording(&mut self) {
        if self.state.replay.take().is_some() {
            self.panels.prepare(&self.state, None);
            self.release_memory_at = Some(Instant::now() + super::RELEASE_MEMORY_AFTER);
            if let Some(v) = &mut self.viewport {
                v.clear_trail();
            }
        }
    }

    /// Moves the cursor of a playing replay and hands the recording to the panels, or the live
    /// view when none is open (only while the plots are shown). Returns true while playing.
    pub(super) fn replay_frame(&mut self, now: Instant) -> bool {
        self.poll_replay_loading();
        let playing = self.state.replay.as_mut().is_some_and(|r| r.advance(now));
        let live = (self.state.replay.is_none() && self.settings.show_plots).then(|| self.live_view());
        self.panels.prepare(&self.state, live.as_deref());
        playing
    }

    /// Plays, pauses, changes the speed of, scrubs or seeks (and pauses) the open recording.
    pub(super) fn control_replay(&mut self, control: ReplayControl) {
        let Some(r) = &mut self.state.replay else { return };
        match control {
            ReplayControl::Play(playing) => r.play(playing),
            ReplayControl::Speed(speed) => r.speed = speed,
            ReplayControl::Scrub(t_s) => r.seek(t_s),
        }
    }

    /// Moves the cursor of the open recording to `t_s` and pauses (an event or a plot clicked).
    pub(super) fn seek_replay(&mut self, t_s: f64) {
        if let Some(r) = &mut self.state.replay {
            r.seek(t_s);
            r.playing = false;
        }
    }

    /// Opens `data` (read from `path`) for replay at once, with the plots shown over
    /// `window_s` seconds, playing or not (the render benchmark uses it).
    pub fn show_replay(&mut self, path: PathBuf, data: ReplayData, playing: bool, window_s: f64) {
        let mut replay = Replay::new(path, Arc::new(data));
        replay.playing = playing;
        self.state.replay = Some(replay);
        self.release_memory_at = Some(Instant::now() + super::RELEASE_MEMORY_AFTER);
        self.settings.show_plots = true;
        // the render benchmark's window (the plots follow a newly opened recording themselves)
        self.panels.plots.window_s = window_s;
    }

    /// The open recording, if any.
    pub fn replay(&self) -> Option<&Replay> {
        self.state.replay.as_ref()
    }

    /// True while a recording is being read.
    pub fn replay_loading(&self) -> bool {
        self.replay_loading.is_some()
    }
}
