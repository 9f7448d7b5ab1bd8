//! The eframe application (`layout`, `link`, `settings_store`, `test_hooks`, `frame_reuse`: see
//! ARCHITECTURE.md): owns the simulation, the optional serial session, the 3D viewport and the panels. Reads one snapshot per frame, lets the panels queue [`AppCommand`]s and
//! executes them after the UI pass. Rendering never waits on physics (the snapshot is a
//! lock-free `Arc`) and repaints are requested only while something moves or the link is live.
//!
//! [`Parol6App::frame`] is the whole UI of one frame; the window ([`eframe::App`]) and the
//! offscreen renderer ([`crate::ui_screenshot`]) both call it.

use eframe::egui;
use std::sync::{Arc, atomic::AtomicI32};
use std::time::{Duration, Instant};
use std::{collections::VecDeque, path::PathBuf};

use anyhow::Context as _;
use eframe::egui_wgpu;
use parol6_core::RobotModel;
use parol6_core::motion::MotionCommand;
use parol6_core::program::runner::ProgramRunner;
use parol6_core::sim::{SimCommand, SimConfig, SimHandle};

use crate::panels::registry::Panels;
use crate::panels::{AppCommand, Notice, PanelContext, PerfStats, READOUT_HZ, RobotState, Settings};
use crate::viewport::Viewport;

mod access;
mod click_after_typing;
mod command_kinds;
mod escape;
mod execute;
pub mod file_menu;
pub(crate) mod frame_reuse;
mod icon;
mod layout;
mod link;
mod live_share;
mod lower_dock;
pub mod measurement;
mod panel_groups;
mod perf;
mod quit;
pub mod remembered;
mod replay;
mod scene;
pub mod settings;
mod settings_store;
mod soak;
pub mod state;
pub mod super_key;
mod telemetry;
mod test_hooks;
#[cfg(test)]
mod tests;

pub use file_menu::FileMenu;
pub use icon::window_icon;
pub use layout::{FLOATING_WINDOW_POS, LEFT_PANEL_WIDTH, RIGHT_PANEL_WIDTH};
use link::HwLink;
pub use link::TITLE_SIMULATION;
pub use replay::read_replay;
pub use settings_store::{load_settings, settings_path};
pub use telemetry::link_health;
use test_hooks::Hook;
pub use test_hooks::TestScript;

/// Window title.
pub const WINDOW_TITLE: &str = "PAROL6 Studio";
/// Notices disappear after this long.
/// A program's outcome when the operator disconnected the robot while it ran.
const RUN_DISCONNECTED: &str = "the operator disconnected the robot";
const NOTICE_TTL: Duration = Duration::from_secs(8);
/// After any command, keep repainting this long so its effect (or refusal) shows up.
const COMMAND_REPAINT_WINDOW: Duration = Duration::from_millis(600);
/// Freed memory is handed back to the system this long after start-up and after a replay is
/// opened or closed, once the frames that follow have left their garbage (on a software
/// rasterizer, shader compilation alone leaves ~10 MB freed but resident).
const RELEASE_MEMORY_AFTER: Duration = Duration::from_secs(2);
/// While idle, repaint this seldom, so the status figures stay true. A frame costs ~15 ms of
/// CPU on a software rasterizer even when only the status bar changed (the UI pass, and
/// handing the whole window to the display), so idle means one frame every two seconds.
const IDLE_REPAINT: Duration = Duration::from_secs(2);
/// While the serial link is open and the arm is still, repaint this often: enough for the
/// link, E-stop and homing LEDs and the link health figures (the session itself reacts to the
/// E-stop within one period, whatever the UI does). Faster idle repaints would compete with
/// the serial thread for the CPU on software-rendered machines. Motion repaints continuously.
const LINK_REPAINT: Duration = Duration::from_millis(100);
/// Jog refresh period (the session's dead-man is 200 ms).
const JOG_REFRESH: Duration = Duration::from_millis(60);
/// A ghost is drawn only when the target differs from the pose by more than this (rad).
const GHOST_MIN_DIFF_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// Which robot to connect to at start.
#[derive(Debug, Clone, PartialEq)]
pub enum ConnectTarget {
    /// A serial port.
    Port(String),
    /// The built-in controller emulator.
    Emulator,
}

