//! URDF → [`RobotModel`]: the serial chain from the root link to a tip link, with fixed joints
//! folded into constant transforms, joint limits, inertials and visual / collision geometry
//! (mesh paths resolved to files).
//!
//! The model is the one description of the robot shared by kinematics, physics, rendering and
//! the serial link. Joint values are in chain order (root → tip), radians for revolute joints,
//! metres for prismatic ones.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Matrix3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::limits::{JointLimit, JointLimits};
use crate::parol6::Tool;

/// The embedded PAROL6 URDF (our own; kinematics per ROBOT.md §6.1, joint values = the
/// controller's software angles).
pub const PAROL6_URDF: &str = include_str!("../../../assets/parol6/parol6.urdf");

/// Errors of loading a URDF into a [`RobotModel`]. Each has its own message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read.
    #[error("cannot read URDF file {path}: {reason}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        reason: String,
    },
    /// The text is not XML, or not a `<robot>` description.
    #[error("not a URDF robot description: {0}")]
    NotUrdf(String),
    /// The robot has no `<link>`.
    #[error("the URDF robot \"{0}\" has no links")]
    NoLinks(String),
    /// Two links share a name.
    #[error("link name \"{0}\" is used twice")]
    DuplicateLink(String),
    /// A joint names a link that does not exist.
    #[error("joint \"{joint}\" names {role} link \"{link}\", which does not exist")]
    MissingLink {
        /// The joint.
        joint: String,
        /// "parent" or "child".
        role: &'static str,
        /// The missing link name.
        link: String,
    },
    /// More than one link has no parent joint.
    #[error("the URDF has several root links ({}); a robot needs exactly one", .0.join(", "))]
    SeveralRoots(Vec<String>),
    /// A link has two parent joints, or the joints form a loop.
    #[error("the joints form a cycle or give link \"{0}\" two parents")]
    Cycle(String),
    /// The requested tip link does not exist.
    #[error("tip link \"{0}\" does not exist in the URDF")]
    TipNotFound(String),
    /// No tip was given and the tree has several leaves.
    #[error("the robot has several leaf links ({}); choose the tip link explicitly", .0.join(", "))]
    AmbiguousTip(Vec<String>),
    /// The chain from root to tip has no revolute / continuous / prismatic joint.
    #[error("the chain from \"{root}\" to \"{tip}\" has no movable joint")]
    NoMovableJoint {
        /// Root link.
        root: String,
        /// Tip link.
        tip: String,
    },
    /// A joint type this loader cannot put in a serial chain.
    #[error("joint \"{joint}\" has type {kind}, which a serial arm model does not support")]
    UnsupportedJoint {
        /// The joint.
        joint: String,
        /// Its type.
        kind: String,
    },
    /// A joint's lower limit lies above its upper limit, or a limit is not finite.
    #[error("joint \"{joint}\" has an invalid range: lower {lower} > upper {upper}")]
    InvalidLimits {
        /// The joint.
        joint: String,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// A joint axis is zero or not finite.
    #[error("joint \"{0}\" has a zero or invalid axis")]
    InvalidAxis(String),
    /// The text is too large or nests too deep to parse safely (checked before parsing).
    #[error(transparent)]
    InputRefused(#[from] crate::urdf_input::UrdfInputError),
    /// A mesh file could not be found. Reported in [`RobotModel::warnings`]; kinematics still load.
    #[error("link \"{link}\": mesh \"{uri}\" not found (resolved to {})", .resolved.display())]
    MeshNotFound {
        /// The link.
        link: String,
        /// The filename as written in the URDF.
        uri: String,
        /// Where it was looked for.
        resolved: PathBuf,
    },
}

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

/// A shape of a link's visual or collision geometry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// Box with full edge lengths, metres.
    Box {
        /// Size x, y, z.
        size_m: [f64; 3],
    },
    /// Cylinder along local z, centred on the origin.
    Cylinder {
        /// Radius.
        radius_m: f64,
        /// Length.
        length_m: f64,
    },
    /// Capsule along local z (cylinder length, without the caps).
    Capsule {
        /// Radius.
        radius_m: f64,
        /// Length.
        length_m: f64,
    },
    /// Sphere.
    Sphere {
        /// Radius.
        radius_m: f64,
    },
    /// Triangle mesh from a file.
    Mesh {
        /// Resolved path of the file (it may not exist; see [`RobotModel::warnings`]).
        path: PathBuf,
        /// Filename as written in the URDF.
        uri: String,
        /// Per-axis scale.
        scale: [f64; 3],
    },
}

