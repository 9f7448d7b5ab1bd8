//! URDF → [`RobotModel`]: the serial chain from the root link to a tip link, with fixed joints
//! folded into constant transforms, joint limits, inertials and visual / collision geometry
//! (mesh paths resolved to files).
//!
//! The model is the one description of the robot shared by kinematics, physics, rendering and
//! the serial link. Joint values are in chain order (root → tip), radians for revolute joints,
//! metres for prismatic ones.

//!
//! Jobs: `urdf` (URDF text → chain and links; the entry point is
//! [`RobotModel::from_urdf_str`] below), `geometry` (shapes, inertials), `mesh_path`
//! (mesh filename → file), `numbers` (every number finite and plausible), `error` ([`ModelError`]), `parol6_chain` (is this the PAROL6?),
//! `srdf` (collision pairs to skip).

use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::limits::JointLimits;
use crate::parol6::Tool;

mod error;
mod geometry;
mod mesh_path;
mod numbers;
mod parol6_chain;
mod srdf;
mod urdf;

pub use error::ModelError;
pub use geometry::{Geometry, Inertial, Shape};
pub use mesh_path::{MAX_MESH_FILE_BYTES, mesh_reader, read_mesh_file, resolve_mesh};
pub use parol6_chain::is_parol6_chain;

/// The embedded PAROL6 URDF (our own; kinematics per ROBOT.md §6.1, joint values = the
/// controller's software angles).
pub const PAROL6_URDF: &str = include_str!("../../../../assets/parol6/parol6.urdf");

/// Kind of a movable joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum JointKind {
    /// Rotation about the axis with limits.
    Revolute,
    /// Rotation about the axis without limits.
    Continuous,
    /// Translation along the axis.
    Prismatic,
}

/// One movable joint of the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainJoint {
    /// URDF joint name.
    pub name: String,
    /// Revolute, continuous or prismatic.
    pub kind: JointKind,
    /// Transform from the previous chain frame to this joint's frame at q = 0 (fixed joints
    /// between them folded in).
    pub origin: Isometry3<f64>,
    /// Unit axis in the joint frame.
    pub axis: Unit<Vector3<f64>>,
    /// True when the axis is exactly +z (fast path).
    pub axis_is_z: bool,
    /// Child link name (the link this joint moves).
    pub child_link: String,
}

/// A link of the model.
#[derive(Debug, Clone, PartialEq)]
pub struct Link {
    /// URDF link name.
    pub name: String,
    /// Index of the chain frame it rides on: 0 = the root frame, k = the frame of movable
    /// joint k (1-based).
    pub frame: usize,
    /// Constant transform from that chain frame to the link frame.
    pub offset: Isometry3<f64>,
    /// Mass properties (None when the URDF gives no mass).
    pub inertial: Option<Inertial>,
    /// Visual geometry.
    pub visuals: Vec<Geometry>,
    /// Collision geometry.
    pub collisions: Vec<Geometry>,
}

/// Options of [`RobotModel::from_urdf_str`].
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// Tip link of the chain; `None` = the single leaf link.
    pub tip: Option<String>,
    /// Folder of the URDF, for relative and `package://` mesh paths.
    pub base_dir: Option<PathBuf>,
    /// Extra folders searched for meshes (`<dir>/<rest>` and `<dir>/<package>/<rest>`).
    pub mesh_search_path: Vec<PathBuf>,
}

/// A robot arm loaded from URDF: one serial chain with its links.
#[derive(Debug, Clone)]
pub struct RobotModel {
    /// Robot name from the URDF.
    pub name: String,
    /// Root link name.
    pub root_link: String,
    /// Tip link name (the flange).
    pub tip_link: String,
    /// Movable joints, root → tip.
    pub joints: Vec<ChainJoint>,
    /// Constant transform from the last joint frame to the tip link.
    pub tip_offset: Isometry3<f64>,
    /// Every link reachable from the root through the chain or through fixed joints.
    pub links: Vec<Link>,
    /// Joint limits in chain order.
    pub limits: JointLimits,
    /// Tool (TCP) transform in the tip frame.
    pub tool: Isometry3<f64>,
    /// Mass properties of the tool, in the tip frame (`None`: no tool mass). Inverse dynamics,
    /// pre-flight torques and the simulation add it to the last chain body
    /// ([`crate::dynamics::body_inertials`]).
    pub tool_inertial: Option<Inertial>,
    /// Problems that did not stop loading (missing meshes).
    pub warnings: Vec<ModelError>,
    /// Names of links the URDF leaves out of self-collision checks (pairs), from an SRDF.
    pub disabled_collision_pairs: Vec<(String, String)>,
    /// True when this is the PAROL6 kinematic chain (closed-form IK applies).
    pub is_parol6: bool,
}

