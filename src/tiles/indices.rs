//! Indices as schedulers write them: `2,7,11-15` (`sbatch --array=`).

/// `indices` (ascending) as a list of values and ranges: `2,7,11-15`.
pub fn index_list(indices: &[u32]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < indices.len() {
        let start = indices[i];
        let mut end = start;
        while i + 1 < indices.len() && indices[i + 1] == end + 1 {
            end += 1;
            i += 1;
        }
        parts.push(match end - start {
            0 => start.to_string(),
            _ => format!("{start}-{end}"),
        });
        i += 1;
    }
    parts.join(",")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_of_indices_become_ranges() {
        assert_eq!(index_list(&[2, 7, 11, 12, 13, 14, 15]), "2,7,11-15");
        assert_eq!(index_list(&[0, 1]), "0-1");
        assert_eq!(index_list(&[4]), "4");
        assert_eq!(index_list(&[]), "");
    }
}
