//! Neighbour search by a cell-linked list, robust to smoothing lengths that vary by orders of
//! magnitude (a blast empties its centre, where h grows).
//!
//! A pair (i, j) interacts when r is below its [`PairReach`]: κ·(h_i + h_j)/2, the reach of the
//! symmetrised kernel W(r, h̄_ij), or κ·max(h_i, h_j) where each side uses its own h (grad-h
//! SPH); the lists are symmetric (j lists i iff i lists j), which the pairwise
//! conservation of momentum and energy needs. Each pair is found once, by its *owner*: the
//! particle with the larger h (the lower index on a tie), whose own reach κ·h covers the pair.
//! Owners search a box of cells sized to their own reach, so a few particles with a large h do
//! not make every particle scan a large box. The owned lists are then transposed, and each
//! particle's list is what it owns and the owners that list it, in index order: a list holds
//! the same partners in the same order however they were found (which h, which cells, which
//! owner), so sums over it do not depend on the search.
//!
//! Cells have the side 1.1 κ·(median h); particles are counting-sorted by cell (stable, so the order
//! is deterministic).

use crate::Vector;
use rayon::prelude::*;

/// Which pairs interact, given κ (the kernel's support in units of h).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairReach {
    /// r < κ (h_i + h_j)/2: the pair kernel is W(r, h̄_ij).
    MeanH,
    /// r < κ max(h_i, h_j): each particle weighs the pair with its own h.
    LargerH,
}

impl PairReach {
    /// The reach of a pair whose owner has `h_owner` ≥ `h_other`.
    #[inline]
    fn of(self, support: f64, h_owner: f64, h_other: f64) -> f64 {
        match self {
            PairReach::MeanH => 0.5 * support * (h_owner + h_other),
            PairReach::LargerH => support * h_owner,
        }
    }
}

/// Neighbour lists, each in ascending index order.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct NeighbourList {
    /// Particle i's partners are `partners[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<usize>,
    partners: Vec<u32>,
}

impl NeighbourList {
    /// The lists of particles 0, 1, … in turn, each in ascending index order.
    pub(crate) fn from_lists(lists: impl IntoIterator<Item = Vec<u32>>) -> Self {
        let mut offsets = vec![0];
        let mut partners = Vec::new();
        for list in lists {
            partners.extend(list);
            offsets.push(partners.len());
        }
        Self { offsets, partners }
    }

    /// Particle i's partners, in ascending index order.
    #[inline]
    pub fn partners(&self, i: usize) -> &[u32] {
        &self.partners[self.offsets[i]..self.offsets[i + 1]]
    }

    /// Particle i's neighbours.
    pub fn of(&self, i: usize) -> impl Iterator<Item = usize> + '_ {
        self.partners(i).iter().map(|&j| j as usize)
    }

    /// Number of particles that have lists.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Total number of (directed) pairs.
    pub fn pair_count(&self) -> usize {
        self.partners.len()
    }
}

/// Particles binned into a uniform grid of cubic cells.
#[derive(Clone, Debug)]
pub struct CellGrid<const D: usize> {
    origin: Vector<D>,
    cell_size: f64,
    dims: [usize; D],
    /// Members of cell c are `members[cell_start[c]..cell_start[c + 1]]`.
    cell_start: Vec<u32>,
    members: Vec<u32>,
}

