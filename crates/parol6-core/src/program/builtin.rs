//! The built-in programs: the old HMI's demos (pick & place, inspection, dodge) and a
//! Cartesian drawing and the LabVIEW GUI's triangle as a time function, embedded from `assets/programs/` in the native file format, plus a joint
//! sweep generated for any robot.

use super::{Program, Step, json};
use crate::model::RobotModel;

/// The embedded program files: (file name, text).
pub const FILES: [(&str, &str); 5] = [
    ("pick_place.json", include_str!("../../../../assets/programs/pick_place.json")),
    ("inspection.json", include_str!("../../../../assets/programs/inspection.json")),
    ("dodge.json", include_str!("../../../../assets/programs/dodge.json")),
    ("draw.json", include_str!("../../../../assets/programs/draw.json")),
    ("triangle.json", include_str!("../../../../assets/programs/triangle.json")),
];

/// The built-in programs for `model`: the PAROL6 programs on the PAROL6, and the joint sweep
/// on every robot. (A file that does not parse is left out; a test keeps them all valid.)
pub fn programs(model: &RobotModel) -> Vec<Program> {
    let mut out: Vec<Program> = if model.is_parol6 {
        FILES.iter().filter_map(|(_, text)| json::parse(text).ok()).collect()
    } else {
        Vec::new()
    };
    out.push(joint_sweep(model, 0.5));
    out
}

/// Every joint between 25 % and 75 % of its range (mid-range ± π/4 for unbounded joints), all
/// joints together, then back to mid-range.
pub fn joint_sweep(model: &RobotModel, speed_fraction: f64) -> Program {
    let at = |f: f64| -> Vec<f64> {
        model
            .limits
            .iter()
            .map(|l| if l.is_bounded() { l.min + f * l.range() } else { (f - 0.5) * std::f64::consts::FRAC_PI_2 })
            .map(f64::to_degrees)
            .collect()
    };
    let mv = |f: f64| Step::MoveJoints { joints_deg: at(f), speed_fraction: Some(speed_fraction), duration_s: None };
    let mut p = Program::from_steps("Joint sweep", vec![mv(0.25), mv(0.75), mv(0.5)]);
    p.description = "every joint between 25 % and 75 % of its range".into();
    p
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::check::{CheckOptions, check_program};

    /// Every built-in program parses and passes pre-flight from the standby pose.
    #[test]
    fn built_in_programs_parse_and_pass_pre_flight() {
        let model = RobotModel::parol6();
        for (name, text) in FILES {
            let p = json::parse(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(!p.name.is_empty() && !p.description.is_empty(), "{name}");
            let r = check_program(&model, &p, &crate::motion::home_position(&model), CheckOptions::default());
            assert!(r.ok, "{name}: {:?}", r.issues);
        }
        assert_eq!(programs(&model).len(), FILES.len() + 1);
        let sweep = joint_sweep(&model, 0.5);
        assert!(check_program(&model, &sweep, &crate::motion::home_position(&model), CheckOptions::default()).ok);
    }
}
