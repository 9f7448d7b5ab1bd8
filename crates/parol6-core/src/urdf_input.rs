//! Bounds on URDF text before it reaches the XML parser.
//!
//! The URDF parser (`urdf-rs` over RustyXML and serde-xml-rs) walks the element tree
//! recursively: a file of 50 000 nested elements (350 KB) overflows the stack and aborts the
//! whole program. Every URDF passes [`check_urdf_input`] first: a byte size limit
//! ([`MAX_URDF_BYTES`]) and a limit on how deep elements nest ([`MAX_URDF_NESTING_DEPTH`]),
//! measured by a single non-recursive scan that understands quoted attribute values,
//! comments, CDATA sections, processing instructions, declarations and self-closing tags.
//! A real robot description nests fewer than 10 levels (robot → link → visual → geometry →
//! mesh is 5).
//!
//! The scan never counts fewer levels than an XML parser sees: text it cannot read as XML is
//! counted as opening an element, and the parser then reports the syntax error.

/// Largest URDF accepted, in bytes (8 MiB; the PAROL6 description is about 10 KB).
pub const MAX_URDF_BYTES: usize = 8 * 1024 * 1024;

/// Deepest element nesting accepted (a real URDF nests fewer than 10 levels).
pub const MAX_URDF_NESTING_DEPTH: usize = 64;

/// Why a URDF text was refused before parsing. Each names the limit and where it was passed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum UrdfInputError {
    /// The text is larger than [`MAX_URDF_BYTES`].
    #[error("URDF refused: it is {size_bytes} bytes, the limit is {limit_bytes} bytes (8 MiB)")]
    TooLarge {
        /// Size of the text.
        size_bytes: usize,
        /// The limit, [`MAX_URDF_BYTES`].
        limit_bytes: usize,
    },
    /// Elements nest deeper than [`MAX_URDF_NESTING_DEPTH`].
    #[error(
        "URDF refused: elements nest deeper than {limit_depth} levels at line {line}, column {column} \
         (a robot description nests fewer than 10)"
    )]
    TooDeep {
        /// 1-based line of the start tag that passed the limit.
        line: usize,
        /// 1-based column (in characters) of that tag's `<`.
        column: usize,
        /// The limit, [`MAX_URDF_NESTING_DEPTH`].
        limit_depth: usize,
    },
}

/// Refuses URDF text that is too large or nests too deep for the parser to handle safely.
pub fn check_urdf_input(xml: &str) -> Result<(), UrdfInputError> {
    if xml.len() > MAX_URDF_BYTES {
        return Err(UrdfInputError::TooLarge { size_bytes: xml.len(), limit_bytes: MAX_URDF_BYTES });
    }
    match first_tag_deeper_than(xml.as_bytes(), MAX_URDF_NESTING_DEPTH) {
        None => Ok(()),
        Some(offset) => {
            let (line, column) = line_and_column(xml, offset);
            Err(UrdfInputError::TooDeep { line, column, limit_depth: MAX_URDF_NESTING_DEPTH })
        }
    }
}

/// Deepest element nesting of `xml` as the scan counts it (an upper bound of what an XML
/// parser sees).
pub fn xml_nesting_depth(xml: &str) -> usize {
    let mut deepest = 0;
    scan_tags(xml.as_bytes(), |depth, _| {
        deepest = deepest.max(depth);
        false
    });
    deepest
}

/// Byte offset of the first start tag that takes the nesting past `limit`, if any.
fn first_tag_deeper_than(bytes: &[u8], limit: usize) -> Option<usize> {
    let mut found = None;
    scan_tags(bytes, |depth, offset| {
        if depth > limit {
            found = Some(offset);
            true
        } else {
            false
        }
    });
    found
}

/// Walks the markup once, calling `on_open(depth, offset)` after each start tag that opens an
/// element (depth counts that element; `offset` is its `<`). Stops when `on_open` returns true
/// or at an unterminated construct (the parser reports that one).
fn scan_tags(bytes: &[u8], mut on_open: impl FnMut(usize, usize) -> bool) {
    let mut depth = 0usize;
    let mut i = 0;
    while let Some(rel) = find_byte(&bytes[i..], b'<') {
        let start = i + rel;
        let rest = &bytes[start..];
        let end = if rest.starts_with(b"<!--") {
            find_seq(bytes, start + 4, b"-->").map(|e| e + 3)
        } else if rest.starts_with(b"<![CDATA[") {
            find_seq(bytes, start + 9, b"]]>").map(|e| e + 3)
        } else if rest.starts_with(b"<?") {
            find_seq(bytes, start + 2, b"?>").map(|e| e + 2)
        } else if rest.starts_with(b"<!") {
            declaration_end(bytes, start + 2)
        } else if rest.starts_with(b"</") {
            depth = depth.saturating_sub(1);
            find_byte(&bytes[start..], b'>').map(|e| start + e + 1)
        } else {
            let end = start_tag_end(bytes, start + 1);
            let self_closing = end.is_some_and(|e| e >= 2 && bytes[e - 2] == b'/');
            if !self_closing {
                depth += 1;
                if on_open(depth, start) {
                    return;
                }
            }
            end
        };
        match end {
            Some(e) => i = e,
            None => return,
        }
    }
}

/// Index just past the `>` closing a start tag whose name begins at `from`, skipping quoted
/// attribute values.
fn start_tag_end(bytes: &[u8], from: usize) -> Option<usize> {
    let mut quote: Option<u8> = None;
    for (k, &b) in bytes.iter().enumerate().skip(from) {
        match quote {
            Some(q) if b == q => quote = None,
            Some(_) => {}
            None if b == b'"' || b == b'\'' => quote = Some(b),
            None if b == b'>' => return Some(k + 1),
            None => {}
        }
    }
    None
}

/// Index just past the `>` closing a `<!…>` declaration (DOCTYPE with an internal subset in
/// `[…]`, quoted literals and nested declarations or comments included).
fn declaration_end(bytes: &[u8], from: usize) -> Option<usize> {
    let mut k = from;
    let mut open_angles = 0usize;
    let mut quote: Option<u8> = None;
    while k < bytes.len() {
        let b = bytes[k];
        if let Some(q) = quote {
            if b == q {
                quote = None;
            }
        } else if bytes[k..].starts_with(b"<!--") {
            k = find_seq(bytes, k + 4, b"-->")? + 3;
            continue;
        } else {
            match b {
                b'"' | b'\'' => quote = Some(b),
                b'<' => open_angles += 1,
                b'>' if open_angles == 0 => return Some(k + 1),
                b'>' => open_angles -= 1,
                _ => {}
            }
        }
        k += 1;
    }
    None
}

fn find_byte(haystack: &[u8], needle: u8) -> Option<usize> {
    haystack.iter().position(|&b| b == needle)
}

/// Start index of `needle` in `bytes` at or after `from`.
fn find_seq(bytes: &[u8], from: usize, needle: &[u8]) -> Option<usize> {
    bytes.get(from..)?.windows(needle.len()).position(|w| w == needle).map(|p| from + p)
}

/// 1-based line and character column of byte `offset` (a `<`, so a char boundary).
fn line_and_column(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset).unwrap_or(text);
    let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |p| p + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

#[cfg(test)]
mod tests;
