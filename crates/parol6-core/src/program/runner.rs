//! [`ProgramRunner`]: runs a [`Program`] on any [`RobotBackend`] on its own thread, with
//! pause, resume, single step and stop, and publishes its progress (step n of m, time left).
//!
//! How it keeps the same meaning on every backend: the program is compiled once, from the
//! commanded position the backend holds at the start, into joint trajectories at the 1 kHz
//! control rate; each is *scheduled* on the backend's motion clock at the instant the previous
//! one ends (dwells add their time), [`LOOKAHEAD`] steps and [`AHEAD_MIN_S`] of motion clock
//! ahead (at most [`MAX_AHEAD`] steps), so the commanded trajectory does not depend on when this
//! thread wakes. I/O steps are sent when the motion clock reaches them (at most one poll late,
//! [`POLL`]); a wait for an input re-starts the schedule when the input arrives.
//!
//! A step handed over after its time (this thread lost the processor, or a headless simulation
//! runs many times faster than the wall clock) is never refused: the backend's schedule slips
//! as a whole ([`crate::motion::ScheduleState`]), every trajectory still starts exactly where
//! the one before it ends, and this thread reads the slip from the backend's state and keeps
//! its I/O, dwells and progress on the slipped schedule. It only trusts a state that has seen
//! every step it submitted.
//!
//! Pause slows the current trajectory to a stop on its path ([`MotionCommand::Pause`]); resume
//! finishes it and schedules the rest again; where the operator moved the arm while the run
//! waited, resume first moves it back to where the next step starts. Stop pauses, then holds. A refused step, a backend
//! that stops accepting motion (link loss, E-stop, disabled) or a failed wait ends the run with
//! the reason; the backend holds the arm.

use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use arc_swap::ArcSwap;
use crossbeam_channel::{Receiver, Sender, TryRecvError};

pub use types::{RunOptions, RunProgress, RunState, RunnerControl};

use super::Program;
use super::check::{CheckOptions, CheckProgress, CheckedProgram, check_shared};
use super::compile::{CompileOptions, CompiledStep, StepAction, compile};
use crate::model::RobotModel;
use crate::motion::{MotionCommand, PlannerMode, RobotBackend, RobotState};

/// How often the runner looks at the backend's state (wall clock). Motion never waits for it
/// (steps are scheduled ahead on the motion clock); I/O steps and the progress readout do, so
/// an output switches at most this late. At 20 ms the runner uses under 1 % of a core
/// (`parol6 bench motion`); at 2 ms it used about 5 %.
pub const POLL: Duration = Duration::from_millis(20);
/// Longest wait for the arm to come to rest between the passes of a looping run.
pub const SETTLE_BETWEEN_PASSES: Duration = Duration::from_secs(10);
/// The time-left readout is published when it changed by this much, s.
const PROGRESS_RESOLUTION_S: f64 = 0.1;
/// At least this many steps are scheduled ahead of the motion clock (when the program has them).
pub const LOOKAHEAD: usize = 8;
/// Steps are also scheduled until they reach this far ahead of the motion clock, s, or
/// [`AHEAD_POLLS`] polls' worth of motion clock where it runs faster than the wall clock.
pub const AHEAD_MIN_S: f64 = 1.0;
/// Polls' worth of motion clock scheduled ahead (a headless simulation advances 0.4 s a poll).
pub const AHEAD_POLLS: f64 = 5.0;
/// At most this many steps are scheduled ahead (the robot session's queue holds 256 requests).
pub const MAX_AHEAD: usize = 64;
/// The first step starts this long after the runner schedules it, s of motion clock. A step
/// that reaches the backend after its time starts late and the schedule slips (with both cores
/// of a 2-core PC busy the runner's thread lost 37–87 ms between reading the clock and
/// scheduling).
pub const LEAD_S: f64 = 0.25;

/// Grid of the instants a schedule starts at, s: the robot's 10 ms control period, so the
/// same program gives samples at the same offsets on every backend.
pub const START_GRID_S: f64 = 0.01;

