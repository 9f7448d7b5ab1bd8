//! The runner's public types: operator controls, run states, progress and options.

/// Operator controls.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunnerControl {
    /// Slow to a stop on the path.
    Pause,
    /// Go on (after a pause or a single step).
    Resume,
    /// Run the next step (or finish the current one), then pause.
    Step,
    /// Pause, then hold and end the run.
    Stop,
}

/// Where a run is.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum RunState {
    /// Compiling and checking before anything moves.
    Preparing,
    /// Running.
    Running,
    /// Paused by the operator (or after a single step).
    Paused,
    /// Every step done.
    Done,
    /// Stopped by the operator.
    Stopped,
    /// Refused or halted; the reason.
    Failed(String),
}

impl RunState {
    /// True once the run has ended.
    pub fn is_finished(&self) -> bool {
        matches!(self, RunState::Done | RunState::Stopped | RunState::Failed(_))
    }
}

/// Progress of a run, published by its thread.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RunProgress {
    /// Program name.
    pub name: String,
    /// 0-based program step under way (or the last one).
    pub step: usize,
    /// Number of program steps.
    pub steps: usize,
    /// State.
    pub state: RunState,
    /// What the run waits for, if anything ("input 1 high").
    pub waiting_for: Option<String>,
    /// Planned time left, s (waits for inputs not counted).
    pub time_left_s: f64,
    /// Planned duration of the whole program, s.
    pub planned_s: f64,
    /// Program steps completed.
    pub steps_done: usize,
    /// Largest commanded − measured joint difference seen while running, rad.
    pub max_tracking_error_rad: f64,
    /// Motion clock when the first step starts and at the end of the run, s.
    pub clock_s: (f64, f64),
    /// Completed passes of a looping run.
    pub passes: u64,
    /// CPU time the runner thread used while executing (checking and planning excluded), s;
    /// `None` where the OS does not report per-thread CPU time.
    pub runner_cpu_s: Option<f64>,
    /// How much later than planned the steps ran, s: steps handed over to the backend after
    /// their time (a busy machine, a fast headless simulation) make the schedule slip rather
    /// than fail; 0 when every step was on time.
    pub schedule_slip_s: f64,
    /// A STOP this run sent that the backend refused (what it stopped, and why it failed);
    /// `None` when every STOP was taken. The arm may not have stopped.
    pub stop_failed: Option<String>,
    /// Pre-flights this run ran itself: 0 when it reused the [`CheckedProgram`] it was given
    /// (started from the joints that program was checked from), one per pass otherwise.
    ///
    /// [`CheckedProgram`]: crate::program::check::CheckedProgram
    #[serde(skip)]
    pub preflights_run: usize,
}

/// How to run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunOptions {
    /// Every step's speed × this (0 < f ≤ 1).
    pub speed_override: f64,
    /// Start paused after the first step (single-step mode).
    pub single_step: bool,
    /// Start over after the last step (each pass is checked and planned again from where
    /// the arm is). A program with [`Program::looping`](crate::program::Program::looping) set loops either way.
    pub looping: bool,
    /// Optional pauses (`pause` steps with `optional`, G-code `M1`) pause the run too.
    pub optional_pauses: bool,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self { speed_override: 1.0, single_step: false, looping: false, optional_pauses: false }
    }
}
