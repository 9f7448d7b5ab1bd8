//! Link geometry and mass properties: URDF `<visual>`, `<collision>` and `<inertial>` →
//! [`Shape`], [`Geometry`], [`Inertial`], with mesh filenames resolved to files
//! ([`super::mesh_path`]).

use std::path::PathBuf;

use nalgebra::{Isometry3, Matrix3, Point3, UnitQuaternion};
use serde::{Deserialize, Serialize};

use super::error::ModelError;
use super::mesh_path::{mesh_file_refusal, resolve_mesh};
use super::{LoadOptions, iso_from_pose};

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
        /// Resolved path of the file (it may not exist; see [`RobotModel::warnings`](crate::RobotModel::warnings)).
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

/// Mass properties of a URDF link (None when it gives no positive mass).
pub(super) fn inertial_from_urdf(ul: &urdf_rs::Link) -> Option<Inertial> {
    (ul.inertial.mass.value > 0.0).then(|| {
        let i = &ul.inertial.inertia;
        let [roll, pitch, yaw] = ul.inertial.origin.rpy.0;
        let rot = UnitQuaternion::from_euler_angles(roll, pitch, yaw).to_rotation_matrix();
        let tensor = Matrix3::new(i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz);
        Inertial {
            mass_kg: ul.inertial.mass.value,
            com_m: Point3::from(ul.inertial.origin.xyz.0),
            inertia_kg_m2: rot.matrix() * tensor * rot.matrix().transpose(),
        }
    })
}

/// Visual geometry of a URDF link, colours taken from the inline material or the robot's
/// named materials. Missing meshes are added to `warnings`.
pub(super) fn visuals_from_urdf(
    robot: &urdf_rs::Robot,
    ul: &urdf_rs::Link,
    opts: &LoadOptions,
    warnings: &mut Vec<ModelError>,
) -> Vec<Geometry> {
    ul.visual
        .iter()
        .map(|v| Geometry {
            origin: iso_from_pose(&v.origin),
            shape: convert_shape(&v.geometry, &ul.name, opts, warnings),
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
        .collect()
}

/// Collision geometry of a URDF link. Missing meshes are added to `warnings`.
pub(super) fn collisions_from_urdf(
    ul: &urdf_rs::Link,
    opts: &LoadOptions,
    warnings: &mut Vec<ModelError>,
) -> Vec<Geometry> {
    ul.collision
        .iter()
        .map(|c| Geometry {
            origin: iso_from_pose(&c.origin),
            shape: convert_shape(&c.geometry, &ul.name, opts, warnings),
            rgba: None,
        })
        .collect()
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
            } else if let Some(reason) = mesh_file_refusal(&path) {
                warnings.push(ModelError::MeshRefused { link: link.to_string(), uri: filename.clone(), reason });
            }
            Shape::Mesh { path, uri: filename.clone(), scale: scale.as_ref().map_or([1.0; 3], |s| s.0) }
        }
    }
}