/// A piece of visual or collision geometry attached to a link.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// Pose in the link frame.
    pub origin: Isometry3<f64>,
    /// The shape.
    pub shape: Shape,
    /// RGBA colour (visuals only; from the material, `None` when not given).
    pub rgba: Option<[f32; 4]>,
}

/// Mass properties of a link.
#[derive(Debug, Clone, PartialEq)]
pub struct Inertial {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Centre of mass in the link frame, m.
    pub com_m: Point3<f64>,
    /// Inertia tensor about the COM, in the link frame axes, kg·m².
    pub inertia_kg_m2: Matrix3<f64>,
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
    /// Problems that did not stop loading (missing meshes).
    pub warnings: Vec<ModelError>,
    /// Names of links the URDF leaves out of self-collision checks (pairs), from an SRDF.
    pub disabled_collision_pairs: Vec<(String, String)>,
    /// True when this is the PAROL6 kinematic chain (closed-form IK applies).
    pub is_parol6: bool,
}

fn iso_from_pose(p: &urdf_rs::Pose) -> Isometry3<f64> {
    let [x, y, z] = p.xyz.0;
    let [r, pi, ya] = p.rpy.0;
    Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(r, pi, ya))
}

impl RobotModel {
    /// The embedded PAROL6 (bare flange).
    pub fn parol6() -> Self {
        match Self::from_urdf_str(PAROL6_URDF, &LoadOptions::default()) {
            Ok(m) => m,
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

    /// Loads a URDF file; meshes are resolved relative to its folder.
    pub fn from_urdf_file(path: &Path, tip: Option<&str>) -> Result<Self, ModelError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| ModelError::Io { path: path.to_path_buf(), reason: e.to_string() })?;
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
        let robot = urdf_rs::read_from_string(xml).map_err(|e| ModelError::NotUrdf(first_line(&e.to_string())))?;
        build(&robot, opts)
    }

    /// Number of movable joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// Joint names, root → tip.
    pub fn joint_names(&self) -> Vec<&str> {
        self.joints.iter().map(|j| j.name.as_str()).collect()
    }

    /// Fits a PAROL6 tool (a translation in the flange frame).
    pub fn set_tool(&mut self, tool: Tool) {
        let [x, y, z] = tool.tcp_offset_m();
        self.tool = Isometry3::translation(x, y, z);
    }

    /// Sets an arbitrary tool transform in the tip frame.
    pub fn set_tool_transform(&mut self, tool: Isometry3<f64>) {
        self.tool = tool;
    }

    /// Index of the link called `name`.
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }

    /// Reads `<disable_collisions link1 link2>` pairs from SRDF text into
    /// [`Self::disabled_collision_pairs`]. Returns how many pairs were added.
    pub fn apply_srdf(&mut self, srdf: &str) -> usize {
        let mut added = 0;
        for tag in srdf.split('<').filter(|t| t.starts_with("disable_collisions")) {
            let attr = |name: &str| {
                let key = format!("{name}=\"");
                tag.find(&key).and_then(|i| {
                    let rest = &tag[i + key.len()..];
                    rest.find('"').map(|j| rest[..j].to_string())
                })
            };
            if let (Some(a), Some(b)) = (attr("link1"), attr("link2")) {
                self.disabled_collision_pairs.push((a, b));
                added += 1;
            }
        }
        added
    }
}

fn first_line(s: &str) -> String {
    s.lines().next().unwrap_or("").chars().take(300).collect()
}

