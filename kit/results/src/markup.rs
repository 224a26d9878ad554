//! Text from reports (reasons, case names, driver messages) made safe inside the markup the kit
//! writes: JUnit XML and the HTML report.

/// Escapes text for an XML or HTML attribute or element (and replaces the characters XML 1.0
/// forbids).
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            // What XML 1.0 has no character for (controls, the surrogates Rust never holds,
            // U+FFFE and U+FFFF) is shown as the replacement character, never written.
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_from_reports_cannot_open_tags() {
        assert_eq!(escape("<img src=x onerror=\"a&b\">"), "&lt;img src=x onerror=&quot;a&amp;b&quot;&gt;");
        assert_eq!(escape("it's\u{7}\u{FFFE}"), "it&apos;s\u{FFFD}\u{FFFD}");
    }
}
