//! The backends a measurement runs on, opened the way `parol6 program run` opens them: the
//! headless simulation (dynamic, [`HEADLESS_TIME_SCALE`]) or the controller (`--port`, or the
//! emulator with `--fake-robot`) through `open`; a progress bar on a terminal while a
//! measurement runs (nothing when stderr is piped).

use std::io::IsTerminal;
use std::sync::Arc;
use std::time::Duration;

use crossbeam_channel::{Receiver, Sender};
use parol6_core::RobotModel;
use parol6_core::measure::driver::{MeasureError, MeasureRun};
use parol6_core::motion::tracking::TrackingMode;
use parol6_core::motion::{MotionSample, RobotBackend};
use parol6_core::sim::{SimConfig, SimHandle, SimMode};
use parol6_hw::emulator::EmulatorHandle;

use super::CliError;
use super::common::{RateArgs, open};
use super::options::ConnectArgs;
use super::program::HEADLESS_TIME_SCALE;

/// Capacity of the sample tap of a path test (drained every 5 ms).
const TAP_CAPACITY: usize = 1 << 16;

/// An open backend; the emulator (if any) outlives the session in front of it.
pub struct Opened {
    /// The backend.
    pub backend: Arc<dyn RobotBackend>,
    /// Its sample tap.
    pub tap: Option<Receiver<MotionSample>>,
    /// "simulation", "robot on /dev/ttyACM0", …
    pub name: String,
    _emulator: Option<EmulatorHandle>,
}

impl Opened {
    /// The headless simulation of `model`, with a sample tap when `tapped`.
    pub fn simulation(model: &RobotModel, tapped: bool, tracking: TrackingMode) -> Result<Self, CliError> {
        let (tx, rx) = tap(tapped);
        let config =
            SimConfig { mode: SimMode::Dynamic, time_scale: HEADLESS_TIME_SCALE, tracking, ..SimConfig::default() };
        let sim = SimHandle::spawn_with_tap(model.clone(), config, tx).map_err(CliError::usage)?;
        Ok(Self { backend: Arc::new(sim), tap: rx, name: "simulation".into(), _emulator: None })
    }

    /// The controller of `connect`, its TCP the tool tip of `model`.
    pub fn robot(model: &RobotModel, connect: &ConnectArgs, rate: &RateArgs, tapped: bool) -> Result<Self, CliError> {
        let (tx, rx) = tap(tapped);
        let link = open(connect, rate, tx, model.tool)?;
        let session = Arc::new(link.session);
        let name = session.state().backend.clone();
        Ok(Self { backend: session, tap: rx, name, _emulator: link.emulator })
    }

    /// The robot when `connect` names one, else the simulation.
    pub fn from_args(
        model: &RobotModel,
        connect: &ConnectArgs,
        rate: &RateArgs,
        tapped: bool,
    ) -> Result<Self, CliError> {
        if connect.port.is_some() || connect.fake_robot {
            Self::robot(model, connect, rate, tapped)
        } else {
            Self::simulation(model, tapped, rate.tracking.unwrap_or_default())
        }
    }
}

fn tap(tapped: bool) -> (Option<Sender<MotionSample>>, Option<Receiver<MotionSample>>) {
    if tapped {
        let (tx, rx) = crossbeam_channel::bounded(TAP_CAPACITY);
        (Some(tx), Some(rx))
    } else {
        (None, None)
    }
}

/// Waits for `run` with a progress bar on a terminal (quiet when stderr is not one), then
/// returns its result as a command-line error: a refusal before moving exits 2, the rest 1;
/// SIGINT / SIGTERM abort the run (the arm stops) and exit 130.
pub fn wait<T: Send + 'static>(run: MeasureRun<T>, label: &str) -> Result<T, CliError> {
    let bar = std::io::stderr().is_terminal().then(|| {
        let bar = indicatif::ProgressBar::new(1000);
        if let Ok(style) =
            indicatif::ProgressStyle::with_template("{prefix} [{bar:30}] {percent:>3}% {msg} ({elapsed})")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_prefix(label.to_string());
        bar
    });
    while !run.is_finished() {
        if super::interrupt::sleep(Duration::from_millis(50)) {
            // stops the arm; the backend closes when the caller drops it (the robot: IDLE)
            run.abort();
            break;
        }
        if let Some(b) = &bar {
            let p = run.progress();
            b.set_position((p.fraction * 1000.0).round() as u64);
            b.set_message(p.describe());
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    // after an abort the thread sends STOP and ends within a few milliseconds
    while !run.is_finished() {
        std::thread::sleep(Duration::from_millis(5));
    }
    if let Some(failure) = &run.progress().stop_failed {
        super::warn(format!("{label}: {failure}"));
    }
    run.join().map_err(|e| match e {
        _ if super::interrupt::requested() => super::interrupt::error(format!("{label}: the arm stopped")),
        MeasureError::Plan(p) => CliError::usage(format!("{label}: {p}")),
        other => CliError::runtime(format!("{label}: {other}")),
    })
}