impl<const D: usize> CellGrid<D> {
    /// Bins `positions` into cells of at least `min_cell_size`. The cell size grows where the
    /// bounding box would otherwise need more than a few cells per particle (a far outlier must
    /// not allocate a huge empty grid).
    pub fn build(positions: &[Vector<D>], min_cell_size: f64) -> Self {
        assert!(min_cell_size > 0.0 && min_cell_size.is_finite());
        let (lo, hi) = bounding_box(positions);
        // callers run the health check (finite positions) before binning
        assert!(
            lo.iter().chain(hi.iter()).all(|x| x.is_finite()),
            "CellGrid::build needs finite positions"
        );
        let max_cells = 4 * positions.len() + 64;
        let mut cell_size = min_cell_size;
        let dims = loop {
            // counted in f64: the product of a far outlier's cell counts overflows usize
            let cells_per_axis: [f64; D] =
                std::array::from_fn(|a| ((hi[a] - lo[a]) / cell_size).floor() + 1.0);
            if cells_per_axis.iter().product::<f64>() <= max_cells as f64 {
                break cells_per_axis.map(|n| n as usize);
            }
            cell_size *= 2.0;
        };
        let mut grid = Self {
            origin: lo,
            cell_size,
            dims,
            cell_start: Vec::new(),
            members: Vec::new(),
        };
        let keys: Vec<u32> = positions
            .par_iter()
            .map(|x| grid.linear_index(&grid.cell_of(x)) as u32)
            .collect();
        let n_cells: usize = dims.iter().product();
        let mut start = vec![0u32; n_cells + 1];
        for &k in &keys {
            start[k as usize + 1] += 1;
        }
        for c in 0..n_cells {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut members = vec![0u32; positions.len()];
        for (i, &k) in keys.iter().enumerate() {
            members[fill[k as usize] as usize] = i as u32;
            fill[k as usize] += 1;
        }
        grid.cell_start = start;
        grid.members = members;
        grid
    }

    /// Particle indices along the Morton (Z-order) curve through the cells: particles close in
    /// space end up close in memory on every axis, not only along the first (as row-major cell
    /// order would leave them).
    pub fn locality_order(&self, positions: &[Vector<D>]) -> Vec<usize> {
        let keys: Vec<u64> = positions
            .par_iter()
            .map(|x| morton_key(&self.cell_of(x)))
            .collect();
        let mut order: Vec<usize> = (0..positions.len()).collect();
        order.par_sort_unstable_by_key(|&i| (keys[i], i));
        order
    }

    fn cell_of(&self, x: &Vector<D>) -> [usize; D] {
        std::array::from_fn(|a| {
            let c = ((x[a] - self.origin[a]) / self.cell_size).floor();
            (c.max(0.0) as usize).min(self.dims[a] - 1)
        })
    }

    fn linear_index(&self, cell: &[usize; D]) -> usize {
        (0..D).rev().fold(0, |acc, a| acc * self.dims[a] + cell[a])
    }

    /// Calls `visit(c)` for each cell c within `rings` cells of `centre` on every axis, in a
    /// fixed order.
    #[inline]
    fn for_each_cell_around(
        &self,
        centre: &[usize; D],
        rings: usize,
        mut visit: impl FnMut(usize),
    ) {
        let lo: [usize; D] = std::array::from_fn(|a| centre[a].saturating_sub(rings));
        let hi: [usize; D] =
            std::array::from_fn(|a| centre[a].saturating_add(rings).min(self.dims[a] - 1));
        let mut cell = lo;
        loop {
            visit(self.linear_index(&cell));
            // odometer increment over the box lo..=hi
            let mut a = 0;
            loop {
                if a == D {
                    return;
                }
                if cell[a] < hi[a] {
                    cell[a] += 1;
                    break;
                }
                cell[a] = lo[a];
                a += 1;
            }
        }
    }

    fn members_of(&self, cell: usize) -> &[u32] {
        &self.members[self.cell_start[cell] as usize..self.cell_start[cell + 1] as usize]
    }

    /// The centre of cell `c`.
    fn centre(&self, c: usize) -> Vector<D> {
        let cell = self.coordinates(c);
        Vector::from_fn(|a, _| self.origin[a] + (cell[a] as f64 + 0.5) * self.cell_size)
    }

    /// The cell coordinates of linear index `c`.
    fn coordinates(&self, mut c: usize) -> [usize; D] {
        std::array::from_fn(|a| {
            let k = c % self.dims[a];
            c /= self.dims[a];
            k
        })
    }
}

/// Interleaves the low 64/D bits of each cell coordinate.
fn morton_key<const D: usize>(cell: &[usize; D]) -> u64 {
    let bits = 64 / D;
    let mut key = 0u64;
    for b in 0..bits {
        for (a, &c) in cell.iter().enumerate() {
            key |= (((c >> b) & 1) as u64) << (b * D + a);
        }
    }
    key
}

fn bounding_box<const D: usize>(positions: &[Vector<D>]) -> (Vector<D>, Vector<D>) {
    let mut lo = Vector::<D>::repeat(f64::INFINITY);
    let mut hi = Vector::<D>::repeat(f64::NEG_INFINITY);
    for x in positions {
        lo = lo.inf(x);
        hi = hi.sup(x);
    }
    if positions.is_empty() {
        (Vector::zeros(), Vector::zeros())
    } else {
        (lo, hi)
    }
}

/// Neighbour lists of the first `n_query` particles among all `positions` (the rest are images:
/// they are found, and own pairs, but get no list). `support` is κ, the kernel's support in
/// units of h.
pub fn find_neighbours<const D: usize>(
    positions: &[Vector<D>],
    smoothing_length: &[f64],
    support: f64,
    reach: PairReach,
    n_query: usize,
) -> NeighbourList {
    assert_eq!(positions.len(), smoothing_length.len());
    if n_query == 0 {
        return NeighbourList::default();
    }
    let grid = CellGrid::build(positions, CELL_MARGIN * support * median(smoothing_length));
    let owned = owned_lists(&grid, positions, smoothing_length, support, reach, n_query);
    symmetric_lists(owned, n_query)
}

/// Cells are this much wider than κ·(median h). A cell reaches out as many rings of cells as
/// its largest member's κ·h needs; where h scatters a little about the median (a lattice
/// whose h is solved to a tolerance, or follows a slightly compressed density), half the cells
/// of cells exactly κ·(median h) wide would hold a member just above it and search two rings,
/// 5^D cells instead of 3^D. Measured on Sedov 3D (10 648 particles, grad-h, global steps,
/// 2 threads), the whole run: 6.6 s at 1.0, 4.7–4.9 s at 1.05, 4.9 s at 1.1, 5.1 s at 1.2
/// (repeats differ by about 0.3 s); the lists are the same at any cell size.
const CELL_MARGIN: f64 = 1.1;

/// The median of `values` (the upper one for an even count).
fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    let middle = sorted.len() / 2;
    *sorted.select_nth_unstable_by(middle, f64::total_cmp).1
}

