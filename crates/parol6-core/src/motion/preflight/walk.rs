//! The walk along one move's samples: per-sample limits and speeds, singularity samples, the
//! collision checkpoints placed by the clearance budget, the decimated TCP path (rules in the
//! parent module's docs).

use super::clearance::Clearance;
use super::problem::{Problem, Tracker};
use super::report::{CheckStatus, CheckedPoint, IssueKind, PreflightIssue, PreflightReport, Severity};
use super::singularity::{manipulability_from_frames, tcp_from_frames};
use super::{
    MIN_COLLISION_STEP_RAD, MoveKind, PAROL6_COUPLED_MOTOR, PATH_SPACING_M, PlannedMove, Preflight, SPEED_TOLERANCE,
};
use super::{SINGULARITY_ERROR_RATIO, SINGULARITY_STEP_RAD, SINGULARITY_WARN_RATIO};

/// At most this many collision checkpoints inside one sample interval. Reached only by a
/// segment moving a joint more than `MAX_CHECKS_PER_SEGMENT × MIN_COLLISION_STEP_RAD` (0.1 rad:
/// 10 rad/s at 10 ms, far above every speed cap, so already an error), where the checkpoints
/// are then spread evenly.
const MAX_CHECKS_PER_SEGMENT: f64 = 100.0;

/// Motor-6 step rate limit, steps/s (ROBOT.md §5).
const PAROL6_MOTOR6_MAX_STEPS_S: f64 = crate::parol6::MAX_SPEED_STEPS_S[5];

/// Motor-6 step rate of the PAROL6 at J4 / J6 speeds (rad/s): the API's differential-wrist
/// rule of ROBOT.md §5, `(|ω6|·10 + |ω4|·4) / (2π/6400)`.
pub fn parol6_motor6_steps_s(j4_rad_s: f64, j6_rad_s: f64) -> f64 {
    let rad_per_step = std::f64::consts::TAU / crate::parol6::MICROSTEPS_PER_MOTOR_REV;
    (j6_rad_s.abs() * crate::parol6::GEAR_RATIOS[5] + j4_rad_s.abs() * crate::parol6::GEAR_RATIOS[3]) / rad_per_step
}

/// State of the walk, reused from move to move (no allocation per sample).
pub(super) struct Walk<'p> {
    pf: &'p Preflight,
    per_sample: Tracker,
    singular: Tracker,
    collision: Tracker,
    clearance: Clearance,
    /// Joint travel since the last collision checkpoint, rad.
    travel_since_check_rad: Vec<f64>,
    /// Bound on how far any collision piece moved since the last checkpoint, m.
    worst_used_m: f64,
    /// Smallest budget of a moving piece at the last checkpoint, m.
    smallest_budget_m: f64,
    /// Scratch: bound on how far each collision piece moved since the last checkpoint, m.
    used_m: Vec<f64>,
    /// Bound on how far each collision piece moves over the current segment, m.
    rate_m: Vec<f64>,
    /// Joint travel since the last singularity sample, rad.
    travel_rad: Vec<f64>,
    /// Bound on the TCP's travel since the last path point, m.
    tcp_moved_m: f64,
    /// Worst status since the last path point.
    window: CheckStatus,
    q: Vec<f64>,
}

fn invalid_reason(mv: &PlannedMove, dof: usize) -> Option<(usize, String)> {
    let dt = mv.trajectory.dt_s();
    if !(dt.is_finite() && dt > 0.0) {
        return Some((0, format!("the sample period {dt} s is not a positive number")));
    }
    let samples = mv.trajectory.samples();
    if samples.is_empty() {
        return Some((0, "the trajectory has no samples".into()));
    }
    for (i, q) in samples.iter().enumerate() {
        if q.len() != dof {
            return Some((i, format!("sample {i} has {} joint values, the robot has {dof} joints", q.len())));
        }
        if let Some(j) = q.iter().position(|v| !v.is_finite()) {
            return Some((i, format!("sample {i}: joint {} is not a finite number ({})", j + 1, q[j])));
        }
    }
    None
}

impl<'p> Walk<'p> {
    pub(super) fn new(pf: &'p Preflight) -> Self {
        let pieces = pf.world.piece_count();
        Self {
            pf,
            per_sample: Tracker::default(),
            singular: Tracker::default(),
            collision: Tracker::default(),
            clearance: Clearance::default(),
            travel_since_check_rad: vec![0.0; pf.model.dof()],
            worst_used_m: 0.0,
            smallest_budget_m: 0.0,
            used_m: vec![0.0; pieces],
            rate_m: vec![0.0; pieces],
            travel_rad: vec![0.0; pf.model.dof()],
            tcp_moved_m: 0.0,
            window: CheckStatus::Ok,
            q: vec![0.0; pf.model.dof()],
        }
    }

