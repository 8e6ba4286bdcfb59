//! The pair driver: how pairs are enumerated, apart from what one pair contributes.
//!
//! An equation ([`PairEquation`]) says what it reads of a particle (its `Source`, packed once
//! per pass for every particle and image, so that a pair touches one or two cache lines rather
//! than one per field), what it sums for a real particle (`Sum`, started from the particle's own
//! source), what one partner adds to that sum, and how the sum is finished. The driver
//! ([`gather`]) visits each real particle's partners in the order of its list, in parallel over
//! particles: each sum is accumulated in one fixed order, so the result is bitwise the same for
//! any number of threads.
//!
//! Partners come from a [`Partners`] enumeration: the step's neighbour lists (a pair is then
//! the two particles alone), or bonds fixed at the start (total-Lagrangian solids), where each
//! pair also carries the bond's reference data (its `Link`).

use crate::neighbours::NeighbourList;
use crate::particles::Particles;
use rayon::prelude::*;

/// Who each real particle's partners are, and what a pair carries besides the two particles.
pub trait Partners: Sync {
    /// The data of one pair (`()` for plain neighbours).
    type Link;
    /// Calls `visit(j, link)` for each partner j of real particle i, in a fixed order.
    fn visit(&self, i: usize, visit: impl FnMut(usize, &Self::Link));
}

impl Partners for NeighbourList {
    type Link = ();

    #[inline]
    fn visit(&self, i: usize, mut visit: impl FnMut(usize, &())) {
        for &j in self.partners(i) {
            visit(j as usize, &());
        }
    }
}

/// What one pair contributes to a real particle's sum, and how that sum starts and ends.
pub trait PairEquation<const D: usize, Link = ()>: Sync {
    /// What the equation reads of a particle.
    type Source: Send + Sync;
    /// What it accumulates for a real particle.
    type Sum;
    /// What the pass returns per real particle.
    type Output: Send;

    /// Particle (or image) k as its partners see it.
    fn source(&self, particles: &Particles<D>, k: usize) -> Self::Source;
    /// The sum before any partner: zero, or the particle's own term.
    fn start(&self, me: &Self::Source) -> Self::Sum;
    /// Adds partner `other`'s contribution to `me`'s sum.
    fn pair(&self, sum: &mut Self::Sum, me: &Self::Source, other: &Self::Source, link: &Link);
    /// The per-particle result from the completed sum.
    fn finish(&self, me: &Self::Source, sum: Self::Sum) -> Self::Output;
}

/// Every particle's and image's source for `equation`.
pub fn sources<const D: usize, L, E: PairEquation<D, L>>(
    equation: &E,
    particles: &Particles<D>,
) -> Vec<E::Source> {
    (0..particles.len())
        .into_par_iter()
        .with_min_len(PARTICLES_PER_TASK)
        .map(|k| equation.source(particles, k))
        .collect()
}

/// Real particle i's sum over its partners, from sources packed by [`sources`].
#[inline]
pub fn sum_at<const D: usize, P: Partners, E: PairEquation<D, P::Link>>(
    equation: &E,
    sources: &[E::Source],
    partners: &P,
    i: usize,
) -> E::Output {
    let me = &sources[i];
    let mut sum = equation.start(me);
    partners.visit(i, |j, link| equation.pair(&mut sum, me, &sources[j], link));
    equation.finish(me, sum)
}

/// The equation's output for every real particle.
pub fn gather<const D: usize, P: Partners, E: PairEquation<D, P::Link>>(
    equation: &E,
    particles: &Particles<D>,
    partners: &P,
) -> Vec<E::Output> {
    let sources = sources(equation, particles);
    (0..particles.n_real())
        .into_par_iter()
        .with_min_len(PARTICLES_PER_TASK)
        .map(|i| sum_at(equation, &sources, partners, i))
        .collect()
}

/// The equation's output for the real particles `which` (in that order): the particles whose
/// step ends now, with individual time steps. Where they are a small part of the scene, each
/// reads its partners' sources directly rather than packing every particle's first (the same
/// values, so the same result).
pub fn gather_at<const D: usize, P: Partners, E: PairEquation<D, P::Link>>(
    equation: &E,
    particles: &Particles<D>,
    partners: &P,
    which: &[usize],
) -> Vec<E::Output> {
    if which.len() * SMALL_PART >= particles.len() {
        let sources = sources(equation, particles);
        return which
            .par_iter()
            .with_min_len(PARTICLES_PER_TASK)
            .map(|&i| sum_at(equation, &sources, partners, i))
            .collect();
    }
    which
        .par_iter()
        .with_min_len(PARTICLES_PER_TASK)
        .map(|&i| sum_reading(equation, particles, partners, i))
        .collect()
}

/// Real particle i's sum over its partners, reading each source from the particles (the
/// same values [`sources`] packs): for a few particles of a scene.
#[inline]
pub fn sum_reading<const D: usize, P: Partners, E: PairEquation<D, P::Link>>(
    equation: &E,
    particles: &Particles<D>,
    partners: &P,
    i: usize,
) -> E::Output {
    let me = equation.source(particles, i);
    let mut sum = equation.start(&me);
    partners.visit(i, |j, link| {
        equation.pair(&mut sum, &me, &equation.source(particles, j), link)
    });
    equation.finish(&me, sum)
}

/// The fewest particles a parallel pass hands to one task: a pass over fewer runs on the
/// calling thread alone, where waking another thread would cost more than the work it takes
/// over (with individual time steps a step often ends for a few dozen particles). Each
/// particle's sum is the same on any thread, so this changes no result.
pub(crate) const PARTICLES_PER_TASK: usize = 32;

/// Below one particle in SMALL_PART, a pass over some particles reads sources directly: a
/// particle has about ten partners in 1D and more beyond, so packing every source costs more
/// than reading each partner's where fewer than a few in ten particles take part.
const SMALL_PART: usize = 4;
