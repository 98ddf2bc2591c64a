//! The raw text of an `.osim` file before XML parsing: character encoding (UTF-8, or
//! ISO-8859-1 when the XML declaration says so) and a bound on element nesting, so that a
//! hostile file gets an error naming its line instead of exhausting the parser's stack.

use super::OsimError;

/// Deepest element nesting accepted in an `.osim` file (OpenSim models nest about 12
/// levels; the bound keeps the recursive XML parser far from the end of its stack).
pub const MAX_XML_DEPTH: usize = 1000;

/// The text of an `.osim` file from its bytes: UTF-8, or ISO-8859-1 (Latin-1) /
/// windows-1252 when the XML declaration declares it; anything else that is not valid UTF-8
/// is an error naming the line of the first invalid byte.
pub(crate) fn decode(bytes: &[u8], source_name: &str) -> Result<String, OsimError> {
    match std::str::from_utf8(bytes) {
        Ok(s) => Ok(s.to_string()),
        Err(e) => {
            let encoding = declared_encoding(bytes).unwrap_or_default();
            if matches!(
                encoding.to_ascii_lowercase().as_str(),
                "iso-8859-1" | "latin1" | "latin-1" | "iso_8859-1" | "windows-1252" | "cp1252"
            ) {
                return Ok(bytes.iter().map(|&b| b as char).collect());
            }
            let at = e.valid_up_to();
            let line = 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count();
            let column = 1 + at
                - bytes[..at]
                    .iter()
                    .rposition(|&b| b == b'\n')
                    .map_or(0, |p| p + 1);
            let declared = if encoding.is_empty() {
                "no encoding declared, so UTF-8 is required".to_string()
            } else {
                format!("declared encoding `{encoding}` is not supported (UTF-8, ISO-8859-1)")
            };
            Err(OsimError::Xml {
                source_name: source_name.to_string(),
                line,
                column,
                message: format!("byte 0x{:02x} is not valid UTF-8 ({declared})", bytes[at]),
            })
        }
    }
}

/// The `encoding` of the XML declaration (`<?xml version="1.0" encoding="..."?>`), if any.
fn declared_encoding(bytes: &[u8]) -> Option<String> {
    let head = &bytes[..bytes.len().min(200)];
    let head: String = head.iter().map(|&b| b as char).collect();
    let decl = head.trim_start_matches('\u{feff}').trim_start();
    let decl = &decl[..decl.find("?>")?];
    if !decl.starts_with("<?xml") {
        return None;
    }
    let rest = &decl[decl.find("encoding")? + "encoding".len()..];
    let rest = rest.trim_start().strip_prefix('=')?.trim_start();
    let quote = rest.chars().next().filter(|c| *c == '"' || *c == '\'')?;
    let value = &rest[1..];
    Some(value[..value.find(quote)?].to_string())
}

/// Check that elements nest at most `max_depth` deep, counting the markup of entity
/// declarations as if it were written in place (so entity expansion cannot nest deeper than
/// a bounded multiple). The scan is lenient about malformed markup: the XML parser reports
/// that afterwards.
pub(crate) fn check_depth(
    text: &str,
    max_depth: usize,
    source_name: &str,
) -> Result<(), OsimError> {
    let b = text.as_bytes();
    let (mut i, mut depth) = (0usize, 0usize);
    let skip_to = |from: usize, end: &[u8]| -> usize {
        find(&b[from..], end).map_or(b.len(), |p| from + p + end.len())
    };
    while i < b.len() {
        match b[i] {
            b'<' if b[i..].starts_with(b"<!--") => i = skip_to(i + 4, b"-->"),
            b'<' if b[i..].starts_with(b"<![CDATA[") => i = skip_to(i + 9, b"]]>"),
            b'<' if b[i..].starts_with(b"<?") => i = skip_to(i + 2, b"?>"),
            b'<' if b[i..].starts_with(b"<!") => i += 2,
            b'<' if b[i..].starts_with(b"</") => {
                depth = depth.saturating_sub(1);
                i += 2;
            }
            b'<' => {
                let end = tag_end(b, i + 1);
                if b.get(end.wrapping_sub(1)) != Some(&b'/') {
                    depth += 1;
                    if depth > max_depth {
                        return Err(OsimError::Xml {
                            source_name: source_name.to_string(),
                            line: 1 + b[..i].iter().filter(|&&c| c == b'\n').count(),
                            column: 1 + i - text[..i].rfind('\n').map_or(0, |p| p + 1),
                            message: format!(
                                "elements nest more than {max_depth} levels deep (an OpenSim model needs about 12)"
                            ),
                        });
                    }
                }
                i = end + 1;
            }
            _ => i += 1,
        }
    }
    Ok(())
}

/// Index of the `>` that closes the tag opened before `from` (quotes respected), or the end.
fn tag_end(b: &[u8], from: usize) -> usize {
    let mut quote = None;
    for (k, &c) in b.iter().enumerate().skip(from) {
        match (quote, c) {
            (None, b'"' | b'\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, b'>') => return k,
            // a `<` outside quotes: the tag is malformed; stop here and let the parser say so
            (None, b'<') => return k.saturating_sub(1).max(from),
            _ => {}
        }
    }
    b.len()
}

/// Position of `needle` in `hay`.
fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nested(n: usize) -> String {
        format!("<a>{}{}</a>", "<b x='>'>".repeat(n), "</b>".repeat(n))
    }

    #[test]
    fn depth_is_counted_and_bounded_with_the_line() {
        assert!(check_depth(&nested(10), 11, "f").is_ok());
        let e = check_depth(&nested(10), 10, "f").unwrap_err().to_string();
        assert!(
            e.starts_with("f:1:") && e.contains("more than 10 levels"),
            "{e}"
        );
        let t = "<a>\n<!-- <b><b><b> -->\n<b/><b/><b/>\n<c>\n<d>x</d></c></a>";
        assert!(check_depth(t, 3, "f").is_ok());
        let e = check_depth(t, 2, "f").unwrap_err().to_string();
        assert!(e.starts_with("f:5:"), "{e}");
        // markup in an entity declaration counts where it is written
        let t = "<!DOCTYPE a [<!ENTITY e \"<b><b><b>\">]><a>&e;</a>";
        assert!(check_depth(t, 3, "f").is_err());
    }

    #[test]
    fn latin1_is_decoded_when_declared_and_invalid_utf8_names_its_line() {
        let mut bytes = b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<a>caf".to_vec();
        bytes.extend([0xe9, b'<', b'/', b'a', b'>']);
        assert_eq!(
            decode(&bytes, "f").unwrap(),
            "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<a>café</a>"
        );
        let mut bytes = b"<?xml version=\"1.0\"?>\n<a>\ncaf".to_vec();
        bytes.extend([0xe9, b'<']);
        let e = decode(&bytes, "f").unwrap_err().to_string();
        assert!(
            e.starts_with("f:3:4:") && e.contains("0xe9") && e.contains("UTF-8"),
            "{e}"
        );
    }
}