    /// Joint name for messages.
    fn joint_name(&self, j: usize) -> String {
        self.pf.limits.get(j).map_or_else(|| format!("J{}", j + 1), |l| l.name.clone())
    }

    /// Adds an issue at joint values `q` (`None`: unusable values).
    fn emit(
        &self,
        report: &mut PreflightReport,
        mv: &PlannedMove,
        (problem, severity): (Problem, Severity),
        t_s: f64,
        q: Option<&[f64]>,
        detail: String,
    ) {
        let pf = self.pf;
        let tcp_mm = q.map_or([0.0; 3], |q| {
            let p = pf.model.tcp_isometry(q).translation.vector * 1000.0;
            [p.x, p.y, p.z]
        });
        let kind = problem.kind(&pf.link_names, &pf.keep_out_names);
        let what = match &kind {
            IssueKind::SelfCollision { a, b } => format!("{a} collides with {b}"),
            IssueKind::KeepOut { link, shape } => format!("{link} enters keep-out shape '{shape}'"),
            IssueKind::Ground { link } => crate::collision::below_floor_text(link),
            _ => detail,
        };
        let where_ = match q {
            Some(_) => format!(" at t = {t_s:.3} s, TCP ({:.1}, {:.1}, {:.1}) mm", tcp_mm[0], tcp_mm[1], tcp_mm[2]),
            None => String::new(),
        };
        report.issues.push(PreflightIssue {
            move_index: mv.index,
            line: mv.line,
            severity,
            kind,
            t_s,
            tcp_mm,
            message: format!("line {}, move {} ({}): {what}{where_}", mv.line, mv.index, mv.label),
        });
    }

    /// Checks one move; false when its samples are unusable (then nothing else is checked).
    pub(super) fn check_move(
        &mut self,
        mv: &PlannedMove,
        previous_end: Option<&[f64]>,
        report: &mut PreflightReport,
    ) -> bool {
        let first_issue = report.issues.len();
        let dof = self.pf.model.dof();
        if let Some((i, reason)) = invalid_reason(mv, dof) {
            let dt = mv.trajectory.dt_s();
            let t = if dt.is_finite() { i as f64 * dt } else { 0.0 };
            self.emit(report, mv, (Problem::InvalidTrajectory, Severity::Error), t, None, reason);
            return false;
        }
        for t in [&mut self.per_sample, &mut self.singular, &mut self.collision] {
            t.reset();
        }
        self.window = CheckStatus::Ok;
        let samples = mv.trajectory.samples();
        let dt = mv.trajectory.dt_s();
        if let Some(prev) = previous_end.filter(|p| p.len() == dof) {
            self.check_seam(mv, prev, &samples[0], dt, report);
        }
        let n = samples.len();
        for i in 0..n {
            let t = i as f64 * dt;
            let q = &samples[i];
            let prev = (i > 0).then(|| samples[i - 1].as_slice());
            self.check_sample(mv, q, prev, t, dt, report);
            match prev {
                None => self.collision_checkpoint(mv, q, t, report),
                Some(p) => self.advance_collision(mv, p, q, t - dt, dt, report),
            }
            let mut longest_travel_rad = 0.0f64;
            if let Some(p) = prev {
                let mut tcp_moved_m = 0.0;
                for (((travel, reach), a), b) in self.travel_rad.iter_mut().zip(&self.pf.tcp_reach_m).zip(p).zip(q) {
                    let d = (b - a).abs();
                    *travel += d;
                    longest_travel_rad = longest_travel_rad.max(*travel);
                    tcp_moved_m += reach * d;
                }
                self.tcp_moved_m += tcp_moved_m;
            }
            let ends = i == 0 || i + 1 == n;
            // on a TCP path inside the warning band, every sample (to see the error band)
            let fine = mv.kind == MoveKind::Cartesian && self.singular.any();
            let need_singular = ends || fine || longest_travel_rad >= SINGULARITY_STEP_RAD;
            let need_point = ends || self.tcp_moved_m >= PATH_SPACING_M;
            if need_singular || need_point {
                self.sample_pose(mv, q, t, need_singular, need_point, report);
            }
        }
        report.issues[first_issue..].sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
        true
    }

