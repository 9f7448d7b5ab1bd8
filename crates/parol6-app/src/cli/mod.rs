//! The `parol6` command line (clap). Every subcommand prints JSON on stdout; errors are one
//! line on stderr, never a panic. Exit status: 0 success, 2 bad input or a refused request
//! ([`EXIT_USAGE`]), 1 device or I/O failure, 130 interrupted by SIGINT or SIGTERM
//! ([`interrupt`]: motion stopped, recording closed, the JSON printed with `"interrupted"`).
//! A closed stdout (`parol6 … | head`) ends the command quietly with status 0.
//!
//! One file per area: [`kin`] (fk, ik), [`bench`](mod@bench) (benchmarks), [`hw`] (serial controller;
//! [`hw_stop`]: how it ends on a signal),
//! [`render`] (screenshots), [`sim`] (dynamics, simulation benchmarks), [`gui`] (the window),
//! [`record`] (recording to MCAP), [`mcap`] (reading recordings), [`options`] (shared options
//! and range checks), [`output`] (stdout/stderr), [`program`] (program check and run),
//! [`measure`] (ISO 9283 pose and path tests, on [`measure_backend`]), [`serve`] (live
//! serving: Foxglove WebSocket, ROS 2), [`common`] (helpers several subcommands share).

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod bench;
pub mod bench_motion;
pub mod bench_program;
pub mod bench_replay;
pub mod bench_seed;
pub mod bench_ui;
pub mod common;
pub mod gui;
pub mod hw;
pub mod hw_bench;
pub mod hw_checks;
pub mod hw_stop;
pub mod interrupt;
pub mod kin;
pub mod mcap;
pub mod measure;
pub mod measure_backend;
pub mod options;
pub mod output;
pub mod program;
pub mod program_torques;
pub mod record;
pub mod render;
pub mod render_run;
pub mod serve;
pub mod serve_ros2;
pub mod sim;

pub use output::{print_json, warn};

/// Exit status for bad or unsolvable input and refused requests.
pub const EXIT_USAGE: u8 = 2;

/// A command-line failure: printed as one line on stderr, mapped to an exit status.
#[derive(Debug)]
pub struct CliError {
    /// Process exit status.
    pub status: u8,
    /// The one-line message (empty: print nothing).
    pub message: String,
}

impl CliError {
    /// Bad or unsolvable input, or a refused request (exit status 2).
    pub fn usage(message: impl std::fmt::Display) -> Self {
        Self { status: EXIT_USAGE, message: message.to_string() }
    }

    /// A runtime failure such as an I/O or device error (exit status 1).
    pub fn runtime(message: impl std::fmt::Display) -> Self {
        Self { status: 1, message: message.to_string() }
    }

    /// Stdout was closed by the reader: end quietly with status 0.
    pub fn stdout_closed() -> Self {
        Self { status: 0, message: String::new() }
    }
}

impl From<anyhow::Error> for CliError {
    fn from(e: anyhow::Error) -> Self {
        Self::runtime(format!("{e:#}"))
    }
}

/// A file refused by type or size (a FIFO, a device, a directory, over its bound) is the
/// user's input (exit 2); a file that cannot be read or saved is an I/O failure (exit 1).
impl From<parol6_core::fsio::FsioError> for CliError {
    fn from(e: parol6_core::fsio::FsioError) -> Self {
        if e.is_refusal() { Self::usage(e) } else { Self::runtime(e) }
    }
}

/// Result of a subcommand.
pub type CliResult = Result<(), CliError>;

