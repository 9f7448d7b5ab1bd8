//! Fuzz body `foxglove_handshake` (issue 30): any bytes as the HTTP head of a WebSocket upgrade
//! request, through the renaming of the Foxglove subprotocol that lets Lichtblick 1.x in
//! (`parol6_core::telemetry::handshake`). Nothing panics; a request is renamed exactly when it
//! offers the old name and none the server knows; a renamed request offers the server's name
//! in the old one's place and keeps every other line; the answer renamed back gives the
//! client the tokens it offered.

use parol6_core::telemetry::handshake::{
    NEW_NAME, OLD_NAME, SERVER_NAMES, head_end, rename_request, rename_response, subprotocols,
};

/// The lines of `head` that are not `Sec-WebSocket-Protocol` headers.
fn other_lines(head: &str) -> Vec<&str> {
    head.split("\r\n")
        .filter(|l| !l.split_once(':').is_some_and(|(n, _)| n.trim().eq_ignore_ascii_case("sec-websocket-protocol")))
        .filter(|l| !l.is_empty())
        .collect()
}

/// See the module docs.
pub fn foxglove_handshake(data: &[u8]) {
    if let Some(end) = head_end(data) {
        assert!(end >= 4 && end <= data.len() && data[..end].ends_with(b"\r\n\r\n"));
    }
    let head = String::from_utf8_lossy(data);
    let offered = subprotocols(&head);
    let wants_renaming = offered.contains(&OLD_NAME) && !offered.iter().any(|t| SERVER_NAMES.contains(t));
    let Some(renamed) = rename_request(&head) else {
        assert!(!wants_renaming, "an offer of only the old name was not renamed: {offered:?}");
        return;
    };
    assert!(wants_renaming, "renamed an offer that needs none: {offered:?}");
    let now = subprotocols(&renamed);
    assert_eq!(now.len(), offered.len(), "{offered:?} -> {now:?}");
    assert!(now.contains(&NEW_NAME) && !now.contains(&OLD_NAME), "{now:?}");
    assert_eq!(other_lines(&renamed), other_lines(&head));
    assert_eq!(subprotocols(&rename_response(&renamed)), offered);
}