/// Whether i, not j, owns the pair (i, j): the larger h, the lower index on a tie.
#[inline]
fn owns(i: u32, h_i: f64, j: u32, h_j: f64) -> bool {
    h_i > h_j || (h_i == h_j && i < j)
}

/// For every particle, the pairs it owns, stored as the blocks the parallel tasks produced:
/// `location[i] = (block, start, len)`. Only pairs with at least one queried particle are kept.
#[derive(Clone, Debug, Default)]
struct OwnedLists {
    blocks: Vec<Vec<u32>>,
    location: Vec<(u32, u32, u32)>,
}

impl OwnedLists {
    fn of(&self, i: usize) -> &[u32] {
        let (b, start, len) = self.location[i];
        &self.blocks[b as usize][start as usize..(start + len) as usize]
    }
}

fn owned_lists<const D: usize>(
    grid: &CellGrid<D>,
    positions: &[Vector<D>],
    smoothing_length: &[f64],
    support: f64,
    reach: PairReach,
    n_query: usize,
) -> OwnedLists {
    let n_cells = grid.cell_start.len() - 1;
    // Work by cell: the particles in the box of cells the cell's members can reach are
    // gathered once into a contiguous buffer and tested against every member in a tight loop.
    // per task: (particle, start of its list) in visiting order, and the lists end to end
    type TaskLists = (Vec<(u32, u32)>, Vec<u32>);
    let tasks: Vec<TaskLists> = (0..n_cells.div_ceil(CELLS_PER_TASK))
        .into_par_iter()
        .map(|task| {
            let mut found: Vec<(u32, u32)> = Vec::new();
            let mut indices = Vec::new();
            let mut candidates = CandidateBuffer::<D>::default();
            for cell in task * CELLS_PER_TASK..((task + 1) * CELLS_PER_TASK).min(n_cells) {
                let members = grid.members_of(cell);
                if members.is_empty() {
                    continue;
                }
                let cell_reach = members
                    .iter()
                    .map(|&i| support * smoothing_length[i as usize])
                    .fold(0.0, f64::max);
                let rings = (cell_reach / grid.cell_size).ceil().max(1.0) as usize;
                // a cell of images only pairs with queried particles: the others are left out
                // of its candidates, and a cell with none around it has nothing to find
                let images_only = members.iter().all(|&i| i as usize >= n_query);
                candidates.clear(grid.centre(cell));
                grid.for_each_cell_around(&grid.coordinates(cell), rings, |c| {
                    for &j in grid.members_of(c) {
                        if !images_only || (j as usize) < n_query {
                            candidates.push(j, &positions[j as usize]);
                        }
                    }
                });
                if candidates.is_empty() {
                    continue;
                }
                for &i in members {
                    let start = indices.len() as u32;
                    candidates.collect_owned(
                        i,
                        positions,
                        smoothing_length,
                        (support, reach),
                        n_query,
                        &mut indices,
                    );
                    found.push((i, start));
                }
            }
            (found, indices)
        })
        .collect();
    let mut location = vec![(0u32, 0u32, 0u32); positions.len()];
    let mut blocks = Vec::with_capacity(tasks.len());
    for (b, (found, indices)) in tasks.into_iter().enumerate() {
        for (k, &(i, start)) in found.iter().enumerate() {
            let end = found.get(k + 1).map_or(indices.len() as u32, |next| next.1);
            location[i as usize] = (b as u32, start, end - start);
        }
        blocks.push(indices);
    }
    OwnedLists { blocks, location }
}

