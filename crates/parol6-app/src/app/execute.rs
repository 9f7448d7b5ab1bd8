//! Executing the commands the panels queued: motion on the active backend (the same call for
//! the simulation and the robot), programs, jog refresh, link operations, and the notices
//! that report what happened.

use std::sync::Arc;
use std::time::Instant;

use parol6_core::motion::{CartesianAxis, IoCommand, JogFrame, MotionCommand, RobotBackend};
use parol6_core::program::runner::ProgramRunner;

use super::command_kinds::{is_stop, manual_motion, refused_by_estop, sets_arm_moving};
use super::state::{MEASUREMENT_RUNNING, PROGRAM_RUNNING, PROGRAM_UNFINISHED, TORQUE_ON_ROBOT, TORQUE_RUNNING};
use super::{ConnectTarget, JOG_REFRESH, Parol6App};
use crate::panels::{AppCommand, LinkCommand, RobotState};

/// A held joint jog stops when the floor lies within this long of jog travel ahead, s (covers
/// the refresh interval and the deceleration).
const JOG_FLOOR_LOOKAHEAD_S: f64 = 0.3;
/// ... and at least this far ahead, rad (1°).
const JOG_FLOOR_MIN_AHEAD_RAD: f64 = 0.017_453_292_519_943_295;

/// A port that has not answered within this long is reported as "no controller answers".
const ANSWER_TIMEOUT_S: f64 = 3.0;

/// A program's outcome when the operator's E-STOP ended it (not the refusals of the disabled
/// controller that follow).
const RUN_ESTOP: &str = "the operator pressed E-STOP";

/// Why a run ended when STOP (the button or Esc) ended it.
const RUN_STOP: &str = "the operator pressed STOP";

/// The answer to the gripper panel's Calibrate.
const GRIPPER_CALIBRATE_SENT: &str = "gripper calibration sent (the I/O & gripper section shows its status)";

/// The answer to Clear error.
const CLEAR_ERROR_SENT: &str = "CLEAR ERROR sent to the controller and the gripper";

/// The measurement's name in the notices.
const ISO_TEST: &str = "ISO 9283 test";

/// How a command that sets the arm moving is kept in [`Parol6App::moves_sent`]: its `Debug` text,
/// but a program run by its name and length (the `Debug` text of a 1 000-step program with its
/// check is megabytes: writing it took 50 ms of the frame that pressed F5).
fn move_text(cmd: &AppCommand) -> String {
    match cmd {
        AppCommand::RunProgram { program, checked, opts } => format!(
            "RunProgram {{ program: {:?} ({} steps), checked: {}, opts: {opts:?} }}",
            program.name,
            program.steps.len(),
            checked.is_some()
        ),
        other => format!("{other:?}"),
    }
}

impl Parol6App {
    /// Says that `cmd` was not sent because `by` (STOP, HOME, another move) came in the same
    /// frame, where it moves the arm to a typed target (a jog simply does not start).
    pub(super) fn dropped_for(&mut self, cmd: &AppCommand, by: &str) {
        if matches!(cmd, AppCommand::Motion(m) | AppCommand::TypedMotion(m) if matches!(m, MotionCommand::MoveJoints { .. }))
        {
            self.notice(format!("{by}: the value typed and not confirmed with Enter was not sent"), false);
        }
    }

