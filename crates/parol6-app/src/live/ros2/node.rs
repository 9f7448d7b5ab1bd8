//! The Zenoh session as a ROS 2 node: its configuration (a peer connecting to a router,
//! listening on localhost, multicast scouting off), the node's liveliness token, and
//! publishers and subscriptions with their own tokens, key expressions and attachments, as
//! `rmw_zenoh` declares them. Zenoh is used synchronously (`.wait()`); nothing of its runtime
//! leaves this module tree.

use std::sync::atomic::{AtomicI64, Ordering};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use parol6_core::ros2::TypeInfo;
use parol6_core::ros2::graph::{Attachment, EntityKind, GID_BYTES, NodeIdentity, Qos, gid, topic_key};
use zenoh::Wait;
use zenoh::liveliness::LivelinessToken;
use zenoh::sample::Sample;
use zenoh_ext::{AdvancedPublisher, AdvancedPublisherBuilderExt, CacheConfig, MissDetectionConfig};

/// Where and how the session connects.
#[derive(Debug, Clone, PartialEq)]
pub struct Ros2Options {
    /// Zenoh endpoints to connect to (the router: `tcp/127.0.0.1:7447`).
    pub connect: Vec<String>,
    /// Endpoints to listen on, for peer-to-peer links from other nodes (`tcp/127.0.0.1:0`:
    /// this host only, a free port).
    pub listen: Vec<String>,
    /// UDP multicast scouting (off: the router introduces the peers, as rmw_zenoh does).
    pub multicast_scouting: bool,
    /// ROS domain id.
    pub domain_id: u32,
    /// The `FollowJointTrajectory` action's name.
    pub action_name: String,
}

impl Default for Ros2Options {
    fn default() -> Self {
        Self {
            connect: vec!["tcp/127.0.0.1:7447".into()],
            listen: vec!["tcp/127.0.0.1:0".into()],
            multicast_scouting: false,
            domain_id: 0,
            action_name: parol6_core::ros2::action::DEFAULT_ACTION_NAME.into(),
        }
    }
}

/// rmw_zenoh's heartbeat period of a reliable transient-local publisher, for late-sample
/// recovery.
const HEARTBEAT: Duration = Duration::from_millis(500);

fn json_list(items: &[String]) -> Result<String, String> {
    serde_json::to_string(items).map_err(|e| e.to_string())
}

/// The session's configuration (rmw_zenoh's session defaults where they matter).
pub fn config(opts: &Ros2Options) -> Result<zenoh::Config, String> {
    let mut c = zenoh::Config::default();
    let multicast = if opts.multicast_scouting { "true" } else { "false" };
    let entries = [
        ("mode", "\"peer\"".to_string()),
        ("connect/endpoints", json_list(&opts.connect)?),
        ("listen/endpoints", json_list(&opts.listen)?),
        ("scouting/multicast/enabled", multicast.to_string()),
        ("scouting/gossip/enabled", "true".to_string()),
        ("timestamping/enabled", "{ router: true, peer: true, client: false }".to_string()),
    ];
    for (key, value) in entries {
        c.insert_json5(key, &value).map_err(|e| format!("Zenoh configuration {key} = {value}: {e}"))?;
    }
    Ok(c)
}

/// The session and the node `parol6` in it.
pub struct Node {
    /// The Zenoh session.
    pub session: zenoh::Session,
    /// The node's names.
    pub identity: NodeIdentity,
    next_id: u32,
    tokens: Vec<LivelinessToken>,
}

impl std::fmt::Debug for Node {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Node").field("identity", &self.identity).finish_non_exhaustive()
    }
}

/// A publisher: its Zenoh publisher (with a cache when transient local), GID and sequence.
pub struct Publisher {
    sink: Sink,
    gid: [u8; GID_BYTES],
    seq: AtomicI64,
    /// Its data key expression.
    pub key: String,
}

