//! The scene-file reader: splits the file into blocks (`background`,
//! `camera`, `light TYPE`, `primitive TYPE` ... `end`), reads each block's
//! `key= values` lines and hands them to the [`Builder`], collecting every
//! error and warning with the place in the file it is about. With two
//! threads the reading of lines and the building of blocks run at once,
//! the blocks passing between them in batches; the scene and its
//! diagnostics are the same on one thread.

use super::builder::Builder;
use super::detect::Evidence;
use super::diags::{DiagCounts, Diags, Site, When};
use super::lexer::{self, Line, Word};
use super::limits::{Limits, LineGuard, ReadError, open_regular};
use super::schema::{self, BlockKind, LIGHTS, PRIMITIVES};
use super::suggest::closest;
use super::values::Entry;
use crate::scene::{Diagnostic, Dialect, Scene, SceneError, Severity};
use std::io::Read;
use std::path::Path;
use std::sync::mpsc::{Receiver, Sender, channel};

/// The words that open a block (`object`: W's `primitive`; `obj`: abcbdf's).
const HEADERS: [&str; 6] = [
    "background",
    "camera",
    "light",
    "primitive",
    "object",
    "obj",
];

/// How much of a scene file is read at a time. Each piece costs one start
/// and end of the two-thread pass: 4 MiB reads the million spheres 3–4 %
/// faster than 1 MiB; 16 MiB was slower than 4 MiB (docs/performance.md).
const CHUNK: usize = 1 << 22;

pub(crate) fn parse_file(path: &Path, dialect: Option<Dialect>) -> Result<Scene, SceneError> {
    let file = open_regular(path).map_err(|e| read_error(path, &e, 0))?;
    let size = file.metadata().ok().map(|m| m.len());
    let dir = path.parent().unwrap_or(Path::new("."));
    parse_chunked(file, size, path, dir, CHUNK, Limits::DEFAULT, dialect)
}

/// The error for a scene file that cannot be read: at `FILE:LINE:1` for a
/// line too long, else the file as a whole (line 0).
fn read_error(path: &Path, e: &dyn std::fmt::Display, line: usize) -> SceneError {
    SceneError {
        diagnostics: vec![Diagnostic {
            severity: Severity::Error,
            message: format!("cannot read the scene file: {e}"),
            file: path.display().to_string(),
            line,
            column: usize::from(line > 0),
            len: 0,
            source_line: String::new(),
            help: None,
        }],
    }
}

/// Parses a scene file from `input`, reading about `chunk` bytes at a time
/// and keeping only the text not yet parsed, within `limits`; `size`, the
/// input's length if known, lets the scene make room for what is to come.
fn parse_chunked(
    mut input: impl Read,
    size: Option<u64>,
    path: &Path,
    base: &Path,
    chunk: usize,
    limits: Limits,
    dialect: Option<Dialect>,
) -> Result<Scene, SceneError> {
    let chunk = chunk.max(1);
    let mut guard = LineGuard::new(limits);
    let mut reader = Parse::new(Some(path), base, dialect, true);
    // The text not yet parsed, read into one buffer (no copy): the block
    // still open, then the bytes read since. It is valid UTF-8 up to
    // `valid`, which ends a line.
    let mut buf: Vec<u8> = Vec::new();
    let mut valid = 0;
    let mut start_of_file = true;
    // Bytes of the input parsed so far (the block still open not counted).
    let mut parsed: u64 = 0;
    loop {
        // A block still open is parsed again from its header after each
        // read; reading an eighth of it at least keeps a huge one linear.
        let want = chunk.max(valid / 8);
        let old = buf.len();
        buf.reserve(want);
        let got = (&mut input)
            .take(want as u64)
            .read_to_end(&mut buf)
            .map_err(|e| read_error(path, &ReadError::Io(e), 0))?;
        let line_end = guard
            .check(buf.get(old..).unwrap_or_default())
            .map_err(|e| {
                let line = match e {
                    ReadError::LineTooLong { line, .. } => line,
                    _ => 0,
                };
                read_error(path, &e, line)
            })?;
        let last = got == 0;
        // Cut after a `\n`: no `\r\n`, no UTF-8 character is split, and
        // `from_utf8_lossy` of each piece is that of the whole file.
        let mut cut = if last {
            buf.len()
        } else {
            match line_end {
                Some(end) => old + end,
                None => continue,
            }
        };
        let carry = loop {
            match std::str::from_utf8(buf.get(..cut).unwrap_or_default()) {
                Ok(text) => {
                    let bom = if start_of_file {
                        text.len() - reader.strip_bom(text).len()
                    } else {
                        0
                    };
                    break bom + reader.feed(&text[bom..], last);
                }
                // Old files carry Latin-1 comments; those bytes only ever
                // matter in comments: they are read as U+FFFD. (The text
                // before `valid` is valid and left as it is: the fault is
                // in the new piece.)
                Err(_) => {
                    let piece = buf.get(..cut).unwrap_or_default();
                    let fixed = String::from_utf8_lossy(piece).into_owned().into_bytes();
                    let len = fixed.len();
                    buf.splice(..cut, fixed);
                    cut = len;
                }
            }
        };
        start_of_file = false;
        if last {
            break;
        }
        parsed += carry.min(cut) as u64;
        if let Some(size) = size {
            reader
                .builder
                .anticipate(parsed, size.saturating_sub(parsed));
        }
        buf.drain(..carry.min(cut));
        valid = cut - carry.min(cut);
    }
    reader.finish()
}

pub(crate) fn parse_str(
    text: &str,
    path: Option<&Path>,
    base: &Path,
    dialect: Option<Dialect>,
) -> Result<Scene, SceneError> {
    parse_text(text, path, base, dialect, true)
}

/// [`parse_str`], looking up the files the scene names only if `files`
/// (otherwise none is found, and the file system is not touched).
pub(crate) fn parse_text(
    text: &str,
    path: Option<&Path>,
    base: &Path,
    dialect: Option<Dialect>,
    files: bool,
) -> Result<Scene, SceneError> {
    let mut reader = Parse::new(path, base, dialect, files);
    let text = reader.strip_bom(text);
    reader.feed(text, true);
    reader.finish()
}

/// A block being read: its kind (`None` when the header was wrong, so its
/// lines are skipped), header site and entries.
struct Open<'a> {
    kind: Option<BlockKind>,
    header: Site,
    /// The header word and the type after it, as written.
    head: &'a str,
    type_word: Option<&'a str>,
    entries: Vec<Entry<'a>>,
    /// The values of all its entries, which hold ranges of it.
    values: Vec<Word<'a>>,
    /// Whether it is a `primitive` block (they are numbered when finished).
    primitive: bool,
    /// The line of its first `key:` when its keys are written so (the
    /// colon family's block, read by that family's row of the schema).
    colon: Option<usize>,
}

