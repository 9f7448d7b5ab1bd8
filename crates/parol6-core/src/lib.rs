//! # parol6-core
//!
//! The robot itself, without GUI or serial: URDF → [`model::RobotModel`], forward kinematics,
//! Jacobians and inverse kinematics ([`kinematics`], [`ik`]), the two three-angle orientation
//! conventions (ours and the official PAROL6 tools', [`angles`]), the commander GUI's TCP frame
//! ([`frames`]), joint limits and limit zones with
//! their colours ([`limits`]), synchronised joint motion profiles ([`profile`]), the rapier3d
//! simulation on its own 1 kHz thread with dynamics and the self-collision guard ([`sim`]), and
//! the motion layer shared by the simulation and the robot ([`motion`]: one command type, one
//! planner, the [`motion::RobotBackend`] trait, pre-flight validation of planned programs in
//! [`motion::preflight`]), robot programs ([`program`]: steps, the native file format,
//! compiling, pre-flight and the runner thread), ISO 9283 measurement ([`measure`]: the test
//! cube, pose and path figures, the measurement CSV, the test driver on any backend), the keep-out shapes of the robot's
//! surroundings ([`scene`]), the PAROL6 facts of the reference pack ([`parol6`]), the size /
//! nesting bounds every URDF text passes before parsing ([`urdf_input`]), sample statistics
//! with one percentile rule ([`stats`]), handing freed memory back ([`process`]), the one atomic
//! file writer and bounded regular-file reader ([`fsio`]), telemetry ([`telemetry`]: the recorder thread with
//! its live ring buffer, MCAP files for Foxglove / Lichtblick, and the reader of our own
//! recordings), and the ROS 2 messages as `rmw_zenoh` carries them ([`ros2`]: CDR, key
//! expressions, liveliness tokens, incoming trajectories → a pre-flighted program).
//!
//! Must not depend on any GUI, windowing, GPU or serial-port crate. `nalgebra` is re-exported
//! as [`na`] so every crate uses the same version.

pub use nalgebra as na;

pub mod angles;
pub mod collision;
pub mod dynamics;
pub mod frames;
pub mod fsio;
pub mod ik;
pub mod kinematics;
pub mod limits;
pub mod measure;
pub mod model;
pub mod motion;
pub mod parol6;
pub mod plural;
pub mod process;
pub mod profile;
pub mod program;
pub mod ros2;
pub mod scene;
pub mod sim;
pub mod stats;
pub mod telemetry;
pub mod urdf_input;

pub use ik::{IkError, IkSolution};
pub use kinematics::{Manipulability, TcpPose};
pub use limits::{JointLimit, JointLimits, LimitPolicy, LimitViolation, LimitZone, ZoneThresholds};
pub use model::{ModelError, RobotModel};
pub use parol6::Tool;
