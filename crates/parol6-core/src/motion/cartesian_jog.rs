//! Cartesian jog: the TCP moves along, or turns about, one axis of the world frame or of the
//! tool frame (the TCP frame at jog start) while the button is held.
//!
//! At jog start the whole path is planned up to where it must stop ([`CartesianJogPlan`]):
//! the first joint limit, the edge of the workspace, a singularity (σ_min falling below
//! [`STOP_SIGMA`], or a joint that would turn faster than the swing bound of
//! [`crate::limits::swing`] per mm or degree of TCP motion), a collision (when a
//! [`JogObstacleCheck`] is given) or the end of the jog range. The arm decelerates to a
//! stop *at* that point, so it stops before the limit, never after. The setpoint is a pure
//! function of the time since jog start, so the simulation (1 kHz) and the serial session
//! (100 Hz) command the same trajectory.
//!
//! The path is cut into knots (1 mm, or 0.5° for rotations, halved down to 1/256 of that where
//! a joint would turn more than [`MAX_KNOT_DQ_RAD`] between two knots). Each knot is solved by
//! IK seeded with the previous one and kept in the start pose's closed-form branch; between
//! knots the joints are interpolated linearly (the TCP stays well within 0.05 mm of the line).
//! Speed along the path is, per knot interval, the least of: the commanded jog speed
//! (|fraction| between [`JOG_MIN_LINEAR_M_S`] and [`JOG_MAX_LINEAR_M_S`], or the angular
//! equivalents, ROBOT.md §5), that speed scaled down near a singularity
//! ([`singularity_scale`]), and the speed at which the fastest joint reaches its speed cap.
//! Acceleration along the path is limited to [`JOG_ACCEL_LINEAR_M_S2`] /
//! [`JOG_ACCEL_ANGULAR_RAD_S2`] (constant acceleration between knots, a forward and a backward
//! pass).

use std::fmt;
use std::sync::Arc;