/// What the app starts with.
#[derive(Debug, Clone)]
pub struct LaunchOptions {
    /// The robot.
    pub model: RobotModel,
    /// Connect to a controller at start.
    pub connect: Option<ConnectTarget>,
    /// Settings file (`None`: defaults, nothing saved).
    pub settings_path: Option<PathBuf>,
    /// Test hook (see [`TestScript::from_env`]).
    pub test_script: Option<TestScript>,
    /// When the process started (for the cold-start report).
    pub started: Instant,
    /// MSAA sample count of the render target the 3D view draws into (the window's).
    pub msaa_samples: u32,
    /// Record the backend the window opens on to this MCAP file (`--record`).
    pub record: Option<PathBuf>,
    /// Open this recording, read already (path, data, seconds it took), for replay at start
    /// (`parol6 replay FILE`).
    pub replay: Option<(PathBuf, parol6_core::telemetry::ReplayData, f64)>,
    /// Tool and URDF text written into recordings.
    pub recording_info: parol6_core::telemetry::RecordingInfo,
}

/// The application state.
pub struct Parol6App {
    model: RobotModel,
    sim: Arc<SimHandle>,
    hw: Option<HwLink>,
    /// The running (or last) program, on the backend that was active when it started.
    program: Option<ProgramRunner>,
    /// What ended the running program by the operator's hand (Disconnect, E-STOP): its outcome
    /// says so, once, instead of the refusals of the link going down or of a disabled controller.
    run_ended_by: Option<&'static str>,
    /// What the panels read (the open recording, the program's progress, the file being
    /// written, the link): changed here only, on their [`AppCommand`]s.
    state: state::AppState,
    /// The jog being held: joint, direction, when the jog command was last sent.
    jog_held: Option<(usize, i8, Instant)>,
    /// The Cartesian jog being held: the command and when it was last sent.
    cartesian_jog_held: Option<(MotionCommand, Instant)>,
    /// The E-stop button latched: motion commands are refused until it is released.
    estop: bool,
    /// The floor rule of manual motions (pre-flight's), built on first use (`execute`).
    floor_guard: std::sync::OnceLock<parol6_core::collision::CollisionGuard>,
    /// Refusal id last shown, per backend name.
    last_refusal_seen: std::collections::HashMap<String, u64>,
    viewport: Option<Viewport>,
    viewport_error: Option<String>,
    settings: Settings,
    /// The tracking mode the simulation was last given.
    sim_tracking: parol6_core::motion::tracking::TrackingMode,
    settings_path: Option<PathBuf>,
    /// The window title last sent (robot or simulation, see `link::source_marks`).
    window_title: Option<String>,
    /// Writes the settings when they change (none without a settings file).
    autosave: Option<settings_store::SettingsAutosave>,
    /// The operator panels (see [`crate::panels::registry`]).
    panels: Panels,
    perf: PerfStats,
    /// Readout state and perf figures, and when they were taken (see `PanelContext::readout`).
    readout: Option<(Instant, RobotState, PerfStats)>,
    frame_starts: VecDeque<Instant>,
    notices: Vec<Notice>,
    commands: Vec<AppCommand>,
    repaint_until: Instant,
    /// The test, sweep or soak script run in the window (`PAROL6_TEST_SCRIPT`), if any.
    hook: Option<Hook>,
    /// The Super key's state on X11, in the window only ([`super_key`]).
    #[cfg(target_os = "linux")]
    super_key: Option<super_key::SuperKeyProbe>,
    click_after_typing: click_after_typing::ClickAfterTyping,
    exit_code: Arc<AtomicI32>,
    started: Instant,
    show_help: bool,
    /// Where the 3D view was laid out last (Esc over it is STOP, see `escape`).
    view_rect: Option<egui::Rect>,
    /// Telemetry of the simulation (its live view feeds the plots while no robot is connected).
    sim_recorder: Option<parol6_core::telemetry::Recorder>,
    /// Program step last passed to the recorder.
    last_program_step: Option<Option<usize>>,
    recording_info: parol6_core::telemetry::RecordingInfo,
    /// A recording being read for replay.
    replay_loading: Option<replay::ReplayLoading>,
    /// The File menu.
    files: FileMenu,
    /// When to hand freed memory back to the system (after the first frames, a replay opened or closed).
    release_memory_at: Option<Instant>,
    /// Frame reuse, when installed in the egui context (see [`frame_reuse`]).
    frame_reuse: Option<frame_reuse::FrameReuse>,
    /// Last input seen (frames are reused only after a quiet spell).
    input_at: Instant,
    /// The ghost the panels asked for in the last full frame (kept while frames are reused).
    kept_preview: Option<Vec<f64>>,
    /// The last commands that set the arm moving, oldest first (see [`Parol6App::moves_sent`]).
    moves_sent: VecDeque<String>,
    /// The "unsaved changes: save before quitting?" question is shown (see `quit`).
    quit_prompt: bool,
    /// Ctrl+Q with nothing to ask: the window closes at the end of this frame.
    close_now: bool,
    /// The operator chose to quit (saved or discarded): the window closes without asking.
    quit_closing: bool,
    /// Live sharing (Foxglove WebSocket) and the remote-control switch.
    live: live_share::LiveShare,
}

