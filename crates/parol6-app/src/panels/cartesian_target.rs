//! Right panel: a Cartesian TCP target (XYZ in mm + RPY) solved by IK; the operator picks the
//! branch (previewed as the ghost arm) and runs a profiled move to it.

use eframe::egui;
use parol6_core::ik::{self, IkSolution};
use parol6_core::kinematics::iso_from_xyz_rpy;

use super::{Panel, PanelContext};

/// The Cartesian target panel.
#[derive(Debug, Default)]
pub struct CartesianTargetPanel {
    /// Target position, mm.
    xyz_mm: [f64; 3],
    /// Target RPY, rad.
    rpy: [f64; 3],
    /// True once the entries hold a target (initialised from the TCP on first show).
    initialised: bool,
    /// Result of the last solve.
    result: Option<Result<Vec<IkSolution>, String>>,
    /// Chosen solution index into the last result.
    selected: usize,
    /// Label of the chosen branch, kept across re-solves.
    selected_label: Option<String>,
    /// Entries changed since the last solve.
    dirty: bool,
}

fn solution_label(s: &IkSolution) -> String {
    s.branch.map(|b| b.label()).unwrap_or_else(|| "numeric".to_string())
}

impl CartesianTargetPanel {
    fn load_from_tcp(&mut self, ctx: &PanelContext<'_>) {
        // 2 decimals are shown: mm, and degrees (5e-3° ≈ 8.7e-5 rad)
        self.xyz_mm = ctx.robot.tcp.position_m.map(|v| super::zero_if_below(v * 1000.0, 5e-3));
        self.rpy = ctx.robot.tcp.rpy_rad.map(|v| super::zero_if_below(v, 8.7e-5));
        self.initialised = true;
        self.dirty = true;
    }

    fn solve(&mut self, ctx: &PanelContext<'_>) {
        self.dirty = false;
        let target = iso_from_xyz_rpy(self.xyz_mm.map(|v| v / 1000.0), self.rpy);
        let res = ik::solve(ctx.model, &target, &ctx.robot.q).map_err(|e| e.to_string());
        self.selected = match (&res, &self.selected_label) {
            (Ok(sols), Some(label)) => sols.iter().position(|s| &solution_label(s) == label).unwrap_or(0),
            _ => 0,
        };
        self.result = Some(res);
    }

    /// The chosen solution, if any.
    fn chosen(&self) -> Option<&IkSolution> {
        match &self.result {
            Some(Ok(s)) => s.get(self.selected),
            _ => None,
        }
    }
}

impl Panel for CartesianTargetPanel {
    fn title(&self) -> &'static str {
        "Cartesian target"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let r = ui.vertical(|ui| self.body(ui, ctx));
        // The chosen branch is previewed as the ghost while the pointer is over this panel.
        if let Some(s) = r.inner
            && ctx.settings.view.show_ghost
            && r.response.contains_pointer()
            && s.joints_rad.iter().zip(&ctx.robot.q).any(|(a, b)| (a - b).abs() > 1e-3)
        {
            *ctx.preview = Some(s.joints_rad);
        }
    }
}

impl CartesianTargetPanel {
    /// The panel's widgets; returns the chosen solution.
    fn body(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) -> Option<IkSolution> {
        if !self.initialised {
            self.load_from_tcp(ctx);
        }
        let unit = ctx.settings.unit;
        ui.heading(Panel::title(self));
        egui::Grid::new("cart_target").num_columns(4).spacing([8.0, 2.0]).show(ui, |ui| {
            for k in 0..3 {
                ui.label(["X", "Y", "Z"][k]);
                self.dirty |= ui
                    .add(egui::DragValue::new(&mut self.xyz_mm[k]).speed(0.5).suffix(" mm").max_decimals(2))
                    .changed();
                ui.label(["Roll", "Pitch", "Yaw"][k]);
                let mut v = unit.from_rad(self.rpy[k]);
                let r = ui.add(
                    egui::DragValue::new(&mut v)
                        .speed(if unit == super::AngleUnit::Deg { 0.5 } else { 0.01 })
                        .suffix(unit.suffix())
                        .max_decimals(unit.decimals()),
                );
                if r.changed() {
                    self.rpy[k] = unit.to_rad(v);
                    self.dirty = true;
                }
                ui.end_row();
            }
        });
        let mut solve_now = false;
        ui.horizontal(|ui| {
            if ui.button("From TCP").on_hover_text("Load the current TCP pose").clicked() {
                self.load_from_tcp(ctx);
            }
            solve_now |= ui.button("Solve IK").clicked();
        });
        // The closed-form PAROL6 solver takes microseconds: solve as the entries change.
        if solve_now || (self.dirty && ctx.model.is_parol6) {
            self.solve(ctx);
        }

        match &self.result {
            None => {
                ui.weak("Edit the target or press Solve IK.");
            }
            Some(Err(e)) => {
                ui.colored_label(ui.visuals().error_fg_color, format!("No solution: {e}"));
            }
            Some(Ok(sols)) => {
                ui.label(format!("{} solution(s) within the limits; pick a branch:", sols.len()));
                let mut picked = None;
                for (i, s) in sols.iter().enumerate() {
                    let text = format!(
                        "{}  Δ{}{}",
                        solution_label(s),
                        unit.fmt(s.distance_to_seed),
                        if s.singular { "  (singular)" } else { "" }
                    );
                    let hover = s.joints_rad.iter().map(|v| unit.fmt(*v)).collect::<Vec<_>>().join(", ");
                    if ui.selectable_label(self.selected == i, text).on_hover_text(hover).clicked() {
                        picked = Some(i);
                    }
                }
                if let Some(i) = picked {
                    self.selected = i;
                    self.selected_label = sols.get(i).map(solution_label);
                }
            }
        }
        let chosen = self.chosen().cloned();
        ui.horizontal(|ui| {
            let go = ui.add_enabled(chosen.is_some(), egui::Button::new("Move to target"));
            if go.on_hover_text("Profiled joint move to the chosen branch").clicked()
                && let Some(s) = &chosen
            {
                ctx.move_to(s.joints_rad.clone());
            }
        });
        chosen
    }
}