/// Each queried particle's list: the pairs it owns and the owners that list it (found by
/// transposing the owned lists), sorted by index.
fn symmetric_lists(owned: OwnedLists, n_query: usize) -> NeighbourList {
    let n = owned.location.len();
    let mut offsets = vec![0usize; n_query + 1];
    for i in 0..n {
        if i < n_query {
            offsets[i + 1] += owned.of(i).len();
        }
        for &j in owned.of(i).iter().filter(|&&j| (j as usize) < n_query) {
            offsets[j as usize + 1] += 1;
        }
    }
    for i in 0..n_query {
        offsets[i + 1] += offsets[i];
    }
    let mut partners = vec![0u32; offsets[n_query]];
    // what each list owns first, then the owners that list it
    let mut cursor = offsets[..n_query].to_vec();
    for (i, at) in cursor.iter_mut().enumerate() {
        let mine = owned.of(i);
        partners[*at..*at + mine.len()].copy_from_slice(mine);
        *at += mine.len();
    }
    for i in 0..n {
        for &j in owned.of(i).iter().filter(|&&j| (j as usize) < n_query) {
            partners[cursor[j as usize]] = i as u32;
            cursor[j as usize] += 1;
        }
    }
    let mut lists: Vec<&mut [u32]> = Vec::with_capacity(n_query);
    let mut rest = partners.as_mut_slice();
    for i in 0..n_query {
        let (list, tail) = rest.split_at_mut(offsets[i + 1] - offsets[i]);
        lists.push(list);
        rest = tail;
    }
    lists
        .into_par_iter()
        .with_min_len(LISTS_PER_TASK)
        .for_each(|list| list.sort_unstable());
    NeighbourList { offsets, partners }
}

/// Lists sorted per parallel task.
const LISTS_PER_TASK: usize = 256;

/// The particles around one cell as single-precision coordinates relative to the cell centre,
/// laid out by axis, with their indices. This f32 pass is a loose, vectorisable filter (its
/// reach is widened by FILTER_SLACK, far more than f32 round-off on coordinates of a few cell
/// sizes); the exact f64 test on the few that pass then decides, so the lists are those of an
/// f64 search.
struct CandidateBuffer<const D: usize> {
    origin: Vector<D>,
    index: Vec<u32>,
    coarse: [Vec<f32>; D],
    /// 1 where a candidate passes the f32 filter, 0 elsewhere.
    near: Vec<u8>,
}

/// Relative widening of the f32 filter's reach.
const FILTER_SLACK: f32 = 1e-3;

