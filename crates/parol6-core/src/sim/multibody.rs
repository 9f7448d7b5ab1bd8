//! The rapier3d multibody built from a [`RobotModel`]: one rigid body per chain frame (links
//! on the same frame merged), one reduced-coordinate joint per movable joint with its limits
//! and a position motor, colliders from the collision geometry (convex shapes; meshes as
//! convex hulls), a ground plane, Z-up gravity, no sleeping.
//!
//! Joint order and values equal the model's: joint k's coordinate is exactly `q[k]` of
//! [`RobotModel::chain_frames`]. rapier works in `f32`; conversions happen here.

use nalgebra::{Isometry3, Matrix3, UnitQuaternion, Vector3};
use rapier3d::prelude::*;

use super::types::SimError;
use crate::collision::{convex_shape, pose_from_iso};
pub use crate::dynamics::GRAVITY_M_S2;
use crate::dynamics::body_inertials;
use crate::model::{JointKind, RobotModel};

/// Solver iterations per step. The multibody's own dynamics are exact in reduced coordinates;
/// the iterations only resolve motors, limits and ground contacts. One keeps the step cheap
/// (rapier's default of 4 costs about 3×); the few mrad a hard push can then pass a limit by
/// are taken back by the end stops ([`Physics::project_into_limits`]).
pub const SOLVER_ITERATIONS: usize = 1;

/// The robot's colliders touch only the ground: its self-collisions are the guard's
/// ([`super::collision`]), so rapier's narrow phase never computes a link–link pair (they were
/// 4.5 % of the step's instructions).
const LINK_GROUPS: InteractionGroups = InteractionGroups::new(Group::GROUP_1, Group::GROUP_2, InteractionTestMode::And);
/// A link whose height cannot change and that clears the ground (the base, and the links
/// turned only about the vertical J1 axis): rapier never pairs it with the ground, which it
/// cannot touch (the ground–L1 pair was about 15 % of the step's time).
const LEVEL_LINK_GROUPS: InteractionGroups =
    InteractionGroups::new(Group::GROUP_3, Group::NONE, InteractionTestMode::And);
/// Half the side of the ground slab, m: its top face is the plane z = 0 over 200 m × 200 m, far
/// beyond any arm's reach.
const GROUND_HALF_EXTENT_M: f32 = 100.0;
/// The ground touches the robot's links.
const GROUND_GROUPS: InteractionGroups =
    InteractionGroups::new(Group::GROUP_2, Group::GROUP_1, InteractionTestMode::And);

/// Position-motor gains (rapier's acceleration-based model: per unit of effective inertia).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorGains {
    /// Stiffness, 1/s².
    pub stiffness: f64,
    /// Damping, 1/s.
    pub damping: f64,
}

impl Default for MotorGains {
    /// ω = √k ≈ 707 rad/s, overdamped (ζ ≈ 2.8) so a step onto a limit does not overshoot it:
    /// ≤ 0.6 mrad steady error under gravity even without the inverse-dynamics feedforward
    /// the simulation adds; a 0.5 rad step settles to 2 mrad in about 45 ms.
    fn default() -> Self {
        Self { stiffness: 5.0e5, damping: 4000.0 }
    }
}

pub(crate) fn vec_from_na(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x as f32, v.y as f32, v.z as f32)
}

/// Per chain frame: true where no joint between it and the fixed root can change its height
/// (every joint on the way is revolute about the world vertical, as J1 is).
pub(crate) fn frames_at_fixed_height(model: &RobotModel, frames: &[Isometry3<f64>]) -> Vec<bool> {
    let mut level = vec![true; frames.len()];
    for (k, j) in model.joints.iter().enumerate() {
        let axis_world = frames.get(k).map(|f| f.rotation * (j.origin.rotation * j.axis.into_inner()));
        let vertical = matches!(j.kind, JointKind::Revolute | JointKind::Continuous)
            && axis_world.is_some_and(|a| a.x.abs() < 1e-9 && a.y.abs() < 1e-9);
        let parent_level = level.get(k).copied().unwrap_or(false);
        if let Some(l) = level.get_mut(k + 1) {
            *l = parent_level && vertical;
        }
    }
    level
}

/// Rotation taking +x to `axis` (the free axis of a rapier revolute/prismatic joint is x).
fn x_to_axis(axis: &Vector3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::rotation_between(&Vector3::x(), axis)
        .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI))
}

