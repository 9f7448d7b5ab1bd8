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
        ReplayError::Recording(e) => super::telemetry::file_error("cannot replay ", path, &e),
    })
}

/// Drops `garbage` on a thread of its own, so that freeing it (unmapping tens of MB) does not
/// run in a frame; where no thread can be started, it is dropped here.
pub fn free_off_ui_thread<T: Send + 'static>(garbage: T) {
    let work = move || drop(garbage);
    let (tx, rx) = bounded::<Box<dyn FnOnce() + Send>>(1);
    let spawned = crate::background::spawn("parol6-free", move || {
        if let Ok(work) = rx.recv() {
            work();
        }
    });
    match spawned {
        Ok(_) => {
            if let Err(e) = tx.send(Box::new(work)) {
                tracing::warn!("the freeing thread ended early: freed on the UI thread");
                (e.into_inner())();
            }
        }
        Err(e) => {
            tracing::warn!("cannot start a thread to free a closed recording ({e}): freed on the UI thread");
            work();
        }
    }
}

/// Why a recording is not opened while the arm moves by hand (see `replay_refused_by`).
const ARM_MOVING: &str = "the arm is moving: let it stop (or press STOP) first";

impl Parol6App {
    /// Why a recording cannot be opened now, if it cannot: while the arm may move, every read-out
    /// would show the recording while the live arm moved (trial 21 D1: a program went on driving
    /// the robot under REPLAY, the 3D view showing the recorded arm at rest).
    fn replay_refused_by(&self) -> Option<&'static str> {
        if self.program_running() {
            Some(super::state::PROGRAM_UNFINISHED)
        } else if self.state.measurement.running() {
            Some(super::state::MEASUREMENT_RUNNING)
        } else if self.state.torque_run {
            Some(super::state::TORQUE_RUNNING)
        } else {
            self.robot_state().moving.then_some(ARM_MOVING)
        }
    }

    /// Starts reading `path` on a thread; the replay opens when it is read, unless the arm has
    /// started moving by then ([`Self::replay_refused_by`]).
    pub(super) fn open_recording(&mut self, path: PathBuf) {
        if let Some(why) = self.replay_refused_by() {
            self.notice(format!("{} not opened: {why}", path.display()), true);
            return;
        }
        let (tx, rx) = bounded(1);
        let model = self.model.clone();
        let p = path.clone();
        let spawned = crate::background::spawn("parol6-replay-load", move || {
            let t0 = Instant::now();
            // the window may have been closed, or another recording opened: nobody waits then
            if tx.send(read_replay(&p, &model).map(|d| (d, t0.elapsed().as_secs_f64()))).is_err() {
                tracing::debug!("a recording was read after it was no longer wanted");
            }
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
        let refused = self.replay_refused_by();
        match result {
            Ok((data, _)) if let Some(why) = refused => {
                let opening = format!("opening {}", path.display());
                crate::panels::Notice::withdraw(&mut self.notices, |t| t == opening);
                self.notice(format!("{} not opened: {why}", path.display()), true);
                free_off_ui_thread(data);
            }
            Ok((data, read_s)) => {
                for w in &data.warnings {
                    self.notice(format!("{}: {w}", path.display()), true);
                }
                // the file's count, as the timeline's header gives it; what replay keeps (at
                // most the live view's rate) is said beside it where it is fewer
                let (in_file, kept) = (data.samples_in_file, data.store.len() as u64);
                let kept = if kept < in_file {
                    format!(", {kept} replayed at {} Hz", parol6_core::telemetry::replay::REPLAY_RATE_HZ)
                } else {
                    String::new()
                };
                let opening = format!("opening {}", path.display());
                crate::panels::Notice::withdraw(&mut self.notices, |t| t == opening);
                let replay = Replay::new(path.clone(), Arc::new(data));
                let (t0, t1) = replay.span_s();
                self.notice(
                    format!(
                        "replaying {} ({:.1} s, {in_file} samples in the file{kept}, read in {read_s:.2} s): the 3D view shows the recording",
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

    /// Closes the open recording: the 3D view and the plots show the live robot again. The
    /// recording (for ten minutes at 1 kHz, tens of MB) and the Dynamics panel's analysis of it
    /// are freed on a thread of their own: the frame that closes it does not wait for that.
    pub(super) fn close_recording(&mut self) {
        if let Some(replay) = self.state.replay.take() {
            // "replaying FILE …: the 3D view shows the recording" no longer holds
            crate::panels::Notice::withdraw(&mut self.notices, |t| t.starts_with("replaying "));
            // the plots let go of their handle; ours and the Dynamics panel's are the last
            self.panels.prepare(&self.state, None);
            let analysis = self.panels.dynamics.forget_replay();
            free_off_ui_thread((replay, analysis));
            self.release_memory_at = Some(Instant::now() + super::RELEASE_MEMORY_AFTER);
            if let Some(v) = &mut self.viewport {
                v.clear_trail();
            }
        }
    }

    /// Moves the cursor of a playing replay and hands the recording to the panels, and the live
    /// view (only while the plots are shown). Returns true while playing.
    pub(super) fn replay_frame(&mut self, now: Instant) -> bool {
        self.poll_replay_loading();
        let playing = self.state.replay.as_mut().is_some_and(|r| r.advance(now));
        // the live history keeps growing during replay, so closing the recording does not
        // take in all the samples of its time at once
        let live = self.settings.show_plots.then(|| self.live_view());
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Sends the thread it is dropped on.
    struct DropProbe(crossbeam_channel::Sender<std::thread::ThreadId>);

    impl Drop for DropProbe {
        fn drop(&mut self) {
            if self.0.send(std::thread::current().id()).is_err() {
                eprintln!("nobody waits for the drop probe");
            }
        }
    }

    #[test]
    fn a_closed_recording_is_freed_on_another_thread() {
        let (tx, rx) = bounded(1);
        free_off_ui_thread(DropProbe(tx));
        let dropped_on = rx.recv_timeout(std::time::Duration::from_secs(10)).expect("dropped");
        assert_ne!(dropped_on, std::thread::current().id());
    }
}