/// A finished block's vectors, emptied, for the next block.
type Spare<'a> = (Vec<Entry<'a>>, Vec<Word<'a>>);

impl<'a> Open<'a> {
    /// Its vectors, emptied, for the next block (once it is built).
    fn into_spare(self) -> Spare<'a> {
        let (mut entries, mut values) = (self.entries, self.values);
        entries.clear();
        values.clear();
        (entries, values)
    }
}

/// Where the block still open began, and the state just before its header,
/// to read it again from there with the next piece of text.
#[derive(Clone, Copy, Default)]
struct Mark {
    /// Byte offset of the header line in the piece.
    start: usize,
    /// 0-based line of the header in the file.
    line: usize,
    /// The diagnostics recorded before the header (`skipping` needs no
    /// saving: the header line clears it when read again).
    diags: DiagCounts,
}

/// Blocks a batch holds before it goes to the builder.
const BATCH: usize = 256;

/// Where the reader puts the blocks it completes: batches sent to the
/// builder, which come back once built, their blocks' vectors emptied
/// for more blocks.
struct Batches<'a> {
    current: Vec<Open<'a>>,
    send: Sender<Vec<Open<'a>>>,
    back: Receiver<Vec<Open<'a>>>,
    /// Emptied vectors for the next blocks.
    spares: Vec<Spare<'a>>,
}

impl<'a> Batches<'a> {
    /// Batches sent on `send`, coming back on `back`.
    fn new(send: Sender<Vec<Open<'a>>>, back: Receiver<Vec<Open<'a>>>) -> Self {
        Batches {
            current: Vec::with_capacity(BATCH),
            send,
            back,
            spares: Vec::new(),
        }
    }

    /// Records `block`; returns emptied vectors for the next block.
    fn push(&mut self, block: Open<'a>) -> Spare<'a> {
        self.current.push(block);
        if self.current.len() >= BATCH {
            self.flush();
        }
        if self.spares.is_empty()
            && let Ok(batch) = self.back.try_recv()
        {
            self.spares.extend(batch.into_iter().map(Open::into_spare));
        }
        self.spares.pop().unwrap_or_default()
    }

    /// Sends the blocks recorded so far to the builder.
    fn flush(&mut self) {
        if self.current.is_empty() {
            return;
        }
        let full = std::mem::replace(&mut self.current, Vec::with_capacity(BATCH));
        // The builder's end stays open while any batch may come.
        let _ = self.send.send(full);
    }
}

/// Where the reader puts the blocks it completes.
enum Sink<'a, 'b, 'p> {
    /// Each built at once, on this thread (a pool of one thread).
    Inline {
        builder: &'b mut Builder<'p>,
        diags: &'b mut Diags,
    },
    /// In batches, to the builder on another thread.
    Batches(Batches<'a>),
}

impl<'a> Sink<'a, '_, '_> {
    /// Records `block`, complete, with the markers it shows into `marks`;
    /// returns emptied vectors for the next block.
    fn complete(&mut self, block: Open<'a>, marks: &mut Evidence) -> Spare<'a> {
        marks.block(
            block.header.line,
            block.head,
            block.type_word,
            block.entries.iter().map(|e| e.key),
        );
        if let Some(line) = block.colon {
            marks.colon(line);
        }
        match self {
            Sink::Inline { builder, diags } => {
                build(&block, builder, diags);
                block.into_spare()
            }
            Sink::Batches(batches) => batches.push(block),
        }
    }
}

/// Builds `block`, the next in file order.
fn build(block: &Open<'_>, builder: &mut Builder<'_>, diags: &mut Diags) {
    // Numbered here, not at the header: a block read again with the next
    // piece of the file must not take a second number.
    let index = if block.primitive {
        builder.next_primitive_block()
    } else {
        0
    };
    match (block.kind, block.type_word) {
        (Some(kind), _) => builder.block(
            kind,
            block.header,
            &block.entries,
            &block.values,
            index,
            diags,
        ),
        (None, Some(_)) if block.colon.is_some() => {}
        (None, Some(t)) => unknown_type(block, t, diags),
        (None, None) => {}
    }
}

/// A scene file being read, piece by piece: the reader of its lines and
/// the builder of its blocks, which work at once (the builder a batch of
/// blocks behind), each with its own diagnostics, merged at the end.
struct Parse<'p> {
    reader: Reader,
    builder: Builder<'p>,
    /// The builder's diagnostics.
    built: Diags,
}

impl<'p> Parse<'p> {
    /// The reading of the file `path` (`None`: a string), resolving relative
    /// paths against `base` first (looking for no file unless `files`).
    fn new(path: Option<&Path>, base: &'p Path, dialect: Option<Dialect>, files: bool) -> Self {
        let file = path.map_or_else(|| "<input>".to_string(), |p| p.display().to_string());
        Parse {
            reader: Reader::new(file.clone(), dialect),
            builder: Builder::new(base, path, files),
            built: Diags::new(file),
        }
    }

    /// The file's first text without a UTF-8 byte-order mark, noting one.
    fn strip_bom<'t>(&mut self, text: &'t str) -> &'t str {
        self.reader.strip_bom(text)
    }

    /// Reads and builds the next piece of the file (see [`Reader::feed`]):
    /// the reader on this thread, the builder on another when the pool
    /// has one, the batches between them. Returns where the block still
    /// open begins.
    fn feed(&mut self, text: &str, last: bool) -> usize {
        let Parse {
            reader,
            builder,
            built,
        } = self;
        let (first_line, first_built) = (reader.line, built.count());
        let carry = if rayon::current_num_threads() == 1 {
            let mut out = Sink::Inline {
                builder,
                diags: built,
            };
            reader.feed(text, last, &mut out)
        } else {
            let (send, batches) = channel::<Vec<Open<'_>>>();
            let (give_back, back) = channel();
            let (carry, ()) = rayon::join(
                || {
                    let mut out = Sink::Batches(Batches::new(send, back));
                    let carry = reader.feed(text, last, &mut out);
                    if let Sink::Batches(mut batches) = out {
                        batches.flush();
                    }
                    carry
                },
                || {
                    for batch in batches {
                        for block in &batch {
                            build(block, builder, built);
                        }
                        let _ = give_back.send(batch);
                    }
                },
            );
            carry
        };
        built.fill_source_lines(first_built, text, first_line);
        carry
    }

    /// The scene, or every error; warnings and errors in file order.
    fn finish(self) -> Result<Scene, SceneError> {
        let Parse {
            mut reader,
            mut builder,
            built,
        } = self;
        reader.diags.append(built);
        builder.evidence.absorb(std::mem::take(&mut reader.marks));
        for note in std::mem::take(&mut reader.notes) {
            builder.note(note);
        }
        reader.finish(builder)
    }
}

