//! The panel registry: every operator panel, where it is docked and in which order. The
//! layout ([`crate::app`]) walks [`Panels::docked`] (pure: it only lists them); adding a panel is
//! a field here and one line in that list. What one panel takes from another or from the app's
//! data (the program to analyse, the recording or live samples to plot) is handed over in
//! [`Panels::prepare`], once per frame, before the layout.

use std::sync::Arc;

use parol6_core::RobotModel;
use parol6_core::telemetry::LiveView;

use crate::app::state::AppState;
use crate::viewport::PathOverlay;

use super::Panel;
use super::cartesian_jog::CartesianJogPanel;
use super::cartesian_target::CartesianTargetPanel;
use super::connection::ConnectionPanel;
use super::dynamics::DynamicsPanel;
use super::io_gripper::IoGripperPanel;
use super::joints::JointsPanel;
use super::measure::MeasurePanel;
use super::plots::PlotsPanel;
use super::program::ProgramPanel;
use super::status_bar::StatusBar;
use super::tcp::TcpPanel;
use super::timeline::TimelinePanel;

/// Where a panel sits in the window.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dock {
    /// The left column (joints, HOME / STOP, program, I/O and gripper, connection).
    Left,
    /// The right column (TCP, Cartesian jog, Cartesian target).
    Right,
    /// The status bar at the bottom.
    Bottom,
    /// Under the 3D view, between the columns, resizable: the replay timeline, on top (each
    /// shown when [`super::Panel::shown`] says so).
    Lower,
    /// In the same panel below the [`Dock::Lower`] ones, sharing the place: the plots and the
    /// dynamics, side by side where the panel is wide enough, else in tabs.
    LowerShared,
}

/// All operator panels. The named fields give the app typed access where it needs it (the
/// test hook drives the joints panel, the bench starts programs).
pub struct Panels {
    /// Joints: sliders, typed entries, HOME / STOP.
    pub joints: JointsPanel,
    /// Serial link to the robot.
    pub connection: ConnectionPanel,
    /// Outputs, inputs, the gripper, Clear error.
    pub io_gripper: IoGripperPanel,
    /// TCP pose and manipulability.
    pub tcp: TcpPanel,
    /// Cartesian target solved by IK.
    pub target: CartesianTargetPanel,
    /// Cartesian jog (world / tool frame, hold or step).
    pub cartesian_jog: CartesianJogPanel,
    /// Programs: built-in and files, pre-flight, run / pause / step / stop.
    pub program: ProgramPanel,
    /// ISO 9283 measurement: cube, pre-flight, run / abort, figures, report.
    pub measure: MeasurePanel,
    /// Status bar.
    pub status: StatusBar,
    /// Replay timeline of an open recording.
    pub timeline: TimelinePanel,
    /// Plots of the live telemetry or of the open recording.
    pub plots: PlotsPanel,
    /// Inverse dynamics of the program, forward dynamics on the simulation.
    pub dynamics: DynamicsPanel,
}

impl Panels {
    /// The panels for `model`.
    pub fn new(model: &RobotModel) -> Self {
        Self {
            joints: JointsPanel::default(),
            connection: ConnectionPanel::default(),
            io_gripper: IoGripperPanel::default(),
            tcp: TcpPanel::default(),
            target: CartesianTargetPanel::default(),
            cartesian_jog: CartesianJogPanel::default(),
            program: ProgramPanel::new(model),
            measure: MeasurePanel::default(),
            status: StatusBar,
            timeline: TimelinePanel::default(),
            plots: PlotsPanel::new(model.dof()),
            dynamics: DynamicsPanel::new(model.dof()),
        }
    }

    /// Hands the panels what they follow, once per frame before the layout: the dynamics panel
    /// the program panel's program, the plots the open recording and its cursor (or, with
    /// `live`, the new live samples).
    pub fn prepare(&mut self, state: &AppState, live: Option<&LiveView>) {
        self.dynamics.set_program(self.program.program());
        self.plots.set_replay(state.replay.as_ref().map(|r| (Arc::clone(&r.data), r.cursor_s)));
        if let Some(view) = live {
            // the live view is the robot's while connected (`AppState::link`), else the simulation's
            self.plots.feed_live(view, state.link.is_some());
        }
    }

    /// The path drawn in the 3D view: the measurement's cube (not during replay) or the loaded
    /// program's planned path (kept during replay, to compare with the recorded motion).
    pub fn planned_path(&self, replaying: bool) -> Option<Arc<PathOverlay>> {
        let cube = if replaying { None } else { self.measure.overlay() };
        cube.or_else(|| self.program.overlay())
    }

    /// Every panel with its dock, top to bottom within a dock.
    pub fn docked(&mut self) -> Vec<(Dock, &mut dyn Panel)> {
        vec![
            (Dock::Left, &mut self.joints),
            (Dock::Left, &mut self.program),
            (Dock::Left, &mut self.io_gripper),
            // last: it folds and unfolds, which moves nothing below it
            (Dock::Left, &mut self.connection),
            (Dock::Right, &mut self.tcp),
            (Dock::Right, &mut self.cartesian_jog),
            (Dock::Right, &mut self.target),
            (Dock::Right, &mut self.measure),
            (Dock::Bottom, &mut self.status),
            (Dock::Lower, &mut self.timeline),
            (Dock::LowerShared, &mut self.plots),
            (Dock::LowerShared, &mut self.dynamics),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_panel_is_docked_once_with_a_title() {
        let mut panels = Panels::new(&RobotModel::parol6());
        let list = panels.docked();
        let titles: Vec<&str> = list.iter().map(|(_, p)| p.title()).collect();
        let mut unique = titles.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), titles.len(), "{titles:?}");
        assert_eq!(list.iter().filter(|(d, _)| *d == Dock::Bottom).count(), 1, "one status bar");
        assert_eq!(list.first().map(|(d, p)| (*d, p.title())), Some((Dock::Left, "Joints")));
    }
}
