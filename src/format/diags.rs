//! Places in a scene file and the diagnostics collected about them.

use super::lexer::{self, Word};
use crate::scene::{Diagnostic, Severity};

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

/// How many diagnostics and errors [`Diags`] held at some point.
#[derive(Clone, Copy, Default)]
pub(crate) struct Checkpoint {
    diags: usize,
    errors: usize,
}

/// Collects diagnostics, turning [`Site`]s into file/line/column/excerpt.
/// The excerpts (`source_line`) are filled from each piece of text once it
/// has been read, so reading keeps nothing per line of the file.
pub(crate) struct Diags {
    file: String,
    out: Vec<Diagnostic>,
    errors: usize,
}

impl Diags {
    pub fn new(file: String) -> Self {
        Diags {
            file,
            out: Vec::new(),
            errors: 0,
        }
    }

    /// How many diagnostics have been recorded.
    pub fn count(&self) -> usize {
        self.out.len()
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

    /// What has been recorded so far, to go back to with [`Diags::rollback`].
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            diags: self.out.len(),
            errors: self.errors,
        }
    }

    /// Forgets everything recorded since `cp`.
    pub fn rollback(&mut self, cp: Checkpoint) {
        self.out.truncate(cp.diags);
        self.errors = cp.errors;
    }

    /// Fills the excerpts of the diagnostics from the `from`-th on, all about
    /// lines of `text`, whose first line is the file's 0-based line `first_line`.
    pub fn fill_source_lines(&mut self, from: usize, text: &str, first_line: usize) {
        let Some(fresh) = self.out.get_mut(from..) else {
            return;
        };
        if fresh.is_empty() {
            return;
        }
        let mut order: Vec<(usize, usize)> =
            fresh.iter().enumerate().map(|(k, d)| (d.line, k)).collect();
        order.sort_unstable();
        let mut next = order.iter().peekable();
        for (k, line) in lexer::split_lines(text).enumerate() {
            let number = first_line + k + 1;
            while let Some(&(at, d)) = next.next_if(|(at, _)| *at <= number) {
                if at == number
                    && let Some(d) = fresh.get_mut(d)
                {
                    d.source_line = line.to_string();
                }
            }
            if next.peek().is_none() {
                break;
            }
        }
    }

    /// The diagnostics in file order.
    pub fn into_sorted(self) -> Vec<Diagnostic> {
        let mut all = self.out;
        // Stable: diagnostics found at the same place keep the order they were found in.
        all.sort_by_key(|d| (d.line, d.column));
        all
    }
}
