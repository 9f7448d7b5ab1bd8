//! The editable numbers of a program step, as the operator sees them (joint angles in the
//! chosen unit, positions in mm, orientations in the chosen angle convention, speeds with
//! their units), and writing an edited number back into the step.
//!
//! Pure functions (no UI), shared by the program panel's step editor and the point-table
//! window, and unit-tested here.

use parol6_core::program::{PoseMm, Step};

use super::{AngleUnit, Settings};

/// What a field holds, so an edit knows where to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldSlot {
    /// Joint `k` of a joint move.
    Joint(usize),
    /// Position axis `k` (x, y, z) of a pose, mm.
    Position(usize),
    /// Orientation angle `k` in the chosen convention.
    Angle(usize),
    /// The joint speed fraction (0 < f ≤ 1).
    SpeedFraction,
    /// TCP speed, mm/s.
    SpeedMmS,
    /// Corner blend radius, mm.
    BlendMm,
    /// A fixed time, s (dwell).
    Seconds,
}

/// One editable number of a step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepField {
    /// Column label ("J1", "X", "RX", "speed"…).
    pub label: String,
    /// Where it goes.
    pub slot: FieldSlot,
    /// The value as shown (display unit).
    pub value: f64,
    /// Decimals shown.
    pub decimals: usize,
    /// Unit shown after the value.
    pub suffix: &'static str,
}

/// Joint moves of programs are in degrees; these are the shown values for `unit`.
fn joint_shown(unit: AngleUnit, deg: f64) -> f64 {
    unit.from_rad(deg.to_radians())
}

fn pose_fields(pose: &PoseMm, settings: &Settings, out: &mut Vec<StepField>) {
    for (k, axis) in ["X", "Y", "Z"].iter().enumerate() {
        out.push(StepField {
            label: (*axis).to_string(),
            slot: FieldSlot::Position(k),
            value: pose.position_mm[k],
            decimals: 2,
            suffix: "mm",
        });
    }
    let shown = settings.shown_angles_rad(pose.rpy_deg.map(f64::to_radians));
    let unit = settings.unit;
    for (k, label) in settings.angle_labels().iter().enumerate() {
        out.push(StepField {
            label: (*label).to_string(),
            slot: FieldSlot::Angle(k),
            value: unit.from_rad(shown[k]),
            decimals: unit.decimals(),
            suffix: unit.suffix().trim(),
        });
    }
}

fn fraction(value: Option<f64>, default: f64) -> StepField {
    StepField {
        label: "speed".into(),
        slot: FieldSlot::SpeedFraction,
        value: value.unwrap_or(default),
        decimals: 2,
        suffix: "×",
    }
}

fn tcp_speed(value: Option<f64>, default: f64) -> StepField {
    StepField {
        label: "speed".into(),
        slot: FieldSlot::SpeedMmS,
        value: value.unwrap_or(default),
        decimals: 1,
        suffix: "mm/s",
    }
}

/// The editable numbers of `step` (empty for steps edited only in the file: arcs, splines,
/// gripper, I/O). Speeds left out show the program default given.
pub fn step_fields(step: &Step, settings: &Settings, defaults: &parol6_core::program::SpeedSettings) -> Vec<StepField> {
    let mut out = Vec::new();
    let unit = settings.unit;
    match step {
        Step::Home { speed_fraction } => out.push(fraction(*speed_fraction, defaults.joint_fraction)),
        Step::MoveJoints { joints_deg, speed_fraction, .. } => {
            for (k, v) in joints_deg.iter().enumerate() {
                out.push(StepField {
                    label: format!("J{}", k + 1),
                    slot: FieldSlot::Joint(k),
                    value: joint_shown(unit, *v),
                    decimals: unit.decimals(),
                    suffix: unit.suffix().trim(),
                });
            }
            out.push(fraction(*speed_fraction, defaults.joint_fraction));
        }
        Step::MovePose { pose, speed_fraction, .. } => {
            pose_fields(pose, settings, &mut out);
            out.push(fraction(*speed_fraction, defaults.joint_fraction));
        }
        Step::MoveL { pose, speed_mm_s, blend_mm, .. } => {
            pose_fields(pose, settings, &mut out);
            out.push(tcp_speed(*speed_mm_s, defaults.tcp_speed_mm_s));
            out.push(StepField {
                label: "blend".into(),
                slot: FieldSlot::BlendMm,
                value: blend_mm.unwrap_or(0.0),
                decimals: 1,
                suffix: "mm",
            });
        }
        Step::Dwell { seconds } => out.push(StepField {
            label: "time".into(),
            slot: FieldSlot::Seconds,
            value: *seconds,
            decimals: 2,
            suffix: "s",
        }),
        _ => {}
    }
    out
}

