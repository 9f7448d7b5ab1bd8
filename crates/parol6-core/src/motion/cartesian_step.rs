//! Step mode of the Cartesian jog: move the TCP by exactly a typed increment along / about an
//! axis of the world or tool frame, as a planned straight-line move ([`super::cartesian::plan`]).

use std::sync::Arc;

use super::cartesian_jog::{
    CartesianAxis, JOG_ACCEL_ANGULAR_RAD_S2, JOG_ACCEL_LINEAR_M_S2, JOG_MAX_ANGULAR_RAD_S, JOG_MAX_LINEAR_M_S,
    JogFrame, JogKinematics, displaced_pose,
};
use super::{MotionCaps, MotionError};

/// Largest linear step, m.
pub const STEP_MAX_LINEAR_M: f64 = 0.3;
/// Largest angular step, rad (120°: the orientation is slerped, which takes the short way).
pub const STEP_MAX_ANGULAR_RAD: f64 = 120.0 * std::f64::consts::PI / 180.0;
/// Sample period of a planned step, s (the simulation's control period; the serial session
/// interpolates between samples).
pub const STEP_SAMPLE_S: f64 = 0.001;

/// Checks a step's arguments: a finite, non-zero distance within the step range and a speed
/// fraction in (0, 1].
pub fn check_step(axis: CartesianAxis, distance: f64, speed_fraction: f64) -> Result<(), MotionError> {
    let (max, unit, scale) = if axis.is_rotation() {
        (STEP_MAX_ANGULAR_RAD, "°", 180.0 / std::f64::consts::PI)
    } else {
        (STEP_MAX_LINEAR_M, " mm", 1000.0)
    };
    if !(distance.is_finite() && distance != 0.0 && distance.abs() <= max) {
        return Err(MotionError::Invalid(format!(
            "{} step must be non-zero and at most {:.0}{unit}, got {}{unit}",
            axis.label(),
            max * scale,
            distance * scale
        )));
    }
    if !(speed_fraction.is_finite() && speed_fraction > 0.0 && speed_fraction <= 1.0) {
        return Err(MotionError::Invalid(format!("step speed fraction must lie in (0, 1], got {speed_fraction}")));
    }
    Ok(())
}

/// Plans a step: a straight MoveL ([`super::cartesian::plan`]) from `start_q` by exactly
/// `distance` (m, or rad for rotations) along `axis` of `frame`, at `speed_fraction` of the
/// jog speed caps (160 mm/s, 80 °/s) and the API's Cartesian accelerations and jerks.
pub fn plan_step(
    kin: &JogKinematics,
    caps: &MotionCaps,
    start_q: &[f64],
    frame: JogFrame,
    axis: CartesianAxis,
    distance: f64,
    speed_fraction: f64,
) -> Result<Arc<super::trajectory::SampledTrajectory>, MotionError> {
    use super::cartesian::{CartesianCaps, plan};
    use super::path::{ROTATION_LENGTH_M_PER_RAD, TcpPath};
    check_step(axis, distance, speed_fraction)?;
    let start = kin.model.tcp_isometry(start_q);
    let goal = displaced_pose(&start, frame, axis, distance);
    // the path parameter of a pure rotation runs ROTATION_LENGTH_M_PER_RAD per rad
    let tcp = if axis.is_rotation() {
        CartesianCaps {
            speed_m_s: JOG_MAX_ANGULAR_RAD_S * ROTATION_LENGTH_M_PER_RAD,
            accel_m_s2: JOG_ACCEL_ANGULAR_RAD_S2 * ROTATION_LENGTH_M_PER_RAD,
            jerk_m_s3: 10.0 * JOG_ACCEL_ANGULAR_RAD_S2 * ROTATION_LENGTH_M_PER_RAD,
        }
    } else {
        CartesianCaps {
            speed_m_s: JOG_MAX_LINEAR_M_S,
            accel_m_s2: JOG_ACCEL_LINEAR_M_S2,
            jerk_m_s3: 10.0 * JOG_ACCEL_LINEAR_M_S2,
        }
    };
    let mv = plan(&kin.model, start_q, &TcpPath::line(&start, &goal), &tcp, caps, speed_fraction, STEP_SAMPLE_S)
        .map_err(|e| MotionError::Invalid(format!("{} step refused: {e}", axis.label())))?;
    Ok(mv.trajectory)
}
