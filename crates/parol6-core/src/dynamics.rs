//! Inverse dynamics by the recursive Newton–Euler algorithm (nalgebra, f64) from the URDF
//! inertials: the joint torques a motion needs, split into gravity and inertial + Coriolis
//! parts. Gravity is −z, [`GRAVITY_M_S2`].
//!
//! The multibody ([`crate::sim::multibody`]) builds on this module (body inertials, gravity), never
//! the other way round.

use nalgebra::{Matrix3, Point3, Vector3};
use serde::Serialize;

use crate::model::{Inertial, JointKind, RobotModel};

/// Why inverse dynamics refused its input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DynamicsError {
    /// A vector of the wrong length or a non-finite value.
    #[error("{0}")]
    InvalidInput(String),
}

/// Standard gravity, m/s² (along −z).
pub const GRAVITY_M_S2: f64 = 9.81;

/// Mass properties of each chain body (index 0 = root), every link riding on that frame merged,
/// expressed in the chain frame: COM in frame coordinates, inertia about the COM in frame axes.
/// The tool's mass ([`RobotModel::tool_inertial`], in the tip frame) rides on the last body.
/// `None` for a frame with no massive link.
pub fn body_inertials(model: &RobotModel) -> Vec<Option<Inertial>> {
    let mut out: Vec<Option<Inertial>> = vec![None; model.dof() + 1];
    let tool = model.tool_inertial.as_ref().map(|t| (model.dof(), model.tip_offset, t));
    let links = model.links.iter().filter_map(|l| l.inertial.as_ref().map(|i| (l.frame, l.offset, i)));
    for (frame, offset, li) in links.chain(tool) {
        if !(li.mass_kg.is_finite() && li.mass_kg > 0.0) {
            continue;
        }
        let Some(slot) = out.get_mut(frame) else { continue };
        let r = offset.rotation.to_rotation_matrix().into_inner();
        let com = offset * li.com_m;
        let inertia = r * li.inertia_kg_m2 * r.transpose();
        *slot = Some(match slot.take() {
            None => Inertial { mass_kg: li.mass_kg, com_m: com, inertia_kg_m2: inertia },
            Some(prev) => merge(&prev, &Inertial { mass_kg: li.mass_kg, com_m: com, inertia_kg_m2: inertia }),
        });
    }
    out
}

/// Parallel-axis term: inertia of a point mass `m` at offset `d`.
fn shift(m: f64, d: &Vector3<f64>) -> Matrix3<f64> {
    (Matrix3::identity() * d.dot(d) - d * d.transpose()) * m
}

fn merge(a: &Inertial, b: &Inertial) -> Inertial {
    let m = a.mass_kg + b.mass_kg;
    let c = Point3::from((a.com_m.coords * a.mass_kg + b.com_m.coords * b.mass_kg) / m);
    let ia = a.inertia_kg_m2 + shift(a.mass_kg, &(a.com_m - c));
    let ib = b.inertia_kg_m2 + shift(b.mass_kg, &(b.com_m - c));
    Inertial { mass_kg: m, com_m: c, inertia_kg_m2: ia + ib }
}

/// Joint torques of a motion (N·m for revolute joints, N for prismatic).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointTorques {
    /// Total: gravity + inertial + Coriolis/centrifugal.
    pub total_nm: Vec<f64>,
    /// Gravity part (the torques to hold `q` at rest).
    pub gravity_nm: Vec<f64>,
    /// Inertial + Coriolis/centrifugal part (`total − gravity`).
    pub inertial_coriolis_nm: Vec<f64>,
}

/// Recursive Newton–Euler inverse dynamics with preallocated buffers (no allocation per call).
#[derive(Debug, Clone)]
pub struct InverseDynamics {
    mass: Vec<f64>,
    com: Vec<Vector3<f64>>,
    inertia: Vec<Matrix3<f64>>,
    omega: Vec<Vector3<f64>>,
    alpha: Vec<Vector3<f64>>,
    acc: Vec<Vector3<f64>>,
    force: Vec<Vector3<f64>>,
    moment: Vec<Vector3<f64>>,
    rot: Vec<Matrix3<f64>>,
    pos: Vec<Vector3<f64>>,
    zeros: Vec<f64>,
}