    pub(super) fn execute(&mut self, cmd: AppCommand) {
        // a typed move that no click overrode (`command_kinds::overridden`) runs as any move
        let cmd = match cmd {
            AppCommand::TypedMotion(m) => AppCommand::Motion(m),
            other => other,
        };
        if is_stop(&cmd) {
            self.state.stops += 1;
        }
        let refused_by = if self.estop {
            Some(crate::panels::io_gripper::ESTOP_LATCHED).filter(|_| refused_by_estop(&cmd))
        } else if self.state.replaying() {
            Some(super::state::REPLAY_OPEN).filter(|_| refused_by_estop(&cmd))
        } else {
            // a torque run is ended by any motion: a program or a measurement is refused too
            // (Run torques again replaces the run, as the form says)
            let ends_torque_run = |why: &&str| {
                *why == TORQUE_RUNNING && sets_arm_moving(&cmd) && !matches!(cmd, AppCommand::RunTorques(_))
            };
            self.automatic_run().filter(|why| manual_motion(&cmd) || ends_torque_run(why))
        };
        if let Some(why) = refused_by {
            if matches!(cmd, AppCommand::Jog(_) | AppCommand::CartesianJog(_)) {
                self.jog_held = None;
                self.cartesian_jog_held = None;
            }
            self.refusal_notice(why);
            return;
        }
        if let Some(why) = self.floor_refusal(&cmd) {
            if let AppCommand::Jog(_) = cmd
                && self.jog_held.take().is_some()
                && let Err(e) = self.backend().send(MotionCommand::JogRelease)
            {
                self.notice(format!("jog release refused: {e}"), true);
            }
            self.refusal_notice(&why);
            return;
        }
        let step = matches!(cmd, AppCommand::Motion(MotionCommand::CartesianStep { .. }));
        if (sets_arm_moving(&cmd) && !step) || matches!(cmd, AppCommand::Link(LinkCommand::Home)) {
            self.state.other_motions += 1;
        }
        if sets_arm_moving(&cmd) {
            if self.moves_sent.len() >= 256 {
                self.moves_sent.pop_front();
            }
            self.moves_sent.push_back(move_text(&cmd));
        }
        match cmd {
            AppCommand::ClearTrail => {
                if let Some(v) = &mut self.viewport {
                    v.clear_trail();
                }
            }
            AppCommand::ResetView => {
                if let Some(v) = &mut self.viewport {
                    v.reset_view();
                }
            }
            AppCommand::Link(l) => self.execute_link(l),
            AppCommand::OpenRecording(path) => self.open_recording(path),
            AppCommand::CloseRecording => self.close_recording(),
            AppCommand::SeekReplay(t_s) => self.seek_replay(t_s),
            AppCommand::Replay(control) => self.control_replay(control),
            AppCommand::Record(Some(path)) => self.start_file_recording(&path),
            AppCommand::Record(None) => self.stop_file_recording(),
            AppCommand::ShareLive(on) => self.share_live(on),
            AppCommand::ShareRos2(on) => self.share_ros2(on),
            AppCommand::RemoteControl(on) => self.set_remote_control(on),
            AppCommand::Motion(m) | AppCommand::TypedMotion(m) => {
                if matches!(m, MotionCommand::Stop) {
                    // said in a notice: at 1024×700 the program's status line is below the fold
                    self.stopped_notices(RUN_STOP);
                    self.stop_program();
                    self.state.measurement.abort();
                }
                if let Err(e) = self.backend().send(m) {
                    self.stop_program();
                    self.notice(format!("command refused: {e}"), true);
                }
            }
            AppCommand::Jog(held) => self.jog(held),
            AppCommand::CartesianJog(held) => self.cartesian_jog(held),
            AppCommand::RunProgram { program, checked, opts } => {
                if self.program_running() {
                    self.notice(PROGRAM_UNFINISHED.to_string(), true);
                    return;
                }
                let name = program.name.clone();
                // not started, so not "stopped" (trial 21 m10: "Pick & place stopped: the arm is
                // moving" during an ISO test, which it did not name)
                if self.state.measurement.running() {
                    self.notice(format!("cannot start {name}: {MEASUREMENT_RUNNING}"), true);
                    return;
                }
                let started = match checked.filter(|c| Arc::ptr_eq(&c.program, &program)) {
                    // the runner reuses the check from the joints it was made at
                    Some(c) => ProgramRunner::start_checked(self.backend(), self.model.clone(), c, opts),
                    None => ProgramRunner::start(self.backend(), self.model.clone(), (*program).clone(), opts),
                };
                match started {
                    Ok(r) => {
                        self.state.program = Some(r.progress());
                        self.program = Some(r);
                        self.run_ended_by = None;
                        self.note_program_start(&name);
                    }
                    Err(e) => self.notice(format!("cannot start {name}: {e}"), true),
                }
            }
            AppCommand::AbortMeasurement => self.state.measurement.abort(),
            AppCommand::StartMeasurement(plan) => {
                if self.program_running() || self.state.measurement.running() {
                    self.notice("a program or measurement is running: stop it first".to_string(), true);
                    return;
                }
                let backend = self.backend();
                let state = backend.state();
                match parol6_core::measure::driver::start_pose_test(backend, self.model.clone(), plan) {
                    Ok(run) => self.state.measurement.attach(run, state.source, state.backend.clone()),
                    Err(e) => self.notice(format!("cannot start the measurement: {e}"), true),
                }
            }
            AppCommand::RunTorques(run) => {
                if self.hw.is_some() {
                    self.notice(format!("torque run refused: {TORQUE_ON_ROBOT}"), true);
                } else if self.program_running() {
                    self.notice(format!("torque run refused: {PROGRAM_UNFINISHED}"), true);
                } else if self.state.measurement.running() {
                    self.notice(format!("torque run refused: {MEASUREMENT_RUNNING}"), true);
                } else if let Err(e) = self.sim.send(parol6_core::sim::SimCommand::RunJointTorques(run)) {
                    self.notice(format!("torque run refused: {e}"), true);
                }
            }
            AppCommand::Program(control) => {
                if let Some(r) = &self.program {
                    r.control(control);
                }
            }
            AppCommand::Io(io) => match self.backend().io(io) {
                // one-shot commands that change nothing on screen at once get an answer
                Ok(()) => match io {
                    IoCommand::GripperCalibrate => self.notice(GRIPPER_CALIBRATE_SENT.to_string(), false),
                    IoCommand::ClearError => self.notice(CLEAR_ERROR_SENT.to_string(), false),
                    _ => {}
                },
                Err(e) => self.notice(format!("{io:?} refused: {e}"), true),
            },
            AppCommand::EStop(true) => self.press_estop(),
            AppCommand::EStop(false) => self.release_estop(),
        }
    }

