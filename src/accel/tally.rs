//! Counting the work of ray queries, for the `cost` pass: a tally the
//! queries are generic over, so that one counting nothing costs nothing.

/// Counts the work of ray queries (the `cost` pass): BVH nodes visited and
/// primitives tested. The queries are generic over it, so `()`, which
/// counts nothing, costs nothing.
pub trait QueryTally {
    /// A BVH node was visited: an inner node, whose two children's boxes
    /// are tested, or a leaf, whose primitives are.
    fn node(&mut self);
    /// `n` primitives were tested against the ray.
    fn tests(&mut self, n: usize);
}

/// Counts nothing.
impl QueryTally for () {
    #[inline(always)]
    fn node(&mut self) {}

    #[inline(always)]
    fn tests(&mut self, _: usize) {}
}

/// A borrowed tally counts into its owner.
impl<T: QueryTally> QueryTally for &mut T {
    #[inline(always)]
    fn node(&mut self) {
        (**self).node()
    }

    #[inline(always)]
    fn tests(&mut self, n: usize) {
        (**self).tests(n)
    }
}

/// Both count.
impl<A: QueryTally, B: QueryTally> QueryTally for (A, B) {
    #[inline(always)]
    fn node(&mut self) {
        self.0.node();
        self.1.node();
    }

    #[inline(always)]
    fn tests(&mut self, n: usize) {
        self.0.tests(n);
        self.1.tests(n);
    }
}

/// The work of ray queries, counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QueryCost {
    /// BVH nodes visited, inner nodes and leaves.
    pub nodes: u64,
    /// Primitives tested: those of the leaves visited, the unbounded ones,
    /// and an any-hit query's hinted blocker.
    pub tests: u64,
}

impl QueryCost {
    /// Adds another count to this one.
    pub fn add(&mut self, o: &QueryCost) {
        self.nodes += o.nodes;
        self.tests += o.tests;
    }
}

impl QueryTally for QueryCost {
    #[inline(always)]
    fn node(&mut self) {
        self.nodes += 1;
    }

    #[inline(always)]
    fn tests(&mut self, n: usize) {
        self.tests += n as u64;
    }
}
