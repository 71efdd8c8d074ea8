//! Diagnostics that point at the source: `file:line:column`, the line, a
//! caret, rendered rustc-style by `annotate-snippets`.

use super::escape::{escaped, hidden};
use annotate_snippets::renderer::{AnsiColor, Effects, Style};
use annotate_snippets::{Level, Renderer, Snippet};
use std::fmt;
use std::ops::Range;
use unicode_width::UnicodeWidthChar;

/// How bad a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    /// The scene cannot be rendered.
    Error,
    /// The scene renders, but something in it is probably not what was meant.
    Warning,
}

/// One message about a place in a scene file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// What is wrong, in one sentence.
    pub message: String,
    /// The file's name as the user gave it (`<input>` for strings).
    pub file: String,
    /// 1-based line (0: the file as a whole).
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    /// Width of the underlined span, in characters (at least 1).
    pub len: usize,
    /// The text of the line, for the excerpt.
    pub source_line: String,
    /// A hint such as "did you mean `sphere`?".
    pub help: Option<String>,
}

impl Diagnostic {
    /// The diagnostic as text for a terminal, with ANSI colours if `color`.
    pub fn render(&self, color: bool) -> String {
        let message = escaped(&self.message);
        let help = self.help.as_deref().map(escaped);
        let excerpt = (self.line > 0 && self.line < usize::MAX)
            .then(|| excerpt(&self.source_line, self.column, self.len))
            .flatten();
        let level = match self.severity {
            Severity::Error => Level::Error,
            Severity::Warning => Level::Warning,
        };
        let mut report = level.title(&message);
        if let Some(x) = &excerpt {
            // `^` under a warning too, as rustc draws it, in the warning's colour (see `renderer`).
            let span = Level::Error.span(x.span.clone());
            let snippet = Snippet::source(&x.text).line_start(self.line);
            report = report.snippet(snippet.annotation(span));
        }
        if let Some(help) = &help {
            report = report.footer(Level::Help.title(help));
        }
        let body = renderer(self.severity, color).render(report).to_string();

        // annotate-snippets would write `--> file:line:col` from an origin, but
        // with the column counted in the excerpt it was given (escapes, tabs,
        // the window), not in the file; so the line goes in here, where it
        // would have put it: after the title.
        let file = escaped(&self.file);
        let (pad, place) = if self.line == 0 {
            ("  ".to_string(), file.into_owned())
        } else {
            let pad = " ".repeat(self.line.to_string().len());
            (pad, format!("{file}:{}:{}", self.line, self.column))
        };
        let arrow = if color {
            format!("{}-->{}", GUTTER.render(), GUTTER.render_reset())
        } else {
            "-->".to_string()
        };
        match body.split_once('\n') {
            Some((title, rest)) => format!("{title}\n{pad}{arrow} {place}\n{rest}"),
            None => format!("{body}\n{pad}{arrow} {place}"),
        }
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(false))
    }
}

/// Colour of the `-->` and of the gutter (line numbers, `|`, `=`).
const GUTTER: Style = AnsiColor::BrightBlue.on_default().effects(Effects::BOLD);
/// Colour of a warning's title and carets.
const WARNING: Style = AnsiColor::Yellow.on_default().effects(Effects::BOLD);
/// The terminal width annotate-snippets is told: wider than any excerpt, so
/// that it never cuts a line itself (it would count bytes and characters as
/// columns, losing the caret under wide characters); [`excerpt`] has cut it.
const TERM_WIDTH: usize = 1 << 16;

/// The renderer for a diagnostic: plain, or in colour with the carets (always
/// an error's `^`) in the colour of the diagnostic's title.
fn renderer(severity: Severity, color: bool) -> Renderer {
    let plain = Renderer::plain().term_width(TERM_WIDTH);
    if !color {
        return plain;
    }
    let styled = Renderer::styled().term_width(TERM_WIDTH).line_no(GUTTER);
    match severity {
        Severity::Error => styled,
        Severity::Warning => styled.warning(WARNING).error(WARNING),
    }
}

/// Tab stops in excerpts.
const TAB: usize = 4;
/// Lines wider than this (in terminal columns) are shown as a window around the span.
const MAX_WIDTH: usize = 200;
/// Columns of the line kept before the span in a window.
const CONTEXT: usize = 60;
/// Blank columns at the start of an excerpt beyond which they are cut, to 4 before the span.
const LONG_BLANK: usize = 20;
/// annotate-snippets cuts more leading blanks than this itself (marking the
/// cut `...`, and losing a caret among them), so no excerpt hands it more.
const TRIMMED_BLANK: usize = 26;
/// How far past the end of the line a span may start (so that a hand-made
/// diagnostic with an absurd column cannot exhaust memory).
const PAST_END: usize = 256;
/// The mark of a cut end.
const CUT: char = '\u{2026}';

