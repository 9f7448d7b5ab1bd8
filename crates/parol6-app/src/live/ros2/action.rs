//! The `control_msgs/action/FollowJointTrajectory` action server (MoveIt's simple controller
//! manager's `FollowJointTrajectory` controller type), as `rmw_zenoh` carries an action: the
//! services `<name>/_action/send_goal`, `get_result` and `cancel_goal` (queryables with `SS`
//! tokens, answered with the request's sequence number and client GID) and the topics
//! `<name>/_action/status` (transient local) and `_action/feedback` (20 Hz while a goal runs,
//! sent by the publishing thread: [`super::feedback`]).
//!
//! The queryables' callbacks hand each request to the command thread's inbox ([`Incoming`]);
//! there a goal takes exactly the path of a trajectory on `/parol6/joint_trajectory`: the
//! remote-control switch ([`RemoteControl::admit`](crate::live::RemoteControl::admit)), the
//! goal's own checks and [`plan_trajectory`](parol6_core::ros2::plan_trajectory)'s (via
//! [`check_goal`]), the pre-flight, the [`ProgramRunner`](parol6_core::program::runner::ProgramRunner)
//! (`Commands::launch`). A refused goal is answered `accepted: false`, logged to `/events`
//! and `/parol6/trajectory_result`, and kept with status ABORTED and its error code, so that a
//! `get_result` for it tells why (rcl_action would answer STATUS_UNKNOWN). A cancel stops the
//! motion as the server's end does (runner aborted, STOP to the backend), whether or not
//! remote control is on (stopping is always allowed), and is logged.
//!
//! While a goal runs, its `path_tolerance` is checked on every telemetry sample
//! ([`GoalWatch`]: positions and velocities); a joint outside it stops the motion the way a
//! cancel does, and the goal ends ABORTED with `PATH_TOLERANCE_VIOLATED` and the joint and
//! deviation in its `error_string` (logged to `/events`). After the trajectory's end the goal
//! waits up to its `goal_time_tolerance` (0: [`DEFAULT_GOAL_TIME_TOLERANCE_S`]) for every joint
//! to be within its `goal_tolerance` of the last point, at rest, else it ends with
//! `GOAL_TOLERANCE_VIOLATED`.
//!
//! [`DEFAULT_GOAL_TIME_TOLERANCE_S`]: parol6_core::ros2::tolerance::DEFAULT_GOAL_TIME_TOLERANCE_S

use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::atomic::Ordering;

use crossbeam_channel::{Sender, TrySendError};
use parol6_core::program::runner::RunState;
use parol6_core::ros2::action::{
    self as fjt, ActionNames, CancelGoalRequest, CancelGoalResponse, FollowJointTrajectoryResult, GetResultRequest,
    GetResultResponse, GoalInfo, GoalStatus, GoalStatusArray, SendGoalRequest, SendGoalResponse, Uuid, cancel, status,
};
use parol6_core::ros2::cdr::{self, MAX_MESSAGE_BYTES};
use parol6_core::ros2::goal::{Tolerances, check_goal};
use parol6_core::ros2::graph::Qos;
use parol6_core::ros2::msgs::Time;
use parol6_core::ros2::tolerance::{GoalEnd, JointMotion, goal_end};
use serde::Serialize;
use zenoh::query::{Query, Queryable};

use super::commands::{Active, CommandCounters, Commands, Incoming, Refusal};
use super::feedback::GoalWatch;
use super::node::{Node, Publisher, now_unix_ns, reply};

/// Goals remembered for `get_result` and the status topic (the oldest finished ones go first).
pub const MAX_GOALS: usize = 64;
/// `get_result` requests waiting for a running goal; more are answered at once with its status.
pub const MAX_WAITING: usize = 64;

/// A goal being run: what it is checked against.
#[derive(Debug, Clone)]
pub struct GoalRun {
    /// The goal.
    pub info: GoalInfo,
    /// Where the arm must end, rad.
    pub final_q: Vec<f64>,
    /// Its path and goal tolerances.
    pub tolerances: Tolerances,
    /// Why it is aborted (control_msgs' error code and the reason), once it is.
    pub aborted: Option<(i32, String)>,
}

struct Record {
    info: GoalInfo,
    status: i8,
    result: FollowJointTrajectoryResult,
}

/// The command thread's view of the action: its goals, waiting `get_result`s and status topic.
pub struct ActionState {
    /// The action's name, e.g. `/parol6_arm_controller/follow_joint_trajectory`.
    pub name: String,
    status: Publisher,
    goals: VecDeque<Record>,
    waiting: Vec<(Uuid, Query)>,
    /// The running goal as the publishing thread checks it and sends its feedback.
    pub watch: Arc<GoalWatch>,
}

/// The action's Zenoh entities, kept alive by the server.
pub struct ActionEndpoints {
    /// The three services.
    pub queryables: Vec<Queryable<()>>,
}

