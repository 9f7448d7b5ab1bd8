//! `parol6 fk`, `parol6 ik` and their benchmarks.

use std::hint::black_box;
use std::time::Instant;

use parol6_core::ik::{self, NumericIkOptions};
use parol6_core::{RobotModel, TcpPose};
use rand::{Rng, SeedableRng};
use serde_json::json;

use super::common::{NsStats, parse_list};
use super::options::RobotArgs;
use super::{CliError, CliResult, print_json, warn};

/// Arguments of `parol6 fk`.
#[derive(Debug, clap::Args)]
pub struct FkArgs {
    /// Joint values J1,…,JN, finite numbers (rad, or degrees with --deg); outside the joint
    /// limits they are still computed, with a warning.
    #[arg(long, value_name = "J1,J2,…", allow_hyphen_values = true)]
    pub joints: String,
    /// Joint values are in degrees.
    #[arg(long)]
    pub deg: bool,
    /// Also give the TCP position in millimetres (`tcp.position_mm`).
    #[arg(long)]
    pub mm: bool,
}

/// Arguments of `parol6 ik`.
#[derive(Debug, clap::Args)]
pub struct IkArgs {
    /// Target TCP pose X,Y,Z,ROLL,PITCH,YAW, finite numbers (m and rad; see --mm and --deg).
    /// RPY is URDF's R = Rz(yaw)·Ry(pitch)·Rx(roll).
    #[arg(long, value_name = "X,Y,Z,R,P,Y", allow_hyphen_values = true)]
    pub pose: String,
    /// Angles (pose RPY and seed) are in degrees.
    #[arg(long)]
    pub deg: bool,
    /// Position is in millimetres.
    #[arg(long)]
    pub mm: bool,
    /// Seed joint values, finite numbers (default: the PAROL6 standby pose, or mid-range for other robots).
    #[arg(long, value_name = "J1,J2,…", allow_hyphen_values = true)]
    pub seed: Option<String>,
    /// Print every solution (every closed-form branch within the limits), best first.
    #[arg(long)]
    pub all: bool,
}

/// Refuses a typed value beyond a plausibility bound of [`parol6_core::limits::plausible`]
/// (exit 2, naming the option and the value). `max_abs_si` is the bound in SI units (m, rad, …);
/// `si_per_typed` converts a typed value to them (e.g. π/180 for degrees, 1e-3 for mm), and
/// `unit` names the typed unit. `first` is the 1-based position of `typed[0]` in the option.
pub fn check_plausible(
    what: &str,
    typed: &[f64],
    first: usize,
    (max_abs_si, si_per_typed): (f64, f64),
    unit: &str,
    quantity: &str,
) -> Result<(), CliError> {
    let max_typed = max_abs_si / si_per_typed;
    let unit = if unit.starts_with('°') { unit.to_string() } else { format!(" {unit}") };
    match typed.iter().position(|v| !parol6_core::limits::plausible::within(*v, max_typed)) {
        None => Ok(()),
        Some(i) => Err(CliError::usage(format!(
            "{what}: value {} ({}{unit}) is not a plausible {quantity}: the bound is ±{}{unit}",
            first + i,
            short_number(typed[i]),
            short_number(max_typed)
        ))),
    }
}

/// A number short enough for a message: scientific notation when large or tiny.
pub fn short_number(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e6 || v.abs() < 1e-4) {
        format!("{v:.3e}")
    } else {
        format!("{}", (v * 1e4).round() / 1e4)
    }
}

/// Parses joint values typed in radians, or degrees with `deg`, refuses implausible ones,
/// and returns them in radians.
pub fn parse_joint_positions(what: &str, text: &str, n: usize, deg: bool) -> Result<Vec<f64>, CliError> {
    let typed = parse_list(what, text, Some(n))?;
    let (scale, unit) = if deg { (std::f64::consts::PI / 180.0, "°") } else { (1.0, "rad") };
    let bound = parol6_core::limits::plausible::JOINT_POSITION_MAX_ABS_RAD;
    check_plausible(what, &typed, 1, (bound, scale), unit, "joint position")?;
    Ok(typed.into_iter().map(|v| v * scale).collect())
}

