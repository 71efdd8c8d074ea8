//! Characters that must not reach a terminal raw: invisible ones, ones that
//! move the cursor or turn the text around, and ones that are no text at all.

use std::borrow::Cow;

/// The format characters (general category Cf, Unicode 15): zero-width
/// spaces and joiners, bidirectional marks, embeddings, overrides and
/// isolates, the byte order mark, tags and the like.
const FORMAT: &[(u32, u32)] = &[
    (0x00AD, 0x00AD),
    (0x0600, 0x0605),
    (0x061C, 0x061C),
    (0x06DD, 0x06DD),
    (0x070F, 0x070F),
    (0x0890, 0x0891),
    (0x08E2, 0x08E2),
    (0x180E, 0x180E),
    (0x200B, 0x200F),
    (0x202A, 0x202E),
    (0x2060, 0x2064),
    (0x2066, 0x206F),
    (0xFEFF, 0xFEFF),
    (0xFFF9, 0xFFFB),
    (0x110BD, 0x110BD),
    (0x110CD, 0x110CD),
    (0x13430, 0x1343F),
    (0x1BCA0, 0x1BCA3),
    (0x1D173, 0x1D17A),
    (0xE0001, 0xE0001),
    (0xE0020, 0xE007F),
];

/// Whether `c` is shown escaped: a control character other than tab, a
/// format character, the line or paragraph separator, or a noncharacter.
pub(crate) fn hidden(c: char) -> bool {
    let u = u32::from(c);
    // Printable ASCII, nearly every character of a scene file, at once
    // (not after a search of the table; a fuzzer's instrumented build paid
    // for each comparison of each character of each message).
    if (0x20..0x7F).contains(&u) {
        return false;
    }
    (c.is_control() && c != '\t')
        || matches!(u, 0x2028 | 0x2029 | 0xFDD0..=0xFDEF)
        || u & 0xFFFE == 0xFFFE
        || FORMAT.iter().any(|&(lo, hi)| (lo..=hi).contains(&u))
}

/// `text` with every invisible, control or direction-changing character written as `\u{..}`.
pub fn escaped(text: &str) -> Cow<'_, str> {
    if !text.chars().any(hidden) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 16);
    for c in text.chars() {
        if hidden(c) {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shortcut for printable ASCII agrees with the definition (control
    /// characters but tab, the format table, separators, noncharacters),
    /// written out again here for every character.
    #[test]
    fn hidden_is_its_definition_for_every_character() {
        let by_definition = |c: char| {
            let u = u32::from(c);
            (c.is_control() && c != '\t')
                || u == 0x2028
                || u == 0x2029
                || (0xFDD0..=0xFDEF).contains(&u)
                || u & 0xFFFE == 0xFFFE
                || FORMAT.iter().any(|&(lo, hi)| lo <= u && u <= hi)
        };
        let differ: Vec<char> = (0..=0x10FFFF_u32)
            .filter_map(char::from_u32)
            .filter(|&c| hidden(c) != by_definition(c))
            .collect();
        assert!(differ.is_empty(), "{differ:?}");
        assert!(!(' '..='~').any(hidden));
        assert!(hidden('\u{7f}') && hidden('\u{1f}') && !hidden('\t'));
    }

    #[test]
    fn invisible_and_turning_characters_are_escaped() {
        for c in [
            '\u{0}',
            '\u{1b}',
            '\r',
            '\n',
            '\u{7f}',
            '\u{85}',
            '\u{ad}',
            '\u{61c}',
            '\u{200b}',
            '\u{200d}',
            '\u{200e}',
            '\u{200f}',
            '\u{2028}',
            '\u{2029}',
            '\u{202a}',
            '\u{202e}',
            '\u{2066}',
            '\u{2069}',
            '\u{feff}',
            '\u{fdd0}',
            '\u{fdef}',
            '\u{fffe}',
            '\u{ffff}',
            '\u{1fffe}',
            '\u{10ffff}',
            '\u{e0001}',
            '\u{13439}',
        ] {
            let text = format!("a{c}b");
            let want = format!("a{}b", c.escape_unicode());
            assert_eq!(escaped(&text), want, "{:?}", c);
        }
    }

    #[test]
    fn visible_text_is_kept_as_is() {
        for text in [
            "",
            "plain",
            "tab\there",
            "中文注释",
            "é\u{301}",
            "\u{fffd}",
            "\u{a0}",
        ] {
            assert!(
                matches!(escaped(text), Cow::Borrowed(t) if t == text),
                "{text:?}"
            );
        }
        // U+FDCF and U+FDF0 border the noncharacter block; U+FFFD is the replacement character.
        assert_eq!(
            escaped("\u{fdcf}\u{fdf0}\u{fffd}"),
            "\u{fdcf}\u{fdf0}\u{fffd}"
        );
    }
}