use nalgebra::{Isometry3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::ik::{self, Branch};
use crate::limits::swing::{SwingOverBound, swing_over_bound};
use crate::model::RobotModel;

use super::{MotionCaps, MotionError, Setpoint};

/// Fastest linear Cartesian jog, m/s (160 mm/s = 0.8 × the 200 mm/s API cap, ROBOT.md §5).
pub const JOG_MAX_LINEAR_M_S: f64 = 0.160;
/// Slowest linear Cartesian jog, m/s (1 mm/s).
pub const JOG_MIN_LINEAR_M_S: f64 = 0.001;
/// Fastest angular Cartesian jog, rad/s (80 °/s).
pub const JOG_MAX_ANGULAR_RAD_S: f64 = 80.0 * std::f64::consts::PI / 180.0;
/// Slowest angular Cartesian jog, rad/s (1 °/s).
pub const JOG_MIN_ANGULAR_RAD_S: f64 = std::f64::consts::PI / 180.0;
/// Linear jog acceleration, m/s² (the API's 550 mm/s², ROBOT.md §5).
pub const JOG_ACCEL_LINEAR_M_S2: f64 = 0.550;
/// Angular jog acceleration, rad/s² (275 °/s²).
pub const JOG_ACCEL_ANGULAR_RAD_S2: f64 = 275.0 * std::f64::consts::PI / 180.0;
/// Knot spacing of a linear jog, m.
pub const KNOT_LINEAR_M: f64 = 0.001;
/// Knot spacing of an angular jog, rad (0.5°).
pub const KNOT_ANGULAR_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;
/// Most a joint may turn between two knots before the spacing is halved, rad (~1.1°).
pub const MAX_KNOT_DQ_RAD: f64 = 0.02;
/// Finest knot spacing, as a fraction of the normal spacing.
const MIN_KNOT_FRACTION: f64 = 1.0 / 256.0;
/// Longest linear jog planned at once, m (beyond the PAROL6's reach; the user presses again).
pub const JOG_RANGE_LINEAR_M: f64 = 1.0;
/// Longest angular jog planned at once, rad (one turn).
pub const JOG_RANGE_ANGULAR_RAD: f64 = std::f64::consts::TAU;
/// Below this smallest singular value σ_min of the TCP Jacobian (linear rows in m per rad,
/// angular rows in rad per rad) the jog slows down in proportion, σ_min / [`SLOW_SIGMA`]
/// ([`singularity_scale`]).
///
/// For the PAROL6 near its wrist singularity (J5 = 0: J4 and J6 in line) σ_min ≈ 180 mm ×
/// |sin J5| (0.0314 at 10°, 0.0157 at 5°), so the slow-down begins about 10° from J5 = 0 and
/// is at half speed 5° from it.
pub const SLOW_SIGMA: f64 = 0.03;
/// The jog stops before σ_min falls below this (about 1° from the PAROL6's wrist singularity)
/// while σ_min is falling. From a start below it (the PAROL6 standby pose has J5 = 0), motion
/// that raises σ_min, out of the singularity, is allowed.
pub const STOP_SIGMA: f64 = 0.003;
/// Largest distance of the commanded TCP from the ideal path between two knots (joint values
/// are interpolated linearly between knots), m; knots are halved until it holds.
pub const CHORD_TOLERANCE_M: f64 = 0.005e-3;
/// Largest orientation error between two knots, rad (0.005°).
pub const CHORD_TOLERANCE_RAD: f64 = 0.005 * std::f64::consts::PI / 180.0;
/// Least speed factor of the singularity slow-down.
const MIN_SCALE: f64 = 0.05;
/// Bisection steps that place a stop at a limit or the workspace edge (a knot / 4096).
const BISECT_STEPS: usize = 12;

/// Frame whose axes a Cartesian jog follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum JogFrame {
    /// The robot base (world) frame.
    World,
    /// The tool (TCP) frame at jog start.
    Tool,
}

/// Axis of a Cartesian jog: a translation along, or a rotation about, X, Y or Z.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum CartesianAxis {
    /// Along X.
    X,
    /// Along Y.
    Y,
    /// Along Z.
    Z,
    /// About X.
    Rx,
    /// About Y.
    Ry,
    /// About Z.
    Rz,
}

impl CartesianAxis {
    /// All axes, translations first.
    pub const ALL: [CartesianAxis; 6] =
        [CartesianAxis::X, CartesianAxis::Y, CartesianAxis::Z, CartesianAxis::Rx, CartesianAxis::Ry, CartesianAxis::Rz];

    /// True for Rx, Ry, Rz.
    pub fn is_rotation(self) -> bool {
        matches!(self, CartesianAxis::Rx | CartesianAxis::Ry | CartesianAxis::Rz)
    }

    /// Label (`X` … `Rz`).
    pub fn label(self) -> &'static str {
        match self {
            CartesianAxis::X => "X",
            CartesianAxis::Y => "Y",
            CartesianAxis::Z => "Z",
            CartesianAxis::Rx => "Rx",
            CartesianAxis::Ry => "Ry",
            CartesianAxis::Rz => "Rz",
        }
    }

    fn unit(self) -> Unit<Vector3<f64>> {
        match self {
            CartesianAxis::X | CartesianAxis::Rx => Vector3::x_axis(),
            CartesianAxis::Y | CartesianAxis::Ry => Vector3::y_axis(),
            CartesianAxis::Z | CartesianAxis::Rz => Vector3::z_axis(),
        }
    }
}

