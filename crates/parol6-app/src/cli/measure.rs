//! `parol6 iso9283` and `parol6 path-test`: ISO 9283 pose and path tests on the simulation
//! (default) or the controller (`--port`, `--fake-robot`), or the pose figures of an external
//! measurement file (`--measurements`). With a controller and `--report`, the same test also
//! runs on the simulation and the report overlays both.

use std::path::{Path, PathBuf};

use parol6_core::RobotModel;
use parol6_core::measure::cube::MAX_EDGE_MM;
use parol6_core::measure::driver::{PathRecording, start_path_test, start_pose_test};
use parol6_core::measure::plan::{DEFAULT_CYCLES, DEFAULT_PATH_CYCLES, MAX_CYCLES};
use parol6_core::measure::pose_figures::{self, PoseSample, PoseTestFigures};
use parol6_core::measure::{PathKind, PathTestPlan, PoseTestPlan, TestCube, compare, measurements};
use parol6_core::motion::tracking::TrackingMode;
use serde_json::json;

use super::common::RateArgs;
use super::common::tool_of;
use super::measure_backend::{Opened, wait};
use super::options::{ConnectArgs, RobotArgs, f64_within};
use super::output::print_line;
use super::{CliError, CliResult, print_json};
use crate::report::{self, PathReport, PoseReport, Report, Setup};

/// The cube options.
#[derive(Debug, Clone, clap::Args)]
pub struct CubeArgs {
    /// Cube centre X,Y,Z in the base frame, mm (each within ±2000; default 0,250,220, the window's).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = triple(2000.0))]
    pub center_mm: Option<[f64; 3]>,
    /// Cube edge, mm, > 0 and ≤ 1000 (default 60, the window's).
    #[arg(long, value_name = "L", value_parser = super::options::f64_above(0.0, MAX_EDGE_MM))]
    pub edge_mm: Option<f64>,
    /// Tool orientation at every pose: our URDF ROLL,PITCH,YAW, deg (R = Rz(yaw)·Ry(pitch)·Rx(roll);
    /// each within ±360; default 90,0,0, the window's).
    #[arg(long, value_name = "ROLL,PITCH,YAW", allow_hyphen_values = true, value_parser = triple(360.0))]
    pub orientation_deg: Option<[f64; 3]>,
}

impl CubeArgs {
    fn cube(&self) -> Result<TestCube, CliError> {
        // what is not given is the window's default cube's
        let d = TestCube::DEFAULT;
        Ok(TestCube {
            center_mm: self.center_mm.unwrap_or(d.center_mm),
            edge_mm: self.edge_mm.unwrap_or(d.edge_mm),
            orientation_rpy_deg: self.orientation_deg.unwrap_or(d.orientation_rpy_deg),
        })
    }

    fn any_given(&self) -> bool {
        self.center_mm.is_some() || self.edge_mm.is_some() || self.orientation_deg.is_some()
    }
}

/// A clap value parser: three comma-separated finite numbers, each within ±`max`.
fn triple(max: f64) -> impl Fn(&str) -> Result<[f64; 3], String> + Clone + Send + Sync + 'static {
    move |text: &str| {
        let parts: Vec<&str> = text.split(',').collect();
        if parts.len() != 3 {
            return Err(format!("three comma-separated numbers expected, got {}", parts.len()));
        }
        let mut out = [0.0; 3];
        for (i, (slot, p)) in out.iter_mut().zip(parts).enumerate() {
            match p.trim().parse::<f64>() {
                Ok(v) if v.is_finite() && v.abs() <= max => *slot = v,
                _ => return Err(format!("value {} (\"{}\") must be a number within ±{max}", i + 1, p.trim())),
            }
        }
        Ok(out)
    }
}

