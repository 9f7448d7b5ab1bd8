//! Measuring the arm the ISO 9283 way, on the simulation or the robot alike.
//!
//! - [`cube`]: the test cube, its diagonal plane and the test poses P1–P5;
//! - [`plan`]: the programs of the pose test and of the path tests (line, circle, triangle)
//!   and their pre-flight (an unreachable cube is refused naming the pose);
//! - [`pose_figures`]: pose accuracy / repeatability AP / RP and distance AD / RD;
//! - [`path_figures`]: path accuracy / repeatability AT_p / RT_p, max and RMS deviation;
//! - [`measurements`]: the measurement CSV (raw attained poses, or a laser tracker's);
//! - [`driver`]: runs a test on any [`RobotBackend`](crate::motion::RobotBackend) with the
//!   program runner, reading the attained pose as the FK of the measured joints once the arm
//!   has settled, with progress and abort;
//! - [`compare`]: simulation against robot, per joint and TCP over time.

pub mod compare;
pub mod cube;
pub mod driver;
pub mod measurements;
pub mod path_figures;
pub mod plan;
pub mod pose_figures;

pub use cube::TestCube;
pub use plan::{PathKind, PathTestPlan, PoseTestPlan};