/// A rapier world holding the robot.
pub struct Physics {
    world: PhysicsWorld,
    /// Rigid body of each chain frame (0 = root, fixed).
    bodies: Vec<RigidBodyHandle>,
    /// Multibody joint of each movable joint.
    joints: Vec<MultibodyJointHandle>,
    kinds: Vec<JointKind>,
    /// Joint axis in each child body's frame (unit).
    axes_local: Vec<Vector>,
    limits: Vec<[f32; 2]>,
    gains: MotorGains,
    motors_enabled: bool,
    collider_count: usize,
    disp: DVector,
}

impl std::fmt::Debug for Physics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Physics").field("joints", &self.joints.len()).field("colliders", &self.collider_count).finish()
    }
}

fn free_axis(kind: JointKind) -> JointAxis {
    if kind == JointKind::Prismatic { JointAxis::LinX } else { JointAxis::AngX }
}

impl Physics {
    /// Builds the multibody at q = 0 (call [`Physics::teleport`] to place it).
    pub fn build(model: &RobotModel, dt_s: f64) -> Result<Self, SimError> {
        Self::build_with_gains(model, dt_s, MotorGains::default())
    }

    /// Like [`Physics::build`] with explicit motor gains.
    pub fn build_with_gains(model: &RobotModel, dt_s: f64, gains: MotorGains) -> Result<Self, SimError> {
        let n = model.dof();
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -GRAVITY_M_S2 as f32);
        world.integration_parameters.dt = dt_s as f32;
        world.integration_parameters.num_solver_iterations = SOLVER_ITERATIONS;

        // ground plane (fixed, its own body so the robot root never touches it in the solver)
        let ground = world.insert_body(RigidBodyBuilder::fixed());
        // a slab, not a half-space: a half-space's bounding box is infinite, so the broad phase
        // paired it with every link and the narrow phase tested them all at every step
        world.insert_collider(
            ColliderBuilder::cuboid(GROUND_HALF_EXTENT_M, GROUND_HALF_EXTENT_M, GROUND_HALF_EXTENT_M)
                .translation(Vector::new(0.0, 0.0, -GROUND_HALF_EXTENT_M))
                .collision_groups(GROUND_GROUPS),
            Some(ground),
        );

        let zeros = vec![0.0; n];
        let frames = model.chain_frames(&zeros);
        let inertials = body_inertials(model);
        let mut bodies = Vec::with_capacity(n + 1);
        for (k, frame) in frames.iter().enumerate() {
            let builder = if k == 0 { RigidBodyBuilder::fixed() } else { RigidBodyBuilder::dynamic() };
            let mut builder =
                builder.pose(pose_from_iso(frame)).can_sleep(false).linear_damping(0.0).angular_damping(0.0);
            if k > 0 {
                // a link with no inertial gets a tiny one so the multibody stays invertible
                let (mass, com, inertia) = match inertials.get(k).and_then(|b| b.as_ref()) {
                    Some(b) if b.mass_kg > 0.0 => (b.mass_kg, b.com_m.coords, b.inertia_kg_m2),
                    _ => (1e-3, Vector3::zeros(), Matrix3::identity() * 1e-7),
                };
                let m = inertia.map(|v| v as f32);
                let mat = Matrix::from_cols(
                    Vector::new(m[(0, 0)], m[(1, 0)], m[(2, 0)]),
                    Vector::new(m[(0, 1)], m[(1, 1)], m[(2, 1)]),
                    Vector::new(m[(0, 2)], m[(1, 2)], m[(2, 2)]),
                );
                builder = builder.additional_mass_properties(MassProperties::with_inertia_matrix(
                    vec_from_na(&com),
                    mass as f32,
                    mat,
                ));
            }
            bodies.push(world.insert_body(builder));
        }

        let level = frames_at_fixed_height(model, &frames);
        let mut collider_count = 0;
        for link in &model.links {
            let Some(&body) = bodies.get(link.frame) else { continue };
            for g in &link.collisions {
                let Some((shape, local)) = convex_shape(&g.shape) else { continue };
                let pose = link.offset * g.origin * local;
                // a collider whose height never changes and that clears the ground never meets it
                let world_aabb = shape.compute_aabb(&pose_from_iso(&(frames[link.frame] * pose)));
                let above_ground = level.get(link.frame).copied().unwrap_or(false) && world_aabb.mins.z > 0.0;
                let groups = if above_ground { LEVEL_LINK_GROUPS } else { LINK_GROUPS };
                let collider = ColliderBuilder::new(shape)
                    .position(pose_from_iso(&pose))
                    .density(0.0)
                    .friction(0.5)
                    .collision_groups(groups);
                world.insert_collider(collider, Some(body));
                collider_count += 1;
            }
        }

