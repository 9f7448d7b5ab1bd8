//! URDF → [`RobotModel`]: checks the link/joint tree (one root, no cycles, every link
//! named exists), picks the tip, walks the serial chain root → tip folding fixed joints into
//! constant transforms, and gathers every link with its frame and geometry.

use std::collections::{HashMap, HashSet};

use nalgebra::{Isometry3, Unit, Vector3};

use super::error::ModelError;
use super::geometry::{collisions_from_urdf, inertial_from_urdf, visuals_from_urdf};
use super::parol6_chain::is_parol6_chain;
use super::{ChainJoint, JointKind, Link, LoadOptions, RobotModel, iso_from_pose};
use crate::limits::{JointLimit, JointLimits};

pub(super) fn first_line(s: &str) -> String {
    s.lines().next().unwrap_or("").chars().take(300).collect()
}

/// The error of a URDF the parser refused: where the XML is malformed (line and column, from
/// `roxmltree`, which reports positions where `urdf-rs` does not), else the parser's first line,
/// with the line of a quoted value it names (`for [0 0 abc]`) when the text has it.
pub(super) fn parse_error(xml: &str, parser_message: &str) -> ModelError {
    if let Err(e) = roxmltree::Document::parse(xml) {
        let pos = e.pos();
        let message = e.to_string();
        let message = message.rsplit_once(" at ").map_or(message.as_str(), |(m, _)| m).to_string();
        return ModelError::XmlSyntax { line: pos.row, column: pos.col, message };
    }
    let first = first_line(parser_message);
    let quoted = first.rsplit_once(" for [").and_then(|(_, v)| v.strip_suffix(']'));
    match quoted.and_then(|v| xml.find(&format!("\"{v}\""))) {
        Some(at) => {
            let line = xml[..at].matches('\n').count() + 1;
            ModelError::NotUrdf(format!("line {line}: {first}"))
        }
        None => ModelError::NotUrdf(first),
    }
}

pub(super) fn build(robot: &urdf_rs::Robot, opts: &LoadOptions) -> Result<RobotModel, ModelError> {
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
        let inertial = inertial_from_urdf(ul);
        let visuals = visuals_from_urdf(robot, ul, opts, &mut warnings);
        let collisions = collisions_from_urdf(ul, opts, &mut warnings);
        links.push(Link { name, frame, offset, inertial, visuals, collisions });
    }
    let is_parol6 = is_parol6_chain(&joints, &tip_offset);
    Ok(RobotModel {
        name: robot.name.clone(),
        root_link: root,
        tip_link: tip,
        joints,
        tip_offset,
        links,
        limits: JointLimits::new(limits),
        tool: Isometry3::identity(),
        tool_inertial: None,
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
