//! The values of `key= values` lines: numbers, vectors and text, parsed
//! and checked against the shape each key expects.

use super::diags::{Diags, Site};
use super::lexer::Word;
use glam::{DVec2, DVec3};
use std::ops::Range;

/// Largest magnitude accepted for a number: far beyond any scene, and small
/// enough that products of a few coordinates cannot overflow.
const MAX_MAGNITUDE: f64 = 1e100;

/// Two unit directions closer to parallel than this (sine of the angle)
/// span no area.
pub(crate) const PARALLEL_SINE: f64 = 1e-12;

/// The shape of a key's values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// One number.
    Num,
    /// One whole number ≥ 0.
    Count,
    /// Three numbers.
    Vec3,
    /// One number (used for all three) or three.
    OneOrThree,
    /// Two numbers or three (a bezier's `P=`: the framework's `z r`,
    /// lazycal's base point).
    TwoOrThree,
    /// Any count of numbers, at least one (lazycal's `control_points=`,
    /// the colon family's `curve:` and `ratio:`).
    List,
    /// The rest of the line (a file name, a blur name).
    Text,
}

pub(crate) use Kind::{Count, List, Num, OneOrThree, Text, TwoOrThree, Vec3};

/// One `key= values` line of a block, as read.
#[derive(Clone, Debug)]
pub(crate) struct Entry<'a> {
    /// The key without `=`.
    pub key: &'a str,
    /// Where the key (with its `=`) is.
    pub key_site: Site,
    /// Where the words after `=` lie in the block's list of values.
    pub values: Range<usize>,
    /// 0-based line index.
    pub line: usize,
    /// The line's text (for values that are the rest of the line).
    pub raw: &'a str,
    /// Whether it was written `key: values` (the colon family), its numbers
    /// then read as C++'s `>>` reads them.
    pub colon: bool,
}

impl Entry<'_> {
    /// The key as written, with its `=` or `:`.
    pub fn written(&self) -> String {
        format!("{}{}", self.key, if self.colon { ':' } else { '=' })
    }
}

/// A parsed value.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Value {
    Num(f64),
    V2(DVec2),
    V3(DVec3),
    List(Vec<f64>),
    Text(String),
}

/// A key with its parsed value and where it was.
#[derive(Clone, Debug)]
pub(crate) struct Field {
    /// The key's canonical name.
    pub name: &'static str,
    /// Its parsed value.
    pub value: Value,
    /// From the key to the last value.
    pub site: Site,
}

/// The parsed keys of one block, in file order.
#[derive(Default)]
pub(crate) struct Fields {
    /// In file order.
    pub list: Vec<Field>,
    /// Keys that were present but whose values were wrong (already reported).
    pub failed: Vec<&'static str>,
}

impl Fields {
    /// The last (overriding) occurrence of `name`.
    pub fn get(&self, name: &str) -> Option<&Field> {
        self.list.iter().rev().find(|f| f.name == name)
    }

    pub fn num(&self, name: &str) -> Option<(f64, Site)> {
        self.get(name).and_then(|f| match f.value {
            Value::Num(x) => Some((x, f.site)),
            _ => None,
        })
    }

    pub fn v3(&self, name: &str) -> Option<(DVec3, Site)> {
        self.get(name).and_then(|f| match f.value {
            Value::V3(v) => Some((v, f.site)),
            _ => None,
        })
    }

    pub fn text(&self, name: &str) -> Option<(&str, Site)> {
        self.get(name).and_then(|f| match &f.value {
            Value::Text(s) => Some((s.as_str(), f.site)),
            _ => None,
        })
    }

    pub fn failed(&self, name: &str) -> bool {
        self.failed.contains(&name)
    }
}

/// Why a word is not a usable number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NumberError {
    /// Not a decimal number at all.
    Malformed,
    /// `inf`, `nan` and the like.
    NotFinite,
    /// Beyond ±1e100 (including overflow such as `1e999`).
    TooLarge,
}