/// Declares the action `name` on `node`: the three services feed `tx`; the `_action/feedback`
/// publisher is for the publishing thread.
pub fn declare(
    node: &mut Node,
    name: &str,
    tx: &Sender<Incoming>,
    counters: &Arc<CommandCounters>,
) -> Result<(ActionEndpoints, ActionState, Publisher), String> {
    let names = ActionNames::of(name);
    let forward = |wrap: fn(Query) -> Incoming| {
        let (tx, counters) = (tx.clone(), Arc::clone(counters));
        move |query: Query| {
            if let Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) = tx.try_send(wrap(query)) {
                counters.dropped.fetch_add(1, Ordering::Relaxed);
            }
        }
    };
    let queryables = vec![
        node.service(&names.send_goal, &fjt::SEND_GOAL, forward(Incoming::Goal))?,
        node.service(&names.get_result, &fjt::GET_RESULT, forward(Incoming::GetResult))?,
        node.service(&names.cancel_goal, &fjt::CANCEL_GOAL, forward(Incoming::Cancel))?,
    ];
    let feedback = node.publisher(&names.feedback, &fjt::FEEDBACK_MESSAGE, Qos::reliable(10))?;
    let status = node.publisher(&names.status, &fjt::GOAL_STATUS_ARRAY, Qos::LATCHED)?;
    let name = format!("/{}", name.trim_matches('/'));
    Ok((
        ActionEndpoints { queryables },
        ActionState { name, status, goals: VecDeque::new(), waiting: Vec::new(), watch: Arc::default() },
        feedback,
    ))
}

/// The request's CDR payload (a size cap before it is copied).
fn payload(query: &Query) -> Result<Vec<u8>, String> {
    let Some(p) = query.payload() else { return Err("the request has no payload".into()) };
    if p.len() > MAX_MESSAGE_BYTES {
        return Err(format!("the request is {} bytes; at most {MAX_MESSAGE_BYTES} are accepted", p.len()));
    }
    Ok(p.to_bytes().into_owned())
}

fn answer<T: Serialize>(query: &Query, msg: &T) {
    if let Err(e) = cdr::encode(msg).map_err(|e| e.to_string()).and_then(|p| reply(query, p)) {
        tracing::warn!("ROS 2 action: {e}");
    }
}

fn now_time() -> Time {
    Time::from_unix_ns(now_unix_ns())
}

impl ActionState {
    fn source(&self) -> String {
        format!("ros2 {}", self.name)
    }

    fn find(&mut self, id: &Uuid) -> Option<&mut Record> {
        self.goals.iter_mut().find(|r| r.info.goal_id == *id)
    }

    fn remember(&mut self, info: GoalInfo, status: i8, result: FollowJointTrajectoryResult) {
        if self.goals.len() >= MAX_GOALS
            && let Some(i) = self.goals.iter().position(|r| r.status >= status::SUCCEEDED)
        {
            self.goals.remove(i);
        }
        self.goals.push_back(Record { info, status, result });
        self.publish_status();
    }

    fn set(&mut self, id: &Uuid, status: i8, result: Option<FollowJointTrajectoryResult>) {
        if let Some(r) = self.find(id) {
            r.status = status;
            if let Some(result) = result {
                r.result = result;
            }
        }
        self.publish_status();
    }

    fn publish_status(&self) {
        let list = GoalStatusArray {
            status_list: self.goals.iter().map(|r| GoalStatus { goal_info: r.info, status: r.status }).collect(),
        };
        if let Err(e) = cdr::encode(&list).map_err(|e| e.to_string()).and_then(|p| self.status.put(p)) {
            tracing::warn!("ROS 2 action status: {e}");
        }
    }

    /// Answers the `get_result`s waiting for `id`, now that it has ended.
    fn release(&mut self, id: &Uuid) {
        let Some(r) = self.goals.iter().find(|r| r.info.goal_id == *id) else { return };
        let response = GetResultResponse { status: r.status, result: r.result.clone() };
        let (done, rest): (Vec<_>, Vec<_>) = std::mem::take(&mut self.waiting).into_iter().partition(|(g, _)| g == id);
        self.waiting = rest;
        for (_, query) in done {
            answer(&query, &response);
        }
    }
}

