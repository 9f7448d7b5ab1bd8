//! # parol6-hw
//!
//! Everything between PAROL6 Studio and a real PAROL6 controller board:
//! - the serial wire protocol ([`frame`], [`parser`]) and the step ↔ angle units ([`units`]),
//! - serial-port discovery ([`ports`]),
//! - the controller [`session`]: one thread streaming the core motion planner's setpoint as
//!   one command frame per period, parsing the status, publishing lock-free snapshots and robot
//!   states, implementing [`parol6_core::motion::RobotBackend`] ([`backend`]), and acting as the
//!   **safety layer** (the firmware has no CRC, no timeout and no limit checks),
//! - a controller [`emulator`] that behaves like the public firmware, on a pseudo-terminal or
//!   (the fake robot) on a local socket (`socket_link`).
//!
//! This crate must not depend on any GUI, windowing or GPU crate, nor on rapier (physics lives
//! in `parol6-core`'s simulation). Motion comes from [`parol6_core::motion`], joint limits from
//! [`parol6_core::limits`] and [`parol6_core::parol6::LIMITS_STEPS`].

pub mod backend;
pub mod emulator;
pub mod frame;
pub mod parser;
pub mod ports;
pub mod priority;
pub mod session;
#[cfg(unix)]
pub mod socket_link;
pub mod units;

pub use emulator::{ControllerModel, EmulatorConfig, EmulatorHandle, StatusCorruptor};
pub use frame::{CommandCode, CommandFields, CommandFrame, GripperCommand, ReceivedCommand, StatusFrame};
pub use parser::{CommandParser, StatusParser};
pub use ports::{PAROL6_PID, PAROL6_VID, PortInfo, find_parol6_port, list_ports};
pub use session::{HomingState, LinkState, MotionState, Session, SessionConfig, Snapshot};

/// Errors of the hardware layer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HwError {
    /// The port exists but we may not open it.
    #[error(
        "permission denied opening {port}: add your user to the 'dialout' group \
         (sudo usermod -aG dialout $USER, then log out and back in) or install a udev rule such as \
         SUBSYSTEM==\"tty\", ATTRS{{idVendor}}==\"0483\", ATTRS{{idProduct}}==\"5740\", MODE=\"0660\", GROUP=\"dialout\" \
         in /etc/udev/rules.d/99-parol6.rules"
    )]
    PermissionDenied {
        /// Port path.
        port: String,
    },
    /// The port could not be opened for another reason.
    #[error(
        "cannot open serial port {port}: {reason}; pick the PAROL6's port (USB 0483:5740, listed by `parol6 hw ports`) and check its cable"
    )]
    PortOpen {
        /// Port path.
        port: String,
        /// What serialport reported.
        reason: String,
    },
    /// No PAROL6 (USB 0483:5740) found.
    #[error("no PAROL6 controller found (USB 0483:5740); ports seen: {seen}")]
    NotFound {
        /// Ports that were listed.
        seen: String,
    },
    /// Listing ports failed.
    #[error("cannot list serial ports: {0}")]
    ListPorts(String),
    /// Bad session settings.
    #[error("invalid session setting: {0}")]
    BadConfig(String),
    /// A request was refused (E-stop, disabled, busy, outside limits …).
    #[error("refused: {0}")]
    Refused(String),
    /// The target violates the joint limits.
    #[error(transparent)]
    Limit(#[from] parol6_core::limits::LimitViolation),
    /// The move could not be planned.
    #[error(transparent)]
    Profile(#[from] parol6_core::profile::ProfileError),
    /// A value cannot be expressed in steps.
    #[error(transparent)]
    Units(#[from] units::UnitError),
    /// Homing did not complete.
    #[error("homing failed: {0}")]
    Homing(String),
    /// The controller or the link failed or reported something impossible (link lost, E-stop
    /// pressed during motion, impossible positions, an arm that does not follow): a device
    /// event, not the user's request.
    #[error("{0}")]
    Device(String),
    /// Waiting for something timed out.
    #[error("timed out: {0}")]
    Timeout(String),
    /// The session thread has ended.
    #[error("the controller session is closed")]
    Closed,
    /// A motion command was refused.
    #[error(transparent)]
    Motion(#[from] parol6_core::motion::MotionError),
    /// The emulator could not start.
    #[error("emulator: {0}")]
    Emulator(String),
}

impl From<parol6_core::motion::BackendError> for HwError {
    fn from(e: parol6_core::motion::BackendError) -> Self {
        use parol6_core::motion::BackendError as B;
        match e {
            B::Motion(m) => HwError::Motion(m),
            B::Refused(r) => HwError::Refused(r),
            B::QueueFull => HwError::Refused("session command queue is full".into()),
            B::Closed => HwError::Closed,
        }
    }
}