/// The TCP pose `amount` (m, or rad for rotations) along `axis` of `frame` from `start`.
/// Rotations turn about the TCP point, so the TCP position stays where it is.
pub fn displaced_pose(start: &Isometry3<f64>, frame: JogFrame, axis: CartesianAxis, amount: f64) -> Isometry3<f64> {
    let local = axis.unit();
    let dir = match frame {
        JogFrame::World => local,
        JogFrame::Tool => Unit::new_unchecked(start.rotation * local.into_inner()),
    };
    let mut out = *start;
    if axis.is_rotation() {
        out.rotation = UnitQuaternion::from_axis_angle(&dir, amount) * start.rotation;
    } else {
        out.translation.vector += dir.into_inner() * amount;
    }
    out
}

/// Checks a joint configuration for a collision (the simulation's collision guard).
pub trait JogObstacleCheck: Send + Sync + fmt::Debug {
    /// The two things in contact at `q` (link names, or a link and `ground`), if any.
    fn contact(&self, model: &RobotModel, q: &[f64]) -> Option<(String, String)>;
}

/// What a Cartesian jog needs besides the joint caps: the kinematic model, and optionally a
/// collision check (the simulation gives one; the serial session stops at limits,
/// singularities and the workspace edge only).
#[derive(Debug, Clone)]
pub struct JogKinematics {
    /// The robot model (FK, IK, Jacobian).
    pub model: Arc<RobotModel>,
    /// Collision check applied at every knot.
    pub obstacles: Option<Arc<dyn JogObstacleCheck>>,
}

/// Why a Cartesian jog stops where it does.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum JogStop {
    /// A joint reaches a limit (0-based joint, its name, true for the upper limit).
    Limit {
        /// 0-based joint.
        joint: usize,
        /// Joint name.
        name: String,
        /// Upper (true) or lower limit.
        upper: bool,
    },
    /// The TCP would leave the workspace (or the start pose's branch).
    Unreachable(String),
    /// A singularity ahead (the text says which measure).
    Singularity(String),
    /// Two links, or a link and the ground, would touch.
    Collision {
        /// First link.
        link_a: String,
        /// Second link or `ground`.
        link_b: String,
    },
    /// The planned range ([`JOG_RANGE_LINEAR_M`], [`JOG_RANGE_ANGULAR_RAD`]) ends.
    RangeEnd,
}

impl fmt::Display for JogStop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            JogStop::Limit { joint, name, upper } => {
                write!(f, "joint {} ({name}) {} limit", joint + 1, if *upper { "upper" } else { "lower" })
            }
            JogStop::Unreachable(why) => write!(f, "edge of the workspace: {why}"),
            JogStop::Singularity(why) => write!(f, "singularity: {why}"),
            JogStop::Collision { link_a, link_b } => write!(f, "collision of {link_a} with {link_b}"),
            JogStop::RangeEnd => write!(f, "end of the jog range: press again"),
        }
    }
}

/// Speed factor of the singularity slow-down for a smallest singular value `sigma_min`:
/// 1 above [`SLOW_SIGMA`], then `sigma_min / SLOW_SIGMA`, never below 5 %.
pub fn singularity_scale(sigma_min: f64) -> f64 {
    (sigma_min / SLOW_SIGMA).clamp(MIN_SCALE, 1.0)
}

/// The jog speed along the path for `|fraction|` (m/s, or rad/s for rotations): linear from
/// the minimum at 0 to the maximum at 1.
pub fn jog_speed(axis: CartesianAxis, fraction: f64) -> f64 {
    let f = fraction.abs().min(1.0);
    if axis.is_rotation() {
        JOG_MIN_ANGULAR_RAD_S + (JOG_MAX_ANGULAR_RAD_S - JOG_MIN_ANGULAR_RAD_S) * f
    } else {
        JOG_MIN_LINEAR_M_S + (JOG_MAX_LINEAR_M_S - JOG_MIN_LINEAR_M_S) * f
    }
}