/// Arguments of `parol6 iso9283`.
#[derive(Debug, clap::Args)]
pub struct Iso9283Args {
    /// The cube (not with --measurements).
    #[command(flatten)]
    pub cube: CubeArgs,
    /// Cycles, 2–1000.
    #[arg(long, default_value_t = DEFAULT_CYCLES, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(2..=MAX_CYCLES as u64))]
    pub cycles: usize,
    /// Fraction of the joint speed caps for the moves between poses, 0.01–1.
    #[arg(long, default_value_t = 0.5, value_parser = f64_within(0.01, 1.0))]
    pub speed: f64,
    /// Rest at each pose before reading it, s of motion clock, 0–10.
    #[arg(long, default_value_t = 0.3, value_parser = f64_within(0.0, 10.0))]
    pub settle_s: f64,
    /// Write the attained poses to this CSV (the --measurements format).
    #[arg(long, value_name = "OUT.csv", value_parser = super::options::output_file)]
    pub raw: Option<PathBuf>,
    /// The report and the printed figures.
    #[command(flatten)]
    pub out: TestOutputArgs,
    /// Compute the figures from this measurement CSV (laser tracker, camera, --raw) instead
    /// of running the test.
    #[arg(long, value_name = "FILE.csv", conflicts_with_all = ["raw", "center_mm", "edge_mm", "orientation_deg"])]
    pub measurements: Option<PathBuf>,
    /// Session settings (robot only).
    #[command(flatten)]
    pub rate: RateArgs,
}

/// The outputs `iso9283` and `path-test` share.
#[derive(Debug, Clone, clap::Args)]
pub struct TestOutputArgs {
    /// Write the HTML report here.
    #[arg(long, value_name = "OUT.html", value_parser = super::options::output_file)]
    pub report: Option<PathBuf>,
    /// Print the figures as JSON.
    #[arg(long)]
    pub json: bool,
}

impl TestOutputArgs {
    /// Writes the HTML report when one is asked for, building it only then.
    fn write_report(&self, build: impl FnOnce() -> Result<Report, CliError>) -> CliResult {
        match &self.report {
            Some(path) => write_file(path, &report::html(&build()?)),
            None => Ok(()),
        }
    }
}

/// Which paths `path-test` runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PathChoice {
    /// Line P2 → P4.
    Line,
    /// Circle about P1 in the diagonal plane.
    Circle,
    /// Right-angled triangle in the diagonal plane.
    Triangle,
    /// All three.
    All,
}

/// Arguments of `parol6 path-test`.
#[derive(Debug, clap::Args)]
pub struct PathTestArgs {
    /// The cube.
    #[command(flatten)]
    pub cube: CubeArgs,
    /// Which path.
    #[arg(long, value_enum, default_value_t = PathChoice::All)]
    pub path: PathChoice,
    /// Cycles, 2–1000.
    #[arg(long, default_value_t = DEFAULT_PATH_CYCLES, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(2..=MAX_CYCLES as u64))]
    pub cycles: usize,
    /// Fraction of the rated TCP speed (200 mm/s) along the path, 0.01–1.
    #[arg(long, default_value_t = 0.5, value_parser = f64_within(0.01, 1.0))]
    pub speed: f64,
    /// Points along the path for AT_p / RT_p, 2–1000.
    #[arg(long, default_value_t = 50, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(2..=1000))]
    pub points: usize,
    /// Write the recorded paths to this CSV (path,tracking,cycle,t_s,cmd_x_mm,…,x_mm,…).
    #[arg(long, value_name = "OUT.csv", value_parser = super::options::output_file)]
    pub raw: Option<PathBuf>,
    /// The report and the printed figures.
    #[command(flatten)]
    pub out: TestOutputArgs,
    /// Session settings (robot only).
    #[command(flatten)]
    pub rate: RateArgs,
    /// Run the test once in each tracking mode (official, lead, feedforward) and compare them side
    /// by side: the JSON, the printed lines and the report's table (on a controller, each mode
    /// beside the simulation in the same mode).
    #[arg(long, conflicts_with = "tracking")]
    pub compare_tracking: bool,
}

fn uses_robot(connect: &ConnectArgs) -> bool {
    connect.port.is_some() || connect.fake_robot
}