impl InverseDynamics {
    /// Prepares the mass properties of `model` (chain bodies 1..=dof).
    pub fn new(model: &RobotModel) -> Self {
        let n = model.dof();
        let bodies = body_inertials(model);
        let mut mass = vec![0.0; n];
        let mut com = vec![Vector3::zeros(); n];
        let mut inertia = vec![Matrix3::zeros(); n];
        for i in 0..n {
            if let Some(Some(b)) = bodies.get(i + 1) {
                mass[i] = b.mass_kg;
                com[i] = b.com_m.coords;
                inertia[i] = b.inertia_kg_m2;
            }
        }
        Self {
            mass,
            com,
            inertia,
            omega: vec![Vector3::zeros(); n],
            alpha: vec![Vector3::zeros(); n],
            acc: vec![Vector3::zeros(); n],
            force: vec![Vector3::zeros(); n],
            moment: vec![Vector3::zeros(); n],
            rot: vec![Matrix3::identity(); n],
            pos: vec![Vector3::zeros(); n],
            zeros: vec![0.0; n],
        }
    }

    /// Torques for (`q`, `qd`, `qdd`) with gravity scaled by `gravity_scale` (1 = Earth,
    /// 0 = none), written into `out`. Inputs must have `dof` values (missing ones read as 0).
    pub fn compute_scaled_into(
        &mut self,
        model: &RobotModel,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        gravity_scale: f64,
        out: &mut [f64],
    ) {
        let n = self.mass.len().min(model.joints.len());
        let at = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(0.0);
        // forward pass, in each body's own frame
        let mut w_prev = Vector3::zeros();
        let mut al_prev = Vector3::zeros();
        // the base accelerates upward at g: gravity for free
        let mut a_prev = Vector3::new(0.0, 0.0, GRAVITY_M_S2 * gravity_scale);
        for i in 0..n {
            let j = &model.joints[i];
            let z = j.axis.into_inner();
            let (qi, qdi, qddi) = (at(q, i), at(qd, i), at(qdd, i));
            let motion = match j.kind {
                JointKind::Prismatic => nalgebra::Isometry3::translation(z.x * qi, z.y * qi, z.z * qi),
                _ => nalgebra::Isometry3::rotation(z * qi),
            };
            let t = j.origin * motion;
            let r = t.rotation.to_rotation_matrix().into_inner();
            let p = t.translation.vector;
            let rt = r.transpose();
            let a_origin = rt * (a_prev + al_prev.cross(&p) + w_prev.cross(&w_prev.cross(&p)));
            let (w, al, a) = match j.kind {
                JointKind::Prismatic => {
                    let w = rt * w_prev;
                    (w, rt * al_prev, a_origin + w.cross(&z) * (2.0 * qdi) + z * qddi)
                }
                _ => {
                    let w0 = rt * w_prev;
                    (w0 + z * qdi, rt * al_prev + w0.cross(&z) * qdi + z * qddi, a_origin)
                }
            };
            self.rot[i] = r;
            self.pos[i] = p;
            self.omega[i] = w;
            self.alpha[i] = al;
            self.acc[i] = a;
            w_prev = w;
            al_prev = al;
            a_prev = a;
        }
        // backward pass
        let mut f_next = Vector3::zeros();
        let mut n_next = Vector3::zeros();
        for i in (0..n).rev() {
            let (w, al, c) = (self.omega[i], self.alpha[i], self.com[i]);
            let a_c = self.acc[i] + al.cross(&c) + w.cross(&w.cross(&c));
            let f_i = a_c * self.mass[i];
            let n_i = self.inertia[i] * al + w.cross(&(self.inertia[i] * w));
            // child's wrench expressed in this frame
            let (f_child, n_child, p_child) = if i + 1 < n {
                (self.rot[i + 1] * f_next, self.rot[i + 1] * n_next, self.pos[i + 1])
            } else {
                (Vector3::zeros(), Vector3::zeros(), Vector3::zeros())
            };
            let f = f_child + f_i;
            let m = n_i + n_child + c.cross(&f_i) + p_child.cross(&f_child);
            self.force[i] = f;
            self.moment[i] = m;
            let z = model.joints[i].axis.into_inner();
            if let Some(o) = out.get_mut(i) {
                *o = if model.joints[i].kind == JointKind::Prismatic { f.dot(&z) } else { m.dot(&z) };
            }
            f_next = f;
            n_next = m;
        }
    }