    /// "refused: `why`": one notice, kept up while the refused command repeats (a held jog key).
    fn refusal_notice(&mut self, why: &str) {
        let text = format!("refused: {why}");
        match self.notices.iter_mut().find(|n| n.text == text) {
            Some(n) => n.at = Instant::now(),
            None => self.notice(text, true),
        }
    }

    /// A Cartesian jog key held over the 3D view while manual motion is refused (the latched
    /// E-stop, replay, a program, an ISO test or a torque run): the jog panel greys its buttons
    /// and ignores its keys then; the notice says why the key does nothing. Every jog key held
    /// meanwhile is disarmed: it does not jog when the refusal ends (Release E-STOP, F6) until
    /// it is let go and pressed anew (trial19 D1: Page Up held under the latch jogged J1 at the
    /// release).
    pub(super) fn refuse_held_jog_keys(&mut self, ctx: &eframe::egui::Context) {
        use crate::panels::shortcuts::{Action, disarm_held, held};
        let why = if self.estop {
            Some(crate::panels::io_gripper::ESTOP_LATCHED)
        } else if self.state.replaying() {
            Some(super::state::REPLAY_OPEN)
        } else {
            self.automatic_run()
        };
        let Some(why) = why else { return };
        let jog = |axis| [-1, 1].into_iter().any(|dir| held(ctx, Action::JogCartesian(axis, dir)));
        if CartesianAxis::ALL.into_iter().any(jog) {
            self.refusal_notice(why);
        }
        disarm_held(ctx);
    }

