//! The Foxglove WebSocket handshake's subprotocol names: one protocol under two names.
//!
//! Foxglove's WebSocket protocol was renamed: `foxglove.websocket.v1` (the `ws-protocol`
//! libraries, Lichtblick up to its 1.x releases of 2025, older Foxglove apps) became
//! `foxglove.sdk.v1` (the `foxglove` crate, Foxglove's current app), with the same messages.
//! These functions read and rename the `Sec-WebSocket-Protocol` headers of an HTTP upgrade
//! request and its answer, as text; the live server's front door (`parol6-app`'s
//! `live::foxglove`) does the socket work. Fuzzed by the `foxglove_handshake` target.

/// The longest HTTP head (request or answer) a reader of heads should accept.
pub const HEAD_MAX_BYTES: usize = 16 * 1024;

/// The header that carries the subprotocols, compared without case.
const PROTOCOL_HEADER: &str = "sec-websocket-protocol";

/// The protocol's former name, which Lichtblick 1.x and `@foxglove/ws-protocol` 0.7 offer.
pub const OLD_NAME: &str = "foxglove.websocket.v1";

/// The name the `foxglove` crate's server answers to for the same protocol.
pub const NEW_NAME: &str = "foxglove.sdk.v1";

/// Every name the crate's server answers to (a client offering one of them needs no renaming).
pub const SERVER_NAMES: [&str; 2] = [NEW_NAME, "foxglove.sdk.v1.1"];

/// Where the HTTP head in `buf` ends (just after its blank line), if it has ended.
pub fn head_end(buf: &[u8]) -> Option<usize> {
    buf.windows(4).position(|w| w == b"\r\n\r\n").map(|i| i + 4)
}

/// The value of `line` when it is a `Sec-WebSocket-Protocol` header.
fn protocol_value(line: &str) -> Option<&str> {
    let (name, value) = line.split_once(':')?;
    name.trim().eq_ignore_ascii_case(PROTOCOL_HEADER).then(|| value.trim())
}

/// The subprotocols a head offers or chooses, from every `Sec-WebSocket-Protocol` line.
pub fn subprotocols(head: &str) -> Vec<&str> {
    head.split("\r\n")
        .filter_map(protocol_value)
        .flat_map(|v| v.split(','))
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .collect()
}

/// `head` with each subprotocol token mapped by `rename` (other lines byte for byte).
fn map_subprotocols(head: &str, rename: impl Fn(&str) -> &str) -> String {
    head.split_inclusive("\r\n")
        .map(|line| match protocol_value(line.trim_end_matches("\r\n")) {
            Some(value) => {
                let tokens: Vec<&str> =
                    value.split(',').map(str::trim).filter(|t| !t.is_empty()).map(&rename).collect();
                format!("Sec-WebSocket-Protocol: {}\r\n", tokens.join(", "))
            }
            None => line.to_string(),
        })
        .collect()
}

/// The client's request head with an offer of only [`OLD_NAME`] renamed to [`NEW_NAME`];
/// `None` when it needs no renaming (it offers a name the server knows, or not the old one).
pub fn rename_request(head: &str) -> Option<String> {
    let offered = subprotocols(head);
    if offered.iter().any(|t| SERVER_NAMES.contains(t)) || !offered.contains(&OLD_NAME) {
        return None;
    }
    Some(map_subprotocols(head, |t| if t == OLD_NAME { NEW_NAME } else { t }))
}

/// The server's answer head with [`NEW_NAME`] given its old name back (for a renamed request).
pub fn rename_response(head: &str) -> String {
    map_subprotocols(head, |t| if t == NEW_NAME { OLD_NAME } else { t })
}

#[cfg(test)]
mod tests {
    use super::*;

    const LICHTBLICK: &str = "GET / HTTP/1.1\r\nHost: 127.0.0.1:8765\r\nUpgrade: websocket\r\n\
        Connection: Upgrade\r\nsec-websocket-protocol: foxglove.websocket.v1\r\n\
        Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";

    #[test]
    fn an_offer_of_only_the_old_name_is_renamed_and_the_answer_renamed_back() {
        let renamed = rename_request(LICHTBLICK).unwrap();
        assert_eq!(subprotocols(&renamed), [NEW_NAME]);
        // every other line byte for byte
        assert_eq!(
            renamed.replace("Sec-WebSocket-Protocol: foxglove.sdk.v1", ""),
            LICHTBLICK.replace("sec-websocket-protocol: foxglove.websocket.v1", "")
        );
        let answer = "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
            Sec-WebSocket-Accept: s3pPLMBiTxaQ9kYGzzhZRbK+xOo=\r\nSec-WebSocket-Protocol: foxglove.sdk.v1\r\n\r\n";
        let back = rename_response(answer);
        assert_eq!(subprotocols(&back), [OLD_NAME]);
        assert_eq!(head_end(back.as_bytes()), Some(back.len()));
    }

    #[test]
    fn offers_the_server_knows_or_without_the_old_name_pass_unchanged() {
        for offer in ["foxglove.sdk.v1, foxglove.websocket.v1", "foxglove.websocket.v1, foxglove.sdk.v1.1", "chat", ""]
        {
            let head = format!("GET / HTTP/1.1\r\nSec-WebSocket-Protocol: {offer}\r\n\r\n");
            assert_eq!(rename_request(&head), None, "{offer}");
        }
        assert_eq!(rename_request("GET / HTTP/1.1\r\nHost: x\r\n\r\n"), None);
    }

    #[test]
    fn offers_on_several_lines_and_other_tokens_are_kept() {
        let head = "GET / HTTP/1.1\r\nSec-WebSocket-Protocol: chat\r\nSEC-WEBSOCKET-PROTOCOL:foxglove.websocket.v1 , x\r\n\r\n";
        let renamed = rename_request(head).unwrap();
        assert_eq!(subprotocols(&renamed), ["chat", NEW_NAME, "x"]);
    }

    #[test]
    fn a_head_ends_at_its_blank_line() {
        assert_eq!(head_end(b"GET / HTTP/1.1\r\n\r\nabc"), Some(18));
        assert_eq!(head_end(b"GET / HTTP/1.1\r\n"), None);
    }
}