/// The reading of a scene file's lines into blocks, piece by piece: what
/// lives from one piece of text to the next.
struct Reader {
    diags: Diags,
    /// The markers of the lineages the blocks show (the builder adds what
    /// their values show at the end).
    marks: Evidence,
    /// Notes about the file as a whole, in the order found.
    notes: Vec<String>,
    /// After text outside a block, stay quiet until the next header: one
    /// error per misspelt header, not one per line of its block.
    skipping: bool,
    /// 0-based line of the file where the next piece starts.
    line: usize,
    /// The dialect asked for (`--dialect`), if any.
    dialect: Option<Dialect>,
    /// Whether any block header was read.
    any_block: bool,
    /// The first text outside a block, if any.
    first_outside: Option<Site>,
    /// The first line outside a block that reads as a block's header (a
    /// word, not a `key=`): a skipped block.
    first_skipped: Option<Site>,
    /// Its first word.
    first_skipped_word: String,
    /// Whether reading stopped at a word `end` outside a block (lazycal's reader).
    stopped: bool,
}

impl Reader {
    /// A reader of the file named `file` in messages, in dialect `dialect` if given.
    fn new(file: String, dialect: Option<Dialect>) -> Self {
        Reader {
            diags: Diags::new(file),
            marks: Evidence::default(),
            notes: Vec::new(),
            skipping: false,
            line: 0,
            dialect,
            any_block: false,
            first_outside: None,
            first_skipped: None,
            first_skipped_word: String::new(),
            stopped: false,
        }
    }

    /// Whether a word `end` outside a block ends the file: lazycal's reader
    /// stops there, so glint does in its dialect (asked for, or marked by
    /// the blocks read so far).
    fn stops_at_end(&self) -> bool {
        match self.dialect {
            Some(d) => d == Dialect::L17,
            None => self.marks.lazycal(),
        }
    }

    /// The file's first text without a UTF-8 byte-order mark, noting one.
    fn strip_bom<'t>(&mut self, text: &'t str) -> &'t str {
        let stripped = lexer::strip_bom(text);
        if stripped.len() != text.len() {
            self.notes.push(
                "a UTF-8 byte-order mark opens the file: skipped (the lineages' readers \
                 would lose the first block to it)"
                    .to_string(),
            );
        }
        stripped
    }

    /// Reads the next piece of the file: whole lines (ending in `\n` unless
    /// `last`), each complete block into `out`. Returns the byte offset where
    /// the block still open at its end begins, to be fed again in front of
    /// the next piece; `text.len()` if none.
    fn feed<'t>(&mut self, text: &'t str, last: bool, out: &mut Sink<'t, '_, '_>) -> usize {
        let first_line = self.line;
        let first_diag = self.diags.count();
        let mut lines = 0;
        let mut open: Option<Open<'_>> = None;
        let mut spare = Spare::default();
        let mut mark = Mark::default();

        let mut lexer = lexer::Lexer::new(text);
        while let Some(line) = lexer.next_line() {
            if self.stopped {
                break;
            }
            let i = first_line + lines;
            lines += 1;
            let line = &line;
            let Some(first) = line.words.first() else {
                if open.is_none() {
                    comment_header(i, line, &mut self.diags);
                }
                continue;
            };
            if let Some(block) = open.as_mut() {
                if first.text == "end" {
                    if let Some(extra) = line.words.get(1) {
                        let last = line.words.last().unwrap_or(extra);
                        self.diags.warn(
                            Site::span(i, extra, last),
                            "text after `end` is ignored",
                            None,
                        );
                    }
                    if let Some(block) = open.take() {
                        spare = out.complete(block, &mut self.marks);
                    }
                    continue;
                }
                if !HEADERS.contains(&first.text) {
                    read_line(block, i, line, &mut self.diags);
                    continue;
                }
                let header = block.header;
                self.diags.warn(
                    header,
                    "this block has no `end`; it ends at the next header",
                    Some(format!("add a line `end` before line {}", i + 1)),
                );
                if let Some(block) = open.take() {
                    spare = out.complete(block, &mut self.marks);
                }
            }
            if first.text == "end" && self.stops_at_end() {
                self.notes.push(format!(
                    "line {}: lazycal's reader stops at a word `end` outside a block: the \
                     rest of the file is not read",
                    i + 1
                ));
                self.stopped = true;
                continue;
            }
            if first.text == "end" {
                if !self.skipping {
                    self.diags.warn(
                        Site::word(i, first),
                        "`end` without a block to close; ignored",
                        None,
                    );
                }
                self.skipping = false;
                continue;
            }
            mark = Mark {
                start: line.start,
                line: i,
                diags: self.diags.counts(),
            };
            match header(i, line, &mut self.diags, &mut spare) {
                Some(block) => {
                    open = Some(block);
                    self.skipping = false;
                    self.any_block = true;
                }
                None if !self.skipping => {
                    let help =
                        closest(first.text, &HEADERS).map(|h| format!("did you mean `{h}`?"));
                    let last = line.words.last().unwrap_or(first);
                    let site = Site::span(i, first, last);
                    self.first_outside.get_or_insert(site);
                    // A would-be header (a word, not a `key=`): the block it opened was skipped.
                    if self.first_skipped.is_none() && !first.text.contains('=') {
                        self.first_skipped = Some(site);
                        self.first_skipped_word = first.text.chars().take(40).collect();
                    }
                    // A binary file's "word" can be very long: quote its start.
                    let found: String = first.text.chars().take(40).collect();
                    let cut = if found.len() < first.text.len() {
                        "…"
                    } else {
                        ""
                    };
                    self.diags.warn(
                        site,
                        format!(
                            "text outside a block, skipped up to the next `end` or block \
                             header: expected a block header (`background`, `camera`, \
                             `light TYPE` or `primitive TYPE`), found `{found}{cut}`"
                        ),
                        help,
                    );
                    self.skipping = true;
                }
                None => {}
            }
        }

        let mut carry = text.len();
        self.line = first_line + lines;
        if let Some(block) = open.take() {
            if last {
                self.diags.warn(
                    block.header,
                    "this block has no `end`; it ends at the end of the file",
                    Some("add a line `end`".to_string()),
                );
                out.complete(block, &mut self.marks);
            } else {
                // Forget the block's lines: they are read again, whole, with the next piece.
                self.diags.rollback(mark.diags);
                self.line = mark.line;
                carry = mark.start;
            }
        }
        self.diags.fill_source_lines(first_diag, text, first_line);
        carry
    }

    /// The scene built by `builder` from the blocks read, or every error;
    /// warnings and errors in file order.
    fn finish(mut self, builder: Builder<'_>) -> Result<Scene, SceneError> {
        if let (false, Some(site)) = (self.any_block, self.first_outside) {
            self.diags.error(
                site,
                "no block in the file: this is not a scene file",
                Some(
                    "a scene is made of `camera`, `light TYPE`, `primitive TYPE` ... `end` blocks"
                        .to_string(),
                ),
            );
            self.diags.share_source_lines();
        }
        let (choice, warning) = builder.evidence.choose(self.dialect);
        if let Some(w) = warning {
            self.diags.warn(
                Site {
                    line: 0,
                    col: 1,
                    len: 1,
                },
                w,
                None,
            );
        }
        self.diags.settle(choice.dialect);
        let mut scene = builder.finish(choice);
        if let (true, true, Some(site)) = (
            self.any_block,
            scene.objects().is_empty(),
            self.first_skipped,
        ) {
            // Every primitive skipped: an error, never an empty picture.
            let word = &self.first_skipped_word;
            let like = match word.to_ascii_lowercase().as_str() {
                "objects" | "shape" | "geometry" => {
                    format!("`{word}` reads like `primitive` (e.g. `primitive sphere`)")
                }
                _ => closest(word, &HEADERS).map_or_else(
                    || "it is no block header glint knows".to_string(),
                    |h| format!("`{word}` reads like `{h}`"),
                ),
            };
            self.diags.error(
                site,
                format!(
                    "nothing to render: no primitive was read, and this block was skipped; {like}"
                ),
                Some(
                    "write primitives as `primitive TYPE` ... `end` blocks (docs/format.md)"
                        .to_string(),
                ),
            );
            self.diags.share_source_lines();
        }
        let errors = self.diags.error_count();
        let all = self.diags.into_sorted();
        if errors > 0 {
            return Err(SceneError { diagnostics: all });
        }
        scene.set_warnings(all);
        Ok(scene)
    }
}