impl Parol6App {
    /// Builds the app: spawns the simulation, creates the 3D viewport on `render_state` (a
    /// plain placeholder without one), connects to a controller if asked.
    pub fn new(opts: LaunchOptions, render_state: Option<&egui_wgpu::RenderState>) -> anyhow::Result<Self> {
        let model = opts.model;
        let sim_recorder = telemetry::start_recorder(&model);
        let tap = sim_recorder.as_ref().map(parol6_core::telemetry::Recorder::tap);
        let settings = load_settings(opts.settings_path.as_deref());
        let sim_config = SimConfig { tracking: settings.tracking, ..SimConfig::default() };
        let sim =
            Arc::new(SimHandle::spawn_with_tap(model.clone(), sim_config, tap).context("starting the simulation")?);
        let (viewport, viewport_error) = match render_state {
            Some(rs) => match Viewport::with_target(rs, &model, opts.msaa_samples, Some(crate::viewport::DEPTH_FORMAT))
            {
                Ok(mut v) => {
                    v.options = settings.view;
                    (Some(v), None)
                }
                Err(e) => (None, Some(format!("3D view unavailable: {e}"))),
            },
            None => (None, Some("3D view unavailable: no wgpu renderer".to_string())),
        };
        let mut app = Self {
            panels: Panels::new(&model),
            model,
            sim,
            hw: None,
            program: None,
            run_ended_by: None,
            state: state::AppState::default(),
            jog_held: None,
            cartesian_jog_held: None,
            estop: false,
            floor_guard: std::sync::OnceLock::new(),
            last_refusal_seen: std::collections::HashMap::new(),
            viewport,
            viewport_error,
            sim_tracking: settings.tracking,
            window_title: None,
            #[cfg(target_os = "linux")]
            super_key: None,
            click_after_typing: Default::default(),
            autosave: opts.settings_path.clone().and_then(|p| {
                settings_store::SettingsAutosave::start(p, &settings)
                    .map_err(|e| tracing::warn!("settings will be saved at exit only: {e}"))
                    .ok()
            }),
            settings,
            settings_path: opts.settings_path,
            perf: PerfStats::default(),
            readout: None,
            frame_starts: VecDeque::new(),
            notices: Vec::new(),
            commands: Vec::new(),
            repaint_until: Instant::now() + COMMAND_REPAINT_WINDOW,
            hook: opts.test_script.map(Hook::new),
            exit_code: Arc::new(AtomicI32::new(0)),
            started: opts.started,
            show_help: false,
            view_rect: None,
            sim_recorder,
            last_program_step: None,
            recording_info: opts.recording_info,
            replay_loading: None,
            files: FileMenu::default(),
            release_memory_at: Some(Instant::now() + RELEASE_MEMORY_AFTER),
            frame_reuse: None,
            input_at: Instant::now(),
            kept_preview: None,
            moves_sent: VecDeque::new(),
            quit_prompt: false,
            close_now: false,
            quit_closing: false,
            live: live_share::LiveShare::new(),
        };
        if let Some(w) = app.viewport.as_ref().map(|v| v.warnings().to_vec()) {
            for w in w {
                app.notice(format!("3D view: {w}"), true);
            }
        }
        for w in &app.model.warnings {
            let text = format!("model: {w}");
            Notice::raise(&mut app.notices, text, false);
        }
        if let Some(target) = opts.connect {
            app.connect(&target);
        }
        if let Some(path) = opts.record {
            app.start_file_recording(&path);
            if app.state.recording.is_none() {
                anyhow::bail!("--record {}: the recording did not start (see the notice above)", path.display());
            }
        }
        app.restore_remembered();
        if let Some((path, data, read_s)) = opts.replay {
            app.open_loaded_recording(path, data, read_s);
        }
        Ok(app)
    }

