//! Binomial coefficients C(m, k) and their inverses, the weights of the
//! Bernstein basis: a static table for the degrees the fixed-size path
//! meets, larger rows built on first use.

use std::sync::OnceLock;

/// Highest profile degree handled at all (products reach twice this; the
/// binomial weights of degree 2·64 stay far from overflow).
pub const MAX_DEGREE: usize = 64;
/// Rows in the static tables: every degree up to 2·16, the products of the
/// profiles solved on fixed-size arrays.
const STATIC_ROWS: usize = 33;

/// `BINOM[m][k]` = C(m, k) for m < [`STATIC_ROWS`].
static BINOM: [[f64; STATIC_ROWS]; STATIC_ROWS] = binomials();
/// `INV_BINOM[m][k]` = 1 / C(m, k).
static INV_BINOM: [[f64; STATIC_ROWS]; STATIC_ROWS] = inverse_binomials();

const fn binomials() -> [[f64; STATIC_ROWS]; STATIC_ROWS] {
    let mut b = [[0.0; STATIC_ROWS]; STATIC_ROWS];
    let mut m = 0;
    while m < STATIC_ROWS {
        b[m][0] = 1.0;
        let mut k = 1;
        while k <= m {
            b[m][k] = b[m - 1][k - 1] + if k < m { b[m - 1][k] } else { 0.0 };
            k += 1;
        }
        m += 1;
    }
    b
}

const fn inverse_binomials() -> [[f64; STATIC_ROWS]; STATIC_ROWS] {
    let b = binomials();
    let mut inv = [[0.0; STATIC_ROWS]; STATIC_ROWS];
    let mut m = 0;
    while m < STATIC_ROWS {
        let mut k = 0;
        while k <= m {
            inv[m][k] = 1.0 / b[m][k];
            k += 1;
        }
        m += 1;
    }
    inv
}

/// Binomials and their inverses for every degree up to 2·[`MAX_DEGREE`]
/// (rows of length m + 1), built on first use.
struct BigTables {
    binom: Vec<Vec<f64>>,
    inv: Vec<Vec<f64>>,
}

fn big_tables() -> &'static BigTables {
    static TABLES: OnceLock<BigTables> = OnceLock::new();
    TABLES.get_or_init(|| {
        let top = 2 * MAX_DEGREE;
        let mut binom: Vec<Vec<f64>> = Vec::with_capacity(top + 1);
        for m in 0..=top {
            let row = (0..=m)
                .map(|k| {
                    if k == 0 || k == m {
                        1.0
                    } else {
                        binom[m - 1][k - 1] + binom[m - 1][k]
                    }
                })
                .collect();
            binom.push(row);
        }
        let inv = binom
            .iter()
            .map(|row| row.iter().map(|b| 1.0 / b).collect())
            .collect();
        BigTables { binom, inv }
    })
}

/// C(m, k) for k = 0..=m (at least), m ≤ 2·[`MAX_DEGREE`].
#[inline]
pub fn binom_row(m: usize) -> &'static [f64] {
    if m < STATIC_ROWS {
        &BINOM[m]
    } else {
        &big_tables().binom[m]
    }
}

/// 1 / C(m, k) for k = 0..=m (at least), m ≤ 2·[`MAX_DEGREE`].
#[inline]
pub fn inv_binom_row(m: usize) -> &'static [f64] {
    if m < STATIC_ROWS {
        &INV_BINOM[m]
    } else {
        &big_tables().inv[m]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The static rows and the rows built on first use agree bit for bit
    /// where both exist.
    #[test]
    fn static_and_built_rows_agree() {
        for m in 0..STATIC_ROWS {
            assert_eq!(BINOM[m][..=m], big_tables().binom[m][..]);
            assert_eq!(INV_BINOM[m][..=m], big_tables().inv[m][..]);
        }
    }
}
