//! The eframe application: owns the simulation, the optional serial session, the 3D viewport
//! and the panels. Reads one snapshot per frame, lets the panels queue [`AppCommand`]s and
//! executes them after the UI pass. Rendering never waits on physics (the snapshot is a
//! lock-free `Arc`) and repaints are requested only while something moves or the link is live.
//!
//! [`Parol6App::frame`] is the whole UI of one frame; the window ([`eframe::App`]) and the
//! offscreen renderer ([`crate::ui_screenshot`]) both call it.

use eframe::egui;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::Context as _;
use eframe::egui_wgpu;
use parol6_core::RobotModel;
use parol6_core::limits::{LimitZone, ZoneThresholds};
use parol6_core::sim::{SimCommand, SimConfig, SimHandle, SimSnapshot};

use crate::panels::cartesian_target::CartesianTargetPanel;
use crate::panels::connection::{ConnectionPanel, LinkView};
use crate::panels::demos::DemosPanel;
use crate::panels::joints::JointsPanel;
use crate::panels::status_bar::StatusBar;
use crate::panels::tcp::TcpPanel;
use crate::panels::{
    AppCommand, LinkCommand, Notice, Panel, PanelContext, PerfStats, READOUT_HZ, RobotState, Settings, StateSource,
};
use crate::viewport::{SceneFrame, Viewport};

/// Window title.
pub const WINDOW_TITLE: &str = "PAROL6 Studio";
/// Notices disappear after this long.
const NOTICE_TTL: Duration = Duration::from_secs(8);
/// After any command, keep repainting this long so its effect (or refusal) shows up.
const COMMAND_REPAINT_WINDOW: Duration = Duration::from_millis(600);
/// While idle, repaint this seldom (refreshes the status figures). Each frame costs tens of
/// milliseconds of CPU on a software rasterizer, so idle means (almost) no frames.
const IDLE_REPAINT: Duration = Duration::from_secs(30);
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
}

/// The default settings file: `$PAROL6_SETTINGS`, else `$XDG_CONFIG_HOME/parol6-studio/settings.json`,
/// else `~/.config/parol6-studio/settings.json`.
pub fn settings_path() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("PAROL6_SETTINGS") {
        return Some(PathBuf::from(p));
    }
    let base = std::env::var_os("XDG_CONFIG_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))?;
    Some(base.join("parol6-studio").join("settings.json"))
}

/// Loads settings; defaults when the file is missing or unreadable (reported on stderr).
pub fn load_settings(path: Option<&Path>) -> Settings {
    let Some(path) = path else {
        return Settings::default();
    };
    match std::fs::read_to_string(path) {
        Ok(text) => serde_json::from_str(&text).unwrap_or_else(|e| {
            tracing::warn!("ignoring settings file {}: {e}", path.display());
            Settings::default()
        }),
        Err(_) => Settings::default(),
    }
}

fn save_settings(path: &Path, settings: &Settings) -> anyhow::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let text = serde_json::to_string_pretty(settings)?;
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}

/// An open serial session (real port or the built-in emulator).
struct HwLink {
    session: parol6_hw::Session,
    /// Kept alive while connected; dropping it stops the emulator.
    _emulator: Option<parol6_hw::EmulatorHandle>,
    emulated: bool,
    last_jog: Option<(usize, i8, Instant)>,
    last_fault: Option<String>,
}

impl HwLink {
    fn connect(target: &ConnectTarget, model: &RobotModel) -> anyhow::Result<Self> {
        if !model.is_parol6 {
            anyhow::bail!("the serial link drives a PAROL6 only; this model is \"{}\"", model.name);
        }
        let config = parol6_hw::SessionConfig::default();
        match target {
            ConnectTarget::Port(p) => {
                let session = parol6_hw::Session::open(p, config)?;
                Ok(Self { session, _emulator: None, emulated: false, last_jog: None, last_fault: None })
            }
            ConnectTarget::Emulator => Self::connect_emulator(config),
        }
    }

    #[cfg(unix)]
    fn connect_emulator(config: parol6_hw::SessionConfig) -> anyhow::Result<Self> {
        let emu = parol6_hw::EmulatorHandle::spawn(parol6_hw::EmulatorConfig::homed_at_standby())?;
        let session = parol6_hw::Session::open(emu.path(), config)?;
        Ok(Self { session, _emulator: Some(emu), emulated: true, last_jog: None, last_fault: None })
    }

    #[cfg(not(unix))]
    fn connect_emulator(_config: parol6_hw::SessionConfig) -> anyhow::Result<Self> {
        anyhow::bail!("the built-in emulator needs a pseudo-terminal (Unix only)")
    }

