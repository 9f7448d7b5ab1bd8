//! The forward-dynamics form of the dynamics panel: a torque profile per joint (constant, a
//! step at a time, a sine), the run time and gravity compensation; Run sends it to the
//! simulation as one [`TorqueRun`], STOP ends it.

use eframe::egui;
use parol6_core::sim::torque_profile::{MAX_PROFILE_TORQUE_NM, MAX_RUN_S};
use parol6_core::sim::{TorqueProfile, TorqueRun};

use super::entry::{EntryEvent, numeric_entry};
use super::{AppCommand, PanelContext};

/// Shape of one joint's profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProfileShape {
    /// One torque throughout.
    Constant,
    /// A torque, then another from a time on.
    Step,
    /// Offset + amplitude · sin(2π t / period).
    Sine,
}

impl ProfileShape {
    const ALL: [ProfileShape; 3] = [ProfileShape::Constant, ProfileShape::Step, ProfileShape::Sine];

    fn label(self) -> &'static str {
        match self {
            ProfileShape::Constant => "constant",
            ProfileShape::Step => "step",
            ProfileShape::Sine => "sine",
        }
    }

    /// Names and units of the second and third numbers (the first is always "torque", N·m:
    /// the constant, the torque before the step, the sine's offset).
    fn extra_fields(self) -> [(&'static str, &'static str); 2] {
        match self {
            ProfileShape::Constant => [("", ""), ("", "")],
            ProfileShape::Step => [("after", "N·m"), ("at", "s")],
            ProfileShape::Sine => [("amplitude", "N·m"), ("period", "s")],
        }
    }
}

/// One joint's row: its shape and three numbers (see `ProfileShape::extra_fields`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointRow {
    /// Shape.
    pub shape: ProfileShape,
    /// Torque, N·m (constant / before the step / the sine's offset).
    pub torque_nm: f64,
    /// After the step or the sine's amplitude, N·m.
    pub second: f64,
    /// Step time or sine period, s.
    pub third: f64,
}

impl Default for JointRow {
    fn default() -> Self {
        Self { shape: ProfileShape::Constant, torque_nm: 0.0, second: 0.0, third: 1.0 }
    }
}

impl JointRow {
    /// The core profile of this row.
    pub fn profile(&self) -> TorqueProfile {
        match self.shape {
            ProfileShape::Constant => TorqueProfile::Constant { torque_nm: self.torque_nm },
            ProfileShape::Step => {
                TorqueProfile::Step { before_nm: self.torque_nm, after_nm: self.second, at_s: self.third }
            }
            ProfileShape::Sine => {
                TorqueProfile::Sine { offset_nm: self.torque_nm, amplitude_nm: self.second, period_s: self.third }
            }
        }
    }
}

/// The form's state.
#[derive(Debug, Clone, PartialEq)]
pub struct TorqueForm {
    /// One row per joint.
    pub rows: Vec<JointRow>,
    /// Run time, s.
    pub duration_s: f64,
    /// Add the gravity torques of the current pose (zero torques then hold the arm).
    pub gravity_compensation: bool,
}

impl TorqueForm {
    /// All-zero constant torques for `joints` joints, 2 s, gravity compensated.
    pub fn new(joints: usize) -> Self {
        Self { rows: vec![JointRow::default(); joints], duration_s: 2.0, gravity_compensation: true }
    }

    /// The run the form describes (checked by the core; the error names joint and field).
    pub fn run(&self) -> Result<TorqueRun, String> {
        let run = TorqueRun {
            joints: self.rows.iter().map(JointRow::profile).collect(),
            duration_s: self.duration_s,
            gravity_compensation: self.gravity_compensation,
        };
        run.validate(self.rows.len())?;
        Ok(run)
    }

    /// Draws the form; Run queues [`AppCommand::RunTorques`], Stop queues STOP.
    pub fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.label(egui::RichText::new("Forward dynamics (simulation)").strong()).on_hover_text(format!(
            "Drive the simulated joints with these torques (motors off) for the run time, then the motors hold \
             where the arm is. Joint limits stay enforced; STOP ends the run. |torque| ≤ {MAX_PROFILE_TORQUE_NM} \
             N·m, run ≤ {MAX_RUN_S} s."
        ));
        let mut invalid = None;
        egui::Grid::new("torque_form").num_columns(5).spacing([6.0, 2.0]).show(ui, |ui| {
            for (i, row) in self.rows.iter_mut().enumerate() {
                let j = i + 1;
                ui.label(format!("J{j}"));
                egui::ComboBox::from_id_salt(("torque_shape", i)).selected_text(row.shape.label()).width(72.0).show_ui(
                    ui,
                    |ui| {
                        for s in ProfileShape::ALL {
                            ui.selectable_value(&mut row.shape, s, s.label());
                        }
                    },
                );
                let mut field = |ui: &mut egui::Ui, name: String, v: &mut f64, unit: &str| match numeric_entry(
                    ui, &name, *v, 3, 56.0, unit,
                )
                .1
                {
                    Some(EntryEvent::Committed(x)) => *v = x,
                    Some(EntryEvent::Invalid(e)) => invalid = Some(format!("{name}: {e}")),
                    None => {}
                };
                field(ui, format!("J{j} torque"), &mut row.torque_nm, "N·m");
                let [(n2, u2), (n3, u3)] = row.shape.extra_fields();
                if n2.is_empty() {
                    ui.label("");
                    ui.label("");
                } else {
                    field(ui, format!("J{j} {n2}"), &mut row.second, u2);
                    field(ui, format!("J{j} {n3}"), &mut row.third, u3);
                }
                ui.end_row();
            }
        });
        ui.horizontal(|ui| {
            match numeric_entry(ui, "Run time", self.duration_s, 2, 56.0, "s").1 {
                Some(EntryEvent::Committed(x)) => self.duration_s = x,
                Some(EntryEvent::Invalid(e)) => invalid = Some(format!("Run time: {e}")),
                None => {}
            }
            ui.checkbox(&mut self.gravity_compensation, "gravity compensation")
                .on_hover_text("add the gravity torques of the current pose at every step");
            if ui.button("Run torques").clicked() {
                match self.run() {
                    Ok(run) => ctx.send(AppCommand::RunTorques(run)),
                    Err(e) => ctx.error(format!("torque run refused: {e}")),
                }
            }
            if ui.button("Stop torques").clicked() {
                ctx.stop();
            }
        });
        if let Some(e) = invalid {
            ctx.error(e);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_become_core_profiles_and_bad_ones_are_refused() {
        let mut form = TorqueForm::new(2);
        form.rows[0] = JointRow { shape: ProfileShape::Step, torque_nm: 0.5, second: -0.5, third: 1.0 };
        form.rows[1] = JointRow { shape: ProfileShape::Sine, torque_nm: 0.0, second: 0.2, third: 2.0 };
        let run = form.run().expect("valid");
        assert_eq!(run.joints[0], TorqueProfile::Step { before_nm: 0.5, after_nm: -0.5, at_s: 1.0 });
        assert_eq!(run.joints[1], TorqueProfile::Sine { offset_nm: 0.0, amplitude_nm: 0.2, period_s: 2.0 });
        form.rows[1].third = 0.0;
        assert!(form.run().expect_err("zero period").contains("joint 2"));
        form.rows[1].third = 2.0;
        form.duration_s = 0.0;
        assert!(form.run().is_err());
    }
}