enum Sink {
    Plain(zenoh::pubsub::Publisher<'static>),
    Cached(AdvancedPublisher<'static>),
}

impl Node {
    /// Opens the session and declares the node `name` (its liveliness token).
    pub fn open(opts: &Ros2Options, name: &str) -> Result<Self, String> {
        let session = zenoh::open(config(opts)?).wait().map_err(|e| format!("cannot open the Zenoh session: {e}"))?;
        let identity =
            NodeIdentity { domain_id: opts.domain_id, zid: session.zid().to_string(), node_id: 0, name: name.into() };
        let mut node = Self { session, identity, next_id: 1, tokens: Vec::new() };
        let token = node.identity.node_token();
        node.declare_token(&token)?;
        Ok(node)
    }

    fn declare_token(&mut self, key: &str) -> Result<(), String> {
        let token = self
            .session
            .liveliness()
            .declare_token(key.to_string())
            .wait()
            .map_err(|e| format!("cannot declare the liveliness token {key}: {e}"))?;
        self.tokens.push(token);
        Ok(())
    }

    /// Declares a publisher of `ty` on `topic` (transient local: a cache of `qos.depth`
    /// samples that late subscribers query, as rmw_zenoh's advanced publisher has).
    pub fn publisher(&mut self, topic: &str, ty: &TypeInfo, qos: Qos) -> Result<Publisher, String> {
        let key = topic_key(self.identity.domain_id, topic, ty);
        let id = self.next_id;
        self.next_id += 1;
        let token = self.identity.topic_token(id, EntityKind::Publisher, topic, ty, &qos);
        let fail = |e: zenoh::Error| format!("cannot declare the publisher {key}: {e}");
        let builder = self.session.declare_publisher(key.clone());
        let sink = if qos.transient_local {
            let depth = usize::try_from(qos.depth).unwrap_or(1).max(1);
            Sink::Cached(
                builder
                    .cache(CacheConfig::default().max_samples(depth))
                    .publisher_detection()
                    .sample_miss_detection(MissDetectionConfig::default().sporadic_heartbeat(HEARTBEAT))
                    .wait()
                    .map_err(fail)?,
            )
        } else {
            Sink::Plain(builder.wait().map_err(fail)?)
        };
        self.declare_token(&token)?;
        Ok(Publisher { sink, gid: gid(&token), seq: AtomicI64::new(1), key })
    }

    /// Declares a subscription of `ty` on `topic`; `on_sample` runs on Zenoh's thread for each
    /// sample (it must not block).
    pub fn subscribe(
        &mut self,
        topic: &str,
        ty: &TypeInfo,
        qos: Qos,
        on_sample: impl Fn(Sample) + Send + Sync + 'static,
    ) -> Result<zenoh::pubsub::Subscriber<()>, String> {
        let key = topic_key(self.identity.domain_id, topic, ty);
        let id = self.next_id;
        self.next_id += 1;
        let token = self.identity.topic_token(id, EntityKind::Subscription, topic, ty, &qos);
        let sub = self
            .session
            .declare_subscriber(key.clone())
            .callback(on_sample)
            .wait()
            .map_err(|e| format!("cannot subscribe to {key}: {e}"))?;
        self.declare_token(&token)?;
        Ok(sub)
    }

    /// Declares a service server of `ty` on `service` (a queryable on its key expression, with
    /// an `SS` token and the services' QoS, reliable keep-last 10); `on_query` runs on Zenoh's
    /// thread for each request (it must not block: a query may be answered later, from
    /// another thread).
    pub fn service(
        &mut self,
        service: &str,
        ty: &TypeInfo,
        on_query: impl Fn(zenoh::query::Query) + Send + Sync + 'static,
    ) -> Result<zenoh::query::Queryable<()>, String> {
        let key = topic_key(self.identity.domain_id, service, ty);
        let id = self.next_id;
        self.next_id += 1;
        let token = self.identity.topic_token(id, EntityKind::ServiceServer, service, ty, &Qos::reliable(10));
        let queryable = self
            .session
            .declare_queryable(key.clone())
            .complete(true)
            .callback(on_query)
            .wait()
            .map_err(|e| format!("cannot declare the service {key}: {e}"))?;
        self.declare_token(&token)?;
        Ok(queryable)
    }

    /// Undeclares the tokens (the node leaves the ROS graph) and closes the session.
    pub fn close(self) -> Result<(), String> {
        for t in self.tokens {
            t.undeclare().wait().map_err(|e| format!("cannot undeclare a liveliness token: {e}"))?;
        }
        self.session.close().wait().map_err(|e| format!("cannot close the Zenoh session: {e}"))
    }
}

/// Nanoseconds since the Unix epoch now.
pub fn now_unix_ns() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX))
}

/// Answers a service request with `payload` (CDR), its attachment carrying the request's
/// sequence number and client GID (a request without a readable attachment is answered with
/// sequence number 0 and a zero GID), as rmw_zenoh's service servers answer.
pub fn reply(query: &zenoh::query::Query, payload: Vec<u8>) -> Result<(), String> {
    let request = query.attachment().and_then(|a| Attachment::from_bytes(&a.to_bytes()));
    let attachment = Attachment {
        sequence_number: request.map_or(0, |a| a.sequence_number),
        source_timestamp_ns: i64::try_from(now_unix_ns()).unwrap_or(i64::MAX),
        source_gid: request.map_or([0; GID_BYTES], |a| a.source_gid),
    };
    query
        .reply(query.key_expr().clone(), payload)
        .attachment(attachment.to_bytes().to_vec())
        .wait()
        .map_err(|e| format!("cannot answer the request on {}: {e}", query.key_expr()))
}

impl Publisher {
    /// Publishes one CDR payload with its attachment (sequence number, time stamp, GID).
    pub fn put(&self, payload: Vec<u8>) -> Result<(), String> {
        let attachment = Attachment {
            sequence_number: self.seq.fetch_add(1, Ordering::Relaxed),
            source_timestamp_ns: i64::try_from(now_unix_ns()).unwrap_or(i64::MAX),
            source_gid: self.gid,
        }
        .to_bytes()
        .to_vec();
        let done = match &self.sink {
            Sink::Plain(p) => p.put(payload).attachment(attachment).wait(),
            Sink::Cached(p) => p.put(payload).attachment(attachment).wait(),
        };
        done.map_err(|e| format!("cannot publish on {}: {e}", self.key))
    }
}

#[cfg(test)]
mod tests {
    use parol6_core::ros2::graph::Attachment;

    /// Our attachment bytes are what Zenoh's own serializer makes of `(i64, i64, [u8; 16])`,
    /// the layout rmw_zenoh reads.
    #[test]
    fn the_attachment_is_zenohs_serialization_of_seq_time_and_gid() {
        let a = Attachment { sequence_number: 42, source_timestamp_ns: -7, source_gid: *b"0123456789abcdef" };
        let theirs = zenoh_ext::z_serialize(&(42i64, -7i64, *b"0123456789abcdef"));
        assert_eq!(theirs.to_bytes().as_ref(), a.to_bytes().as_slice());
    }

    #[test]
    fn the_configuration_connects_to_the_router_and_listens_on_localhost() {
        let c = super::config(&super::Ros2Options::default()).unwrap();
        let text = format!("{c}");
        assert!(text.contains("tcp/127.0.0.1:7447"), "{text}");
        assert!(text.contains("tcp/127.0.0.1:0"), "{text}");
    }
}
