//! `rmw_zenoh`'s names for things (its Jazzy conventions, `rmw_zenoh_cpp/src/detail/
//! liveliness_utils.cpp` and `attachment_helpers.cpp`):
//!
//! - a topic's data key expression: `<domain>/<topic without its leading slash>/<DDS type
//!   name>/<RIHS01 hash>`, e.g. `0/joint_states/sensor_msgs::msg::dds_::JointState_/RIHS01_a13e…`;
//! - a liveliness token per entity: `@ros2_lv/<domain>/<session zid>/<node id>/<entity id>/<NN |
//!   MP | MS | SS | SC>/<enclave>/<namespace>/<node name>`, and for a publisher or subscription
//!   `/<topic>/<DDS type name>/<hash>/<QoS>`, every `/` inside a name written `%` (the root
//!   namespace and enclave are `%`);
//! - the QoS string: `reliability:durability:history,depth:deadline s,ns:lifespan s,ns:
//!   liveliness,lease s,ns`, each left empty where it equals `rmw_zenoh`'s default (reliable,
//!   volatile, keep-last 42, infinite durations, automatic liveliness);
//! - an entity's GID: XXH3-128 of its liveliness key expression (low 64 bits, then high, both
//!   little-endian);
//! - the attachment of every sample, in Zenoh's serialization format: the sequence number
//!   (`int64`, from 1), the source time stamp (`int64`, ns since the Unix epoch) and the GID
//!   (a 16-byte array: its LEB128 length `0x10`, then the bytes), 33 bytes.

/// Prefix of every liveliness token.
pub const ADMIN_SPACE: &str = "@ros2_lv";
/// Size of a GID, bytes.
pub const GID_BYTES: usize = 16;
/// Size of an attachment, bytes.
pub const ATTACHMENT_BYTES: usize = 8 + 8 + 1 + GID_BYTES;

/// What an entity is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EntityKind {
    /// A node (`NN`).
    Node,
    /// A publisher (`MP`).
    Publisher,
    /// A subscription (`MS`).
    Subscription,
    /// A service server (`SS`): a queryable on the service's key expression.
    ServiceServer,
}

impl EntityKind {
    /// Its two letters in a token.
    pub fn code(self) -> &'static str {
        match self {
            EntityKind::Node => "NN",
            EntityKind::Publisher => "MP",
            EntityKind::Subscription => "MS",
            EntityKind::ServiceServer => "SS",
        }
    }
}

/// The QoS of a publisher or subscription, as far as a token tells it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Qos {
    /// Reliable (else best effort).
    pub reliable: bool,
    /// Transient local (late joiners get the last `depth` samples), else volatile.
    pub transient_local: bool,
    /// Keep-last depth.
    pub depth: u32,
}

impl Qos {
    /// Reliable, volatile, keep last `depth` (`rclcpp`'s default with depth 10).
    pub const fn reliable(depth: u32) -> Self {
        Self { reliable: true, transient_local: false, depth }
    }

    /// Reliable, transient local, keep last 1 (`robot_state_publisher`'s `/robot_description`).
    pub const LATCHED: Self = Self { reliable: true, transient_local: true, depth: 1 };

    /// Its token form, e.g. `::,10:,:,:,,` (reliable volatile depth 10) or `:1:,1:,:,:,,`.
    pub fn token(&self) -> String {
        // rmw's enum values: reliability 1 reliable / 2 best effort, durability 1 transient
        // local / 2 volatile; defaults (reliable, volatile, depth 42) are left out
        let reliability = if self.reliable { "" } else { "2" };
        let durability = if self.transient_local { "1" } else { "" };
        let depth = if self.depth == 42 { String::new() } else { self.depth.to_string() };
        format!("{reliability}:{durability}:,{depth}:,:,:,,")
    }
}

/// The node this program declares.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeIdentity {
    /// ROS domain id.
    pub domain_id: u32,
    /// The Zenoh session's id, as Zenoh prints it.
    pub zid: String,
    /// The node's entity id within the session.
    pub node_id: u32,
    /// Node name.
    pub name: String,
}

/// A name with every `/` written `%` (`/` alone, the root namespace, becomes `%`).
pub fn mangle(name: &str) -> String {
    name.replace('/', "%")
}

/// The data key expression of `topic` (e.g. `/joint_states`) of type `ty` in `domain_id`; a
/// service's (its queryable's) has the same form, with the service type.
pub fn topic_key(domain_id: u32, topic: &str, ty: &super::TypeInfo) -> String {
    let name = topic.trim_matches('/');
    format!("{domain_id}/{name}/{}/{}", ty.dds_name, ty.hash)
}

impl NodeIdentity {
    /// The node's liveliness token.
    pub fn node_token(&self) -> String {
        self.token_head(self.node_id, EntityKind::Node)
    }

    /// The liveliness token of publisher, subscription or service server `entity_id` on
    /// `topic` (a service's name for a server).
    pub fn topic_token(
        &self,
        entity_id: u32,
        kind: EntityKind,
        topic: &str,
        ty: &super::TypeInfo,
        qos: &Qos,
    ) -> String {
        format!("{}/{}/{}/{}/{}", self.token_head(entity_id, kind), mangle(topic), ty.dds_name, ty.hash, qos.token())
    }

    fn token_head(&self, entity_id: u32, kind: EntityKind) -> String {
        format!(
            "{ADMIN_SPACE}/{}/{}/{}/{entity_id}/{}/%/%/{}",
            self.domain_id,
            self.zid,
            self.node_id,
            kind.code(),
            mangle(&self.name)
        )
    }
}

/// The GID of the entity whose liveliness token is `token`.
pub fn gid(token: &str) -> [u8; GID_BYTES] {
    let h = xxhash_rust::xxh3::xxh3_128(token.as_bytes());
    let mut out = [0; GID_BYTES];
    out[..8].copy_from_slice(&(h as u64).to_le_bytes());
    out[8..].copy_from_slice(&((h >> 64) as u64).to_le_bytes());
    out
}

/// A sample's attachment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Attachment {
    /// Sequence number of the publisher's samples, from 1.
    pub sequence_number: i64,
    /// When it was published, ns since the Unix epoch.
    pub source_timestamp_ns: i64,
    /// The publisher's GID.
    pub source_gid: [u8; GID_BYTES],
}

impl Attachment {
    /// Its bytes (Zenoh's serialization of `(i64, i64, [u8; 16])`).
    pub fn to_bytes(&self) -> [u8; ATTACHMENT_BYTES] {
        let mut out = [0; ATTACHMENT_BYTES];
        out[..8].copy_from_slice(&self.sequence_number.to_le_bytes());
        out[8..16].copy_from_slice(&self.source_timestamp_ns.to_le_bytes());
        out[16] = GID_BYTES as u8;
        out[17..].copy_from_slice(&self.source_gid);
        out
    }

    /// Reads one (`None` unless it is exactly that layout).
    pub fn from_bytes(bytes: &[u8]) -> Option<Self> {
        let b: &[u8; ATTACHMENT_BYTES] = bytes.try_into().ok()?;
        if usize::from(b[16]) != GID_BYTES {
            return None;
        }
        let mut seq = [0; 8];
        seq.copy_from_slice(&b[..8]);
        let mut ts = [0; 8];
        ts.copy_from_slice(&b[8..16]);
        let mut source_gid = [0; GID_BYTES];
        source_gid.copy_from_slice(&b[17..]);
        Some(Self { sequence_number: i64::from_le_bytes(seq), source_timestamp_ns: i64::from_le_bytes(ts), source_gid })
    }
}