fn build(robot: &urdf_rs::Robot, opts: &LoadOptions) -> Result<RobotModel, ModelError> {
    if robot.links.is_empty() {
        return Err(ModelError::NoLinks(robot.name.clone()));
    }
    let mut link_by_name: HashMap<&str, &urdf_rs::Link> = HashMap::new();
    for l in &robot.links {
        if link_by_name.insert(l.name.as_str(), l).is_some() {
            return Err(ModelError::DuplicateLink(l.name.clone()));
        }
    }
    // parent joint of each link; children joints of each link
    let mut parent_joint: HashMap<&str, &urdf_rs::Joint> = HashMap::new();
    let mut children: HashMap<&str, Vec<&urdf_rs::Joint>> = HashMap::new();
    for j in &robot.joints {
        for (role, name) in [("parent", &j.parent.link), ("child", &j.child.link)] {
            if !link_by_name.contains_key(name.as_str()) {
                return Err(ModelError::MissingLink { joint: j.name.clone(), role, link: name.clone() });
            }
        }
        if parent_joint.insert(j.child.link.as_str(), j).is_some() {
            return Err(ModelError::Cycle(j.child.link.clone()));
        }
        children.entry(j.parent.link.as_str()).or_default().push(j);
    }
    let roots: Vec<String> =
        robot.links.iter().filter(|l| !parent_joint.contains_key(l.name.as_str())).map(|l| l.name.clone()).collect();
    if roots.is_empty() {
        return Err(ModelError::Cycle(robot.links[0].name.clone()));
    }
    if roots.len() > 1 {
        return Err(ModelError::SeveralRoots(roots));
    }
    let root = roots[0].clone();
    // every link must be reachable from the root (else there is a cycle elsewhere)
    let mut reachable: HashSet<&str> = HashSet::new();
    let mut stack = vec![root.as_str()];
    while let Some(l) = stack.pop() {
        if !reachable.insert(l) {
            return Err(ModelError::Cycle(l.to_string()));
        }
        if let Some(cs) = children.get(l) {
            stack.extend(cs.iter().map(|j| j.child.link.as_str()));
        }
    }
    if let Some(l) = robot.links.iter().find(|l| !reachable.contains(l.name.as_str())) {
        return Err(ModelError::Cycle(l.name.clone()));
    }
    let tip = match &opts.tip {
        Some(t) => {
            if !link_by_name.contains_key(t.as_str()) {
                return Err(ModelError::TipNotFound(t.clone()));
            }
            t.clone()
        }
        None => {
            let leaves: Vec<String> = robot
                .links
                .iter()
                .filter(|l| children.get(l.name.as_str()).is_none_or(Vec::is_empty))
                .map(|l| l.name.clone())
                .collect();
            if leaves.len() == 1 {
                leaves[0].clone()
            } else {
                // prefer the single leaf reached through at least one movable joint
                let movable_leaves: Vec<String> = leaves
                    .iter()
                    .filter(|l| {
                        path_to_root(l, &parent_joint).iter().any(|j| j.joint_type != urdf_rs::JointType::Fixed)
                    })
                    .cloned()
                    .collect();
                if movable_leaves.len() == 1 {
                    movable_leaves[0].clone()
                } else {
                    return Err(ModelError::AmbiguousTip(leaves));
                }
            }
        }
    };
    // chain joints root → tip
    let mut chain: Vec<&urdf_rs::Joint> = path_to_root(&tip, &parent_joint);
    chain.reverse();

    let mut joints = Vec::new();
    let mut limits = Vec::new();
    let mut pending = Isometry3::identity();
    // chain-frame index of each link on the chain, with its offset
    let mut link_frame: HashMap<String, (usize, Isometry3<f64>)> = HashMap::new();
    link_frame.insert(root.clone(), (0, Isometry3::identity()));
    for j in &chain {
        let origin = iso_from_pose(&j.origin);
        let kind = match j.joint_type {
            urdf_rs::JointType::Fixed => {
                pending *= origin;
                link_frame.insert(j.child.link.clone(), (joints.len(), pending));
                continue;
            }
            urdf_rs::JointType::Revolute => JointKind::Revolute,
            urdf_rs::JointType::Continuous => JointKind::Continuous,
            urdf_rs::JointType::Prismatic => JointKind::Prismatic,
            ref other => {
                return Err(ModelError::UnsupportedJoint {
                    joint: j.name.clone(),
                    kind: format!("{other:?}").to_lowercase(),
                });
            }
        };
        let a = Vector3::from(j.axis.xyz.0);
        if !a.iter().all(|v| v.is_finite()) || a.norm() < 1e-12 {
            return Err(ModelError::InvalidAxis(j.name.clone()));
        }
        let axis = Unit::new_normalize(a);
        let axis_is_z = (axis.into_inner() - Vector3::z()).norm() < 1e-15;
        let (min, max) = if kind == JointKind::Continuous {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            let (lo, hi) = (j.limit.lower, j.limit.upper);
            if !lo.is_finite() || !hi.is_finite() || lo > hi {
                return Err(ModelError::InvalidLimits { joint: j.name.clone(), lower: lo, upper: hi });
            }
            (lo, hi)
        };
        let max_velocity = if j.limit.velocity > 0.0 { j.limit.velocity } else { f64::INFINITY };
        limits.push(JointLimit { name: j.name.clone(), min, max, max_velocity });
        joints.push(ChainJoint {
            name: j.name.clone(),
            kind,
            origin: pending * origin,
            axis,
            axis_is_z,
            child_link: j.child.link.clone(),
        });
        pending = Isometry3::identity();
        link_frame.insert(j.child.link.clone(), (joints.len(), Isometry3::identity()));
    }
    if joints.is_empty() {
        return Err(ModelError::NoMovableJoint { root: root.clone(), tip: tip.clone() });
    }
    let tip_offset = pending;

    // links hanging off chain links through fixed joints (and, frozen at 0, through movable ones)
    let mut order: Vec<String> = vec![root.clone()];
    let mut queue = vec![root.clone()];
    while let Some(l) = queue.pop() {
        let Some(&(frame, off)) = link_frame.get(&l) else { continue };
        if let Some(cs) = children.get(l.as_str()) {
            for j in cs {
                let c = j.child.link.clone();
                if !link_frame.contains_key(&c) {
                    link_frame.insert(c.clone(), (frame, off * iso_from_pose(&j.origin)));
                }
                order.push(c.clone());
                queue.push(c);
            }
        }
    }
    let mut warnings = Vec::new();
    let mut links = Vec::new();
    let mut seen = HashSet::new();
    for name in order {
        if !seen.insert(name.clone()) {
            continue;
        }
        let Some(ul) = link_by_name.get(name.as_str()) else { continue };
        let Some(&(frame, offset)) = link_frame.get(&name) else { continue };
        let inertial = (ul.inertial.mass.value > 0.0).then(|| {
            let i = &ul.inertial.inertia;
            let rot = UnitQuaternion::from_euler_angles(
                ul.inertial.origin.rpy.0[0],
                ul.inertial.origin.rpy.0[1],
                ul.inertial.origin.rpy.0[2],
            )
            .to_rotation_matrix();
            let tensor = Matrix3::new(i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz);
            Inertial {
                mass_kg: ul.inertial.mass.value,
                com_m: Point3::from(ul.inertial.origin.xyz.0),
                inertia_kg_m2: rot.matrix() * tensor * rot.matrix().transpose(),
            }
        });
        let mut conv = |g: &urdf_rs::Geometry| convert_shape(g, &name, opts, &mut warnings);
        let visuals = ul
            .visual
            .iter()
            .map(|v| Geometry {
                origin: iso_from_pose(&v.origin),
                shape: conv(&v.geometry),
                rgba: v
                    .material
                    .as_ref()
                    .and_then(|m| m.color.as_ref())
                    .or_else(|| {
                        let mname = v.material.as_ref().map(|m| m.name.as_str())?;
                        robot.materials.iter().find(|m| m.name == mname).and_then(|m| m.color.as_ref())
                    })
                    .map(|c| c.rgba.0.map(|x| x as f32)),
            })
            .collect();
        let collisions = ul
            .collision
            .iter()
            .map(|c| Geometry { origin: iso_from_pose(&c.origin), shape: conv(&c.geometry), rgba: None })
            .collect();
        links.push(Link { name, frame, offset, inertial, visuals, collisions });
    }
    let is_parol6 = crate::ik::is_parol6_chain(&joints, &tip_offset);
    Ok(RobotModel {
        name: robot.name.clone(),
        root_link: root,
        tip_link: tip,
        joints,
        tip_offset,
        links,
        limits: JointLimits::new(limits),
        tool: Isometry3::identity(),
        warnings,
        disabled_collision_pairs: Vec::new(),
        is_parol6,
    })
}

