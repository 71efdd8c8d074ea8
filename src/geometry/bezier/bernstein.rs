//! Polynomials in the Bernstein basis on [0, 1]: evaluation, subdivision,
//! restriction, derivatives, products and maxima. Degrees up to
//! 2·[`MAX_DEGREE`](super::binomials::MAX_DEGREE).

use super::binomials::{binom_row, inv_binom_row};

/// Value of the degree-`m` polynomial `c` at `x`.
#[cfg(test)]
pub fn eval(c: &[f64], m: usize, x: f64) -> f64 {
    if m == 0 {
        return c[0];
    }
    let s = 1.0 - x;
    let bm = binom_row(m);
    let mut xn = 1.0;
    let mut f = c[0] * s;
    for i in 1..m {
        xn *= x;
        f = (f + xn * bm[i] * c[i]) * s;
    }
    f + xn * x * c[m]
}

/// Value and derivative of the degree-`m` polynomial `c` at `x`.
#[inline(always)]
pub fn eval_d(c: &[f64], m: usize, x: f64) -> (f64, f64) {
    match m {
        0 => (c[0], 0.0),
        1 => (c[0] * (1.0 - x) + c[1] * x, c[1] - c[0]),
        _ => horner_d(c, m, x, binom_row(m), binom_row(m - 1)),
    }
}

/// Value and derivative at `x` of the degree-`m` polynomial `c` (m ≥ 2),
/// given the binomial rows `bm` of degree m and `bd` of degree m − 1.
#[inline(always)]
fn horner_d(c: &[f64], m: usize, x: f64, bm: &[f64], bd: &[f64]) -> (f64, f64) {
    // Slices of the exact lengths up front: no bounds checks in the loop.
    let (c, bm, bd) = (&c[..=m], &bm[..m], &bd[..m]);
    let s = 1.0 - x;
    let mut xn = 1.0;
    let mut f = c[0] * s;
    // The derivative is m·Σ (c[i+1] − c[i]) B(m−1, i): the same Horner scheme one degree lower.
    let mut d = (c[1] - c[0]) * s;
    for i in 1..m - 1 {
        xn *= x;
        f = (f + xn * bm[i] * c[i]) * s;
        d = (d + xn * bd[i] * (c[i + 1] - c[i])) * s;
    }
    xn *= x;
    f = (f + xn * bm[m - 1] * c[m - 1]) * s;
    d += xn * (c[m] - c[m - 1]);
    (f + xn * x * c[m], m as f64 * d)
}

/// Splits `c` (degree `m`) at `x` into the coefficients on [0, x] and [x, 1]
/// (de Casteljau, in place in `right`).
pub fn split(c: &[f64], m: usize, x: f64, left: &mut [f64], right: &mut [f64]) {
    right[..=m].copy_from_slice(&c[..=m]);
    for (j, l) in left[..=m].iter_mut().enumerate() {
        *l = right[0];
        for i in 0..m - j {
            right[i] += x * (right[i + 1] - right[i]);
        }
    }
}

/// Splits the polynomial in `right` at ½: `left` gets its coefficients on
/// [0, ½] and `right` is left with those on [½, 1] (de Casteljau with
/// midpoints, in place; both slices as long as the polynomial).
#[inline(always)]
pub fn halve(left: &mut [f64], right: &mut [f64]) {
    let m = right.len() - 1;
    for (j, l) in left[..=m].iter_mut().enumerate() {
        *l = right[0];
        for i in 0..m - j {
            right[i] = 0.5 * (right[i] + right[i + 1]);
        }
    }
}

/// The coefficients of `c` (degree `m`) restricted to [a, b] ⊂ [0, 1].
pub fn restrict(c: &[f64], m: usize, a: f64, b: f64) -> Vec<f64> {
    let mut left = vec![0.0; m + 1];
    let mut right = vec![0.0; m + 1];
    split(c, m, a, &mut left, &mut right);
    if a >= 1.0 {
        return right;
    }
    let x = ((b - a) / (1.0 - a)).clamp(0.0, 1.0);
    let mut out = vec![0.0; m + 1];
    split(&right, m, x, &mut out, &mut left);
    out
}

/// Coefficients of the derivative (degree `m − 1`, `m ≥ 1`).
pub fn derivative(c: &[f64], m: usize) -> Vec<f64> {
    (0..m).map(|i| m as f64 * (c[i + 1] - c[i])).collect()
}

/// Coefficients of the product of two degree-`n` polynomials (degree 2n,
/// n ≤ [`MAX_DEGREE`](super::binomials::MAX_DEGREE)).
pub fn product(a: &[f64], b: &[f64], n: usize) -> Vec<f64> {
    let mut out = vec![0.0; 2 * n + 1];
    let bn = binom_row(n);
    for i in 0..=n {
        let ai = a[i] * bn[i];
        for j in 0..=n {
            out[i + j] += ai * b[j] * bn[j];
        }
    }
    let inv = inv_binom_row(2 * n);
    for k in 0..=2 * n {
        out[k] *= inv[k];
    }
    out
}

