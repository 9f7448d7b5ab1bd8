//! Forward dynamics input: a torque profile per joint (constant, a step at a time, a sine) run
//! on the dynamic simulation for a bounded time ([`super::SimCommand::RunJointTorques`]). The
//! joint limits stay enforced (the multibody stops a joint at its limit) and a motion command
//! (STOP among them) ends the run; at the end the motors take over and hold where the arm is.

use serde::{Deserialize, Serialize};

/// Largest |torque| a profile may ask of one joint, N·m: a sanity bound on input (ten times the
/// strongest PAROL6 joint limit, [`crate::parol6::joint_torque_limits_nm`]), not a motor rating.
pub const MAX_PROFILE_TORQUE_NM: f64 = 100.0;
/// Longest run, s.
pub const MAX_RUN_S: f64 = 600.0;

/// The torque of one joint over the run's time `t` (from its start), N·m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum TorqueProfile {
    /// `torque_nm` throughout.
    Constant {
        /// Torque, N·m.
        torque_nm: f64,
    },
    /// `before_nm` until `at_s`, then `after_nm`.
    Step {
        /// Torque before the step, N·m.
        before_nm: f64,
        /// Torque from `at_s` on, N·m.
        after_nm: f64,
        /// Time of the step from the start of the run, s.
        at_s: f64,
    },
    /// `offset_nm + amplitude_nm · sin(2π t / period_s)`.
    Sine {
        /// Mean torque, N·m.
        offset_nm: f64,
        /// Amplitude, N·m.
        amplitude_nm: f64,
        /// Period, s (> 0).
        period_s: f64,
    },
}

impl Default for TorqueProfile {
    fn default() -> Self {
        TorqueProfile::Constant { torque_nm: 0.0 }
    }
}

impl TorqueProfile {
    /// Torque at `t_s` from the start of the run, N·m.
    pub fn at(&self, t_s: f64) -> f64 {
        match *self {
            TorqueProfile::Constant { torque_nm } => torque_nm,
            TorqueProfile::Step { before_nm, after_nm, at_s } => {
                if t_s < at_s {
                    before_nm
                } else {
                    after_nm
                }
            }
            TorqueProfile::Sine { offset_nm, amplitude_nm, period_s } => {
                offset_nm + amplitude_nm * (std::f64::consts::TAU * t_s / period_s).sin()
            }
        }
    }

    /// Largest |torque| the profile reaches, N·m.
    pub fn peak_abs_nm(&self) -> f64 {
        match *self {
            TorqueProfile::Constant { torque_nm } => torque_nm.abs(),
            TorqueProfile::Step { before_nm, after_nm, .. } => before_nm.abs().max(after_nm.abs()),
            TorqueProfile::Sine { offset_nm, amplitude_nm, .. } => offset_nm.abs() + amplitude_nm.abs(),
        }
    }

    /// Checks the numbers; the error names the field.
    pub fn validate(&self) -> Result<(), String> {
        let fields: &[(&str, f64)] = match self {
            TorqueProfile::Constant { torque_nm } => &[("torque_nm", *torque_nm)],
            TorqueProfile::Step { before_nm, after_nm, at_s } => {
                &[("before_nm", *before_nm), ("after_nm", *after_nm), ("at_s", *at_s)]
            }
            TorqueProfile::Sine { offset_nm, amplitude_nm, period_s } => {
                &[("offset_nm", *offset_nm), ("amplitude_nm", *amplitude_nm), ("period_s", *period_s)]
            }
        };
        if let Some((name, _)) = fields.iter().find(|(_, v)| !v.is_finite()) {
            return Err(format!("{name} is not a finite number"));
        }
        if let TorqueProfile::Sine { period_s, .. } = self
            && *period_s <= 0.0
        {
            return Err(format!("period_s must be > 0, got {period_s}"));
        }
        if let TorqueProfile::Step { at_s, .. } = self
            && *at_s < 0.0
        {
            return Err(format!("at_s must be ≥ 0, got {at_s}"));
        }
        if self.peak_abs_nm() > MAX_PROFILE_TORQUE_NM {
            return Err(format!("peak torque {:.3} N·m exceeds {MAX_PROFILE_TORQUE_NM} N·m", self.peak_abs_nm()));
        }
        Ok(())
    }
}

