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

impl<'a> Entry<'a> {
    /// The key as written, with its `=` or `:`, for messages.
    pub fn written(&self) -> Written<'a> {
        Written {
            key: self.key,
            colon: self.colon,
        }
    }
}

/// A key as written (`R=`, or `R:` in the colon family's), displayed in
/// messages: formatted only when a message is, not for every line read.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Written<'a> {
    key: &'a str,
    colon: bool,
}

impl std::fmt::Display for Written<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}{}", self.key, if self.colon { ':' } else { '=' })
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
    list: Vec<Field>,
    /// Keys that were present but whose values were wrong (already reported).
    pub failed: Vec<&'static str>,
    /// The [`key_bit`]s of the names in `list`: most lookups are of keys
    /// the block does not have, answered without comparing names.
    held: u64,
}

/// A bit for key `name`, from its length and end bytes: distinct for the
/// keys one block usually holds (a shared bit only costs a search).
#[inline(always)]
fn key_bit(name: &str) -> u64 {
    let b = name.as_bytes();
    let (first, last) = (b.first().copied(), b.last().copied());
    let h = 5 * b.len() + 3 * usize::from(first.unwrap_or(0)) + usize::from(last.unwrap_or(0));
    1 << (h % 64)
}

impl Fields {
    /// Empties both lists.
    pub fn clear(&mut self) {
        self.list.clear();
        self.failed.clear();
        self.held = 0;
    }

    /// Adds a parsed key (after those before it: a later one overrides).
    pub fn push(&mut self, f: Field) {
        self.held |= key_bit(f.name);
        self.list.push(f);
    }

    /// The parsed keys, in file order.
    pub fn list(&self) -> &[Field] {
        &self.list
    }