/// The first instant on the start grid at least [`LEAD_S`] after `now_s`.
fn start_clock(now_s: f64) -> f64 {
    ((now_s + LEAD_S) / START_GRID_S).ceil() * START_GRID_S
}

/// The backend's motion clock on the runner's schedule: its time less the schedule's delay.
fn schedule_clock(s: &RobotState) -> f64 {
    s.time_s - s.schedule.delay_s
}

/// Planned time of the steps after `index`, s.
fn left_after(compiled: &[CompiledStep], index: usize) -> f64 {
    compiled.get(index + 1..).map_or(0.0, |rest| rest.iter().map(CompiledStep::duration_s).sum())
}

/// A program running on its own thread. Dropping it stops the run (the arm holds).
pub struct ProgramRunner {
    progress: Arc<ArcSwap<RunProgress>>,
    abort: Arc<AtomicBool>,
    control: Sender<RunnerControl>,
    join: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for ProgramRunner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ProgramRunner").field("progress", &self.progress()).finish()
    }
}

impl ProgramRunner {
    /// Starts running `program` on `backend` (whose robot is `model`). The thread checks and
    /// compiles first; a refusal shows as [`RunState::Failed`].
    pub fn start(
        backend: Arc<dyn RobotBackend>,
        model: RobotModel,
        program: Program,
        opts: RunOptions,
    ) -> std::io::Result<Self> {
        Self::start_shared(backend, model, Arc::new(program), None, opts)
    }

    /// Starts running a program already checked (`checked.program`): the thread reuses the
    /// check when the arm starts from the joints it was checked from (within
    /// [`RECHECK_TOLERANCE_RAD`](super::check::RECHECK_TOLERANCE_RAD)) at the same speed
    /// override, and checks again otherwise; then it compiles at the control rate.
    pub fn start_checked(
        backend: Arc<dyn RobotBackend>,
        model: RobotModel,
        checked: Arc<CheckedProgram>,
        opts: RunOptions,
    ) -> std::io::Result<Self> {
        let program = Arc::clone(&checked.program);
        Self::start_shared(backend, model, program, Some(checked), opts)
    }

    fn start_shared(
        backend: Arc<dyn RobotBackend>,
        model: RobotModel,
        program: Arc<Program>,
        checked: Option<Arc<CheckedProgram>>,
        opts: RunOptions,
    ) -> std::io::Result<Self> {
        let progress = Arc::new(ArcSwap::from_pointee(RunProgress {
            name: program.name.clone(),
            step: 0,
            steps: program.steps.len(),
            state: RunState::Preparing,
            waiting_for: None,
            time_left_s: 0.0,
            planned_s: 0.0,
            steps_done: 0,
            max_tracking_error_rad: 0.0,
            clock_s: (0.0, 0.0),
            passes: 0,
            runner_cpu_s: None,
            schedule_slip_s: 0.0,
            stop_failed: None,
            preflights_run: 0,
        }));
        let (tx, rx) = crossbeam_channel::bounded(16);
        let p = Arc::clone(&progress);
        let abort = Arc::new(AtomicBool::new(false));
        let a = Arc::clone(&abort);
        let join = std::thread::Builder::new().name("parol6-program".into()).spawn(move || {
            let schedule = backend.state().schedule;
            let mut run = Run {
                backend: backend.as_ref(),
                progress: &p,
                control: &rx,
                abort: &a,
                single: false,
                optional_pauses: opts.optional_pauses,
                exec_cpu_ns: None,
                last_end_s: 0.0,
                received_base: schedule.received,
                submitted: 0,
                delay_s: schedule.delay_s,
                checked,
                start_q: Vec::new(),
            };
            run.run(&model, &program, opts);
        })?;
        Ok(Self { progress, abort, control: tx, join: Some(join) })
    }

    /// The latest progress.
    pub fn progress(&self) -> RunProgress {
        self.progress.load().as_ref().clone()
    }