impl Commands {
    /// A `send_goal` request: accepted and started, or refused with a logged reason.
    pub(super) fn send_goal(&self, st: &mut ActionState, id: u64, query: Query, busy: bool) -> Option<Active> {
        let source = st.source();
        let decoded = payload(&query)
            .and_then(|p| cdr::decode::<SendGoalRequest>(&p).map_err(|e| format!("malformed SendGoal: {e}")));
        let what = match &decoded {
            Ok(r) => format!("goal {} ({} points)", r.goal_id.hex(), r.goal.trajectory.points.len()),
            Err(_) => format!("goal request {id}"),
        };
        let stamp = now_time();
        let reject = |st: &mut ActionState, goal: Option<Uuid>, code: i32, reason: String, admitted: bool| {
            if admitted {
                self.remote.outcome(&source, &what, false, &reason);
            }
            self.refused(id, &reason, None);
            if let Some(goal_id) = goal
                && st.find(&goal_id).is_none()
            {
                let result = FollowJointTrajectoryResult { error_code: code, error_string: reason };
                st.remember(GoalInfo { goal_id, stamp }, status::ABORTED, result);
            }
            answer(&query, &SendGoalResponse { accepted: false, stamp });
            None
        };
        let goal_id = decoded.as_ref().ok().map(|r| r.goal_id);
        if let Err(refusal) = self.remote.admit(&source, &what) {
            return reject(st, goal_id, fjt::INVALID_GOAL, refusal.to_string(), false);
        }
        let req = match decoded {
            Ok(r) => r,
            Err(e) => return reject(st, None, fjt::INVALID_GOAL, e, true),
        };
        if st.find(&req.goal_id).is_some() {
            return reject(
                st,
                None,
                fjt::INVALID_GOAL,
                format!("goal id {} was already sent", req.goal_id.hex()),
                true,
            );
        }
        let started = self.launch(busy, |q| {
            check_goal(&self.model, &req.goal, q, now_unix_ns())
                .map(|g| (g.plan, (g.final_q, g.tolerances)))
                .map_err(|e| Refusal { code: e.error_code, reason: e.message })
        });
        let (runner, plan, (final_q, tolerances)) = match started {
            Ok(s) => s,
            Err(r) => return reject(st, Some(req.goal_id), r.code, r.reason, true),
        };
        let info = GoalInfo { goal_id: req.goal_id, stamp };
        answer(&query, &SendGoalResponse { accepted: true, stamp });
        st.remember(info, status::EXECUTING, FollowJointTrajectoryResult::default());
        st.watch.start(req.goal_id, tolerances.path.clone());
        let goal = GoalRun { info, final_q, tolerances, aborted: None };
        Some(self.running(id, what, &source, runner, &plan, Some(goal)))
    }

    /// A `get_result` request: answered now for an ended or unknown goal, else when it ends.
    pub(super) fn get_result(&self, st: &mut ActionState, query: Query) {
        let req = match payload(&query).and_then(|p| cdr::decode::<GetResultRequest>(&p).map_err(|e| e.to_string())) {
            Ok(r) => r,
            Err(e) => {
                tracing::info!("ROS 2 action: malformed GetResult request: {e}");
                let result = FollowJointTrajectoryResult { error_code: fjt::INVALID_GOAL, error_string: e };
                return answer(&query, &GetResultResponse { status: status::UNKNOWN, result });
            }
        };
        let waiting = st.waiting.len();
        match st.find(&req.goal_id) {
            Some(r) if r.status < status::SUCCEEDED && waiting < MAX_WAITING => st.waiting.push((req.goal_id, query)),
            Some(r) => answer(&query, &GetResultResponse { status: r.status, result: r.result.clone() }),
            None => answer(&query, &GetResultResponse { status: status::UNKNOWN, result: Default::default() }),
        }
    }

    /// A `cancel_goal` request: the running goal (by id, or every goal with a zero id) stops.
    pub(super) fn cancel(&self, st: &mut ActionState, query: Query, active: Option<&Active>) {
        let source = st.source();
        let req = match payload(&query).and_then(|p| cdr::decode::<CancelGoalRequest>(&p).map_err(|e| e.to_string())) {
            Ok(r) => r,
            Err(e) => {
                self.remote.outcome(&source, "cancel", false, &format!("malformed CancelGoal: {e}"));
                return answer(
                    &query,
                    &CancelGoalResponse { return_code: cancel::ERROR_REJECTED, goals_canceling: vec![] },
                );
            }
        };
        let wanted = req.goal_info.goal_id;
        let all = wanted == Uuid::default();
        let what = if all { "cancel of every goal".to_string() } else { format!("cancel of goal {}", wanted.hex()) };
        let running = active.and_then(|a| match &a.goal {
            Some(g) if all || g.info.goal_id == wanted => Some((g.info, a)),
            _ => None,
        });
        let response = match running {
            Some((info, a)) => {
                self.stop_motion(a);
                st.set(&info.goal_id, status::CANCELING, None);
                self.remote.outcome(&source, &what, true, "stopping the motion (STOP)");
                CancelGoalResponse { return_code: cancel::ERROR_NONE, goals_canceling: vec![info] }
            }
            None => {
                let code = match st.find(&wanted) {
                    Some(_) => cancel::ERROR_GOAL_TERMINATED,
                    None if all => cancel::ERROR_NONE,
                    None => cancel::ERROR_UNKNOWN_GOAL_ID,
                };
                self.remote.outcome(&source, &what, true, "no such goal running");
                CancelGoalResponse { return_code: code, goals_canceling: vec![] }
            }
        };
        answer(&query, &response);
    }

