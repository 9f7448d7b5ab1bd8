//! Trajectories from ROS 2: the subscription's callback hands each payload to a bounded inbox
//! (`try_send`: a full inbox drops and counts), and this thread decodes it, asks the
//! remote-control switch ([`RemoteControl::admit`]: refused and logged unless remote control
//! is on), checks it and runs the pre-flight ([`plan_trajectory`]), then runs it on the backend
//! with the [`ProgramRunner`] (as `parol6 program run` does). Every step's verdict goes to
//! `/events` and, as one JSON object in a `std_msgs/msg/String`, to
//! `/parol6/trajectory_result`: `{"id", "state": "refused" | "running" | "done" | "stopped" |
//! "failed", "reason", "points", "duration_s", "warnings"}`.
//!
//! One trajectory runs at a time: another that arrives meanwhile is refused. STOP and the
//! dead-man on the PC go to the backend directly and win over a running trajectory (the runner
//! then ends as stopped or failed, and that is published); a backend that refuses motion
//! (E-stop, link lost, not homed) refuses the trajectory before it starts.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use crossbeam_channel::{Receiver, RecvTimeoutError, Sender, TrySendError};
use parol6_core::RobotModel;
use parol6_core::motion::{MotionCommand, RobotBackend};
use parol6_core::program::runner::{ProgramRunner, RunOptions, RunState};
use parol6_core::ros2::action::INVALID_GOAL;
use parol6_core::ros2::cdr::{self, MAX_MESSAGE_BYTES};
use parol6_core::ros2::msgs::{JointTrajectory, StringMsg};
use parol6_core::ros2::{TOPIC_JOINT_TRAJECTORY, TrajectoryPlan, plan_trajectory};
use serde_json::json;

use super::action::{ActionState, GoalRun};
use super::node::Publisher;
use crate::live::RemoteControl;

/// Payloads the inbox holds before it drops.
pub const INBOX_CAPACITY: usize = 8;
/// How often a running trajectory's progress is looked at.
const POLL: Duration = Duration::from_millis(20);

/// Who sends the commands, as `/events` names them.
pub fn source() -> String {
    format!("ros2 {TOPIC_JOINT_TRAJECTORY}")
}

/// A payload as the subscription's callback hands it over, or a request to the action's
/// services ([`super::action`]).
#[derive(Debug)]
pub enum Incoming {
    /// The payload's bytes.
    Payload(Vec<u8>),
    /// A payload over [`MAX_MESSAGE_BYTES`] (not copied), its size.
    TooLarge(usize),
    /// A `send_goal` request.
    Goal(zenoh::query::Query),
    /// A `get_result` request.
    GetResult(zenoh::query::Query),
    /// A `cancel_goal` request.
    Cancel(zenoh::query::Query),
}

/// The command thread's counters.
#[derive(Debug, Default)]
pub struct CommandCounters {
    /// Trajectories received.
    pub received: AtomicU64,
    /// Refused (remote control off, malformed, invalid, pre-flight, busy, backend).
    pub refused: AtomicU64,
    /// Started on the backend.
    pub started: AtomicU64,
    /// Ran to their end.
    pub done: AtomicU64,
    /// Dropped because the inbox was full.
    pub dropped: AtomicU64,
}

/// The subscription's callback: copies the payload into the inbox, never blocking.
pub fn on_sample(tx: Sender<Incoming>, counters: Arc<CommandCounters>) -> impl Fn(zenoh::sample::Sample) {
    move |sample| {
        let len = sample.payload().len();
        let item = if len > MAX_MESSAGE_BYTES {
            Incoming::TooLarge(len)
        } else {
            Incoming::Payload(sample.payload().to_bytes().into_owned())
        };
        if let Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) = tx.try_send(item) {
            counters.dropped.fetch_add(1, Ordering::Relaxed);
        }
    }
}

/// What the thread works with.
pub struct Commands {
    /// The robot.
    pub model: RobotModel,
    /// Where trajectories run.
    pub backend: Arc<dyn RobotBackend>,
    /// The remote-control switch (and `/events`).
    pub remote: RemoteControl,
    /// `/parol6/trajectory_result`.
    pub result: Publisher,
    /// Counters.
    pub counters: Arc<CommandCounters>,
    /// The `FollowJointTrajectory` action's goals and status topic.
    pub action: Option<ActionState>,
}

