//! The `/tf` transforms: one per URDF joint (movable and fixed), parent link → child link, frame
//! ids = URDF link names, from the model's link poses at the recorded joint values. The
//! parent/child pairs come from the URDF text (the model folds fixed joints away); without it,
//! or for joints it does not name, the chain order gives them.

use nalgebra::Isometry3;

use crate::model::RobotModel;

use super::schema::{FrameTransform, Quaternion, Time, Vector3};

/// A parent → child link pair, as indices into [`RobotModel::links`].
#[derive(Debug, Clone, PartialEq, Eq)]
struct Edge {
    parent: usize,
    child: usize,
}

/// Computes the transforms of every joint for given joint values.
#[derive(Debug, Clone)]
pub struct TfFrames {
    edges: Vec<Edge>,
    names: Vec<String>,
}

impl TfFrames {
    /// The joints of `urdf_text` whose links are both in `model` (fixed joints included), or the
    /// chain's joints when the text does not parse.
    pub fn new(model: &RobotModel, urdf_text: Option<&str>) -> Self {
        let names: Vec<String> = model.links.iter().map(|l| l.name.clone()).collect();
        let mut edges = Vec::new();
        let parsed = urdf_text
            .filter(|t| crate::urdf_input::check_urdf_input(t).is_ok())
            .and_then(|t| urdf_rs::read_from_string(t).ok());
        if let Some(robot) = parsed {
            for j in &robot.joints {
                if let (Some(parent), Some(child)) = (model.link_index(&j.parent.link), model.link_index(&j.child.link))
                {
                    edges.push(Edge { parent, child });
                }
            }
        }
        if edges.is_empty() {
            let mut parent = model.link_index(&model.root_link);
            for j in &model.joints {
                let child = model.link_index(&j.child_link);
                if let (Some(p), Some(c)) = (parent, child) {
                    edges.push(Edge { parent: p, child: c });
                }
                parent = child;
            }
        }
        Self { edges, names }
    }

    /// Number of transforms per message.
    pub fn len(&self) -> usize {
        self.edges.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty()
    }

    /// The transforms at joint values `q`, stamped `stamp`.
    pub fn transforms(&self, model: &RobotModel, q: &[f64], stamp: Time) -> Vec<FrameTransform> {
        let poses = model.link_poses(q);
        self.edges
            .iter()
            .filter_map(|e| {
                let rel: Isometry3<f64> = poses.get(e.parent)?.inverse() * poses.get(e.child)?;
                let t = rel.translation.vector;
                let r = rel.rotation;
                Some(FrameTransform {
                    timestamp: stamp,
                    parent_frame_id: self.names.get(e.parent)?.clone(),
                    child_frame_id: self.names.get(e.child)?.clone(),
                    translation: Vector3 { x: t.x, y: t.y, z: t.z },
                    rotation: Quaternion { x: r.i, y: r.j, z: r.k, w: r.w },
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::PAROL6_URDF;
    use nalgebra::{Translation3, UnitQuaternion};

    /// Chaining the transforms from the root gives the model's link poses.
    #[test]
    fn chained_transforms_give_the_link_poses() {
        let model = RobotModel::parol6();
        let frames = TfFrames::new(&model, Some(PAROL6_URDF));
        assert_eq!(frames.len(), 6);
        let q = [0.3, -0.9, 1.2, 0.4, -0.5, 2.0];
        let tfs = frames.transforms(&model, &q, Time::default());
        let expected: Vec<(&str, &str)> =
            vec![("base_link", "L1"), ("L1", "L2"), ("L2", "L3"), ("L3", "L4"), ("L4", "L5"), ("L5", "L6")];
        let got: Vec<(&str, &str)> =
            tfs.iter().map(|t| (t.parent_frame_id.as_str(), t.child_frame_id.as_str())).collect();
        assert_eq!(got, expected);
        let mut pose = Isometry3::identity();
        for t in &tfs {
            let rel = Isometry3::from_parts(
                Translation3::new(t.translation.x, t.translation.y, t.translation.z),
                UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                    t.rotation.w,
                    t.rotation.x,
                    t.rotation.y,
                    t.rotation.z,
                )),
            );
            pose *= rel;
        }
        let flange = model.flange_pose(&q);
        assert!((pose.translation.vector - flange.translation.vector).norm() < 1e-9);
        assert!(pose.rotation.angle_to(&flange.rotation) < 1e-9);
    }

    #[test]
    fn without_urdf_text_the_chain_gives_the_pairs() {
        let model = RobotModel::parol6();
        let a = TfFrames::new(&model, None);
        let b = TfFrames::new(&model, Some("not xml"));
        let c = TfFrames::new(&model, Some(PAROL6_URDF));
        assert_eq!(a.edges, c.edges);
        assert_eq!(b.edges, c.edges);
    }
}
