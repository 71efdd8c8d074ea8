//! Splits scene text into lines of words, dropping comments, keeping each
//! word's column so diagnostics can point at it. Comments are `#` and `//`,
//! anywhere in a line; only a `//` inside a `texture=` / `file=` path is
//! kept (the rule is on [`words_into`]).

/// One whitespace-separated word of a line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Word<'a> {
    /// The word's text.
    pub text: &'a str,
    /// Byte offset of the word in its line.
    pub start: usize,
    /// 1-based column, in characters.
    pub col: usize,
    /// Width in characters.
    pub len: usize,
}

impl<'a> Word<'a> {
    /// The part of the word after its first `chars` characters, as a word of
    /// its own (for `key=value` glued together).
    pub fn split_off(&self, chars: usize) -> Word<'a> {
        let byte = if self.text.is_ascii() {
            chars.min(self.text.len())
        } else {
            self.text
                .char_indices()
                .nth(chars)
                .map_or(self.text.len(), |(i, _)| i)
        };
        Word {
            text: &self.text[byte..],
            start: self.start + byte,
            col: self.col + chars,
            len: self.len.saturating_sub(chars),
        }
    }
}

/// One line of the file: its text (without the line break) and its words
/// before any comment, which live in the [`Lexer`]'s buffer until the next line.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Line<'a, 'w> {
    /// Byte offset of the line's start in the lexed text.
    pub start: usize,
    /// The line's text, for excerpts.
    pub text: &'a str,
    /// The words before any comment.
    pub words: &'w [Word<'a>],
}

/// Splits `text` into lines (`\n`, `\r\n` or a lone `\r` end a line),
/// lazily: a million-primitive file is never held as a list of lines.
pub(crate) fn split_lines(text: &str) -> impl Iterator<Item = &str> {
    Spans { text, start: 0 }.map(|(_, line)| line)
}

/// The lines of a text, each with the byte offset of its start.
struct Spans<'a> {
    text: &'a str,
    /// Where the next line starts.
    start: usize,
}

/// Where the line holding byte `from` of `bytes` ends: its first `\n` or
/// `\r` from there, or the end (memchr's search is vectorised).
fn line_end(bytes: &[u8], from: usize) -> usize {
    memchr::memchr2(b'\n', b'\r', bytes.get(from..).unwrap_or_default())
        .map_or(bytes.len(), |k| from + k)
}

impl Spans<'_> {
    /// Past the line break (`\n`, `\r\n` or `\r`) at `start`, if any.
    fn skip_break(&mut self) {
        let rest = self.text.as_bytes().get(self.start..).unwrap_or_default();
        self.start += match rest {
            [b'\r', b'\n', ..] => 2,
            [b'\r' | b'\n', ..] => 1,
            _ => 0,
        };
    }
}