/// What one character of a line looks like in an excerpt.
#[derive(Clone, Copy)]
enum Shown {
    /// Itself.
    Char(char),
    /// Blanks: a tab expanded to the next stop, or room past the line's end.
    Spaces(usize),
    /// Its `\u{..}` escape (see [`escaped`]).
    Escape(char),
}

impl Shown {
    /// How `c` is shown at terminal column `col`.
    fn of(c: char, col: usize) -> Shown {
        if c == '\t' {
            Shown::Spaces(TAB - col % TAB)
        } else if hidden(c) {
            Shown::Escape(c)
        } else {
            Shown::Char(c)
        }
    }

    /// Terminal columns it takes.
    fn width(self) -> usize {
        match self {
            Shown::Char(c) => c.width().unwrap_or(0),
            Shown::Spaces(n) => n,
            Shown::Escape(c) => c.escape_unicode().len(),
        }
    }

    /// Its share of an excerpt's width: at least 1, so that a window holds a
    /// bounded number of characters even of zero-width ones.
    fn cost(self) -> usize {
        self.width().max(1)
    }

    /// Whether it looks blank (annotate-snippets' notion: Unicode white space).
    fn blank(self) -> bool {
        match self {
            Shown::Char(c) => c.is_whitespace(),
            Shown::Spaces(_) => true,
            Shown::Escape(_) => false,
        }
    }

    fn push_to(self, out: &mut String) {
        match self {
            Shown::Char(c) => out.push(c),
            Shown::Spaces(n) => out.extend(std::iter::repeat_n(' ', n)),
            Shown::Escape(c) => out.extend(c.escape_unicode()),
        }
    }
}

/// How the characters of `line` are shown, then `pad` blanks past its end.
fn shown(line: &str, pad: usize) -> impl Iterator<Item = Shown> + '_ {
    let mut col = 0;
    line.chars()
        .map(move |c| {
            let s = Shown::of(c, col);
            col += s.width();
            s
        })
        .chain(std::iter::repeat_n(Shown::Spaces(1), pad))
}

/// A line as handed to annotate-snippets, and the byte range of the span in it.
struct Excerpt {
    text: String,
    span: Range<usize>,
}

/// The excerpt of `line` for the span of `len` characters at 1-based
/// character `column`: tabs expanded, hidden characters escaped, and a long
/// line cut to a window around the span (`…` at each cut end). None when
/// there is nothing but blanks to show.
fn excerpt(line: &str, column: usize, len: usize) -> Option<Excerpt> {
    let count = line.chars().count();
    let limit = count.saturating_add(PAST_END);
    // Character indices of the span, which may lie past the end of the line
    // (a missing value): it is then shown over blanks.
    let first = column.saturating_sub(1).min(limit);
    let last = first.saturating_add(len.max(1)).min(limit);
    let pad = last.saturating_sub(count);

    // Where the span starts, and the whole width, in columns.
    let (mut at, mut total) = (None, 0);
    for (i, s) in shown(line, pad).enumerate() {
        if i == first {
            at = Some(total);
        }
        total += s.cost();
    }
    let at = at.unwrap_or(total);
    let (lo, hi) = if total <= MAX_WIDTH {
        (0, total)
    } else {
        let lo = at.saturating_sub(CONTEXT).min(total - MAX_WIDTH);
        (lo, lo + MAX_WIDTH)
    };

    // (index, column, look) of the characters within the window.
    let mut kept = Vec::new();
    let (mut cut_left, mut cut_right) = (lo > 0, false);
    let mut col = 0;
    for (i, s) in shown(line, pad).enumerate() {
        let next = col + s.cost();
        if next > hi {
            cut_right = true;
            break;
        }
        if col >= lo {
            kept.push((i, col, s));
        }
        col = next;
    }
    // A long run of blanks at the start is cut too, up to 4 columns before the span.
    let start = kept.first()?.1;
    let seen = kept.iter().find(|k| !k.2.blank())?.1;
    if seen - start > LONG_BLANK {
        let from = seen.min(at).saturating_sub(4).max(start);
        kept.retain(|k| k.1 >= from);
        cut_left |= from > start;
    }
    if !cut_left && seen - kept.first()?.1 > TRIMMED_BLANK {
        return None;
    }

    let mut text = String::new();
    if cut_left {
        text.push(CUT);
    }
    let (mut from, mut to) = (None, None);
    for &(i, _, s) in &kept {
        if i >= first && from.is_none() {
            from = Some(text.len());
        }
        if i >= last && to.is_none() {
            to = Some(text.len());
        }
        s.push_to(&mut text);
    }
    let from = from.unwrap_or(text.len());
    let to = to.unwrap_or(text.len());
    if cut_right {
        text.push(CUT);
    }
    Some(Excerpt {
        text,
        span: from..to,
    })
}

