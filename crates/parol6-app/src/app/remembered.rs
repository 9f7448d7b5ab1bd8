//! What the panels and the 3D view hold that survives a restart, kept in [`Settings`](crate::panels::Settings) beside
//! the plain settings: the program last opened or saved ([`LastProgram`]), the Cartesian jog's
//! frame, mode and increments ([`CartesianJogSetting`]), the forward-dynamics form
//! ([`TorqueFormSetting`]) and the camera ([`CameraSetting`]). Each is checked when read back: a
//! value out of its range gives that value's default (never 0 or a negative increment, never a
//! NaN view). The app hands them to the panels once at start (`Parol6App::restore_remembered`)
//! and takes them back after every frame (`Parol6App::remember`); the settings writer then
//! saves them as any other setting.

use std::path::PathBuf;

use parol6_core::motion::JogFrame;
use parol6_core::program::gcode::AbcChoice;
use serde::{Deserialize, Serialize};

use super::Parol6App;
use crate::panels::cartesian_jog::{STEP_DEG_RANGE, STEP_MM_RANGE};
use crate::panels::torque_form::{JointRow, TorqueForm};
use crate::viewport::OrbitCamera;

/// The program the window reopens at start: the file last opened or saved, or the built-in
/// program last picked.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub enum LastProgram {
    /// A built-in program, by name.
    Builtin(String),
    /// A program file, by path.
    File(String),
}

/// The Cartesian jog panel's choices.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CartesianJogSetting {
    /// The frame the buttons jog in.
    pub frame: JogFrame,
    /// Step mode (each click one increment), else hold mode.
    pub step_mode: bool,
    /// Step increment, mm.
    pub step_mm: f64,
    /// Step increment, degrees.
    pub step_deg: f64,
}

impl Default for CartesianJogSetting {
    fn default() -> Self {
        Self { frame: JogFrame::World, step_mode: false, step_mm: 1.0, step_deg: 1.0 }
    }
}

impl CartesianJogSetting {
    /// As read back: an increment outside the range an operator may type
    /// ([`STEP_MM_RANGE`], [`STEP_DEG_RANGE`]) is the default's.
    pub fn checked(self) -> Self {
        let d = Self::default();
        let within = |v: f64, (lo, hi): (f64, f64)| (lo..=hi).contains(&v);
        Self {
            step_mm: if within(self.step_mm, STEP_MM_RANGE) { self.step_mm } else { d.step_mm },
            step_deg: if within(self.step_deg, STEP_DEG_RANGE) { self.step_deg } else { d.step_deg },
            ..self
        }
    }
}

/// The forward-dynamics form (the dynamics panel): each joint's torque profile, the run time,
/// gravity compensation and "hold other joints".
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TorqueFormSetting {
    /// One row per joint.
    pub rows: Vec<JointRow>,
    /// Run time, s.
    pub duration_s: f64,
    /// Gravity compensation.
    pub gravity_compensation: bool,
    /// Hold the joints without a torque.
    pub hold_others: bool,
}

impl Default for TorqueFormSetting {
    fn default() -> Self {
        Self::of(&TorqueForm::new(0))
    }
}

impl TorqueFormSetting {
    /// What `form` holds.
    pub fn of(form: &TorqueForm) -> Self {
        Self {
            rows: form.rows.clone(),
            duration_s: form.duration_s,
            gravity_compensation: form.gravity_compensation,
            hold_others: form.hold_others,
        }
    }

    /// Puts the remembered values into `form` (of the robot's joints): rows of another robot
    /// (another joint count) are not taken, a row the core would refuse (a NaN, a torque over
    /// the profile limit, a period ≤ 0) is the default row, a run time outside (0, max] is the form's.
    pub fn restore_into(&self, form: &mut TorqueForm) {
        if self.rows.len() == form.rows.len() {
            for (row, kept) in form.rows.iter_mut().zip(&self.rows) {
                *row = if kept.profile().validate().is_ok() { *kept } else { JointRow::default() };
            }
        }
        let max_s = parol6_core::sim::torque_profile::MAX_RUN_S;
        if self.duration_s > 0.0 && self.duration_s <= max_s {
            form.duration_s = self.duration_s;
        }
        form.gravity_compensation = self.gravity_compensation;
        form.hold_others = self.hold_others;
    }
}

/// The 3D view's camera (`viewport::camera::OrbitCamera`): orbit target, yaw, pitch, distance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CameraSetting {
    /// Orbit target, world m.
    pub target_m: [f32; 3],
    /// Azimuth, rad.
    pub yaw_rad: f32,
    /// Elevation, rad.
    pub pitch_rad: f32,
    /// Distance from the target, m.
    pub distance_m: f32,
}