    /// Sends an operator control (ignored once the run has ended).
    pub fn control(&self, c: RunnerControl) {
        let _ = self.control.try_send(c);
    }

    /// Ends the run at once without waiting (the STOP button): the thread schedules nothing
    /// more and ends within one poll; the caller sends [`MotionCommand::Stop`] to the backend,
    /// which drops what was scheduled. A step the thread submits while this happens is
    /// followed by its own STOP.
    pub fn abort(&self) {
        self.abort.store(true, Ordering::SeqCst);
    }

    /// True once the run has ended.
    pub fn is_finished(&self) -> bool {
        self.progress.load().state.is_finished()
    }

    /// Waits for the run to end.
    pub fn join(mut self) -> RunProgress {
        if let Some(j) = self.join.take() {
            let _ = j.join();
        }
        self.progress()
    }
}

impl Drop for ProgramRunner {
    fn drop(&mut self) {
        if let Some(j) = self.join.take() {
            let _ = self.control.send(RunnerControl::Stop);
            let _ = j.join();
        }
    }
}

/// Why the run ends early.
enum Halt {
    Stopped,
    /// STOP pressed: the caller holds the arm.
    Aborted,
    /// Refused before anything was sent.
    Refused(String),
    Failed(String),
}

struct Run<'a> {
    backend: &'a dyn RobotBackend,
    progress: &'a ArcSwap<RunProgress>,
    control: &'a Receiver<RunnerControl>,
    abort: &'a AtomicBool,
    single: bool,
    /// Optional pause steps pause the run.
    optional_pauses: bool,
    /// Thread CPU time when the first step was scheduled (planning excluded), ns.
    exec_cpu_ns: Option<u64>,
    /// Motion clock at which the last finished step ended (as scheduled, slip included), s.
    last_end_s: f64,
    /// The backend's count of scheduled commands received before this run submitted any.
    received_base: u64,
    /// Steps this run submitted with a time.
    submitted: u64,
    /// The backend's schedule delay last seen, s.
    delay_s: f64,
    /// The program's check, reused while the arm starts where it was checked from.
    checked: Option<Arc<CheckedProgram>>,
    /// Where the pass under way started (commanded joints), rad.
    start_q: Vec<f64>,
}

/// A step scheduled on the motion clock.
struct Slot {
    index: usize,
    start_s: f64,
    end_s: f64,
}