    fn notice(&mut self, text: impl Into<String>, error: bool) {
        let text = text.into();
        if error {
            tracing::warn!("{text}");
        }
        Notice::raise(&mut self.notices, text, error);
    }

    fn connect(&mut self, target: &ConnectTarget) {
        self.disconnect();
        match HwLink::connect(target, &self.model, self.settings.tracking) {
            Ok(link) => {
                let what = match target {
                    ConnectTarget::Port(p) => format!("opened {p}: waiting for the controller to answer"),
                    ConnectTarget::Emulator => "started the built-in emulator: waiting for it to answer".to_string(),
                };
                self.notice(what, false);
                self.plots_take_rows_before_switch();
                self.hw = Some(link);
                // the plots now take the robot's rows: the simulation's would never be drawn
                self.sim_recorder.as_ref().inspect(|r| r.keep_live_rows(false));
                self.latch_the_new_backend();
            }
            Err(e) => self.notice(format!("connect failed: {e:#}"), true),
        }
    }

    fn disconnect(&mut self) {
        if self.program_running() && self.hw.is_some() {
            self.run_ended_by = Some(RUN_DISCONNECTED);
        }
        self.stop_program();
        if self.state.recording.as_ref().is_some_and(|r| r.on_robot) {
            self.stop_file_recording();
        }
        self.plots_take_rows_before_switch();
        if let Some(link) = self.hw.take() {
            // Hand the view back to the simulation where the robot last was (when that pose
            // is valid), so the arm does not jump back to its pose from before connecting.
            let measured = link.session.snapshot();
            let q = if measured.status.is_some() && self.model.limits.contains(&measured.joint_rad) {
                measured.joint_rad.to_vec()
            } else {
                self.sim.snapshot().q.clone()
            };
            self.plots_take_the_last_rows_of(link);
            self.sim_recorder.as_ref().inspect(|r| r.keep_live_rows(true));
            if let Err(e) = self.sim.send(SimCommand::Teleport(q)) {
                self.notice(format!("simulation: {e}"), true);
            }
            self.latch_the_new_backend();
        }
    }

    /// Ends a running program at once (STOP): its thread schedules nothing more; the caller
    /// holds the arm with a STOP to the backend.
    fn stop_program(&mut self) {
        if let Some(r) = &self.program {
            r.abort();
        }
    }

    fn keyboard(&mut self, ctx: &egui::Context, arm_moving: bool) {
        use crate::panels::shortcuts::{self, Action};
        // the held jog keys see this frame's key presses before any panel consumes one; the
        // Cartesian jog keys act only with the pointer over the 3D view
        shortcuts::note_pass_start(ctx);
        shortcuts::set_pointer_over_view(ctx, self.pointer_over_view(ctx));
        shortcuts::update_held(ctx);
        self.refuse_held_jog_keys(ctx);
        // Esc closes the topmost dialog where nothing moves and the 3D view or a motion
        // control does not have it (`escape`); else it is STOP
        let closes = self.escape_closes(ctx, arm_moving);
        let esc = shortcuts::pressed(ctx, Action::Stop);
        let home = shortcuts::pressed(ctx, Action::Home);
        let quit = shortcuts::pressed(ctx, Action::Quit) || std::mem::take(&mut self.files.quit_clicked);
        let help = shortcuts::pressed(ctx, Action::ToggleHelp);
        match (esc, closes) {
            (true, Some(what)) => self.close_on_escape(ctx, what),
            (true, None) => self.commands.push(AppCommand::Motion(MotionCommand::Stop)),
            (false, _) => {}
        }
        if home {
            let (speed_fraction, profile) = (self.settings.speed_fraction, self.settings.profile.kind());
            self.commands.push(AppCommand::Motion(MotionCommand::Home { speed_fraction, profile }));
        }
        self.quit_requests(ctx, quit);
        self.show_help ^= help;
    }

