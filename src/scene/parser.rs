//! The scene-file parser: splits the file into blocks (`background`,
//! `camera`, `light TYPE`, `primitive TYPE` ... `end`), reads each block's
//! `key= values` lines and hands them to [`super::build`], collecting every
//! error and warning with the place in the file it is about.

use super::build::{BlockKind, Builder, Entry, LIGHT_TYPES, PRIMITIVE_TYPES};
use super::lexer::{self, Line, Word};
use super::suggest::closest;
use super::{Diagnostic, Scene, SceneError, Severity};
use std::path::Path;

/// The words that open a block.
const HEADERS: [&str; 4] = ["background", "camera", "light", "primitive"];

/// A place in the file: 0-based line index, 1-based column, width (chars).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Site {
    /// 0-based index into the file's lines.
    pub line: usize,
    /// 1-based column in characters.
    pub col: usize,
    /// Width in characters.
    pub len: usize,
}

impl Site {
    /// The site of one word.
    pub fn word(line: usize, w: &Word<'_>) -> Site {
        Site {
            line,
            col: w.col,
            len: w.len.max(1),
        }
    }

    /// From the start of `a` to the end of `b` (same line).
    pub fn span(line: usize, a: &Word<'_>, b: &Word<'_>) -> Site {
        Site {
            line,
            col: a.col,
            len: (b.col + b.len).saturating_sub(a.col).max(1),
        }
    }

    /// The column just after `w` (where a missing word was expected).
    pub fn after(line: usize, w: &Word<'_>) -> Site {
        Site {
            line,
            col: w.col + w.len + 1,
            len: 1,
        }
    }
}

/// Collects diagnostics, turning [`Site`]s into file/line/column/excerpt.
/// The excerpts (`source_line`) are filled in one pass over the text at the
/// end, so reading keeps nothing per line of the file.
pub(crate) struct Diags {
    file: String,
    out: Vec<Diagnostic>,
    errors: usize,
}

impl Diags {
    fn new(file: String) -> Self {
        Diags {
            file,
            out: Vec::new(),
            errors: 0,
        }
    }

    fn push(&mut self, severity: Severity, site: Site, message: String, help: Option<String>) {
        let source_line = String::new();
        if severity == Severity::Error {
            self.errors += 1;
        }
        self.out.push(Diagnostic {
            severity,
            message,
            file: self.file.clone(),
            line: site.line + 1,
            column: site.col.max(1),
            len: site.len.max(1),
            source_line,
            help,
        });
    }

    /// Records an error (the scene will not render).
    pub fn error(&mut self, site: Site, message: impl Into<String>, help: Option<String>) {
        self.push(Severity::Error, site, message.into(), help);
    }

    /// Records a warning (the scene still renders).
    pub fn warn(&mut self, site: Site, message: impl Into<String>, help: Option<String>) {
        self.push(Severity::Warning, site, message.into(), help);
    }

    /// Number of errors so far.
    pub fn error_count(&self) -> usize {
        self.errors
    }

    /// The diagnostics in file order, each with the text of its line.
    fn into_sorted(self, text: &str) -> Vec<Diagnostic> {
        let mut all = self.out;
        // Stable: diagnostics found at the same place keep the order they were found in.
        all.sort_by_key(|d| (d.line, d.column));
        let mut next = all.iter_mut().peekable();
        for (i, line) in lexer::lex(text).enumerate() {
            while let Some(d) = next.next_if(|d| d.line <= i + 1) {
                if d.line == i + 1 {
                    d.source_line = line.text.to_string();
                }
            }
            if next.peek().is_none() {
                break;
            }
        }
        all
    }
}

pub(super) fn parse_file(path: &Path) -> Result<Scene, SceneError> {
    let bytes = std::fs::read(path).map_err(|e| SceneError {
        diagnostics: vec![Diagnostic {
            severity: Severity::Error,
            message: format!("cannot read the scene file: {e}"),
            file: path.display().to_string(),
            line: 0,
            column: 0,
            len: 0,
            source_line: String::new(),
            help: None,
        }],
    })?;
    // Old files carry Latin-1 comments; those bytes only ever matter in comments.
    let text = String::from_utf8_lossy(&bytes);
    let dir = path.parent().unwrap_or(Path::new("."));
    parse_str(&text, Some(path), dir)
}

