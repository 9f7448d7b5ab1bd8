//! [`SequenceRunner`]: runs a list of motion commands one after another on any
//! [`RobotBackend`], on its own thread, so a sequence keeps its pace whatever the UI does
//! (minimised window, 5 FPS, a busy machine).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use arc_swap::ArcSwap;

use super::{MotionCommand, RobotBackend};

/// How often the runner looks at the backend's state.
const POLL: Duration = Duration::from_millis(2);
/// A step that the backend has not taken within this time fails.
const ACCEPT_TIMEOUT: Duration = Duration::from_secs(2);

/// Where a sequence is.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum SequenceState {
    /// Running step [`SequenceProgress::step`].
    Running,
    /// All steps done (and not looping).
    Done,
    /// Cancelled by the operator.
    Cancelled,
    /// A step was refused or the backend stopped accepting motion; the reason.
    Failed(String),
}

/// Progress of a sequence, published by its thread.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SequenceProgress {
    /// Name of the sequence.
    pub name: String,
    /// 0-based index of the step under way (or the last one).
    pub step: usize,
    /// Number of steps.
    pub steps: usize,
    /// Completed passes through the whole list.
    pub passes: u64,
    /// State.
    pub state: SequenceState,
}

/// A sequence of motion commands running on its own thread. Dropping it cancels the sequence.
pub struct SequenceRunner {
    progress: Arc<ArcSwap<SequenceProgress>>,
    cancel: Arc<AtomicBool>,
    join: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for SequenceRunner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SequenceRunner").field("progress", &self.progress()).finish()
    }
}

impl SequenceRunner {
    /// Starts running `steps` on `backend`: each step is sent when the previous one has been
    /// applied and the arm has settled. With `looping`, starts over after the last step.
    pub fn start(
        backend: Arc<dyn RobotBackend>,
        name: impl Into<String>,
        steps: Vec<MotionCommand>,
        looping: bool,
    ) -> std::io::Result<Self> {
        let progress = Arc::new(ArcSwap::from_pointee(SequenceProgress {
            name: name.into(),
            step: 0,
            steps: steps.len(),
            passes: 0,
            state: SequenceState::Running,
        }));
        let cancel = Arc::new(AtomicBool::new(false));
        let (p, c) = (Arc::clone(&progress), Arc::clone(&cancel));
        let join = std::thread::Builder::new()
            .name("parol6-sequence".into())
            .spawn(move || run(backend.as_ref(), &steps, looping, &p, &c))?;
        Ok(Self { progress, cancel, join: Some(join) })
    }

    /// The latest progress.
    pub fn progress(&self) -> SequenceProgress {
        self.progress.load().as_ref().clone()
    }

    /// True while the sequence runs.
    pub fn is_running(&self) -> bool {
        self.progress.load().state == SequenceState::Running
    }

    /// Stops sending steps (the step under way finishes unless the caller also sends STOP).
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::SeqCst);
    }

    /// Waits for the thread to end.
    pub fn join(mut self) -> SequenceProgress {
        if let Some(j) = self.join.take() {
            let _ = j.join();
        }
        self.progress()
    }
}

impl Drop for SequenceRunner {
    fn drop(&mut self) {
        self.cancel();
        if let Some(j) = self.join.take() {
            let _ = j.join();
        }
    }
}

fn run(
    backend: &dyn RobotBackend,
    steps: &[MotionCommand],
    looping: bool,
    progress: &ArcSwap<SequenceProgress>,
    cancel: &AtomicBool,
) {
    let publish = |step: usize, passes: u64, state: SequenceState| {
        let mut p = progress.load().as_ref().clone();
        p.step = step;
        p.passes = passes;
        p.state = state;
        progress.store(Arc::new(p));
    };
    let mut passes = 0;
    loop {
        for (i, cmd) in steps.iter().enumerate() {
            publish(i, passes, SequenceState::Running);
            if let Err(reason) = run_step(backend, cmd, cancel) {
                let state = if cancel.load(Ordering::SeqCst) {
                    SequenceState::Cancelled
                } else {
                    SequenceState::Failed(format!("step {} ({}): {reason}", i + 1, cmd.name()))
                };
                publish(i, passes, state);
                return;
            }
        }
        passes += 1;
        if !looping || steps.is_empty() {
            publish(steps.len().saturating_sub(1), passes, SequenceState::Done);
            return;
        }
    }
}