pub(crate) fn iso_from_pose(p: &urdf_rs::Pose) -> Isometry3<f64> {
    let [x, y, z] = p.xyz.0;
    let [r, pi, ya] = p.rpy.0;
    Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(r, pi, ya))
}

impl RobotModel {
    /// The embedded PAROL6 (bare flange).
    ///
    /// Its joint ranges are the controller's step limits converted to radians
    /// ([`crate::parol6::LIMITS_RAD`], the one source of truth); the URDF carries them rounded.
    pub fn parol6() -> Self {
        match Self::from_urdf_str(PAROL6_URDF, &LoadOptions::default()) {
            Ok(mut m) => {
                for (l, (lo, hi)) in m.limits.joints_mut().iter_mut().zip(crate::parol6::LIMITS_RAD) {
                    l.min = lo;
                    l.max = hi;
                }
                m
            }
            // The embedded file is checked by tests; reaching this is a build defect.
            Err(e) => unreachable!("embedded PAROL6 URDF is invalid: {e}"),
        }
    }

    /// The embedded PAROL6 with `tool` fitted.
    pub fn parol6_with_tool(tool: Tool) -> Self {
        let mut m = Self::parol6();
        m.set_tool(tool);
        m
    }

    /// Loads a URDF file (a regular file only, read through the
    /// [`crate::urdf_input::MAX_URDF_BYTES`] bound); meshes are resolved relative to its folder.
    pub fn from_urdf_file(path: &Path, tip: Option<&str>) -> Result<Self, ModelError> {
        let limit_bytes = crate::urdf_input::MAX_URDF_BYTES;
        let text = crate::fsio::read_regular_bounded_string(path, limit_bytes as u64).map_err(|e| match e {
            crate::fsio::FsioError::TooLarge { .. } => {
                let size_bytes = std::fs::metadata(path).map_or(limit_bytes + 1, |m| m.len() as usize);
                ModelError::InputRefused(crate::urdf_input::UrdfInputError::TooLarge { size_bytes, limit_bytes })
            }
            crate::fsio::FsioError::NotRegular { kind, .. } => ModelError::NotRegularFile {
                path: path.to_path_buf(),
                reason: format!("refused, it is {kind}, not a regular file"),
            },
            e => ModelError::Io {
                path: path.to_path_buf(),
                reason: e.io_error().map_or_else(|| e.to_string(), ToString::to_string),
            },
        })?;
        let opts = LoadOptions {
            tip: tip.map(str::to_string),
            base_dir: path.parent().map(Path::to_path_buf),
            mesh_search_path: Vec::new(),
        };
        Self::from_urdf_str(&text, &opts)
    }

    /// Loads a URDF from text.
    pub fn from_urdf_str(xml: &str, opts: &LoadOptions) -> Result<Self, ModelError> {
        crate::urdf_input::check_urdf_input(xml)?;
        if !xml.contains("<robot") {
            return Err(ModelError::NotUrdf("no <robot> element".into()));
        }
        let robot = urdf_rs::read_from_string(xml).map_err(|e| urdf::parse_error(xml, &e.to_string()))?;
        numbers::check_numbers(&robot)?;
        urdf::build(&robot, opts)
    }

    /// Number of movable joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// Joint names, root → tip.
    pub fn joint_names(&self) -> Vec<&str> {
        self.joints.iter().map(|j| j.name.as_str()).collect()
    }

    /// Fits a PAROL6 tool: its TCP (a translation in the flange frame) and its mass
    /// ([`Tool::mass_kg`], centre of mass [`Tool::com_m`], inertia [`Tool::inertia_kg_m2`]).
    pub fn set_tool(&mut self, tool: Tool) {
        let [x, y, z] = tool.tcp_offset_m();
        self.tool = Isometry3::translation(x, y, z);
        let mass_kg = tool.mass_kg();
        self.tool_inertial = (mass_kg > 0.0).then(|| Inertial {
            mass_kg,
            com_m: nalgebra::Point3::from(Vector3::from(tool.com_m())),
            inertia_kg_m2: nalgebra::Matrix3::identity() * tool.inertia_kg_m2(),
        });
    }

    /// Sets an arbitrary tool transform in the tip frame (the tool's mass, if any, stays).
    pub fn set_tool_transform(&mut self, tool: Isometry3<f64>) {
        self.tool = tool;
    }

    /// Index of the link called `name`.
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }
}

#[cfg(test)]
mod tests;
