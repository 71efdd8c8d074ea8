//! Real roots of a Bernstein polynomial on [0, 1], nearest first in either
//! direction: isolated by subdivision (Descartes' rule for the Bernstein
//! basis) and refined by Newton's method kept inside a bracket. Written
//! once, over any [`Store`] of the coefficients.

use super::bernstein::eval_d;
use super::store::{Scratch, Store};

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

/// Visits the real roots in [0, 1] of `c` in increasing order (`forward`)
/// or decreasing order, until `visit` says stop. Roots are isolated by
/// subdividing until the coefficients change sign at most once; clusters
/// narrower than 2⁻⁴⁸ are visited once. Roots on interval ends may be
/// visited twice.
#[inline]
pub fn visit_roots<S: Store, V: FnMut(f64) -> Flow>(
    store: &mut S,
    c: &S::Poly,
    forward: bool,
    visit: &mut V,
) -> Flow {
    Search {
        store,
        forward,
        visit,
    }
    .run(c, (0.0, 1.0), 0)
}

/// One root search: the store its halves go in, the direction and the
/// visitor, shared by every level of the subdivision (one pointer a level).
struct Search<'a, S, V> {
    store: &'a mut S,
    forward: bool,
    visit: &'a mut V,
}

impl<S: Store, V: FnMut(f64) -> Flow> Search<'_, S, V> {
    /// The roots of `c`, the polynomial on the interval `(xa, xb)` of the
    /// original, `depth` halvings down.
    fn run(&mut self, c: &S::Poly, (xa, xb): (f64, f64), depth: u32) -> Flow {
        let (forward, m) = (self.forward, self.store.degree());
        let (c0, cm) = {
            let c = self.store.coefs(c);
            (c[0], c[m])
        };
        let (first, last) = if forward { (xa, xb) } else { (xb, xa) };
        let (c_first, c_last) = if forward { (c0, cm) } else { (cm, c0) };
        if c_first == 0.0 && (self.visit)(first) == Flow::Stop {
            return Flow::Stop;
        }
        let changes = sign_changes(self.store.coefs(c));
        if changes == 1 && c0 != 0.0 && cm != 0.0 {
            let x = bracketed_root(self.store, c);
            if (self.visit)(xa + x * (xb - xa)) == Flow::Stop {
                return Flow::Stop;
            }
        } else if changes >= 1 {
            if depth >= MAX_DEPTH {
                if (self.visit)(0.5 * (xa + xb)) == Flow::Stop {
                    return Flow::Stop;
                }
            } else {
                let halves = self.store.halve(c);
                let xm = 0.5 * (xa + xb);
                let [left, right] = &halves;
                let ((near, near_span), (far, far_span)) = if forward {
                    ((left, (xa, xm)), (right, (xm, xb)))
                } else {
                    ((right, (xm, xb)), (left, (xa, xm)))
                };
                let stop = self.run(near, near_span, depth + 1) == Flow::Stop
                    || self.run(far, far_span, depth + 1) == Flow::Stop;
                self.store.release(halves);
                if stop {
                    return Flow::Stop;
                }
            }
        }
        if c_last == 0.0 && (self.visit)(last) == Flow::Stop {
            return Flow::Stop;
        }
        Flow::Continue
    }
}

/// Sign changes in the coefficient sequence, zeros skipped: an upper bound
/// on the number of roots in the open interval, exact when 0 or 1.
#[inline(always)]
fn sign_changes(c: &[f64]) -> u32 {
    let mut n = 0;
    let mut prev = 0.0;
    for &v in c {
        if v != 0.0 {
            if prev != 0.0 && (v > 0.0) != (prev > 0.0) {
                n += 1;
            }
            prev = v;
        }
    }
    n
}

/// The root in (0, 1) of the polynomial `c`, whose end values have
/// opposite signs and which has exactly one root there.
#[inline(always)]
fn bracketed_root<S: Store>(store: &S, c: &S::Poly) -> f64 {
    let (m, c) = (store.degree(), store.coefs(c));
    let positive_at_0 = c[0] > 0.0;
    // Start where the control polygon first crosses zero.
    let mut x = 0.5;
    for k in 0..m {
        if (c[k + 1] > 0.0) != positive_at_0 {
            x = ((k as f64 + c[k] / (c[k] - c[k + 1])) / m as f64).clamp(0.0, 1.0);
            break;
        }
    }
    // (The degree read again inside: a constant there for a fixed store.)
    newton_in_bracket(x, positive_at_0, |x| eval_d(c, store.degree(), x))
}