/// Sends one step and waits until it has been applied and the motion has ended.
fn run_step(backend: &dyn RobotBackend, cmd: &MotionCommand, cancel: &AtomicBool) -> Result<(), String> {
    let before = backend.state();
    if let Some(b) = &before.blocked {
        return Err(b.clone());
    }
    let refusal_id = before.last_refusal.as_ref().map_or(0, |r| r.0);
    backend.send(cmd.clone()).map_err(|e| e.to_string())?;
    let sent = Instant::now();
    let mut accepted = false;
    loop {
        if cancel.load(Ordering::SeqCst) {
            return Err("cancelled".into());
        }
        std::thread::sleep(POLL);
        let s = backend.state();
        if let Some((id, msg)) = &s.last_refusal
            && *id > refusal_id
        {
            return Err(msg.clone());
        }
        if let Some(b) = &s.blocked {
            return Err(b.clone());
        }
        if !accepted {
            accepted = s.commands_applied > before.commands_applied;
            if !accepted && sent.elapsed() > ACCEPT_TIMEOUT {
                return Err("the backend did not take the command within 2 s".into());
            }
            continue;
        }
        if !s.moving {
            return Ok(());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::RobotModel;
    use crate::profile::ProfileKind;
    use crate::sim::{SimConfig, SimHandle};

    /// A sequence keeps its pace on its own thread: nobody polls or draws frames while it runs.
    #[test]
    fn a_sequence_runs_without_anyone_driving_it() {
        let model = RobotModel::parol6();
        let sim = Arc::new(SimHandle::spawn(model.clone(), SimConfig::default()).expect("sim"));
        let home = crate::parol6::standby_rad().to_vec();
        let mut a = home.clone();
        a[0] -= 0.3;
        a[2] -= 0.2;
        let steps = vec![
            MotionCommand::MoveJoints { goal_rad: a.clone(), speed_fraction: 1.0, profile: ProfileKind::Trapezoidal },
            MotionCommand::MoveJoints {
                goal_rad: home.clone(),
                speed_fraction: 1.0,
                profile: ProfileKind::JerkLimited,
            },
        ];
        let planned: f64 = [(&home, &a, ProfileKind::Trapezoidal), (&a, &home, ProfileKind::JerkLimited)]
            .iter()
            .map(|(s, g, k)| crate::profile::JointMove::parol6(s, g, 1.0, *k).expect("plan").duration_s())
            .sum();
        let t0 = Instant::now();
        let runner = SequenceRunner::start(sim.clone(), "test", steps, false).expect("thread");
        let done = runner.join();
        let took = t0.elapsed().as_secs_f64();
        assert_eq!(done.state, SequenceState::Done, "{done:?}");
        assert_eq!(done.passes, 1);
        // the planned time plus settling and polling, never stalled
        assert!(took >= planned && took < planned + 1.5, "took {took:.3} s for {planned:.3} s of motion");
        let q = sim.state().q.clone();
        assert!(q.iter().zip(&home).all(|(a, b)| (a - b).abs() < 2e-3), "{q:?}");
    }

    #[test]
    fn a_refused_step_fails_the_sequence_with_the_reason() {
        let model = RobotModel::parol6();
        let sim = Arc::new(SimHandle::spawn(model, SimConfig::default()).expect("sim"));
        let mut bad = crate::parol6::standby_rad().to_vec();
        bad[1] = 3.0;
        let steps =
            vec![MotionCommand::MoveJoints { goal_rad: bad, speed_fraction: 1.0, profile: ProfileKind::Trapezoidal }];
        let p = SequenceRunner::start(sim, "bad", steps, false).expect("thread").join();
        match p.state {
            SequenceState::Failed(why) => assert!(why.contains("step 1") && why.contains("joint 2"), "{why}"),
            other => panic!("expected a failure, got {other:?}"),
        }
    }
}