/// A planned Cartesian jog: knots along the path with their joint values and timing.
#[derive(Debug, Clone, PartialEq)]
pub struct CartesianJogPlan {
    /// Path parameter of each knot (m, or rad for rotations), from 0, increasing.
    s: Vec<f64>,
    /// Joint values at each knot.
    q: Vec<Vec<f64>>,
    /// Path speed at each knot.
    v: Vec<f64>,
    /// Time of each knot, s.
    t: Vec<f64>,
    /// Path acceleration in each interval.
    a: Vec<f64>,
    /// +1 or −1: the direction along the axis.
    sign: f64,
    stop: JogStop,
}

struct Walker<'a> {
    kin: &'a JogKinematics,
    start: Isometry3<f64>,
    frame: JogFrame,
    axis: CartesianAxis,
    sign: f64,
    branch: Option<Branch>,
}

impl Walker<'_> {
    /// IK of the pose at `s` seeded with `seed`, in the jog's branch.
    fn solve(&self, s: f64, seed: &[f64]) -> Result<Vec<f64>, String> {
        let pose = displaced_pose(&self.start, self.frame, self.axis, self.sign * s);
        let sols = ik::solve(&self.kin.model, &pose, seed).map_err(|e| e.to_string())?;
        let pick = match self.branch {
            Some(b) => sols.into_iter().find(|x| x.branch == Some(b)),
            None => sols.into_iter().next(),
        };
        let q = pick.map(|x| x.joints_rad).ok_or_else(|| "no solution in the start pose's branch".to_string())?;
        // a joint wrapped by a turn (J6 past 0° / 360°) is the limit, not a path
        if max_dq(seed, &q) > std::f64::consts::PI {
            return Err("a joint would have to wrap round a full turn".into());
        }
        Ok(q)
    }

    /// The joint that would turn beyond the swing bound ([`crate::limits::swing`]) between two
    /// knots `ds` apart along the path (joints interpolate linearly between knots, so this bounds
    /// every setpoint in between).
    fn swing(&self, ds: f64, q_a: &[f64], q_b: &[f64]) -> Option<SwingOverBound> {
        let (travel_m, rotation_rad) = if self.axis.is_rotation() { (0.0, ds) } else { (ds, 0.0) };
        swing_over_bound(q_a, q_b, travel_m, rotation_rad)
    }

    /// True when the joints interpolated halfway between two knots put the TCP within the
    /// chord tolerances of the ideal pose halfway along the path.
    fn chord_ok(&self, s_a: f64, q_a: &[f64], s_b: f64, q_b: &[f64]) -> bool {
        let mid: Vec<f64> = q_a.iter().zip(q_b).map(|(a, b)| 0.5 * (a + b)).collect();
        let got = self.kin.model.tcp_isometry(&mid);
        let ideal = displaced_pose(&self.start, self.frame, self.axis, self.sign * 0.5 * (s_a + s_b));
        let (dp, dr) = ik::pose_error(&got, &ideal);
        dp <= CHORD_TOLERANCE_M && dr <= CHORD_TOLERANCE_RAD
    }
}

fn sigma_min(model: &RobotModel, q: &[f64]) -> f64 {
    model.manipulability(q).sigma_min
}

fn max_dq(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (y - x).abs()).fold(0.0, f64::max)
}

/// The joint nearest its limit in the direction it moves (within 0.5°), for naming a stop.
fn limit_near(model: &RobotModel, prev: &[f64], here: &[f64]) -> Option<JogStop> {
    let mut best: Option<(f64, JogStop)> = None;
    for (j, l) in model.limits.iter().enumerate() {
        let (Some(&p), Some(&h)) = (prev.get(j), here.get(j)) else { continue };
        let (gap, upper) = if h >= p { (l.max - h, true) } else { (h - l.min, false) };
        if gap < 0.5f64.to_radians() && best.as_ref().is_none_or(|(g, _)| gap < *g) {
            best = Some((gap, JogStop::Limit { joint: j, name: l.name.clone(), upper }));
        }
    }
    best.map(|(_, s)| s)
}