/// Reads a header line; `None` (with no diagnostic) when the first word is
/// not a header word, `Some` with `kind: None` when it is but its type is
/// missing or unknown (the block is skipped, with a warning at its end).
/// The block takes the vectors of `spare` (the last block's, emptied: no
/// allocation per block).
fn header<'a>(
    i: usize,
    line: &Line<'a, '_>,
    diags: &mut Diags,
    spare: &mut Spare<'a>,
) -> Option<Open<'a>> {
    let first = line.words.first()?;
    let type_word = line.words.get(1);
    let (kind, used) = match first.text {
        "background" => (Some(&schema::BACKGROUND), 1),
        "camera" => (Some(&schema::CAMERA), 1),
        "light" | "primitive" | "object" | "obj" => {
            let rows: &'static [schema::Row] = if first.text == "light" {
                &LIGHTS
            } else {
                &PRIMITIVES
            };
            if first.text == "object" {
                diags.warn_when(
                    When::NotIn(Dialect::W),
                    Site::word(i, first),
                    "`object` opens a primitive only in the W lineage's reader; read as `primitive`",
                    None,
                );
            }
            if first.text == "obj" {
                diags.warn_when(
                    When::NotIn(Dialect::A18),
                    Site::word(i, first),
                    "`obj` opens a primitive only in abcbdf's reader; read as `primitive`",
                    None,
                );
            }
            match type_word {
                None => {
                    let what = if first.text == "light" {
                        "light"
                    } else {
                        "primitive"
                    };
                    diags.warn(
                        Site::after(i, first),
                        format!(
                            "expected a {what} type after `{}`; block skipped",
                            first.text
                        ),
                        Some(format!("the {what} types are {}", type_list(rows))),
                    );
                    (None, 1)
                }
                Some(t) => (schema::find(rows, t.text), 2),
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
    let (entries, values) = std::mem::take(spare);
    Some(Open {
        kind,
        header: Site::span(i, first, header_end),
        head: first.text,
        type_word: type_word.filter(|_| used == 2).map(|w| w.text),
        entries,
        values,
        primitive: matches!(first.text, "primitive" | "object" | "obj"),
        colon: None,
    })
}

/// The types of `rows`, quoted, for messages.
fn type_list(rows: &'static [schema::Row]) -> String {
    rows.iter()
        .map(|r| format!("`{}`", r.name))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Warns at a block of unknown type `t` (skipped): says what glint reads,
/// suggesting a type only when every key of the block is one of its keys.
fn unknown_type(block: &Open<'_>, t: &str, diags: &mut Diags) {
    let rows: &'static [schema::Row] = if block.head == "light" {
        &LIGHTS
    } else {
        &PRIMITIVES
    };
    let what = if block.head == "light" {
        "light"
    } else {
        "primitive"
    };
    let fits = |name: &str| {
        schema::find(rows, name)
            .is_some_and(|row| block.entries.iter().all(|e| row.lookup(e.key).is_some()))
    };
    let help = match closest(t, &schema::names(rows)).filter(|s| fits(s)) {
        Some(s) => format!("did you mean `{s}`?"),
        None => format!("the {what} types are {}", type_list(rows)),
    };
    let site = Site {
        line: block.header.line,
        col: block.header.col,
        len: block.header.len,
    };
    diags.warn(
        site,
        format!("unknown {what} type `{t}`: no lineage reads it; block skipped"),
        Some(help),
    );
}

/// Reads one line inside a block into an [`Entry`] (or diagnoses it).
fn read_line<'a>(block: &mut Open<'a>, i: usize, line: &Line<'a, '_>, diags: &mut Diags) {
    let Some(first) = line.words.first() else {
        return;
    };
    if let Some(key) = first.text.strip_suffix(':').filter(|k| !k.is_empty()) {
        colon_line(block, key, i, line, diags);
        return;
    }
    let Some(kind) = block.kind else {
        // A skipped block: its keys only say what the block was.
        if let Some(eq) = first.text.find('=') {
            block.entries.push(Entry {
                key: &first.text[..eq],
                key_site: Site::word(i, first),
                values: 0..0,
                line: i,
                raw: line.text,
                colon: false,
            });
        }
        return;
    };
    let rest = line.words.get(1..).unwrap_or(&[]);
    // The words after `=`: the rest of a word glued to it, then the others.
    // (A byte search: `=` is ASCII, and a short word is not worth memchr's set-up.)
    let eq = first.text.bytes().position(|b| b == b'=');
    let (key, key_site, glued, rest) = if let Some(eq) = eq {
        // `key= v ...` or `key=v ...`.
        let key = &first.text[..eq];
        let key_chars = if key.is_ascii() {
            key.len()
        } else {
            key.chars().count()
        };
        let site = Site {
            line: i,
            col: first.col,
            len: key_chars + 1,
        };
        (key, site, first.split_off(key_chars + 1), rest)
    } else if let Some(eq) = rest.first().filter(|w| w.text.starts_with('=')) {
        // `key = v ...` or `key =v ...`.
        let site = Site::span(i, first, eq);
        (
            first.text,
            site,
            eq.split_off(1),
            rest.get(1..).unwrap_or(&[]),
        )
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
    let start = block.values.len();
    if !glued.text.is_empty() {
        block.values.push(glued);
    }
    block.values.extend_from_slice(rest);
    block.entries.push(Entry {
        key,
        key_site,
        values: start..block.values.len(),
        line: i,
        raw: line.text,
        colon: block.colon.is_some(),
    });
}

/// Reads a `key: values` line (the colon family's syntax). The block's
/// first such key makes it that family's block, read by its row of the
/// schema (hta1996/Raytracing `object.cpp`: `primitive`, `light`,
/// `camera` and `background` blocks of `key:` lines).
fn colon_line<'a>(
    block: &mut Open<'a>,
    key: &'a str,
    i: usize,
    line: &Line<'a, '_>,
    diags: &mut Diags,
) {
    let Some(first) = line.words.first() else {
        return;
    };
    let key_site = Site::word(i, first);
    if block.colon.is_none() {
        if !block.entries.is_empty() {
            diags.warn(
                key_site,
                format!(
                    "`{key}:` in a block of `key=` lines: only the colon family writes `key:`; ignored"
                ),
                Some(format!("did you mean `{key}=`?")),
            );
            return;
        }
        block.colon = Some(i);
        block.kind = schema::colon_row(block.head, block.type_word);
        if block.kind.is_none() {
            let what = match block.type_word {
                Some(t) => format!("{} {t}", block.head),
                None => block.head.to_string(),
            };
            diags.warn(
                block.header,
                format!("the colon family (`key:` lines) has no `{what}` block; skipped"),
                Some(format!(
                    "its blocks are {}",
                    schema::colon_titles()
                        .iter()
                        .map(|t| format!("`{t}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )),
            );
        }
    }
    if block.kind.is_none() {
        return;
    }
    let start = block.values.len();
    block
        .values
        .extend_from_slice(line.words.get(1..).unwrap_or(&[]));
    block.entries.push(Entry {
        key,
        key_site,
        values: start..block.values.len(),
        line: i,
        raw: line.text,
        colon: true,
    });
}

/// A line inside a block whose first word is not `key=`.
fn bare_word(kind: BlockKind, i: usize, line: &Line<'_, '_>, diags: &mut Diags) {
    let Some(first) = line.words.first() else {
        return;
    };
    let last = line.words.last().unwrap_or(first);
    if first.text == "Cylinder" {
        // The framework's bezier needs it to build its bounds; glint does not.
        if kind.title == "primitive bezier" {
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
                    kind.title
                ),
                None,
            );
        }
        return;
    }
    let keys = kind.key_names();
    if keys.contains(&first.text) {
        diags.warn(
            Site::span(i, first, last),
            format!(
                "`{}` without `=` is not read (no lineage's reader reads it); ignored",
                first.text
            ),
            Some(format!("did you mean `{}=`?", first.text)),
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
    diags.warn(
        Site::span(i, first, last),
        format!(
            "expected `key= values` or `end` in a `{}` block, found `{}`; ignored",
            kind.title, first.text
        ),
        help,
    );
}

/// Warns at a comment line outside a block that holds `light`,
/// `primitive` or `object`: a lineage's reader, which has no comments,
/// would open a block there and lose the next block to it. (A `camera` or
/// `background` there only reads the next block's lines as its own.)
fn comment_header(i: usize, line: &Line<'_, '_>, diags: &mut Diags) {
    for word in line.text.split_whitespace() {
        if matches!(word, "light" | "primitive" | "object") {
            // The word's 1-based column in characters.
            let at = line.text.find(word).unwrap_or(0);
            let site = Site {
                line: i,
                col: line.text[..at].chars().count() + 1,
                len: word.chars().count(),
            };
            // The framework's format documents comments: warned in the relatives' files only.
            diags.warn_when(
                When::NotIn(Dialect::F),
                site,
                format!(
                    "a comment with `{word}`: glint skips it, but the lineages' readers (which \
                     have no comments) would open a block here and lose the next one"
                ),
                None,
            );
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::common::corpus_scenes;
    use std::io;

    /// Chunk sizes to read the test files with: tiny ones cut every block.
    const SIZES: [usize; 9] = [1, 2, 3, 5, 7, 13, 64, 4096, CHUNK];

    /// The first difference between two parses, if any.
    fn difference(a: &Result<Scene, SceneError>, b: &Result<Scene, SceneError>) -> Option<String> {
        match (a, b) {
            (Ok(a), Ok(b)) => {
                let fields = [
                    ("path", a.path() == b.path()),
                    ("camera", a.camera() == b.camera()),
                    ("background", a.background() == b.background()),
                    ("materials", a.materials().eq(b.materials())),
                    ("textures", a.textures() == b.textures()),
                    ("lights", a.lights() == b.lights()),
                    // Objects have no `PartialEq`; `Debug` prints every float exactly.
                    (
                        "objects",
                        format!("{:?}", a.objects()) == format!("{:?}", b.objects()),
                    ),
                    ("warnings", a.warnings() == b.warnings()),
                    ("notes", a.notes() == b.notes()),
                ];
                let (name, _) = fields.iter().find(|(_, same)| !same)?;
                Some(format!("the scenes' {name} differ"))
            }
            (Err(a), Err(b)) => {
                if a.diagnostics == b.diagnostics {
                    return None;
                }
                let k = a
                    .diagnostics
                    .iter()
                    .zip(&b.diagnostics)
                    .position(|(x, y)| x != y)
                    .unwrap_or(a.diagnostics.len().min(b.diagnostics.len()));
                Some(format!(
                    "diagnostic {k} differs:\n{:#?}\nvs\n{:#?}",
                    a.diagnostics.get(k),
                    b.diagnostics.get(k)
                ))
            }
            (Ok(_), Err(e)) => Some(format!(
                "the first parse succeeded, the second failed:\n{e}"
            )),
            (Err(e), Ok(_)) => Some(format!(
                "the first parse failed, the second succeeded:\n{e}"
            )),
        }
    }

    /// Where the in-memory test files pretend to be (textures resolve there).
    fn mem_path() -> &'static Path {
        Path::new("tests/data/mem.txt")
    }

    /// A pool of `threads` threads: the reader and the builder share one
    /// thread in a pool of one, and work at once in a pool of two.
    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool") // invariant: the test machine starts two threads (every render test needs them)
    }

    /// Parses `bytes` as a whole text on two threads, then in chunks of
    /// every size in [`SIZES`] on two threads and on one, and checks every
    /// parse gives exactly the same; returns it.
    fn same_in_chunks(name: &str, bytes: &[u8]) -> Result<Scene, SceneError> {
        let base = Path::new("tests/data");
        let (one, two) = (pool(1), pool(2));
        let text = String::from_utf8_lossy(bytes);
        let whole = two.install(|| parse_str(&text, Some(mem_path()), base, None));
        for n in SIZES {
            let read = |n| {
                parse_chunked(
                    bytes,
                    Some(bytes.len() as u64),
                    mem_path(),
                    base,
                    n,
                    Limits::DEFAULT,
                    None,
                )
            };
            let d = difference(&whole, &two.install(|| read(n)));
            assert_eq!(d, None, "{name}, read in chunks of {n} bytes");
            let d = difference(&whole, &one.install(|| read(n)));
            assert_eq!(d, None, "{name}, read in chunks of {n} bytes on one thread");
        }
        whole
    }

    /// Words scene files are made of, right and wrong, glued or not, with
    /// comments (`#`, `//`) and a path that holds `//`.
    const TOKENS: [&str; 26] = [
        "camera",
        "background",
        "light",
        "point",
        "square",
        "primitive",
        "sphere",
        "plane",
        "bezier",
        "end",
        "O=",
        "R=",
        "N=",
        "color=",
        "diff=",
        "top=",
        "=",
        "1",
        "-2.5e3",
        "x",
        "é",
        "#c",
        "//c",
        "end//",
        "O=1",
        "texture= a//b.bmp",
    ];
    /// What separates them: blanks and every kind of line break.
    const SEPARATORS: [&str; 5] = [" ", "\t", "\n", "\r\n", "\r"];

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config {
            cases: 2000,
            failure_persistence: None,
            rng_seed: proptest::test_runner::RngSeed::Fixed(23),
            ..proptest::test_runner::Config::default()
        })]

        /// Any text made of scene words parses without a panic, and read in
        /// chunks of any size it gives exactly what it gives read whole.
        #[test]
        fn any_text_parses_alike_in_chunks(
            parts in proptest::collection::vec((0..TOKENS.len(), 0..SEPARATORS.len()), 0..120)
        ) {
            let text: String = parts
                .iter()
                .map(|&(t, s)| format!("{}{}", TOKENS[t], SEPARATORS[s]))
                .collect();
            let parsed = same_in_chunks(&format!("{text:?}"), text.as_bytes());
            // Every diagnostic points at a line of the text and quotes it.
            let lines: Vec<&str> = lexer::split_lines(&text).collect();
            for d in diags_of(&parsed) {
                let quoted = d.line.checked_sub(1).and_then(|k| lines.get(k));
                proptest::prop_assert_eq!(quoted, Some(&d.source_line.as_str()), "{:?}", d);
                proptest::prop_assert!(d.column >= 1);
            }
        }
    }

    /// The diagnostics of a parse, errors and warnings alike.
    fn diags_of(r: &Result<Scene, SceneError>) -> &[Diagnostic] {
        match r {
            Ok(s) => s.warnings(),
            Err(e) => &e.diagnostics,
        }
    }

    /// (line, column, source line) of each diagnostic.
    fn places(r: &Result<Scene, SceneError>) -> Vec<(usize, usize, &str)> {
        diags_of(r)
            .iter()
            .map(|d| (d.line, d.column, d.source_line.as_str()))
            .collect()
    }

    /// A scene that renders, with a warning in most blocks.
    const WARNED: &str = "# warnings in most blocks
camera
    O= 0 -5 1
    N= 0 1 0
    image_W= 64
    image_H= 48
end
background top
    top= 0.1 0.2 0.3
    colour= 1 1 1
end
light point
    O= 0 0 5
    color= 1 1 1
end   trailing words
primitive sphere
    O= 0 0 0
    R= 1
    Cylinder
    color= 1 0 0
    diff= 0.5
end

primitive plane
    N= 0 0 1
    R= -1
    color= 0.5 0.5 0.5
    diff= 1
end
camera
    O= 0 -6 1
end
primitive square
    O= 0 0 2
    Dx= 1 0 0
    Dy= 0 1 0
    texture= tiny.bmp
    diff= 1
end
primitive sphere
    O= 2 2 2
    R= 0.5
    refr= 1
    rindex= 1.5
end";

    /// A scene with errors all over, of every kind the parser itself finds.
    const BROKEN: &str = "camera
    O= 0 -5 1
    lens_W= -1
end
primitve sphere
    O= 0 0 0
end
end
primitive spere
    O= 1 1 1
    R= 1
end
primitive sphere
    O= 2 2 2
    R x
    R= 1
primitive sphere
    O= 3 3 3
    R= many
    = 4
    radius= 2
end
light
    O= 0 0 0
end
primitive sphere
    O= 4 4 4
    R= 1";

    #[test]
    fn blocks_split_across_chunks() -> Result<(), SceneError> {
        let s = same_in_chunks("warned", WARNED.as_bytes())?;
        assert_eq!(s.objects().len(), 4);
        assert_eq!(s.warnings().len(), 5, "{:#?}", s.warnings());
        let e = same_in_chunks("broken", BROKEN.as_bytes()).unwrap_err();
        assert!(e.diagnostics.len() >= 8, "{:#?}", e.diagnostics);
        // The block without `end` at the end of the file: its header.
        let last = e
            .diagnostics
            .last()
            .map(|d| (d.line, d.column, d.message.as_str()));
        assert_eq!(
            last,
            Some((
                26,
                1,
                "this block has no `end`; it ends at the end of the file"
            ))
        );
        Ok(())
    }

    #[test]
    fn line_breaks_at_the_cuts() {
        for (name, text) in [("warned", WARNED), ("broken", BROKEN)] {
            let crlf = text.replace('\n', "\r\n");
            let cr = text.replace('\n', "\r");
            // Every kind of line break, in turn.
            let mixed: String = text
                .split('\n')
                .enumerate()
                .map(|(k, l)| format!("{l}{}", ["\n", "\r\n", "\r"][k % 3]))
                .collect();
            let lf = same_in_chunks(name, text.as_bytes());
            for (kind, t) in [("CRLF", &crlf), ("CR", &cr), ("mixed", &mixed)] {
                let other = same_in_chunks(&format!("{name} {kind}"), t.as_bytes());
                // The same lines, so the same places.
                assert_eq!(places(&lf), places(&other), "{name} {kind}");
            }
        }
    }

    #[test]
    fn byte_order_mark_only_at_the_start() -> Result<(), SceneError> {
        let bom = format!("\u{feff}{WARNED}");
        let with = same_in_chunks("BOM", bom.as_bytes())?;
        assert!(
            with.warnings()
                .iter()
                .all(|d| !d.source_line.contains('\u{feff}'))
        );
        assert!(with.notes().iter().any(|n| n.contains("byte-order mark")));
        // A misspelt header on the first line: the excerpt has no mark.
        let e = same_in_chunks("BOM error", "\u{feff}camra\nend\n".as_bytes()).unwrap_err();
        assert_eq!(places(&Err(e)), vec![(1, 1, "camra"), (1, 1, "camra")]);
        // A mark at the start of a later line is a character like any other,
        // also when a chunk starts with that line (after the long comment).
        let later = format!("{WARNED}\n# {}\n\u{feff}camera\nend\n", "-".repeat(200));
        let s = same_in_chunks("later BOM", later.as_bytes())?;
        let d = s
            .warnings()
            .last()
            .map(|d| (d.line, d.source_line.as_str()));
        assert_eq!(d, Some((47, "\u{feff}camera")));
        Ok(())
    }

    #[test]
    fn bytes_that_are_not_utf8() -> Result<(), SceneError> {
        // Latin-1 comments (é = 0xE9), a byte cut off a UTF-8 character just
        // before a line break, and a bad byte in a line with an error.
        let mut bytes = b"# caf\xe9 au lait\n".to_vec();
        bytes.extend_from_slice(WARNED.as_bytes());
        bytes.extend_from_slice(
            b"\n# \xc3\nprimitive sphere # \xe9t\xe9\n    O= 0 0 0\n    R= 1\nend\n",
        );
        let s = same_in_chunks("latin-1", &bytes)?;
        assert_eq!(s.objects().len(), 5);
        bytes.extend_from_slice(b"primitive sph\xe8re\nend\n");
        let s = same_in_chunks("latin-1 unknown type", &bytes)?;
        let d = s
            .warnings()
            .last()
            .map(|d| (d.column, d.source_line.clone()));
        assert_eq!(d, Some((1, "primitive sph\u{fffd}re".to_string())));
        Ok(())
    }

    #[test]
    fn characters_of_several_bytes() -> Result<(), SceneError> {
        let text = format!(
            "# café ☕ 日本語 🎨\n{WARNED}\nprimitive sphere // ½ 🎨\n    O= 0 0 0\n    colör= 1 1 1\n    R= 1\nend\n"
        );
        let s = same_in_chunks("multi-byte", text.as_bytes())?;
        let w = s
            .warnings()
            .last()
            .map(|d| (d.column, d.len, d.source_line.as_str()));
        assert_eq!(w, Some((5, 6, "    colör= 1 1 1")));
        let e = same_in_chunks("multi-byte error", "日本 🎨 x\n".as_bytes()).unwrap_err();
        assert_eq!(
            places(&Err(e)),
            vec![(1, 1, "日本 🎨 x"), (1, 1, "日本 🎨 x")]
        );
        Ok(())
    }

    #[test]
    fn blocks_without_end() {
        // One block, never closed: the carried text grows to the whole file.
        let mut open = "primitive sphere\n    O= 0 0 0\n    R= x\n".to_string();
        for k in 0..200 {
            open += &format!("    # line {k}\n    diff= 0.5\n");
        }
        let e = same_in_chunks("open to the end", open.as_bytes()).unwrap_err();
        assert_eq!(
            places(&Err(e)),
            vec![(1, 1, "primitive sphere"), (3, 8, "    R= x")]
        );
        // Closed by the next header (a warning: both blocks are read).
        let text = "camera\n    O= 0 -1 0\nprimitive sphere\n    R= 1\nend\n";
        let s = same_in_chunks("closed by a header", text.as_bytes());
        assert_eq!(places(&s), vec![(1, 1, "camera")]);
        assert!(s.is_ok_and(|s| s.camera().origin.y == -1.0 && s.objects().len() == 1));
    }

    #[test]
    fn text_after_end_and_last_lines_without_a_break() -> Result<(), SceneError> {
        let text = "camera\nend and more\nprimitive sphere\n R= 1\nend   // done";
        let s = same_in_chunks("after end", text.as_bytes())?;
        assert_eq!(places(&Ok(s)), vec![(2, 5, "end and more")]);
        for (text, want) in [
            (
                "primitive sphere\n R= 1\nend\nprimitive cube",
                (4, 1, "primitive cube"),
            ),
            ("primitive sphere\n R= x", (2, 5, " R= x")),
        ] {
            let e = same_in_chunks(text, text.as_bytes()).unwrap_err();
            let first = e
                .errors()
                .last()
                .map(|d| (d.line, d.column, d.source_line.as_str()));
            assert_eq!(first, Some(want), "{text:?}");
        }
        for (text, want) in [
            ("primitive sphere\n R= 1\nend\nend", (4, 1, "end")),
            (
                "primitive sphere\r\n R= 1\r\nend\r\nsphere\r",
                (4, 1, "sphere"),
            ),
        ] {
            let s = same_in_chunks(text, text.as_bytes());
            assert_eq!(places(&s).last().copied(), Some(want), "{text:?}");
            assert!(s.is_ok(), "{text:?}");
        }
        for text in ["", "\n", "\r\n\r\n", "\u{feff}", "  # nothing\n\n"] {
            same_in_chunks(text, text.as_bytes())?;
        }
        Ok(())
    }

    #[test]
    fn places_far_into_the_file() -> Result<(), SceneError> {
        // 300 spheres, the 250th broken: checked against numbers, not only
        // against the whole-text parse.
        let mut text = String::new();
        for k in 0..300 {
            let r = if k == 249 { "oops" } else { "1" };
            text += &format!("primitive sphere\n    O= {k} 0 0\n    R= {r}\nend\n");
        }
        let e = same_in_chunks("300 spheres", text.as_bytes()).unwrap_err();
        assert_eq!(places(&Err(e)), vec![(249 * 4 + 3, 8, "    R= oops")]);
        let s = same_in_chunks("300 spheres", text.replace("oops", "2").as_bytes())?;
        assert_eq!(s.objects().len(), 300);
        assert_eq!(s.objects().last().and_then(|o| o.block()), Some(299));
        Ok(())
    }

    #[test]
    fn a_block_read_again_leaves_no_trace() {
        let mut p = Parse::new(None, Path::new("."), None, true);
        let text = "primitive sphere\n R= 1\nend\nprimitive spere\n R= x\n";
        let carry = p.feed(text, false);
        assert_eq!(text.get(carry..), Some("primitive spere\n R= x\n"));
        let r = &p.reader;
        assert_eq!((r.line, r.diags.count(), r.diags.error_count()), (3, 0, 0));
        assert_eq!((p.built.count(), p.builder.next_primitive_block()), (0, 1));
    }

    #[test]
    fn a_difference_is_caught() -> Result<(), String> {
        let base = Path::new("tests/data");
        let broken = parse_str(BROKEN, Some(mem_path()), base, None);
        let Err(mut e) = broken.clone() else {
            return Err("BROKEN parses".into());
        };
        assert_eq!(difference(&broken, &Err(e.clone())), None);
        // A line number off by one.
        if let Some(d) = e.diagnostics.get_mut(3) {
            d.line += 1;
        }
        assert!(difference(&broken, &Err(e)).is_some());
        let warned = parse_str(WARNED, Some(mem_path()), base, None);
        let Ok(mut s) = warned.clone() else {
            return Err("WARNED does not parse".into());
        };
        let mut warnings = s.warnings().to_vec();
        if let Some(d) = warnings.last_mut() {
            d.source_line.push(' ');
        }
        s.set_warnings(warnings);
        assert!(difference(&warned, &Ok(s.clone())).is_some());
        let Ok(mut s) = warned.clone() else {
            return Err("WARNED does not parse".into());
        };
        s.take_objects();
        assert!(difference(&warned, &Ok(s)).is_some());
        Ok(())
    }

    /// A reader that hands out `step` bytes at a time, failing or
    /// interrupted as told.
    struct Stuttering<'a> {
        bytes: &'a [u8],
        step: usize,
        /// Fails with this once `bytes` is down to this many.
        fail_at: Option<usize>,
        interrupt: bool,
    }

    impl Read for Stuttering<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            if self.fail_at.is_some_and(|n| self.bytes.len() <= n) {
                return Err(io::Error::other("the disk is on fire"));
            }
            self.interrupt = !self.interrupt;
            if self.interrupt {
                return Err(io::ErrorKind::Interrupted.into());
            }
            let n = self.step.min(buf.len()).min(self.bytes.len());
            let (now, rest) = self.bytes.split_at(n);
            buf[..n].copy_from_slice(now);
            self.bytes = rest;
            Ok(n)
        }
    }

    #[test]
    fn short_and_interrupted_reads() {
        let base = Path::new("tests/data");
        let whole = parse_str(BROKEN, Some(mem_path()), base, None);
        for step in [1, 3, 100] {
            let input = Stuttering {
                bytes: BROKEN.as_bytes(),
                step,
                fail_at: None,
                interrupt: false,
            };
            let chunked = parse_chunked(input, None, mem_path(), base, 16, Limits::DEFAULT, None);
            assert_eq!(difference(&whole, &chunked), None, "step {step}");
        }
    }

    #[test]
    fn endless_files_and_lines_are_refused_with_the_line() {
        let small = Limits {
            file: 4096,
            line: 64,
        };
        let text = format!("camera\n image_W= 3\n{}\nend\n", "x".repeat(65));
        let e = parse_chunked(
            text.as_bytes(),
            None,
            mem_path(),
            Path::new("."),
            7,
            small,
            None,
        )
        .unwrap_err();
        let m = e
            .diagnostics
            .first()
            .map(|d| (d.message.as_str(), d.line, d.column));
        assert_eq!(
            m,
            Some((
                "cannot read the scene file: line 3 is longer than 64 bytes, the longest line glint reads",
                3,
                1
            ))
        );
        // Named as every scene error is: FILE:LINE:1.
        assert!(format!("{e}").contains("--> tests/data/mem.txt:3:1"), "{e}");
        // NUL bytes without end, and endless short lines.
        let endless = |byte: u8| {
            let input = io::repeat(byte);
            parse_chunked(input, None, mem_path(), Path::new("."), 16, small, None).unwrap_err()
        };
        let e = endless(0);
        assert!(format!("{e}").contains("line 1 is longer"), "{e}");
        let e = endless(b'\n');
        assert!(format!("{e}").contains("larger than 4096 bytes"), "{e}");
        // Not a regular file: said so, never "not found", never blocking.
        for (p, why) in [
            ("/", "is a directory"),
            ("/dev/zero", "is not a regular file"),
        ] {
            let e = parse_file(Path::new(p), None).unwrap_err();
            assert!(format!("{e}").contains(why), "{e}");
        }
    }

    #[test]
    fn a_failed_read_is_an_error_about_the_file() {
        let input = Stuttering {
            bytes: WARNED.as_bytes(),
            step: 10,
            fail_at: Some(100),
            interrupt: false,
        };
        let e = parse_chunked(
            input,
            None,
            mem_path(),
            Path::new("."),
            64,
            Limits::DEFAULT,
            None,
        )
        .unwrap_err();
        let d = e.diagnostics.first();
        assert_eq!(e.diagnostics.len(), 1);
        assert_eq!(
            d.map(|d| (d.severity, d.line, d.message.as_str(), d.file.as_str())),
            Some((
                Severity::Error,
                0,
                "cannot read the scene file: the disk is on fire",
                "tests/data/mem.txt"
            ))
        );
        // As when the file cannot be opened at all.
        let e = parse_file(Path::new("tests/data/no such file.txt"), None).unwrap_err();
        let d = e.diagnostics.first();
        assert_eq!(e.diagnostics.len(), 1);
        assert_eq!(
            d.map(|d| (d.line, d.column, d.len, d.file.as_str())),
            Some((0, 0, 0, "tests/data/no such file.txt"))
        );
    }

    #[test]
    fn a_file_whose_every_primitive_is_skipped_is_an_error_naming_the_first() {
        let camera =
            "camera\n O= 0 -5 0\n N= 0 1 0\nend\nlight point\n O= 0 0 5\n color= 1 1 1\nend\n";
        let objs = format!(
            "{camera}shape sphere\n O= 0 0 0\n R= 1\nend\nshape plane\n N= 0 0 1\n R= 0\nend\n"
        );
        let e = parse_str(&objs, None, Path::new("."), None).unwrap_err();
        let errors: Vec<_> = e
            .diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .map(|d| (d.line, d.message.as_str()))
            .collect();
        assert_eq!(
            errors,
            vec![(
                9,
                "nothing to render: no primitive was read, and this block was skipped; `shape` reads like `primitive` (e.g. `primitive sphere`)"
            )]
        );
        // A misspelt header is named with the header it resembles.
        let typo = format!("{camera}primitiv sphere\n O= 0 0 0\n R= 1\nend\n");
        let e = parse_str(&typo, None, Path::new("."), None).unwrap_err();
        assert!(
            format!("{e}").contains("`primitiv` reads like `primitive`"),
            "{e}"
        );
        // One primitive read: the skipped block is a warning, as before;
        // and a file with no primitive and nothing skipped renders empty.
        let one = format!("{objs}primitive sphere\n O= 0 0 0\n R= 1\nend\n");
        assert!(parse_str(&one, None, Path::new("."), None).is_ok());
        assert!(parse_str(camera, None, Path::new("."), None).is_ok());
    }

    #[test]
    fn shared_scenes_read_in_chunks() -> io::Result<()> {
        let mut paths = corpus_scenes("framework");
        paths.extend(corpus_scenes("community"));
        for path in paths {
            let bytes = std::fs::read(&path)?;
            let dir = path.parent().unwrap_or(Path::new("."));
            let whole = parse_str(&String::from_utf8_lossy(&bytes), Some(&path), dir, None);
            let objects = whole.as_ref().map(|s| s.objects().len());
            assert!(
                objects.is_ok_and(|n| n > 0),
                "{}: {objects:?}",
                path.display()
            );
            let from_file = Scene::from_file(&path);
            let d = difference(&whole, &from_file);
            assert_eq!(d, None, "{}", path.display());
            for n in [1, 7, 64] {
                let chunked = parse_chunked(
                    &bytes[..],
                    Some(bytes.len() as u64),
                    &path,
                    dir,
                    n,
                    Limits::DEFAULT,
                    None,
                );
                let d = difference(&whole, &chunked);
                assert_eq!(d, None, "{}, chunks of {n} bytes", path.display());
            }
        }
        Ok(())
    }
}
