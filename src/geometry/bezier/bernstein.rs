//! Polynomials in the Bernstein basis on [0, 1]: evaluation, subdivision,
//! products and real-root isolation.
//!
//! The per-ray routines come twice: on fixed-size arrays (lengths known at
//! compile time, for profiles up to [`MAX_DEGREE`]), and on slices of any
//! length with a caller's scratch buffer (the `_any` functions, for profiles
//! up to [`LARGEST_DEGREE`]). Both run the same arithmetic in the same order.
//! The construction-time helpers take any degree up to [`LARGEST_DEGREE`].

use std::sync::OnceLock;

/// Highest profile degree the fixed-size arrays hold.
pub const MAX_DEGREE: usize = 16;
/// Coefficients of a product of two profile polynomials.
pub const MAXF: usize = 2 * MAX_DEGREE + 1;
/// Highest profile degree handled at all (products reach twice this; the
/// binomial weights of degree 2·64 stay far from overflow).
pub const LARGEST_DEGREE: usize = 64;

/// `BINOM[m][k]` = C(m, k) for m ≤ 2·[`MAX_DEGREE`].
pub static BINOM: [[f64; MAXF]; MAXF] = binomials();
/// `INV_BINOM[m][k]` = 1 / C(m, k).
pub static INV_BINOM: [[f64; MAXF]; MAXF] = inverse_binomials();