impl Run<'_> {
    fn publish(&self, f: impl FnOnce(&mut RunProgress)) {
        let mut p = self.progress.load().as_ref().clone();
        f(&mut p);
        self.progress.store(Arc::new(p));
    }

    fn run(&mut self, model: &RobotModel, program: &Arc<Program>, opts: RunOptions) {
        self.single = opts.single_step;
        let mut outcome = self.prepare(model, program, opts).and_then(|compiled| self.execute(&compiled));
        while (opts.looping || program.looping) && outcome.is_ok() && !program.steps.is_empty() {
            self.publish(|p| p.passes += 1);
            outcome = self
                .settle_between_passes()
                .and_then(|()| self.prepare(model, program, opts))
                .and_then(|compiled| self.execute(&compiled));
        }
        // a finished run ends when its last step was scheduled to end (not when this thread
        // noticed); an interrupted one when it stopped
        let end = if outcome.is_ok() { self.last_end_s } else { self.backend.state().time_s };
        let state = match outcome {
            Ok(()) => RunState::Done,
            Err(Halt::Stopped | Halt::Aborted) => RunState::Stopped,
            Err(Halt::Refused(why)) => RunState::Failed(why),
            Err(Halt::Failed(why)) => {
                // hold whatever moves (the backend holds on its own when it blocks motion)
                self.stop_arm("the run failed");
                RunState::Failed(why)
            }
        };
        let cpu =
            self.exec_cpu_ns.zip(crate::process::thread_cpu_time_ns()).map(|(a, b)| b.saturating_sub(a) as f64 * 1e-9);
        self.publish(|p| {
            p.state = state;
            p.runner_cpu_s = cpu;
            p.waiting_for = None;
            p.clock_s.1 = end;
            if p.state == RunState::Done {
                p.time_left_s = 0.0;
                p.steps_done = p.steps;
            }
        });
    }

    /// Refuses to start unless the backend accepts motion, is homed, holds still and the
    /// program passes pre-flight from where the arm is; then compiles at the control rate.
    fn prepare(&self, model: &RobotModel, program: &Arc<Program>, opts: RunOptions) -> Result<Vec<CompiledStep>, Halt> {
        let s = self.backend.state();
        if let Some(b) = &s.blocked {
            return Err(Halt::Refused(format!("the robot does not accept motion: {b}")));
        }
        if !s.homed {
            return Err(Halt::Refused("the robot is not homed: home it before running a program".into()));
        }
        if s.moving || s.mode != PlannerMode::Hold {
            return Err(Halt::Refused("the arm is moving: stop it before running a program".into()));
        }
        let start_q = pausing::hold_position(&s);
        let check_opts = CheckOptions { speed_override: opts.speed_override };
        let reusable = self.checked.as_ref().filter(|c| c.opts == check_opts && c.is_from(&start_q));
        let first_error = match reusable {
            Some(c) => c.first_error(),
            None => {
                self.publish(|p| p.preflights_run += 1);
                let progress = CheckProgress::default();
                check_shared(model, program, &start_q, check_opts, &progress).and_then(|c| c.first_error())
            }
        };
        if let Some(first) = first_error {
            return Err(Halt::Refused(format!("pre-flight: {first}")));
        }
        let compiled = compile(
            model,
            program,
            &start_q,
            CompileOptions { speed_override: opts.speed_override, ..CompileOptions::RUN },
        )
        .map_err(|e| Halt::Refused(e.to_string()))?;
        let planned: f64 = compiled.iter().map(CompiledStep::duration_s).sum();
        self.publish(|p| {
            p.state = RunState::Running;
            p.steps_done = 0;
            p.step = 0;
            p.planned_s = planned;
            p.time_left_s = planned;
        });
        Ok(compiled)
    }

    fn execute(&mut self, compiled: &[CompiledStep]) -> Result<(), Halt> {
        if self.exec_cpu_ns.is_none() {
            self.exec_cpu_ns = crate::process::thread_cpu_time_ns();
        }
        let mut next = 0; // first step not yet scheduled
        let mut slots: VecDeque<Slot> = VecDeque::new();
        let s0 = self.backend.state();
        self.start_q = pausing::hold_position(&s0);
        self.see_delay(&s0);
        let mut clock = start_clock(schedule_clock(&s0));
        let mut refusal = s0.last_refusal.as_ref().map_or(0, |r| r.0);
        let first_s = clock + self.delay_s;
        self.publish(|p| p.clock_s.0 = first_s);
        // motion clock per poll, s (a headless simulation runs faster than the wall clock)
        let mut last_seen = s0.time_s;
        let mut per_poll_s = 0.0_f64;
        // single-step mode: a step has been scheduled; wait for the operator once it is done
        let mut hold_at_boundary = false;
        loop {
            if slots.is_empty() && hold_at_boundary && next < compiled.len() {
                self.idle_until_control()?;
                self.regain(compiled, next)?;
                refusal = self.seen_refusal(refusal);
                hold_at_boundary = false;
                clock = start_clock(schedule_clock(&self.backend.state()));
            }
            // schedule ahead on the motion clock (one step at a time in single-step mode; a
            // wait for an input ends the batch: what follows it starts when the input comes)
            let ahead_until = last_seen - self.delay_s + AHEAD_MIN_S.max(AHEAD_POLLS * per_poll_s);
            while next < compiled.len()
                && !(self.single && hold_at_boundary)
                && (slots.len() < LOOKAHEAD || (slots.len() < MAX_AHEAD && clock < ahead_until))
            {
                let c = &compiled[next];
                // what follows a wait for an input or the operator is scheduled once it ends
                let wait = matches!(c.action, StepAction::WaitInput { .. } | StepAction::Pause { .. });
                if wait && !slots.is_empty() {
                    break;
                }
                if self.abort.load(Ordering::SeqCst) {
                    return Err(Halt::Aborted);
                }
                if let StepAction::Motion(t) = &c.action {
                    self.backend
                        .submit(MotionCommand::Trajectory(Arc::clone(t)), Some(clock))
                        .map_err(|e| Halt::Failed(format!("step {}: {e}", c.steps.start + 1)))?;
                    self.submitted += 1;
                    if self.abort.load(Ordering::SeqCst) {
                        // submitted while the operator pressed STOP: stop it too
                        self.stop_arm("a step submitted while STOP was pressed");
                        return Err(Halt::Aborted);
                    }
                }
                let end = clock + c.duration_s();
                slots.push_back(Slot { index: next, start_s: clock, end_s: end });
                clock = end;
                next += 1;
                hold_at_boundary = self.single;
                if wait {
                    break;
                }
            }
            if slots.is_empty() {
                if next >= compiled.len() {
                    return Ok(());
                }
                continue;
            }
            std::thread::sleep(POLL);
            let s = self.backend.state();
            self.watch(&s, &mut refusal, compiled, &slots)?;
            if self.abort.load(Ordering::SeqCst) {
                return Err(Halt::Aborted);
            }
            per_poll_s = s.time_s - last_seen;
            last_seen = s.time_s;
            if let Some(ctrl) = self.poll_control() {
                if ctrl == RunnerControl::Resume {
                    self.single = false;
                    hold_at_boundary = false;
                    continue;
                }
                // pause, stop and step all bring the arm to a stop on its path first
                let resume_at = self.pause_now(compiled, &mut slots, next)?;
                if ctrl == RunnerControl::Stop {
                    self.stop_arm("stopped while running");
                    return Err(Halt::Stopped);
                }
                if ctrl == RunnerControl::Pause {
                    self.idle_until_control()?;
                    self.regain(compiled, resume_at)?;
                    refusal = self.seen_refusal(refusal);
                    // a step pressed while paused mid-way finishes that step, then waits
                    let midway = self.backend.state().mode == PlannerMode::Paused;
                    next = self.resume_from(compiled, resume_at)?;
                    hold_at_boundary = self.single && midway;
                } else {
                    // step: finish the step under way, then wait at its end
                    let midway = self.backend.state().mode == PlannerMode::Paused;
                    next = self.resume_from(compiled, resume_at)?;
                    self.single = true;
                    hold_at_boundary = midway;
                }
                slots.clear();
                let s = self.backend.state();
                self.see_delay(&s);
                clock = start_clock(schedule_clock(&s));
                continue;
            }
            // the slots are judged on the backend's schedule, from a state that has seen every
            // step submitted (a state from before one arrived knows nothing of its slip)
            if s.schedule.received < self.received_base + self.submitted {
                continue;
            }
            self.see_delay(&s);
            if let Some(rebased) = self.advance_slots(compiled, &mut slots, schedule_clock(&s))? {
                clock = rebased;
                refusal = self.seen_refusal(refusal);
            }
        }
    }

    /// Takes the backend's schedule delay from a state that has seen every submitted step; a
    /// growth is the run's slip (STOP and PAUSE reset the backend's delay to 0).
    fn see_delay(&mut self, s: &RobotState) {
        let d = s.schedule.delay_s;
        if d > self.delay_s {
            let slip = d - self.delay_s;
            self.publish(|p| p.schedule_slip_s += slip);
        }
        self.delay_s = d;
    }

    /// Acts on every slot whose time has come at `now_s` (the backend's clock on the runner's
    /// schedule): sends I/O, waits for inputs and pause steps, retires finished motions and
    /// dwells, publishes the progress. Returns the new schedule start after a wait.
    fn advance_slots(
        &mut self,
        compiled: &[CompiledStep],
        slots: &mut VecDeque<Slot>,
        now_s: f64,
    ) -> Result<Option<f64>, Halt> {
        while let Some(&Slot { index, start_s, end_s }) = slots.front() {
            let c = &compiled[index];
            if now_s < start_s {
                break;
            }
            match &c.action {
                StepAction::Io(cmd) => {
                    self.backend.io(*cmd).map_err(|e| Halt::Failed(format!("step {}: {e}", c.steps.start + 1)))?;
                    self.finish_slot(slots, compiled);
                }
                StepAction::WaitInput { input, on, timeout_s } => {
                    self.wait_input(*input, *on, *timeout_s)?;
                    self.finish_slot(slots, compiled);
                    return Ok(Some(start_clock(schedule_clock(&self.backend.state()))));
                }
                StepAction::Pause { optional } => {
                    if !*optional || self.optional_pauses {
                        self.publish(|p| {
                            p.step = c.steps.start;
                            p.waiting_for = Some("the operator: a pause step (Resume goes on)".into());
                        });
                        self.idle_until_control()?;
                        self.publish(|p| p.waiting_for = None);
                        self.regain(compiled, index + 1)?;
                    }
                    self.finish_slot(slots, compiled);
                    return Ok(Some(start_clock(schedule_clock(&self.backend.state()))));
                }
                StepAction::Motion(_) | StepAction::Dwell(_) if now_s >= end_s => {
                    self.finish_slot(slots, compiled);
                }
                _ => {
                    let shown = self.progress.load();
                    let left = (end_s - now_s).max(0.0) + left_after(compiled, index);
                    if shown.step != c.steps.start || (shown.time_left_s - left).abs() >= PROGRESS_RESOLUTION_S {
                        self.publish(|p| {
                            p.step = c.steps.start;
                            p.time_left_s = left;
                        });
                    }
                    break;
                }
            }
        }
        Ok(None)
    }

    fn finish_slot(&mut self, slots: &mut VecDeque<Slot>, compiled: &[CompiledStep]) {
        if let Some(done) = slots.pop_front() {
            self.last_end_s = done.end_s + self.delay_s;
            let c = &compiled[done.index];
            self.publish(|p| {
                p.steps_done = c.steps.end;
                p.step = c.steps.end.min(p.steps.saturating_sub(1));
            });
        }
    }

    /// Fails the run on a refusal, a blocked backend or a stalled schedule; tracks the error.
    fn watch(
        &self,
        s: &RobotState,
        refusal: &mut u64,
        compiled: &[CompiledStep],
        slots: &VecDeque<Slot>,
    ) -> Result<(), Halt> {
        if let Some((id, msg)) = &s.last_refusal
            && *id > *refusal
        {
            *refusal = *id;
            let step = slots.front().map_or(0, |sl| compiled[sl.index].steps.start + 1);
            return Err(Halt::Failed(format!("step {step}: {msg}")));
        }
        if let Some(b) = &s.blocked {
            return Err(Halt::Failed(format!("halted: {b}")));
        }
        let err = s.commanded.q.iter().zip(&s.q).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        if err > self.progress.load().max_tracking_error_rad {
            self.publish(|p| p.max_tracking_error_rad = err);
        }
        Ok(())
    }

    /// The latest refusal the backend reported, at least `seen`: a command the operator gave
    /// while the run waited (a jog refused at a limit) is not one of the run's.
    fn seen_refusal(&self, seen: u64) -> u64 {
        self.backend.state().last_refusal.as_ref().map_or(seen, |r| r.0.max(seen))
    }

    fn poll_control(&self) -> Option<RunnerControl> {
        if self.abort.load(Ordering::SeqCst) {
            return Some(RunnerControl::Stop);
        }
        match self.control.try_recv() {
            Ok(c) => Some(c),
            Err(TryRecvError::Empty) => None,
            // the handle is gone: stop
            Err(TryRecvError::Disconnected) => Some(RunnerControl::Stop),
        }
    }
}

mod pausing;
mod types;

#[cfg(test)]
mod checked_tests;
#[cfg(test)]
mod late_tests;
#[cfg(test)]
pub(crate) mod tests;