#[derive(Debug, Parser)]
#[command(name = "parol6", version, about = "PAROL6 Studio: simulate, visualise and jog the PAROL6 arm")]
#[command(after_help = "Without a subcommand, opens the window. Options marked global may be given before or \
                        after the subcommand. Exit status: 0 ok, 2 bad input or refused, 1 device or I/O failure, \
                        130 interrupted (Ctrl-C or SIGTERM: motion stopped, recording closed; a second one \
                        exits at once).")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Robot selection (global).
    #[command(flatten)]
    pub robot: options::RobotArgs,
    /// Controller connection (global).
    #[command(flatten)]
    pub connect: options::ConnectArgs,
    /// The window only: record the backend it opens on (the simulation, or the robot with
    /// --port / --fake-robot) to this MCAP file until the window closes.
    #[arg(long, value_name = "OUT.mcap", value_parser = options::output_file)]
    pub record: Option<std::path::PathBuf>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Forward kinematics: joint values → TCP pose (JSON).
    Fk(kin::FkArgs),
    /// Inverse kinematics: TCP pose → joint solutions (JSON), best first.
    Ik(kin::IkArgs),
    /// Benchmarks printing JSON.
    Bench(bench::BenchArgs),
    /// Talk to a PAROL6 controller over USB serial (or run the controller emulator).
    Hw(hw::HwArgs),
    /// Render the robot to a PNG with no window and no display.
    Screenshot(render::ScreenshotArgs),
    /// Inverse dynamics: joint torques (gravity + inertial + Coriolis) of a motion (JSON).
    Dynamics(sim::DynamicsArgs),
    /// Robot programs: pre-flight check and run (simulation, emulator or robot).
    Program(program::ProgramArgs),
    /// Record the simulation (default) or the controller (--port / --fake-robot) to an MCAP file.
    Record(record::RecordArgs),
    /// Read MCAP recordings: info (JSON), csv.
    Mcap(mcap::McapArgs),
    /// Open the window on a recording: the 3D view and the plots follow its timeline.
    Replay(gui::ReplayArgs),
    /// ISO 9283 pose accuracy / repeatability on the simulation (default) or the robot, or
    /// from a measurement CSV (--measurements).
    Iso9283(measure::Iso9283Args),
    /// ISO 9283 path accuracy / repeatability (line, circle, triangle in the cube's diagonal
    /// plane) on the simulation (default) or the robot.
    PathTest(measure::PathTestArgs),
    /// Serve the simulation (default) or the controller live: Foxglove WebSocket (--foxglove),
    /// ROS 2 over Zenoh (--ros2), until Ctrl-C / SIGTERM or --seconds.
    Serve(serve::ServeArgs),
}

impl Cli {
    /// The subcommand's name as typed (`"bench fk"`), for messages.
    fn command_name(&self) -> String {
        match &self.command {
            None => "parol6 (the window)".into(),
            Some(Command::Fk(_)) => "fk".into(),
            Some(Command::Ik(_)) => "ik".into(),
            Some(Command::Dynamics(_)) => "dynamics".into(),
            Some(Command::Screenshot(_)) => "screenshot".into(),
            Some(Command::Bench(b)) => format!("bench {}", b.target.name()),
            Some(Command::Hw(h)) => format!("hw {}", h.command.name()),
            Some(Command::Program(p)) => format!("program {}", p.command.name()),
            Some(Command::Record(_)) => "record".into(),
            Some(Command::Mcap(m)) => format!("mcap {}", m.command.name()),
            Some(Command::Replay(_)) => "replay".into(),
            Some(Command::Iso9283(_)) => "iso9283".into(),
            Some(Command::PathTest(_)) => "path-test".into(),
            Some(Command::Serve(_)) => "serve".into(),
        }
    }

    /// True for the commands that open a graphics adapter: the window (its own and `replay`'s)
    /// and the headless renders. Each of them gets a private `XDG_RUNTIME_DIR` where none is set
    /// ([`output::PrivateRuntimeDir`]).
    fn opens_gpu(&self) -> bool {
        match &self.command {
            None | Some(Command::Replay(_) | Command::Screenshot(_)) => true,
            Some(Command::Bench(b)) => b.target.opens_gpu(),
            Some(
                Command::Fk(_)
                | Command::Ik(_)
                | Command::Hw(_)
                | Command::Dynamics(_)
                | Command::Program(_)
                | Command::Record(_)
                | Command::Mcap(_)
                | Command::Iso9283(_)
                | Command::PathTest(_)
                | Command::Serve(_),
            ) => false,
        }
    }

    /// True for the commands that run until they end or are stopped, and stop cleanly on
    /// SIGINT / SIGTERM ([`interrupt`]); the others keep the default action (the process ends).
    pub fn stops_on_signal(&self) -> bool {
        match &self.command {
            None | Some(Command::Replay(_) | Command::Record(_) | Command::PathTest(_) | Command::Serve(_)) => true,
            Some(Command::Hw(h)) => {
                matches!(
                    h.command,
                    hw::HwCommand::Jog { .. } | hw::HwCommand::Move { .. } | hw::HwCommand::Emulate { .. }
                )
            }
            Some(Command::Program(p)) => matches!(p.command, program::ProgramCommand::Run { .. }),
            Some(Command::Iso9283(a)) => a.measurements.is_none(),
            Some(_) => false,
        }
    }

