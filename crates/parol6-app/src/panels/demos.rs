//! Right panel: the old HMI's demo trajectories (pick & place, inspection, dodge),
//! re-expressed as joint waypoints inside the PAROL6 limits, plus a joint sweep that works for
//! any robot (also used by `parol6 bench render`).
//!
//! A demo is a list of profiled joint moves. The panel asks the app to run it as a sequence:
//! the core's `SequenceRunner` sends one move after another on its own thread, on whichever
//! backend is active, so a demo keeps its pace with the window minimised or slow. STOP (or any
//! refused move) ends it.

use eframe::egui;

use parol6_core::RobotModel;
use parol6_core::motion::{MotionCommand, SequenceState};
use parol6_core::profile::ProfileKind;

use super::{AppCommand, Panel, PanelContext};

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

const STANDBY: [f64; 6] = parol6_core::parol6::STANDBY_DEG;

fn wp(deg: [f64; 6], speed_fraction: f64, kind: ProfileKind) -> Waypoint {
    Waypoint { goal: deg.iter().map(|d| d.to_radians()).collect(), speed_fraction, kind }
}

/// The PAROL6 demos. Every waypoint lies within the joint limits and clears the ground and
/// self-collision (checked by the tests against the simulation).
pub fn parol6_demos() -> Vec<Demo> {
    use ProfileKind::{JerkLimited as J, Trapezoidal as T};
    // Tool pointing down; J1 swings the arm between a pick spot on the right (J1 = 45°) and a
    // place spot straight ahead (J1 = 85°), lowering the TCP from z ≈ 300 mm to z ≈ 150 mm at
    // each. J1 stays over 33° from both of its limits (±123°): never in its red zone (standby's
    // 90° itself is in the amber band).
    let above_pick = [45.0, -80.0, 170.0, 0.0, 80.0, 135.0];
    let pick = [45.0, -55.0, 160.0, 0.0, 75.0, 135.0];
    let above_place = [85.0, -80.0, 170.0, 0.0, 80.0, 175.0];
    let place = [85.0, -55.0, 160.0, 0.0, 75.0, 175.0];
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

impl Demo {
    /// The demo as motion commands, each waypoint's speed scaled by `speed_scale` (0, 1].
    pub fn steps(&self, speed_scale: f64) -> Vec<MotionCommand> {
        let scale = if speed_scale.is_finite() && speed_scale > 0.0 { speed_scale.min(1.0) } else { 1.0 };
        self.waypoints
            .iter()
            .map(|w| MotionCommand::MoveJoints {
                goal_rad: w.goal.clone(),
                speed_fraction: (w.speed_fraction * scale).clamp(0.01, 1.0),
                profile: w.kind,
            })
            .collect()
    }
}

/// The demos panel.
#[derive(Debug)]
pub struct DemosPanel {
    demos: Vec<Demo>,
    /// Start over after the last waypoint.
    pub looping: bool,
    /// Speed scale applied on top of each waypoint's speed (0, 1].
    pub speed_scale: f64,
}

impl DemosPanel {
    /// Demos for `model` (the PAROL6 demos only on the PAROL6; the sweep always).
    pub fn new(model: &RobotModel) -> Self {
        let mut demos = if model.is_parol6 { parol6_demos() } else { Vec::new() };
        demos.push(joint_sweep(model, 0.5));
        Self { demos, looping: false, speed_scale: 1.0 }
    }

    /// The command that runs the demo called `name` (with this panel's loop and speed settings).
    pub fn run_command(&self, name: &str) -> Option<AppCommand> {
        let d = self.demos.iter().find(|d| d.name.eq_ignore_ascii_case(name))?;
        Some(AppCommand::RunSequence {
            name: d.name.to_string(),
            steps: d.steps(self.speed_scale),
            looping: self.looping,
        })
    }
}

impl Panel for DemosPanel {
    fn title(&self) -> &'static str {
        "Demo trajectories"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.heading(self.title());
        let running = ctx.sequence.is_some_and(|p| p.state == SequenceState::Running);
        ui.horizontal_wrapped(|ui| {
            for d in &self.demos {
                if ui.button(d.name).on_hover_text(d.description).clicked() {
                    ctx.send(AppCommand::RunSequence {
                        name: d.name.to_string(),
                        steps: d.steps(self.speed_scale),
                        looping: self.looping,
                    });
                }
            }
        });
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.looping, "Loop");
            ui.label("Speed ×");
            ui.add(egui::Slider::new(&mut self.speed_scale, 0.1..=1.0).max_decimals(2));
        });
        // One line, always present, so nothing below moves when a demo starts or ends.
        ui.horizontal(|ui| match ctx.sequence {
            Some(p) if p.state == SequenceState::Running => {
                ui.label(format!("Running {}: waypoint {}/{}", p.name, p.step + 1, p.steps));
                if ui.button("Stop demo").clicked() {
                    ctx.stop();
                }
            }
            Some(p) => {
                let what = match &p.state {
                    SequenceState::Done => "done".to_string(),
                    SequenceState::Cancelled => "stopped".to_string(),
                    SequenceState::Failed(why) => format!("stopped: {why}"),
                    SequenceState::Running => String::new(),
                };
                ui.weak(format!("{}: {what}", p.name));
            }
            None => {
                ui.weak("Idle. STOP (Esc) ends a running demo.");
            }
        });
        if running {
            ui.ctx().request_repaint_after(std::time::Duration::from_millis(100));
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
            let cmd = MotionCommand::MoveJoints {
                goal_rad: w.goal.clone(),
                speed_fraction: w.speed_fraction,
                profile: w.kind,
            };
            sim.apply(SimCommand::Motion(cmd))
                .unwrap_or_else(|e| panic!("{} waypoint {} refused: {e}", demo.name, i + 1));
            let mut steps = 0;
            loop {
                sim.step();
                steps += 1;
                let s = sim.snapshot();
                if !s.moving && w.goal.iter().zip(&s.q).all(|(g, q)| (g - q).abs() < 0.5f64.to_radians()) {
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
    fn pick_and_place_keeps_j1_out_of_the_red_zone() {
        let model = RobotModel::parol6();
        let t = parol6_core::limits::ZoneThresholds::default();
        let demos = parol6_demos();
        let pp = demos.iter().find(|d| d.name == "Pick & place").expect("demo");
        let j1 = model.limits.get(0).expect("J1");
        for w in &pp.waypoints {
            assert_ne!(
                t.zone(j1, w.goal[0]),
                parol6_core::limits::LimitZone::Critical,
                "J1 at {}°",
                w.goal[0].to_degrees()
            );
        }
    }

    #[test]
    fn steps_scale_the_speed() {
        let model = RobotModel::parol6();
        let d = joint_sweep(&model, 0.8);
        let steps = d.steps(0.5);
        assert_eq!(steps.len(), d.waypoints.len());
        assert!(steps.iter().all(
            |s| matches!(s, MotionCommand::MoveJoints { speed_fraction, .. } if (*speed_fraction - 0.4).abs() < 1e-12)
        ));
    }
}