/// The single root in (0, 1) of a function (`eval` gives its value and
/// derivative) whose values at 0 and 1 have opposite signs, positive at 0
/// when `positive_at_0`: Newton's method from `x`, kept inside a shrinking
/// bracket, bisecting when a step leaves it.
#[inline(always)]
pub fn newton_in_bracket(mut x: f64, positive_at_0: bool, eval: impl Fn(f64) -> (f64, f64)) -> f64 {
    let (mut a, mut b) = (0.0, 1.0);
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
fn converged(step: f64, last_step: f64) -> bool {
    let step = step.abs();
    step <= 1e-15 || (step <= 1e-8 && step <= 1e-3 * last_step.abs())
}

/// All real roots in the open interval (0, 1) of `c` (degree `m`),
/// ascending (construction time only).
pub fn roots_in_open_unit(c: &[f64], m: usize) -> Vec<f64> {
    let mut out = Vec::new();
    if m == 0 || c[..=m].iter().all(|&v| v == 0.0) {
        return out;
    }
    Scratch::with(m, |store| {
        let poly = store.build(|coefs, _| coefs.copy_from_slice(&c[..=m]));
        visit_roots(store, &poly, true, &mut |x| {
            if x > 0.0 && x < 1.0 && out.last().is_none_or(|&l: &f64| x > l) {
                out.push(x);
            }
            Flow::Continue
        });
    });
    out
}

#[cfg(test)]
mod tests {
    use super::super::store::Fixed;
    use super::super::test_polys::{Lcg, from_power, from_roots};
    use super::*;

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

    /// The roots `store` visits for `c` (of the store's degree), as bits.
    fn visited<S: Store>(store: &mut S, c: &[f64], forward: bool) -> Vec<u64> {
        let poly = store.build(|coefs, spare| {
            // Leftover content in the scratch must not matter.
            spare.fill(7.0);
            coefs.copy_from_slice(c);
        });
        let mut out = Vec::new();
        visit_roots(store, &poly, forward, &mut |x| {
            out.push(x.to_bits());
            Flow::Continue
        });
        out
    }

    /// The search visits exactly (bit for bit) the same roots on the stack
    /// and in the scratch buffer, in both directions, for every length the
    /// fixed-size path has, and gives the scratch back.
    #[test]
    fn stack_and_scratch_searches_agree() {
        fn on_stack<const L: usize>(c: &[f64], forward: bool) -> Option<Vec<u64>> {
            (c.len() == L).then(|| visited(&mut Fixed::<L>, c, forward))
        }
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
                let fixed = [
                    on_stack::<2>,
                    on_stack::<3>,
                    on_stack::<4>,
                    on_stack::<5>,
                    on_stack::<6>,
                    on_stack::<7>,
                    on_stack::<8>,
                    on_stack::<9>,
                    on_stack::<10>,
                    on_stack::<11>,
                    on_stack::<12>,
                    on_stack::<13>,
                    on_stack::<14>,
                    on_stack::<15>,
                    on_stack::<16>,
                    on_stack::<17>,
                    on_stack::<18>,
                    on_stack::<19>,
                    on_stack::<20>,
                    on_stack::<21>,
                    on_stack::<22>,
                    on_stack::<23>,
                    on_stack::<24>,
                    on_stack::<25>,
                    on_stack::<26>,
                    on_stack::<27>,
                    on_stack::<28>,
                    on_stack::<29>,
                    on_stack::<30>,
                    on_stack::<31>,
                    on_stack::<32>,
                    on_stack::<33>,
                ]
                .iter()
                .find_map(|f| f(&c, forward));
                let (any, held) = Scratch::with(m, |store| {
                    let any = visited(store, &c, forward);
                    // The next halves go right after the polynomial.
                    (any, store.halve(&0)[0])
                });
                assert_eq!(fixed, Some(any), "{c:?}");
                assert_eq!(held, m + 1, "the scratch is given back");
            }
        }
    }

    /// Degrees above the fixed-size path: a few simple roots in (0, 1), two
    /// of them 1e-4 apart, the rest of the degree outside [0, 1] (as for a
    /// ray's polynomial).
    #[test]
    fn high_degree_roots_are_found() {
        let mut rng = Lcg(5);
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
}