impl<const D: usize> Default for CandidateBuffer<D> {
    fn default() -> Self {
        Self {
            origin: Vector::zeros(),
            index: Vec::new(),
            coarse: std::array::from_fn(|_| Vec::new()),
            near: Vec::new(),
        }
    }
}

impl<const D: usize> CandidateBuffer<D> {
    fn clear(&mut self, origin: Vector<D>) {
        self.origin = origin;
        self.index.clear();
        self.coarse.iter_mut().for_each(Vec::clear);
    }

    fn is_empty(&self) -> bool {
        self.index.is_empty()
    }

    fn push(&mut self, index: u32, position: &Vector<D>) {
        self.index.push(index);
        for a in 0..D {
            self.coarse[a].push((position[a] - self.origin[a]) as f32);
        }
    }

    /// Appends to `out` every candidate j that i owns within the pair's reach, skipping pairs of
    /// two unqueried particles. The owner's own reach κ h_i covers every such pair, so the
    /// filter tests r < κ h_i.
    fn collect_owned(
        &mut self,
        i: u32,
        positions: &[Vector<D>],
        smoothing_length: &[f64],
        (support, pair_reach): (f64, PairReach),
        n_query: usize,
        out: &mut Vec<u32>,
    ) {
        let n = self.index.len();
        let (xi, h_i) = (positions[i as usize], smoothing_length[i as usize]);
        let centre: [f32; D] = std::array::from_fn(|a| (xi[a] - self.origin[a]) as f32);
        let reach = (support * h_i) as f32 * (1.0 + FILTER_SLACK);
        let reach2 = reach * reach;
        self.near.resize(n, 0);
        let coarse: [&[f32]; D] = std::array::from_fn(|a| &self.coarse[a][..n]);
        for (k, near) in self.near[..n].iter_mut().enumerate() {
            let mut r2 = 0.0f32;
            for a in 0..D {
                let d = coarse[a][k] - centre[a];
                r2 += d * d;
            }
            *near = u8::from(r2 < reach2);
        }
        // most candidates fail: eight flags are read as one word, and only the set ones
        // visited, in candidate order
        let queried = (i as usize) < n_query;
        for (c, flags) in self.near[..n].chunks(8).enumerate() {
            let mut word = [0u8; 8];
            word[..flags.len()].copy_from_slice(flags);
            let mut passed = u64::from_le_bytes(word);
            while passed != 0 {
                let k = 8 * c + (passed.trailing_zeros() / 8) as usize;
                passed &= passed - 1;
                let j = self.index[k];
                let h_j = smoothing_length[j as usize];
                let reach = pair_reach.of(support, h_i, h_j);
                if owns(i, h_i, j, h_j)
                    && (queried || (j as usize) < n_query)
                    && (positions[j as usize] - xi).norm_squared() < reach * reach
                {
                    out.push(j);
                }
            }
        }
    }
}