impl CartesianJogPlan {
    /// Plans a jog from `start_q` along `axis` of `frame`, direction and speed from `fraction`
    /// (−1…1, not 0). Refused (with the reason) when it cannot move at all.
    pub fn plan(
        kin: &JogKinematics,
        caps: &MotionCaps,
        start_q: &[f64],
        frame: JogFrame,
        axis: CartesianAxis,
        fraction: f64,
    ) -> Result<Self, MotionError> {
        if !(fraction.is_finite() && fraction != 0.0) {
            return Err(MotionError::Invalid(format!("Cartesian jog fraction must be non-zero, got {fraction}")));
        }
        let model = &kin.model;
        if start_q.len() != model.dof() {
            return Err(MotionError::Invalid(format!(
                "Cartesian jog from {} joint values, the robot has {}",
                start_q.len(),
                model.dof()
            )));
        }
        let rot = axis.is_rotation();
        let (h0, range, accel) = if rot {
            (KNOT_ANGULAR_RAD, JOG_RANGE_ANGULAR_RAD, JOG_ACCEL_ANGULAR_RAD_S2)
        } else {
            (KNOT_LINEAR_M, JOG_RANGE_LINEAR_M, JOG_ACCEL_LINEAR_M_S2)
        };
        let v_cmd = jog_speed(axis, fraction);
        let v_min = jog_speed(axis, 0.0);
        let start = model.tcp_isometry(start_q);
        let mut w = Walker { kin, start, frame, axis, sign: fraction.signum(), branch: None };
        // the branch of the solution nearest the start a little way along (at a wrist
        // singularity this picks the wrist flip that does not swing J4 and J6 round)
        if model.is_parol6 {
            let probe = displaced_pose(&start, frame, axis, w.sign * h0 * MIN_KNOT_FRACTION);
            w.branch = ik::solve(model, &probe, start_q).ok().and_then(|s| s.into_iter().next()).and_then(|s| s.branch);
        }
        let mut s = vec![0.0];
        let mut q = vec![start_q.to_vec()];
        let mut sig = vec![sigma_min(model, start_q)];
        let mut h = h0;
        let stop = loop {
            let (s_a, q_a) = (s[s.len() - 1], q[q.len() - 1].clone());
            if s_a >= range {
                break JogStop::RangeEnd;
            }
            let s_b = (s_a + h).min(range);
            let q_b = match w.solve(s_b, &q_a) {
                Ok(q_b) => {
                    let chord = w.chord_ok(s_a, &q_a, s_b, &q_b);
                    if chord && max_dq(&q_a, &q_b) <= MAX_KNOT_DQ_RAD {
                        q_b
                    } else if h > h0 * MIN_KNOT_FRACTION {
                        h *= 0.5;
                        continue;
                    } else if chord {
                        // the finest knot and still a large turn: the swing bound below stops it
                        q_b
                    } else {
                        break JogStop::Singularity("the joints cannot follow the path here".into());
                    }
                }
                Err(why) => {
                    // place the stop at the boundary: bisect between the last good knot and here
                    let (mut lo, mut hi, mut q_lo) = (s_a, s_b, q_a.clone());
                    for _ in 0..BISECT_STEPS {
                        let mid = 0.5 * (lo + hi);
                        match w.solve(mid, &q_lo) {
                            Ok(qm) if max_dq(&q_lo, &qm) <= MAX_KNOT_DQ_RAD => {
                                lo = mid;
                                q_lo = qm;
                            }
                            _ => hi = mid,
                        }
                    }
                    let reason = limit_near(model, &q_a, &q_lo)
                        .or_else(|| q.len().checked_sub(2).and_then(|k| limit_near(model, &q[k], &q_lo)))
                        .unwrap_or(JogStop::Unreachable(why));
                    if lo > s_a
                        && w.swing(lo - s_a, &q_a, &q_lo).is_none()
                        && kin.obstacles.as_ref().is_none_or(|o| o.contact(model, &q_lo).is_none())
                    {
                        sig.push(sigma_min(model, &q_lo));
                        s.push(lo);
                        q.push(q_lo);
                    }
                    break reason;
                }
            };
            // near a singular pose: stop rather than swing a joint round (the swing bound)
            if let Some(swing) = w.swing(s_b - s_a, &q_a, &q_b) {
                break JogStop::Singularity(swing.message());
            }
            let sig_b = sigma_min(model, &q_b);
            if sig_b < STOP_SIGMA && sig_b < sig[sig.len() - 1] {
                break JogStop::Singularity(format!(
                    "the Jacobian's smallest singular value would fall below {STOP_SIGMA} (σ_min = {sig_b:.2e})"
                ));
            }
            if let Some((a, b)) = kin.obstacles.as_ref().and_then(|o| o.contact(model, &q_b)) {
                break JogStop::Collision { link_a: a, link_b: b };
            }
            // the interval's speed: joint caps (too slow → a singularity ahead)
            let cap_speed = q_b
                .iter()
                .zip(&q_a)
                .zip(&caps.speed_rad_s)
                .map(|((b, a), cap)| if b == a { f64::INFINITY } else { cap * (s_b - s_a) / (b - a).abs() })
                .fold(f64::INFINITY, f64::min);
            if cap_speed < v_min && sig_b <= sig[sig.len() - 1] {
                break JogStop::Singularity("the joints would need more than their speed caps".into());
            }
            s.push(s_b);
            q.push(q_b);
            sig.push(sig_b);
            h = (h * 2.0).min(h0);
        };
        if s.len() < 2 {
            return Err(MotionError::Invalid(format!(
                "cannot jog {}{} in the {} frame: {stop}",
                if fraction > 0.0 { "+" } else { "−" },
                axis.label(),
                if frame == JogFrame::World { "world" } else { "tool" }
            )));
        }
        if s.len() == 2 {
            // one interval: add its middle so the speed can rise and fall again
            let mid = 0.5 * s[1];
            let halfway = || q[0].iter().zip(&q[1]).map(|(a, b)| 0.5 * (a + b)).collect::<Vec<f64>>();
            let qm = w
                .solve(mid, &q[0])
                .ok()
                .filter(|qm| w.swing(mid, &q[0], qm).is_none() && w.swing(s[1] - mid, qm, &q[1]).is_none())
                .unwrap_or_else(halfway);
            s.insert(1, mid);
            sig.insert(1, sigma_min(model, &qm));
            q.insert(1, qm);
        }
        Ok(Self::timed(s, q, &sig, caps, v_cmd, v_min, accel, w.sign, stop))
    }