impl<'a> Iterator for Spans<'a> {
    type Item = (usize, &'a str);

    fn next(&mut self) -> Option<(usize, &'a str)> {
        let (text, start) = (self.text, self.start);
        let bytes = text.as_bytes();
        // A final line without a line break still counts; an empty tail does not.
        if start >= bytes.len() {
            return None;
        }
        let line_end = line_end(bytes, start);
        self.start = line_end;
        self.skip_break();
        Some((start, &text[start..line_end]))
    }
}

/// Keys whose value is a file path (see [`words_into`]).
const PATH_KEYS: [&str; 2] = ["texture", "file"];

/// Byte offset just after the `=` when the line's key is a path key
/// (`texture= ...`, `file=...`, `texture = ...`), else `None`.
fn path_value_start(line: &str) -> Option<usize> {
    // Most lines start with another letter: no trimming, no search.
    let first = line.bytes().find(|b| !matches!(b, b'\t'..=b'\r' | b' '));
    if first.is_some_and(|b| b.is_ascii() && b != b't' && b != b'f') {
        return None;
    }
    let lead = line.len() - line.trim_start().len();
    let rest = &line[lead..];
    let key_len = rest.find(|c: char| c == '=' || c.is_whitespace())?;
    if !PATH_KEYS.contains(&&rest[..key_len]) {
        return None;
    }
    let after = &rest[key_len..];
    let gap = after.len() - after.trim_start().len();
    after[gap..]
        .starts_with('=')
        .then_some(lead + key_len + gap + 1)
}

/// The words of one line (it holds no line break), before any comment,
/// into `out` (cleared first).
///
/// A comment starts at any `#`, and at any `//`, even one glued to a value
/// (`O= 0 5 0// centre`, `end// sphere`, `R= 1#x`), as the spec allows both
/// after the values. One exception keeps file paths whole: in the value of
/// a `texture=` or `file=` line, a `//` glued between two characters of a
/// word (`maps//wood.bmp`) is part of the path. There a `//` still starts a
/// comment at the start of a word or when a blank or the end of the line
/// follows it (`wood.bmp// oak`, `wood.bmp//`), since no file path ends in
/// `//`. A `#` always starts a comment, in paths too.
pub(crate) fn words_into<'a>(line: &'a str, out: &mut Vec<Word<'a>>) {
    out.clear();
    // Where a path value starts, on a `texture=` / `file=` line.
    let path = path_value_start(line);
    if line.is_ascii() {
        ascii_words(line, path, out);
    } else {
        char_words(line, path, out);
    }
}

/// [`words_into`] for a line of ASCII text (nearly every line of every
/// file): a byte is a character, so a column is a byte offset plus one.
fn ascii_words<'a>(line: &'a str, path: Option<usize>, out: &mut Vec<Word<'a>>) {
    let found = ascii_line(line, 0, Some(path), out);
    debug_assert_eq!(
        found,
        Some(line.len()),
        "an ASCII line without a line break"
    );
}

/// The words of the line that starts at byte `start` of `text` and ends at
/// the next line break (or the text's end), pushed onto `out` as
/// [`words_into`] makes them, in one pass over its bytes; returns where it
/// ends. `path` is [`path_value_start`] of the line when the caller knows
/// it, `None` to work it out here. Gives up (`None`, with `out` in any
/// state) at a byte that is not ASCII before any comment: such a line is
/// read character by character.
fn ascii_line<'a>(
    text: &'a str,
    start: usize,
    mut path: Option<Option<usize>>,
    out: &mut Vec<Word<'a>>,
) -> Option<usize> {
    // The text from the line's start: words are taken from it.
    let rest = &text[start..];
    let r = rest.as_bytes();
    // Byte start (in the line, and so column − 1) of the word being read.
    let mut current: Option<usize> = None;
    let word = |start: Option<usize>| start.map(|s| (s, s + 1));
    let mut at = 0;
    let stop = loop {
        let Some(&c) = r.get(at) else {
            break r.len();
        };
        match CLASS[usize::from(c)] {
            Class::Word => {
                if current.is_none() {
                    current = Some(at);
                }
                // The word's plain bytes that follow, at once.
                let plain = |c: &&u8| matches!(CLASS[usize::from(**c)], Class::Word);
                at += r
                    .get(at + 1..)
                    .unwrap_or_default()
                    .iter()
                    .take_while(plain)
                    .count();
            }
            Class::Blank => close(out, rest, word(current.take()), at, at + 1),
            Class::Break => break at,
            Class::Other => return None,
            Class::Comment | Class::Slash => {
                // A `#` or a `//`: a comment unless a `//` glued inside a
                // word of a path value, which the line's end tells.
                let mark = c == b'#' || r.get(at + 1) == Some(&b'/');
                let line_end = if mark { line_end(r, at) } else { 0 };
                let kept = c == b'/' && mark && {
                    let line = &rest[..line_end];
                    let p = *path.get_or_insert_with(|| path_value_start(line));
                    inside_path(line, p, word(current), at)
                };
                if mark && !kept {
                    close(out, rest, word(current), at, at + 1);
                    return Some(start + line_end);
                }
                if current.is_none() {
                    current = Some(at);
                }
            }
        }
        at += 1;
    };
    close(out, rest, word(current), stop, stop + 1);
    Some(start + stop)
}

