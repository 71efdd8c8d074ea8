//! Polynomials for the unit tests of the Bernstein routines and the root
//! search: from power-basis coefficients or from roots, evaluated by de
//! Casteljau, with a small deterministic generator.

use super::binomials::binom_row;

/// A small deterministic generator for the tests.
pub struct Lcg(pub u64);

impl Lcg {
    /// The next value, uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Bernstein coefficients of Σ p_j x^j.
pub fn from_power(p: &[f64]) -> Vec<f64> {
    // b_k = Σ_{j≤k} C(k,j)/C(m,j) p_j.
    let m = p.len() - 1;
    (0..=m)
        .map(|k| {
            (0..=k)
                .map(|j| binom_row(k)[j] / binom_row(m)[j] * p[j])
                .sum()
        })
        .collect()
}

/// Value by de Casteljau (independent of the binomial tables).
pub fn casteljau(c: &[f64], x: f64) -> f64 {
    let mut b = c.to_vec();
    for k in 1..b.len() {
        for i in 0..b.len() - k {
            b[i] = b[i] * (1.0 - x) + b[i + 1] * x;
        }
    }
    b[0]
}

/// Bernstein coefficients of Π (x − r), built one linear factor at a
/// time (degree elevation of p·x and p·(1 − x)), well conditioned.
pub fn from_roots(roots: &[f64]) -> Vec<f64> {
    let mut p = vec![1.0];
    for &r in roots {
        let k = p.len() - 1; // degree of p
        let k1 = (k + 1) as f64;
        // p·(x − r) = (1 − r)·x·p − r·(1 − x)·p.
        p = (0..=k + 1)
            .map(|j| {
                let times_x = if j > 0 { p[j - 1] * j as f64 / k1 } else { 0.0 };
                let times_s = if j <= k {
                    p[j] * (k + 1 - j) as f64 / k1
                } else {
                    0.0
                };
                (1.0 - r) * times_x - r * times_s
            })
            .collect();
    }
    p
}