    /// Times the knots: interval speed caps, then forward / backward acceleration passes.
    #[allow(clippy::too_many_arguments)]
    fn timed(
        s: Vec<f64>,
        q: Vec<Vec<f64>>,
        sig: &[f64],
        caps: &MotionCaps,
        v_cmd: f64,
        v_min: f64,
        accel: f64,
        sign: f64,
        stop: JogStop,
    ) -> Self {
        let n = s.len();
        let limit: Vec<f64> = (0..n - 1)
            .map(|i| {
                let ds = s[i + 1] - s[i];
                let joint = q[i + 1]
                    .iter()
                    .zip(&q[i])
                    .zip(&caps.speed_rad_s)
                    .map(|((b, a), cap)| if b == a { f64::INFINITY } else { cap * ds / (b - a).abs() })
                    .fold(f64::INFINITY, f64::min);
                let scale = singularity_scale(sig[i].min(sig[i + 1]));
                (v_cmd * scale).max(v_min.min(v_cmd)).min(joint)
            })
            .collect();
        let mut v = vec![0.0; n];
        for k in 1..n - 1 {
            v[k] = limit[k - 1].min(limit[k]);
        }
        for k in 1..n {
            v[k] = v[k].min((v[k - 1] * v[k - 1] + 2.0 * accel * (s[k] - s[k - 1])).sqrt());
        }
        for k in (0..n - 1).rev() {
            v[k] = v[k].min((v[k + 1] * v[k + 1] + 2.0 * accel * (s[k + 1] - s[k])).sqrt());
        }
        let mut t = vec![0.0; n];
        let mut a = vec![0.0; n - 1];
        for k in 0..n - 1 {
            let ds = s[k + 1] - s[k];
            let dt = 2.0 * ds / (v[k] + v[k + 1]).max(1e-12);
            t[k + 1] = t[k] + dt;
            a[k] = (v[k + 1] - v[k]) / dt;
        }
        Self { s, q, v, t, a, sign, stop }
    }

