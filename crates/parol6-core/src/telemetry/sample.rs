//! [`TelemetrySample`]: one control tick as the recorder keeps it, built by [`SampleBuilder`]
//! from a backend's [`MotionSample`].

use serde::{Deserialize, Serialize};

use crate::kinematics::TcpPose;
use crate::limits::{LimitZone, ZoneThresholds};
use crate::model::RobotModel;
use crate::motion::{JointDrive, MotionSample};

/// What [`JointTelemetry::drive`] holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum DriveKind {
    /// Joint torque of the simulation, N·m.
    #[default]
    TorqueNm,
    /// Step rate reported by the controller, steps/s.
    StepsPerS,
}

/// One joint at one tick.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct JointTelemetry {
    /// Commanded position, rad.
    pub cmd_q_rad: f64,
    /// Commanded velocity, rad/s.
    pub cmd_qd_rad_s: f64,
    /// Commanded acceleration, rad/s².
    pub cmd_qdd_rad_s2: f64,
    /// Measured position, rad.
    pub q_rad: f64,
    /// Measured velocity, rad/s.
    pub qd_rad_s: f64,
    /// Measured acceleration (difference of the measured velocities of successive ticks), rad/s².
    pub qdd_rad_s2: f64,
    /// Torque (N·m, simulation) or step rate (steps/s, robot): see [`TelemetrySample::drive`].
    pub drive: f64,
    /// Limit zone of the measured position and velocity.
    pub zone: LimitZone,
}

/// Health of the serial link, as the session reports it (robot only).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct LinkHealth {
    /// Link state in words (`Connected`, `Lost`, …).
    pub state: String,
    /// Achieved frame rate, Hz.
    pub loop_rate_hz: f64,
    /// Frames sent without a reply.
    pub missing_replies: u64,
    /// Times the link was lost.
    pub link_losses: u64,
    /// E-stop input pressed.
    pub estop_pressed: bool,
}

/// One control tick.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TelemetrySample {
    /// Tick counter of the backend (contiguous while nothing is dropped).
    pub seq: u64,
    /// Motion clock of the backend, s.
    pub time_s: f64,
    /// Per joint, chain order.
    pub joints: Vec<JointTelemetry>,
    /// What [`JointTelemetry::drive`] holds.
    pub drive: DriveKind,
    /// TCP pose of the measured joints.
    pub tcp: TcpPose,
    /// Worst limit zone over the joints, with the joint index (`None` when all are safe).
    pub worst_zone: Option<(usize, LimitZone)>,
    /// Program step being run, as the caller last set it.
    pub program_step: Option<usize>,
    /// Link health as the caller last set it (`None` for the simulation).
    pub link: Option<LinkHealth>,
}

/// Builds [`TelemetrySample`]s from successive [`MotionSample`]s of one backend: differentiates
/// the measured velocity, computes the TCP pose and the limit zones.
#[derive(Debug, Clone)]
pub struct SampleBuilder {
    model: RobotModel,
    thresholds: ZoneThresholds,
    prev: Option<(f64, Vec<f64>)>,
    /// Program step stamped on the coming samples.
    pub program_step: Option<usize>,
    /// Link health stamped on the coming samples.
    pub link: Option<LinkHealth>,
}

impl SampleBuilder {
    /// A builder for `model`'s joints with these zone thresholds.
    pub fn new(model: RobotModel, thresholds: ZoneThresholds) -> Self {
        Self { model, thresholds, prev: None, program_step: None, link: None }
    }

