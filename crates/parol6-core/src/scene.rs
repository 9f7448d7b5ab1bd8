//! Keep-out shapes placed in the robot's scene (boxes, cylinders, spheres; the floor is always
//! one), in the base frame, units in the field names.

use serde::{Deserialize, Serialize};

/// The geometry of a keep-out shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum KeepOutShape {
    /// A box.
    Box {
        /// Centre, mm.
        center_mm: [f64; 3],
        /// Edge lengths, mm.
        size_mm: [f64; 3],
        /// Roll, pitch, yaw, deg.
        #[serde(default)]
        rpy_deg: [f64; 3],
    },
    /// A sphere.
    Sphere {
        /// Centre, mm.
        center_mm: [f64; 3],
        /// Radius, mm.
        radius_mm: f64,
    },
    /// A cylinder along its local z.
    Cylinder {
        /// Centre, mm.
        center_mm: [f64; 3],
        /// Radius, mm.
        radius_mm: f64,
        /// Height, mm.
        height_mm: f64,
        /// Roll, pitch, yaw, deg.
        #[serde(default)]
        rpy_deg: [f64; 3],
    },
}

/// A named keep-out shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KeepOut {
    /// Name used in messages.
    pub name: String,
    /// The shape.
    #[serde(flatten)]
    pub shape: KeepOutShape,
}