    fn view(&self, snap: &parol6_hw::Snapshot) -> LinkView {
        LinkView {
            port: snap.port.clone(),
            emulated: self.emulated,
            link_ok: snap.link == parol6_hw::LinkState::Connected,
            link_state: format!("{:?}", snap.link),
            enabled: snap.enabled.unwrap_or(true) && !snap.needs_enable,
            estop: snap.estop_pressed,
            homing: matches!(snap.homing, parol6_hw::HomingState::Sending | parol6_hw::HomingState::Waiting),
            homed: snap.homed.to_vec(),
            loop_rate_hz: snap.loop_rate_hz,
            jitter_ms: snap.period_jitter_p99_ms,
            dropped_frames: snap.invalid_frames + snap.missing_replies,
            last_error: snap.fault.clone(),
        }
    }

    /// The measured state; `None` until the first status frame arrived.
    fn robot_state(snap: &parol6_hw::Snapshot, model: &RobotModel) -> Option<RobotState> {
        snap.status.as_ref()?;
        let q = snap.joint_rad.to_vec();
        let qd = snap.joint_speed_rad_s.to_vec();
        let target_q =
            snap.target_steps.map(|s| parol6_hw::units::joints_steps_to_rad(&s).to_vec()).unwrap_or_else(|| q.clone());
        let moving = !matches!(snap.motion, parol6_hw::MotionState::Idle | parol6_hw::MotionState::Holding)
            || qd.iter().any(|v| v.abs() > 1e-3);
        Some(RobotState {
            source: StateSource::Robot,
            zones: model.limits.zone_reports(&q, &qd, &ZoneThresholds::default()),
            tcp: model.fk(&q),
            q,
            qd,
            target_q,
            moving,
        })
    }
}

/// Test hook driven by `PAROL6_TEST_SCRIPT` (used by the GUI smoke test).
#[derive(Debug, Clone, PartialEq)]
pub enum TestScript {
    /// `smoke:OUT.png`: screenshot, move joint 1 through the slider path, wait for the
    /// simulation to follow, screenshot again (`OUT.png`; the first one beside it as
    /// `OUT.before.png`), print a JSON line, exit 0 (1 on failure).
    Smoke(PathBuf),
    /// `sweep:SECONDS`: run the joint sweep for that long in the window, print frame statistics
    /// as JSON (`fps_median`, `frame_ms_p50`, `frame_ms_p99`, `ui_cpu_ms_p50`, `first_frame_ms`,
    /// `rss_mb_peak`) and exit.
    Sweep(f64),
}

impl TestScript {
    /// Parses `PAROL6_TEST_SCRIPT`; `Err` for an unknown script.
    pub fn from_env() -> anyhow::Result<Option<Self>> {
        match std::env::var("PAROL6_TEST_SCRIPT") {
            Err(_) => Ok(None),
            Ok(s) => match s.split_once(':') {
                Some(("smoke", path)) if !path.is_empty() => Ok(Some(TestScript::Smoke(PathBuf::from(path)))),
                Some(("sweep", secs)) => match secs.parse::<f64>() {
                    Ok(v) if v.is_finite() && v > 0.0 => Ok(Some(TestScript::Sweep(v))),
                    _ => anyhow::bail!("PAROL6_TEST_SCRIPT: sweep needs seconds > 0, got \"{secs}\""),
                },
                _ => anyhow::bail!(
                    "PAROL6_TEST_SCRIPT: unknown script \"{s}\" (expected smoke:OUT.png or sweep:SECONDS)"
                ),
            },
        }
    }
}

type Shot = Arc<Mutex<Option<Arc<egui::ColorImage>>>>;

#[derive(Debug)]
enum SmokeStep {
    Warmup,
    ShotBefore(Shot),
    Move,
    Wait { target: f64, since: Instant },
    ShotAfter(Shot, Instant),
    Done,
}

struct TestRunner {
    out: PathBuf,
    step: SmokeStep,
    frames: u64,
    q_before: f64,
    target: f64,
    first_frame_ms: Option<f64>,
}

/// Window frame statistics collected by the `sweep:SECONDS` test script.
#[derive(Debug, Default)]
struct SweepRun {
    seconds: f64,
    frames: u64,
    started: Option<Instant>,
    last: Option<Instant>,
    first_frame_ms: Option<f64>,
    frame_ms: Vec<f64>,
    ui_ms: Vec<f64>,
    moving_frames: usize,
}

fn pct(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    sorted[((sorted.len() as f64 - 1.0) * q).round() as usize]
}

/// Writes an egui screenshot as PNG.
fn write_color_image(path: &Path, img: &egui::ColorImage) -> anyhow::Result<()> {
    let [w, h] = img.size;
    let rgba: Vec<u8> = img.pixels.iter().flat_map(|c| c.to_srgba_unmultiplied()).collect();
    crate::ui_screenshot::write_rgba_png(path, w as u32, h as u32, &rgba)
}

/// The application state.
pub struct Parol6App {
    model: RobotModel,
    sim: SimHandle,
    hw: Option<HwLink>,
    viewport: Option<Viewport>,
    viewport_error: Option<String>,
    settings: Settings,
    settings_path: Option<PathBuf>,
    joints: JointsPanel,
    tcp: TcpPanel,
    target: CartesianTargetPanel,
    demos: DemosPanel,
    connection: ConnectionPanel,
    status: StatusBar,
    perf: PerfStats,
    /// Readout state and perf figures, and when they were taken (see `PanelContext::readout`).
    readout: Option<(Instant, RobotState, PerfStats)>,
    frame_starts: VecDeque<Instant>,
    notices: Vec<Notice>,
    last_sim_error_id: u64,
    commands: Vec<AppCommand>,
    repaint_until: Instant,
    test: Option<TestRunner>,
    sweep: Option<SweepRun>,
    exit_code: Arc<AtomicI32>,
    started: Instant,
    show_help: bool,
}

