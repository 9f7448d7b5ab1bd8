//! The Foxglove WebSocket server (skeleton: filled in next).

use std::net::SocketAddr;

use super::{LiveServer, LiveSource};

/// The Foxglove WebSocket server.
#[derive(Debug)]
pub struct FoxgloveServer {
    addr: SocketAddr,
}

impl FoxgloveServer {
    /// Starts it on `source` at `addr`.
    pub fn start(_source: &LiveSource<'_>, addr: SocketAddr) -> Result<Self, String> {
        Err(format!("the Foxglove server at {addr} is not built yet"))
    }
}

impl LiveServer for FoxgloveServer {
    fn name(&self) -> &'static str {
        "foxglove"
    }
    fn address(&self) -> String {
        format!("ws://{}", self.addr)
    }
    fn stats(&self) -> serde_json::Value {
        serde_json::json!({})
    }
    fn stop(self: Box<Self>) -> serde_json::Value {
        self.stats()
    }
}
