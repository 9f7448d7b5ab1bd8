//! The ROS 2 options of `parol6 serve --ros2` and the server's start (feature `ros2`).

use super::CliError;
use crate::live::{LiveServer, LiveSource};

/// Where the ROS 2 node connects (with `--ros2`).
#[derive(Debug, Clone, clap::Args)]
pub struct Ros2Args {
    /// Zenoh endpoint of the router to connect to (rmw_zenoh's `ros2 run rmw_zenoh_cpp
    /// rmw_zenohd` listens on tcp/127.0.0.1:7447); repeat for more. TCP only.
    #[arg(long = "ros2-connect", value_name = "ENDPOINT", default_value = "tcp/127.0.0.1:7447")]
    pub connect: Vec<String>,
    /// Zenoh endpoint to listen on for peer-to-peer links from other ROS 2 nodes (default this
    /// host only, a free port; tcp/0.0.0.0:0 for every interface); repeat for more.
    #[arg(long = "ros2-listen", value_name = "ENDPOINT", default_value = "tcp/127.0.0.1:0")]
    pub listen: Vec<String>,
    /// Find peers by UDP multicast scouting too (off: the router introduces them).
    #[arg(long = "ros2-scouting")]
    pub scouting: bool,
    /// ROS domain id (ROS_DOMAIN_ID of the other nodes), 0–232.
    #[arg(long = "ros2-domain", value_name = "ID", default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=232))]
    pub domain: u32,
    /// Name of the control_msgs/action/FollowJointTrajectory action served (MoveIt's
    /// `<controller name>/<action_ns>`).
    #[arg(long = "ros2-action", value_name = "NAME", default_value = parol6_core::ros2::action::DEFAULT_ACTION_NAME)]
    pub action: String,
}

/// Refuses an endpoint this build cannot use (only TCP is built in).
fn checked(flag: &str, endpoints: &[String]) -> Result<Vec<String>, CliError> {
    crate::live::tcp_endpoints(flag, endpoints).map_err(CliError::usage)
}

/// Refuses an action name that is not a ROS name.
fn action_name(name: &str) -> Result<String, CliError> {
    if parol6_core::ros2::action::valid_action_name(name) {
        Ok(name.to_string())
    } else {
        Err(CliError::usage(format!(
            "--ros2-action {name:?}: not a ROS name (letters, digits and _ in /-separated parts, e.g. \
             /parol6_arm_controller/follow_joint_trajectory)"
        )))
    }
}

/// Starts the ROS 2 node.
#[cfg(feature = "ros2")]
pub fn start(args: &Ros2Args, source: &LiveSource<'_>) -> Result<Box<dyn LiveServer>, CliError> {
    let opts = crate::live::ros2::Ros2Options {
        connect: checked("--ros2-connect", &args.connect)?,
        listen: checked("--ros2-listen", &args.listen)?,
        multicast_scouting: args.scouting,
        domain_id: args.domain,
        action_name: action_name(&args.action)?,
    };
    crate::live::ros2::Ros2Server::start(source, &opts)
        .map(|s| Box::new(s) as Box<dyn LiveServer>)
        .map_err(|e| CliError::runtime(format!("--ros2: {e}")))
}

/// Without the `ros2` feature: refused.
#[cfg(not(feature = "ros2"))]
pub fn start(args: &Ros2Args, _source: &LiveSource<'_>) -> Result<Box<dyn LiveServer>, CliError> {
    checked("--ros2-connect", &args.connect)?;
    action_name(&args.action)?;
    Err(CliError::usage("--ros2: this parol6 was built without the `ros2` feature"))
}
