//! Bounds on what glint reads: no scene, mesh or rays file may be endless
//! (`/dev/zero`) or one endless line, and only regular files are opened.

use std::fmt;
use std::io::Read;
use std::path::Path;

/// The most bytes read from a scene, mesh or rays file, and the longest line.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limits {
    /// Bytes in the whole file.
    pub file: u64,
    /// Bytes in one line (its `\n` not counted).
    pub line: usize,
}

impl Limits {
    /// The limits documented in docs/format.md: 1 GiB a file, 1 MiB a line.
    pub const DEFAULT: Limits = Limits {
        file: 1 << 30,
        line: 1 << 20,
    };
}

/// Why a file was not read.
#[derive(Debug)]
pub(crate) enum ReadError {
    /// The operating system's error (or not a regular file).
    Io(std::io::Error),
    /// More bytes than [`Limits::file`].
    TooLarge(u64),
    /// The 1-based line that is longer than [`Limits::line`].
    LineTooLong { line: usize, limit: usize },
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadError::Io(e) => write!(f, "{e}"),
            ReadError::TooLarge(limit) => write!(
                f,
                "the file is larger than {}, the most glint reads",
                size(*limit as usize)
            ),
            ReadError::LineTooLong { line, limit } => write!(
                f,
                "line {line} is longer than {}, the longest line glint reads",
                size(*limit)
            ),
        }
    }
}

/// A size in bytes as people write it (1 MiB, 1 GiB).
fn size(bytes: usize) -> String {
    match bytes {
        b if b >= 1 << 30 && b % (1 << 30) == 0 => format!("{} GiB", b >> 30),
        b if b >= 1 << 20 && b % (1 << 20) == 0 => format!("{} MiB", b >> 20),
        b => format!("{b} bytes"),
    }
}

/// What is wrong with opening a file of this type, if anything: only
/// regular files are read (a FIFO or a device could block or never end).
pub(crate) fn not_regular(meta: &std::fs::Metadata) -> Option<&'static str> {
    if meta.is_dir() {
        Some("is a directory")
    } else if !meta.is_file() {
        Some("is not a regular file")
    } else {
        None
    }
}

/// Opens a regular file, after checking its type (so a FIFO never blocks).
pub(crate) fn open_regular(path: &Path) -> std::io::Result<std::fs::File> {
    let meta = std::fs::metadata(path)?;
    if let Some(why) = not_regular(&meta) {
        return Err(std::io::Error::other(why));
    }
    std::fs::File::open(path)
}

/// Counts the lines of `bytes` (the text after a line start) and checks the
/// last, unfinished one: `lines` and `line_start` carry the count and the
/// offset of the current line from one call to the next.
pub(crate) struct LineGuard {
    lines: usize,
    line_start: u64,
    seen: u64,
    limits: Limits,
}

impl LineGuard {
    /// A guard at the start of a file.
    pub fn new(limits: Limits) -> Self {
        LineGuard {
            lines: 0,
            line_start: 0,
            seen: 0,
            limits,
        }
    }

    /// Takes the next bytes of the file, refusing them past a limit;
    /// returns the offset just past their last `\n`, if they hold one.
    pub fn check(&mut self, bytes: &[u8]) -> Result<Option<usize>, ReadError> {
        let limit = self.limits.line as u64;
        // From each line's start, the last `\n` within the limit's reach
        // ends it and every line before it, all short enough: only a reach
        // without any `\n` holds a line too long. So the bytes are searched
        // about once, in long vectorised runs, not line by line.
        let mut from = 0;
        while self.seen + bytes.len() as u64 - self.line_start > limit {
            // The line starts at `from` or before: within the limit.
            let reach = (self.line_start + limit - self.seen) as usize;
            match memchr::memrchr(b'\n', bytes.get(from..=reach).unwrap_or_default()) {
                Some(k) => {
                    from += k + 1;
                    self.line_start = self.seen + from as u64;
                }
                None => {
                    self.lines += newlines(bytes.get(..from).unwrap_or_default());
                    return Err(self.too_long());
                }
            }
        }
        self.lines += newlines(bytes);
        let line_end = memchr::memrchr(b'\n', bytes).map(|k| k + 1);
        if let Some(end) = line_end {
            self.line_start = self.seen + end as u64;
        }
        self.seen += bytes.len() as u64;
        if self.seen > self.limits.file {
            return Err(ReadError::TooLarge(self.limits.file));
        }
        Ok(line_end)
    }

