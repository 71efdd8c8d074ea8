//! "Did you mean ...?": the closest known word to a misspelt one.

/// Edit distance counting insertions, deletions, substitutions and swaps of
/// two neighbouring characters (optimal string alignment).
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let (n, m) = (a.len(), b.len());
    // Three rolling rows: i-2, i-1, i.
    let mut prev2 = vec![0usize; m + 1];
    let mut prev: Vec<usize> = (0..=m).collect();
    let mut cur = vec![0usize; m + 1];
    for i in 1..=n {
        cur[0] = i;
        for j in 1..=m {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut d = (prev[j] + 1).min(cur[j - 1] + 1).min(prev[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(prev2[j - 2] + 1);
            }
            cur[j] = d;
        }
        std::mem::swap(&mut prev2, &mut prev);
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[m]
}

/// The candidate closest to `word`, if it is close enough to be a likely
/// misspelling: equal ignoring case, or at most 2 edits and at most a third
/// of the longer word's length (so `x` does not suggest `R`).
pub(crate) fn closest<'c>(word: &str, candidates: &[&'c str]) -> Option<&'c str> {
    // Very long words are never misspellings of the short keywords.
    if word.chars().count() > 64 {
        return None;
    }
    if let Some(c) = candidates.iter().find(|c| c.eq_ignore_ascii_case(word)) {
        return Some(c);
    }
    let mut best: Option<(usize, &'c str)> = None;
    let len = word.chars().count();
    for &c in candidates {
        let c_len = c.chars().count();
        // The distance is at least the difference in length: past 2, no
        // need to work it out (a mutated file's every odd word asks).
        if len.abs_diff(c_len) > 2 {
            continue;
        }
        let d = edit_distance(word, c);
        let longest = len.max(c_len);
        if d <= 2 && 3 * d <= longest && best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, c));
        }
    }
    best.map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        assert_eq!(edit_distance("", ""), 0);
        assert_eq!(edit_distance("abc", ""), 3);
        assert_eq!(edit_distance("spher", "sphere"), 1);
        assert_eq!(edit_distance("sphree", "sphere"), 1);
        assert_eq!(edit_distance("colour", "color"), 1);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }

    /// Skipping candidates whose length differs by more than 2 changes no
    /// answer: the same as trying every candidate.
    #[test]
    fn the_length_shortcut_changes_no_suggestion() {
        let keys = [
            "O",
            "R",
            "N",
            "color",
            "diff",
            "spec",
            "refl",
            "refr",
            "rindex",
            "texture",
            "shade_quality",
            "drefl_quality",
            "image_W",
            "end",
            "sphere",
            "cylinder",
        ];
        let full = |word: &str| {
            if let Some(c) = keys.iter().find(|c| c.eq_ignore_ascii_case(word)) {
                return Some(*c);
            }
            let mut best: Option<(usize, &str)> = None;
            for &c in &keys {
                let d = edit_distance(word, c);
                let longest = word.chars().count().max(c.chars().count());
                if d <= 2 && 3 * d <= longest && best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, c));
                }
            }
            best.map(|(_, c)| c)
        };
        let words = [
            "",
            "o",
            "colr",
            "colour",
            "coloured",
            "shadequality",
            "shade_qualty",
            "drefl",
            "imageW",
            "image_H",
            "ed",
            "endd",
            "spere",
            "cylinders",
            "Rr",
            "xx",
            "refrr",
        ];
        for w in words {
            assert_eq!(closest(w, &keys), full(w), "{w}");
        }
        assert_eq!(closest("shade_qualty", &keys), Some("shade_quality"));
    }

    #[test]
    fn suggestions() {
        let types = ["sphere", "plane", "square", "cube", "cylinder", "bezier"];
        assert_eq!(closest("spher", &types), Some("sphere"));
        assert_eq!(closest("Sphere", &types), Some("sphere"));
        assert_eq!(closest("cylnder", &types), Some("cylinder"));
        assert_eq!(closest("torus", &types), None);
        assert_eq!(closest("x", &["O", "R"]), None);
        assert_eq!(closest("o", &["O", "R"]), Some("O"));
    }
}
