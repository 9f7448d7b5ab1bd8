//! Right panel: the old HMI's demo trajectories (pick & place, inspection, dodge),
//! re-expressed as joint waypoints inside the PAROL6 limits and run as profiled moves, plus a
//! joint sweep that works for any robot (also used by `parol6 bench render`).
//!
//! A demo is a list of waypoints; [`DemoRunner`] sends one profiled move at a time and sends
//! the next when the arm has arrived. STOP (or any refused move) cancels it.

use eframe::egui;
use std::time::{Duration, Instant};

use parol6_core::RobotModel;
use parol6_core::profile::ProfileKind;

use super::{AppCommand, Panel, PanelContext, RobotState};

/// One waypoint of a demo.
#[derive(Debug, Clone, PartialEq)]
pub struct Waypoint {
    /// Joint goal, rad.
    pub goal: Vec<f64>,
    /// Speed fraction of this segment (0, 1].
    pub speed_fraction: f64,
    /// Profile of this segment.
    pub kind: ProfileKind,
}

/// A named demo trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct Demo {
    /// Name on the button.
    pub name: &'static str,
    /// One-line description.
    pub description: &'static str,
    /// Waypoints in order.
    pub waypoints: Vec<Waypoint>,
}

/// Arrival tolerance per joint, rad (0.5°).
const ARRIVAL_TOL_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;
/// A segment that has not arrived after this long is abandoned.
const SEGMENT_TIMEOUT: Duration = Duration::from_secs(30);
/// A segment is not judged before this long after it was sent (the simulation must see it).
const SEGMENT_MIN_TIME: Duration = Duration::from_millis(40);

const STANDBY: [f64; 6] = parol6_core::parol6::STANDBY_DEG;

fn wp(deg: [f64; 6], speed_fraction: f64, kind: ProfileKind) -> Waypoint {
    Waypoint { goal: deg.iter().map(|d| d.to_radians()).collect(), speed_fraction, kind }
}

/// The PAROL6 demos. Every waypoint lies within the joint limits and clears the ground and
/// self-collision (checked by the tests against the simulation).
pub fn parol6_demos() -> Vec<Demo> {
    use ProfileKind::{JerkLimited as J, Trapezoidal as T};
    // Tool pointing down; J1 swings the arm between a pick spot at x ≈ +150 mm and a place spot
    // at x ≈ −150 mm (y ≈ 260 mm), lowering the TCP from z ≈ 300 mm to z ≈ 150 mm at each.
    let above_pick = [60.0, -80.0, 170.0, 0.0, 80.0, 150.0];
    let pick = [60.0, -55.0, 160.0, 0.0, 75.0, 150.0];
    let above_place = [120.0, -80.0, 170.0, 0.0, 80.0, 210.0];
    let place = [120.0, -55.0, 160.0, 0.0, 75.0, 210.0];
    let pick_place = Demo {
        name: "Pick & place",
        description: "approach, descend, grip, lift, carry across, descend, release, lift, home",
        waypoints: vec![
            wp(above_pick, 0.7, T),
            wp(pick, 0.25, J),
            wp(above_pick, 0.35, J),
            wp(above_place, 0.7, T),
            wp(place, 0.25, J),
            wp(above_place, 0.35, J),
            wp(STANDBY, 0.6, T),
        ],
    };
    // Looks at a part near (0, 250, 100) mm from above, the left, the right and the front, then
    // rolls the flange over the top view.
    let inspection = Demo {
        name: "Inspection",
        description: "views of a part from the top, left, right and front; wrist roll over the top view",
        waypoints: vec![
            wp([90.0, -100.0, 200.0, 0.0, 60.0, 180.0], 0.5, J),
            wp([75.0, -70.0, 150.0, -40.0, 60.0, 180.0], 0.4, J),
            wp([90.0, -60.0, 150.0, 0.0, 60.0, 180.0], 0.4, J),
            wp([105.0, -70.0, 150.0, 40.0, 60.0, 180.0], 0.4, J),
            wp([90.0, -100.0, 200.0, 0.0, 60.0, 180.0], 0.4, J),
            wp([90.0, -100.0, 200.0, 0.0, 60.0, 120.0], 0.5, J),
            wp([90.0, -100.0, 200.0, 0.0, 60.0, 240.0], 0.5, J),
            wp(STANDBY, 0.5, J),
        ],
    };
    // Fast evasive moves: duck back, lean left, lean right, recover.
    let dodge = Demo {
        name: "Dodge",
        description: "fast evasive moves: duck back, lean left, lean right, recover",
        waypoints: vec![
            wp([90.0, -125.0, 235.0, 0.0, -40.0, 180.0], 1.0, T),
            wp([40.0, -110.0, 200.0, 0.0, 30.0, 180.0], 1.0, T),
            wp([120.0, -110.0, 200.0, 0.0, 30.0, 180.0], 1.0, T),
            wp([90.0, -95.0, 190.0, 0.0, 10.0, 180.0], 0.8, T),
            wp(STANDBY, 0.6, T),
        ],
    };
    vec![pick_place, inspection, dodge]
}

