//! Stratified sampling: grids of strata as close to square as possible,
//! and where samplers get their random numbers.

use rand_pcg::Pcg32;

/// Where a sampler gets its random numbers: a generator, or a stream that
/// is seeded only when first asked. A sampler asks once, before its draws.
pub(crate) trait RandomSource {
    /// The generator to draw from.
    fn generator(&mut self) -> &mut Pcg32;
}

impl RandomSource for Pcg32 {
    #[inline(always)]
    fn generator(&mut self) -> &mut Pcg32 {
        self
    }
}

/// A grid of exactly `n` strata as close to square as possible: (rows, cols).
pub(crate) fn strata(n: u32) -> (u32, u32) {
    let n = n.max(1);
    let mut rows = (n as f64).sqrt() as u32;
    while !n.is_multiple_of(rows) {
        rows -= 1;
    }
    (rows, n / rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_are_exact_and_squarish() {
        assert_eq!(strata(16), (4, 4));
        assert_eq!(strata(32), (4, 8));
        assert_eq!(strata(64), (8, 8));
        assert_eq!(strata(7), (1, 7));
        assert_eq!(strata(0), (1, 1));
    }
}