    fn too_long(&self) -> ReadError {
        ReadError::LineTooLong {
            line: self.lines + 1,
            limit: self.limits.line,
        }
    }
}

/// The line breaks in `bytes`: counted in bytes, 255 at most at a time,
/// which the compiler vectorises.
fn newlines(bytes: &[u8]) -> usize {
    bytes
        .chunks(255)
        .map(|c| c.iter().fold(0u8, |n, &b| n + u8::from(b == b'\n')) as usize)
        .sum()
}

/// Reads all of `input` within `limits`.
pub(crate) fn read_bounded(mut input: impl Read, limits: Limits) -> Result<Vec<u8>, ReadError> {
    let mut guard = LineGuard::new(limits);
    let mut bytes = Vec::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = match input.read(&mut buf) {
            Ok(0) => return Ok(bytes),
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(ReadError::Io(e)),
        };
        let new = buf.get(..n).unwrap_or_default();
        guard.check(new)?;
        bytes.extend_from_slice(new);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: Limits = Limits { file: 20, line: 4 };

    #[test]
    fn limits_hold_in_any_pieces() {
        assert_eq!(
            read_bounded(&b"abcd\nef\n"[..], SMALL).ok(),
            Some(b"abcd\nef\n".to_vec())
        );
        let e = read_bounded(&b"ab\nabcde\n"[..], SMALL).unwrap_err();
        assert!(matches!(e, ReadError::LineTooLong { line: 2, .. }), "{e}");
        let e = read_bounded(std::io::repeat(0), SMALL).unwrap_err();
        assert!(matches!(e, ReadError::LineTooLong { line: 1, .. }), "{e}");
        let e = read_bounded(std::io::repeat(b'\n'), SMALL).unwrap_err();
        assert!(matches!(e, ReadError::TooLarge(20)), "{e}");
        // One byte at a time: the same answers.
        let mut g = LineGuard::new(SMALL);
        let r: Result<Vec<_>, _> = b"ab\nabcde".iter().map(|b| g.check(&[*b])).collect();
        assert!(matches!(r, Err(ReadError::LineTooLong { line: 2, .. })));
        assert_eq!(
            ReadError::LineTooLong {
                line: 3,
                limit: 1 << 20
            }
            .to_string(),
            "line 3 is longer than 1 MiB, the longest line glint reads"
        );
    }

    /// The first line longer than `line` bytes (1-based), line by line.
    fn first_long_line(bytes: &[u8], line: usize) -> Option<usize> {
        let mut pieces = bytes.split(|&b| b == b'\n');
        pieces.position(|piece| piece.len() > line).map(|n| n + 1)
    }

    #[test]
    fn long_lines_are_found_in_any_pieces() {
        let mut state = 7u64;
        let mut next = |n: u64| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        for _ in 0..3000 {
            let line = 1 + next(12) as usize;
            let limits = Limits {
                file: 1 << 20,
                line,
            };
            // Lines of random lengths around the limit.
            let mut bytes = Vec::new();
            for _ in 0..next(20) {
                bytes.extend(std::iter::repeat_n(b'x', next(line as u64 + 3) as usize));
                bytes.push(b'\n');
            }
            bytes.extend(std::iter::repeat_n(b'y', next(line as u64 + 3) as usize));
            let mut guard = LineGuard::new(limits);
            let mut rest = &bytes[..];
            let got = loop {
                if rest.is_empty() {
                    break None;
                }
                let (piece, after) = rest.split_at((1 + next(9) as usize).min(rest.len()));
                rest = after;
                if let Err(e) = guard.check(piece) {
                    // Only a line too long can go wrong here (0: another error).
                    break Some(match e {
                        ReadError::LineTooLong { line, .. } => line,
                        _ => 0,
                    });
                }
            };
            assert_eq!(
                got,
                first_long_line(&bytes, line),
                "{:?}, limit {line}",
                String::from_utf8_lossy(&bytes)
            );
        }
    }

    #[test]
    fn only_regular_files_are_opened() {
        let e = open_regular(Path::new("/")).unwrap_err();
        assert_eq!(e.to_string(), "is a directory");
        let e = open_regular(Path::new("/dev/zero")).unwrap_err();
        assert_eq!(e.to_string(), "is not a regular file");
    }
}