    /// Torques for (`q`, `qd`, `qdd`) under Earth gravity, written into `out`.
    pub fn compute_into(&mut self, model: &RobotModel, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        self.compute_scaled_into(model, q, qd, qdd, 1.0, out);
    }

    /// Torques with their gravity and inertial + Coriolis parts. Refuses vectors of the wrong
    /// length and non-finite values.
    pub fn compute(
        &mut self,
        model: &RobotModel,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> Result<JointTorques, DynamicsError> {
        let n = model.dof();
        for (what, v) in [("positions", q), ("velocities", qd), ("accelerations", qdd)] {
            if v.len() != n {
                return Err(DynamicsError::InvalidInput(format!("expected {n} joint {what}, got {}", v.len())));
            }
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(DynamicsError::InvalidInput(format!("joint {} {what} value is not finite", i + 1)));
            }
        }
        let mut total = vec![0.0; n];
        let mut gravity = vec![0.0; n];
        self.compute_into(model, q, qd, qdd, &mut total);
        let zeros = std::mem::take(&mut self.zeros);
        self.compute_into(model, q, &zeros, &zeros, &mut gravity);
        self.zeros = zeros;
        let inertial = total.iter().zip(&gravity).map(|(t, g)| t - g).collect();
        Ok(JointTorques { total_nm: total, gravity_nm: gravity, inertial_coriolis_nm: inertial })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parol6::Tool;

    /// Gravity torques (holding) at `q`.
    fn holding(model: &RobotModel, q: &[f64]) -> Vec<f64> {
        let zeros = vec![0.0; model.dof()];
        InverseDynamics::new(model).compute(model, q, &zeros, &zeros).expect("valid").gravity_nm
    }

    /// The issue: `--tool ssg48` gave the same torques as no tool. With the SSG-48 on the
    /// flange and the arm stretched out horizontally, J2 must hold the tool's weight on its
    /// lever too: the extra holding torque is the tool's weight through the Jacobian of its
    /// centre of mass, `J_v(com)ᵀ · m·g·ẑ`.
    #[test]
    fn the_ssg48_raises_the_j2_holding_torque_at_a_stretched_pose() {
        let bare = RobotModel::parol6();
        let tool = RobotModel::parol6_with_tool(Tool::Ssg48);
        let mass_kg = Tool::Ssg48.mass_kg();
        assert!(mass_kg > 0.1, "the SSG-48 has a mass: {mass_kg} kg");
        // stretched: the arm (J2 / J3) reaching out as far as it goes horizontally, J5 pointing the tool on
        let mut best = (0.0, crate::parol6::standby_rad().to_vec());
        for k in 0..=60 {
            let mut q = crate::parol6::standby_rad().to_vec();
            q[1] = bare.limits.get(1).map_or(0.0, |l| l.min + (l.max - l.min) * f64::from(k) / 60.0);
            let reach = bare.tcp_isometry(&q).translation.vector.xy().norm();
            if reach > best.0 {
                best = (reach, q);
            }
        }
        let q = best.1;
        let (t_bare, t_tool) = (holding(&bare, &q), holding(&tool, &q));
        let frames = tool.chain_frames(&q);
        let com = tool.flange_pose(&q) * nalgebra::Point3::from(Vector3::from(Tool::Ssg48.com_m()));
        let jac = tool.jacobian_from_frames(&frames, &com.coords);
        let weight = Vector3::new(0.0, 0.0, mass_kg * GRAVITY_M_S2);
        for j in 0..6 {
            let expected = jac.fixed_view::<3, 1>(0, j).dot(&weight);
            let got = t_tool[j] - t_bare[j];
            assert!((got - expected).abs() < 1e-9, "J{}: +{got:.4} N·m, expected +{expected:.4} N·m", j + 1);
        }
        let extra = (t_tool[1] - t_bare[1]).abs();
        assert!(
            t_tool[1].abs() > t_bare[1].abs() && extra > mass_kg * GRAVITY_M_S2 * 0.1,
            "J2 holds {:.3} N·m bare, {:.3} N·m with the SSG-48 at reach {:.0} mm",
            t_bare[1],
            t_tool[1],
            best.0 * 1e3
        );
        // no tool, no change
        assert_eq!(holding(&RobotModel::parol6_with_tool(Tool::None), &q), t_bare);
    }
}