    /// The last (overriding) occurrence of `name`.
    #[inline]
    pub fn get(&self, name: &str) -> Option<&Field> {
        if self.held & key_bit(name) == 0 {
            return None;
        }
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
    let negative = b.first() == Some(&b'-');
    let sign = usize::from(matches!(b.first(), Some(b'+' | b'-')));
    let mut i = sign;
    // The digits' value (meaningful while there are at most 19 of them).
    let mut w: u64 = 0;
    let mut digits = |i: &mut usize| {
        let start = *i;
        while let Some(d) = b.get(*i).filter(|d| d.is_ascii_digit()) {
            w = w.wrapping_mul(10).wrapping_add(u64::from(d - b'0'));
            *i += 1;
        }
        *i - start
    };
    let whole = digits(&mut i);
    let mut fraction = 0;
    if b.get(i) == Some(&b'.') {
        i += 1;
        fraction = digits(&mut i);
    }
    let mantissa = whole + fraction;
    if mantissa == 0 {
        let unsigned = &s[sign..];
        let words = ["inf", "infinity", "nan"];
        return Err(if words.iter().any(|w| unsigned.eq_ignore_ascii_case(w)) {
            NumberError::NotFinite
        } else {
            NumberError::Malformed
        });
    }
    let mut exponent: i64 = 0;
    if matches!(b.get(i), Some(b'e' | b'E')) {
        i += 1;
        let minus = b.get(i) == Some(&b'-');
        if matches!(b.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        let start = i;
        while let Some(d) = b.get(i).filter(|d| d.is_ascii_digit()) {
            exponent = (exponent * 10 + i64::from(d - b'0')).min(1 << 20);
            i += 1;
        }
        if i == start {
            return Err(NumberError::Malformed);
        }
        if minus {
            exponent = -exponent;
        }
    }
    if i != b.len() {
        return Err(NumberError::Malformed);
    }
    // Clinger's fast path: at most 15 digits are exact in an f64, as are the
    // powers of ten up to 1e22, so one multiplication or division rounds
    // once: the correctly rounded value, which is what `str::parse` gives.
    let scale = exponent - fraction as i64;
    let x = if mantissa <= 15 && scale.abs() <= 22 {
        // Every digit counts, leading zeros too: w < 10^15 < 2^53, so both
        // conversions are exact, and the signed one is one instruction on
        // any x86-64.
        let x = (w as i64) as f64;
        let p = POWERS_OF_TEN[scale.unsigned_abs() as usize];
        let x = if scale >= 0 { x * p } else { x / p };
        if negative { -x } else { x }
    } else {
        s.parse().map_err(|_| NumberError::Malformed)?
    };
    if !x.is_finite() || x.abs() > MAX_MAGNITUDE {
        return Err(NumberError::TooLarge);
    }
    Ok(x)
}

/// 10⁰ to 10²², each exact in an f64.
static POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

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
                    number_error(key, w, err, line, diags);
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
                number_error(key, w, err, line, diags);
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
fn number_error(key: Written<'_>, w: &Word<'_>, err: NumberError, line: usize, diags: &mut Diags) {
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
    use rand::{Rng, SeedableRng};

    #[test]
    fn a_lookup_finds_what_a_search_of_every_key_finds() {
        // Every key of every block kind, and names no block has.
        let mut names: Vec<&'static str> = super::super::schema::all_kinds()
            .flat_map(|k| k.key_names())
            .collect();
        names.extend(["", "x", "é", "colour", "Dz", "O4"]);
        names.sort_unstable();
        names.dedup();
        let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
        let mut fields = Fields::default();
        for _ in 0..3000 {
            fields.clear();
            for _ in 0..rng.random_range(0..9) {
                let name = names[rng.random_range(0..names.len())];
                let value = Value::Num(rng.random());
                let site = Site {
                    line: 0,
                    col: 1,
                    len: 1,
                };
                fields.push(Field { name, value, site });
            }
            for &name in &names {
                let searched = fields.list().iter().rev().find(|f| f.name == name);
                assert_eq!(
                    fields.get(name).map(|f| (f.name, &f.value)),
                    searched.map(|f| (f.name, &f.value)),
                    "{name:?} in {:?}",
                    fields.list().iter().map(|f| f.name).collect::<Vec<_>>()
                );
            }
        }
    }

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
        assert_eq!(
            parse_number("-0").map(f64::to_bits),
            Ok((-0.0f64).to_bits())
        );
        assert_eq!(parse_number("0.1"), Ok(0.1));
        assert_eq!(parse_number("9007199254740993"), Ok(9007199254740992.0));
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config {
            cases: 4096,
            rng_seed: proptest::test_runner::RngSeed::Fixed(31),
            ..proptest::test_runner::Config::default()
        })]
        /// Every number the grammar takes reads as the standard library's
        /// correctly rounded parse reads it, bit for bit (the fast path for
        /// short numbers included).
        #[test]
        fn numbers_read_as_the_standard_parse_reads_them(
            sign in proptest::sample::select(vec!["", "+", "-"]),
            whole in "[0-9]{0,20}",
            point in proptest::bool::ANY,
            fraction in "[0-9]{0,20}",
            exponent in proptest::option::of((proptest::sample::select(vec!["e", "E"]),
                proptest::sample::select(vec!["", "+", "-"]), 0u32..40)),
        ) {
            let fraction = if point { format!(".{fraction}") } else { String::new() };
            let exponent = exponent.map_or(String::new(), |(e, s, k)| format!("{e}{s}{k}"));
            let text = format!("{sign}{whole}{fraction}{exponent}");
            let theirs = text.parse::<f64>();
            match parse_number(&text) {
                Ok(x) => proptest::prop_assert_eq!(Ok(x.to_bits()), theirs.map(f64::to_bits), "{}", text),
                Err(NumberError::TooLarge) => proptest::prop_assert!(theirs.is_ok_and(|y| y.abs() > MAX_MAGNITUDE), "{}", text),
                Err(e) => proptest::prop_assert!(
                    whole.is_empty() && fraction.len() <= 1, "{} refused: {:?}", text, e
                ),
            }
        }
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