/// An upper bound within `tol` of the maximum of `c` (degree `m`) on [0, 1]
/// (branch and bound on the convex hull property; construction time only).
pub fn max_on_unit(c: &[f64], m: usize, tol: f64) -> f64 {
    if !c[..=m].iter().all(|v| v.is_finite()) {
        return f64::INFINITY;
    }
    let mut best = c[0].max(c[m]);
    let mut bound = best;
    let mut stack = vec![(c[..=m].to_vec(), 0u32)];
    let mut budget = 100_000;
    while let Some((cur, depth)) = stack.pop() {
        budget -= 1;
        if budget == 0 {
            // (Unreachable for finite input; a safe answer regardless.)
            return cur
                .iter()
                .chain(stack.iter().flat_map(|s| &s.0))
                .fold(bound, |a, &b| a.max(b));
        }
        let hull = cur.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        best = best.max(cur[0]).max(cur[m]);
        if hull <= best + tol {
            continue;
        }
        if depth >= 40 {
            bound = bound.max(hull);
            continue;
        }
        let mut left = vec![0.0; m + 1];
        let mut right = vec![0.0; m + 1];
        split(&cur, m, 0.5, &mut left, &mut right);
        stack.push((left, depth + 1));
        stack.push((right, depth + 1));
    }
    bound.max(best + tol)
}

#[cfg(test)]
mod tests {
    use super::super::test_polys::{Lcg, casteljau, from_power};
    use super::*;

    #[test]
    fn eval_matches_power_form() {
        let p = [0.3, -2.0, 1.5, 4.0, -1.0];
        let c = from_power(&p);
        for i in 0..=20 {
            let x = i as f64 / 20.0;
            let want: f64 = p
                .iter()
                .enumerate()
                .map(|(j, a)| a * x.powi(j as i32))
                .sum();
            let dwant: f64 = p
                .iter()
                .enumerate()
                .skip(1)
                .map(|(j, a)| j as f64 * a * x.powi(j as i32 - 1))
                .sum();
            let (f, d) = eval_d(&c, 4, x);
            assert!((f - want).abs() < 1e-13, "{x}: {f} vs {want}");
            assert!((d - dwant).abs() < 1e-12, "{x}: {d} vs {dwant}");
            assert!((eval(&c, 4, x) - want).abs() < 1e-13);
        }
    }

    /// Halving at ½ is splitting at ½, to rounding.
    #[test]
    fn halves_are_the_split_at_one_half() {
        let mut rng = Lcg(11);
        for m in [1, 3, 8, 40] {
            let c: Vec<f64> = (0..=m).map(|_| 2.0 * rng.next() - 1.0).collect();
            let (mut l1, mut r1) = (vec![0.0; m + 1], vec![0.0; m + 1]);
            split(&c, m, 0.5, &mut l1, &mut r1);
            let (mut l2, mut r2) = (vec![0.0; m + 1], c.clone());
            halve(&mut l2, &mut r2);
            for (a, b) in l1.iter().chain(&r1).zip(l2.iter().chain(&r2)) {
                assert!((a - b).abs() < 1e-13, "m {m}: {a} vs {b}");
            }
        }
    }

    /// Degrees above the static tables: evaluation, products, restriction
    /// and maxima against de Casteljau.
    #[test]
    fn high_degree_routines_are_accurate() {
        let mut rng = Lcg(5);
        for m in [33, 40, 64, 100, 128] {
            let c: Vec<f64> = (0..=m).map(|_| 2.0 * rng.next() - 1.0).collect();
            // The derivative: de Casteljau on the hodograph m·(c[i+1] − c[i]).
            let hodograph: Vec<f64> = c.windows(2).map(|w| m as f64 * (w[1] - w[0])).collect();
            for i in 0..=50 {
                let x = i as f64 / 50.0;
                let (f, d) = eval_d(&c, m, x);
                let want = casteljau(&c, x);
                assert!((f - want).abs() < 1e-13, "m {m} x {x}: {f} vs {want}");
                let want = casteljau(&hodograph, x);
                assert!(
                    (d - want).abs() < 1e-13 * m as f64,
                    "m {m} x {x}: {d} vs {want}"
                );
            }
        }
        for n in [20, 30, 64] {
            let a: Vec<f64> = (0..=n).map(|_| 2.0 * rng.next() - 1.0).collect();
            let b: Vec<f64> = (0..=n).map(|_| 2.0 * rng.next() - 1.0).collect();
            let ab = product(&a, &b, n);
            let part = restrict(&a, n, 0.3, 0.55);
            let der = derivative(&a, n);
            for i in 0..=20 {
                let x = i as f64 / 20.0;
                let want = casteljau(&a, x) * casteljau(&b, x);
                assert!((casteljau(&ab, x) - want).abs() < 1e-13, "n {n} x {x}");
                let want = casteljau(&a, 0.3 + 0.25 * x);
                assert!((casteljau(&part, x) - want).abs() < 1e-13, "n {n} x {x}");
                let want = eval_d(&a, n, x).1;
                assert!((casteljau(&der, x) - want).abs() < 1e-12 * n as f64);
            }
            let max = max_on_unit(&a, n, 1e-12);
            let sampled = (0..=100_000)
                .map(|i| casteljau(&a, i as f64 / 100_000.0))
                .fold(f64::NEG_INFINITY, f64::max);
            assert!(
                max >= sampled && max < sampled + 1e-6,
                "n {n}: {max} vs {sampled}"
            );
        }
    }

    #[test]
    fn max_bound_is_close_and_above() {
        let c = from_power(&[0.0, 4.0, -4.0]); // 4x(1−x), max 1 at 0.5
        let m = max_on_unit(&c, 2, 1e-12);
        assert!((1.0..1.0 + 2e-12).contains(&m), "{m}");
    }
}