impl Parol6App {
    /// Builds the app: spawns the simulation, creates the 3D viewport on `render_state` (a
    /// plain placeholder without one), connects to a controller if asked.
    pub fn new(opts: LaunchOptions, render_state: Option<&egui_wgpu::RenderState>) -> anyhow::Result<Self> {
        let model = opts.model;
        let sim = SimHandle::spawn(model.clone(), SimConfig::default()).context("starting the simulation")?;
        let settings = load_settings(opts.settings_path.as_deref());
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
            demos: DemosPanel::new(&model),
            model,
            sim,
            hw: None,
            viewport,
            viewport_error,
            settings,
            settings_path: opts.settings_path,
            joints: JointsPanel::default(),
            tcp: TcpPanel::default(),
            target: CartesianTargetPanel::default(),
            connection: ConnectionPanel::default(),
            status: StatusBar,
            perf: PerfStats::default(),
            readout: None,
            frame_starts: VecDeque::new(),
            notices: Vec::new(),
            last_sim_error_id: 0,
            commands: Vec::new(),
            repaint_until: Instant::now() + COMMAND_REPAINT_WINDOW,
            test: match &opts.test_script {
                Some(TestScript::Smoke(out)) => Some(TestRunner {
                    out: out.clone(),
                    step: SmokeStep::Warmup,
                    frames: 0,
                    q_before: 0.0,
                    target: 0.0,
                    first_frame_ms: None,
                }),
                _ => None,
            },
            sweep: match opts.test_script {
                Some(TestScript::Sweep(seconds)) => Some(SweepRun { seconds, ..Default::default() }),
                _ => None,
            },
            exit_code: Arc::new(AtomicI32::new(0)),
            started: opts.started,
            show_help: false,
        };
        if let Some(w) = app.viewport.as_ref().map(|v| v.warnings().to_vec()) {
            for w in w {
                app.notice(format!("3D view: {w}"), true);
            }
        }
        for w in &app.model.warnings {
            let text = format!("model: {w}");
            app.notices.push(Notice { text, error: false, at: Instant::now() });
        }
        if let Some(target) = opts.connect {
            app.connect(&target);
        }
        Ok(app)
    }

    /// Shares the slot where the test hook stores the process exit status (0 = success).
    pub fn set_exit_code(&mut self, slot: Arc<AtomicI32>) {
        self.exit_code = slot;
    }

    /// The simulation (the bench drives it).
    pub fn sim(&self) -> &SimHandle {
        &self.sim
    }

    /// The demos panel (the bench starts the joint sweep through it).
    pub fn demos_mut(&mut self) -> &mut DemosPanel {
        &mut self.demos
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

    fn notice(&mut self, text: impl Into<String>, error: bool) {
        let text = text.into();
        if error {
            tracing::warn!("{text}");
        }
        self.notices.push(Notice { text, error, at: Instant::now() });
    }

    fn connect(&mut self, target: &ConnectTarget) {
        self.disconnect();
        match HwLink::connect(target, &self.model) {
            Ok(link) => {
                let what = match target {
                    ConnectTarget::Port(p) => format!("connected to {p}"),
                    ConnectTarget::Emulator => "connected to the built-in emulator".to_string(),
                };
                self.notice(what, false);
                self.hw = Some(link);
            }
            Err(e) => self.notice(format!("connect failed: {e:#}"), true),
        }
    }

    fn disconnect(&mut self) {
        if let Some(link) = self.hw.take() {
            link.session.close();
            // Hand the view back to the simulation where the robot was.
            let q = self.sim.snapshot().q.clone();
            if let Err(e) = self.sim.send(SimCommand::Teleport(q)) {
                self.notice(format!("simulation: {e}"), true);
            }
        }
    }

    /// The state shown this frame.
    fn robot_state(&self, snap: &SimSnapshot) -> RobotState {
        if let Some(link) = &self.hw
            && let Some(state) = HwLink::robot_state(&link.session.snapshot(), &self.model)
        {
            return state;
        }
        RobotState {
            source: StateSource::Simulation,
            q: snap.q.clone(),
            qd: snap.qd.clone(),
            target_q: snap.target_q.clone(),
            zones: snap.zones.clone(),
            tcp: snap.tcp,
            moving: snap.moving,
        }
    }

    fn update_perf(&mut self, now: Instant, snap: &SimSnapshot) {
        self.frame_starts.push_back(now);
        while self.frame_starts.front().is_some_and(|t| now.duration_since(*t) > Duration::from_secs(1)) {
            self.frame_starts.pop_front();
        }
        let n = self.frame_starts.len();
        self.perf.fps = match (self.frame_starts.front(), n) {
            (Some(first), n) if n > 1 => (n - 1) as f64 / now.duration_since(*first).as_secs_f64().max(1e-6),
            _ => 0.0,
        };
        self.perf.physics_rate_hz = snap.step_rate_hz;
        self.perf.physics_step_us = snap.last_step_ns as f64 / 1000.0;
        self.perf.command_latency_ms = snap.last_command_latency_ns.map(|ns| ns as f64 / 1e6);
        self.perf.sim_time_s = snap.sim_time_s;
    }

    fn keyboard(&mut self, ctx: &egui::Context) {
        let typing = ctx.memory(|m| m.focused().is_some());
        let (esc, home, ctrl_home, quit, help) = ctx.input_mut(|i| {
            (
                i.consume_key(egui::Modifiers::NONE, egui::Key::Escape),
                !typing && i.consume_key(egui::Modifiers::NONE, egui::Key::H),
                i.consume_key(egui::Modifiers::COMMAND, egui::Key::H),
                i.consume_key(egui::Modifiers::COMMAND, egui::Key::Q),
                i.consume_key(egui::Modifiers::NONE, egui::Key::F1),
            )
        });
        if esc {
            self.commands.push(AppCommand::Stop);
        }
        if home || ctrl_home {
            self.commands.push(AppCommand::Home);
        }
        if quit {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        if help {
            self.show_help = !self.show_help;
        }
    }

    /// Draws one frame of the whole UI into `ui` and executes the commands it produced.
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        let t0 = Instant::now();
        let ctx = ui.ctx().clone();
        let snap = self.sim.snapshot();
        self.update_perf(t0, &snap);

        if let Some((id, msg)) = &snap.last_error
            && *id > self.last_sim_error_id
        {
            self.last_sim_error_id = *id;
            let text = format!("simulation refused a command: {msg}");
            self.notice(text, true);
            self.demos.runner.cancel();
        }
        let link_view = self.hw.as_ref().map(|l| {
            let s = l.session.snapshot();
            (l.view(&s), s.fault.clone())
        });
        if let Some((_, fault)) = &link_view
            && let Some(link) = &mut self.hw
            && fault != &link.last_fault
        {
            link.last_fault = fault.clone();
            if let Some(f) = fault.clone() {
                self.notice(format!("robot: {f}"), true);
            }
        }
        let link_view = link_view.map(|(v, _)| v);
        let robot = self.robot_state(&snap);
        self.sweep_step(&ctx, t0, robot.moving);

        self.keyboard(&ctx);
        match self.demos.runner.tick(&robot) {
            Ok(Some(cmd)) => self.commands.push(cmd),
            Ok(None) => {}
            Err(e) => self.notice(e, true),
        }
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
        let (readout, readout_perf) = match &self.readout {
            Some((_, r, p)) => (r, p),
            None => (&robot, &self.perf),
        };
        let mut preview: Option<Vec<f64>> = None;
        let mut commands = std::mem::take(&mut self.commands);
        let mut notices = std::mem::take(&mut self.notices);
        {
            let mut pctx = PanelContext {
                model: &self.model,
                robot: &robot,
                readout,
                settings: &mut self.settings,
                commands: &mut commands,
                notices: &mut notices,
                perf: readout_perf,
                link: link_view.as_ref(),
                preview: &mut preview,
            };
            if let Some(t) = &mut self.test {
                t.frames += 1;
                Self::test_step(t, &ctx, &mut self.joints, &mut pctx, &self.exit_code, self.started);
            }
            Self::layout(
                ui,
                &mut pctx,
                &mut self.joints,
                &mut self.tcp,
                &mut self.target,
                &mut self.demos,
                &mut self.connection,
                &mut self.status,
                self.viewport.as_mut(),
                self.viewport_error.as_deref(),
                &mut self.show_help,
            );
        }
        self.notices = notices;

        // 3D view in the remaining space.
        let ghost: Option<Vec<f64>> = preview.or_else(|| {
            let differs = robot.target_q.len() == robot.q.len()
                && robot.target_q.iter().zip(&robot.q).any(|(t, q)| (t - q).abs() > GHOST_MIN_DIFF_RAD);
            differs.then(|| robot.target_q.clone())
        });
        let zones: Vec<LimitZone> = robot.zones.iter().map(|z| z.zone).collect();
        let mut scene = SceneFrame::with_zones(&self.model, &robot.q, &zones, ghost.as_deref());
        if robot.source == StateSource::Simulation && snap.link_poses.len() == scene.link_poses.len() {
            scene.link_poses = snap.link_poses.clone();
        }
        self.central(ui, &scene);

        for c in &commands {
            self.execute(c.clone());
        }
        self.commands.clear();
        if !commands.is_empty() {
            self.repaint_until = Instant::now() + COMMAND_REPAINT_WINDOW;
        }
        if let Some(v) = &self.viewport
            && v.options != self.settings.view
        {
            self.settings.view = v.options;
        }

        // Repaint policy: continuous only while something moves or the link is live.
        let busy = robot.moving || self.demos.runner.is_running() || Instant::now() < self.repaint_until;
        if busy || self.test.is_some() || self.sweep.is_some() {
            ctx.request_repaint();
        } else if self.hw.is_some() {
            ctx.request_repaint_after(LINK_REPAINT);
        } else {
            ctx.request_repaint_after(IDLE_REPAINT);
        }
        self.perf.ui_cpu_ms = t0.elapsed().as_secs_f64() * 1000.0;
    }

    #[allow(clippy::too_many_arguments)]
    fn layout(
        ui: &mut egui::Ui,
        pctx: &mut PanelContext<'_>,
        joints: &mut JointsPanel,
        tcp: &mut TcpPanel,
        target: &mut CartesianTargetPanel,
        demos: &mut DemosPanel,
        connection: &mut ConnectionPanel,
        status: &mut StatusBar,
        viewport: Option<&mut Viewport>,
        viewport_error: Option<&str>,
        show_help: &mut bool,
    ) {
        egui::Panel::top("menu").show(ui, |ui| {
            egui::MenuBar::new().ui(ui, |ui| {
                ui.label(egui::RichText::new(WINDOW_TITLE).strong());
                ui.separator();
                ui.menu_button("View", |ui| {
                    ui.checkbox(&mut pctx.settings.show_left, "Joints panel");
                    ui.checkbox(&mut pctx.settings.show_right, "TCP / target / demos panel");
                    ui.separator();
                    if let Some(v) = viewport {
                        v.options_ui(ui);
                    }
                });
                ui.menu_button("Units", |ui| {
                    ui.radio_value(&mut pctx.settings.unit, crate::panels::AngleUnit::Deg, "Degrees");
                    ui.radio_value(&mut pctx.settings.unit, crate::panels::AngleUnit::Rad, "Radians");
                });
                if ui.button("Help").clicked() {
                    *show_help = !*show_help;
                }
                ui.separator();
                ui.weak(format!("{} · {} joints", pctx.model.name, pctx.model.dof()));
            });
        });
        egui::Panel::bottom("status").show(ui, |ui| status.ui(ui, pctx));
        if pctx.settings.show_left {
            egui::Panel::left("joints").default_size(360.0).min_size(300.0).show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    joints.ui(ui, pctx);
                    ui.separator();
                    egui::CollapsingHeader::new(connection.title())
                        .default_open(pctx.link.is_some())
                        .show(ui, |ui| connection.ui(ui, pctx));
                });
            });
        }
        if pctx.settings.show_right {
            egui::Panel::right("right").default_size(330.0).min_size(280.0).show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    tcp.ui(ui, pctx);
                    ui.separator();
                    target.ui(ui, pctx);
                    ui.separator();
                    demos.ui(ui, pctx);
                });
            });
        }
        if *show_help {
            egui::Window::new("Keyboard").open(show_help).resizable(false).show(ui.ctx(), |ui| {
                egui::Grid::new("keys").show(ui, |ui| {
                    for (k, what) in [
                        ("Esc", "STOP (also cancels a demo)"),
                        ("H, Ctrl+H", "HOME (profiled move to standby)"),
                        ("1–6, PgUp/PgDn", "select joint, jog (robot connected)"),
                        ("drag / wheel", "orbit, zoom the 3D view (right drag: pan)"),
                        ("R, arrows, +/−", "3D view: reset, orbit, zoom (mouse over it)"),
                        ("F1", "this help"),
                        ("Ctrl+Q", "quit"),
                    ] {
                        ui.monospace(k);
                        ui.label(what);
                        ui.end_row();
                    }
                });
            });
        }
        let _ = viewport_error;
    }

    fn central(&mut self, ui: &mut egui::Ui, scene: &SceneFrame) {
        egui::CentralPanel::no_frame().show(ui, |ui| {
            let rect = ui.max_rect();
            match &mut self.viewport {
                Some(v) => {
                    v.ui(ui, scene);
                }
                None => {
                    ui.painter().rect_filled(rect, 0.0, egui::Color32::from_gray(30));
                    let msg = self.viewport_error.as_deref().unwrap_or("3D view unavailable");
                    ui.put(rect, egui::Label::new(egui::RichText::new(msg).color(egui::Color32::LIGHT_GRAY)));
                }
            }
            // Notices on top of the view, newest first.
            let mut y = rect.top() + 8.0;
            for n in self.notices.iter().rev().take(4) {
                let color = if n.error { ui.visuals().error_fg_color } else { ui.visuals().selection.bg_fill };
                let galley = ui.painter().layout(
                    n.text.clone(),
                    egui::FontId::proportional(14.0),
                    egui::Color32::WHITE,
                    (rect.width() - 40.0).max(100.0),
                );
                let r = egui::Rect::from_min_size(
                    egui::pos2(rect.left() + 10.0, y),
                    galley.size() + egui::vec2(16.0, 10.0),
                );
                ui.painter().rect_filled(r, 4.0, color.gamma_multiply(0.85));
                ui.painter().galley(r.min + egui::vec2(8.0, 5.0), galley, egui::Color32::WHITE);
                y = r.bottom() + 4.0;
            }
        });
    }

    fn execute(&mut self, cmd: AppCommand) {
        if matches!(cmd, AppCommand::Stop) {
            self.demos.runner.cancel();
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
            motion => {
                let res = match &self.hw {
                    Some(link) => Self::execute_on_robot(link, motion, &self.settings).map_err(|e| e.to_string()),
                    None => {
                        let sc = match motion {
                            AppCommand::SetJointTargets(q) => SimCommand::SetJointTargets(q),
                            AppCommand::MoveTo { goal, speed_fraction, kind } => {
                                SimCommand::MoveTo { goal, speed_fraction, kind }
                            }
                            AppCommand::Stop => SimCommand::Stop,
                            AppCommand::Home => SimCommand::Home,
                            _ => return,
                        };
                        self.sim.send(sc).map_err(|e| e.to_string())
                    }
                };
                if let Err(e) = res {
                    self.demos.runner.cancel();
                    self.notice(format!("command refused: {e}"), true);
                }
            }
        }
    }

    fn execute_on_robot(link: &HwLink, cmd: AppCommand, settings: &Settings) -> Result<(), parol6_hw::HwError> {
        let s = &link.session;
        match cmd {
            AppCommand::SetJointTargets(q) => s.move_to(&q, settings.speed_fraction, settings.profile.kind()),
            AppCommand::MoveTo { goal, speed_fraction, kind } => s.move_to(&goal, speed_fraction, kind),
            AppCommand::Stop => s.stop(),
            AppCommand::Home => {
                s.move_to(&parol6_core::parol6::standby_rad(), settings.speed_fraction, settings.profile.kind())
            }
            _ => Ok(()),
        }
    }

    fn execute_link(&mut self, cmd: LinkCommand) {
        let res: Result<(), String> = match (&mut self.hw, cmd) {
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
            (Some(l), LinkCommand::Jog(None)) => {
                if l.last_jog.take().is_some() {
                    l.session.jog_release().map_err(|e| e.to_string())
                } else {
                    Ok(())
                }
            }
            (Some(l), LinkCommand::Jog(Some((joint, dir)))) => {
                let due = match l.last_jog {
                    Some((j, d, at)) => j != joint || d != dir || at.elapsed() >= JOG_REFRESH,
                    None => true,
                };
                if due {
                    l.last_jog = Some((joint, dir, Instant::now()));
                    l.session.jog(joint, f64::from(dir) * self.settings.jog_speed_fraction).map_err(|e| e.to_string())
                } else {
                    Ok(())
                }
            }
        };
        if let Err(e) = res {
            self.notice(format!("robot: {e}"), true);
        }
    }

    fn test_step(
        t: &mut TestRunner,
        ctx: &egui::Context,
        joints: &mut JointsPanel,
        pctx: &mut PanelContext<'_>,
        exit_code: &Arc<AtomicI32>,
        started: Instant,
    ) {
        const TIMEOUT: Duration = Duration::from_secs(20);
        let fail = |msg: String| {
            eprintln!("smoke test failed: {msg}");
            exit_code.store(1, Ordering::SeqCst);
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        };
        if t.first_frame_ms.is_none() {
            t.first_frame_ms = Some(started.elapsed().as_secs_f64() * 1000.0);
        }
        let request = |ctx: &egui::Context| -> Shot {
            let shot: Shot = Arc::new(Mutex::new(None));
            let s2 = Arc::clone(&shot);
            ctx.request_screenshot(move |img| {
                if let Ok(mut g) = s2.lock() {
                    *g = Some(img);
                }
            });
            shot
        };
        let take = |shot: &Shot| shot.lock().ok().and_then(|mut g| g.take());
        match &mut t.step {
            SmokeStep::Warmup => {
                if t.frames >= 5 && !pctx.robot.moving {
                    t.step = SmokeStep::ShotBefore(request(ctx));
                }
            }
            SmokeStep::ShotBefore(shot) => {
                if let Some(img) = take(shot) {
                    let before = t.out.with_extension("before.png");
                    if let Err(e) = write_color_image(&before, &img) {
                        return fail(format!("{e:#}"));
                    }
                    t.step = SmokeStep::Move;
                }
            }
            SmokeStep::Move => {
                // Joint 1 by +30° (or −30° if that would leave the range), through the slider path.
                let q0 = pctx.robot.q.first().copied().unwrap_or(0.0);
                let delta = 30f64.to_radians();
                let target = match pctx.model.limits.get(0) {
                    Some(l) if l.is_bounded() && q0 + delta > l.max => q0 - delta,
                    _ => q0 + delta,
                };
                t.q_before = q0;
                t.target = target;
                joints.set_joint(0, target, pctx);
                t.step = SmokeStep::Wait { target, since: Instant::now() };
            }
            SmokeStep::Wait { target, since } => {
                let q = pctx.robot.q.first().copied().unwrap_or(0.0);
                if (q - *target).abs() < 0.5f64.to_radians() && !pctx.robot.moving {
                    t.step = SmokeStep::ShotAfter(request(ctx), Instant::now());
                } else if since.elapsed() > TIMEOUT {
                    fail(format!("joint 1 did not reach {target:.4} rad (at {q:.4} rad)"));
                }
            }
            SmokeStep::ShotAfter(shot, since) => {
                if let Some(img) = take(shot) {
                    if let Err(e) = write_color_image(&t.out, &img) {
                        return fail(format!("{e:#}"));
                    }
                    let q = pctx.robot.q.first().copied().unwrap_or(0.0);
                    println!(
                        "{}",
                        serde_json::json!({
                            "smoke": "ok",
                            "joint": 1,
                            "q_before_rad": t.q_before,
                            "target_rad": t.target,
                            "q_after_rad": q,
                            "screenshot": t.out.display().to_string(),
                            "first_frame_ms": t.first_frame_ms,
                            "frames": t.frames,
                        })
                    );
                    t.step = SmokeStep::Done;
                    ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                } else if since.elapsed() > TIMEOUT {
                    fail("no screenshot arrived".to_string());
                }
            }
            SmokeStep::Done => {}
        }
    }

    fn sweep_step(&mut self, ctx: &egui::Context, now: Instant, moving: bool) {
        let Some(sw) = &mut self.sweep else {
            return;
        };
        sw.frames += 1;
        if sw.first_frame_ms.is_none() {
            sw.first_frame_ms = Some(self.started.elapsed().as_secs_f64() * 1000.0);
        }
        if sw.frames == 5 {
            self.demos.start_by_name("Joint sweep");
            self.demos.runner.looping = true;
        }
        if sw.frames < 10 {
            return;
        }
        let started = *sw.started.get_or_insert(now);
        if let Some(last) = sw.last {
            sw.frame_ms.push(now.duration_since(last).as_secs_f64() * 1000.0);
            sw.ui_ms.push(self.perf.ui_cpu_ms);
            if moving {
                sw.moving_frames += 1;
            }
        }
        sw.last = Some(now);
        if now.duration_since(started).as_secs_f64() >= sw.seconds {
            let mut f = sw.frame_ms.clone();
            let mut u = sw.ui_ms.clone();
            f.sort_by(f64::total_cmp);
            u.sort_by(f64::total_cmp);
            let p50 = pct(&f, 0.5);
            println!(
                "{}",
                serde_json::json!({
                    "target": "window",
                    "seconds": now.duration_since(started).as_secs_f64(),
                    "frames": f.len(),
                    "moving_frames": sw.moving_frames,
                    "fps_median": if p50 > 0.0 { 1000.0 / p50 } else { 0.0 },
                    "frame_ms_p50": p50,
                    "frame_ms_p99": pct(&f, 0.99),
                    "ui_cpu_ms_p50": pct(&u, 0.5),
                    "ui_cpu_ms_p99": pct(&u, 0.99),
                    "first_frame_ms": sw.first_frame_ms,
                    "rss_mb_peak": crate::ui_screenshot::peak_rss_mb(),
                })
            );
            self.sweep = None;
            self.demos.runner.cancel();
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }

    /// Saves the settings (also done on exit).
    pub fn save_settings(&self) {
        if let Some(p) = &self.settings_path
            && let Err(e) = save_settings(p, &self.settings)
        {
            tracing::warn!("settings not saved: {e:#}");
        }
    }
}

