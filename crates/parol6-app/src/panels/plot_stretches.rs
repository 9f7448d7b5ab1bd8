//! What the drive series held, stretch by stretch, in the live plots' history: torque (N·m)
//! from the simulation, step rates (steps/s) from the robot. The history is kept over a
//! backend switch, but the drive plot's axis has the unit of the current backend, so the
//! stretches of the other quantity are not drawn there ([`split_shown`]) and the plot says
//! what it leaves out ([`hidden_note`]).

use parol6_core::telemetry::DriveKind;

/// One stretch of the live history: the drive quantity of its rows and its backend.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriveStretch {
    /// Rows after this plot time, s, belong to the stretch (−∞ for the first).
    pub after_s: f64,
    /// What its drive series hold.
    pub drive: DriveKind,
    /// Its rows came from the robot (else from the simulation).
    pub robot: bool,
}

/// The drive stretches of the live history, oldest first.
#[derive(Clone, Debug, Default)]
pub struct DriveStretches {
    stretches: Vec<DriveStretch>,
}

impl DriveStretches {
    /// Notes the drive quantity of rows taken after plot time `after_s` (`None`: the history's
    /// first rows) from the robot (`robot`) or the simulation. A new stretch starts when the
    /// quantity or the backend changes.
    pub fn note(&mut self, after_s: Option<f64>, drive: DriveKind, robot: bool) {
        let same = self.stretches.last().is_some_and(|s| s.drive == drive && s.robot == robot);
        if !same {
            self.stretches.push(DriveStretch { after_s: after_s.unwrap_or(f64::NEG_INFINITY), drive, robot });
        }
    }

    /// The spans (`(from_s, to_s, stretch)`, `from_s` excluded, `to_s` included) whose drive
    /// quantity is not `shown`.
    pub fn hidden(&self, shown: DriveKind) -> Vec<(f64, f64, DriveStretch)> {
        let ends = self.stretches.iter().skip(1).map(|s| s.after_s).chain([f64::INFINITY]);
        self.stretches.iter().zip(ends).filter(|(s, _)| s.drive != shown).map(|(s, end)| (s.after_s, end, *s)).collect()
    }
}

impl DriveStretches {
    /// The stretch a row at plot time `t_s` belongs to (`None` before any was noted).
    pub fn at(&self, t_s: f64) -> Option<DriveStretch> {
        self.stretches.iter().rev().find(|s| s.after_s < t_s).copied()
    }

    /// True when no stretch was noted (no live rows yet, or a replay's store).
    pub fn is_empty(&self) -> bool {
        self.stretches.is_empty()
    }
}

/// The unit of a drive quantity.
pub fn drive_unit(drive: DriveKind) -> &'static str {
    match drive {
        DriveKind::TorqueNm => "N·m",
        DriveKind::StepsPerS => "steps/s",
    }
}

/// Splits `points` (`[t_s, value]`, time order) into the runs outside every `hidden` span,
/// each span widened by `pad_s` both sides (a decimated point stands for a pixel column, which
/// may straddle a switch).
pub fn split_shown(points: &[[f64; 2]], hidden: &[(f64, f64, DriveStretch)], pad_s: f64) -> Vec<Vec<[f64; 2]>> {
    let mut runs: Vec<Vec<[f64; 2]>> = Vec::new();
    let mut open = false;
    for p in points {
        let out = hidden.iter().any(|(from, to, _)| p[0] > from - pad_s && p[0] <= to + pad_s);
        if out {
            open = false;
            continue;
        }
        match runs.last_mut() {
            Some(run) if open => run.push(*p),
            _ => runs.push(vec![*p]),
        }
        open = true;
    }
    runs
}

/// What the drive plot leaves out between `x0` and `x1` (s), in words, or `None` when it
/// leaves out nothing there.
pub fn hidden_note(hidden: &[(f64, f64, DriveStretch)], x0: f64, x1: f64, shown: DriveKind) -> Option<String> {
    let parts: Vec<String> = hidden
        .iter()
        .filter(|(from, to, _)| *to > x0 && *from < x1)
        .map(|(from, to, s)| {
            let backend = if s.robot { "robot" } else { "simulation" };
            let what = match s.drive {
                DriveKind::TorqueNm => "torque",
                DriveKind::StepsPerS => "step rate",
            };
            format!(
                "{} to {} s ({backend}, {what} in {})",
                span_end(from.max(x0)),
                span_end(to.min(x1)),
                drive_unit(s.drive)
            )
        })
        .collect();
    (!parts.is_empty()).then(|| format!("not drawn under {}: {}", drive_unit(shown), parts.join("; ")))
}

fn span_end(t_s: f64) -> String {
    format!("{:.1}", t_s + 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sim_robot_sim() -> DriveStretches {
        let mut s = DriveStretches::default();
        s.note(None, DriveKind::TorqueNm, false);
        s.note(Some(1.0), DriveKind::TorqueNm, false);
        s.note(Some(10.0), DriveKind::StepsPerS, true);
        s.note(Some(20.0), DriveKind::TorqueNm, false);
        s
    }

    #[test]
    fn the_stretches_of_the_other_quantity_are_hidden() {
        let s = sim_robot_sim();
        let h = s.hidden(DriveKind::StepsPerS);
        assert_eq!(h.len(), 2, "{h:?}");
        assert_eq!((h[0].0, h[0].1), (f64::NEG_INFINITY, 10.0));
        assert_eq!((h[1].0, h[1].1), (20.0, f64::INFINITY));
        let h = s.hidden(DriveKind::TorqueNm);
        assert_eq!(h.iter().map(|(a, b, _)| (*a, *b)).collect::<Vec<_>>(), vec![(10.0, 20.0)]);
    }

    #[test]
    fn only_the_points_outside_hidden_spans_are_drawn_in_separate_runs() {
        let s = sim_robot_sim();
        let pts: Vec<[f64; 2]> = (0..30).map(|i| [f64::from(i), f64::from(i)]).collect();
        let runs = split_shown(&pts, &s.hidden(DriveKind::TorqueNm), 0.0);
        assert_eq!(runs.len(), 2, "the robot's stretch breaks the line");
        assert_eq!(runs[0].last().map(|p| p[0]), Some(10.0), "the simulation's last row is drawn");
        assert_eq!(runs[1].first().map(|p| p[0]), Some(21.0));
        let padded = split_shown(&pts, &s.hidden(DriveKind::TorqueNm), 0.5);
        assert_eq!(padded[0].last().map(|p| p[0]), Some(9.0), "a column at the switch is left out");
    }

    #[test]
    fn the_note_names_what_is_left_out_in_the_visible_window() {
        let s = sim_robot_sim();
        let note = hidden_note(&s.hidden(DriveKind::StepsPerS), 5.0, 15.0, DriveKind::StepsPerS);
        assert_eq!(note.as_deref(), Some("not drawn under steps/s: 5.0 to 10.0 s (simulation, torque in N·m)"));
        assert_eq!(hidden_note(&s.hidden(DriveKind::StepsPerS), 11.0, 19.0, DriveKind::StepsPerS), None);
    }
}