/// A forward-dynamics run: one profile per joint for `duration_s`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TorqueRun {
    /// Per joint, chain order.
    pub joints: Vec<TorqueProfile>,
    /// How long, s (0 < d ≤ [`MAX_RUN_S`]).
    pub duration_s: f64,
    /// Add the gravity torques of the current pose at every step, so that all-zero profiles
    /// hold the arm still and the entered torques only accelerate it.
    pub gravity_compensation: bool,
    /// Keep the joints without a torque (a constant 0 N·m profile) on their position motors,
    /// holding where they were when the run started; off, every joint is free.
    #[serde(default)]
    pub hold_others: bool,
}

impl TorqueRun {
    /// Checks the run for a robot of `dof` joints; the error names the joint and field.
    pub fn validate(&self, dof: usize) -> Result<(), String> {
        if self.joints.len() != dof {
            return Err(format!("expected {dof} joint torque profiles, got {}", self.joints.len()));
        }
        if !(self.duration_s.is_finite() && self.duration_s > 0.0 && self.duration_s <= MAX_RUN_S) {
            return Err(format!("duration must be within (0, {MAX_RUN_S}] s, got {}", self.duration_s));
        }
        for (i, p) in self.joints.iter().enumerate() {
            p.validate().map_err(|e| format!("joint {}: {e}", i + 1))?;
        }
        Ok(())
    }

    /// The profile torques at `t_s` from the start, into `out`.
    /// The joints the run holds on their motors: with [`TorqueRun::hold_others`], those
    /// without a torque (a constant 0 N·m profile).
    pub fn held_joints(&self) -> Vec<bool> {
        self.joints.iter().map(|p| self.hold_others && *p == TorqueProfile::Constant { torque_nm: 0.0 }).collect()
    }

    pub fn torques_into(&self, t_s: f64, out: &mut [f64]) {
        for (o, p) in out.iter_mut().zip(&self.joints) {
            *o = p.at(t_s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_give_their_torques() {
        assert_eq!(TorqueProfile::Constant { torque_nm: -1.5 }.at(3.0), -1.5);
        let step = TorqueProfile::Step { before_nm: 1.0, after_nm: 2.0, at_s: 0.5 };
        assert_eq!((step.at(0.49), step.at(0.5), step.at(9.0)), (1.0, 2.0, 2.0));
        let sine = TorqueProfile::Sine { offset_nm: 1.0, amplitude_nm: 2.0, period_s: 4.0 };
        assert!((sine.at(1.0) - 3.0).abs() < 1e-12 && (sine.at(3.0) + 1.0).abs() < 1e-12);
        assert_eq!(sine.peak_abs_nm(), 3.0);
    }

    #[test]
    fn bad_numbers_are_refused_naming_the_joint_and_field() {
        let ok = TorqueRun {
            joints: vec![TorqueProfile::default(); 2],
            duration_s: 1.0,
            gravity_compensation: true,
            hold_others: false,
        };
        assert!(ok.validate(2).is_ok());
        assert!(ok.validate(3).is_err());
        let mut bad = ok.clone();
        bad.joints[1] = TorqueProfile::Sine { offset_nm: 0.0, amplitude_nm: 1.0, period_s: 0.0 };
        let e = bad.validate(2).expect_err("zero period");
        assert!(e.contains("joint 2") && e.contains("period_s"), "{e}");
        bad.joints[1] = TorqueProfile::Constant { torque_nm: f64::NAN };
        assert!(bad.validate(2).expect_err("nan").contains("torque_nm"));
        bad.joints[1] = TorqueProfile::Constant { torque_nm: 1e3 };
        assert!(bad.validate(2).is_err());
        for d in [0.0, -1.0, f64::INFINITY, MAX_RUN_S + 1.0] {
            assert!(TorqueRun { duration_s: d, ..ok.clone() }.validate(2).is_err(), "{d}");
        }
    }
}