fn path_to_root<'a>(link: &str, parent_joint: &HashMap<&str, &'a urdf_rs::Joint>) -> Vec<&'a urdf_rs::Joint> {
    let mut out = Vec::new();
    let mut cur = link.to_string();
    while let Some(j) = parent_joint.get(cur.as_str()) {
        out.push(*j);
        cur = j.parent.link.clone();
        if out.len() > parent_joint.len() {
            break;
        }
    }
    out
}

fn convert_shape(g: &urdf_rs::Geometry, link: &str, opts: &LoadOptions, warnings: &mut Vec<ModelError>) -> Shape {
    match g {
        urdf_rs::Geometry::Box { size } => Shape::Box { size_m: size.0 },
        urdf_rs::Geometry::Cylinder { radius, length } => Shape::Cylinder { radius_m: *radius, length_m: *length },
        urdf_rs::Geometry::Capsule { radius, length } => Shape::Capsule { radius_m: *radius, length_m: *length },
        urdf_rs::Geometry::Sphere { radius } => Shape::Sphere { radius_m: *radius },
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let (path, found) = resolve_mesh(filename, opts);
            if !found {
                warnings.push(ModelError::MeshNotFound {
                    link: link.to_string(),
                    uri: filename.clone(),
                    resolved: path.clone(),
                });
            }
            Shape::Mesh { path, uri: filename.clone(), scale: scale.as_ref().map_or([1.0; 3], |s| s.0) }
        }
    }
}