    /// The robot model.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// The sample of `m`. Joint vectors shorter than the model's joint count are padded with
    /// NaN (what a backend did not report), longer ones cut.
    pub fn build(&mut self, m: &MotionSample) -> TelemetrySample {
        let n = self.model.dof();
        let at = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(f64::NAN);
        let dt_s = self.prev.as_ref().map(|(t, _)| m.time_s - t).filter(|dt| *dt > 0.0);
        let drive_values = m.drive.values();
        let joints: Vec<JointTelemetry> = (0..n)
            .map(|i| {
                let qd = at(&m.measured_qd, i);
                let qdd = match (dt_s, &self.prev) {
                    (Some(dt), Some((_, prev_qd))) => (qd - at(prev_qd, i)) / dt,
                    _ => 0.0,
                };
                JointTelemetry {
                    cmd_q_rad: at(&m.commanded.q, i),
                    cmd_qd_rad_s: at(&m.commanded.qd, i),
                    cmd_qdd_rad_s2: at(&m.commanded.qdd, i),
                    q_rad: at(&m.measured_q, i),
                    qd_rad_s: qd,
                    qdd_rad_s2: qdd,
                    drive: at(drive_values, i),
                    zone: LimitZone::Safe,
                }
            })
            .collect();
        match &mut self.prev {
            Some((t, v)) => {
                *t = m.time_s;
                v.clear();
                v.extend_from_slice(&m.measured_qd);
            }
            None => self.prev = Some((m.time_s, m.measured_qd.clone())),
        }
        let mut joints = joints;
        let q: Vec<f64> = joints.iter().map(|j| j.q_rad).collect();
        for (j, (l, &q)) in joints.iter_mut().zip(self.model.limits.iter().zip(&q)) {
            j.zone = self.thresholds.predictive_zone(l, q, j.qd_rad_s).zone;
        }
        let worst_zone = joints
            .iter()
            .enumerate()
            .filter(|(_, j)| j.zone != LimitZone::Safe)
            .max_by_key(|(_, j)| j.zone)
            .map(|(i, j)| (i, j.zone));
        TelemetrySample {
            seq: m.seq,
            time_s: m.time_s,
            joints,
            drive: match m.drive {
                JointDrive::TorqueNm(_) => DriveKind::TorqueNm,
                JointDrive::StepsPerS(_) => DriveKind::StepsPerS,
            },
            tcp: self.model.fk(&q),
            worst_zone,
            program_step: self.program_step,
            link: self.link.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::Setpoint;

    fn motion(seq: u64, t: f64, q: &[f64], qd: &[f64]) -> MotionSample {
        MotionSample {
            seq,
            time_s: t,
            commanded: Setpoint::at_rest(q),
            measured_q: q.to_vec(),
            measured_qd: qd.to_vec(),
            drive: JointDrive::TorqueNm(vec![1.5; q.len()]),
        }
    }

    #[test]
    fn builds_joints_acceleration_tcp_and_zone() {
        let model = RobotModel::parol6();
        let home = crate::motion::home_position(&model);
        let mut b = SampleBuilder::new(model.clone(), ZoneThresholds::default());
        b.program_step = Some(3);
        let s0 = b.build(&motion(1, 0.0, &home, &[0.0; 6]));
        assert_eq!(s0.joints.len(), 6);
        assert_eq!(s0.joints[0].qdd_rad_s2, 0.0);
        assert_eq!(s0.program_step, Some(3));
        assert_eq!(s0.drive, DriveKind::TorqueNm);
        assert_eq!(s0.joints[2].drive, 1.5);
        assert_eq!(s0.tcp, model.fk(&home));
        let s1 = b.build(&motion(2, 0.001, &home, &[0.002, 0.0, 0.0, 0.0, 0.0, 0.0]));
        assert!((s1.joints[0].qdd_rad_s2 - 2.0).abs() < 1e-9, "{}", s1.joints[0].qdd_rad_s2);
        // a joint at its upper limit is the worst zone
        let mut q = home.clone();
        q[1] = model.limits.iter().nth(1).map(|l| l.max).unwrap_or(0.0);
        let s2 = b.build(&motion(3, 0.002, &q, &[0.0; 6]));
        assert_eq!(s2.worst_zone, Some((1, LimitZone::Critical)));
    }

    #[test]
    fn short_vectors_are_padded_with_nan_not_a_panic() {
        let mut b = SampleBuilder::new(RobotModel::parol6(), ZoneThresholds::default());
        let s = b.build(&motion(1, 0.0, &[0.1, 0.2], &[]));
        assert_eq!(s.joints.len(), 6);
        assert!(s.joints[3].q_rad.is_nan() && s.joints[0].qd_rad_s.is_nan());
    }
}
