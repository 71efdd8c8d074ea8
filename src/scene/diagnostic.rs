//! Diagnostics that point at the source: `file:line:column`, the line, a caret.

use std::fmt;

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

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        writeln!(f, "{kind}: {}", self.message)?;
        if self.line == 0 {
            write!(f, "  --> {}", self.file)?;
        } else {
            let num = self.line.to_string();
            let pad = " ".repeat(num.len());
            writeln!(f, "{pad}--> {}:{}:{}", self.file, self.line, self.column)?;
            writeln!(f, "{pad} |")?;
            // Tabs are shown as spaces so the caret lines up under the span.
            let (shown, caret_at, caret_len) = excerpt(&self.source_line, self.column, self.len);
            writeln!(f, "{num} | {shown}")?;
            write!(
                f,
                "{pad} | {}{}",
                " ".repeat(caret_at),
                "^".repeat(caret_len.max(1))
            )?;
        }
        if let Some(help) = &self.help {
            let pad = " ".repeat(self.line.max(1).to_string().len());
            write!(f, "\n{pad} = help: {help}")?;
        }
        Ok(())
    }
}

/// Tab stops in excerpts.
const TAB: usize = 4;

/// The line with tabs expanded (and control characters shown as spaces),
/// plus the display offset and width of the span at 1-based char `column`.
fn excerpt(line: &str, column: usize, len: usize) -> (String, usize, usize) {
    let mut shown = String::with_capacity(line.len());
    let (mut at, mut end) = (None, None);
    let first = column.saturating_sub(1);
    let last = first.saturating_add(len.max(1));
    let mut width = 0;
    for (i, c) in line.chars().enumerate() {
        if i == first {
            at = Some(width);
        }
        if i == last {
            end = Some(width);
        }
        if c == '\t' {
            let n = TAB - width % TAB;
            shown.extend(std::iter::repeat_n(' ', n));
            width += n;
        } else if c.is_control() {
            shown.push(' ');
            width += 1;
        } else {
            shown.push(c);
            width += 1;
        }
    }
    // Spans may point just past the end of the line (a missing value).
    let count = line.chars().count();
    // Capped so a hand-made diagnostic with an absurd column cannot exhaust memory.
    let cap = width + 256;
    let at = at
        .unwrap_or(width.saturating_add(first.saturating_sub(count)))
        .min(cap);
    let end = end
        .unwrap_or(width.saturating_add(last.saturating_sub(count)))
        .min(cap);
    (shown, at, end.saturating_sub(at))
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

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, d) in self.diagnostics.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
                writeln!(f)?;
            }
            write!(f, "{d}")?;
        }
        let n = self.errors().count();
        write!(
            f,
            "\n\n{n} error{} in the scene; nothing was rendered",
            if n == 1 { "" } else { "s" }
        )
    }
}

impl std::error::Error for SceneError {}
