//! The dynamic arm's rapier step and the joint torques of a [`Simulation`]: the links carried
//! to the drives' step counters (firmware servo) or to the setpoint (ideal motors), user
//! torques, the measured state read back.

use super::{QDD_FILTER_S, SimMode, Simulation};

impl Simulation {
    /// One rapier step of the dynamic arm: torques and motor targets in, measured state out.
    pub(super) fn step_physics(&mut self) {
        if self.torque_control {
            self.physics.set_joint_torques(&self.user_torques);
        } else if let Some(servo) = self.servo.as_ref() {
            // the links carried stiffly to the drives' step counters: computed-torque
            // feedforward at the drives' position and speed, motors correct the rest
            servo.read(&mut self.q, &mut self.qd);
            self.id.compute_into(&self.model, &self.q, &self.qd, &self.sp.qdd, &mut self.ff);
            self.physics.set_joint_torques(&self.ff);
            self.physics.set_motor_targets(&self.q, &self.qd);
        } else {
            // computed-torque feedforward on the setpoint, motors correct the rest
            self.id.compute_into(&self.model, &self.sp.q, &self.sp.qd, &self.sp.qdd, &mut self.ff);
            self.physics.set_joint_torques(&self.ff);
            self.physics.set_motor_targets(&self.sp.q, &self.sp.qd);
        }
        self.physics.stop_at_limits(&self.speed_cap, self.dt_s);
        self.physics.step();
        self.physics.clamp_joint_velocities(&self.speed_cap);
        self.qd_prev.copy_from_slice(&self.link_qd);
        self.physics.read_state(&mut self.link_q, &mut self.link_qd);
        // measured acceleration, low-passed (time constant QDD_FILTER_S)
        let alpha = self.dt_s / (QDD_FILTER_S + self.dt_s);
        for i in 0..self.link_qd.len() {
            let raw = (self.link_qd[i] - self.qd_prev[i]) / self.dt_s;
            self.qdd_filt[i] += alpha * (raw - self.qdd_filt[i]);
        }
        // the board reports its step counters; without drives (ideal motors, user torques)
        // the links are what is measured
        match self.servo.as_ref().filter(|_| !self.torque_control) {
            Some(servo) => servo.read(&mut self.q, &mut self.qd),
            None => {
                self.q.copy_from_slice(&self.link_q);
                self.qd.copy_from_slice(&self.link_qd);
            }
        }
    }

    /// A torque run: this step's profile torques (plus gravity when asked), or, once its time
    /// is up, back to the motors holding where the arm is.
    pub(super) fn update_run_torques(&mut self) {
        let Some((run, start_s)) = &self.torque_run else { return };
        let t = self.sim_time_s() - start_s;
        if t >= run.duration_s {
            self.leave_torque_control();
            return;
        }
        let gravity = run.gravity_compensation;
        run.torques_into(t, &mut self.user_torques);
        if gravity {
            // missing velocities and accelerations read as 0: the gravity torques of `q`
            self.id.compute_into(&self.model, &self.q, &[], &[], &mut self.ff);
            for (u, g) in self.user_torques.iter_mut().zip(&self.ff) {
                *u += g;
            }
        }
    }

    pub(super) fn update_torques(&mut self) {
        match (self.mode, self.torque_control) {
            (SimMode::Dynamic, true) => self.torques.copy_from_slice(&self.user_torques),
            (SimMode::Dynamic, false) => {
                self.id.compute_into(&self.model, &self.link_q, &self.link_qd, &self.qdd_filt, &mut self.torques);
            }
            (SimMode::Kinematic, _) => {
                self.id.compute_into(&self.model, &self.q, &self.qd, &self.sp.qdd, &mut self.torques);
            }
        }
    }
}