fn tcp_json(p: &TcpPose) -> serde_json::Value {
    json!({"position_m": p.position_m, "rpy_rad": p.rpy_rad, "quaternion_wxyz": p.quaternion_wxyz, "matrix": p.matrix4()})
}

/// Runs `parol6 fk`.
pub fn run_fk(a: &FkArgs, robot: &RobotArgs) -> CliResult {
    let model = robot.load()?;
    let q = parse_joint_positions("--joints", &a.joints, model.dof(), a.deg)?;
    let pose = model.fk(&q);
    let within = model.limits.check(&q);
    if let Err(e) = &within {
        warn(e);
    }
    let mut tcp = tcp_json(&pose);
    if a.mm {
        tcp["position_mm"] = json!(pose.position_m.map(|m| m * 1e3));
    }
    print_json(&json!({"joints_rad": q, "within_limits": within.is_ok(), "tcp": tcp}))
}

/// Default IK seed: standby for the PAROL6, mid-range otherwise.
pub fn default_seed(model: &RobotModel) -> Vec<f64> {
    if model.is_parol6 {
        parol6_core::parol6::standby_rad().to_vec()
    } else {
        model.limits.iter().map(|l| if l.is_bounded() { 0.5 * (l.min + l.max) } else { 0.0 }).collect()
    }
}

/// Runs `parol6 ik`.
pub fn run_ik(a: &IkArgs, robot: &RobotArgs) -> CliResult {
    let model = robot.load()?;
    let p = parse_list("--pose", &a.pose, Some(6))?;
    let scale = if a.mm { 1e-3 } else { 1.0 };
    let (length_unit, angle_unit) = (if a.mm { "mm" } else { "m" }, if a.deg { "°" } else { "rad" });
    let angle_scale = if a.deg { std::f64::consts::PI / 180.0 } else { 1.0 };
    let bounds = parol6_core::limits::plausible::LENGTH_MAX_ABS_M;
    check_plausible("--pose", &p[..3], 1, (bounds, scale), length_unit, "position")?;
    let angle_bound = parol6_core::limits::plausible::ANGLE_MAX_ABS_RAD;
    check_plausible("--pose", &p[3..], 4, (angle_bound, angle_scale), angle_unit, "angle")?;
    let ang = |v: f64| if a.deg { v.to_radians() } else { v };
    let target = parol6_core::kinematics::iso_from_xyz_rpy(
        [p[0] * scale, p[1] * scale, p[2] * scale],
        [ang(p[3]), ang(p[4]), ang(p[5])],
    );
    let seed = match &a.seed {
        Some(s) => parse_joint_positions("--seed", s, model.dof(), a.deg)?,
        None => default_seed(&model),
    };
    let mut sols =
        ik::solve(&model, &target, &seed).map_err(|e| CliError::usage(format!("{e}{}", unit_hint(&p[..3], a.mm))))?;
    if !a.all {
        sols.truncate(1);
    }
    let solver = if model.is_parol6 { "closed-form" } else { "numeric" };
    let list: Vec<serde_json::Value> = sols
        .iter()
        .map(|s| {
            json!({
                "joints_rad": s.joints_rad,
                "branch": s.branch.map(|b| b.label()),
                "distance_to_seed": s.distance_to_seed,
                "singular": s.singular,
            })
        })
        .collect();
    print_json(&json!({"solver": solver, "solutions": list}))
}

/// Positions beyond this distance from the base, m, are taken for millimetres typed without
/// `--mm` (no arm this program drives reaches that far).
const MM_HINT_ABOVE_M: f64 = 2.0;