/// The largest |position| a step may be given, mm (far beyond any arm's reach; a typo such
/// as 1e9 is refused).
pub const POSITION_MAX_MM: f64 = 5000.0;
/// The largest |joint angle| or |orientation angle| a step may be given, degrees.
pub const ANGLE_MAX_DEG: f64 = 360.0;
/// The largest TCP speed a step may be given, mm/s.
pub const TCP_SPEED_MAX_MM_S: f64 = 10_000.0;
/// The largest corner blend radius, mm.
pub const BLEND_MAX_MM: f64 = 1000.0;
/// The longest dwell, s (an hour).
pub const DWELL_MAX_S: f64 = 3600.0;

/// `value` inside `lo..=hi` (in `unit`), or why not.
fn within(value: f64, (lo, hi): (f64, f64), unit: &str) -> Result<(), String> {
    if (lo..=hi).contains(&value) {
        return Ok(());
    }
    let range = if lo == -hi { format!("±{hi}") } else { format!("{lo}–{hi}") };
    Err(format!("{value} {unit} is outside {range} {unit}"))
}

/// `step` with the field `slot` set to `value` (in the display unit of [`step_fields`]).
/// Values the program would refuse (a speed fraction outside (0, 1], a negative time) or that
/// can only be typos (a position beyond ±[`POSITION_MAX_MM`], an angle beyond ±[`ANGLE_MAX_DEG`],
/// a dwell over [`DWELL_MAX_S`]) are refused here with a message, so the edit never makes the
/// program invalid.
pub fn with_field(step: &Step, slot: FieldSlot, value: f64, settings: &Settings) -> Result<Step, String> {
    if !value.is_finite() {
        return Err("not a finite number".into());
    }
    let unit = settings.unit;
    // rounded: 2π rad shows as ±6.2832 rad
    let angle_max = (unit.from_rad(ANGLE_MAX_DEG.to_radians()) * 1e4).round() / 1e4;
    match slot {
        FieldSlot::Position(_) => within(value, (-POSITION_MAX_MM, POSITION_MAX_MM), "mm")?,
        FieldSlot::Joint(_) | FieldSlot::Angle(_) => within(value, (-angle_max, angle_max), unit.suffix().trim())?,
        FieldSlot::SpeedMmS => within(value, (0.0, TCP_SPEED_MAX_MM_S), "mm/s")?,
        FieldSlot::BlendMm => within(value, (0.0, BLEND_MAX_MM), "mm")?,
        FieldSlot::Seconds => within(value, (0.0, DWELL_MAX_S), "s")?,
        FieldSlot::SpeedFraction => {}
    }
    let check_fraction = |v: f64| {
        if v > 0.0 && v <= 1.0 { Ok(Some(v)) } else { Err(format!("speed {v} is outside (0, 1]")) }
    };
    let set_pose = |pose: &mut PoseMm| -> Result<(), String> {
        match slot {
            FieldSlot::Position(k) if k < 3 => pose.position_mm[k] = value,
            FieldSlot::Angle(k) if k < 3 => {
                let mut shown = settings.shown_angles_rad(pose.rpy_deg.map(f64::to_radians));
                shown[k] = settings.unit.to_rad(value);
                pose.rpy_deg = settings.rpy_from_shown_rad(shown).map(f64::to_degrees);
            }
            _ => return Err("not a field of this step".into()),
        }
        Ok(())
    };
    let mut s = step.clone();
    match (&mut s, slot) {
        (Step::Home { speed_fraction }, FieldSlot::SpeedFraction)
        | (Step::MoveJoints { speed_fraction, .. }, FieldSlot::SpeedFraction)
        | (Step::MovePose { speed_fraction, .. }, FieldSlot::SpeedFraction) => *speed_fraction = check_fraction(value)?,
        (Step::MoveJoints { joints_deg, .. }, FieldSlot::Joint(k)) => {
            let slot = joints_deg.get_mut(k).ok_or("no such joint")?;
            *slot = settings.unit.to_rad(value).to_degrees();
        }
        (Step::MovePose { pose, .. }, _) | (Step::MoveL { pose, .. }, FieldSlot::Position(_) | FieldSlot::Angle(_)) => {
            set_pose(pose)?
        }
        (Step::MoveL { speed_mm_s, .. }, FieldSlot::SpeedMmS) => {
            if value <= 0.0 {
                return Err(format!("speed {value} mm/s must be above 0"));
            }
            *speed_mm_s = Some(value);
        }
        (Step::MoveL { blend_mm, .. }, FieldSlot::BlendMm) => {
            if value < 0.0 {
                return Err(format!("blend {value} mm must not be negative"));
            }
            *blend_mm = if value == 0.0 { None } else { Some(value) };
        }
        (Step::Dwell { seconds }, FieldSlot::Seconds) => {
            if value < 0.0 {
                return Err(format!("time {value} s must not be negative"));
            }
            *seconds = value;
        }
        _ => return Err("not a field of this step".into()),
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use parol6_core::angles::AngleConvention;
    use parol6_core::program::SpeedSettings;

    fn pose_step() -> Step {
        Step::MoveL {
            pose: PoseMm { position_mm: [200.0, 0.0, 300.0], rpy_deg: [0.0, 20.0, 90.0] },
            speed_mm_s: None,
            blend_mm: None,
            duration_s: None,
        }
    }

    #[test]
    fn official_convention_shows_and_takes_rx_ry_rz() {
        let settings = Settings { angle_convention: AngleConvention::OfficialAbc, ..Settings::default() };
        let fields = step_fields(&pose_step(), &settings, &SpeedSettings::default());
        let labels: Vec<_> = fields.iter().map(|f| f.label.as_str()).collect();
        assert_eq!(labels, ["X", "Y", "Z", "RX", "RY", "RZ", "speed", "blend"]);
        let shown: Vec<f64> = fields[3..6].iter().map(|f| f.value).collect();
        assert!((shown[0] - 90.0).abs() < 1e-9 && shown[1].abs() < 1e-9 && (shown[2] + 20.0).abs() < 1e-9, "{shown:?}");
        // Typing RZ = -30 (official) changes our pitch to 30, keeps yaw 90.
        let s = with_field(&pose_step(), FieldSlot::Angle(2), -30.0, &settings).unwrap();
        let Step::MoveL { pose, .. } = s else { panic!() };
        assert!((pose.rpy_deg[1] - 30.0).abs() < 1e-9 && (pose.rpy_deg[2] - 90.0).abs() < 1e-9, "{:?}", pose.rpy_deg);
    }

    #[test]
    fn joints_in_radians_are_stored_in_degrees() {
        let settings = Settings { unit: AngleUnit::Rad, ..Settings::default() };
        let step = Step::MoveJoints { joints_deg: vec![0.0; 6], speed_fraction: None, duration_s: None };
        let s = with_field(&step, FieldSlot::Joint(1), -0.5, &settings).unwrap();
        let Step::MoveJoints { joints_deg, .. } = s else { panic!() };
        assert!((joints_deg[1] - (-0.5f64).to_degrees()).abs() < 1e-12);
        let f = step_fields(
            &Step::MoveJoints { joints_deg, speed_fraction: None, duration_s: None },
            &settings,
            &SpeedSettings::default(),
        );
        assert!((f[1].value + 0.5).abs() < 1e-12 && f[1].suffix == "rad");
    }

    #[test]
    fn out_of_range_values_are_refused_and_leave_the_step() {
        let settings = Settings::default();
        let step = Step::MoveJoints { joints_deg: vec![0.0; 6], speed_fraction: None, duration_s: None };
        assert!(with_field(&step, FieldSlot::SpeedFraction, 1.5, &settings).unwrap_err().contains("(0, 1]"));
        assert!(with_field(&step, FieldSlot::SpeedFraction, 0.0, &settings).is_err());
        assert!(with_field(&Step::Dwell { seconds: 1.0 }, FieldSlot::Seconds, -1.0, &settings).is_err());
        assert!(with_field(&pose_step(), FieldSlot::SpeedMmS, 0.0, &settings).is_err());
        assert!(with_field(&pose_step(), FieldSlot::Joint(0), 1.0, &settings).is_err());
        assert!(with_field(&step, FieldSlot::Joint(0), f64::NAN, &settings).is_err());
    }
}