    /// Draws one frame of the whole UI into `ui` and executes the commands it produced.
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        if self.settings.tracking != self.sim_tracking {
            // the simulation takes a new tracking mode at once; the robot at its next connection
            self.sim_tracking = self.settings.tracking;
            if let Err(e) = self.sim.send(SimCommand::SetTracking(self.settings.tracking)) {
                self.notice(format!("tracking mode: {e}"), true);
            }
        }
        let t0 = Instant::now();
        let ctx = ui.ctx().clone();
        crate::theme::install_fonts(&ctx);
        let snap = self.sim.snapshot();
        self.update_perf(t0, &snap);

        self.state.link = self.hw.as_ref().map(|l| l.view(&l.session.snapshot()));
        self.state.torque_run = snap.torque_run && self.hw.is_none();
        self.link_notices();
        let live_arc = self.robot_state();
        self.source_marks(&ctx, live_arc.source);
        self.refusal_notices(&live_arc);
        self.feed_telemetry(&live_arc);
        self.live_share_frame();
        if let Some(autosave) = &mut self.autosave {
            autosave.frame(&self.settings);
        }
        let replay_playing = self.replay_frame(t0);
        // during replay every read-out shows the recording at the cursor (`state::AppState::replayed_robot`)
        // the window repaints and reuses frames by the live arm's motion, as before replay
        let live_moving = live_arc.moving;
        let robot_arc = match self.state.replayed_robot(&self.model, &live_arc) {
            Some(recorded) => Arc::new(recorded),
            None => Arc::clone(&live_arc),
        };
        let robot: &RobotState = &robot_arc;
        if let Some(run) = &self.program {
            let mut p = run.progress();
            if let Some(why) = self.run_ended_by.filter(|_| p.state.is_finished()) {
                p.state = parol6_core::program::runner::RunState::Failed(why.into());
                p.stop_failed = None;
            }
            if let parol6_core::program::runner::RunState::Failed(why) = &p.state
                && self.state.program.as_ref().map(|q| &q.state) != Some(&p.state)
            {
                self.notice(format!("{} stopped: {why}", p.name), true);
            }
            if let Some(failure) = &p.stop_failed
                && self.state.program.as_ref().and_then(|q| q.stop_failed.as_ref()) != Some(failure)
            {
                self.notice(format!("{}: {failure}", p.name), true);
            }
            self.state.program = Some(p);
        }
        self.state.measurement.collect();
        self.sweep_step(&ctx, t0, live_moving);
        self.soak_step(&ctx, t0);
        if self.release_memory_at.is_some_and(|at| t0 >= at) {
            self.release_memory_at = None;
            parol6_core::process::release_freed_memory();
        }

        self.keyboard(&ctx, live_moving);
        self.notices.retain(|n| n.at.elapsed() < NOTICE_TTL);

