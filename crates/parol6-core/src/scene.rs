//! The robot's surroundings as far as motion is concerned: keep-out shapes (boxes, spheres,
//! cylinders) placed in the world frame, which planned motion must not enter. The floor
//! (z = 0) is always an obstacle and needs no entry here.
//!
//! A [`KeepOut`] is embedded in program files as JSON, units in the field names:
//!
//! ```json
//! {"name":"fixture","kind":"box","center_mm":[250,0,40],"size_mm":[120,80,80],"rpy_deg":[0,0,30]}
//! {"name":"ball","kind":"sphere","center_mm":[0,-300,100],"radius_mm":50}
//! {"name":"post","kind":"cylinder","center_mm":[-200,200,150],"radius_mm":30,"height_mm":300}
//! ```
//!
//! Angles are URDF roll / pitch / yaw, `R = Rz(yaw)·Ry(pitch)·Rx(roll)` (as
//! [`crate::kinematics::iso_from_xyz_rpy`]); `rpy_deg` may be left out (no rotation). A
//! cylinder's axis is its local z, centred on `center_mm`.

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

/// A named region of the world the robot must stay out of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KeepOut {
    /// Name shown in reports ("fixture", "camera post").
    pub name: String,
    /// Shape and placement.
    #[serde(flatten)]
    pub shape: KeepOutShape,
}

/// Shape and placement of a keep-out region, world frame, millimetres and degrees.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum KeepOutShape {
    /// A box centred on `center_mm` with full edge lengths `size_mm`.
    Box {
        /// Centre, mm.
        center_mm: [f64; 3],
        /// Full edge lengths along the local x, y, z, mm.
        size_mm: [f64; 3],
        /// Orientation, URDF roll / pitch / yaw, degrees.
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
    /// A cylinder along its local z, centred on `center_mm`.
    Cylinder {
        /// Centre (middle of the axis), mm.
        center_mm: [f64; 3],
        /// Radius, mm.
        radius_mm: f64,
        /// Full length along the axis, mm.
        height_mm: f64,
        /// Orientation, URDF roll / pitch / yaw, degrees.
        #[serde(default)]
        rpy_deg: [f64; 3],
    },
}

/// A keep-out shape that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("keep-out '{name}' ({kind}): {reason}")]
pub struct SceneError {
    /// Name of the keep-out shape.
    pub name: String,
    /// "box", "sphere" or "cylinder".
    pub kind: &'static str,
    /// What is wrong, naming the field.
    pub reason: String,
}

impl KeepOutShape {
    /// "box", "sphere" or "cylinder" (the JSON tag).
    pub fn kind_name(&self) -> &'static str {
        match self {
            KeepOutShape::Box { .. } => "box",
            KeepOutShape::Sphere { .. } => "sphere",
            KeepOutShape::Cylinder { .. } => "cylinder",
        }
    }

    /// Centre, mm.
    pub fn center_mm(&self) -> [f64; 3] {
        match self {
            KeepOutShape::Box { center_mm, .. }
            | KeepOutShape::Sphere { center_mm, .. }
            | KeepOutShape::Cylinder { center_mm, .. } => *center_mm,
        }
    }

    /// Orientation, degrees (zero for a sphere).
    pub fn rpy_deg(&self) -> [f64; 3] {
        match self {
            KeepOutShape::Box { rpy_deg, .. } | KeepOutShape::Cylinder { rpy_deg, .. } => *rpy_deg,
            KeepOutShape::Sphere { .. } => [0.0; 3],
        }
    }
}

impl KeepOut {
    /// A named keep-out shape.
    pub fn new(name: impl Into<String>, shape: KeepOutShape) -> Self {
        Self { name: name.into(), shape }
    }

    /// Checks that every number is finite and every size positive; the error names the
    /// shape and the field.
    pub fn validate(&self) -> Result<(), SceneError> {
        let err = |reason: String| SceneError { name: self.name.clone(), kind: self.shape.kind_name(), reason };
        if self.name.trim().is_empty() {
            return Err(err("the name is empty".into()));
        }
        let finite3 = |field: &str, v: &[f64; 3]| -> Result<(), SceneError> {
            match v.iter().position(|x| !x.is_finite()) {
                Some(i) => Err(err(format!("{field}[{i}] must be a finite number, got {}", v[i]))),
                None => Ok(()),
            }
        };
        let positive = |field: &str, v: f64| -> Result<(), SceneError> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(err(format!("{field} must be a positive finite number, got {v}")))
            }
        };
        finite3("center_mm", &self.shape.center_mm())?;
        finite3("rpy_deg", &self.shape.rpy_deg())?;
        match &self.shape {
            KeepOutShape::Box { size_mm, .. } => {
                for (i, &s) in size_mm.iter().enumerate() {
                    positive(&format!("size_mm[{i}]"), s)?;
                }
            }
            KeepOutShape::Sphere { radius_mm, .. } => positive("radius_mm", *radius_mm)?,
            KeepOutShape::Cylinder { radius_mm, height_mm, .. } => {
                positive("radius_mm", *radius_mm)?;
                positive("height_mm", *height_mm)?;
            }
        }
        Ok(())
    }

    /// World pose of the shape's centre (metres, radians).
    pub fn pose_m(&self) -> Isometry3<f64> {
        let c = self.shape.center_mm().map(|v| v * 1e-3);
        let rpy = self.shape.rpy_deg().map(f64::to_radians);
        crate::kinematics::iso_from_xyz_rpy(c, rpy)
    }
}

