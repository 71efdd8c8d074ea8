//! Where the root search keeps a polynomial and the halves it splits it
//! into: fixed-size arrays on the stack (the degree a compile-time
//! constant: the fastest code, one specialisation per degree), or a scratch
//! buffer that grows to the largest size needed and is then reused (any
//! degree). Neither allocates per ray once warm.

use super::bernstein::halve;
use std::cell::RefCell;

/// Storage for polynomials of one degree: the root search is written once
/// over it (see [`super::roots::visit_roots`]).
pub trait Store {
    /// A polynomial held in this store.
    type Poly;
    /// The degree of every polynomial held where the type fixes it: a
    /// constant also in code that cannot reach the store (a root visitor).
    const FIXED_DEGREE: Option<usize>;
    /// The degree of every polynomial held.
    fn degree(&self) -> usize;
    /// A new polynomial whose coefficients `fill` writes into zeros; `fill`
    /// also gets as many values of scratch for its own use.
    fn build(&mut self, fill: impl FnOnce(&mut [f64], &mut [f64])) -> Self::Poly;
    /// The coefficients of `p` (degree + 1 of them).
    fn coefs<'a>(&'a self, p: &'a Self::Poly) -> &'a [f64];
    /// The coefficients of `p` on [0, ½] and on [½, 1].
    fn halve(&mut self, p: &Self::Poly) -> [Self::Poly; 2];
    /// Gives back the halves of the last [`Store::halve`] once searched.
    fn release(&mut self, halves: [Self::Poly; 2]);
}

/// Polynomials of degree L − 1 as arrays on the stack.
pub struct Fixed<const L: usize>;

impl<const L: usize> Store for Fixed<L> {
    type Poly = [f64; L];
    const FIXED_DEGREE: Option<usize> = Some(L - 1);

    #[inline(always)]
    fn degree(&self) -> usize {
        L - 1
    }

    #[inline(always)]
    fn build(&mut self, fill: impl FnOnce(&mut [f64], &mut [f64])) -> [f64; L] {
        let mut c = [0.0; L];
        let mut spare = [0.0; L];
        fill(&mut c, &mut spare);
        c
    }

    #[inline(always)]
    fn coefs<'a>(&'a self, p: &'a [f64; L]) -> &'a [f64] {
        p
    }

    #[inline(always)]
    fn halve(&mut self, p: &[f64; L]) -> [[f64; L]; 2] {
        let mut left = [0.0; L];
        let mut right = *p;
        halve(&mut left, &mut right);
        [left, right]
    }

    #[inline(always)]
    fn release(&mut self, _: [[f64; L]; 2]) {}
}

/// Polynomials of any degree in a growing buffer: each is known by where
/// its coefficients start, and halves go on the end while they are searched.
pub struct Scratch<'a> {
    buf: &'a mut Vec<f64>,
    m: usize,
}

impl Scratch<'_> {
    /// Runs `f` with a store for polynomials of degree `m` on the calling
    /// thread's scratch buffer (a fresh one if that is in use).
    pub fn with<R>(m: usize, f: impl FnOnce(&mut Scratch<'_>) -> R) -> R {
        thread_local! {
            static BUFFER: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
        }
        BUFFER.with(|cell| match cell.try_borrow_mut() {
            Ok(mut buf) => f(&mut Scratch { buf: &mut buf, m }),
            Err(_) => f(&mut Scratch {
                buf: &mut Vec::new(),
                m,
            }),
        })
    }
}

impl Store for Scratch<'_> {
    /// Where the coefficients start in the buffer.
    type Poly = usize;
    const FIXED_DEGREE: Option<usize> = None;

    fn degree(&self) -> usize {
        self.m
    }

    fn build(&mut self, fill: impl FnOnce(&mut [f64], &mut [f64])) -> usize {
        let len = self.m + 1;
        self.buf.clear();
        self.buf.resize(2 * len, 0.0);
        let (c, spare) = self.buf.split_at_mut(len);
        fill(c, spare);
        self.buf.truncate(len);
        0
    }

    fn coefs<'a>(&'a self, p: &'a usize) -> &'a [f64] {
        &self.buf[*p..=*p + self.m]
    }

    fn halve(&mut self, p: &usize) -> [usize; 2] {
        let len = self.m + 1;
        let base = self.buf.len();
        self.buf.resize(base + 2 * len, 0.0);
        let (held, halves) = self.buf.split_at_mut(base);
        let (left, right) = halves.split_at_mut(len);
        right.copy_from_slice(&held[*p..*p + len]);
        halve(left, right);
        [base, base + len]
    }

    fn release(&mut self, [left, _]: [usize; 2]) {
        self.buf.truncate(left);
    }
}