    fn check_seam(&mut self, mv: &PlannedMove, prev: &[f64], q0: &[f64], dt: f64, report: &mut PreflightReport) {
        let over = |j: usize| (q0[j] - prev[j]).abs() / (self.pf.speed_cap_rad_s[j] * dt);
        let worst = (0..q0.len()).max_by(|&a, &b| over(a).total_cmp(&over(b)));
        if let Some(j) = worst.filter(|&j| over(j) > 1.0 + SPEED_TOLERANCE) {
            let detail = format!(
                "starts {:.2}° ({}) away from where the previous move ends, more than one sample at the speed cap",
                (q0[j] - prev[j]).to_degrees(),
                self.joint_name(j)
            );
            self.emit(report, mv, (Problem::Discontinuity(j), Severity::Error), 0.0, Some(q0), detail);
        }
    }

    /// Limits, joint speeds and the motor-6 rate at sample `q` (speeds from `prev`).
    fn check_sample(
        &mut self,
        mv: &PlannedMove,
        q: &[f64],
        prev: Option<&[f64]>,
        t: f64,
        dt: f64,
        report: &mut PreflightReport,
    ) {
        self.per_sample.begin();
        for (j, (&v, l)) in q.iter().zip(self.pf.limits.iter()).enumerate() {
            if !l.contains(v) && self.per_sample.note(Problem::JointLimit(j), Severity::Error) {
                let (side, lim) = if v < l.min { ("lower", l.min) } else { ("upper", l.max) };
                let detail =
                    format!("{} at {:.2}° is beyond its {side} limit {:.2}°", l.name, v.to_degrees(), lim.to_degrees());
                self.emit(report, mv, (Problem::JointLimit(j), Severity::Error), t, Some(q), detail);
            }
        }
        if let Some(p) = prev {
            let per_s = 1.0 / dt;
            for (j, ((&a, &b), &cap)) in p.iter().zip(q).zip(&self.pf.speed_cap_rad_s).enumerate() {
                let w = (b - a).abs() * per_s;
                if w > cap * (1.0 + SPEED_TOLERANCE) && self.per_sample.note(Problem::JointSpeed(j), Severity::Error) {
                    let detail = format!(
                        "{} at {:.1}°/s exceeds its speed cap {:.1}°/s",
                        self.joint_name(j),
                        w.to_degrees(),
                        cap.to_degrees()
                    );
                    self.emit(report, mv, (Problem::JointSpeed(j), Severity::Error), t, Some(q), detail);
                }
            }
            if self.pf.motor6_coupling {
                let (w4, w6) = ((q[3] - p[3]) / dt, (q[5] - p[5]) / dt);
                let rate = parol6_motor6_steps_s(w4, w6);
                let m = Problem::MotorSpeed(PAROL6_COUPLED_MOTOR);
                if rate > PAROL6_MOTOR6_MAX_STEPS_S * (1.0 + SPEED_TOLERANCE)
                    && self.per_sample.note(m, Severity::Error)
                {
                    let detail = format!(
                        "motor 6 at {rate:.0} steps/s exceeds {PAROL6_MOTOR6_MAX_STEPS_S:.0} steps/s \
                         (J6 {:.1}°/s plus J4 {:.1}°/s through the differential wrist, ROBOT.md §5)",
                        w6.to_degrees(),
                        w4.to_degrees()
                    );
                    self.emit(report, mv, (m, Severity::Error), t, Some(q), detail);
                }
            }
        }
        self.per_sample.end();
        self.window = self.window.max(self.per_sample.status());
    }

    /// Singularity sample and / or path point at sample `q`.
    fn sample_pose(
        &mut self,
        mv: &PlannedMove,
        q: &[f64],
        t: f64,
        singular: bool,
        point: bool,
        report: &mut PreflightReport,
    ) {
        let model = &self.pf.model;
        let frames = if singular { model.chain_frames(q) } else { Vec::new() };
        let tcp = if singular { tcp_from_frames(model, &frames) } else { model.tcp_isometry(q).translation.vector };
        if singular {
            self.travel_rad.fill(0.0);
            self.singular.begin();
            if let Some(reference) = self.pf.reference_manipulability {
                let ratio = manipulability_from_frames(model, &frames, &tcp) / reference;
                let severity = if ratio < SINGULARITY_ERROR_RATIO && mv.kind == MoveKind::Cartesian {
                    Some(Severity::Error)
                } else if ratio < SINGULARITY_WARN_RATIO {
                    Some(Severity::Warning)
                } else {
                    None
                };
                if let Some(s) = severity.filter(|&s| self.singular.note(Problem::Singularity, s)) {
                    let detail = format!(
                        "near a singular pose (manipulability {ratio:.3} of the reference; warning below \
                         {SINGULARITY_WARN_RATIO}, error on a TCP path below {SINGULARITY_ERROR_RATIO})"
                    );
                    self.emit(report, mv, (Problem::Singularity, s), t, Some(q), detail);
                }
            }
            self.singular.end();
        }
        self.window = self.window.max(self.singular.status()).max(self.collision.status());
        if point {
            report.path.push(CheckedPoint {
                move_index: mv.index,
                t_s: t,
                tcp_m: [tcp.x, tcp.y, tcp.z],
                status: self.window,
            });
            self.tcp_moved_m = 0.0;
            self.window = self.per_sample.status().max(self.singular.status()).max(self.collision.status());
        }
    }