const fn binomials() -> [[f64; MAXF]; MAXF] {
    let mut b = [[0.0; MAXF]; MAXF];
    let mut m = 0;
    while m < MAXF {
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

const fn inverse_binomials() -> [[f64; MAXF]; MAXF] {
    let b = binomials();
    let mut inv = [[0.0; MAXF]; MAXF];
    let mut m = 0;
    while m < MAXF {
        let mut k = 0;
        while k <= m {
            inv[m][k] = 1.0 / b[m][k];
            k += 1;
        }
        m += 1;
    }
    inv
}

/// Binomials and their inverses for every degree up to 2·[`LARGEST_DEGREE`]
/// (rows of length m + 1), built on first use.
struct BigTables {
    binom: Vec<Vec<f64>>,
    inv: Vec<Vec<f64>>,
}

fn big_tables() -> &'static BigTables {
    static TABLES: OnceLock<BigTables> = OnceLock::new();
    TABLES.get_or_init(|| {
        let top = 2 * LARGEST_DEGREE;
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

/// C(m, k) for k = 0..=m (at least), m ≤ 2·[`LARGEST_DEGREE`].
#[inline]
pub fn binom_row(m: usize) -> &'static [f64] {
    if m < MAXF {
        &BINOM[m]
    } else {
        &big_tables().binom[m]
    }
}

/// 1 / C(m, k) for k = 0..=m (at least), m ≤ 2·[`LARGEST_DEGREE`].
#[inline]
pub fn inv_binom_row(m: usize) -> &'static [f64] {
    if m < MAXF {
        &INV_BINOM[m]
    } else {
        &big_tables().inv[m]
    }
}

/// Value of the degree-`m` polynomial `c` at `x`.
#[cfg(test)]
pub fn eval(c: &[f64], m: usize, x: f64) -> f64 {
    if m == 0 {
        return c[0];
    }
    let s = 1.0 - x;
    let bm = &BINOM[m];
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
        _ => horner_d(c, m, x, &BINOM[m], &BINOM[m - 1]),
    }
}

/// [`eval_d`] for any degree `m` ≤ 2·[`LARGEST_DEGREE`] (the same Horner
/// scheme, with binomials from the larger tables above the fixed ones).
#[inline]
pub fn eval_d_any(c: &[f64], m: usize, x: f64) -> (f64, f64) {
    if m < MAXF {
        return eval_d(c, m, x);
    }
    let tables = big_tables();
    horner_d(c, m, x, &tables.binom[m], &tables.binom[m - 1])
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
/// n ≤ [`LARGEST_DEGREE`]).
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

/// Sign changes in the coefficient sequence, zeros skipped: an upper bound
/// on the number of roots in the open interval, exact when 0 or 1.
#[inline(always)]
pub fn sign_changes(c: &[f64], m: usize) -> u32 {
    let mut n = 0;
    let mut prev = 0.0;
    for &v in &c[..=m] {
        if v != 0.0 {
            if prev != 0.0 && (v > 0.0) != (prev > 0.0) {
                n += 1;
            }
            prev = v;
        }
    }
    n
}

/// Splits a polynomial of degree L − 1 at ½ into its halves.
#[inline(always)]
fn halve<const L: usize>(c: &[f64; L]) -> ([f64; L], [f64; L]) {
    let m = L - 1;
    let mut tmp = *c;
    let mut left = [0.0; L];
    let mut right = [0.0; L];
    for j in 0..=m {
        left[j] = tmp[0];
        right[m - j] = tmp[m - j];
        for i in 0..m - j {
            tmp[i] = 0.5 * (tmp[i] + tmp[i + 1]);
        }
    }
    (left, right)
}

/// The root in (0, 1) of a polynomial (degree L − 1) whose end values have
/// opposite signs and which has exactly one root there.
fn bracketed_root<const L: usize>(c: &[f64; L]) -> f64 {
    newton_in_bracket(c, L - 1, |x| eval_d(c, L - 1, x))
}

/// [`bracketed_root`] for a polynomial of any degree `m` (the slice `c`).
fn bracketed_root_any(c: &[f64], m: usize) -> f64 {
    newton_in_bracket(c, m, |x| eval_d_any(c, m, x))
}

/// The single root in (0, 1) of the degree-`m` polynomial `c` (`eval` gives
/// its value and derivative), whose end values have opposite signs: Newton's
/// method kept inside a shrinking bracket, bisecting when a step leaves it.
#[inline(always)]
fn newton_in_bracket(c: &[f64], m: usize, eval: impl Fn(f64) -> (f64, f64)) -> f64 {
    let positive_at_0 = c[0] > 0.0;
    let (mut a, mut b) = (0.0, 1.0);
    // Start where the control polygon first crosses zero.
    let mut x = 0.5;
    for k in 0..m {
        if (c[k + 1] > 0.0) != positive_at_0 {
            x = ((k as f64 + c[k] / (c[k] - c[k + 1])) / m as f64).clamp(0.0, 1.0);
            break;
        }
    }
    let mut last_step = 1.0f64;
    for _ in 0..200 {
        let (f, d) = eval(x);
        if f == 0.0 {
            return x;
        }
        if (f > 0.0) == positive_at_0 {
            a = x;
        } else {
            b = x;
        }
        let step = f / d;
        if converged(step, last_step) {
            return (x - step).clamp(a, b);
        }
        last_step = step;
        let mut next = x - step;
        if !(next > a && next < b) {
            next = 0.5 * (a + b);
        }
        if b - a <= 1e-15 {
            return next;
        }
        x = next;
    }
    x
}

/// Whether a Newton iteration whose last two steps were `step` and
/// `last_step` is done: the step is at the last bit, or small and
/// converging quadratically, so that what remains is below the last bit.
/// (Near a double root convergence is linear and the test keeps iterating.)
#[inline(always)]
pub fn converged(step: f64, last_step: f64) -> bool {
    let step = step.abs();
    step <= 1e-15 || (step <= 1e-8 && step <= 1e-3 * last_step.abs())
}

/// What a root visitor wants next.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Flow {
    /// Look for the next root.
    Continue,
    /// Stop the search.
    Stop,
}

/// Deepest subdivision of the root search: intervals of width 2⁻⁴⁸ are
/// below what double precision can separate, and are reported as one root.
const MAX_DEPTH: u32 = 48;

/// Visits the real roots in [0, 1] of `c` (degree L − 1) in increasing
/// order (`forward`) or decreasing order, until `visit` says stop. Roots are
/// isolated by subdividing until the coefficients change sign at most once
/// (Descartes' rule for the Bernstein basis); clusters narrower than 2⁻⁴⁸
/// are visited once. Roots on interval ends may be visited twice.
pub fn visit_roots<const L: usize>(
    c: &[f64; L],
    forward: bool,
    visit: &mut impl FnMut(f64) -> Flow,
) -> Flow {
    search(c, 0.0, 1.0, forward, 0, visit)
}

fn search<const L: usize>(
    c: &[f64; L],
    xa: f64,
    xb: f64,
    forward: bool,
    depth: u32,
    visit: &mut impl FnMut(f64) -> Flow,
) -> Flow {
    let m = L - 1;
    let (first, last) = if forward { (xa, xb) } else { (xb, xa) };
    let (c_first, c_last) = if forward { (c[0], c[m]) } else { (c[m], c[0]) };
    if c_first == 0.0 && visit(first) == Flow::Stop {
        return Flow::Stop;
    }
    let changes = sign_changes(c, m);
    if changes == 1 && c[0] != 0.0 && c[m] != 0.0 {
        let x = bracketed_root(c);
        if visit(xa + x * (xb - xa)) == Flow::Stop {
            return Flow::Stop;
        }
    } else if changes >= 1 {
        if depth >= MAX_DEPTH {
            if visit(0.5 * (xa + xb)) == Flow::Stop {
                return Flow::Stop;
            }
        } else {
            let (left, right) = halve(c);
            let xm = 0.5 * (xa + xb);
            let ((near, n0, n1), (far, f0, f1)) = if forward {
                ((&left, xa, xm), (&right, xm, xb))
            } else {
                ((&right, xm, xb), (&left, xa, xm))
            };
            if search(near, n0, n1, forward, depth + 1, visit) == Flow::Stop
                || search(far, f0, f1, forward, depth + 1, visit) == Flow::Stop
            {
                return Flow::Stop;
            }
        }
    }
    if c_last == 0.0 && visit(last) == Flow::Stop {
        return Flow::Stop;
    }
    Flow::Continue
}

/// [`visit_roots`] for a polynomial of any degree `m` ≤ 2·[`LARGEST_DEGREE`],
/// held in `buf[..=m]`: the rest of `buf` is scratch for the subdivision
/// (grown as needed, truncated back to m + 1 on return), so that a caller
/// that keeps its buffer allocates nothing once it has grown. The same
/// search as the fixed-size one, step for step.
pub fn visit_roots_any(
    buf: &mut Vec<f64>,
    m: usize,
    forward: bool,
    visit: &mut impl FnMut(f64) -> Flow,
) -> Flow {
    buf.truncate(m + 1);
    search_any(buf, 0, m, 0.0, 1.0, forward, 0, visit)
}

/// [`search`] on the coefficients `buf[off..=off + m]`; the halves of a
/// subdivision go on the end of `buf` while they are searched.
#[allow(clippy::too_many_arguments)]
fn search_any(
    buf: &mut Vec<f64>,
    off: usize,
    m: usize,
    xa: f64,
    xb: f64,
    forward: bool,
    depth: u32,
    visit: &mut impl FnMut(f64) -> Flow,
) -> Flow {
    let (c0, cm) = (buf[off], buf[off + m]);
    let (first, last) = if forward { (xa, xb) } else { (xb, xa) };
    let (c_first, c_last) = if forward { (c0, cm) } else { (cm, c0) };
    if c_first == 0.0 && visit(first) == Flow::Stop {
        return Flow::Stop;
    }
    let changes = sign_changes(&buf[off..], m);
    if changes == 1 && c0 != 0.0 && cm != 0.0 {
        let x = bracketed_root_any(&buf[off..=off + m], m);
        if visit(xa + x * (xb - xa)) == Flow::Stop {
            return Flow::Stop;
        }
    } else if changes >= 1 {
        if depth >= MAX_DEPTH {
            if visit(0.5 * (xa + xb)) == Flow::Stop {
                return Flow::Stop;
            }
        } else {
            // Halve at ½ (as `halve`): the left half at `base`, the right
            // half after it, computed in place.
            let base = buf.len();
            buf.resize(base + 2 * (m + 1), 0.0);
            let (src, halves) = buf.split_at_mut(base);
            let (left, right) = halves.split_at_mut(m + 1);
            right.copy_from_slice(&src[off..=off + m]);
            for (j, l) in left.iter_mut().enumerate() {
                *l = right[0];
                for i in 0..m - j {
                    right[i] = 0.5 * (right[i] + right[i + 1]);
                }
            }
            let xm = 0.5 * (xa + xb);
            let (l_off, r_off) = (base, base + m + 1);
            let ((n_off, n0, n1), (f_off, f0, f1)) = if forward {
                ((l_off, xa, xm), (r_off, xm, xb))
            } else {
                ((r_off, xm, xb), (l_off, xa, xm))
            };
            let stop = search_any(buf, n_off, m, n0, n1, forward, depth + 1, visit) == Flow::Stop
                || search_any(buf, f_off, m, f0, f1, forward, depth + 1, visit) == Flow::Stop;
            buf.truncate(base);
            if stop {
                return Flow::Stop;
            }
        }
    }
    if c_last == 0.0 && visit(last) == Flow::Stop {
        return Flow::Stop;
    }
    Flow::Continue
}

/// Calls `$f::<L>(args)` for the array length `$len` (1 ≤ L ≤ [`MAXF`]),
/// or gives `$default` for any other length.
macro_rules! with_len {
    ($len:expr, $default:expr, $f:ident ( $($arg:expr),* )) => {
        match $len {
            1 => $f::<1>($($arg),*), 2 => $f::<2>($($arg),*), 3 => $f::<3>($($arg),*),
            4 => $f::<4>($($arg),*), 5 => $f::<5>($($arg),*), 6 => $f::<6>($($arg),*),
            7 => $f::<7>($($arg),*), 8 => $f::<8>($($arg),*), 9 => $f::<9>($($arg),*),
            10 => $f::<10>($($arg),*), 11 => $f::<11>($($arg),*), 12 => $f::<12>($($arg),*),
            13 => $f::<13>($($arg),*), 14 => $f::<14>($($arg),*), 15 => $f::<15>($($arg),*),
            16 => $f::<16>($($arg),*), 17 => $f::<17>($($arg),*), 18 => $f::<18>($($arg),*),
            19 => $f::<19>($($arg),*), 20 => $f::<20>($($arg),*), 21 => $f::<21>($($arg),*),
            22 => $f::<22>($($arg),*), 23 => $f::<23>($($arg),*), 24 => $f::<24>($($arg),*),
            25 => $f::<25>($($arg),*), 26 => $f::<26>($($arg),*), 27 => $f::<27>($($arg),*),
            28 => $f::<28>($($arg),*), 29 => $f::<29>($($arg),*), 30 => $f::<30>($($arg),*),
            31 => $f::<31>($($arg),*), 32 => $f::<32>($($arg),*), 33 => $f::<33>($($arg),*),
            _ => $default,
        }
    };
}

/// All real roots in the open interval (0, 1), ascending (construction time only).
pub fn roots_in_open_unit(c: &[f64], m: usize) -> Vec<f64> {
    fn roots<const L: usize>(c: &[f64]) -> Vec<f64> {
        let coeffs: [f64; L] = std::array::from_fn(|i| c[i]);
        let mut out = Vec::new();
        visit_roots(&coeffs, true, &mut |x| {
            if x > 0.0 && x < 1.0 && out.last().is_none_or(|&l: &f64| x > l) {
                out.push(x);
            }
            Flow::Continue
        });
        out
    }
    if m == 0 || c[..=m].iter().all(|&v| v == 0.0) {
        return Vec::new();
    }
    if m < MAXF {
        return with_len!(m + 1, Vec::new(), roots(c));
    }
    let mut out = Vec::new();
    let mut buf = c[..=m].to_vec();
    visit_roots_any(&mut buf, m, true, &mut |x| {
        if x > 0.0 && x < 1.0 && out.last().is_none_or(|&l: &f64| x > l) {
            out.push(x);
        }
        Flow::Continue
    });
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
    use super::*;

    fn from_power(p: &[f64]) -> Vec<f64> {
        // Bernstein coefficients of Σ p_j x^j: b_k = Σ_{j≤k} C(k,j)/C(m,j) p_j.
        let m = p.len() - 1;
        (0..=m)
            .map(|k| (0..=k).map(|j| BINOM[k][j] / BINOM[m][j] * p[j]).sum())
            .collect()
    }

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

    #[test]
    fn roots_of_product_of_linear_factors() {
        // (x − 0.1)(x − 0.5)(x − 0.500001)(x − 0.9)
        let p = [
            0.1 * 0.5 * 0.500001 * 0.9,
            -(0.5 * 0.500001 * 0.9 + 0.1 * 0.500001 * 0.9 + 0.1 * 0.5 * 0.9 + 0.1 * 0.5 * 0.500001),
            0.1 * 0.5 + 0.1 * 0.500001 + 0.1 * 0.9 + 0.5 * 0.500001 + 0.5 * 0.9 + 0.500001 * 0.9,
            -(0.1 + 0.5 + 0.500001 + 0.9),
            1.0,
        ];
        let c = from_power(&p);
        let r = roots_in_open_unit(&c, 4);
        assert_eq!(r.len(), 4, "{r:?}");
        // The pair 1e-6 apart moves by ~ε/|f'| ≈ 1e-9 under rounding of the coefficients.
        for (got, want) in r.iter().zip([0.1, 0.5, 0.500001, 0.9]) {
            assert!((got - want).abs() < 1e-8, "{got} vs {want}");
        }
    }

    /// A small deterministic generator for the tests.
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Value by de Casteljau (independent of the binomial tables).
    fn casteljau(c: &[f64], x: f64) -> f64 {
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
    fn from_roots(roots: &[f64]) -> Vec<f64> {
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

    fn visited_fixed<const L: usize>(c: &[f64], forward: bool) -> Vec<f64> {
        let coeffs: [f64; L] = std::array::from_fn(|i| c[i]);
        let mut out = Vec::new();
        visit_roots(&coeffs, forward, &mut |x| {
            out.push(x);
            Flow::Continue
        });
        out
    }

    fn visited_any(c: &[f64], forward: bool) -> Vec<f64> {
        let mut buf = c.to_vec();
        // Leftover content past the polynomial must not matter.
        buf.extend([7.0; 5]);
        let mut out = Vec::new();
        visit_roots_any(&mut buf, c.len() - 1, forward, &mut |x| {
            out.push(x);
            Flow::Continue
        });
        assert_eq!(buf.len(), c.len(), "the scratch is given back");
        out
    }

    /// The slice search visits exactly (bit for bit) what the fixed-size
    /// search visits, in both directions, for every length the fixed one has.
    #[test]
    fn any_degree_search_matches_fixed_search() {
        let mut rng = Lcg(3);
        for trial in 0..600 {
            let m = 1 + trial % 32;
            let c: Vec<f64> = if trial % 2 == 0 {
                (0..=m).map(|_| 2.0 * rng.next() - 1.0).collect()
            } else {
                let roots: Vec<f64> = (0..m).map(|_| 1.4 * rng.next() - 0.2).collect();
                from_roots(&roots)
            };
            for forward in [true, false] {
                let fixed = with_len!(m + 1, unreachable!(), visited_fixed(&c, forward));
                let any = visited_any(&c, forward);
                assert_eq!(
                    fixed.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    any.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    "{c:?}"
                );
            }
        }
    }

    /// Degrees above the fixed tables: evaluation, products, restriction,
    /// maxima and roots against de Casteljau and known roots.
    #[test]
    fn high_degree_routines_are_accurate() {
        let mut rng = Lcg(5);
        for m in [33, 40, 64, 100, 128] {
            let c: Vec<f64> = (0..=m).map(|_| 2.0 * rng.next() - 1.0).collect();
            // The derivative: de Casteljau on the hodograph m·(c[i+1] − c[i]).
            let hodograph: Vec<f64> = c.windows(2).map(|w| m as f64 * (w[1] - w[0])).collect();
            for i in 0..=50 {
                let x = i as f64 / 50.0;
                let (f, d) = eval_d_any(&c, m, x);
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
                let want = eval_d_any(&a, n, x).1;
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
        // Roots: a few simple roots in (0, 1), two of them 1e-4 apart, the
        // rest of the degree outside [0, 1] (as for a ray's polynomial).
        for m in [34, 40, 64, 100, 128] {
            let mut want: Vec<f64> = (0..5)
                .map(|k| (k as f64 + 0.1 + 0.8 * rng.next()) / 5.0)
                .collect();
            want.push(want[2] + 1e-4);
            let outside = (want.len()..m).map(|k| {
                if k % 2 == 0 {
                    -0.3 - 2.0 * rng.next()
                } else {
                    1.3 + 2.0 * rng.next()
                }
            });
            let all: Vec<f64> = want.iter().copied().chain(outside).collect();
            let c = from_roots(&all);
            let got = roots_in_open_unit(&c, m);
            want.sort_by(f64::total_cmp);
            assert_eq!(got.len(), want.len(), "m {m}: {got:?}");
            for (g, w) in got.iter().zip(&want) {
                assert!((g - w).abs() < 1e-9, "m {m}: root {g} vs {w}");
            }
        }
    }

    #[test]
    fn max_bound_is_close_and_above() {
        let c = from_power(&[0.0, 4.0, -4.0]); // 4x(1−x), max 1 at 0.5
        let m = max_on_unit(&c, 2, 1e-12);
        assert!((1.0..1.0 + 2e-12).contains(&m), "{m}");
    }
}