    /// Why a manual joint motion (a typed or Go to pose, a slider, HOME, Move to target, a held
    /// joint jog) is refused by the floor rule pre-flight applies to programs, on the simulation
    /// and the robot alike: its straight joint path from the commanded pose would take a link
    /// below the floor. A held jog looks [`JOG_FLOOR_LOOKAHEAD_S`] ahead and stops before it.
    /// From a pose already below the floor only the end is checked (a way out is allowed).
    fn floor_refusal(&self, cmd: &AppCommand) -> Option<String> {
        let state = self.backend().state();
        let dof = self.model.dof();
        let from = if state.commanded.q.len() == dof { &state.commanded.q } else { &state.q };
        if from.len() != dof {
            return None;
        }
        let to = match cmd {
            AppCommand::Motion(MotionCommand::MoveJoints { goal_rad, .. }) => goal_rad.clone(),
            AppCommand::Motion(MotionCommand::Follow { target_rad, .. }) => target_rad.clone(),
            AppCommand::Motion(MotionCommand::Home { .. }) => parol6_core::motion::home_position(&self.model),
            AppCommand::Jog(Some((joint, dir))) => {
                let speed_rad_s = parol6_core::motion::MotionCaps::of(&self.model).speed_rad_s.get(*joint).copied()?;
                let ahead_rad = (speed_rad_s * self.settings.jog_speed_fraction * JOG_FLOOR_LOOKAHEAD_S)
                    .max(JOG_FLOOR_MIN_AHEAD_RAD);
                let mut to = from.clone();
                let (lo, hi) = self.model.limits.get(*joint).map_or((f64::MIN, f64::MAX), |l| (l.min, l.max));
                *to.get_mut(*joint)? = (from[*joint] + f64::from(*dir) * ahead_rad).clamp(lo.min(hi), hi.max(lo));
                to
            }
            _ => return None,
        };
        if to.len() != dof {
            return None;
        }
        let guard = self.floor_guard.get_or_init(|| parol6_core::collision::CollisionGuard::new(&self.model));
        let (contact, at) = if guard.floor_contact(&self.model, from).is_some() {
            (guard.floor_contact(&self.model, &to)?, 1.0)
        } else {
            guard.floor_on_path(&self.model, from, &to)?
        };
        Some(match cmd {
            AppCommand::Jog(Some((joint, _))) => {
                let name = self.model.joints.get(*joint).map_or("the joint", |j| j.name.as_str());
                // no depth: it changes with every refresh, and one notice is kept up while held
                let rule = parol6_core::collision::below_floor_text(&contact.link);
                format!("{name} jog stopped before the floor: {rule} just ahead; jog the other way")
            }
            _ if at >= 1.0 => format!("{contact} at that pose (pre-flight's floor rule); nothing was sent"),
            _ => format!(
                "{contact} on the way there ({:.0} % of the move; pre-flight's floor rule); nothing was sent",
                at * 100.0
            ),
        })
    }