    /// A joint of the running goal outside its `path_tolerance` (seen by the publishing
    /// thread): the motion stops as on a cancel, and the goal is to end aborted.
    pub(super) fn check_path(&self, st: &ActionState, a: &mut Active) {
        let Some(g) = a.goal.as_mut().filter(|g| g.aborted.is_none()) else { return };
        let Some(v) = st.watch.violation() else { return };
        let names: Vec<&str> = self.model.joints.iter().map(|j| j.name.as_str()).collect();
        let why = format!("path_tolerance violated: {}", v.describe(&names, "path_tolerance", "desired"));
        g.aborted = Some((fjt::PATH_TOLERANCE_VIOLATED, why.clone()));
        self.stop_motion(a);
        self.remote.outcome(&a.source, &a.what, true, &format!("stopping the motion (STOP): {why}"));
    }

    /// True while the running goal's trajectory has ended and it waits for its goal tolerance
    /// (up to its goal time tolerance after the end); when the wait is over, a miss is kept as
    /// the goal's abort.
    pub(super) fn goal_settling(&self, st: &ActionState, a: &mut Active) -> bool {
        let Some(g) = a.goal.as_mut().filter(|g| g.aborted.is_none()) else { return false };
        let canceling = st.goals.iter().any(|r| r.info.goal_id == g.info.goal_id && r.status == status::CANCELING);
        let p = a.runner.progress();
        if canceling || p.state != RunState::Done {
            return false;
        }
        st.watch.trajectory_ended();
        let state = self.backend.state();
        let since_end_s = state.time_s - p.clock_s.1;
        let t = &g.tolerances;
        let actual = JointMotion { q_rad: &state.q, qd_rad_s: &state.qd };
        match goal_end(&t.goal, &g.final_q, actual, since_end_s, t.goal_time_s) {
            GoalEnd::Reached => false,
            GoalEnd::Waiting => true,
            GoalEnd::Violated(v) => {
                let names: Vec<&str> = self.model.joints.iter().map(|j| j.name.as_str()).collect();
                let why = format!(
                    "goal_tolerance violated {since_end_s:.3} s after the trajectory's end (goal_time_tolerance {:.3} s): {}",
                    t.goal_time_s,
                    v.describe(&names, "goal_tolerance", "goal")
                );
                g.aborted = Some((fjt::GOAL_TOLERANCE_VIOLATED, why));
                false
            }
        }
    }

    /// A goal's run ended: its status and result (an abort decided while it ran, or how the
    /// run ended).
    pub(super) fn goal_ended(&self, st: &mut ActionState, goal: &GoalRun, ended: &RunState) {
        let id = goal.info.goal_id;
        st.watch.end();
        let canceling = st.find(&id).is_some_and(|r| r.status == status::CANCELING);
        let result = |error_code, error_string: String| FollowJointTrajectoryResult { error_code, error_string };
        let (code, outcome) = match ended {
            _ if canceling => (status::CANCELED, result(fjt::SUCCESSFUL, "canceled: the motion was stopped".into())),
            _ if goal.aborted.is_some() => {
                let (code, why) = goal.aborted.clone().unwrap_or_default();
                (status::ABORTED, result(code, why))
            }
            RunState::Done => {
                // the last look (the wait may have been cut short by the server's end)
                let (t, state) = (&goal.tolerances, self.backend.state());
                let actual = JointMotion { q_rad: &state.q, qd_rad_s: &state.qd };
                match goal_end(&t.goal, &goal.final_q, actual, f64::INFINITY, t.goal_time_s) {
                    GoalEnd::Violated(v) => {
                        let names: Vec<&str> = self.model.joints.iter().map(|j| j.name.as_str()).collect();
                        let why = format!("goal_tolerance violated: {}", v.describe(&names, "goal_tolerance", "goal"));
                        (status::ABORTED, result(fjt::GOAL_TOLERANCE_VIOLATED, why))
                    }
                    _ => (status::SUCCEEDED, result(fjt::SUCCESSFUL, String::new())),
                }
            }
            RunState::Failed(why) => (status::ABORTED, result(fjt::PATH_TOLERANCE_VIOLATED, why.clone())),
            RunState::Stopped => (status::ABORTED, result(fjt::PATH_TOLERANCE_VIOLATED, "stopped on the PC".into())),
            _ => (status::ABORTED, result(fjt::PATH_TOLERANCE_VIOLATED, "the server stopped".into())),
        };
        st.set(&id, code, Some(outcome));
        st.release(&id);
    }
}
