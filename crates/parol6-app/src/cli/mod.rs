//! The `parol6` command line (clap). Every subcommand prints JSON on stdout; errors are one
//! line on stderr with a non-zero exit status (2 for bad or unsolvable input), never a panic.
//!
//! One file per area: [`kin`] (fk, ik), [`bench`] (benchmarks), [`hw`] (serial controller).

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod bench;
pub mod gui;
pub mod hw;
pub mod kin;
pub mod render;
pub mod sim;

/// Exit status for bad or unsolvable input.
pub const EXIT_USAGE: u8 = 2;

/// A command-line failure: printed as one line on stderr, mapped to an exit status.
#[derive(Debug)]
pub struct CliError {
    /// Process exit status.
    pub status: u8,
    /// The one-line message.
    pub message: String,
}

impl CliError {
    /// Bad or unsolvable input (exit status 2).
    pub fn usage(message: impl std::fmt::Display) -> Self {
        Self { status: EXIT_USAGE, message: message.to_string() }
    }

    /// A runtime failure such as an I/O or device error (exit status 1).
    pub fn runtime(message: impl std::fmt::Display) -> Self {
        Self { status: 1, message: message.to_string() }
    }
}

impl From<anyhow::Error> for CliError {
    fn from(e: anyhow::Error) -> Self {
        Self::runtime(format!("{e:#}"))
    }
}

/// Result of a subcommand.
pub type CliResult = Result<(), CliError>;

#[derive(Debug, Parser)]
#[command(name = "parol6", version, about = "PAROL6 Studio: simulate, visualise and jog the PAROL6 arm")]
#[command(args_conflicts_with_subcommands = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Window options, used when no subcommand is given (the GUI).
    #[command(flatten)]
    pub gui: gui::GuiArgs,
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
}

/// Prints `value` as one line of JSON on stdout.
pub fn print_json(value: &serde_json::Value) {
    println!("{value}");
}

/// Entry point used by `main.rs`.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { ExitCode::from(EXIT_USAGE) } else { ExitCode::SUCCESS };
        }
    };
    let result = match cli.command {
        None => gui::run(&cli.gui),
        Some(Command::Fk(a)) => kin::run_fk(&a),
        Some(Command::Ik(a)) => kin::run_ik(&a),
        Some(Command::Bench(a)) => bench::run(&a),
        Some(Command::Hw(a)) => hw::run(&a),
        Some(Command::Screenshot(a)) => render::run_screenshot(&a),
        Some(Command::Dynamics(a)) => sim::run_dynamics(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", e.message);
            ExitCode::from(e.status)
        }
    }
}
