//! Right panel, top: TCP position (mm) and RPY, the 4×4 T and 3×3 R matrices, and a
//! manipulability / singularity indicator.

use eframe::egui;
use parol6_core::kinematics::{Manipulability, SINGULARITY_SIGMA_MIN};

use super::{Panel, PanelContext};

/// The TCP panel.
#[derive(Debug, Default)]
pub struct TcpPanel {
    /// σ_min at the home pose, the reference for the indicator bar (computed once).
    sigma_ref: Option<f64>,
    /// Cached manipulability for the last joint values.
    cache: Option<(Vec<f64>, Manipulability)>,
}

impl TcpPanel {
    fn manipulability(&mut self, ctx: &PanelContext<'_>) -> Manipulability {
        if let Some((q, m)) = &self.cache
            && q == &ctx.readout.q
        {
            return *m;
        }
        let m = ctx.model.manipulability(&ctx.readout.q);
        self.cache = Some((ctx.readout.q.clone(), m));
        m
    }

    fn sigma_ref(&mut self, ctx: &PanelContext<'_>) -> f64 {
        *self.sigma_ref.get_or_insert_with(|| {
            let home: Vec<f64> = if ctx.model.is_parol6 {
                parol6_core::parol6::standby_rad().to_vec()
            } else {
                ctx.model.limits.iter().map(|l| if l.is_bounded() { 0.5 * (l.min + l.max) } else { 0.0 }).collect()
            };
            ctx.model.manipulability(&home).sigma_min.max(1e-6)
        })
    }
}

/// Hides the sign of values that print as zero with 4 decimals (no "-0.0000").
fn clean(v: f64) -> f64 {
    super::zero_if_below(v, 5e-5)
}

fn matrix_grid(ui: &mut egui::Ui, id: &str, rows: &[&[f64]], fmt: impl Fn(usize, f64) -> String) {
    egui::Grid::new(id).num_columns(rows.first().map_or(0, |r| r.len())).spacing([10.0, 2.0]).striped(true).show(
        ui,
        |ui| {
            for row in rows {
                for (c, v) in row.iter().enumerate() {
                    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                        ui.monospace(fmt(c, *v));
                    });
                }
                ui.end_row();
            }
        },
    );
}

impl Panel for TcpPanel {
    fn title(&self) -> &'static str {
        "TCP"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let tcp = ctx.readout.tcp;
        let unit = ctx.settings.unit;
        ui.heading(self.title());
        egui::Grid::new("tcp_pose").num_columns(4).spacing([12.0, 2.0]).show(ui, |ui| {
            for (k, label) in ["X", "Y", "Z"].iter().enumerate() {
                ui.label(*label);
                ui.monospace(format!("{:9.2} mm", tcp.position_m[k] * 1000.0));
                ui.label(["Roll", "Pitch", "Yaw"][k]);
                ui.monospace(unit.fmt(tcp.rpy_rad[k]));
                ui.end_row();
            }
        });
        egui::CollapsingHeader::new("T (4×4, translation in mm)").default_open(true).show(ui, |ui| {
            let m = tcp.matrix4();
            // Translation column in mm; the bottom row stays [0 0 0 1].
            let mut mm = m;
            for row in mm.iter_mut().take(3) {
                row[3] *= 1000.0;
            }
            let rows: Vec<&[f64]> = mm.iter().map(|r| r.as_slice()).collect();
            matrix_grid(
                ui,
                "tcp_t",
                &rows,
                |c, v| if c == 3 { format!("{:9.2}", v) } else { format!("{:7.4}", clean(v)) },
            );
        });
        egui::CollapsingHeader::new("R (3×3)").default_open(false).show(ui, |ui| {
            let rows: Vec<&[f64]> = tcp.rotation.iter().map(|r| r.as_slice()).collect();
            matrix_grid(ui, "tcp_r", &rows, |_, v| format!("{:7.4}", clean(v)));
        });

        let m = self.manipulability(ctx);
        let sref = self.sigma_ref(ctx);
        let frac = (m.sigma_min / sref).clamp(0.0, 1.0) as f32;
        let (color, text) = if m.singular {
            (ui.visuals().error_fg_color, "SINGULAR")
        } else if m.sigma_min < 10.0 * SINGULARITY_SIGMA_MIN || frac < 0.1 {
            (ui.visuals().warn_fg_color, "near singularity")
        } else {
            (ui.visuals().selection.bg_fill, "well-conditioned")
        };
        ui.horizontal(|ui| {
            ui.label("Manipulability");
            ui.add(egui::ProgressBar::new(frac).fill(color).text(text).desired_width(ui.available_width()))
                .on_hover_text(format!(
                    "σ_min = {:.2e}, σ_max = {:.2e}, Yoshikawa w = {:.3e}\nbar: σ_min relative to the home pose; \
                     singular below σ_min = {SINGULARITY_SIGMA_MIN:e}",
                    m.sigma_min, m.sigma_max, m.yoshikawa
                ));
        });
        ui.small(format!("w = {:.3e}   σ_min = {:.2e}", m.yoshikawa, m.sigma_min));
    }
}
