//! ROS 2 over Zenoh (cargo feature `ros2`), speaking `rmw_zenoh`'s conventions so that ROS 2
//! nodes running `RMW_IMPLEMENTATION=rmw_zenoh_cpp` see a node `parol6`:
//!
//! - the session is a Zenoh peer that connects to a router (`tcp/127.0.0.1:7447` unless told
//!   otherwise), listens on localhost only, with multicast scouting off unless asked for
//!   ([`node`]);
//! - the node and each of its publishers and subscriptions declare `rmw_zenoh`'s liveliness
//!   tokens; every sample carries its attachment (sequence number, time stamp, GID);
//! - `/joint_states` (`sensor_msgs/msg/JointState`, URDF joint names, 100 Hz) and `/tf`
//!   (`tf2_msgs/msg/TFMessage`, one transform per URDF joint, 50 Hz) from the recorder's live
//!   outlet ([`publish`]); `/robot_description` (`std_msgs/msg/String`, the URDF) transient local
//!   (a cache of one sample that late subscribers query, as `rmw_zenoh`'s advanced publisher
//!   keeps);
//! - `trajectory_msgs/msg/JointTrajectory` on `/parol6/joint_trajectory`, refused unless remote
//!   control is on, else checked, pre-flighted and run; the result on
//!   `/parol6/trajectory_result` ([`commands`]);
//! - the `control_msgs/action/FollowJointTrajectory` action MoveIt's simple controller manager
//!   sends to (default `/parol6_arm_controller/follow_joint_trajectory`), its goals on the same
//!   path as those trajectories ([`action`]); its feedback (20 Hz) and path tolerance from the
//!   same telemetry samples as `/joint_states` ([`feedback`]).
//!
//! The message encodings, names and checks are in `parol6_core::ros2`. Zenoh's runtime (tokio)
//! stays inside this module: the rest of the app sees [`Ros2Server`] and [`Ros2Options`].

pub mod action;
pub mod commands;
pub mod feedback;
pub mod node;
pub mod publish;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;

use parol6_core::ros2::cdr;
use parol6_core::ros2::graph::Qos;
use parol6_core::ros2::msgs::StringMsg;
use parol6_core::ros2::{self as msgs, NODE_NAME};
use parol6_core::telemetry::frames::TfFrames;
use serde_json::json;

pub use node::Ros2Options;

use super::{LiveServer, LiveSource};
use commands::{CommandCounters, Commands};
use publish::{PublishCounters, Telemetry};

/// The running ROS 2 node.
pub struct Ros2Server {
    node: Option<node::Node>,
    subscriber: Option<zenoh::pubsub::Subscriber<()>>,
    action: Option<action::ActionEndpoints>,
    description: Option<node::Publisher>,
    stop: Arc<AtomicBool>,
    threads: Vec<JoinHandle<()>>,
    publish: Arc<PublishCounters>,
    commands: Arc<CommandCounters>,
    address: String,
}

impl std::fmt::Debug for Ros2Server {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ros2Server").field("address", &self.address).finish_non_exhaustive()
    }
}

/// What the node serves, owned so that the session can be opened on another thread.
struct Parts {
    model: parol6_core::model::RobotModel,
    urdf_text: String,
    outlet: parol6_core::telemetry::LiveOutlet,
    remote: super::RemoteControl,
    backend: Arc<dyn parol6_core::motion::RobotBackend>,
}

impl Parts {
    fn of(source: &LiveSource<'_>) -> Result<Self, String> {
        let outlet = source
            .recorder
            .live_outlet(publish::OUTLET_CAPACITY)
            .map_err(|e| format!("cannot open the recorder's live outlet: {e}"))?;
        Ok(Self {
            model: source.model.clone(),
            urdf_text: source.urdf_text.to_string(),
            outlet,
            remote: source.remote.clone(),
            backend: Arc::clone(&source.backend),
        })
    }
}

/// A node being started on its own thread ([`Ros2Server::start_in_background`]): opening a
/// Zenoh session may wait on the network, which the window never does.
#[derive(Debug)]
pub struct PendingRos2 {
    rx: crossbeam_channel::Receiver<Result<Ros2Server, String>>,
}

impl PendingRos2 {
    /// The started node or why it failed, once the start is over (`None` while it goes on).
    pub fn try_take(&self) -> Option<Result<Ros2Server, String>> {
        match self.rx.try_recv() {
            Ok(result) => Some(result),
            Err(crossbeam_channel::TryRecvError::Empty) => None,
            Err(crossbeam_channel::TryRecvError::Disconnected) => {
                Some(Err("the ROS 2 start thread ended without a result".into()))
            }
        }
    }
}

impl Ros2Server {
    /// Opens the session, declares the node, its publishers and subscription, publishes the
    /// URDF and starts the publishing and command threads.
    pub fn start(source: &LiveSource<'_>, opts: &Ros2Options) -> Result<Self, String> {
        Self::start_parts(Parts::of(source)?, opts)
    }