    /// Why a manual motion is refused now: a program runs (preparing, running, returning to its
    /// path; not paused) or a measurement drives the arm, and the motion would pull the arm off
    /// the planned path; or a torque run drives the simulation, and the motion would end it.
    fn automatic_run(&self) -> Option<&'static str> {
        use parol6_core::program::runner::RunState;
        let program = self
            .program
            .as_ref()
            .is_some_and(|r| matches!(r.progress().state, RunState::Preparing | RunState::Running));
        if program {
            Some(PROGRAM_RUNNING)
        } else if self.state.measurement.running() {
            Some(MEASUREMENT_RUNNING)
        } else {
            self.state.torque_run.then_some(TORQUE_RUNNING)
        }
    }

    /// The E-stop button: ends a program or measurement, STOP and DISABLE to the active backend,
    /// and latches (motion refused here until released) even when the backend refused them.
    fn press_estop(&mut self) {
        self.estop = true;
        if self.program_running() {
            self.run_ended_by = Some(RUN_ESTOP);
        }
        if self.state.measurement.running() {
            self.notice(format!("{ISO_TEST} stopped: {RUN_ESTOP}"), true);
        }
        self.stop_program();
        self.state.measurement.abort();
        self.jog_held = None;
        self.cartesian_jog_held = None;
        let backend = self.backend();
        let failed: Vec<String> = [
            backend.send(MotionCommand::Stop).err().map(|e| format!("STOP: {e}")),
            backend.io(IoCommand::Disable).err().map(|e| format!("DISABLE: {e}")),
        ]
        .into_iter()
        .flatten()
        .collect();
        if failed.is_empty() {
            self.notice("E-STOP: STOP and DISABLE sent; all motion refused (Release E-STOP to move again)", true);
        } else {
            self.notice(format!("E-STOP latched, but {}: motion is refused here", failed.join(", ")), true);
        }
    }

    /// STOP (the button or Esc) ends a running program or ISO test: a notice says which, and why.
    fn stopped_notices(&mut self, why: &str) {
        if let Some(r) = self.program.as_ref().filter(|r| !r.is_finished()) {
            let name = r.progress().name.clone();
            self.notice(format!("{name} stopped: {why}"), false);
        }
        if self.state.measurement.running() {
            self.notice(format!("{ISO_TEST} stopped: {why}"), false);
        }
    }

    /// Under the latch, the backend that has just become the active one (a connect or a
    /// disconnect) gets DISABLE too: the latched line says "drives disabled", and the other
    /// backend's drives were enabled (trial14 m5: the simulation's green LED under it).
    pub(super) fn latch_the_new_backend(&mut self) {
        if self.estop
            && let Err(e) = self.backend().io(IoCommand::Disable)
        {
            self.notice(format!("E-STOP latched, but DISABLE: {e}: motion is refused here"), true);
        }
    }

    /// Releases the E-stop latch with ENABLE; it stays latched when ENABLE is refused.
    fn release_estop(&mut self) {
        match self.backend().io(IoCommand::Enable) {
            Ok(()) => {
                self.estop = false;
                // the latch's "all motion refused" no longer holds
                // (trial 23 m12: it stayed under this one)
                self.notices.retain(|n| !n.text.starts_with("E-STOP: STOP and DISABLE sent"));
                // trial 26 m6: during replay motion stays refused until the recording is closed
                let then = if self.state.replaying() {
                    "motion is accepted once the recording is closed"
                } else {
                    "motion is accepted again"
                };
                self.notice(format!("E-stop released: ENABLE sent; {then}"), false);
            }
            Err(e) => self.notice(format!("E-stop stays latched: ENABLE refused: {e}"), true),
        }
    }

    /// Hold-to-run jog: sends the jog command when it changes and refreshes it within the
    /// backend's dead-man time while held; releases it when let go.
    fn jog(&mut self, held: Option<(usize, i8)>) {
        let backend: Arc<dyn RobotBackend> = self.backend();
        let res = match held {
            None => match self.jog_held.take() {
                Some(_) => backend.send(MotionCommand::JogRelease),
                None => Ok(()),
            },
            Some((joint, dir)) => {
                let due = match self.jog_held {
                    Some((j, d, at)) => j != joint || d != dir || at.elapsed() >= JOG_REFRESH,
                    None => true,
                };
                if due {
                    self.jog_held = Some((joint, dir, Instant::now()));
                    let fraction = f64::from(dir) * self.settings.jog_speed_fraction;
                    backend.send(MotionCommand::JogJoint { joint, fraction })
                } else {
                    Ok(())
                }
            }
        };
        if let Err(e) = res {
            self.jog_held = None;
            self.notice(format!("jog refused: {e}"), true);
        }
    }

    /// Hold-to-run Cartesian jog: sends the jog when it changes and refreshes it within the
    /// backend's dead-man time while held; releases it when let go.
    fn cartesian_jog(&mut self, held: Option<(JogFrame, CartesianAxis, f64)>) {
        let backend: Arc<dyn RobotBackend> = self.backend();
        let res = match held {
            None => match self.cartesian_jog_held.take() {
                Some(_) => backend.send(MotionCommand::JogRelease),
                None => Ok(()),
            },
            Some((frame, axis, fraction)) => {
                let cmd = MotionCommand::JogCartesian { frame, axis, fraction };
                let due = match &self.cartesian_jog_held {
                    Some((c, at)) => *c != cmd || at.elapsed() >= JOG_REFRESH,
                    None => true,
                };
                if due {
                    self.cartesian_jog_held = Some((cmd.clone(), Instant::now()));
                    backend.send(cmd)
                } else {
                    Ok(())
                }
            }
        };
        if let Err(e) = res {
            self.cartesian_jog_held = None;
            self.notice(format!("Cartesian jog refused: {e}"), true);
        }
    }

    fn execute_link(&mut self, cmd: LinkCommand) {
        if matches!(cmd, LinkCommand::Connect(_) | LinkCommand::ConnectEmulator | LinkCommand::Disconnect) {
            self.state.other_motions += 1;
        }
        let res: Result<(), String> = match (&self.hw, cmd) {
            (_, LinkCommand::Connect(p)) => {
                self.connect(&ConnectTarget::Port(p));
                Ok(())
            }
            (_, LinkCommand::ConnectEmulator) => {
                self.connect(&ConnectTarget::Emulator);
                Ok(())
            }
            (_, LinkCommand::Disconnect) => {
                self.disconnect();
                Ok(())
            }
            (None, _) => Err("no robot connected".to_string()),
            (Some(l), LinkCommand::Enable) => l.session.enable().map_err(|e| e.to_string()),
            (Some(l), LinkCommand::Disable) => l.session.disable().map_err(|e| e.to_string()),
            (Some(l), LinkCommand::Home) => l.session.home().map_err(|e| e.to_string()),
        };
        if let Err(e) = res {
            self.notice(format!("robot: {e}"), true);
        }
    }

    /// Tells the operator when the link changes: the controller answered (the port is then
    /// remembered), no controller answers, the link was lost or came back; and new faults.
    pub(super) fn link_notices(&mut self) {
        let Some(link) = &mut self.hw else { return };
        let snap = link.session.snapshot();
        let mut out: Vec<(String, bool)> = Vec::new();
        let mut remember_port = None;
        if snap.homing != link.told_homing {
            link.told_homing = snap.homing.clone();
            match &snap.homing {
                parol6_hw::HomingState::Sending => out.push(("robot: homing started".to_string(), false)),
                parol6_hw::HomingState::Done => out.push(("robot: homing done, all joints homed".to_string(), false)),
                // the session's fault says why ("homing failed: …")
                _ => {}
            }
        }
        if snap.fault != link.last_fault {
            link.last_fault.clone_from(&snap.fault);
            if let Some(f) = &snap.fault {
                out.push((format!("robot: {f}"), true));
            }
        }
        let state = snap.link;
        if link.told != Some(state) {
            use parol6_hw::LinkState as L;
            let waited_s = link.opened_at.elapsed().as_secs_f64();
            let msg = match (state, snap.status_frames) {
                (L::Connected, _) => {
                    if !link.emulated {
                        remember_port = Some(snap.port.clone());
                    }
                    Some((format!("PAROL6 answered on {}", snap.port), false))
                }
                (L::Connecting | L::Lost, 0) if waited_s >= ANSWER_TIMEOUT_S => Some((
                    format!(
                        "no PAROL6 answered on {} within {ANSWER_TIMEOUT_S:.0} s: check the port and the power",
                        snap.port
                    ),
                    true,
                )),
                (L::Connecting | L::Lost, 0) => None,
                (L::Lost, _) => Some((format!("link to {} lost: motion stopped", snap.port), true)),
                (L::Connecting, _) => None,
                (L::Closed, _) => Some((format!("link to {} closed", snap.port), true)),
                // The session's fault says it ("no PAROL6 answered on … within 3 s").
                (L::NoAnswer, _) => None,
            };
            if let Some(m) = msg {
                link.told = Some(state);
                out.push(m);
            }
        }
        if let Some(p) = remember_port {
            self.settings.last_port = p;
        }
        if !out.is_empty() {
            crate::panels::Notice::withdraw(&mut self.notices, |t| {
                t.ends_with("waiting for it to answer") || t.ends_with("waiting for the controller to answer")
            });
        }
        for (text, error) in out {
            self.notice(text, error);
        }
    }

    /// Shows each refusal of the active backend once (ids are counted per backend).
    pub(super) fn refusal_notices(&mut self, robot: &RobotState) {
        let Some((id, msg)) = &robot.last_refusal else { return };
        if self.last_refusal_seen.get(&robot.backend).is_some_and(|seen| *id <= *seen) {
            return;
        }
        self.last_refusal_seen.insert(robot.backend.clone(), *id);
        self.notice(format!("{} refused a command: {msg}", robot.backend), true);
    }
}
