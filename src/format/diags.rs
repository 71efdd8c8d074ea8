//! Places in a scene file and the diagnostics collected about them.

use super::lexer::{self, Word};
use crate::scene::{Diagnostic, Dialect, Severity};

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

/// How many diagnostics of one line are shown; the rest are counted.
pub(crate) const PER_LINE: usize = 10;
/// How many diagnostics of one file are shown; the rest are counted.
pub(crate) const PER_FILE: usize = 200;
/// How many diagnostics are kept at most while reading (the first
/// [`PER_FILE`] in file order are among them unless the file is read
/// far out of order); beyond, they are only counted.
const STORED: usize = 100_000;

/// How many diagnostics and errors [`Diags`] held at some point.
#[derive(Clone, Copy, Default)]
pub(crate) struct DiagCounts {
    diags: usize,
    errors: usize,
    dropped: usize,
    dropped_error: bool,
}

/// Collects diagnostics, turning [`Site`]s into file/line/column/excerpt.
/// The excerpts (`source_line`) are filled from each piece of text once it
/// has been read, so reading keeps nothing per line of the file.
/// Reports are bounded: at most [`PER_LINE`] a line and [`PER_FILE`] a
/// file are shown, then how many more.
pub(crate) struct Diags {
    file: String,
    out: Vec<Diagnostic>,
    errors: usize,
    /// Diagnostics past [`STORED`], counted only, and whether one was an error.
    dropped: usize,
    dropped_error: bool,
    /// Per entry of `out`, the dialects it holds in (`None`: all).
    when: Vec<Option<When>>,
}

/// The dialects a warning holds in: some depend on the dialect, chosen
/// only once the whole file is read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum When {
    /// Only when the file is read in this dialect.
    In(Dialect),
    /// Unless the file is read in this dialect.
    NotIn(Dialect),
}

impl When {
    fn holds(self, d: Dialect) -> bool {
        match self {
            When::In(x) => x == d,
            When::NotIn(x) => x != d,
        }
    }
}