fn write_file(path: &Path, text: &str) -> CliResult {
    Ok(parol6_core::fsio::write_atomic_bytes(path, text.as_bytes())?)
}

fn setup(model: &RobotModel, robot: &RobotArgs, source: &str, speed: f64, cycles: usize, cube: TestCube) -> Setup {
    Setup {
        robot: if model.is_parol6 { "PAROL6".into() } else { model.name.clone() },
        tool: tool_of(robot),
        source: source.to_string(),
        speed_fraction: speed,
        cycles,
        date_utc: report::now_utc(),
        cube,
    }
}

/// Runs `parol6 iso9283`.
pub fn run_iso9283(args: &Iso9283Args, robot: &RobotArgs, connect: &ConnectArgs) -> CliResult {
    let model = robot.load()?;
    if let Some(file) = &args.measurements {
        if uses_robot(connect) || args.cube.any_given() {
            return Err(CliError::usage("--measurements computes from a file; it takes no cube and no robot"));
        }
        let samples = read_measurements(file)?;
        let figures =
            pose_figures::compute(&samples).map_err(|e| CliError::usage(format!("{}: {e}", file.display())))?;
        args.out.write_report(|| {
            let cycles = samples.iter().map(|s| s.cycle).max().unwrap_or(0) as usize;
            let cube = cube_of_measurements(&samples);
            let source = format!("measurement file {}", file.display());
            let setup = setup(&model, robot, &source, 0.0, cycles, cube);
            let pose = PoseReport { figures: figures.clone(), samples, simulation: None };
            Ok(Report { setup, pose: Some(pose), paths: Vec::new() })
        })?;
        return print_pose_figures(&figures, args.out.json);
    }
    let cube = args.cube.cube()?;
    let plan = PoseTestPlan { cube, cycles: args.cycles, speed_fraction: args.speed, settle_s: args.settle_s };
    let opened = Opened::from_args(&model, connect, &args.rate, false)?;
    let run = start_pose_test(opened.backend.clone(), model.clone(), plan)
        .map_err(|e| CliError::runtime(format!("cannot start the measurement thread: {e}")))?;
    let samples = wait(run, &format!("ISO 9283 on the {}", opened.name))?;
    let figures = pose_figures::compute(&samples).map_err(CliError::runtime)?;
    if let Some(path) = &args.raw {
        write_file(path, &measurements::write(&samples))?;
    }
    args.out.write_report(|| {
        let simulation = if uses_robot(connect) {
            let sim = Opened::simulation(&model, false, args.rate.tracking.unwrap_or_default())?;
            let run = start_pose_test(sim.backend.clone(), model.clone(), plan)
                .map_err(|e| CliError::runtime(format!("cannot start the measurement thread: {e}")))?;
            let s = wait(run, "ISO 9283 on the simulation")?;
            Some((pose_figures::compute(&s).map_err(CliError::runtime)?, s))
        } else {
            None
        };
        let setup = setup(&model, robot, &opened.name, args.speed, args.cycles, cube);
        let pose = PoseReport { figures: figures.clone(), samples, simulation };
        Ok(Report { setup, pose: Some(pose), paths: Vec::new() })
    })?;
    print_pose_figures(&figures, args.out.json)
}

fn read_measurements(file: &Path) -> Result<Vec<PoseSample>, CliError> {
    let bytes = match parol6_core::fsio::read_regular_bounded(file, measurements::MAX_FILE_BYTES as u64) {
        Ok(bytes) => bytes,
        Err(parol6_core::fsio::FsioError::TooLarge { .. }) => {
            let len = std::fs::metadata(file).map_or(measurements::MAX_FILE_BYTES as u64 + 1, |m| m.len());
            return Err(CliError::usage(format!(
                "{}: {}",
                file.display(),
                measurements::CsvError::TooLarge(len as usize)
            )));
        }
        Err(e) => return Err(e.into()),
    };
    let text = String::from_utf8(bytes).map_err(|e| {
        CliError::usage(format!("{}: not UTF-8 text (byte {})", file.display(), e.utf8_error().valid_up_to()))
    })?;
    measurements::parse(&text).map_err(|e| CliError::usage(format!("{}: {e}", file.display())))
}