/// Why a scene could not be read: every error found (not only the first),
/// plus the warnings seen on the way.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    /// Errors and warnings, in file order.
    pub diagnostics: Vec<Diagnostic>,
}

impl SceneError {
    /// Only the errors.
    pub fn errors(&self) -> impl Iterator<Item = &Diagnostic> {
        self.diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error)
    }
}

impl SceneError {
    /// Every diagnostic, then how many errors there were, with ANSI colours if `color`.
    pub fn render(&self, color: bool) -> String {
        let mut out = String::new();
        for d in &self.diagnostics {
            out.push_str(&d.render(color));
            out.push_str("\n\n");
        }
        let n = self.errors().count();
        let s = if n == 1 { "" } else { "s" };
        out.push_str(&format!("{n} error{s} in the scene; nothing was rendered"));
        out
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(false))
    }
}

impl std::error::Error for SceneError {}

#[cfg(test)]
mod tests {
    use super::*;

    /// An error at 1-based `column` of line 3, `len` characters wide.
    fn at(source_line: &str, column: usize, len: usize) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            message: "unknown word".to_string(),
            file: "s.txt".to_string(),
            line: 3,
            column,
            len,
            source_line: source_line.to_string(),
            help: None,
        }
    }

    /// The excerpt's line (after `3 | `) and the caret line's carets: their
    /// terminal column in the excerpt and how many.
    fn excerpt_and_carets(shown: &str) -> (String, usize, usize) {
        let line = shown.lines().find_map(|l| l.strip_prefix("3 | "));
        let carets = shown.lines().find_map(|l| l.strip_prefix("  | "));
        let (Some(line), Some(carets)) = (line, carets.filter(|c| c.contains('^'))) else {
            panic!("no excerpt or no carets in\n{shown}"); // invariant: the test's own fixed input (a failure fails the test)
        };
        let column = carets.find('^').unwrap_or(0);
        (line.to_string(), column, carets.matches('^').count())
    }

    /// Terminal columns of `text` in the tests' scripts: CJK ideographs are 2, the rest 1.
    fn columns(text: &str) -> usize {
        text.chars()
            .map(|c| {
                if ('\u{4e00}'..='\u{9fff}').contains(&c) {
                    2
                } else {
                    1
                }
            })
            .sum()
    }

    #[test]
    fn the_layout_is_rustc_s() {
        let mut d = at(" colour= 1 0 0", 2, 7);
        d.severity = Severity::Warning;
        d.message = "unknown key `colour=`".to_string();
        d.help = Some("did you mean `color=`?".to_string());
        assert_eq!(
            d.to_string(),
            "warning: unknown key `colour=`
 --> s.txt:3:2
  |
3 |  colour= 1 0 0
  |  ^^^^^^^
  |
  = help: did you mean `color=`?"
        );
        // Line 0: the file as a whole, no excerpt.
        let mut d = at("", 0, 0);
        d.line = 0;
        d.message = "cannot read the scene file: gone".to_string();
        assert_eq!(
            d.to_string(),
            "error: cannot read the scene file: gone\n  --> s.txt"
        );
        d.help = Some("check the path".to_string());
        assert!(
            d.to_string()
                .ends_with("\n  --> s.txt\n = help: check the path")
        );
    }

    #[test]
    fn carets_line_up_under_wide_characters() {
        // 4 ideographs (2 columns each), then ` primitive `, then the word.
        let line = "中文注释 primitive spher";
        let before = "中文注释 primitive ";
        let d = at(line, before.chars().count() + 1, 5);
        let shown = d.to_string();
        let (excerpt, column, carets) = excerpt_and_carets(&shown);
        assert_eq!(excerpt, line, "{shown}");
        assert_eq!(column, 4 * 2 + " primitive ".len(), "{shown}");
        assert_eq!(column, columns(before), "{shown}");
        assert_eq!(carets, 5, "{shown}");
        assert!(shown.contains(" --> s.txt:3:16\n"), "{shown}");
        // Carets under a wide word are as wide as it is.
        let d = at("R= 半径", 4, 2);
        let (_, column, carets) = excerpt_and_carets(&d.to_string());
        assert_eq!((column, carets), (3, 4));
        // Tabs stop every 4 columns, counting the wide characters' width.
        let d = at("中\tbad", 3, 3);
        let (excerpt, column, _) = excerpt_and_carets(&d.to_string());
        assert_eq!((excerpt.as_str(), column), ("中  bad", 4));
    }

    #[test]
    fn invisible_and_turning_characters_are_shown_escaped_and_the_caret_follows() {
        for c in ['\u{feff}', '\u{200b}', '\u{202e}', '\u{2028}', '\u{ffff}'] {
            let escape: String = c.escape_unicode().collect();
            let word = format!("sp{c}her");
            let mut d = at(&format!("primitive {word} # {c}"), 11, 6);
            d.message = format!("unknown primitive type `{word}`");
            d.help = Some(format!("did you mean `sphere`, not `{word}`?"));
            d.file = format!("dir{c}/s.txt");
            for shown in [
                d.to_string(),
                d.render(true),
                SceneError {
                    diagnostics: vec![d.clone()],
                }
                .to_string(),
            ] {
                assert!(!shown.contains(c), "{c:?} shown raw: {shown:?}");
                assert!(shown.contains(&format!("type `sp{escape}her`")), "{shown}");
                assert!(shown.contains(&format!("not `sp{escape}her`?")), "{shown}");
                assert!(
                    shown.contains(&format!("dir{escape}/s.txt:3:11")),
                    "{shown}"
                );
            }
            let shown = d.to_string();
            let (excerpt, column, carets) = excerpt_and_carets(&shown);
            assert_eq!(
                excerpt,
                format!("primitive sp{escape}her # {escape}"),
                "{shown}"
            );
            // The carets cover the word, escape and all.
            assert_eq!(column, "primitive ".len(), "{shown}");
            assert_eq!(carets, 5 + escape.len(), "{shown}");
        }
    }

    #[test]
    fn colour_only_when_asked() {
        let mut d = at(" colour= 1 0 0", 2, 7);
        d.help = Some("did you mean `color=`?".to_string());
        for severity in [Severity::Error, Severity::Warning] {
            d.severity = severity;
            let plain = d.render(false);
            let coloured = d.render(true);
            assert!(!plain.contains('\u{1b}'), "{plain:?}");
            assert!(coloured.contains("\u{1b}["), "{coloured:?}");
            // Without its colour codes the coloured text is the plain one.
            let mut stripped = String::new();
            let mut rest = coloured.as_str();
            while let Some(i) = rest.find('\u{1b}') {
                stripped.push_str(&rest[..i]);
                let code = &rest[i..];
                let end = code.find('m').unwrap_or(code.len() - 1);
                rest = &code[end + 1..];
            }
            stripped.push_str(rest);
            assert_eq!(stripped, plain);
        }
        let e = SceneError {
            diagnostics: vec![d.clone()],
        };
        assert!(e.render(true).contains("\u{1b}["));
        assert_eq!(e.to_string(), e.render(false));
        assert!(!e.to_string().contains('\u{1b}'));
    }

    #[test]
    fn long_lines_are_cut_to_a_window_around_the_span() {
        // 20 000 characters, the word in the middle.
        let line = format!("{}WORD{}", "a ".repeat(5000), " b".repeat(4998));
        assert_eq!(line.chars().count(), 20_000);
        let d = at(&line, 10_001, 4);
        let shown = d.to_string();
        assert!(shown.len() < 1000, "{} bytes:\n{shown}", shown.len());
        let (excerpt, column, carets) = excerpt_and_carets(&shown);
        assert!(
            excerpt.starts_with('…') && excerpt.ends_with('…'),
            "{shown}"
        );
        assert_eq!(
            excerpt.chars().skip(column).take(4).collect::<String>(),
            "WORD"
        );
        assert_eq!(carets, 4, "{shown}");
        assert!(shown.contains(":3:10001\n"), "{shown}");

        // The same with wide characters around the word.
        let line = format!("{}WORD{}", "中文".repeat(5000), "中文".repeat(5000));
        let d = at(&line, 10_001, 4);
        let shown = d.to_string();
        assert!(shown.len() < 1000, "{} bytes:\n{shown}", shown.len());
        let (excerpt, column, carets) = excerpt_and_carets(&shown);
        let word = excerpt.find("WORD").unwrap_or_else(|| panic!("{shown}")); // invariant: the test's own fixed input (a failure fails the test)
        assert_eq!(column, columns(&excerpt[..word]), "{shown}");
        assert_eq!(carets, 4, "{shown}");
        // At the end of a long line, or at its start: one cut only.
        let line = "x".repeat(20_000);
        let (excerpt, column, _) = excerpt_and_carets(&at(&line, 20_000, 1).to_string());
        assert!(excerpt.starts_with('…') && !excerpt.ends_with('…'));
        assert_eq!(column, excerpt.chars().count() - 1);
        let (excerpt, column, _) = excerpt_and_carets(&at(&line, 1, 1).to_string());
        assert!(!excerpt.starts_with('…') && excerpt.ends_with('…'));
        assert_eq!(column, 0);
        // Zero-width characters count for the window's size too.
        let line = format!("a{}", "\u{301}".repeat(20_000));
        assert!(at(&line, 1, 1).to_string().len() < 1000);
    }

    #[test]
    fn spans_past_the_end_and_absurd_ones_stay_small() {
        // A missing value: the caret goes just past the end, as the column says.
        let (excerpt, column, carets) = excerpt_and_carets(&at(" O=", 5, 1).to_string());
        assert_eq!((excerpt.trim_end(), column, carets), (" O=", 4, 1));
        for (column, len) in [(usize::MAX, usize::MAX), (1 << 40, 3), (2, usize::MAX)] {
            let shown = at(" O= 1 2 3", column, len).to_string();
            assert!(shown.len() < 1000, "{column} {len}: {} bytes", shown.len());
        }
        let mut d = at("x", 1, 1);
        d.line = usize::MAX;
        assert!(d.to_string().contains(&format!(":{}:1", usize::MAX)));
    }

    #[test]
    fn long_leading_blanks_are_cut_and_blank_lines_have_no_excerpt() {
        let line = format!("{}R= -1", " ".repeat(40));
        let (excerpt, column, carets) = excerpt_and_carets(&at(&line, 41, 2).to_string());
        assert_eq!((excerpt.as_str(), column, carets), ("…    R= -1", 5, 2));
        let tabs = format!("{}R= -1", "\t".repeat(10));
        assert_eq!(
            excerpt_and_carets(&at(&tabs, 11, 2).to_string()).0,
            "…    R= -1"
        );
        // A caret among the blanks stays where it points.
        let (excerpt, column, _) = excerpt_and_carets(&at(&line, 31, 1).to_string());
        assert_eq!(column, 5);
        assert_eq!(excerpt, format!("…{}R= -1", " ".repeat(14)));
        for blank in ["", "   ", "\t"] {
            let shown = at(blank, 1, 1).to_string();
            assert_eq!(shown, "error: unknown word\n --> s.txt:3:1", "{blank:?}");
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config {
            cases: 2000,
            failure_persistence: None,
            rng_seed: proptest::test_runner::RngSeed::Fixed(29),
            ..proptest::test_runner::Config::default()
        })]

        /// Whatever a hand-made diagnostic holds, it renders without a panic,
        /// short, and with nothing hidden shown raw.
        #[test]
        fn any_diagnostic_renders_small_and_escaped(
            line in "[ a\t中\u{301}\u{feff}\u{202e}\u{2028}\u{1b}\r]{0,400}|\\PC{0,50}",
            column in proptest::prop_oneof![0usize..500, proptest::prelude::any::<usize>()],
            len in proptest::prop_oneof![0usize..500, proptest::prelude::any::<usize>()],
            number in proptest::prop_oneof![0usize..20, proptest::prelude::any::<usize>()],
        ) {
            let mut d = at(&line, column, len);
            d.line = number;
            for shown in [d.render(false), d.render(true)] {
                proptest::prop_assert!(shown.len() < 2000, "{} bytes: {shown}", shown.len());
                proptest::prop_assert!(
                    !shown.chars().any(|c| hidden(c) && c != '\n' && c != '\u{1b}'),
                    "{shown:?}"
                );
            }
            let plain = d.render(false);
            proptest::prop_assert!(!plain.contains('\u{1b}'), "{plain:?}");
        }
    }
}
