//! [`SampledTrajectory`]: a joint trajectory sampled at a fixed rate, the form every compiled
//! motion takes (Cartesian moves, time functions, point tables) before the planner streams it.

use super::Setpoint;

/// A joint trajectory sampled at a fixed rate; sampled in between by linear interpolation.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledTrajectory {
    dt_s: f64,
    q: Vec<Vec<f64>>,
}

impl SampledTrajectory {
    /// From samples every `dt_s`, starting at t = 0.
    pub fn new(dt_s: f64, q: Vec<Vec<f64>>) -> Self {
        Self { dt_s, q }
    }

    /// Duration, s.
    pub fn duration_s(&self) -> f64 {
        self.dt_s * self.q.len().saturating_sub(1) as f64
    }

    /// Sample period, s.
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// The samples.
    pub fn samples(&self) -> &[Vec<f64>] {
        &self.q
    }

    /// Joint values at the end.
    pub fn goal(&self) -> &[f64] {
        self.q.last().map_or(&[], Vec::as_slice)
    }

    /// The setpoint at `t_s` (held at the ends); velocity and acceleration by differences.
    pub fn sample(&self, t_s: f64) -> Setpoint {
        let mut out = Setpoint::at_rest(&[]);
        self.sample_into(t_s, &mut out);
        out
    }

    /// [`SampledTrajectory::sample`] into a caller-owned setpoint (no allocation once `out`
    /// has the right size: the 1 kHz loops use it).
    pub fn sample_into(&self, t_s: f64, out: &mut Setpoint) {
        let n = self.q.len();
        let Some(last) = self.q.last() else {
            out.set_rest(&[]);
            return;
        };
        if n == 1 || t_s >= self.duration_s() {
            out.set_rest(last);
            return;
        }
        let x = (t_s / self.dt_s).clamp(0.0, (n - 1) as f64);
        let k = (x.floor() as usize).min(n - 2);
        let f = x - k as f64;
        let (a, b) = (&self.q[k], &self.q[k + 1]);
        let dof = a.len();
        out.resize(dof);
        for i in 0..dof {
            out.q[i] = a[i] + (b[i] - a[i]) * f;
            out.qd[i] = (b[i] - a[i]) / self.dt_s;
            out.qdd[i] = match self.q.get(k + 2) {
                Some(c) => (c[i] - 2.0 * b[i] + a[i]) / (self.dt_s * self.dt_s),
                None => 0.0,
            };
        }
    }
}