    /// Collision checkpoint at `q`: contacts become issues, budgets refresh.
    fn collision_checkpoint(&mut self, mv: &PlannedMove, q: &[f64], t: f64, report: &mut PreflightReport) {
        let poses = self.pf.model.link_poses(q);
        self.pf.world.evaluate(&poses, &mut self.clearance);
        self.collision.begin();
        for k in 0..self.clearance.contacts.len() {
            let p = self.clearance.contacts[k];
            if self.collision.note(p, Severity::Error) {
                self.emit(report, mv, (p, Severity::Error), t, Some(q), String::new());
            }
        }
        self.collision.end();
        self.travel_since_check_rad.fill(0.0);
        self.worst_used_m = 0.0;
        self.smallest_budget_m = self
            .clearance
            .budget_m
            .iter()
            .enumerate()
            .filter(|&(p, _)| self.pf.world.moves(p))
            .map(|(_, &b)| b)
            .fold(f64::INFINITY, f64::min);
        self.window = self.window.max(self.collision.status());
    }

    /// Walks the segment `a → b` (starting at `t0`, lasting `dt`), placing checkpoints where a
    /// piece's budget runs out.
    fn advance_collision(
        &mut self,
        mv: &PlannedMove,
        a: &[f64],
        b: &[f64],
        t0: f64,
        dt: f64,
        report: &mut PreflightReport,
    ) {
        if self.collision.any() {
            // in contact: check every sample until clear
            self.collision_checkpoint(mv, b, t0 + dt, report);
            return;
        }
        let world = &self.pf.world;
        // cheap test first: every piece as if it had the largest reach, against the smallest budget
        let mut max_step = 0.0f64;
        let mut worst_m = 0.0;
        for ((x, y), r) in a.iter().zip(b).zip(world.max_reach_m()) {
            let d = (y - x).abs();
            max_step = max_step.max(d);
            worst_m += r * d;
        }
        if self.worst_used_m + worst_m < self.smallest_budget_m {
            self.worst_used_m += worst_m;
            for ((t, x), y) in self.travel_since_check_rad.iter_mut().zip(a).zip(b) {
                *t += (y - x).abs();
            }
            return;
        }
        // per piece: used so far and what the segment adds
        for (p, (used, rate)) in self.used_m.iter_mut().zip(self.rate_m.iter_mut()).enumerate() {
            let reach = world.reach_m(p);
            *used = self.travel_since_check_rad.iter().zip(reach).map(|(d, r)| d * r).sum();
            *rate = a.iter().zip(b).zip(reach).map(|((x, y), r)| r * (y - x).abs()).sum();
        }
        let min_fraction = (MIN_COLLISION_STEP_RAD / max_step).max(1.0 / MAX_CHECKS_PER_SEGMENT);
        let mut s = 0.0;
        loop {
            let mut allowed = f64::INFINITY;
            for ((&budget, &used), &rate) in self.clearance.budget_m.iter().zip(&self.used_m).zip(&self.rate_m) {
                if rate > 0.0 {
                    allowed = allowed.min((budget - used) / rate);
                }
            }
            if s + allowed >= 1.0 {
                let rest = 1.0 - s;
                self.worst_used_m += rest * worst_m;
                for ((t, x), y) in self.travel_since_check_rad.iter_mut().zip(a).zip(b) {
                    *t += rest * (y - x).abs();
                }
                return;
            }
            let f = (s + allowed.max(min_fraction)).min(1.0);
            let mut q = std::mem::take(&mut self.q);
            q.clear();
            q.extend(a.iter().zip(b).map(|(x, y)| x + (y - x) * f));
            self.collision_checkpoint(mv, &q, t0 + f * dt, report);
            self.q = q;
            self.used_m.fill(0.0);
            s = f;
            if s >= 1.0 {
                return;
            }
            if self.collision.any() {
                self.collision_checkpoint(mv, b, t0 + dt, report);
                return;
            }
        }
    }
}
