//! What the binary's scripts, the benchmarks and the tests reach into: the exit-code slot,
//! the simulation, built-in programs to load and run, panels and figures, a teleport.

use std::sync::Arc;
use std::sync::atomic::AtomicI32;

use parol6_core::motion::RobotBackend;
use parol6_core::sim::{SimCommand, SimHandle};

use super::{Notice, Parol6App, PerfStats, Settings};

impl Parol6App {
    /// The window title last sent: robot (with its port) or simulation.
    pub fn window_title(&self) -> Option<&str> {
        self.window_title.as_deref()
    }

    /// Shares the slot where the test hook stores the process exit status (0 = success).
    pub fn set_exit_code(&mut self, slot: Arc<AtomicI32>) {
        self.exit_code = slot;
    }

    /// Watches the Super key on the window's X server (the window only; [`super::super_key`]).
    #[cfg(target_os = "linux")]
    pub fn watch_super_key(&mut self) {
        self.super_key = super::super_key::SuperKeyProbe::connect();
    }

    /// The simulation (the bench drives it).
    pub fn sim(&self) -> &SimHandle {
        &self.sim
    }

    /// Loads the built-in program called `name` and runs it on the active backend (the bench
    /// and the sweep script use it); false when there is no such program.
    pub fn start_program(&mut self, name: &str, looping: bool) -> bool {
        if !self.load_program(name) {
            return false;
        }
        self.run_program(looping);
        true
    }

    /// Loads the built-in program called `name` into the program panel (its pre-flight and
    /// planned path follow on the next frame); false when there is no such program.
    pub fn load_program(&mut self, name: &str) -> bool {
        self.panels.program.load_builtin(name)
    }

    /// Starts opening the program file `path` in the program panel, as its Open button does: read
    /// and checked from the commanded pose on a worker (`program_panel().checking()` until done).
    pub fn open_program_file(&mut self, path: &std::path::Path) -> Result<(), String> {
        let start_q = self.backend().state().commanded.q.clone();
        let abc = parol6_core::program::gcode::AbcChoice::default_to(self.settings.gcode_abc);
        self.panels.program.start_load(&self.model, path, abc, start_q)
    }

    /// Waits at most `timeout` for the program panel's load or check in flight (headless
    /// rendering wants the planned path in its first frames); true when none is left.
    pub fn wait_for_program_check(&mut self, timeout: std::time::Duration) -> bool {
        self.panels.program.wait_for_check(timeout)
    }

    /// Runs the program loaded in the program panel on the active backend.
    pub fn run_program(&mut self, looping: bool) {
        self.panels.program.looping = looping;
        let cmd = self.panels.program.run_command(false);
        self.execute(cmd);
    }

    /// The persistent settings (tests and scripts change them as the menus would).
    pub fn settings_mut(&mut self) -> &mut Settings {
        &mut self.settings
    }

    /// The persistent settings as they are now.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The 3D view's camera (`None`: no 3D view).
    pub fn view_camera(&self) -> Option<crate::viewport::OrbitCamera> {
        self.viewport.as_ref().map(|v| *v.camera())
    }

    /// Where the 3D view was laid out in the last frame.
    pub fn view_rect(&self) -> Option<eframe::egui::Rect> {
        self.view_rect
    }

    /// Shows the plots panel with `quantity` alone (as a click on its toggle does).
    pub fn show_plot(&mut self, quantity: parol6_core::telemetry::Quantity) {
        self.settings.show_plots = true;
        self.panels.plots.show_only(quantity);
    }

    /// The File menu (its recording dialog).
    pub fn file_menu(&self) -> &super::FileMenu {
        &self.files
    }

    /// The plots panel (tests read its series and the backend switches it marks).
    pub fn plots_panel(&self) -> &crate::panels::plots::PlotsPanel {
        &self.panels.plots
    }

    /// The program panel (its program, dirty state).
    pub fn program_panel(&self) -> &crate::panels::program::ProgramPanel {
        &self.panels.program
    }

    /// The program panel, to act on it as its buttons do (benchmarks and tests).
    pub fn program_panel_mut(&mut self) -> &mut crate::panels::program::ProgramPanel {
        &mut self.panels.program
    }

    /// Queues `command` as a panel's button does; it is carried out after the next frame's UI
    /// pass, inside that frame (`parol6 bench ui-actions` drives the app with it).
    pub fn queue_command(&mut self, command: crate::panels::AppCommand) {
        self.commands.push(command);
    }

    /// The Cartesian jog panel (its frame and increments).
    pub fn cartesian_jog_panel(&self) -> &crate::panels::cartesian_jog::CartesianJogPanel {
        &self.panels.cartesian_jog
    }

    /// The dynamics panel (tests read its analysis).
    pub fn dynamics_panel(&self) -> &crate::panels::dynamics::DynamicsPanel {
        &self.panels.dynamics
    }

    /// The notices shown over the 3D view now, oldest first.
    pub fn notices(&self) -> &[Notice] {
        &self.notices
    }

    /// The built-in emulator, while the window is connected to it (tests read what reached it).
    pub fn emulator(&self) -> Option<&parol6_hw::EmulatorHandle> {
        self.hw.as_ref().and_then(|l| l.emulator.as_ref())
    }

    /// True while the E-stop button is latched.
    pub fn estop_latched(&self) -> bool {
        self.estop
    }

    /// True while the help window (F1) is open.
    pub fn help_open(&self) -> bool {
        self.show_help
    }

    /// True while a controller (the robot or the built-in emulator) is connected.
    pub fn robot_connected(&self) -> bool {
        self.hw.is_some()
    }

    /// The progress of the running or last program, as of the last frame.
    pub fn program_progress(&self) -> Option<&parol6_core::program::runner::RunProgress> {
        self.state.program.as_ref()
    }

    /// True while a program runs (paused included).
    pub fn program_running(&self) -> bool {
        self.program.as_ref().is_some_and(|r| !r.is_finished())
    }

    /// The backend that motion commands go to: the robot when connected, else the simulation.
    pub fn backend(&self) -> Arc<dyn RobotBackend> {
        match &self.hw {
            Some(link) => Arc::clone(&link.session) as Arc<dyn RobotBackend>,
            None => Arc::clone(&self.sim) as Arc<dyn RobotBackend>,
        }
    }

    /// The measurement panel (its test set-up), for scripted use and tests.
    pub fn measure_panel(&mut self) -> &mut crate::panels::measure::MeasurePanel {
        &mut self.panels.measure
    }

    /// The ISO 9283 measurement the app runs (its progress and finished runs).
    pub fn measurement(&self) -> &super::measurement::MeasurementState {
        &self.state.measurement
    }

    /// The figures of the last frame.
    pub fn perf(&self) -> &PerfStats {
        &self.perf
    }

    /// Teleports the simulated arm (screenshots at given joints).
    pub fn teleport(&mut self, q: Vec<f64>) -> anyhow::Result<()> {
        self.sim.send(SimCommand::Teleport(q))?;
        Ok(())
    }

    /// The last commands (at most 256, oldest first, as `Debug` text) that set the arm moving
    /// (jogs, moves, HOME, program runs and steps, measurements, torque runs; not STOP or a jog
    /// release): what the keyboard tests watch.
    pub fn moves_sent(&self) -> impl Iterator<Item = &str> {
        self.moves_sent.iter().map(String::as_str)
    }
}