        let mut joints = Vec::with_capacity(n);
        let mut kinds = Vec::with_capacity(n);
        let mut axes_local = Vec::with_capacity(n);
        let mut limits = Vec::with_capacity(n);
        for (k, j) in model.joints.iter().enumerate() {
            let ra = x_to_axis(&j.axis);
            let frame1 = j.origin * Isometry3::from_parts(nalgebra::Translation3::identity(), ra);
            let frame2 = Isometry3::from_parts(nalgebra::Translation3::identity(), ra);
            let axis = free_axis(j.kind);
            let locked = if j.kind == JointKind::Prismatic {
                JointAxesMask::LOCKED_PRISMATIC_AXES
            } else {
                JointAxesMask::LOCKED_REVOLUTE_AXES
            };
            let mut builder = GenericJointBuilder::new(locked)
                .local_frame1(pose_from_iso(&frame1))
                .local_frame2(pose_from_iso(&frame2))
                .contacts_enabled(false)
                .motor_model(axis, MotorModel::AccelerationBased)
                .set_motor(axis, 0.0, 0.0, gains.stiffness as f32, gains.damping as f32);
            let lim = model.limits.get(k).map(|l| [l.min as f32, l.max as f32]).unwrap_or([f32::MIN, f32::MAX]);
            if lim[0].is_finite() && lim[1].is_finite() {
                builder = builder.limits(axis, lim);
            }
            limits.push(lim);
            let handle = world
                .insert_multibody_joint(bodies[k], bodies[k + 1], builder.build())
                .ok_or_else(|| SimError::Build(format!("rapier refused joint {}", j.name)))?;
            joints.push(handle);
            kinds.push(j.kind);
            axes_local.push(vec_from_na(&j.axis.into_inner()));
        }
        let Some(&first) = joints.first() else { return Err(SimError::Build("the model has no movable joint".into())) };
        {
            let PhysicsWorld { multibody_joints, bodies: rb_set, .. } = &mut world;
            let Some((mb, _)) = multibody_joints.get_mut(first) else {
                return Err(SimError::Build("multibody missing after insertion".into()));
            };
            mb.set_self_contacts_enabled(false);
            mb.forward_kinematics(rb_set, true);
            mb.damping_mut().fill(0.0);
            if mb.ndofs() != n {
                return Err(SimError::Build(format!("multibody has {} DOF, the model {n}", mb.ndofs())));
            }
        }
        // one DOF per joint in chain order: joint k is link k + 1 with generalized index k
        for (k, &h) in joints.iter().enumerate() {
            let ok = world
                .multibody_joints
                .get(h)
                .and_then(|(mb, id)| mb.link(id).map(|l| id == k + 1 && l.joint.ndofs() == 1))
                .unwrap_or(false);
            if !ok {
                return Err(SimError::Build(format!(
                    "multibody joint {} is not link {} of a chain",
                    model.joints[k].name,
                    k + 1
                )));
            }
        }
        Ok(Self {
            world,
            bodies,
            joints,
            kinds,
            axes_local,
            limits,
            gains,
            motors_enabled: true,
            collider_count,
            disp: DVector::zeros(n),
        })
    }

    /// Sets the number of solver iterations per step (at least 1).
    pub fn set_solver_iterations(&mut self, n: usize) {
        self.world.integration_parameters.num_solver_iterations = n.max(1);
    }

    /// rapier's integration parameters (solver tuning).
    pub fn integration_parameters_mut(&mut self) -> &mut IntegrationParameters {
        &mut self.world.integration_parameters
    }

    /// Motor gains in use.
    pub fn gains(&self) -> MotorGains {
        self.gains
    }

    /// Number of robot colliders (the ground plane not counted).
    pub fn collider_count(&self) -> usize {
        self.collider_count
    }

    /// The pairs of colliders rapier's narrow phase keeps contact data for, as (robot–robot,
    /// robot–ground) counts (the ground is the only collider without a chain body).
    #[cfg(test)]
    pub(crate) fn narrow_phase_pairs(&self) -> (usize, usize) {
        let on_robot = |h: ColliderHandle| {
            self.world.colliders.get(h).and_then(|c| c.parent()).is_some_and(|b| self.bodies.contains(&b))
        };
        let (mut robot, mut ground) = (0, 0);
        for pair in self.world.narrow_phase.contact_pairs() {
            match (on_robot(pair.collider1), on_robot(pair.collider2)) {
                (true, true) => robot += 1,
                (true, false) | (false, true) => ground += 1,
                (false, false) => {}
            }
        }
        (robot, ground)
    }

    /// Joint limits set on the multibody (rad or m), per joint.
    pub fn multibody_limits(&self) -> Vec<Option<[f64; 2]>> {
        self.joints
            .iter()
            .zip(&self.kinds)
            .map(|(&h, &kind)| {
                let (mb, link) = self.world.multibody_joints.get(h)?;
                let l = mb.link(link)?.joint.data.limits(free_axis(kind))?;
                Some([f64::from(l.min), f64::from(l.max)])
            })
            .collect()
    }

    /// Degrees of freedom of the multibody.
    pub fn ndofs(&self) -> usize {
        self.joints.first().and_then(|&h| self.world.multibody_joints.get(h)).map_or(0, |(mb, _)| mb.ndofs())
    }

    /// Reads joint positions and velocities into `q` and `qd` (model order).
    pub fn read_state(&self, q: &mut [f64], qd: &mut [f64]) {
        for (k, (&h, &kind)) in self.joints.iter().zip(&self.kinds).enumerate() {
            let Some((mb, link_id)) = self.world.multibody_joints.get(h) else { continue };
            let Some(link) = mb.link(link_id) else { continue };
            let idx = if kind == JointKind::Prismatic { 0 } else { 3 };
            if let Some(v) = q.get_mut(k) {
                *v = f64::from(link.joint.coords()[idx]);
            }
            if let Some(v) = qd.get_mut(k) {
                *v = mb.joint_velocity(link).get(0).copied().map_or(0.0, f64::from);
            }
        }
    }

    /// Puts the joints at `q` (clamped into the multibody limits), at rest.
    pub fn teleport(&mut self, q: &[f64]) {
        let n = self.joints.len();
        let mut cur_q = vec![0.0; n];
        let mut cur_qd = vec![0.0; n];
        self.read_state(&mut cur_q, &mut cur_qd);
        let Some(&first) = self.joints.first() else { return };
        let PhysicsWorld { multibody_joints, bodies, .. } = &mut self.world;
        let Some((mb, _)) = multibody_joints.get_mut(first) else { return };
        self.disp.fill(0.0);
        for (k, &h) in self.joints.iter().enumerate() {
            let target = q.get(k).copied().filter(|v| v.is_finite()).unwrap_or(cur_q[k]);
            let [lo, hi] = self.limits[k];
            let target = target.clamp(f64::from(lo), f64::from(hi));
            // assembly id of link k+1 = k (one DOF per joint, in chain order)
            let _ = h;
            self.disp[k] = (target - cur_q[k]) as f32;
        }
        mb.apply_displacements(self.disp.as_slice());
        mb.generalized_velocity_mut().fill(0.0);
        mb.forward_kinematics(bodies, true);
        mb.update_rigid_bodies(bodies, true);
        for &b in &self.bodies {
            if let Some(rb) = bodies.get_mut(b) {
                rb.set_linvel(Vector::ZERO, true);
                rb.set_angvel(Vector::ZERO, true);
            }
        }
        for (k, &h) in self.joints.iter().enumerate() {
            if let Some((mb, link)) = multibody_joints.get_mut(h)
                && let Some(l) = mb.link_mut(link)
            {
                let axis = free_axis(self.kinds[k]);
                let t = f64::from(self.disp[k]) + cur_q[k];
                if self.motors_enabled {
                    l.joint.data.set_motor(axis, t as f32, 0.0, self.gains.stiffness as f32, self.gains.damping as f32);
                }
            }
        }
    }

    /// Sets the motor position / velocity targets (rad, rad/s).
    pub fn set_motor_targets(&mut self, q: &[f64], qd: &[f64]) {
        if !self.motors_enabled {
            return;
        }
        let (kp, kd) = (self.gains.stiffness, self.gains.damping);
        for (k, &h) in self.joints.iter().enumerate() {
            let (Some(&tq), Some(&tqd)) = (q.get(k), qd.get(k)) else { continue };
            if !(tq.is_finite() && tqd.is_finite()) {
                continue;
            }
            let [lo, hi] = self.limits[k];
            let tq = tq.clamp(f64::from(lo), f64::from(hi));
            if let Some((mb, link)) = self.world.multibody_joints.get_mut(h)
                && let Some(l) = mb.link_mut(link)
            {
                l.joint.data.set_motor(free_axis(self.kinds[k]), tq as f32, tqd as f32, kp as f32, kd as f32);
            }
        }
    }

    /// Turns the position motors on or off (off: the joints move only under torques, gravity
    /// and limits; on again: the motors hold the current position until new targets arrive).
    pub fn set_motors_enabled(&mut self, on: bool) {
        if self.motors_enabled == on {
            return;
        }
        self.motors_enabled = on;
        let n = self.joints.len();
        let (mut q, mut qd) = (vec![0.0; n], vec![0.0; n]);
        self.read_state(&mut q, &mut qd);
        let (kp, kd) = (self.gains.stiffness as f32, self.gains.damping as f32);
        for (k, &h) in self.joints.iter().enumerate() {
            if let Some((mb, link)) = self.world.multibody_joints.get_mut(h)
                && let Some(l) = mb.link_mut(link)
            {
                let axis = free_axis(self.kinds[k]);
                if on {
                    l.joint.data.set_motor(axis, q[k] as f32, 0.0, kp, kd);
                } else {
                    // a motor with zero gains would lock the joint: remove it
                    l.joint.data.motor_axes.remove(axis.into());
                }
            }
        }
    }

    /// With the motors off (a torque run), puts the joints marked in `held` back on their
    /// position motors, holding where they are now; the others stay free.
    pub fn hold_joints(&mut self, held: &[bool]) {
        if self.motors_enabled {
            return;
        }
        let n = self.joints.len();
        let (mut q, mut qd) = (vec![0.0; n], vec![0.0; n]);
        self.read_state(&mut q, &mut qd);
        let (kp, kd) = (self.gains.stiffness as f32, self.gains.damping as f32);
        for (k, &h) in self.joints.iter().enumerate() {
            if !held.get(k).copied().unwrap_or(false) {
                continue;
            }
            if let Some((mb, link)) = self.world.multibody_joints.get_mut(h)
                && let Some(l) = mb.link_mut(link)
            {
                l.joint.data.set_motor(free_axis(self.kinds[k]), q[k] as f32, 0.0, kp, kd);
            }
        }
    }

    /// Sets the generalised joint forces (N·m for revolute joints, N for prismatic) applied
    /// during the next steps, as equal and opposite wrenches on each joint's two bodies.
    pub fn set_joint_torques(&mut self, tau: &[f64]) {
        let n = self.joints.len();
        let bodies = &mut self.world.bodies;
        for &b in self.bodies.iter().skip(1) {
            if let Some(rb) = bodies.get_mut(b) {
                rb.reset_forces(false);
                rb.reset_torques(false);
            }
        }
        for k in 0..n {
            let Some(&t) = tau.get(k) else { continue };
            if !t.is_finite() || t == 0.0 {
                continue;
            }
            let (parent, child) = (self.bodies[k], self.bodies[k + 1]);
            let Some(c) = bodies.get(child) else { continue };
            let axis_w = c.position().rotation * self.axes_local[k];
            let origin_w = c.position().translation;
            let w = axis_w * t as f32;
            for (h, sign) in [(child, 1.0f32), (parent, -1.0f32)] {
                let Some(rb) = bodies.get_mut(h) else { continue };
                if self.kinds[k] == JointKind::Prismatic {
                    // same point on both bodies, so no moment leaks into the other joints
                    rb.add_force_at_point(w * sign, origin_w, false);
                } else {
                    rb.add_torque(w * sign, false);
                }
            }
        }
    }

    /// Clamps every joint speed to `±caps[k]` (rad/s or m/s): actuator speed saturation.
    pub fn clamp_joint_velocities(&mut self, caps: &[f64]) {
        self.limit_velocities(caps, None);
    }

    /// Before a step: clamps joint speeds to `caps` and, as a hard end stop, so that no joint
    /// moving at its current speed would pass its limit within `dt_s` (a joint reaching a stop
    /// loses its speed into it, like an inelastic impact). rapier's own limit constraints
    /// then only have to absorb the acceleration of a single step.
    pub fn stop_at_limits(&mut self, caps: &[f64], dt_s: f64) {
        self.limit_velocities(caps, Some(dt_s));
    }

    fn limit_velocities(&mut self, caps: &[f64], dt_s: Option<f64>) {
        let n = self.joints.len();
        let mut q = [0.0f64; 16];
        let mut qv = vec![];
        let q: &mut [f64] = if n <= q.len() {
            &mut q[..n]
        } else {
            qv.resize(n, 0.0);
            &mut qv
        };
        let mut qd_dummy = [0.0f64; 16];
        let mut qdv = vec![];
        let qd: &mut [f64] = if n <= qd_dummy.len() {
            &mut qd_dummy[..n]
        } else {
            qdv.resize(n, 0.0);
            &mut qdv
        };
        if dt_s.is_some() {
            self.read_state(q, qd);
        }
        let Some(&first) = self.joints.first() else { return };
        let Some((mb, _)) = self.world.multibody_joints.get_mut(first) else { return };
        let mut v = mb.generalized_velocity_mut();
        for (k, x) in v.iter_mut().enumerate().take(n) {
            let mut lo = f64::NEG_INFINITY;
            let mut hi = f64::INFINITY;
            if let Some(&c) = caps.get(k)
                && c.is_finite()
                && c > 0.0
            {
                lo = -c;
                hi = c;
            }
            if let Some(dt) = dt_s
                && dt > 0.0
            {
                let [min, max] = self.limits[k];
                if max.is_finite() {
                    hi = hi.min((f64::from(max) - q[k]).max(0.0) / dt);
                }
                if min.is_finite() {
                    lo = lo.max((f64::from(min) - q[k]).min(0.0) / dt);
                }
            }
            let val = f64::from(*x);
            if val > hi {
                *x = hi as f32;
            } else if val < lo {
                *x = lo as f32;
            }
        }
    }

    /// After a step: a joint found past its limit (rapier's limits are velocity-level and let
    /// a very hard push through by a few mrad) is put back on the limit with its outward speed
    /// removed — a rigid end stop. Returns true when a joint was moved.
    pub fn project_into_limits(&mut self) -> bool {
        let n = self.joints.len();
        let Some(&first) = self.joints.first() else { return false };
        let PhysicsWorld { multibody_joints, bodies, .. } = &mut self.world;
        let Some((mb, _)) = multibody_joints.get_mut(first) else { return false };
        let mut moved = false;
        self.disp.fill(0.0);
        for k in 0..n {
            let Some(link) = mb.link(k + 1) else { continue };
            let idx = if self.kinds[k] == JointKind::Prismatic { 0 } else { 3 };
            let q = link.joint.coords()[idx];
            let [lo, hi] = self.limits[k];
            let target = q.clamp(lo, hi);
            if target != q {
                self.disp[k] = target - q;
                moved = true;
            }
        }
        if moved {
            mb.apply_displacements(self.disp.as_slice());
            let mut v = mb.generalized_velocity_mut();
            for k in 0..n {
                if (self.disp[k] < 0.0 && v[k] > 0.0) || (self.disp[k] > 0.0 && v[k] < 0.0) {
                    v[k] = 0.0;
                }
            }
            mb.forward_kinematics(bodies, true);
            mb.update_rigid_bodies(bodies, true);
        }
        moved
    }

    /// One physics step, then the rigid end stops ([`Physics::project_into_limits`]).
    pub fn step(&mut self) {
        self.world.step();
        self.project_into_limits();
    }

    /// World pose of chain body `k` (0 = root), as rapier sees it.
    pub fn body_pose(&self, k: usize) -> Option<Isometry3<f64>> {
        let rb = self.world.bodies.get(*self.bodies.get(k)?)?;
        let p = rb.position();
        let t = p.translation;
        let r = p.rotation;
        Some(Isometry3::from_parts(
            nalgebra::Translation3::new(f64::from(t.x), f64::from(t.y), f64::from(t.z)),
            UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                f64::from(r.w),
                f64::from(r.x),
                f64::from(r.y),
                f64::from(r.z),
            )),
        ))
    }
}