impl CameraSetting {
    /// Where `camera` looks from.
    pub fn of(camera: &OrbitCamera) -> Self {
        let t = camera.target_m;
        Self {
            target_m: [t.x, t.y, t.z],
            yaw_rad: camera.yaw_rad,
            pitch_rad: camera.pitch_rad,
            distance_m: camera.distance_m,
        }
    }

    /// The camera, clamped (`OrbitCamera::remembered`); `None` (the default view) for an absurd one.
    pub fn camera(&self) -> Option<OrbitCamera> {
        OrbitCamera::remembered(self.target_m, self.yaw_rad, self.pitch_rad, self.distance_m)
    }
}

impl Parol6App {
    /// At start: hands the remembered panel state and camera to the panels and the 3D view, and
    /// reopens the last program (a file is read and checked on the panel's worker, as any open;
    /// if it cannot be, the built-in default stays and a notice says why).
    pub(super) fn restore_remembered(&mut self) {
        let s = &self.settings;
        let jog = s.cartesian_jog.checked();
        self.panels.cartesian_jog.restore(jog);
        // trial 25 m10: Step mode with a 50.80 mm increment came back without a word
        let step_notice = jog.step_mode.then(|| {
            let deg = self.settings.unit.fmt(jog.step_deg.to_radians());
            format!("Cartesian jog: Step mode, {:.2} mm and {deg} per click, as left last time", jog.step_mm)
        });
        if let Some(form) = &s.torque_form {
            form.restore_into(&mut self.panels.dynamics.form);
        }
        if let (Some(v), Some(camera)) = (&mut self.viewport, s.camera.and_then(|c| c.camera())) {
            v.set_camera(camera);
        }
        let default = self.panels.program.program().name.clone();
        let outcome = match s.last_program.clone() {
            None => Ok(()),
            Some(LastProgram::Builtin(name)) => match self.panels.program.load_builtin(&name) {
                true => Ok(()),
                false => Err(format!("the last program, built-in \"{name}\", is not built in any more")),
            },
            Some(LastProgram::File(path)) => {
                let abc = AbcChoice::default_to(s.gcode_abc);
                let start_q = self.sim.snapshot().q.clone();
                self.panels.program.reopen(&self.model, PathBuf::from(path), abc, start_q)
            }
        };
        if let Err(why) = outcome {
            self.notice(format!("{why}; started with {default}"), true);
        }
        if let Some(text) = step_notice {
            self.notice(text, false);
        }
    }

    /// After each frame: what the panels and the 3D view hold now, into the settings (written
    /// by the settings writer when it changed). A value at its default is left out of the file.
    pub(super) fn remember(&mut self) {
        let s = &mut self.settings;
        s.cartesian_jog = self.panels.cartesian_jog.remembered();
        let form = TorqueFormSetting::of(&self.panels.dynamics.form);
        let fresh = TorqueFormSetting::of(&TorqueForm::new(self.model.dof()));
        s.torque_form = (form != fresh).then_some(form);
        if let Some(v) = &self.viewport {
            s.view = v.options;
            let camera = *v.camera();
            s.camera = (camera != OrbitCamera::default()).then(|| CameraSetting::of(&camera));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn increments_out_of_range_fall_back_to_the_default() {
        let d = CartesianJogSetting::default();
        for bad in [0.0, -1.0, 1e9, f64::NAN] {
            let s = CartesianJogSetting { step_mm: bad, step_deg: bad, ..d }.checked();
            assert_eq!((s.step_mm, s.step_deg), (d.step_mm, d.step_deg), "{bad}");
        }
        let good = CartesianJogSetting { frame: JogFrame::Tool, step_mode: true, step_mm: 2.5, step_deg: 45.0 };
        assert_eq!(good.checked(), good);
    }

    #[test]
    fn a_bad_torque_row_is_the_default_row_and_another_robots_rows_are_not_taken() {
        let mut kept = TorqueFormSetting::of(&TorqueForm::new(2));
        kept.rows[0].torque_nm = 0.3;
        kept.rows[1].torque_nm = f64::NAN;
        kept.duration_s = -1.0;
        kept.hold_others = true;
        let mut form = TorqueForm::new(2);
        kept.restore_into(&mut form);
        assert_eq!(form.rows[0].torque_nm, 0.3);
        assert_eq!(form.rows[1], JointRow::default());
        assert_eq!(form.duration_s, TorqueForm::new(2).duration_s);
        assert!(form.hold_others);
        let mut six = TorqueForm::new(6);
        kept.restore_into(&mut six);
        assert_eq!(six.rows, TorqueForm::new(6).rows);
    }
}
