//! Every number of a parsed URDF checked before the model is built: finite, and within the
//! plausibility bounds of [`crate::limits::plausible`]. `1e400` parses as infinity and `NaN`
//! as NaN; without this check they reach FK and come out as `null` positions. Each refusal names
//! the link or joint and the field.

use super::error::ModelError;
use crate::limits::plausible::{ANGLE_MAX_ABS_RAD, JOINT_POSITION_MAX_ABS_RAD, LENGTH_MAX_ABS_M, MASS_MAX_KG, within};

/// Refuses the first number of `robot` that is not finite or is beyond its bound.
pub(super) fn check_numbers(robot: &urdf_rs::Robot) -> Result<(), ModelError> {
    for j in &robot.joints {
        let place = |field: &str| format!("joint \"{}\" {field}", j.name);
        pose(&j.origin, &place("origin"))?;
        values(&j.axis.xyz.0, 1.0, &place("axis xyz"), "")?;
        let range =
            if j.joint_type == urdf_rs::JointType::Prismatic { LENGTH_MAX_ABS_M } else { JOINT_POSITION_MAX_ABS_RAD };
        if j.joint_type != urdf_rs::JointType::Continuous {
            values(&[j.limit.lower, j.limit.upper], range, &place("limit lower/upper"), "")?;
        }
        values(&[j.limit.effort, j.limit.velocity], f64::MAX, &place("limit effort/velocity"), "")?;
        if let Some(d) = &j.dynamics {
            values(&[d.damping, d.friction], f64::MAX, &place("dynamics damping/friction"), "")?;
        }
    }
    for l in &robot.links {
        let place = |field: &str| format!("link \"{}\" {field}", l.name);
        let i = &l.inertial;
        pose(&i.origin, &place("inertial origin"))?;
        values(&[i.mass.value], MASS_MAX_KG, &place("mass"), " kg")?;
        let t = &i.inertia;
        values(&[t.ixx, t.ixy, t.ixz, t.iyy, t.iyz, t.izz], MASS_MAX_KG, &place("inertia"), " kg·m²")?;
        for v in &l.visual {
            pose(&v.origin, &place("visual origin"))?;
            geometry(&v.geometry, &place("visual geometry"))?;
        }
        for c in &l.collision {
            pose(&c.origin, &place("collision origin"))?;
            geometry(&c.geometry, &place("collision geometry"))?;
        }
    }
    Ok(())
}

fn pose(p: &urdf_rs::Pose, place: &str) -> Result<(), ModelError> {
    values(&p.xyz.0, LENGTH_MAX_ABS_M, &format!("{place} xyz"), " m")?;
    values(&p.rpy.0, ANGLE_MAX_ABS_RAD, &format!("{place} rpy"), " rad")
}

fn geometry(g: &urdf_rs::Geometry, place: &str) -> Result<(), ModelError> {
    match g {
        urdf_rs::Geometry::Box { size } => values(&size.0, LENGTH_MAX_ABS_M, &format!("{place} box size"), " m"),
        urdf_rs::Geometry::Cylinder { radius, length } | urdf_rs::Geometry::Capsule { radius, length } => {
            values(&[*radius, *length], LENGTH_MAX_ABS_M, &format!("{place} radius/length"), " m")
        }
        urdf_rs::Geometry::Sphere { radius } => values(&[*radius], LENGTH_MAX_ABS_M, &format!("{place} radius"), " m"),
        urdf_rs::Geometry::Mesh { scale, .. } => match scale {
            Some(s) => values(&s.0, LENGTH_MAX_ABS_M, &format!("{place} mesh scale"), ""),
            None => Ok(()),
        },
    }
}

fn values(vs: &[f64], max_abs: f64, place: &str, unit: &str) -> Result<(), ModelError> {
    match vs.iter().find(|v| !within(**v, max_abs)) {
        None => Ok(()),
        Some(v) => {
            let why = if v.is_finite() {
                format!("beyond the plausible ±{max_abs}{unit}")
            } else {
                "not a finite number (written as NaN or inf, or too large for a number, such as 1e400)".to_string()
            };
            Err(ModelError::ImplausibleNumber { place: place.to_string(), value: format!("{v:e}"), why })
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::model::{LoadOptions, RobotModel};

    fn one_joint(origin_xyz: &str, extra: &str) -> String {
        format!(
            r#"<robot name="r"><link name="a"/><link name="b">{extra}</link>
<joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="{origin_xyz}"/>
<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#
        )
    }

    fn load(xml: &str) -> Result<RobotModel, String> {
        RobotModel::from_urdf_str(xml, &LoadOptions::default()).map_err(|e| e.to_string())
    }

    #[test]
    fn urdf_with_nan_or_1e400_in_an_origin_is_refused_naming_the_joint() {
        for bad in ["0 0 NaN", "0 0 1e400", "0 -inf 0", "5000 0 0"] {
            let e = load(&one_joint(bad, "")).expect_err(bad);
            assert!(e.contains("joint \"j\" origin xyz"), "{bad}: {e}");
        }
        assert!(load(&one_joint("0 0 0.1", "")).is_ok());
    }

    #[test]
    fn urdf_with_a_non_finite_mass_or_shape_is_refused_naming_the_link() {
        let mass =
            r#"<inertial><mass value="NaN"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>"#;
        let e = load(&one_joint("0 0 0", mass)).expect_err("mass");
        assert!(e.contains("link \"b\" mass"), "{e}");
        let shape = r#"<collision><geometry><sphere radius="1e400"/></geometry></collision>"#;
        let e = load(&one_joint("0 0 0", shape)).expect_err("shape");
        assert!(e.contains("link \"b\" collision geometry radius") && e.contains("not a finite number"), "{e}");
    }

    #[test]
    fn the_embedded_parol6_urdf_passes_the_number_check() {
        assert!(load(crate::model::PAROL6_URDF).is_ok());
    }
}