/// Resolves a URDF mesh filename to a path: absolute paths as they are, `file://` stripped,
/// `package://NAME/rest` → `<urdf folder>/rest`, relative paths against the URDF folder, then
/// the search path. Returns the first candidate and whether a file exists there.
pub fn resolve_mesh(uri: &str, opts: &LoadOptions) -> (PathBuf, bool) {
    let mut candidates: Vec<PathBuf> = Vec::new();
    let base = opts.base_dir.clone().unwrap_or_else(|| PathBuf::from("."));
    if let Some(rest) = uri.strip_prefix("package://") {
        let (pkg, rel) = rest.split_once('/').unwrap_or((rest, ""));
        candidates.push(base.join(rel));
        candidates.push(base.join("..").join(rel));
        for d in &opts.mesh_search_path {
            candidates.push(d.join(rel));
            candidates.push(d.join(pkg).join(rel));
        }
    } else {
        let plain = uri.strip_prefix("file://").unwrap_or(uri);
        let p = PathBuf::from(plain);
        if p.is_absolute() {
            candidates.push(p);
        } else {
            candidates.push(base.join(&p));
            for d in &opts.mesh_search_path {
                candidates.push(d.join(&p));
            }
        }
    }
    match candidates.iter().find(|c| c.is_file()) {
        Some(c) => (c.clone(), true),
        None => (candidates.into_iter().next().unwrap_or_default(), false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(xml: &str) -> Result<RobotModel, ModelError> {
        RobotModel::from_urdf_str(xml, &LoadOptions::default())
    }

    const LINK: &str = r#"<link name="{}"/>"#;

    fn links(names: &[&str]) -> String {
        names.iter().map(|n| LINK.replace("{}", n)).collect()
    }

    fn rev(name: &str, parent: &str, child: &str) -> String {
        format!(
            r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#
        )
    }

    #[test]
    fn embedded_parol6_loads_cleanly() {
        let m = RobotModel::parol6();
        assert_eq!(m.dof(), 6);
        assert_eq!(m.joint_names(), ["J1", "J2", "J3", "J4", "J5", "J6"]);
        assert_eq!(m.root_link, "base_link");
        assert_eq!(m.tip_link, "L6");
        assert!(m.is_parol6);
        assert!(m.warnings.is_empty());
        assert_eq!(m.links.len(), 7);
        assert!(m.links.iter().all(|l| !l.visuals.is_empty() && !l.collisions.is_empty()));
        assert!(m.links.iter().all(|l| l.inertial.is_some()));
        for (l, (lo, hi)) in m.limits.iter().zip(crate::parol6::LIMITS_RAD) {
            // the URDF rounds the limits; LIMITS_RAD is derived from the steps (± half a step)
            assert!((l.min - lo).abs() < 2e-4 && (l.max - hi).abs() < 2e-4, "{l:?}");
        }
    }

    #[test]
    fn malformed_not_xml() {
        assert!(matches!(load("this is not xml"), Err(ModelError::NotUrdf(_))));
        assert!(matches!(load("<robot name='x'><link name="), Err(ModelError::NotUrdf(_))));
    }

    #[test]
    fn malformed_no_links() {
        assert!(matches!(load(r#"<robot name="empty"></robot>"#), Err(ModelError::NoLinks(n)) if n == "empty"));
    }

    #[test]
    fn malformed_duplicate_link() {
        let x = format!(r#"<robot name="r">{}</robot>"#, links(&["a", "a"]));
        assert!(matches!(load(&x), Err(ModelError::DuplicateLink(n)) if n == "a"));
    }

    #[test]
    fn malformed_missing_link() {
        let x = format!(r#"<robot name="r">{}{}</robot>"#, links(&["a"]), rev("j", "a", "ghost"));
        assert!(matches!(load(&x), Err(ModelError::MissingLink { link, role: "child", .. }) if link == "ghost"));
    }

    #[test]
    fn malformed_several_roots() {
        let x = format!(r#"<robot name="r">{}{}</robot>"#, links(&["a", "b", "c"]), rev("j", "a", "b"));
        assert!(matches!(load(&x), Err(ModelError::SeveralRoots(r)) if r == ["a", "c"]));
    }

    #[test]
    fn malformed_cycle() {
        let x = format!(
            r#"<robot name="r">{}{}{}{}</robot>"#,
            links(&["a", "b", "c"]),
            rev("j1", "a", "b"),
            rev("j2", "b", "c"),
            rev("j3", "c", "b")
        );
        assert!(matches!(load(&x), Err(ModelError::Cycle(_))));
        let loop_only =
            format!(r#"<robot name="r">{}{}{}</robot>"#, links(&["a", "b"]), rev("j1", "a", "b"), rev("j2", "b", "a"));
        assert!(matches!(load(&loop_only), Err(ModelError::Cycle(_))));
    }

    #[test]
    fn malformed_no_movable_joint() {
        let x = format!(
            r#"<robot name="r">{}<joint name="f" type="fixed"><parent link="a"/><child link="b"/></joint></robot>"#,
            links(&["a", "b"])
        );
        assert!(matches!(load(&x), Err(ModelError::NoMovableJoint { .. })));
    }

    #[test]
    fn malformed_tip_not_found_and_ambiguous_tip() {
        let x = format!(
            r#"<robot name="r">{}{}{}</robot>"#,
            links(&["a", "b", "c"]),
            rev("j1", "a", "b"),
            rev("j2", "a", "c")
        );
        assert!(matches!(load(&x), Err(ModelError::AmbiguousTip(_))));
        let opts = LoadOptions { tip: Some("nope".into()), ..Default::default() };
        assert!(matches!(RobotModel::from_urdf_str(&x, &opts), Err(ModelError::TipNotFound(t)) if t == "nope"));
        let opts = LoadOptions { tip: Some("c".into()), ..Default::default() };
        let m = RobotModel::from_urdf_str(&x, &opts).expect("explicit tip");
        assert_eq!(m.joint_names(), ["j2"]);
        assert_eq!(m.links.len(), 3, "the side branch is kept for display");
    }

    #[test]
    fn malformed_inverted_limits_and_zero_axis() {
        let x = format!(
            r#"<robot name="r">{}<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="1" upper="-1" effort="1" velocity="1"/></joint></robot>"#,
            links(&["a", "b"])
        );
        assert!(matches!(load(&x), Err(ModelError::InvalidLimits { .. })));
        let y =
            x.replace(r#"lower="1" upper="-1""#, r#"lower="-1" upper="1""#).replace(r#"xyz="0 0 1""#, r#"xyz="0 0 0""#);
        assert!(matches!(load(&y), Err(ModelError::InvalidAxis(_))));
    }

    #[test]
    fn malformed_unsupported_joint_type() {
        let x = format!(
            r#"<robot name="r">{}<joint name="j" type="floating"><parent link="a"/><child link="b"/></joint></robot>"#,
            links(&["a", "b"])
        );
        assert!(matches!(load(&x), Err(ModelError::UnsupportedJoint { .. })));
    }

    #[test]
    fn missing_mesh_is_a_warning_with_resolved_path() {
        let x = format!(
            r#"<robot name="r"><link name="a"><visual><geometry><mesh filename="package://pkg/meshes/gone.stl"/></geometry></visual></link>{}{}</robot>"#,
            links(&["b"]),
            rev("j", "a", "b")
        );
        let opts = LoadOptions { base_dir: Some(PathBuf::from("/tmp/nowhere")), ..Default::default() };
        let m = RobotModel::from_urdf_str(&x, &opts).expect("kinematics still load");
        assert_eq!(m.dof(), 1);
        match m.warnings.as_slice() {
            [ModelError::MeshNotFound { resolved, uri, .. }] => {
                assert_eq!(resolved, &PathBuf::from("/tmp/nowhere/meshes/gone.stl"));
                assert_eq!(uri, "package://pkg/meshes/gone.stl");
            }
            other => panic!("unexpected warnings {other:?}"),
        }
        assert!(m.warnings[0].to_string().contains("/tmp/nowhere/meshes/gone.stl"));
    }

    #[test]
    fn prismatic_and_continuous_joints() {
        let x = format!(
            r#"<robot name="r">{}<joint name="p" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/><limit lower="0" upper="0.5" effort="1" velocity="1"/></joint><joint name="c" type="continuous"><origin xyz="0 0 1"/><parent link="b"/><child link="c"/><axis xyz="0 1 0"/></joint></robot>"#,
            links(&["a", "b", "c"])
        );
        let m = load(&x).expect("loads");
        assert_eq!(m.joints[0].kind, JointKind::Prismatic);
        assert_eq!(m.joints[1].kind, JointKind::Continuous);
        assert!(m.limits.get(1).is_some_and(|l| !l.is_bounded()));
        let p = m.fk(&[0.3, 0.0]);
        assert!((p.position_m[0] - 0.3).abs() < 1e-12 && (p.position_m[2] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn srdf_pairs_are_read() {
        let mut m = RobotModel::parol6();
        let n = m.apply_srdf(r#"<robot><disable_collisions link1="base_link" link2="L4" reason="Never"/><disable_collisions link1="L1" link2="L5"/></robot>"#);
        assert_eq!(n, 2);
        assert_eq!(m.disabled_collision_pairs[1], ("L1".to_string(), "L5".to_string()));
    }
}