/// The cube the commanded poses of a measurement file describe (P1 is the centre; the edge
/// from P2–P4 when both are there).
fn cube_of_measurements(samples: &[PoseSample]) -> TestCube {
    let find = |pose: usize| samples.iter().find(|s| s.pose == pose).map(|s| s.commanded);
    let center = find(0).or_else(|| samples.first().map(|s| s.commanded));
    let edge = match (find(1), find(3)) {
        (Some(a), Some(b)) => {
            let d: f64 = (0..3).map(|k| (a.position_mm[k] - b.position_mm[k]).powi(2)).sum::<f64>().sqrt();
            d / (0.8 * 3f64.sqrt())
        }
        _ => 0.0,
    };
    TestCube {
        center_mm: center.map_or([0.0; 3], |c| c.position_mm),
        edge_mm: edge,
        orientation_rpy_deg: center.map_or([0.0; 3], |c| c.rpy_deg),
    }
}

fn print_pose_figures(f: &PoseTestFigures, as_json: bool) -> CliResult {
    if as_json {
        return print_json(&serde_json::to_value(f).map_err(|e| CliError::runtime(e.to_string()))?);
    }
    let mut out = String::from(
        "pose  AP_p mm  AP_x mm  AP_y mm  AP_z mm  RP_l mm  AP_a °   AP_b °   AP_c °   RP_a °   RP_b °   RP_c °\n",
    );
    for p in &f.poses {
        out.push_str(&format!(
            "{:<4} {:8.4} {:8.4} {:8.4} {:8.4} {:8.4} {:8.4} {:8.4} {:8.4} {:8.4} {:8.4} {:8.4}\n",
            p.name,
            p.ap_p_mm,
            p.ap_x_mm,
            p.ap_y_mm,
            p.ap_z_mm,
            p.rp_l_mm,
            p.ap_a_deg,
            p.ap_b_deg,
            p.ap_c_deg,
            p.rp_a_deg,
            p.rp_b_deg,
            p.rp_c_deg
        ));
    }
    let opt = |v: Option<f64>| v.map_or_else(|| "–".to_string(), |v| format!("{v:.4}"));
    out.push_str(&format!("P2–P4 distance: AD_p {} mm, RD {} mm", opt(f.ad_p_mm), opt(f.rd_mm)));
    print_line(&out)
}