/// What a byte is to [`ascii_line`].
#[derive(Clone, Copy)]
enum Class {
    /// Part of a word.
    Word,
    /// An ASCII blank that `char::is_whitespace` takes (line breaks aside).
    Blank,
    /// `\n` or `\r`.
    Break,
    /// `#`.
    Comment,
    /// `/`.
    Slash,
    /// Not ASCII.
    Other,
}

/// [`Class`] by byte.
const CLASS: [Class; 256] = {
    let mut t = [Class::Other; 256];
    let mut c = 0;
    while c < 128 {
        t[c] = match c as u8 {
            b'\t' | b'\x0b' | b'\x0c' | b' ' => Class::Blank,
            b'\n' | b'\r' => Class::Break,
            b'#' => Class::Comment,
            b'/' => Class::Slash,
            _ => Class::Word,
        };
        c += 1;
    }
    t
};

/// [`words_into`] for any line, character by character.
fn char_words<'a>(line: &'a str, path: Option<usize>, out: &mut Vec<Word<'a>>) {
    // (byte start, column) of the word being read.
    let mut current: Option<(usize, usize)> = None;
    let mut col = 0;
    for (i, c) in line.char_indices() {
        col += 1;
        let comment = c == '#'
            || (c == '/' && line[i..].starts_with("//") && !inside_path(line, path, current, i));
        if comment {
            close(out, line, current, i, col);
            return;
        }
        if c.is_whitespace() {
            close(out, line, current.take(), i, col);
        } else if current.is_none() {
            current = Some((i, col));
        }
    }
    close(out, line, current, line.len(), col + 1);
}

/// Whether the `//` at byte `i` is part of a path (see [`words_into`]): after
/// the first character of the path value, inside a word, and followed by
/// more than a blank or the end of the line.
fn inside_path(line: &str, path: Option<usize>, current: Option<(usize, usize)>, i: usize) -> bool {
    let Some(value) = path else {
        return false;
    };
    current.is_some()
        && i > value
        && line[i + 2..]
            .chars()
            .next()
            .is_some_and(|c| !c.is_whitespace())
}

/// Ends the word being read (if any) at byte `end`, column `col`.
fn close<'a>(
    out: &mut Vec<Word<'a>>,
    line: &'a str,
    cur: Option<(usize, usize)>,
    end: usize,
    col: usize,
) {
    if let Some((start, c0)) = cur {
        out.push(Word {
            text: &line[start..end],
            start,
            col: c0,
            len: col - c0,
        });
    }
}

/// The text without a leading byte-order mark; only the very start of a
/// file may carry one.
pub(crate) fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// Lexes text line by line, as it is: a byte-order mark is the caller's
/// business ([`strip_bom`]), as the text may be a later piece of a file.
/// One buffer holds the words of the current line: no allocation per line.
pub(crate) struct Lexer<'a> {
    spans: Spans<'a>,
    words: Vec<Word<'a>>,
}

impl<'a> Lexer<'a> {
    /// A lexer at the start of `text`.
    pub(crate) fn new(text: &'a str) -> Self {
        Lexer {
            spans: Spans { text, start: 0 },
            words: Vec::new(),
        }
    }