    /// [`Ros2Server::start`] on a thread of its own: the recorder's outlet is opened here, the
    /// session there. A start dropped before it ends stops the node it made.
    pub fn start_in_background(source: &LiveSource<'_>, opts: &Ros2Options) -> Result<PendingRos2, String> {
        let parts = Parts::of(source)?;
        let opts = opts.clone();
        let (tx, rx) = crossbeam_channel::bounded(1);
        spawn("parol6-ros2-open", move || {
            let started = Self::start_parts(parts, &opts);
            if let Err(crossbeam_channel::TrySendError::Disconnected(Ok(server))) = tx.try_send(started) {
                // nobody waits any more: the node closes
                Box::new(server).stop();
            }
        })?;
        Ok(PendingRos2 { rx })
    }

    fn start_parts(parts: Parts, opts: &Ros2Options) -> Result<Self, String> {
        let mut node = node::Node::open(opts, NODE_NAME)?;
        let joint_states = node.publisher(msgs::TOPIC_JOINT_STATES, &msgs::JOINT_STATE, Qos::reliable(10))?;
        let tf = node.publisher(msgs::TOPIC_TF, &msgs::TF_MESSAGE, Qos::reliable(100))?;
        let description = node.publisher(msgs::TOPIC_ROBOT_DESCRIPTION, &msgs::STRING, Qos::LATCHED)?;
        let result = node.publisher(msgs::TOPIC_TRAJECTORY_RESULT, &msgs::STRING, Qos::reliable(10))?;
        let urdf = cdr::encode(&StringMsg { data: parts.urdf_text.clone() }).map_err(|e| e.to_string())?;
        description.put(urdf)?;

        let stop = Arc::new(AtomicBool::new(false));
        let commands = Arc::new(CommandCounters::default());
        let (tx, rx) = crossbeam_channel::bounded(commands::INBOX_CAPACITY);
        let subscriber = node.subscribe(
            msgs::TOPIC_JOINT_TRAJECTORY,
            &msgs::JOINT_TRAJECTORY,
            Qos::reliable(10),
            commands::on_sample(tx.clone(), Arc::clone(&commands)),
        )?;
        let (endpoints, action_state, feedback) = action::declare(&mut node, &opts.action_name, &tx, &commands)?;
        let publish = Arc::new(PublishCounters::default());
        let telemetry = Telemetry {
            frames: TfFrames::new(&parts.model, Some(&parts.urdf_text)),
            model: parts.model.clone(),
            joint_states,
            tf,
            feedback: Some((feedback, Arc::clone(&action_state.watch))),
        };
        let mut threads = Vec::new();
        let (s, p) = (Arc::clone(&stop), Arc::clone(&publish));
        let outlet = parts.outlet;
        threads.push(spawn("parol6-ros2-pub", move || publish::run(telemetry, outlet, s, p))?);
        let cmd = Commands {
            model: parts.model,
            backend: parts.backend,
            remote: parts.remote,
            result,
            counters: Arc::clone(&commands),
            action: Some(action_state),
        };
        let s = Arc::clone(&stop);
        threads.push(spawn("parol6-ros2-cmd", move || commands::run(cmd, rx, s))?);
        let address = format!(
            "zenoh peer {} (domain {}, action {}, connect {}, listen {})",
            node.identity.zid,
            opts.domain_id,
            opts.action_name,
            opts.connect.join(","),
            opts.listen.join(",")
        );
        Ok(Self {
            node: Some(node),
            subscriber: Some(subscriber),
            action: Some(endpoints),
            description: Some(description),
            stop,
            threads,
            publish,
            commands,
            address,
        })
    }

    fn counters(&self) -> serde_json::Value {
        let n = |a: &std::sync::atomic::AtomicU64| a.load(Ordering::Relaxed);
        json!({
            "joint_states_sent": n(&self.publish.joint_states),
            "tf_sent": n(&self.publish.tf),
            "action_feedback_sent": n(&self.publish.feedback),
            "samples_seen": n(&self.publish.samples),
            "samples_dropped": n(&self.publish.outlet_dropped),
            "publish_errors": n(&self.publish.errors),
            "trajectories_received": n(&self.commands.received),
            "trajectories_refused": n(&self.commands.refused),
            "trajectories_started": n(&self.commands.started),
            "trajectories_done": n(&self.commands.done),
            "trajectories_dropped": n(&self.commands.dropped),
        })
    }
}

fn spawn(name: &str, f: impl FnOnce() + Send + 'static) -> Result<JoinHandle<()>, String> {
    std::thread::Builder::new().name(name.into()).spawn(f).map_err(|e| format!("cannot start the {name} thread: {e}"))
}

impl LiveServer for Ros2Server {
    fn name(&self) -> &'static str {
        "ros2"
    }

    fn address(&self) -> String {
        self.address.clone()
    }

    fn stats(&self) -> serde_json::Value {
        self.counters()
    }

    fn stop(mut self: Box<Self>) -> serde_json::Value {
        self.stop.store(true, Ordering::Release);
        for t in self.threads.drain(..) {
            if t.join().is_err() {
                tracing::warn!("ROS 2: a server thread panicked");
            }
        }
        let out = self.counters();
        drop(self.subscriber.take());
        drop(self.action.take());
        drop(self.description.take());
        if let Some(node) = self.node.take()
            && let Err(e) = node.close()
        {
            tracing::warn!("ROS 2: {e}");
        }
        out
    }
}

impl Drop for Ros2Server {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Release);
    }
}
