//! The Foxglove server's front door: one protocol under its two names.
//!
//! The `foxglove` crate's server answers only `foxglove.sdk.v1`; a client that offers only the
//! protocol's former name `foxglove.websocket.v1` (Lichtblick 1.x, `@foxglove/ws-protocol` 0.7,
//! older Foxglove apps) got HTTP 400. The front listens at the public address. For each
//! connection it reads the client's HTTP upgrade request (at most [`HEAD_MAX_BYTES`], within
//! [`HEAD_TIMEOUT`]), renames an offer of **only** the old name to the new one
//! ([`rename_request`]), forwards it to the crate's server on a loopback port, gives the chosen
//! subprotocol its old name back in the answer ([`rename_response`]), and then copies bytes both
//! ways unchanged. A client that offers a new name, or neither, is passed through as it is.
//!
//! Memory per client: two copy buffers (8 kB each) and one more pair of loopback socket
//! buffers; a client that reads slowly holds back the relay, so the crate's server still thins
//! its queue. At most [`MAX_CONNECTIONS`] connections are relayed at once; more are answered
//! `503`.

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use parol6_core::telemetry::handshake::{HEAD_MAX_BYTES, head_end, rename_request, rename_response};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};

/// How long a client (or the server) may take to send its HTTP head.
pub const HEAD_TIMEOUT: Duration = Duration::from_secs(5);

/// Connections relayed at once.
pub const MAX_CONNECTIONS: usize = 64;

/// Why one connection was not relayed.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum FrontError {
    /// The head did not end within [`HEAD_MAX_BYTES`].
    #[error("its HTTP head is longer than {HEAD_MAX_BYTES} bytes")]
    HeadTooLong,
    /// The peer closed before the head ended.
    #[error("it closed the connection before its HTTP head ended")]
    Closed,
    /// No whole head within [`HEAD_TIMEOUT`].
    #[error("no HTTP head within {} s", HEAD_TIMEOUT.as_secs())]
    Timeout,
    /// The head is not text.
    #[error("its HTTP head is not UTF-8 text")]
    NotText,
    /// A socket error.
    #[error("{0}")]
    Io(String),
}

impl From<std::io::Error> for FrontError {
    fn from(e: std::io::Error) -> Self {
        Self::Io(e.to_string())
    }
}

/// An HTTP head read from a peer, and the bytes that came after it in the same reads.
struct Head {
    text: String,
    rest: Vec<u8>,
}

/// Reads one HTTP head from `peer`, within [`HEAD_TIMEOUT`].
async fn read_head(peer: &mut TcpStream) -> Result<Head, FrontError> {
    let read = async {
        let mut buf = Vec::with_capacity(1024);
        let mut chunk = [0_u8; 2048];
        loop {
            if let Some(end) = head_end(&buf) {
                let rest = buf.split_off(end);
                let text = String::from_utf8(buf).map_err(|_| FrontError::NotText)?;
                return Ok(Head { text, rest });
            }
            if buf.len() > HEAD_MAX_BYTES {
                return Err(FrontError::HeadTooLong);
            }
            let n = peer.read(&mut chunk).await?;
            if n == 0 {
                return Err(FrontError::Closed);
            }
            buf.extend_from_slice(&chunk[..n]);
        }
    };
    tokio::time::timeout(HEAD_TIMEOUT, read).await.unwrap_or(Err(FrontError::Timeout))
}

/// Answers `status` with a one-line reason and closes.
async fn refuse(client: &mut TcpStream, status: &str, why: &str) {
    let answer = format!(
        "HTTP/1.1 {status}\r\nConnection: close\r\nContent-Type: text/plain\r\nContent-Length: {}\r\n\r\n{why}",
        why.len()
    );
    if let Err(e) = client.write_all(answer.as_bytes()).await {
        tracing::debug!("Foxglove front: the refusal did not reach the client: {e}");
    }
}

/// Relays one client to the server at `inner`.
async fn relay(mut client: TcpStream, inner: SocketAddr) -> Result<(), FrontError> {
    client.set_nodelay(true)?;
    let request = match read_head(&mut client).await {
        Ok(r) => r,
        Err(e) => {
            refuse(&mut client, "400 Bad Request", &e.to_string()).await;
            return Err(e);
        }
    };
    let renamed = rename_request(&request.text);
    let mut server = match TcpStream::connect(inner).await {
        Ok(s) => s,
        Err(e) => {
            refuse(&mut client, "503 Service Unavailable", "the Foxglove server is not running").await;
            return Err(e.into());
        }
    };
    server.set_nodelay(true)?;
    server.write_all(renamed.as_deref().unwrap_or(&request.text).as_bytes()).await?;
    server.write_all(&request.rest).await?;
    let answer = read_head(&mut server).await?;
    let answer_text = if renamed.is_some() { rename_response(&answer.text) } else { answer.text };
    client.write_all(answer_text.as_bytes()).await?;
    client.write_all(&answer.rest).await?;
    // a peer that goes away ends the relay; that is how connections end, not an error
    if let Err(e) = tokio::io::copy_bidirectional(&mut client, &mut server).await {
        tracing::debug!("Foxglove front: relay ended: {e}");
    }
    Ok(())
}

/// Counts a relayed connection while it lives.
struct Slot(Arc<AtomicUsize>);

impl Drop for Slot {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::AcqRel);
    }
}

/// Accepts clients at `listener` and relays each to the crate's server at `inner`, until the
/// runtime stops (or the task is aborted).
pub async fn serve(listener: TcpListener, inner: SocketAddr) {
    let open = Arc::new(AtomicUsize::new(0));
    loop {
        let (mut client, peer) = match listener.accept().await {
            Ok(c) => c,
            Err(e) => {
                // e.g. out of file descriptors: wait instead of spinning
                tracing::warn!("Foxglove front: cannot accept a connection: {e}");
                tokio::time::sleep(Duration::from_millis(100)).await;
                continue;
            }
        };
        if open.fetch_add(1, Ordering::AcqRel) >= MAX_CONNECTIONS {
            open.fetch_sub(1, Ordering::AcqRel);
            tracing::warn!("Foxglove front: refused {peer}: {MAX_CONNECTIONS} connections are open");
            tokio::spawn(async move {
                refuse(&mut client, "503 Service Unavailable", "too many connections").await;
            });
            continue;
        }
        let slot = Slot(Arc::clone(&open));
        tokio::spawn(async move {
            let _slot = slot;
            if let Err(e) = relay(client, inner).await {
                tracing::warn!("Foxglove: client {peer} not connected: {e}");
            }
        });
    }
}