    /// The next line, or `None` at the end of the text.
    pub(crate) fn next_line(&mut self) -> Option<Line<'a, '_>> {
        let (all, start) = (self.spans.text, self.spans.start);
        if start >= all.len() {
            return None;
        }
        // An ASCII line is split into words in the same pass that finds its end.
        self.words.clear();
        let (start, text) = match ascii_line(all, start, None, &mut self.words) {
            Some(end) => {
                self.spans.start = end;
                self.spans.skip_break();
                (start, &all[start..end])
            }
            None => {
                let (start, text) = self.spans.next()?;
                words_into(text, &mut self.words);
                (start, text)
            }
        };
        Some(Line {
            start,
            text,
            words: &self.words,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(line: &str) -> Vec<Word<'_>> {
        let mut out = Vec::new();
        words_into(line, &mut out);
        out
    }

    /// Every line of `text` with its start.
    fn lex(text: &str) -> Vec<(usize, &str)> {
        let mut lexer = Lexer::new(text);
        std::iter::from_fn(|| lexer.next_line().map(|l| (l.start, l.text))).collect()
    }

    fn texts(line: &str) -> Vec<(&str, usize, usize)> {
        words(line)
            .into_iter()
            .map(|w| (w.text, w.col, w.len))
            .collect()
    }

    #[test]
    fn words_and_columns() {
        assert_eq!(
            texts("  O= 1 .5\t-2"),
            vec![("O=", 3, 2), ("1", 6, 1), (".5", 8, 2), ("-2", 11, 2)]
        );
        assert_eq!(texts("é= 1"), vec![("é=", 1, 2), ("1", 4, 1)]);
    }

    #[test]
    fn comments() {
        assert_eq!(texts("# all"), vec![]);
        assert_eq!(
            texts("N= 0 1 0  # look"),
            vec![("N=", 1, 2), ("0", 4, 1), ("1", 6, 1), ("0", 8, 1)]
        );
        assert_eq!(texts("R= 1#x"), vec![("R=", 1, 2), ("1", 4, 1)]);
        assert_eq!(texts("// all"), vec![]);
        assert_eq!(texts("R= 2 // two"), vec![("R=", 1, 2), ("2", 4, 1)]);
        assert_eq!(
            texts("texture= a//b.bmp"),
            vec![("texture=", 1, 8), ("a//b.bmp", 10, 8)]
        );
    }

    #[test]
    fn slash_comments_glued_to_words() {
        assert_eq!(
            texts("O= 0 5 0// centre"),
            vec![("O=", 1, 2), ("0", 4, 1), ("5", 6, 1), ("0", 8, 1)]
        );
        assert_eq!(texts("end// sphere"), vec![("end", 1, 3)]);
        assert_eq!(texts("end//"), vec![("end", 1, 3)]);
        assert_eq!(texts("R=1//x"), vec![("R=1", 1, 3)]);
        assert_eq!(texts("a/b/c"), vec![("a/b/c", 1, 5)]);
        // A `blur=` value is not a path.
        assert_eq!(texts("blur= exp//x"), vec![("blur=", 1, 5), ("exp", 7, 3)]);
        // A key that merely starts like a path key is not one.
        assert_eq!(
            texts("textures= a//b"),
            vec![("textures=", 1, 9), ("a", 11, 1)]
        );
    }

    #[test]
    fn slashes_inside_paths() {
        assert_eq!(texts("  file=m//a.obj"), vec![("file=m//a.obj", 3, 13)]);
        assert_eq!(
            texts("texture = a//b.bmp"),
            vec![("texture", 1, 7), ("=", 9, 1), ("a//b.bmp", 11, 8)]
        );
        // A blank or the end of the line after `//`: a comment.
        assert_eq!(
            texts("texture= a.bmp// oak"),
            vec![("texture=", 1, 8), ("a.bmp", 10, 5)]
        );
        assert_eq!(
            texts("texture= a.bmp//"),
            vec![("texture=", 1, 8), ("a.bmp", 10, 5)]
        );
        // At the start of a word or of the glued value: a comment.
        assert_eq!(texts("texture= //a.bmp"), vec![("texture=", 1, 8)]);
        assert_eq!(texts("texture=//a.bmp"), vec![("texture=", 1, 8)]);
        assert_eq!(
            texts("texture= a.bmp //x"),
            vec![("texture=", 1, 8), ("a.bmp", 10, 5)]
        );
        // `#` always starts a comment.
        assert_eq!(
            texts("texture= a#b.bmp"),
            vec![("texture=", 1, 8), ("a", 10, 1)]
        );
    }

    #[test]
    fn line_breaks() {
        assert_eq!(
            split_lines("a\r\nb\rc\nd").collect::<Vec<_>>(),
            vec!["a", "b", "c", "d"]
        );
        assert_eq!(split_lines("a\n").collect::<Vec<_>>(), vec!["a"]);
        assert_eq!(split_lines("a\n\n").collect::<Vec<_>>(), vec!["a", ""]);
        assert_eq!(split_lines("").count(), 0);
    }

    #[test]
    fn line_starts_and_byte_order_marks() {
        let starts = lex("a\r\nbé\rc\n\nd");
        assert_eq!(
            starts,
            vec![(0, "a"), (3, "bé"), (7, "c"), (9, ""), (10, "d")]
        );
        // Only `strip_bom` drops the mark: a later piece of a file keeps it.
        assert_eq!(lex("\u{feff}a"), vec![(0, "\u{feff}a")]);
        assert_eq!(strip_bom("\u{feff}\u{feff}a"), "\u{feff}a");
        assert_eq!(strip_bom("a\u{feff}"), "a\u{feff}");
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config {
            cases: 4096,
            rng_seed: proptest::test_runner::RngSeed::Fixed(37),
            ..proptest::test_runner::Config::default()
        })]
        /// ASCII lines split byte by byte as character by character: the
        /// same words, offsets and columns, comments and paths included.
        /// (A line holds no line break: those are the next test's.)
        #[test]
        fn ascii_lines_split_as_characters_do(
            parts in proptest::collection::vec(proptest::sample::select(vec![
                "texture=", "file=", "texture", "=", "O=", "R=", "1", "-2.5", "a//b", "//", "/",
                "#", "x#y", "end", "a.bmp", " ", "  ", "\t", "\x0b", "\x0c",
            ]), 0..12),
        ) {
            let line = parts.concat();
            let (mut fast, mut slow) = (Vec::new(), Vec::new());
            let path = path_value_start(&line);
            ascii_words(&line, path, &mut fast);
            char_words(&line, path, &mut slow);
            proptest::prop_assert_eq!(fast, slow, "{:?}", line);
        }

        /// The lexer's one pass over ASCII lines finds the lines and words
        /// that splitting the text into lines and then each line into words
        /// finds: line breaks of every kind, blank and final lines, comments,
        /// paths and characters that are not ASCII included.
        #[test]
        fn one_pass_lines_are_split_lines_split_into_words(
            parts in proptest::collection::vec(proptest::sample::select(vec![
                "texture=", "file=", "texture", "=", "O=", "R=", "1", "-2.5", "a//b", "//", "/",
                "#", "x#y", "end", "a.bmp", "é", "t", "f", " ", "  ", "\t", "\x0b", "\x0c",
                "\r", "\n", "\r\n", "\n\n",
            ]), 0..24),
        ) {
            let text = parts.concat();
            let mut lexer = Lexer::new(&text);
            let mut got = Vec::new();
            while let Some(line) = lexer.next_line() {
                got.push((line.start, line.text, line.words.to_vec()));
            }
            let want: Vec<_> = (Spans { text: &text, start: 0 })
                .map(|(start, line)| (start, line, words(line)))
                .collect();
            proptest::prop_assert_eq!(got, want, "{:?}", text);
        }
    }

    #[test]
    fn split_off() {
        let w = words("color=1")[0];
        let v = w.split_off(6);
        assert_eq!((v.text, v.col, v.len, v.start), ("1", 7, 1, 6));
        let w = words("é=1")[0];
        let v = w.split_off(2);
        assert_eq!((v.text, v.col, v.len, v.start), ("1", 3, 1, 3));
        assert_eq!(w.split_off(9).text, "");
    }
}