    /// Duration to the stop, s.
    pub fn duration_s(&self) -> f64 {
        self.t.last().copied().unwrap_or(0.0)
    }

    /// Why the jog stops at its end.
    pub fn stop_reason(&self) -> &JogStop {
        &self.stop
    }

    /// The fastest path speed reached in the first `window_s` seconds (m/s, or rad/s for
    /// rotations): below the commanded speed where a singularity or a joint's speed limit slows
    /// the jog from its start (trial 25 m3: 1.5 mm/s at the standby wrist, the panel said 40.8).
    pub fn top_speed_within(&self, window_s: f64) -> f64 {
        let reached = self.t.iter().take_while(|t| **t <= window_s).count();
        self.v.iter().take(reached + 1).copied().fold(0.0, f64::max)
    }

    /// Signed travel to the stop along the axis (m, or rad for rotations).
    pub fn travel(&self) -> f64 {
        self.sign * self.s.last().copied().unwrap_or(0.0)
    }

    /// Joint values at the stop.
    pub fn end_q(&self) -> &[f64] {
        self.q.last().map_or(&[], Vec::as_slice)
    }

    /// Joint values at each knot (for checks and tests).
    pub fn knots(&self) -> &[Vec<f64>] {
        &self.q
    }

    /// Signed path position (m or rad along the axis) and path speed at `t_s` after jog start.
    pub fn progress(&self, t_s: f64) -> (f64, f64) {
        let (k, tau) = self.interval(t_s);
        let ds = self.v[k] * tau + 0.5 * self.a[k] * tau * tau;
        (self.sign * (self.s[k] + ds), self.sign * (self.v[k] + self.a[k] * tau))
    }

    /// The interval at `t_s` and the time into it (clamped to the plan).
    fn interval(&self, t_s: f64) -> (usize, f64) {
        let n = self.t.len();
        let t = t_s.clamp(0.0, self.duration_s());
        let k = self.t.partition_point(|&x| x <= t).saturating_sub(1).min(n - 2);
        (k, t - self.t[k])
    }

    /// The setpoint `t_s` after jog start (at rest at the stop once past it).
    pub fn sample_into(&self, t_s: f64, out: &mut Setpoint) {
        if t_s >= self.duration_s() {
            out.set_rest(self.end_q());
            return;
        }
        let (k, tau) = self.interval(t_s);
        let ds_k = self.s[k + 1] - self.s[k];
        let ds = (self.v[k] * tau + 0.5 * self.a[k] * tau * tau).clamp(0.0, ds_k);
        let vel = self.v[k] + self.a[k] * tau;
        let f = ds / ds_k;
        let (qa, qb) = (&self.q[k], &self.q[k + 1]);
        out.resize(qa.len());
        for i in 0..qa.len() {
            let slope = (qb[i] - qa[i]) / ds_k;
            out.q[i] = qa[i] + (qb[i] - qa[i]) * f;
            out.qd[i] = slope * vel;
            out.qdd[i] = slope * self.a[k];
        }
    }
}

#[cfg(test)]
mod swing_tests;
#[cfg(test)]
mod tests;