/// A sweep of every joint between 25 % and 75 % of its range (mid-range ± π/4 for unbounded
/// joints), all joints together, then back to mid-range. Works for any robot.
pub fn joint_sweep(model: &RobotModel, speed_fraction: f64) -> Demo {
    let at = |f: f64| -> Vec<f64> {
        model
            .limits
            .iter()
            .map(|l| if l.is_bounded() { l.min + f * l.range() } else { (f - 0.5) * std::f64::consts::FRAC_PI_2 })
            .collect()
    };
    let mk = |goal| Waypoint { goal, speed_fraction, kind: ProfileKind::Trapezoidal };
    Demo {
        name: "Joint sweep",
        description: "every joint between 25 % and 75 % of its range",
        waypoints: vec![mk(at(0.25)), mk(at(0.75)), mk(at(0.5))],
    }
}

/// Runs a demo: one profiled move at a time.
#[derive(Debug, Default)]
pub struct DemoRunner {
    demo: Option<Demo>,
    step: usize,
    sent_at: Option<Instant>,
    /// Restart from the first waypoint when finished.
    pub looping: bool,
    /// Global speed scale applied on top of each waypoint's speed (0, 1].
    pub speed_scale: f64,
}

impl DemoRunner {
    /// Starts `demo` (replacing any running one).
    pub fn start(&mut self, demo: Demo) {
        self.demo = Some(demo);
        self.step = 0;
        self.sent_at = None;
    }

    /// Cancels the running demo.
    pub fn cancel(&mut self) {
        self.demo = None;
        self.sent_at = None;
    }

    /// Name of the running demo and the current step (1-based) / total.
    pub fn progress(&self) -> Option<(&'static str, usize, usize)> {
        self.demo.as_ref().map(|d| (d.name, (self.step + 1).min(d.waypoints.len()), d.waypoints.len()))
    }

    /// True while a demo runs.
    pub fn is_running(&self) -> bool {
        self.demo.is_some()
    }

    fn arrived(goal: &[f64], robot: &RobotState) -> bool {
        !robot.moving
            && goal.len() == robot.q.len()
            && goal.iter().zip(&robot.q).all(|(g, q)| (g - q).abs() < ARRIVAL_TOL_RAD)
    }

    /// Advances the demo: returns the next move to send, if it is time for one. Call every frame.
    pub fn tick(&mut self, robot: &RobotState) -> Result<Option<AppCommand>, String> {
        let Some(demo) = &self.demo else {
            return Ok(None);
        };
        let scale = if self.speed_scale > 0.0 { self.speed_scale.min(1.0) } else { 1.0 };
        if let Some(sent) = self.sent_at {
            let Some(w) = demo.waypoints.get(self.step) else {
                self.cancel();
                return Ok(None);
            };
            if sent.elapsed() < SEGMENT_MIN_TIME || !Self::arrived(&w.goal, robot) {
                if sent.elapsed() > SEGMENT_TIMEOUT {
                    let msg = format!("demo \"{}\" stopped: waypoint {} not reached in time", demo.name, self.step + 1);
                    self.cancel();
                    return Err(msg);
                }
                return Ok(None);
            }
            self.step += 1;
            if self.step >= demo.waypoints.len() {
                if self.looping {
                    self.step = 0;
                } else {
                    self.cancel();
                    return Ok(None);
                }
            }
        }
        let Some(demo) = &self.demo else {
            return Ok(None);
        };
        let Some(w) = demo.waypoints.get(self.step) else {
            self.cancel();
            return Ok(None);
        };
        self.sent_at = Some(Instant::now());
        Ok(Some(AppCommand::MoveTo {
            goal: w.goal.clone(),
            speed_fraction: (w.speed_fraction * scale).clamp(0.01, 1.0),
            kind: w.kind,
        }))
    }
}

/// The demos panel.
#[derive(Debug)]
pub struct DemosPanel {
    demos: Vec<Demo>,
    /// The runner (ticked by the app every frame, shown here).
    pub runner: DemoRunner,
}

