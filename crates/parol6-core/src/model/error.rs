//! [`ModelError`]: every way loading a URDF into a [`super::RobotModel`] can fail, each with
//! its own message naming the link or joint.

use std::path::PathBuf;

/// Errors of loading a URDF into a [`RobotModel`](crate::RobotModel). Each has its own message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read.
    #[error("cannot read URDF file {path}: {reason}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        reason: String,
    },
    /// The path is not a regular file (a FIFO, a device, a directory): refused before reading.
    #[error("cannot read URDF file {path}: {reason}")]
    NotRegularFile {
        /// The file.
        path: PathBuf,
        /// What it is instead.
        reason: String,
    },
    /// The text is not XML, or not a `<robot>` description.
    #[error("not a URDF robot description: {0}")]
    NotUrdf(String),
    /// The robot has no `<link>`.
    #[error("the URDF robot \"{0}\" has no links")]
    NoLinks(String),
    /// Two links share a name.
    #[error("link name \"{0}\" is used twice")]
    DuplicateLink(String),
    /// A joint names a link that does not exist.
    #[error("joint \"{joint}\" names {role} link \"{link}\", which does not exist")]
    MissingLink {
        /// The joint.
        joint: String,
        /// "parent" or "child".
        role: &'static str,
        /// The missing link name.
        link: String,
    },
    /// More than one link has no parent joint.
    #[error("the URDF has several root links ({}); a robot needs exactly one", .0.join(", "))]
    SeveralRoots(Vec<String>),
    /// A link has two parent joints, or the joints form a loop.
    #[error("the joints form a cycle or give link \"{0}\" two parents")]
    Cycle(String),
    /// The requested tip link does not exist.
    #[error("tip link \"{0}\" does not exist in the URDF")]
    TipNotFound(String),
    /// No tip was given and the tree has several leaves.
    #[error("the robot has several leaf links ({}); choose the tip link explicitly", .0.join(", "))]
    AmbiguousTip(Vec<String>),
    /// The chain from root to tip has no revolute / continuous / prismatic joint.
    #[error("the chain from \"{root}\" to \"{tip}\" has no movable joint")]
    NoMovableJoint {
        /// Root link.
        root: String,
        /// Tip link.
        tip: String,
    },
    /// A joint type this loader cannot put in a serial chain.
    #[error("joint \"{joint}\" has type {kind}, which a serial arm model does not support")]
    UnsupportedJoint {
        /// The joint.
        joint: String,
        /// Its type.
        kind: String,
    },
    /// A joint's lower limit lies above its upper limit, or a limit is not finite.
    #[error("joint \"{joint}\" has an invalid range: lower {lower} > upper {upper}")]
    InvalidLimits {
        /// The joint.
        joint: String,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// A joint axis is zero or not finite.
    #[error("joint \"{0}\" has a zero or invalid axis")]
    InvalidAxis(String),
    /// A number of the URDF is not finite or beyond a plausibility bound.
    #[error("{place} is {value}: {why}")]
    ImplausibleNumber {
        /// The link or joint and the field.
        place: String,
        /// The value as read.
        value: String,
        /// What is wrong with it.
        why: String,
    },
    /// The text is not well-formed XML; `line` and `column` are 1-based.
    #[error("not a URDF robot description: line {line}, column {column}: {message}")]
    XmlSyntax {
        /// Line of the error.
        line: u32,
        /// Column of the error.
        column: u32,
        /// What the XML parser found.
        message: String,
    },
    /// The text is too large or nests too deep to parse safely (checked before parsing).
    #[error(transparent)]
    InputRefused(#[from] crate::urdf_input::UrdfInputError),
    /// A mesh file could not be found. Reported in [`RobotModel::warnings`](crate::RobotModel::warnings); kinematics still load.
    #[error("link \"{link}\": mesh \"{uri}\" not found (resolved to {})", .resolved.display())]
    MeshNotFound {
        /// The link.
        link: String,
        /// The filename as written in the URDF.
        uri: String,
        /// Where it was looked for.
        resolved: PathBuf,
    },
    /// A mesh file exists but is not read: it is not a regular file (a FIFO, a device) or is
    /// larger than [`super::MAX_MESH_FILE_BYTES`]. Reported in [`super::RobotModel::warnings`]; the
    /// link is drawn as a placeholder and has no collision shape from it.
    #[error("link \"{link}\": mesh \"{uri}\" not read: {reason}")]
    MeshRefused {
        /// The link.
        link: String,
        /// The filename as written in the URDF.
        uri: String,
        /// Why (names the resolved path).
        reason: String,
    },
}