impl Diags {
    pub fn new(file: String) -> Self {
        Diags {
            file,
            out: Vec::new(),
            errors: 0,
            dropped: 0,
            dropped_error: false,
            when: Vec::new(),
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
        if self.out.len() >= STORED {
            self.dropped += 1;
            self.dropped_error |= severity == Severity::Error;
            return;
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
        self.when.push(None);
    }

    /// A warning that holds only in the dialects of `when` (see [`Diags::settle`]).
    pub fn warn_when(
        &mut self,
        when: When,
        site: Site,
        message: impl Into<String>,
        help: Option<String>,
    ) {
        let before = self.when.len();
        self.push(Severity::Warning, site, message.into(), help);
        if self.when.len() > before
            && let Some(last) = self.when.last_mut()
        {
            *last = Some(when);
        }
    }

    /// Gives a diagnostic recorded after its text was gone the excerpt of
    /// another one on the same line.
    pub fn share_source_lines(&mut self) {
        let known: std::collections::HashMap<usize, String> = self
            .out
            .iter()
            .filter(|d| !d.source_line.is_empty())
            .map(|d| (d.line, d.source_line.clone()))
            .collect();
        for d in self.out.iter_mut().filter(|d| d.source_line.is_empty()) {
            if let Some(line) = known.get(&d.line) {
                d.source_line = line.clone();
            }
        }
    }

    /// Drops the warnings that do not hold in dialect `d`.
    pub fn settle(&mut self, d: Dialect) {
        let when = std::mem::take(&mut self.when);
        let mut keep = when.iter().map(|w| w.is_none_or(|w| w.holds(d)));
        self.out.retain(|_| keep.next().unwrap_or(true));
        self.when = vec![None; self.out.len()];
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
    pub fn counts(&self) -> DiagCounts {
        DiagCounts {
            diags: self.out.len(),
            errors: self.errors,
            dropped: self.dropped,
            dropped_error: self.dropped_error,
        }
    }

    /// Takes in the diagnostics of `other` (about the same file). Past
    /// [`STORED`] in all, those latest in the file are only counted.
    pub fn append(&mut self, other: Diags) {
        self.errors += other.errors;
        self.dropped += other.dropped;
        self.dropped_error |= other.dropped_error;
        self.out.extend(other.out);
        self.when.extend(other.when);
        if self.out.len() > STORED {
            let mut both: Vec<_> = self.out.drain(..).zip(self.when.drain(..)).collect();
            both.sort_by_key(|(d, _)| (d.line, d.column));
            for (d, _) in both.drain(STORED..) {
                self.dropped += 1;
                self.dropped_error |= d.severity == Severity::Error;
            }
            (self.out, self.when) = both.into_iter().unzip();
        }
    }

    /// Forgets everything recorded since `cp`.
    pub fn rollback(&mut self, cp: DiagCounts) {
        self.out.truncate(cp.diags);
        self.when.truncate(cp.diags);
        self.errors = cp.errors;
        self.dropped = cp.dropped;
        self.dropped_error = cp.dropped_error;
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
        // Only the diagnostics shown get their line (see `into_sorted`):
        // a long line with many errors is not copied for each.
        let mut order: Vec<(usize, usize, usize)> = fresh
            .iter()
            .enumerate()
            .map(|(k, d)| (d.line, d.column, k))
            .collect();
        order.sort_unstable();
        let mut next = order.iter().peekable();
        for (k, line) in lexer::split_lines(text).enumerate() {
            let number = first_line + k + 1;
            let mut on_line = 0;
            while let Some(&(at, _, d)) = next.next_if(|(at, _, _)| *at <= number) {
                if at == number
                    && on_line < PER_LINE
                    && let Some(d) = fresh.get_mut(d)
                {
                    d.source_line = line.to_string();
                    on_line += 1;
                }
            }
            if next.peek().is_none() {
                break;
            }
        }
    }

    /// The diagnostics in file order, at most [`PER_LINE`] a line (then one
    /// "… and N more on line L") and [`PER_FILE`] in all (then "… and N more").
    pub fn into_sorted(self) -> Vec<Diagnostic> {
        let mut all = self.out;
        // Stable: diagnostics found at the same place keep the order they were found in.
        all.sort_by_key(|d| (d.line, d.column));
        let file = self.file;
        // A note about the file as a whole (line 0), as severe as the worst it stands for.
        let summary = |message: String, error: bool| Diagnostic {
            severity: if error {
                Severity::Error
            } else {
                Severity::Warning
            },
            message,
            file: file.clone(),
            line: 0,
            column: 0,
            len: 0,
            source_line: String::new(),
            help: None,
        };
        let mut kept = Vec::new();
        let (mut more, mut more_errors) = (self.dropped, self.dropped_error);
        let mut rest = all.into_iter().peekable();
        while let Some(first) = rest.next() {
            let line = first.line;
            let mut group = vec![first];
            while let Some(d) = rest.next_if(|d| d.line == line) {
                group.push(d);
            }
            let hidden = group.split_off(group.len().min(PER_LINE));
            let hidden_error = hidden.iter().any(|d| d.severity == Severity::Error);
            for d in group {
                if kept.len() < PER_FILE {
                    kept.push(d);
                } else {
                    more += 1;
                    more_errors |= d.severity == Severity::Error;
                }
            }
            if hidden.is_empty() {
                continue;
            }
            if kept.len() < PER_FILE {
                let m = format!("… and {} more on line {line}", hidden.len());
                kept.push(summary(m, hidden_error));
            } else {
                more += hidden.len();
                more_errors |= hidden_error;
            }
        }
        if more > 0 {
            kept.push(summary(format!("… and {more} more"), more_errors));
        }
        kept
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_are_capped_per_line_and_per_file() {
        let mut d = Diags::new("s.txt".to_string());
        let line = "x ".repeat(20_000);
        for k in 0..20_000 {
            let site = Site {
                line: 1,
                col: 2 * k + 1,
                len: 1,
            };
            d.error(site, "bad word", None);
        }
        d.fill_source_lines(0, &format!("camera\n{line}\n"), 0);
        let all = d.into_sorted();
        assert_eq!(all.len(), PER_LINE + 1);
        assert_eq!(all[PER_LINE].message, "… and 19990 more on line 2");
        assert_eq!(all[PER_LINE].severity, Severity::Error);
        let filled = all.iter().filter(|d| !d.source_line.is_empty()).count();
        assert_eq!(filled, PER_LINE);

        let mut d = Diags::new("s.txt".to_string());
        for k in 0..(STORED + 50) {
            d.warn(
                Site {
                    line: k,
                    col: 1,
                    len: 1,
                },
                "odd",
                None,
            );
        }
        let all = d.into_sorted();
        assert_eq!(all.len(), PER_FILE + 1);
        let last = all.last().map(|d| (d.message.clone(), d.severity));
        let more = STORED + 50 - PER_FILE;
        assert_eq!(
            last,
            Some((format!("… and {more} more"), Severity::Warning))
        );
    }
}