impl DemosPanel {
    /// Demos for `model` (the PAROL6 demos only on the PAROL6; the sweep always).
    pub fn new(model: &RobotModel) -> Self {
        let mut demos = if model.is_parol6 { parol6_demos() } else { Vec::new() };
        demos.push(joint_sweep(model, 0.5));
        Self { demos, runner: DemoRunner { speed_scale: 1.0, ..Default::default() } }
    }

    /// Starts the demo called `name`; false when there is none.
    pub fn start_by_name(&mut self, name: &str) -> bool {
        match self.demos.iter().find(|d| d.name.eq_ignore_ascii_case(name)) {
            Some(d) => {
                self.runner.start(d.clone());
                true
            }
            None => false,
        }
    }
}

impl Panel for DemosPanel {
    fn title(&self) -> &'static str {
        "Demo trajectories"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.heading(self.title());
        ui.horizontal_wrapped(|ui| {
            for d in &self.demos {
                if ui.button(d.name).on_hover_text(d.description).clicked() {
                    self.runner.start(d.clone());
                }
            }
        });
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.runner.looping, "Loop");
            ui.label("Speed ×");
            ui.add(egui::Slider::new(&mut self.runner.speed_scale, 0.1..=1.0).max_decimals(2));
        });
        match self.runner.progress() {
            Some((name, step, total)) => {
                ui.horizontal(|ui| {
                    ui.label(format!("Running {name}: waypoint {step}/{total}"));
                    if ui.button("Stop demo").clicked() {
                        ctx.send(AppCommand::Stop);
                    }
                });
                ui.ctx().request_repaint();
            }
            None => {
                ui.weak("Idle. STOP (Esc) cancels a running demo.");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use parol6_core::sim::{SimCommand, SimConfig, Simulation};

    /// Drives the deterministic simulation through every waypoint: each move must be accepted
    /// (limits and collision checks) and arrive.
    fn run_in_sim(demo: &Demo, model: &RobotModel) {
        let mut sim = Simulation::new(model.clone(), SimConfig::default()).expect("sim");
        sim.apply(SimCommand::Teleport(parol6_core::parol6::standby_rad().to_vec())).expect("teleport");
        for (i, w) in demo.waypoints.iter().enumerate() {
            assert!(model.limits.contains(&w.goal), "{} waypoint {} outside the limits", demo.name, i + 1);
            sim.apply(SimCommand::MoveTo { goal: w.goal.clone(), speed_fraction: w.speed_fraction, kind: w.kind })
                .unwrap_or_else(|e| panic!("{} waypoint {} refused: {e}", demo.name, i + 1));
            let mut steps = 0;
            loop {
                sim.step();
                steps += 1;
                let s = sim.snapshot();
                if !s.moving && w.goal.iter().zip(&s.q).all(|(g, q)| (g - q).abs() < ARRIVAL_TOL_RAD) {
                    break;
                }
                assert!(steps < 20_000, "{} waypoint {} not reached in 20 s: {:?}", demo.name, i + 1, s.q);
            }
        }
    }

    #[test]
    fn parol6_demos_run_in_the_simulation() {
        let model = RobotModel::parol6();
        let demos = parol6_demos();
        assert_eq!(demos.len(), 3);
        for d in &demos {
            run_in_sim(d, &model);
        }
        run_in_sim(&joint_sweep(&model, 1.0), &model);
    }

    #[test]
    fn runner_waits_for_arrival_then_advances() {
        let model = RobotModel::parol6();
        let demo = joint_sweep(&model, 1.0);
        let mut r = DemoRunner { speed_scale: 1.0, ..Default::default() };
        r.start(demo.clone());
        let mut robot = RobotState {
            source: super::super::StateSource::Simulation,
            q: parol6_core::parol6::standby_rad().to_vec(),
            qd: vec![0.0; 6],
            target_q: vec![0.0; 6],
            zones: Vec::new(),
            tcp: model.fk(&parol6_core::parol6::standby_rad()),
            moving: false,
        };
        let first = r.tick(&robot).expect("ok");
        assert!(matches!(first, Some(AppCommand::MoveTo { ref goal, .. }) if goal == &demo.waypoints[0].goal));
        // Not arrived: nothing new.
        std::thread::sleep(SEGMENT_MIN_TIME);
        assert_eq!(r.tick(&robot).expect("ok"), None);
        // Arrived: the second waypoint is sent.
        robot.q = demo.waypoints[0].goal.clone();
        let second = r.tick(&robot).expect("ok");
        assert!(matches!(second, Some(AppCommand::MoveTo { ref goal, .. }) if goal == &demo.waypoints[1].goal));
        assert_eq!(r.progress().map(|p| p.1), Some(2));
        r.cancel();
        assert!(!r.is_running());
        assert_eq!(r.tick(&robot).expect("ok"), None);
    }
}
