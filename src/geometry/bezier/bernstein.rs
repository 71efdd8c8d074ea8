//! Polynomials in the Bernstein basis on [0, 1]: evaluation, subdivision,
//! products and real-root isolation, all on fixed-size arrays.

/// Highest profile degree the fixed-size arrays hold.
pub const MAX_DEGREE: usize = 16;
/// Coefficients of a profile polynomial (degree ≤ [`MAX_DEGREE`]).
pub const MAXC: usize = MAX_DEGREE + 1;
/// Coefficients of a product of two profile polynomials.
pub const MAXF: usize = 2 * MAX_DEGREE + 1;

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
        0 => return (c[0], 0.0),
        1 => return (c[0] * (1.0 - x) + c[1] * x, c[1] - c[0]),
        _ => {}
    }
    let s = 1.0 - x;
    let bm = &BINOM[m];
    let bd = &BINOM[m - 1];
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

/// Splits `c` (degree `m`) at `x` into the coefficients on [0, x] and [x, 1].
#[inline]
pub fn split(c: &[f64], m: usize, x: f64, left: &mut [f64], right: &mut [f64]) {
    let mut tmp = [0.0; MAXF];
    tmp[..=m].copy_from_slice(&c[..=m]);
    for j in 0..=m {
        left[j] = tmp[0];
        right[m - j] = tmp[m - j];
        for i in 0..m - j {
            tmp[i] += x * (tmp[i + 1] - tmp[i]);
        }
    }
}

/// The coefficients of `c` (degree `m`) restricted to [a, b] ⊂ [0, 1].
pub fn restrict(c: &[f64], m: usize, a: f64, b: f64) -> [f64; MAXF] {
    let mut left = [0.0; MAXF];
    let mut right = [0.0; MAXF];
    split(c, m, a, &mut left, &mut right);
    if a >= 1.0 {
        return right;
    }
    let x = ((b - a) / (1.0 - a)).clamp(0.0, 1.0);
    let mut out = [0.0; MAXF];
    split(&right, m, x, &mut out, &mut left);
    out
}

/// Coefficients of the derivative (degree `m − 1`, `m ≥ 1`).
pub fn derivative(c: &[f64], m: usize) -> [f64; MAXF] {
    let mut d = [0.0; MAXF];
    for i in 0..m {
        d[i] = m as f64 * (c[i + 1] - c[i]);
    }
    d
}

/// Coefficients of the product of two degree-`n` polynomials (degree 2n).
pub fn product(a: &[f64], b: &[f64], n: usize) -> [f64; MAXF] {
    let mut out = [0.0; MAXF];
    let bn = &BINOM[n];
    for i in 0..=n {
        let ai = a[i] * bn[i];
        for j in 0..=n {
            out[i + j] += ai * b[j] * bn[j];
        }
    }
    let inv = &INV_BINOM[2 * n];
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
/// opposite signs and which has exactly one root there: Newton's method
/// kept inside a shrinking bracket, bisecting when a step leaves it.
fn bracketed_root<const L: usize>(c: &[f64; L]) -> f64 {
    let m = L - 1;
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
        let (f, d) = eval_d(c, m, x);
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
    with_len!(m + 1, Vec::new(), roots(c))
}

/// An upper bound within `tol` of the maximum of `c` (degree `m`) on [0, 1]
/// (branch and bound on the convex hull property; construction time only).
pub fn max_on_unit(c: &[f64], m: usize, tol: f64) -> f64 {
    if !c[..=m].iter().all(|v| v.is_finite()) {
        return f64::INFINITY;
    }
    let mut first = [0.0; MAXF];
    first[..=m].copy_from_slice(&c[..=m]);
    let mut best = c[0].max(c[m]);
    let mut bound = best;
    let mut stack = vec![(first, 0u32)];
    let mut budget = 100_000;
    while let Some((cur, depth)) = stack.pop() {
        budget -= 1;
        if budget == 0 {
            // (Unreachable for finite input; a safe answer regardless.)
            return cur[..=m]
                .iter()
                .chain(stack.iter().flat_map(|s| &s.0[..=m]))
                .fold(bound, |a, &b| a.max(b));
        }
        let hull = cur[..=m].iter().copied().fold(f64::NEG_INFINITY, f64::max);
        best = best.max(cur[0]).max(cur[m]);
        if hull <= best + tol {
            continue;
        }
        if depth >= 40 {
            bound = bound.max(hull);
            continue;
        }
        let mut left = [0.0; MAXF];
        let mut right = [0.0; MAXF];
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

    #[test]
    fn max_bound_is_close_and_above() {
        let c = from_power(&[0.0, 4.0, -4.0]); // 4x(1−x), max 1 at 0.5
        let m = max_on_unit(&c, 2, 1e-12);
        assert!((1.0..1.0 + 2e-12).contains(&m), "{m}");
    }
}