/// Cells handled per parallel task.
const CELLS_PER_TASK: usize = 64;

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn brute_force<const D: usize>(
        x: &[Vector<D>],
        h: &[f64],
        support: f64,
        pair_reach: PairReach,
    ) -> Vec<Vec<u32>> {
        (0..x.len())
            .map(|i| {
                let mut list: Vec<u32> = (0..x.len())
                    .filter(|&j| {
                        let reach = pair_reach.of(support, h[i].max(h[j]), h[i].min(h[j]));
                        j != i && (x[j] - x[i]).norm_squared() < reach * reach
                    })
                    .map(|j| j as u32)
                    .collect();
                list.sort_unstable();
                list
            })
            .collect()
    }

    /// The first `n_query` lists equal the O(N²) scan's (the rest are unqueried images), for
    /// both reach rules.
    fn agrees_with_brute_force<const D: usize>(coords: &[f64], hs: &[f64], n_query: usize) {
        let x: Vec<Vector<D>> = coords
            .chunks_exact(D)
            .map(Vector::<D>::from_column_slice)
            .collect();
        let h = &hs[..x.len()];
        let n_query = n_query.min(x.len());
        for reach in [PairReach::MeanH, PairReach::LargerH] {
            let lists = find_neighbours(&x, h, 2.0, reach, n_query);
            let expected = brute_force(&x, h, 2.0, reach);
            for (i, want) in expected.iter().enumerate().take(n_query) {
                assert_eq!(
                    lists.partners(i),
                    want.as_slice(),
                    "particle {i}, {reach:?}"
                );
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        /// The cell list finds exactly the pairs an O(N²) scan finds, with variable h, in 1D/2D/3D.
        #[test]
        fn cell_list_equals_brute_force(
            coords in proptest::collection::vec(-3.0f64..3.0, 600),
            hs in proptest::collection::vec(0.05f64..0.6, 600),
        ) {
            agrees_with_brute_force::<1>(&coords[..200], &hs, 200);
            agrees_with_brute_force::<2>(&coords[..400], &hs, 200);
            agrees_with_brute_force::<3>(&coords, &hs, 200);
        }

        /// Also when h spans three decades (a blast's empty centre beside its dense shell),
        /// when only some particles are queried (the rest being images), and in lengths a
        /// thousand times larger (h from 1 to 1000: the search's reach is κ·h in whatever unit,
        /// never a sum or ratio that only works out below h = 1).
        #[test]
        fn cell_list_equals_brute_force_over_decades_of_h(
            coords in proptest::collection::vec(-3.0f64..3.0, 600),
            log_h in proptest::collection::vec(-3.0f64..0.0, 600),
            n_query in 1usize..200,
            scale in prop_oneof![Just(1.0), Just(1000.0)],
        ) {
            let coords: Vec<f64> = coords.iter().map(|x| x * scale).collect();
            let hs: Vec<f64> = log_h.iter().map(|l| scale * 10f64.powf(*l)).collect();
            agrees_with_brute_force::<1>(&coords[..200], &hs, n_query);
            agrees_with_brute_force::<2>(&coords[..400], &hs, n_query);
            agrees_with_brute_force::<3>(&coords, &hs, n_query);
        }
    }

    #[test]
    fn a_far_outlier_does_not_blow_up_the_grid() {
        let mut x: Vec<Vector<3>> = (0..100)
            .map(|i| Vector::<3>::repeat(i as f64 * 0.01))
            .collect();
        x.push(Vector::<3>::repeat(1e9));
        let h = vec![0.02; x.len()];
        let lists = find_neighbours(&x, &h, 2.0, PairReach::MeanH, x.len());
        assert_eq!(lists.of(100).count(), 0);
        // spacing 0.01·√3 ≈ 0.0173 along the diagonal, reach 2h = 0.04: two on each side
        assert_eq!(lists.of(50).count(), 4);
    }

    /// A list per queried particle and every directed pair counted once: five particles on a
    /// line one apart, reach 2h = 1.2, link only to their next ones (4 links, 8 directed pairs).
    #[test]
    fn lists_count_their_particles_and_pairs() {
        let x: Vec<Vector<1>> = (0..5).map(|i| Vector::<1>::new(i as f64)).collect();
        let lists = find_neighbours(&x, &[0.6; 5], 2.0, PairReach::MeanH, 5);
        assert_eq!(lists.len(), 5);
        assert!(!lists.is_empty());
        assert_eq!(lists.pair_count(), 8);
        assert_eq!(lists.partners(2), &[1, 3]);
        let none = NeighbourList::default();
        assert!(none.is_empty());
        assert_eq!((none.len(), none.pair_count()), (0, 0));
    }

    /// A pair is within reach only for r < κ·h: at r exactly κ·h the kernel and its slope are
    /// zero, so the particle one spacing away is no partner when the reach is exactly one
    /// spacing (h = 0.5, κ = 2, all exact in binary), under either reach rule.
    #[test]
    fn a_particle_exactly_at_the_reach_is_no_partner() {
        let x: Vec<Vector<1>> = (0..5).map(|i| Vector::<1>::new(i as f64)).collect();
        for reach in [PairReach::MeanH, PairReach::LargerH] {
            let lists = find_neighbours(&x, &[0.5; 5], 2.0, reach, 5);
            assert_eq!(lists.pair_count(), 0, "{reach:?}");
        }
    }

    /// Cells as wide as asked, floor(extent / size) + 1 of them per axis, and every particle in
    /// the cell whose box holds it (its distance from the cell's centre at most half a side
    /// on each axis).
    #[test]
    fn each_particle_lies_in_its_cell() {
        let x: Vec<Vector<2>> = [
            (0.0, 0.0),
            (0.05, 0.65),
            (0.95, 0.35),
            (0.45, 0.75),
            (0.31, 0.29),
            (1.0, 0.9),
        ]
        .iter()
        .map(|&(a, b)| Vector::<2>::new(a + 2.0, b - 1.0))
        .collect();
        let grid = CellGrid::build(&x, 0.3);
        assert_eq!(grid.cell_size, 0.3);
        assert_eq!(grid.dims, [4, 4]);
        assert_eq!(grid.members.len(), x.len());
        for (i, xi) in x.iter().enumerate() {
            let c = grid.linear_index(&grid.cell_of(xi));
            assert!(grid.members_of(c).contains(&(i as u32)), "particle {i}");
            let offset = xi - grid.centre(c);
            assert!(offset.amax() <= 0.15 + 1e-12, "particle {i}: {offset:?}");
        }
    }

    /// A far outlier: the cells double in size from the one asked for until there are at most
    /// 4n + 64 of them, and no further (half that size would need more).
    #[test]
    fn an_outlier_doubles_the_cells_only_as_far_as_needed() {
        let mut x: Vec<Vector<3>> = (0..100)
            .map(|i| Vector::<3>::repeat(i as f64 * 0.01))
            .collect();
        x.push(Vector::<3>::repeat(1e3));
        let most = 4 * x.len() + 64;
        let grid = CellGrid::build(&x, 0.04);
        let doublings = (grid.cell_size / 0.04).log2();
        assert!(doublings > 0.0 && doublings.fract() == 0.0, "{doublings}");
        assert!(grid.dims.iter().product::<usize>() <= most);
        let half = (1e3 / (0.5 * grid.cell_size)).floor() + 1.0;
        assert!(half.powi(3) > most as f64);
    }

    /// Morton keys interleave the coordinates' bits, the first axis lowest.
    #[test]
    fn morton_keys_interleave_the_bits() {
        assert_eq!(morton_key(&[1, 0]), 1);
        assert_eq!(morton_key(&[0, 1]), 2);
        assert_eq!(morton_key(&[1, 1]), 3);
        assert_eq!(morton_key(&[2, 0]), 4);
        assert_eq!(morton_key(&[0, 2]), 8);
        assert_eq!(morton_key(&[1, 1, 1]), 7);
        assert_eq!(morton_key(&[2, 0, 0]), 8);
        assert_eq!(morton_key(&[0, 0, 2]), 32);
    }

    /// The locality order visits the cells along the Z curve, and a cell's particles in index
    /// order: here 2 × 2 cells, the particles given in the reverse of that order.
    #[test]
    fn the_locality_order_follows_the_z_curve() {
        let x: Vec<Vector<2>> = [(1.5, 1.5), (0.5, 1.5), (1.5, 0.5), (0.6, 0.5), (0.5, 0.5)]
            .iter()
            .map(|&(a, b)| Vector::<2>::new(a, b))
            .collect();
        let grid = CellGrid::build(&x, 1.0);
        assert_eq!(grid.locality_order(&x), vec![3, 4, 2, 1, 0]);
    }

    /// A particle whose h has grown without bound (a gas expanded to nothing) reaches every
    /// other particle: its search covers the whole grid instead of overflowing the cell range.
    #[test]
    fn an_unbounded_smoothing_length_reaches_everyone() {
        let x: Vec<Vector<2>> = (0..50)
            .map(|i| Vector::<2>::new(i as f64 * 0.01, 0.0))
            .collect();
        let mut h = vec![0.012; x.len()];
        h[10] = f64::MAX;
        let lists = find_neighbours(&x, &h, 2.0, PairReach::LargerH, x.len());
        assert_eq!(lists.of(10).count(), x.len() - 1);
    }
}