/// Runs `parol6 path-test`.
pub fn run_path_test(args: &PathTestArgs, robot: &RobotArgs, connect: &ConnectArgs) -> CliResult {
    let model = robot.load()?;
    let cube = args.cube.cube()?;
    let kinds: Vec<PathKind> = match args.path {
        PathChoice::Line => vec![PathKind::Line],
        PathChoice::Circle => vec![PathKind::Circle],
        PathChoice::Triangle => vec![PathKind::Triangle],
        PathChoice::All => PathKind::ALL.to_vec(),
    };
    let plans: Vec<PathTestPlan> = kinds
        .iter()
        .map(|&kind| PathTestPlan { cube, kind, cycles: args.cycles, speed_fraction: args.speed, points: args.points })
        .collect();
    let run_all = |o: &Opened| -> Result<Vec<PathRecording>, CliError> {
        plans
            .iter()
            .map(|plan| {
                let run = start_path_test(o.backend.clone(), model.clone(), *plan, o.tap.clone())
                    .map_err(|e| CliError::runtime(format!("cannot start the measurement thread: {e}")))?;
                wait(run, &format!("{} path on the {}", plan.kind.name(), o.name))
            })
            .collect()
    };
    let modes =
        if args.compare_tracking { TrackingMode::ALL.to_vec() } else { vec![args.rate.tracking.unwrap_or_default()] };
    let mut paths_json = Vec::new();
    let mut reports = Vec::new();
    let mut recordings = Vec::new();
    let mut source = String::new();
    for mode in modes {
        let rate = RateArgs { tracking: Some(mode), ..args.rate.clone() };
        let opened = Opened::from_args(&model, connect, &rate, true)?;
        source.clone_from(&opened.name);
        let runs = run_all(&opened)?;
        drop(opened);
        let simulation =
            if uses_robot(connect) { Some(run_all(&Opened::simulation(&model, true, mode)?)?) } else { None };
        for (i, rec) in runs.iter().enumerate() {
            let sim = simulation.as_ref().and_then(|s| s.get(i));
            let r = PathReport::new(&model, rec, sim)
                .map_err(|e| CliError::runtime(format!("{}: {e}", rec.plan.kind.name())))?
                .with_tracking(mode);
            let mut v = serde_json::to_value(&r.figures).map_err(|e| CliError::runtime(e.to_string()))?;
            v["path"] = json!(rec.plan.kind.name());
            v["tracking"] = json!(mode.name());
            if let Some((sim_figures, _, diff)) = &r.simulation {
                v["simulation"] = serde_json::to_value(sim_figures).unwrap_or_default();
                v["robot_minus_simulation"] = serde_json::to_value(compare::summarize(diff)).unwrap_or_default();
            }
            paths_json.push(v);
            reports.push(r);
        }
        recordings.extend(runs.into_iter().map(|r| (mode, r)));
    }
    if let Some(path) = &args.raw {
        write_file(path, &path_csv(&model, &recordings))?;
    }
    args.out.write_report(|| {
        let setup = setup(&model, robot, &source, args.speed, args.cycles, cube);
        Ok(Report { setup, pose: None, paths: reports })
    })?;
    let out = json!({ "paths": paths_json });
    if args.out.json {
        print_json(&out)
    } else {
        let lines: Vec<String> = paths_json
            .iter()
            .map(|p| {
                let corners = match (p["CR_mm"].as_f64(), p["CO_mm"].as_f64()) {
                    (Some(cr), Some(co)) => format!("  CR {cr:.4} mm  CO {co:.4} mm"),
                    _ => String::new(),
                };
                format!(
                    "{:<8} {:<11} AT_p {:.4} mm  RT_p {:.4} mm  max deviation {:.4} mm  RMS {:.4} mm{corners}",
                    p["path"].as_str().unwrap_or(""),
                    p["tracking"].as_str().unwrap_or(""),
                    p["AT_p_mm"].as_f64().unwrap_or(f64::NAN),
                    p["RT_p_mm"].as_f64().unwrap_or(f64::NAN),
                    p["max_deviation_mm"].as_f64().unwrap_or(f64::NAN),
                    p["rms_deviation_mm"].as_f64().unwrap_or(f64::NAN)
                )
            })
            .collect();
        print_line(&lines.join("\n"))
    }
}

/// The recorded paths as CSV: one row per sample.
fn path_csv(model: &RobotModel, recordings: &[(TrackingMode, PathRecording)]) -> String {
    use std::fmt::Write as _;
    let mut out = String::from("path,tracking,cycle,t_s,cmd_x_mm,cmd_y_mm,cmd_z_mm,x_mm,y_mm,z_mm\n");
    for (mode, rec) in recordings {
        for (k, cycle) in rec.cycles.iter().enumerate() {
            for s in cycle {
                let c = model.tcp_isometry(&s.commanded_q).translation.vector * 1000.0;
                let a = model.tcp_isometry(&s.measured_q).translation.vector * 1000.0;
                let _ = writeln!(
                    out,
                    "{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4}",
                    rec.plan.kind.name(),
                    mode.name(),
                    k + 1,
                    s.t_s,
                    c.x,
                    c.y,
                    c.z,
                    a.x,
                    a.y,
                    a.z
                );
            }
        }
    }
    out
}