/// A trajectory running on the backend.
pub(super) struct Active {
    pub(super) id: u64,
    pub(super) what: String,
    /// Who sent it, as `/events` names them.
    pub(super) source: String,
    pub(super) runner: ProgramRunner,
    pub(super) points: usize,
    pub(super) duration_s: f64,
    /// The action goal it runs, if it came as one.
    pub(super) goal: Option<GoalRun>,
}

/// Why a checked trajectory is not started: control_msgs' error code and the reason.
#[derive(Debug)]
pub(super) struct Refusal {
    pub(super) code: i32,
    pub(super) reason: String,
}

/// Runs until `stop` is set; a trajectory still running then is stopped.
pub fn run(mut c: Commands, rx: Receiver<Incoming>, stop: Arc<AtomicBool>) {
    let mut action = c.action.take();
    let mut active: Option<Active> = None;
    while !stop.load(Ordering::Acquire) {
        match rx.recv_timeout(POLL) {
            Ok(Incoming::GetResult(query)) => match action.as_mut() {
                Some(st) => c.get_result(st, query),
                None => tracing::warn!("ROS 2: a get_result request without the action"),
            },
            Ok(Incoming::Cancel(query)) => match action.as_mut() {
                Some(st) => c.cancel(st, query, active.as_ref()),
                None => tracing::warn!("ROS 2: a cancel_goal request without the action"),
            },
            Ok(Incoming::Goal(query)) => {
                let id = c.counters.received.fetch_add(1, Ordering::Relaxed) + 1;
                match action.as_mut() {
                    Some(st) => {
                        if let Some(a) = c.send_goal(st, id, query, active.is_some()) {
                            active = Some(a);
                        }
                    }
                    None => tracing::warn!("ROS 2: a send_goal request without the action"),
                }
            }
            Ok(item) => {
                let id = c.counters.received.fetch_add(1, Ordering::Relaxed) + 1;
                if let Some(a) = c.take(id, item, active.is_some()) {
                    active = Some(a);
                }
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        if let (Some(a), Some(st)) = (active.as_mut(), action.as_ref()) {
            c.check_path(st, a);
        }
        let settling = |a: &mut Active| action.as_ref().is_some_and(|st| c.goal_settling(st, a));
        if active.as_mut().is_some_and(|a| a.runner.is_finished() && !settling(a))
            && let Some(a) = active.take()
        {
            c.finish(a, action.as_mut());
        }
    }
    if let Some(a) = active {
        if !a.runner.is_finished() {
            c.stop_motion(&a);
        }
        c.finish(a, action.as_mut());
    }
}

impl Commands {
    /// Handles one payload; the trajectory started, if it was.
    fn take(&self, id: u64, item: Incoming, busy: bool) -> Option<Active> {
        let source = source();
        let decoded = match item {
            Incoming::Payload(bytes) => cdr::decode::<JointTrajectory>(&bytes).map_err(|e| e.to_string()),
            Incoming::TooLarge(len) => {
                Err(format!("the message is {len} bytes; at most {MAX_MESSAGE_BYTES} are accepted"))
            }
            Incoming::Goal(_) | Incoming::GetResult(_) | Incoming::Cancel(_) => {
                Err("an action request is not a JointTrajectory".to_string())
            }
        };
        let what = match &decoded {
            Ok(t) => format!("trajectory {id} ({} points)", t.points.len()),
            Err(_) => format!("trajectory {id}"),
        };
        if let Err(refusal) = self.remote.admit(&source, &what) {
            self.refused(id, &refusal.to_string(), None);
            return None;
        }
        let refuse = |reason: String, points: Option<usize>| {
            self.remote.outcome(&source, &what, false, &reason);
            self.refused(id, &reason, points);
            None
        };
        let traj = match decoded {
            Ok(t) => t,
            Err(e) => return refuse(format!("malformed JointTrajectory: {e}"), None),
        };
        let points = Some(traj.points.len());
        let started = self.launch(busy, |q| {
            plan_trajectory(&self.model, &traj, q)
                .map(|p| (p, ()))
                .map_err(|e| Refusal { code: INVALID_GOAL, reason: e.to_string() })
        });
        match started {
            Ok((runner, plan, ())) => Some(self.running(id, what, &source, runner, &plan, None)),
            Err(r) => refuse(r.reason, points),
        }
    }

    /// The one way a checked trajectory starts, from the topic or the action: refused while
    /// another runs, while the backend refuses motion or the arm moves; else `plan` (given the
    /// commanded position, rad) checks and pre-flights it, and the program runner starts it.
    pub(super) fn launch<X>(
        &self,
        busy: bool,
        plan: impl FnOnce(&[f64]) -> Result<(TrajectoryPlan, X), Refusal>,
    ) -> Result<(ProgramRunner, TrajectoryPlan, X), Refusal> {
        let refuse = |reason: String| Refusal { code: INVALID_GOAL, reason };
        if busy {
            return Err(refuse("another trajectory is running".into()));
        }
        let state = self.backend.state();
        if let Some(why) = &state.blocked {
            return Err(refuse(format!("the backend does not accept motion: {why}")));
        }
        if state.moving {
            return Err(refuse("the arm is moving".into()));
        }
        let (plan, extra) = plan(&state.commanded.q)?;
        let runner = ProgramRunner::start(
            Arc::clone(&self.backend),
            self.model.clone(),
            plan.program.clone(),
            RunOptions::default(),
        )
        .map_err(|e| refuse(format!("cannot start the program thread: {e}")))?;
        self.counters.started.fetch_add(1, Ordering::Relaxed);
        Ok((runner, plan, extra))
    }

    /// Logs and publishes a started trajectory.
    pub(super) fn running(
        &self,
        id: u64,
        what: String,
        source: &str,
        runner: ProgramRunner,
        plan: &TrajectoryPlan,
        goal: Option<GoalRun>,
    ) -> Active {
        let warnings: Vec<String> = plan.report.issues.iter().map(|i| i.message.clone()).collect();
        self.remote.outcome(source, &what, true, &format!("running, {:.2} s planned", plan.report.duration_s));
        self.publish(json!({
            "id": id, "state": "running", "reason": null, "points": plan.points,
            "duration_s": plan.duration_s, "warnings": warnings,
        }));
        Active { id, what, source: source.to_string(), runner, points: plan.points, duration_s: plan.duration_s, goal }
    }

    /// Stops a running trajectory the way the server's end does: the runner aborts and the
    /// backend gets STOP.
    pub(super) fn stop_motion(&self, a: &Active) {
        a.runner.abort();
        if let Err(e) = self.backend.send(MotionCommand::Stop) {
            tracing::warn!("ROS 2: STOP of the running trajectory: {e}");
        }
    }

    /// Publishes how a run ended and logs it.
    fn finish(&self, a: Active, action: Option<&mut ActionState>) {
        let p = a.runner.join();
        if let (Some(goal), Some(st)) = (&a.goal, action) {
            self.goal_ended(st, goal, &p.state);
        }
        let aborted = a.goal.as_ref().and_then(|g| g.aborted.clone());
        let (state, reason) = match p.state {
            _ if aborted.is_some() => ("failed", aborted.map(|(_, why)| why)),
            RunState::Done => ("done", None),
            RunState::Stopped => ("stopped", Some("stopped on the PC".to_string())),
            RunState::Failed(why) => ("failed", Some(why)),
            _ => ("stopped", Some("the server stopped".to_string())),
        };
        if state == "done" {
            self.counters.done.fetch_add(1, Ordering::Relaxed);
        }
        let detail = match &reason {
            Some(why) => format!("{state}: {why}"),
            None => state.to_string(),
        };
        self.remote.outcome(&a.source, &a.what, true, &detail);
        self.publish(json!({
            "id": a.id, "state": state, "reason": reason, "points": a.points,
            "duration_s": a.duration_s, "warnings": [],
        }));
    }

    pub(super) fn refused(&self, id: u64, reason: &str, points: Option<usize>) {
        self.counters.refused.fetch_add(1, Ordering::Relaxed);
        tracing::info!("ROS 2 trajectory {id} refused: {reason}");
        self.publish(json!({
            "id": id, "state": "refused", "reason": reason, "points": points, "duration_s": null, "warnings": [],
        }));
    }

    fn publish(&self, result: serde_json::Value) {
        let sent = cdr::encode(&StringMsg { data: result.to_string() })
            .map_err(|e| e.to_string())
            .and_then(|payload| self.result.put(payload));
        if let Err(e) = sent {
            tracing::warn!("ROS 2: the trajectory result: {e}");
        }
    }
}