        let refresh = match &self.readout {
            None => true,
            Some((at, shown, _)) => {
                !robot.moving || shown.source != robot.source || at.elapsed().as_secs_f64() >= 1.0 / READOUT_HZ
            }
        };
        if refresh {
            self.readout = Some((t0, robot.clone(), self.perf.clone()));
        }
        if self.frame_reuse.is_none() {
            self.frame_reuse = frame_reuse::FrameReuse::find(&ctx);
        }
        let partial = self.partial_layout(&ctx, t0, refresh, live_moving);
        let (readout, readout_perf) = match &self.readout {
            Some((_, r, p)) => (r, p),
            None => (robot, &self.perf),
        };
        let mut preview: Option<Vec<f64>> = None;
        let mut commands = std::mem::take(&mut self.commands);
        let mut notices = std::mem::take(&mut self.notices);
        let mut groups = panel_groups::GroupRects::default();
        {
            let mut pctx = PanelContext {
                model: &self.model,
                robot,
                live_robot: &live_arc,
                readout,
                settings: &mut self.settings,
                commands: &mut commands,
                notices: &mut notices,
                perf: readout_perf,
                preview: &mut preview,
                app: &self.state,
                live: &self.live.status,
            };
            if let Some(Hook::Smoke(t)) = &mut self.hook {
                t.frames += 1;
                Self::test_step(t, &ctx, &mut self.panels.joints, &mut pctx, &self.exit_code, self.started);
            }
            if partial.is_none_or(|p| !p.lay_out.is_empty()) {
                let menu = layout::MenuTargets {
                    viewport: self.viewport.as_mut(),
                    settings_path: self.settings_path.as_deref(),
                    show_help: &mut self.show_help,
                    files: &mut self.files,
                };
                groups = Self::layout(ui, &mut pctx, &mut self.panels, menu, partial.as_ref());
            }
        }
        self.notices = notices;
        // a partial frame may not lay out the panel that previews a target (it changes on input,
        // which makes the frame full)
        if partial.is_none() || preview.is_some() {
            self.kept_preview = preview.clone();
        } else {
            preview = self.kept_preview.clone();
        }

        let scene = self.scene(robot, preview);
        self.central_and_reuse(ui, partial.as_ref(), groups, &scene);
        self.quit_prompt_ui(&ctx);
        crate::theme::paint_focus_ring(&ctx);
        escape::remember_focus(&ctx);

        let newest_error = |notices: &[Notice]| notices.iter().filter(|n| n.error).map(|n| n.at).max();
        let newest_error_before = newest_error(&self.notices);
        // STOP, E-STOP and HOME win over the other motions of their frame (`command_kinds::overridden`)
        let stopped = commands.iter().any(command_kinds::is_stop);
        for (i, c) in commands.iter().enumerate() {
            match command_kinds::overridden(&commands, i) {
                Some(by) => self.dropped_for(c, by),
                None => self.execute(c.clone()),
            }
        }
        if stopped {
            crate::panels::shortcuts::disarm_held(&ctx);
        }
        // an action that failed closes the menu it came from, so the error is seen, not hidden
        // under the menu (issue 32: "The File menu stays open over an error")
        if newest_error(&self.notices) != newest_error_before {
            egui::Popup::close_all(&ctx);
        }
        self.commands.clear();
        if !commands.is_empty() {
            self.repaint_until = Instant::now() + COMMAND_REPAINT_WINDOW;
        }
        self.remember();

        // Repaint policy: continuous only while something moves or the link is live.
        let busy = live_moving
            || self.program_running()
            || replay_playing
            || self.replay_loading.is_some()
            || Instant::now() < self.repaint_until;
        if busy || self.hook.is_some() {
            ctx.request_repaint();
        } else if self.hw.is_some() {
            ctx.request_repaint_after(LINK_REPAINT);
        } else {
            ctx.request_repaint_after(IDLE_REPAINT);
        }
        self.perf.ui_cpu_ms = t0.elapsed().as_secs_f64() * 1000.0;
    }
}

impl eframe::App for Parol6App {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame(ui);
    }

    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        crate::theme::clear_color()
    }

    #[cfg_attr(not(target_os = "linux"), allow(unused_variables))]
    fn raw_input_hook(&mut self, ctx: &egui::Context, raw_input: &mut egui::RawInput) {
        let typing_into_field = crate::panels::shortcuts::text_field_focused(ctx);
        if self.click_after_typing.apply(&mut raw_input.events, typing_into_field) {
            ctx.request_repaint(); // the held click, in the next frame
        }
        #[cfg(target_os = "linux")]
        if let Some(probe) = &mut self.super_key {
            let current = ctx.input(|i| i.modifiers);
            let looked = if super_key::needs_look(raw_input, ctx.input(|i| !i.keys_down.is_empty()), current) {
                probe.held().map(|held| super_key::apply_super(raw_input, held, current))
            } else {
                probe.observe()
            };
            if let Err(e) = looked {
                tracing::warn!("Super key no longer watched (X server: {e})");
                self.super_key = None;
            }
        }
    }

    fn on_exit(&mut self) {
        self.save_settings();
        self.stop_file_recording();
        self.disconnect();
    }
}