/// A hint for an IK failure whose position looks like it was given in the other unit.
fn unit_hint(position: &[f64], mm: bool) -> String {
    let norm = position.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !mm && norm > MM_HINT_ABOVE_M && norm * 1e-3 <= MM_HINT_ABOVE_M {
        format!(" (the position is {norm:.3} m from the base: did you mean --mm?)")
    } else if mm && norm > 0.0 && norm < MM_HINT_ABOVE_M {
        format!(" (the position is {norm:.3} mm from the base: did you mean metres, without --mm?)")
    } else {
        String::new()
    }
}

fn random_in_limits(model: &RobotModel, rng: &mut impl Rng) -> Vec<f64> {
    model
        .limits
        .iter()
        .map(|l| {
            if l.is_bounded() {
                rng.random_range(l.min..=l.max)
            } else {
                rng.random_range(-std::f64::consts::PI..std::f64::consts::PI)
            }
        })
        .collect()
}

/// `parol6 bench fk`.
pub fn bench_fk(n: usize) -> CliResult {
    let model = RobotModel::parol6();
    let mut rng = rand::rngs::StdRng::seed_from_u64(1);
    for _ in 0..n.min(1000) {
        black_box(model.tcp_isometry(black_box(&random_in_limits(&model, &mut rng))));
    }
    // Configurations are drawn between the timed calls: no n-sized set of them in memory.
    let mut samples = Vec::with_capacity(n);
    for _ in 0..n {
        let q = random_in_limits(&model, &mut rng);
        let t0 = Instant::now();
        black_box(model.tcp_isometry(black_box(&q)));
        samples.push(t0.elapsed().as_nanos() as f64);
    }
    let s = NsStats::from_samples(&mut samples);
    let mut out = s.json();
    out["bench"] = json!("fk");
    print_json(&out)
}

/// `parol6 bench ik`: both solvers on the same random reachable in-limit poses.
pub fn bench_ik(n: usize) -> CliResult {
    let model = RobotModel::parol6();
    let mut rng = rand::rngs::StdRng::seed_from_u64(2);
    let seed = parol6_core::parol6::standby_rad();
    let targets: Vec<_> = (0..n).map(|_| model.tcp_isometry(&random_in_limits(&model, &mut rng))).collect();
    let opts = NumericIkOptions::default();
    let mut report = serde_json::Map::new();
    for solver in ["analytic", "numeric"] {
        let mut samples = Vec::with_capacity(targets.len());
        let mut ok = 0usize;
        for (i, t) in targets.iter().enumerate() {
            let t0 = Instant::now();
            let found = if solver == "analytic" {
                ik::solve_parol6(&model, black_box(t), &seed).ok().and_then(|v| v.into_iter().next())
            } else {
                ik::solve_numeric(&model, black_box(t), &seed, &opts).ok()
            };
            samples.push(t0.elapsed().as_nanos() as f64);
            if let Some(s) = found {
                let (ep, er) = ik::pose_error(&model.tcp_isometry(&s.joints_rad), t);
                if ep < 1e-6 && er < 1e-6 && model.limits.contains(&s.joints_rad) {
                    ok += 1;
                }
            }
            if i % 20_000 == 19_999 {
                super::output::progress(format_args!("bench ik {solver}: {}/{}", i + 1, targets.len()));
            }
        }
        let s = NsStats::from_samples(&mut samples);
        let mut o = s.json();
        o["success_rate"] = json!(ok as f64 / targets.len() as f64);
        report.insert(solver.to_string(), o);
    }
    let mut out = report.get("analytic").cloned().unwrap_or_default();
    out["bench"] = json!("ik");
    out["analytic"] = report.get("analytic").cloned().unwrap_or_default();
    out["numeric"] = report.get("numeric").cloned().unwrap_or_default();
    print_json(&out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ik_position_in_mm_without_mm_gets_a_hint() {
        assert!(unit_hint(&[200.0, 100.0, 300.0], false).contains("did you mean --mm?"));
        assert!(unit_hint(&[0.2, 0.1, 0.3], true).contains("without --mm"));
        assert_eq!(unit_hint(&[0.9, 0.0, 0.0], false), "");
        assert_eq!(unit_hint(&[200.0, 100.0, 300.0], true), "");
    }
}
