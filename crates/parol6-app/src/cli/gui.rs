//! `parol6` with no subcommand: the GUI window (eframe + wgpu), and `parol6 bench render`.
//!
//! Top-level options: `--urdf PATH` (another robot), `--tip LINK`, `--tool NAME`, `--port P`
//! (open connected to a controller), `--fake-robot` (connected to the built-in emulator).

use eframe::egui;
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::time::Instant;

use super::kin::RobotArgs;
use super::{CliError, CliResult};
use crate::app::{ConnectTarget, LaunchOptions, Parol6App, TestScript, WINDOW_TITLE, settings_path, window_icon};

/// Options of the GUI (given without a subcommand).
#[derive(Debug, Clone, clap::Args)]
pub struct GuiArgs {
    /// URDF file of another robot (default: the embedded PAROL6).
    #[arg(long, value_name = "PATH", global = false)]
    pub urdf: Option<PathBuf>,
    /// Tip link of the chain (with --urdf).
    #[arg(long, value_name = "LINK")]
    pub tip: Option<String>,
    /// Tool on the flange: none, pneumatic-vertical, pneumatic-horizontal, ssg48, msg, vacuum.
    #[arg(long, value_name = "NAME")]
    pub tool: Option<String>,
    /// Open connected to the PAROL6 controller on this serial port (the 3D arm mirrors it).
    #[arg(long, value_name = "PORT", conflicts_with = "fake_robot")]
    pub port: Option<String>,
    /// Open connected to the built-in controller emulator.
    #[arg(long)]
    pub fake_robot: bool,
}

impl GuiArgs {
    fn robot(&self) -> RobotArgs {
        RobotArgs { urdf: self.urdf.clone(), tip: self.tip.clone(), tool: self.tool.clone() }
    }
}

/// Opens the window; returns when it is closed.
pub fn run(args: &GuiArgs) -> CliResult {
    let started = Instant::now();
    let model = args.robot().load()?;
    let test_script = TestScript::from_env().map_err(|e| CliError::usage(format!("{e:#}")))?;
    let connect = match (&args.port, args.fake_robot) {
        (Some(p), _) => Some(ConnectTarget::Port(p.clone())),
        (None, true) => Some(ConnectTarget::Emulator),
        (None, false) => None,
    };
    let title = if model.is_parol6 { WINDOW_TITLE.to_string() } else { format!("{WINDOW_TITLE} — {}", model.name) };

    let mut native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(&title)
            .with_app_id("parol6-studio")
            .with_inner_size([1280.0, 800.0])
            .with_min_inner_size([800.0, 500.0])
            .with_icon(window_icon()),
        renderer: eframe::Renderer::Wgpu,
        ..Default::default()
    };
    let msaa_samples = crate::viewport::configure_native_options(&mut native);
    let opts = LaunchOptions { model, connect, settings_path: settings_path(), test_script, started, msaa_samples };

    let exit_code = std::sync::Arc::new(std::sync::atomic::AtomicI32::new(0));
    let exit_slot = std::sync::Arc::clone(&exit_code);
    let result = eframe::run_native(
        &title,
        native,
        Box::new(move |cc| {
            cc.egui_ctx.set_visuals(crate::theme::visuals());
            let mut app = Parol6App::new(opts, cc.wgpu_render_state.as_ref())?;
            app.set_exit_code(exit_slot);
            Ok(Box::new(app))
        }),
    );
    if let Err(e) = result {
        return Err(CliError::runtime(format!("cannot open the window: {e}")));
    }
    let code = exit_code.load(Ordering::SeqCst);
    if code != 0 {
        return Err(CliError { status: code.clamp(1, 255) as u8, message: "test script failed".into() });
    }
    Ok(())
}

/// Arguments of `parol6 bench render`.
#[derive(Debug, Clone, clap::Args)]
pub struct BenchRenderArgs {
    /// Measuring time, s.
    #[arg(long, default_value_t = 10.0)]
    pub seconds: f64,
    /// Frame size WIDTHxHEIGHT in pixels.
    #[arg(long, value_name = "WxH", default_value = "1280x800")]
    pub size: String,
    /// Exit 1 when the targets (FPS median, UI CPU p50, peak RSS) are not met.
    #[arg(long)]
    pub check: bool,
    #[command(flatten)]
    pub robot: RobotArgs,
}

/// Runs `parol6 bench render`.
pub fn bench_render(a: &BenchRenderArgs) -> CliResult {
    let (w, h) = super::render::parse_size(&a.size)?;
    let model = a.robot.load()?;
    crate::ui_screenshot::bench_render(model, a.seconds, w, h, a.check)
}
