//! Right panel, top: TCP position (mm) and RPY, the 4×4 T and 3×3 R matrices, and a
//! manipulability / singularity indicator.

use eframe::egui;
use parol6_core::kinematics::{Manipulability, SINGULARITY_SIGMA_MIN};

use super::{Panel, PanelContext, entry};
use crate::palette;

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

/// Decimals of unitless matrix entries (rotation); millimetres always show 2.
const MATRIX_DECIMALS: usize = 4;
/// Decimals of millimetres.
const MM_DECIMALS: usize = 2;

/// A matrix as monospace lines, every entry right-aligned in a column of the same width (a
/// grid of separate labels does not line up the decimal points). `decimals` per column.
fn matrix_text(rows: &[Vec<f64>], decimals: &[usize]) -> String {
    let cells: Vec<Vec<String>> =
        rows.iter().map(|r| r.iter().zip(decimals).map(|(v, d)| entry::fmt_fixed(*v, *d)).collect()).collect();
    let width = cells.iter().flatten().map(|c| c.chars().count()).max().unwrap_or(0);
    cells
        .iter()
        .map(|r| r.iter().map(|c| format!("{c:>width$}")).collect::<Vec<_>>().join(" "))
        .collect::<Vec<_>>()
        .join("\n")
}

/// What the manipulability badge says: text and whether it is a singularity. A wrist
/// singularity of the PAROL6 (J5 = 0 or ±180°: J4 and J6 line up) is named as such.
fn condition_text(ctx: &PanelContext<'_>, m: &Manipulability, near: bool) -> String {
    let wrist_aligned = ctx.model.is_parol6 && ctx.readout.q.get(4).is_some_and(|q5| q5.sin().abs() < 0.02);
    let unit = ctx.settings.unit;
    match (m.singular, near, wrist_aligned) {
        (true, _, true) => format!("wrist singular (J5 = {})", unit.fmt(ctx.readout.q[4])),
        (true, _, false) => "singular".to_string(),
        (false, true, true) => format!("near wrist singularity (J5 = {})", unit.fmt(ctx.readout.q[4])),
        (false, true, false) => "near singularity".to_string(),
        (false, false, _) => "well-conditioned".to_string(),
    }
}

impl Panel for TcpPanel {
    fn title(&self) -> &'static str {
        "TCP"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let tcp = ctx.readout.tcp;
        let unit = ctx.settings.unit;
        ui.heading(self.title());
        let shown = ctx.settings.tcp_readout_rad(tcp.rpy_rad);
        let labels = ctx.settings.angle_labels();
        egui::Grid::new("tcp_pose").num_columns(4).spacing([12.0, 2.0]).show(ui, |ui| {
            for (k, label) in ["X", "Y", "Z"].iter().enumerate() {
                ui.label(*label);
                ui.monospace(format!("{:>9} mm", entry::fmt_fixed(tcp.position_m[k] * 1000.0, MM_DECIMALS)));
                ui.label(labels[k]).on_hover_text(ctx.settings.readout_angle_hover());
                ui.monospace(format!("{:>10}", unit.fmt(shown[k])));
                ui.end_row();
            }
        });
        egui::CollapsingHeader::new("T (4×4, translation in mm)").default_open(true).show(ui, |ui| {
            let m = tcp.matrix4();
            // Translation column in mm; the bottom row stays [0 0 0 1].
            let rows: Vec<Vec<f64>> = m
                .iter()
                .enumerate()
                .map(|(r, row)| {
                    row.iter().enumerate().map(|(c, v)| if c == 3 && r < 3 { v * 1000.0 } else { *v }).collect()
                })
                .collect();
            let d = [MATRIX_DECIMALS, MATRIX_DECIMALS, MATRIX_DECIMALS, MM_DECIMALS];
            ui.label(egui::RichText::new(matrix_text(&rows, &d)).monospace());
        });
        egui::CollapsingHeader::new("R (3×3)").default_open(false).show(ui, |ui| {
            let rows: Vec<Vec<f64>> = tcp.rotation.iter().map(|r| r.to_vec()).collect();
            ui.label(egui::RichText::new(matrix_text(&rows, &[MATRIX_DECIMALS; 3])).monospace());
        });

        let m = self.manipulability(ctx);
        let sref = self.sigma_ref(ctx);
        let frac = (m.sigma_min / sref).clamp(0.0, 1.0) as f32;
        // A singularity is a fact about the pose, not a risk by itself (the arm is not
        // driven in Cartesian space): a calm, neutral badge, never the alarm colours.
        let near = !m.singular && (m.sigma_min < 10.0 * SINGULARITY_SIGMA_MIN || frac < 0.1);
        let text = condition_text(ctx, &m, near);
        let color = if m.singular || near {
            palette::rgb(palette::CONDITION_SINGULAR)
        } else {
            palette::rgb(palette::CONDITION_GOOD)
        };
        ui.horizontal(|ui| {
            ui.label("Manipulability");
            ui.add(crate::theme::bar(frac).fill(color).text(text.as_str()).desired_width(ui.available_width()))
                .on_hover_text(format!(
                    "σ_min = {:.2e}, σ_max = {:.2e}, Yoshikawa w = {:.3e}\nbar: σ_min relative to the home pose; \
                     singular below σ_min = {SINGULARITY_SIGMA_MIN:e}",
                    m.sigma_min, m.sigma_max, m.yoshikawa
                ));
        });
        ui.small(format!("w = {:.3e}   σ_min = {:.2e}", m.yoshikawa, m.sigma_min));
    }
}