impl eframe::App for Parol6App {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame(ui);
    }

    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        crate::theme::clear_color()
    }

    fn on_exit(&mut self) {
        self.save_settings();
        self.disconnect();
    }
}

/// The window icon: a small orange arm on a dark tile, drawn in code (no asset file).
pub fn window_icon() -> egui::IconData {
    const N: usize = 64;
    let mut rgba = vec![0u8; N * N * 4];
    let mut put = |x: i32, y: i32, c: [u8; 4]| {
        if (0..N as i32).contains(&x) && (0..N as i32).contains(&y) {
            let i = (y as usize * N + x as usize) * 4;
            rgba[i..i + 4].copy_from_slice(&c);
        }
    };
    let bg = [28, 32, 40, 255];
    for y in 0..N as i32 {
        for x in 0..N as i32 {
            let (dx, dy) = ((x - 31).abs().max(0) as f32, (y - 31).abs() as f32);
            if dx < 30.0 && dy < 30.0 {
                put(x, y, bg);
            }
        }
    }
    let orange = [255, 140, 26, 255];
    let seg = |put: &mut dyn FnMut(i32, i32, [u8; 4]), a: (f32, f32), b: (f32, f32), w: f32| {
        for y in 0..N as i32 {
            for x in 0..N as i32 {
                let (px, py) = (x as f32, y as f32);
                let (vx, vy) = (b.0 - a.0, b.1 - a.1);
                let t = (((px - a.0) * vx + (py - a.1) * vy) / (vx * vx + vy * vy)).clamp(0.0, 1.0);
                let (cx, cy) = (a.0 + t * vx - px, a.1 + t * vy - py);
                if cx * cx + cy * cy <= w * w {
                    put(x, y, orange);
                }
            }
        }
    };
    seg(&mut put, (14.0, 54.0), (50.0, 54.0), 3.0); // base
    seg(&mut put, (24.0, 52.0), (24.0, 30.0), 4.0); // upper arm
    seg(&mut put, (24.0, 30.0), (46.0, 18.0), 3.5); // forearm
    seg(&mut put, (46.0, 18.0), (50.0, 28.0), 2.5); // wrist / tool
    egui::IconData { rgba, width: N as u32, height: N as u32 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run_frame(app: &mut Parol6App, ctx: &egui::Context) {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1280.0, 800.0))),
            ..Default::default()
        };
        let _ = ctx.run_ui(input, |ui| app.frame(ui));
    }

    fn wait_for(app: &mut Parol6App, ctx: &egui::Context, what: &str, mut done: impl FnMut(&RobotState) -> bool) {
        let deadline = Instant::now() + Duration::from_secs(15);
        loop {
            run_frame(app, ctx);
            let snap = app.sim.snapshot();
            let state = app.robot_state(&snap);
            if done(&state) {
                return;
            }
            assert!(Instant::now() < deadline, "timed out waiting for {what}: {state:?}");
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    fn launch(connect: Option<ConnectTarget>) -> Parol6App {
        let opts = LaunchOptions {
            model: RobotModel::parol6(),
            connect,
            settings_path: None,
            test_script: None,
            started: Instant::now(),
            msaa_samples: 1,
        };
        Parol6App::new(opts, None).expect("app")
    }

    #[test]
    fn slider_path_moves_the_simulation_and_stop_cancels_a_demo() {
        let mut app = launch(None);
        let ctx = egui::Context::default();
        run_frame(&mut app, &ctx);
        let snap = app.sim.snapshot();
        let robot = app.robot_state(&snap);
        assert_eq!(robot.source, StateSource::Simulation);
        let target = robot.q[0] + 0.3;
        {
            let mut commands = Vec::new();
            let mut notices = Vec::new();
            let mut preview = None;
            let mut pctx = PanelContext {
                model: &app.model,
                robot: &robot,
                readout: &robot,
                settings: &mut app.settings,
                commands: &mut commands,
                notices: &mut notices,
                perf: &app.perf,
                link: None,
                preview: &mut preview,
            };
            app.joints.set_joint(0, target, &mut pctx);
            // A value beyond the limit is clamped to it, never passed on.
            app.joints.set_joint(1, 10.0, &mut pctx);
            app.commands = commands;
        }
        match app.commands.last() {
            Some(AppCommand::SetJointTargets(q)) => {
                let lim = app.model.limits.get(1).expect("J2");
                assert!((q[1] - lim.max).abs() < 1e-12, "J2 target {} not clamped to {}", q[1], lim.max);
                assert!((q[0] - target).abs() < 1e-12);
            }
            other => panic!("expected joint targets, got {other:?}"),
        }
        wait_for(&mut app, &ctx, "joint 1 to follow the slider", |s| (s.q[0] - target).abs() < 0.01 && !s.moving);

        assert!(app.demos.start_by_name("Joint sweep"));
        run_frame(&mut app, &ctx);
        assert!(app.demos.runner.is_running());
        app.commands.push(AppCommand::Stop);
        run_frame(&mut app, &ctx);
        assert!(!app.demos.runner.is_running(), "STOP must cancel the demo");
    }

    #[cfg(unix)]
    #[test]
    fn fake_robot_is_mirrored_and_moves() {
        let mut app = launch(Some(ConnectTarget::Emulator));
        assert!(app.hw.is_some(), "emulator did not connect: {:?}", app.notices);
        let ctx = egui::Context::default();
        let standby = parol6_core::parol6::standby_rad();
        wait_for(&mut app, &ctx, "the first status", |s| {
            s.source == StateSource::Robot && s.q.iter().zip(&standby).all(|(a, b)| (a - b).abs() < 1e-3)
        });
        let mut goal = standby.to_vec();
        goal[0] -= 0.2;
        app.execute(AppCommand::MoveTo {
            goal: goal.clone(),
            speed_fraction: 1.0,
            kind: parol6_core::profile::ProfileKind::Trapezoidal,
        });
        assert!(app.notices.iter().all(|n| !n.error), "{:?}", app.notices);
        wait_for(&mut app, &ctx, "the robot to reach the goal", |s| (s.q[0] - goal[0]).abs() < 0.01);
        let view = app.hw.as_ref().map(|l| l.view(&l.session.snapshot())).expect("link");
        assert!(view.link_ok && view.emulated && view.homed.iter().all(|h| *h), "{view:?}");
        app.execute(AppCommand::Link(LinkCommand::Disconnect));
        assert!(app.hw.is_none());
        run_frame(&mut app, &ctx);
        let snap = app.sim.snapshot();
        assert_eq!(app.robot_state(&snap).source, StateSource::Simulation);
    }
}
