//! A realistic program for timing pre-flight (the criterion bench `preflight` and
//! `parol6 bench motion`): PAROL6 pick-and-place cycles over [`STATIONS_DEG`]. Each cycle is
//! a jerk-limited joint move at [`JOINT_SPEED_FRACTION`] to above the next station, a straight
//! TCP line [`APPROACH_MM`] down and the same line back up (100 mm/s, jerk-limited), all
//! sampled every [`BENCH_DT_S`]. Trajectories are planned once per station and shared by the
//! cycles that repeat them (checking costs the same). [`bench_scene`] adds keep-out shapes
//! near, not on, the path, so every keep-out pair is measured.

use std::sync::Arc;

use nalgebra::Vector3;

use super::{MoveKind, PlannedMove};
use crate::model::RobotModel;
use crate::motion::MotionCaps;
use crate::motion::cartesian::{self, CartesianCaps};
use crate::motion::path::TcpPath;
use crate::motion::trajectory::SampledTrajectory;
use crate::profile::ProfileKind;
use crate::scene::{KeepOut, KeepOutShape};

/// Sample period of the bench program, s (pre-flight's usual 10 ms).
pub const BENCH_DT_S: f64 = 0.01;

/// Speed fraction of the joint moves between stations.
pub const JOINT_SPEED_FRACTION: f64 = 0.8;

/// Depth of the approach lines, mm.
pub const APPROACH_MM: f64 = 40.0;

/// Joint values above each station, degrees (J1 spread across the front; wrist off its
/// singularity).
pub const STATIONS_DEG: [[f64; 6]; 4] = [
    [60.0, -70.0, 160.0, 10.0, 40.0, 190.0],
    [80.0, -65.0, 155.0, -5.0, 45.0, 170.0],
    [100.0, -70.0, 160.0, 5.0, 40.0, 185.0],
    [120.0, -65.0, 150.0, -10.0, 50.0, 175.0],
];

/// Why the bench program cannot be built (a model that is not the PAROL6).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("bench program: {0}")]
pub struct BenchProgramError(pub String);

fn joint_move(from: &[f64], to: &[f64], caps: &MotionCaps) -> Result<Arc<SampledTrajectory>, BenchProgramError> {
    let mv = caps
        .plan_joint_move(from, to, JOINT_SPEED_FRACTION, ProfileKind::JerkLimited)
        .map_err(|e| BenchProgramError(e.to_string()))?;
    Ok(Arc::new(SampledTrajectory::new(BENCH_DT_S, mv.positions_every(BENCH_DT_S))))
}

fn line(
    model: &RobotModel,
    from: &[f64],
    dz_m: f64,
    caps: &MotionCaps,
) -> Result<Arc<SampledTrajectory>, BenchProgramError> {
    let a = model.tcp_isometry(from);
    let mut b = a;
    b.translation.vector += Vector3::new(0.0, 0.0, dz_m);
    let mv = cartesian::plan(model, from, &TcpPath::line(&a, &b), &CartesianCaps::default(), caps, 1.0, BENCH_DT_S)
        .map_err(|e| BenchProgramError(e.to_string()))?;
    Ok(mv.trajectory)
}

/// `moves` planned moves of pick-and-place cycles for `model` (the PAROL6 with any tool),
/// starting above the first station.
pub fn bench_program(model: &RobotModel, moves: usize) -> Result<Vec<PlannedMove>, BenchProgramError> {
    if !(model.is_parol6 && model.dof() == crate::parol6::JOINT_COUNT) {
        return Err(BenchProgramError(format!("needs the PAROL6, not '{}'", model.name)));
    }
    let caps = MotionCaps::of(model);
    let above: Vec<Vec<f64>> = STATIONS_DEG.iter().map(|s| s.iter().map(|d| d.to_radians()).collect()).collect();
    let mut down = Vec::new();
    let mut up = Vec::new();
    for q in &above {
        let d = line(model, q, -APPROACH_MM * 1e-3, &caps)?;
        up.push(line(model, d.goal(), APPROACH_MM * 1e-3, &caps)?);
        down.push(d);
    }
    let n = above.len();
    // the joint move from where station i's up-line ends to above station i + 1
    let mut transfer = Vec::new();
    for i in 0..n {
        transfer.push(joint_move(up[i].goal(), &above[(i + 1) % n], &caps)?);
    }
    let mut out = Vec::with_capacity(moves);
    let mut station = 0;
    while out.len() < moves {
        let cycle = [
            (format!("MoveL down at station {}", station + 1), MoveKind::Cartesian, down[station].clone()),
            (format!("MoveL up at station {}", station + 1), MoveKind::Cartesian, up[station].clone()),
            (format!("MoveJ to station {}", (station + 1) % n + 1), MoveKind::Joint, transfer[station].clone()),
        ];
        for (label, kind, trajectory) in cycle {
            if out.len() == moves {
                break;
            }
            let index = out.len();
            out.push(PlannedMove { index, line: index + 1, label, kind, trajectory });
        }
        station = (station + 1) % n;
    }
    Ok(out)
}

/// Keep-out shapes beside the bench program's path: a fixture box between the robot's back
/// and its cable, a camera post and a sphere (a lamp) overhead.
pub fn bench_scene() -> Vec<KeepOut> {
    vec![
        KeepOut::new(
            "fixture",
            KeepOutShape::Box { center_mm: [0.0, -250.0, 60.0], size_mm: [200.0, 100.0, 120.0], rpy_deg: [0.0; 3] },
        ),
        KeepOut::new(
            "camera post",
            KeepOutShape::Cylinder {
                center_mm: [350.0, 150.0, 250.0],
                radius_mm: 25.0,
                height_mm: 500.0,
                rpy_deg: [0.0; 3],
            },
        ),
        KeepOut::new("lamp", KeepOutShape::Sphere { center_mm: [0.0, 200.0, 750.0], radius_mm: 80.0 }),
    ]
}