/// A block being read: its kind (`None` when the header was wrong, so its
/// lines are skipped), header site and entries.
struct Open<'a> {
    kind: Option<BlockKind>,
    header: Site,
    entries: Vec<Entry<'a>>,
    /// 0-based index among `primitive` blocks (primitives only).
    index: Option<u32>,
}

pub(super) fn parse_str(text: &str, path: Option<&Path>, base: &Path) -> Result<Scene, SceneError> {
    let file = path.map_or_else(|| "<input>".to_string(), |p| p.display().to_string());
    let mut diags = Diags::new(file);
    let mut builder = Builder::new(base, path);
    let mut open: Option<Open<'_>> = None;
    // After text outside a block, stay quiet until the next header: one
    // error per misspelt header, not one per line of its block.
    let mut skipping = false;

    for (i, line) in lexer::lex(text).enumerate() {
        let line = &line;
        let Some(first) = line.words.first() else {
            continue;
        };
        if let Some(block) = open.as_mut() {
            if first.text == "end" {
                if let Some(extra) = line.words.get(1) {
                    let last = line.words.last().unwrap_or(extra);
                    diags.warn(
                        Site::span(i, extra, last),
                        "text after `end` is ignored",
                        None,
                    );
                }
                if let Some(block) = open.take() {
                    finish(block, &mut builder, &mut diags);
                }
                continue;
            }
            if !HEADERS.contains(&first.text) {
                read_line(block, i, line, &mut diags);
                continue;
            }
            let header = block.header;
            diags.error(
                header,
                "this block has no `end`",
                Some(format!("expected a line `end` before line {}", i + 1)),
            );
            if let Some(block) = open.take() {
                finish(block, &mut builder, &mut diags);
            }
        }
        if first.text == "end" {
            if !skipping {
                diags.error(Site::word(i, first), "`end` without a block to close", None);
            }
            skipping = false;
            continue;
        }
        match header(i, line, &mut diags, &mut builder) {
            Some(block) => {
                open = Some(block);
                skipping = false;
            }
            None if !skipping => {
                let help = closest(first.text, &HEADERS).map(|h| format!("did you mean `{h}`?"));
                let last = line.words.last().unwrap_or(first);
                diags.error(
                    Site::span(i, first, last),
                    format!(
                        "text outside a block: expected a block header (`background`, `camera`, \
                         `light TYPE` or `primitive TYPE`), found `{}`",
                        first.text
                    ),
                    help,
                );
                skipping = true;
            }
            None => {}
        }
    }
    if let Some(block) = open.take() {
        diags.error(
            block.header,
            "this block has no `end`",
            Some("expected a line `end` before the end of the file".to_string()),
        );
        finish(block, &mut builder, &mut diags);
    }

    let mut scene = builder.finish();
    let errors = diags.error_count();
    let all = diags.into_sorted(text);
    if errors > 0 {
        return Err(SceneError { diagnostics: all });
    }
    scene.warnings = all;
    Ok(scene)
}