/// Parses a decimal number: optional sign, digits with an optional `.`
/// (either side may be empty, not both), optional exponent.
pub(crate) fn parse_number(s: &str) -> Result<f64, NumberError> {
    let b = s.as_bytes();
    let mut i = 0;
    if matches!(b.first(), Some(b'+' | b'-')) {
        i += 1;
    }
    let unsigned = &s[i..];
    if ["inf", "infinity", "nan"]
        .iter()
        .any(|w| unsigned.eq_ignore_ascii_case(w))
    {
        return Err(NumberError::NotFinite);
    }
    let digits = |i: &mut usize| {
        let start = *i;
        while b.get(*i).is_some_and(u8::is_ascii_digit) {
            *i += 1;
        }
        *i - start
    };
    let mut mantissa = digits(&mut i);
    if b.get(i) == Some(&b'.') {
        i += 1;
        mantissa += digits(&mut i);
    }
    if mantissa == 0 {
        return Err(NumberError::Malformed);
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        i += 1;
        if matches!(b.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        if digits(&mut i) == 0 {
            return Err(NumberError::Malformed);
        }
    }
    if i != b.len() {
        return Err(NumberError::Malformed);
    }
    let x: f64 = s.parse().map_err(|_| NumberError::Malformed)?;
    if !x.is_finite() || x.abs() > MAX_MAGNITUDE {
        return Err(NumberError::TooLarge);
    }
    Ok(x)
}

/// The length in bytes of the longest prefix of `s` that C++'s `>>` into a
/// double reads as a number (0 when none): `2.5.0` reads `2.5`, then `.0`.
pub(crate) fn number_prefix(s: &str) -> usize {
    let b = s.as_bytes();
    let mut i = usize::from(matches!(b.first(), Some(b'+' | b'-')));
    let digits = |i: &mut usize| {
        let start = *i;
        while b.get(*i).is_some_and(u8::is_ascii_digit) {
            *i += 1;
        }
        *i - start
    };
    let mut mantissa = digits(&mut i);
    if b.get(i) == Some(&b'.') {
        i += 1;
        mantissa += digits(&mut i);
    }
    if mantissa == 0 {
        return 0;
    }
    let end = i;
    if matches!(b.get(i), Some(b'e' | b'E')) {
        i += 1;
        if matches!(b.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        if digits(&mut i) > 0 {
            return i;
        }
    }
    end
}

/// The words of a `key:` line as the colon family's reader takes them: a
/// word holding several numbers (`2.5.000000`) is as many values, as C++'s
/// `>>` reads them (a word that starts with no number stays whole).
fn stream_words<'a>(values: &[Word<'a>]) -> Vec<Word<'a>> {
    let mut out = Vec::with_capacity(values.len());
    for w in values {
        let mut rest = *w;
        loop {
            let n = number_prefix(rest.text);
            if n == 0 || n == rest.text.len() {
                out.push(rest);
                break;
            }
            let chars = rest.text[..n].chars().count();
            out.push(Word {
                text: &rest.text[..n],
                len: chars,
                ..rest
            });
            rest = rest.split_off(chars);
        }
    }
    out
}

/// What a kind of value looks like, for messages.
fn describe(name: &str, kind: Kind) -> &'static str {
    match kind {
        Num => "a number",
        Count => "a whole number",
        Vec3 => "3 numbers",
        OneOrThree => "1 or 3 numbers",
        TwoOrThree => "2 numbers (z r) or 3 (x y z)",
        List => "numbers",
        Text if name == "blur" => "a blur name (`exp`)",
        Text => "a file name",
    }
}

