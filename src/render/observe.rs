//! The one way a pass picks what watches its samples: the anti-aliasing's
//! hash, the shading AOVs' tally, the queries' cost, any of them together
//! or nothing, each choice its own monomorphised loop (watching nothing
//! costs nothing).

use super::shading_aovs::LightTally;
use crate::accel::QueryCost;
use crate::integrator::{AaHash, NoObserver, PathObserver};

/// What a pass keeps of a sample's observer: the anti-aliasing's hash, the
/// shading AOVs' tally and the queries' cost, where it watches them.
pub(super) trait Kept: PathObserver + Clone {
    /// The folded hash.
    fn hash(&self) -> Option<u32> {
        None
    }

    /// The tally.
    fn tally(&self) -> Option<&LightTally> {
        None
    }

    /// The queries' cost.
    fn cost(&self) -> Option<QueryCost> {
        None
    }
}

impl Kept for NoObserver {}

impl Kept for AaHash {
    fn hash(&self) -> Option<u32> {
        Some(self.folded())
    }
}

impl Kept for LightTally {
    fn tally(&self) -> Option<&LightTally> {
        Some(self)
    }
}

impl Kept for QueryCost {
    fn cost(&self) -> Option<QueryCost> {
        Some(*self)
    }
}

impl<A: Kept, B: Kept> Kept for (A, B) {
    fn hash(&self) -> Option<u32> {
        self.0.hash().or(self.1.hash())
    }

    fn tally(&self) -> Option<&LightTally> {
        self.0.tally().or(self.1.tally())
    }

    fn cost(&self) -> Option<QueryCost> {
        self.0.cost().or(self.1.cost())
    }
}

/// Work run with the observer [`with_observer`] picks; a trait with a
/// generic method, since a closure cannot be generic over the observer.
pub(super) trait ObservedJob {
    /// What the work returns.
    type Out;

    /// Runs the work, each sample watched by a copy of `fresh`.
    fn run<O: Kept>(self, fresh: &O) -> Self::Out;
}

/// What a pass asks to watch.
#[derive(Clone, Copy)]
pub(super) struct Watched<'t> {
    /// The anti-aliasing's hash.
    pub hash: bool,
    /// The shading AOVs' tally, from this fresh one.
    pub tally: Option<&'t LightTally>,
    /// The queries' cost.
    pub cost: bool,
}

/// Runs `job` with a fresh observer of what `watched` asks for.
pub(super) fn with_observer<J: ObservedJob>(watched: Watched, job: J) -> J::Out {
    if watched.hash {
        without_hash(watched, HashedToo(job))
    } else {
        without_hash(watched, job)
    }
}

/// [`with_observer`] for the tally and the cost.
fn without_hash<J: ObservedJob>(watched: Watched, job: J) -> J::Out {
    match (watched.tally, watched.cost) {
        (None, false) => job.run(&NoObserver),
        (Some(t), false) => job.run(t),
        (None, true) => job.run(&QueryCost::default()),
        (Some(t), true) => job.run(&(*t, QueryCost::default())),
    }
}

/// A job whose observer watches the anti-aliasing's hash too.
struct HashedToo<J>(J);

impl<J: ObservedJob> ObservedJob for HashedToo<J> {
    type Out = J::Out;

    fn run<O: Kept>(self, fresh: &O) -> J::Out {
        self.0.run(&(AaHash::default(), fresh.clone()))
    }
}