/// Reads a header line; `None` (with no diagnostic) when the first word is
/// not a header word, `Some` with `kind: None` when it is but its type is wrong.
fn header<'a>(
    i: usize,
    line: &Line<'a>,
    diags: &mut Diags,
    builder: &mut Builder<'_>,
) -> Option<Open<'a>> {
    let first = line.words.first()?;
    let mut index = None;
    let (kind, used) = match first.text {
        "background" => (Some(BlockKind::Background), 1),
        "camera" => (Some(BlockKind::Camera), 1),
        "light" | "primitive" => {
            let is_light = first.text == "light";
            let types: &[&str] = if is_light {
                &LIGHT_TYPES
            } else {
                &PRIMITIVE_TYPES
            };
            if !is_light {
                index = Some(builder.next_primitive_block());
            }
            let what = first.text;
            // Only for error messages: built when one is reported.
            let list = || {
                types
                    .iter()
                    .map(|t| format!("`{t}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            match line.words.get(1) {
                None => {
                    diags.error(
                        Site::after(i, first),
                        format!("expected a {what} type after `{what}`"),
                        Some(format!("the {what} types are {}", list())),
                    );
                    (None, 1)
                }
                Some(t) => {
                    let kind = if is_light {
                        BlockKind::light(t.text)
                    } else {
                        BlockKind::primitive(t.text)
                    };
                    if kind.is_none() {
                        let help = match closest(t.text, types) {
                            Some(s) => format!("did you mean `{s}`?"),
                            None => format!("the {what} types are {}", list()),
                        };
                        diags.error(
                            Site::word(i, t),
                            format!("unknown {what} type `{}`", t.text),
                            Some(help),
                        );
                    }
                    (kind, 2)
                }
            }
        }
        _ => return None,
    };
    let header_end = line.words.get(used - 1).unwrap_or(first);
    if let (Some(extra), Some(last)) = (line.words.get(used), line.words.last()) {
        diags.warn(
            Site::span(i, extra, last),
            format!("text after the `{}` header is ignored", first.text),
            None,
        );
    }
    Some(Open {
        kind,
        header: Site::span(i, first, header_end),
        entries: Vec::new(),
        index,
    })
}

/// Reads one line inside a block into an [`Entry`] (or diagnoses it).
fn read_line<'a>(block: &mut Open<'a>, i: usize, line: &Line<'a>, diags: &mut Diags) {
    let Some(kind) = block.kind else {
        return;
    };
    let Some(first) = line.words.first() else {
        return;
    };
    let rest = line.words.get(1..).unwrap_or(&[]);
    let (key, key_site, values): (&str, Site, Vec<Word<'a>>) =
        if let Some(eq) = first.text.find('=') {
            // `key= v ...` or `key=v ...`.
            let key = &first.text[..eq];
            let key_chars = key.chars().count();
            let mut values = Vec::with_capacity(rest.len() + 1);
            let glued = first.split_off(key_chars + 1);
            if !glued.text.is_empty() {
                values.push(glued);
            }
            values.extend_from_slice(rest);
            let site = Site {
                line: i,
                col: first.col,
                len: key_chars + 1,
            };
            (key, site, values)
        } else if let Some(eq) = rest.first().filter(|w| w.text.starts_with('=')) {
            // `key = v ...` or `key =v ...`.
            let mut values = Vec::with_capacity(rest.len());
            let glued = eq.split_off(1);
            if !glued.text.is_empty() {
                values.push(glued);
            }
            values.extend_from_slice(&rest[1..]);
            (first.text, Site::span(i, first, eq), values)
        } else {
            bare_word(kind, i, line, diags);
            return;
        };
    if key.is_empty() {
        diags.error(
            key_site,
            "expected a key before `=`",
            Some("lines in a block look like `key= values`".to_string()),
        );
        return;
    }
    block.entries.push(Entry {
        key,
        key_site,
        values,
        line: i,
        raw: line.text,
    });
}

/// A line inside a block whose first word is not `key=`.
fn bare_word(kind: BlockKind, i: usize, line: &Line<'_>, diags: &mut Diags) {
    let Some(first) = line.words.first() else {
        return;
    };
    let last = line.words.last().unwrap_or(first);
    if first.text == "Cylinder" {
        // The framework's bezier needs it to build its bounds; glint does not.
        if kind == BlockKind::Primitive(super::build::PrimitiveType::Bezier) {
            if let Some(extra) = line.words.get(1) {
                diags.warn(
                    Site::span(i, extra, last),
                    "text after `Cylinder` is ignored",
                    None,
                );
            }
        } else {
            diags.warn(
                Site::word(i, first),
                format!(
                    "`Cylinder` only means something in a `primitive bezier` block; ignored in a `{}` block",
                    kind.name()
                ),
                None,
            );
        }
        return;
    }
    let keys = kind.key_names();
    if keys.contains(&first.text) {
        diags.error(
            Site::word(i, first),
            format!("expected `=` after `{}`", first.text),
            Some(format!("write `{}= ...`", first.text)),
        );
        return;
    }
    let mut candidates: Vec<&str> = keys;
    candidates.push("end");
    let help = closest(first.text, &candidates).map(|c| {
        if c == "end" {
            "did you mean `end`?".to_string()
        } else {
            format!("did you mean `{c}=`?")
        }
    });
    diags.error(
        Site::span(i, first, last),
        format!(
            "expected `key= values` or `end` in a `{}` block, found `{}`",
            kind.name(),
            first.text
        ),
        help,
    );
}

/// Hands a complete block to the builder.
fn finish(block: Open<'_>, builder: &mut Builder<'_>, diags: &mut Diags) {
    if let Some(kind) = block.kind {
        builder.block(
            kind,
            block.header,
            &block.entries,
            block.index.unwrap_or(0),
            diags,
        );
    }
}