/// Parses an entry's values as `kind`, reporting what is wrong.
pub(crate) fn parse_entry(
    e: &Entry<'_>,
    values: &[Word<'_>],
    name: &'static str,
    kind: Kind,
    diags: &mut Diags,
) -> Option<Field> {
    let values = values.get(e.values.clone()).unwrap_or_default();
    let split;
    let values = if e.colon && kind != Text {
        split = stream_words(values);
        if split.len() != values.len() {
            let (first, last) = (&values[0], &values[values.len() - 1]);
            diags.warn(
                Site::span(e.line, first, last),
                format!(
                    "`{}` holds numbers run together: read as {}, as its reader's `>>` reads them",
                    e.written(),
                    split.iter().map(|w| w.text).collect::<Vec<_>>().join(" ")
                ),
                None,
            );
        }
        &split[..]
    } else {
        values
    };
    let key = e.written();
    let line = e.line;
    let site = match values.last() {
        Some(last) => Site {
            line,
            col: e.key_site.col,
            len: (last.col + last.len).saturating_sub(e.key_site.col).max(1),
        },
        None => e.key_site,
    };
    let what = describe(name, kind);
    let (Some(first), Some(last)) = (values.first(), values.last()) else {
        diags.error(
            e.key_site,
            format!("`{key}` expects {what}, found nothing"),
            None,
        );
        return None;
    };
    if kind == Text {
        let text = e
            .raw
            .get(first.start..last.start + last.text.len())
            .unwrap_or(first.text);
        return Some(Field {
            name,
            value: Value::Text(text.to_string()),
            site,
        });
    }
    let n = values.len();
    if kind == List {
        let mut list = Vec::with_capacity(n);
        for w in values {
            match parse_number(w.text) {
                Ok(x) => list.push(x),
                Err(err) => {
                    number_error(&key, w, err, line, diags);
                    return None;
                }
            }
        }
        return Some(Field {
            name,
            value: Value::List(list),
            site,
        });
    }
    let counts: &[usize] = match kind {
        Num | Count => &[1],
        Vec3 => &[3],
        OneOrThree => &[1, 3],
        TwoOrThree => &[2, 3],
        Text | List => &[],
    };
    let max = counts.iter().copied().max().unwrap_or(1);
    // The lineages' readers take the values they need and drop the rest.
    if n > max {
        let extra = &values[max];
        diags.warn(
            Site::span(line, extra, last),
            format!("`{key}` takes {what}, found {n}: the rest is ignored"),
            None,
        );
    }
    // No kind takes more than 3 numbers.
    let mut numbers = [0.0; 3];
    let mut ok = true;
    for (k, w) in values.iter().take(max).enumerate() {
        match parse_number(w.text) {
            Ok(x) => {
                if let Some(slot) = numbers.get_mut(k) {
                    *slot = x;
                }
            }
            Err(err) => {
                ok = false;
                number_error(&key, w, err, line, diags);
            }
        }
    }
    if !ok {
        return None;
    }
    // Missing values: the lineages' readers leave them 0.
    let n = n.min(max);
    let n = if counts.contains(&n) {
        n
    } else {
        diags.warn(
            site,
            format!("`{key}` takes {what}, found {n}: the missing ones read as 0"),
            None,
        );
        counts.iter().copied().find(|&c| c > n).unwrap_or(max)
    };
    let value = match kind {
        Num => Value::Num(numbers[0]),
        Count => {
            let x = numbers[0];
            if x < 0.0 {
                diags.error(
                    Site::word(line, first),
                    format!("`{key}` must not be negative, found {x}"),
                    None,
                );
                return None;
            }
            // Read as written (rounded); the lineages' `>>` into an integer
            // stops at the first character that is not a digit.
            let x = x.round();
            let theirs = integer_prefix(first.text);
            if theirs != x {
                diags.warn(
                    Site::word(line, first),
                    format!(
                        "`{key} {}` is read as {x}; the lineages' readers read {theirs} \
                         (they stop at the first character that is not a digit)",
                        first.text
                    ),
                    Some(format!("write `{key} {x}`")),
                );
            }
            Value::Num(x)
        }
        Vec3 => Value::V3(DVec3::new(numbers[0], numbers[1], numbers[2])),
        OneOrThree if n == 1 => Value::V3(DVec3::splat(numbers[0])),
        OneOrThree | TwoOrThree if n == 3 => {
            Value::V3(DVec3::new(numbers[0], numbers[1], numbers[2]))
        }
        TwoOrThree => Value::V2(DVec2::new(numbers[0], numbers[1])),
        OneOrThree | Text | List => return None,
    };
    Some(Field { name, value, site })
}

/// Reports word `w` after `key` (as written, `key=` or `key:`), which is
/// not a usable number.
fn number_error(key: &str, w: &Word<'_>, err: NumberError, line: usize, diags: &mut Diags) {
    let message = match err {
        NumberError::Malformed => format!("expected a number after `{key}`, found `{}`", w.text),
        NumberError::NotFinite => format!("`{}` is not a finite number", w.text),
        NumberError::TooLarge => {
            format!("`{}` is too large (numbers must lie within ±1e100)", w.text)
        }
    };
    diags.error(Site::word(line, w), message, None);
}
/// What C++'s `>>` into an integer reads of `text`: its leading sign and
/// digits (0 when there are none).
fn integer_prefix(text: &str) -> f64 {
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    let end = digits
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(digits.len());
    let x: f64 = digits[..end].parse().unwrap_or(0.0);
    if text.starts_with('-') { -x } else { x }
}

/// The unit vector along `v`, or `None` when `v` has zero length (scaled
/// first so tiny or huge components neither underflow nor overflow).
pub(crate) fn unit(v: DVec3) -> Option<DVec3> {
    let m = v.abs().max_element();
    if m == 0.0 || !m.is_finite() {
        return None;
    }
    let w = v / m;
    Some(w / w.length())
}

/// Whether two unit vectors are (numerically) parallel.
pub(crate) fn parallel(a: DVec3, b: DVec3) -> bool {
    a.cross(b).length() <= PARALLEL_SINE
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_number(".5"), Ok(0.5));
        assert_eq!(parse_number("-1e-3"), Ok(-1e-3));
        assert_eq!(parse_number("+2"), Ok(2.0));
        assert_eq!(parse_number("1."), Ok(1.0));
        assert_eq!(parse_number("1E+2"), Ok(100.0));
        assert_eq!(parse_number("."), Err(NumberError::Malformed));
        assert_eq!(parse_number("1e"), Err(NumberError::Malformed));
        assert_eq!(parse_number("1.2.3"), Err(NumberError::Malformed));
        assert_eq!(parse_number("0x10"), Err(NumberError::Malformed));
        assert_eq!(parse_number("1,5"), Err(NumberError::Malformed));
        assert_eq!(parse_number(""), Err(NumberError::Malformed));
        assert_eq!(parse_number("-"), Err(NumberError::Malformed));
        assert_eq!(parse_number("inf"), Err(NumberError::NotFinite));
        assert_eq!(parse_number("-NaN"), Err(NumberError::NotFinite));
        assert_eq!(parse_number("1e999"), Err(NumberError::TooLarge));
        assert_eq!(parse_number("-1e101"), Err(NumberError::TooLarge));
        assert_eq!(parse_number("1e-999"), Ok(0.0));
    }

    #[test]
    fn unit_vectors() {
        assert_eq!(unit(DVec3::ZERO), None);
        let u = unit(DVec3::new(1e-200, 0.0, 0.0));
        assert_eq!(u, Some(DVec3::X));
        let u = unit(DVec3::new(3e100, 4e100, 0.0));
        assert!(u.is_some_and(|u| (u - DVec3::new(0.6, 0.8, 0.0)).length() < 1e-15));
    }
}