/// Validates every shape of `keep_out`, and that names are unique (reports name them).
pub fn validate_keep_out(keep_out: &[KeepOut]) -> Result<(), SceneError> {
    for (i, k) in keep_out.iter().enumerate() {
        k.validate()?;
        if keep_out[..i].iter().any(|o| o.name == k.name) {
            return Err(SceneError {
                name: k.name.clone(),
                kind: k.shape.kind_name(),
                reason: "another keep-out shape has the same name".into(),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLES: [&str; 3] = [
        r#"{"name":"fixture","kind":"box","center_mm":[250,0,40],"size_mm":[120,80,80],"rpy_deg":[0,0,30]}"#,
        r#"{"name":"ball","kind":"sphere","center_mm":[0,-300,100],"radius_mm":50}"#,
        r#"{"name":"post","kind":"cylinder","center_mm":[-200,200,150],"radius_mm":30,"height_mm":300,"rpy_deg":[90,0,0]}"#,
    ];

    #[test]
    fn json_examples_round_trip() {
        for text in EXAMPLES {
            let k: KeepOut = serde_json::from_str(text).expect(text);
            k.validate().expect("valid");
            let back = serde_json::to_string(&k).expect("serialises");
            let again: KeepOut = serde_json::from_str(&back).expect("reads back");
            assert_eq!(k, again, "{back}");
            // the same field names as the example
            let a: serde_json::Value = serde_json::from_str(text).expect("json");
            let b: serde_json::Value = serde_json::from_str(&back).expect("json");
            let keys = |v: &serde_json::Value| v.as_object().map(|o| o.keys().cloned().collect::<Vec<_>>());
            assert_eq!(keys(&a), keys(&b), "{back}");
        }
        let k: KeepOut = serde_json::from_str(EXAMPLES[0]).expect("box");
        assert_eq!(
            k.shape,
            KeepOutShape::Box {
                center_mm: [250.0, 0.0, 40.0],
                size_mm: [120.0, 80.0, 80.0],
                rpy_deg: [0.0, 0.0, 30.0]
            }
        );
    }

    #[test]
    fn rpy_is_optional() {
        let k: KeepOut = serde_json::from_str(
            r#"{"name":"post","kind":"cylinder","center_mm":[0,0,0],"radius_mm":5,"height_mm":9}"#,
        )
        .expect("no rpy");
        assert_eq!(k.shape.rpy_deg(), [0.0; 3]);
    }

    #[test]
    fn bad_shapes_name_shape_and_field() {
        let bad = KeepOut::new(
            "fixture",
            KeepOutShape::Box { center_mm: [0.0; 3], size_mm: [10.0, -1.0, 5.0], rpy_deg: [0.0; 3] },
        );
        let e = bad.validate().expect_err("negative size").to_string();
        assert!(e.contains("'fixture'") && e.contains("box") && e.contains("size_mm[1]"), "{e}");
        let nan = KeepOut::new("ball", KeepOutShape::Sphere { center_mm: [0.0, f64::NAN, 0.0], radius_mm: 3.0 });
        assert!(nan.validate().expect_err("NaN").to_string().contains("center_mm[1]"));
        let flat = KeepOut::new(
            "post",
            KeepOutShape::Cylinder { center_mm: [0.0; 3], radius_mm: 3.0, height_mm: 0.0, rpy_deg: [0.0; 3] },
        );
        assert!(flat.validate().expect_err("zero height").to_string().contains("height_mm"));
        let twice = [flat.clone(), flat];
        assert!(validate_keep_out(&twice).is_err());
        assert!(serde_json::from_str::<KeepOut>(r#"{"name":"x","kind":"cone","center_mm":[0,0,0]}"#).is_err());
    }

    #[test]
    fn pose_is_in_metres_and_radians() {
        let k: KeepOut = serde_json::from_str(EXAMPLES[0]).expect("box");
        let p = k.pose_m();
        assert!((p.translation.vector - nalgebra::Vector3::new(0.25, 0.0, 0.04)).norm() < 1e-12);
        assert!((p.rotation.angle() - 30f64.to_radians()).abs() < 1e-12);
    }
}
