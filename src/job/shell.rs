//! Words quoted for bash, so that any path survives a script as it is.

use super::plan::Word;
use std::borrow::Cow;

/// `word` as one bash word: as it is when every character is plain
/// (letters, digits, `_@%+:,./-`), else in single quotes, each `'` as `'\''`.
pub(crate) fn quote(word: &str) -> Cow<'_, str> {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_@%+:,./-".contains(c);
    if !word.is_empty() && word.chars().all(plain) {
        return Cow::Borrowed(word);
    }
    Cow::Owned(format!("'{}'", word.replace('\'', r"'\''")))
}

/// The words of a command, each after a space: text quoted, an engine's
/// expression (already bash) as it is.
pub(crate) fn words(command: &[Word]) -> String {
    let mut s = String::new();
    for word in command {
        match word {
            Word::Text(text) => s.push_str(&format!(" {}", quote(text))),
            Word::Engine(expression) => s.push_str(&format!(" {expression}")),
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::quote;

    #[test]
    fn plain_words_stay_and_others_are_single_quoted() {
        assert_eq!(quote("/a/b-c_d.png"), "/a/b-c_d.png");
        assert_eq!(quote(""), "''");
        assert_eq!(quote("a b"), "'a b'");
        assert_eq!(quote("it's"), r"'it'\''s'");
        assert_eq!(quote("$HOME"), "'$HOME'");
        assert_eq!(quote("x=y"), "'x=y'");
        assert_eq!(quote("~"), "'~'");
    }
}