    /// Refuses global options the chosen subcommand does not use (they would be ignored).
    pub fn check_global_options(&self) -> CliResult {
        let uses_robot = match &self.command {
            None
            | Some(
                Command::Fk(_) | Command::Ik(_) | Command::Dynamics(_) | Command::Screenshot(_) | Command::Record(_),
            ) => true,
            Some(Command::Bench(b)) => matches!(b.target, bench::BenchTarget::Render(_)),
            Some(Command::Hw(_) | Command::Mcap(_)) => false,
            Some(Command::Program(_) | Command::Iso9283(_) | Command::PathTest(_) | Command::Serve(_)) => true,
            Some(Command::Replay(_)) => true,
        };
        let uses_connection = match &self.command {
            None | Some(Command::Record(_) | Command::Serve(_)) => true,
            Some(Command::Hw(h)) => h.command.talks_to_controller(),
            Some(Command::Program(p)) => p.command.talks_to_controller(),
            Some(Command::Iso9283(a)) => a.measurements.is_none(),
            Some(Command::PathTest(_)) => true,
            Some(Command::Screenshot(s)) => s.run.is_some(),
            Some(_) => false,
        };
        let unused = [
            (!uses_robot).then(|| self.robot.first_given()).flatten(),
            (!uses_connection).then(|| self.connect.first_given()).flatten(),
        ];
        if self.command.is_some() && self.record.is_some() {
            return Err(CliError::usage(format!(
                "--record before the subcommand applies to the window only; `parol6 {}` does not take it there \
                 (program run, hw jog|move and record take their own --record)",
                self.command_name()
            )));
        }
        match unused.into_iter().flatten().next() {
            Some(option) => {
                Err(CliError::usage(format!("{option} does not apply to `parol6 {}`", self.command_name())))
            }
            None => Ok(()),
        }
    }
}

/// Entry point used by `main.rs`.
pub fn main() -> ExitCode {
    parol6_core::process::limit_heap_arenas();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { ExitCode::from(EXIT_USAGE) } else { ExitCode::SUCCESS };
        }
    };
    // Before any thread exists (it sets an environment variable).
    let _runtime_dir = if cli.opens_gpu() { output::PrivateRuntimeDir::ensure() } else { None };
    let result = cli
        .check_global_options()
        .and_then(|()| if cli.stops_on_signal() { interrupt::install() } else { Ok(()) })
        .and_then(|()| run(&cli));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            if !e.message.is_empty() {
                output::error_line(&e.message);
            }
            ExitCode::from(e.status)
        }
    }
}

fn run(cli: &Cli) -> CliResult {
    match &cli.command {
        None => gui::run(&cli.robot, &cli.connect, cli.record.as_deref(), None),
        Some(Command::Replay(a)) => gui::run(&cli.robot, &cli.connect, None, Some(&a.file)),
        Some(Command::Fk(a)) => kin::run_fk(a, &cli.robot),
        Some(Command::Ik(a)) => kin::run_ik(a, &cli.robot),
        Some(Command::Bench(a)) => bench::run(a, &cli.robot),
        Some(Command::Hw(a)) => hw::run(a, &cli.connect),
        Some(Command::Screenshot(a)) => render::run_screenshot(a, &cli.robot, &cli.connect),
        Some(Command::Dynamics(a)) => sim::run_dynamics(a, &cli.robot),
        Some(Command::Program(a)) => program::run(a, &cli.robot, &cli.connect),
        Some(Command::Record(a)) => record::run(a, &cli.robot, &cli.connect),
        Some(Command::Mcap(a)) => mcap::run(a),
        Some(Command::Iso9283(a)) => measure::run_iso9283(a, &cli.robot, &cli.connect),
        Some(Command::PathTest(a)) => measure::run_path_test(a, &cli.robot, &cli.connect),
        Some(Command::Serve(a)) => serve::run(a, &cli.robot, &cli.connect),
    }
}
