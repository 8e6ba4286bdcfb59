//! Individual time steps on a power-of-two hierarchy ("block steps"; Makino 1991, as in
//! GADGET and SWIFT), with Saitoh & Makino's (2009, ApJ 697, L99) limiter.
//!
//! Time inside a block is counted in ticks. Each real particle steps 2^k ticks, the longest
//! power of two within its own stable step, and starts a new step only at a tick that is a
//! multiple of that length, so that all steps nest and every particle is synchronised at the
//! block's end. The limiter keeps each particle's step within a factor 4 of its neighbours':
//! a new step is capped at four times the shortest step among its neighbours, and a particle
//! whose step has become more than four times a neighbour's is woken, its step ended at the
//! current tick. Without the wake-up a particle resting on a long step cannot feel a shock that
//! arrives during it (Saitoh & Makino's Sedov test loses the blast).

/// Levels below the block's shortest starting step that a particle may descend to during the
/// block (a step may shrink by 2^20 before the block ends).
const DEEPEST: u32 = 20;

/// The limiter's factor: a particle's step is at most this many times a neighbour's.
const NEIGHBOUR_STEP_RATIO: u64 = 4;

/// The hierarchy of one block.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct BlockSteps {
    /// The times at the block's start and end (s).
    start_time: f64,
    end_time: f64,
    /// One tick (s).
    tick: f64,
    /// The block's length in ticks, a power of two.
    length: u64,
    /// The current tick.
    now: u64,
    /// Each real particle's step in ticks (a power of two) and the tick its step started.
    step: Vec<u64>,
    started: Vec<u64>,
}

impl BlockSteps {
    /// A block starting at `time` for particles whose stable steps are `stable` (s): as long
    /// as the longest of them, at most `max_ratio` times the shortest (both rounded down to a
    /// power of two), and ending no later than `end`.
    pub fn new(time: f64, stable: &[f64], max_ratio: u64, end: f64) -> Self {
        let shortest = stable.iter().copied().fold(f64::INFINITY, f64::min);
        let longest = stable.iter().copied().fold(0.0, f64::max);
        let mut levels = 0;
        while levels < 62 - DEEPEST
            && 2 << levels <= max_ratio
            && shortest * (2u64 << levels) as f64 <= longest
        {
            levels += 1;
        }
        let mut duration = shortest * (1u64 << levels) as f64;
        let mut end_time = time + duration;
        if end - time < duration * (1.0 + 1e-9) {
            // the last block ends at `end`; steps are never longer than stable (see
            // `start_step`), so the levels only set the tick's resolution
            duration = end - time;
            end_time = end;
            levels = 0;
            while levels < 62 - DEEPEST && shortest * ((1u64 << levels) as f64) < duration {
                levels += 1;
            }
        }
        let length = 1u64 << (levels + DEEPEST);
        Self {
            start_time: time,
            end_time,
            tick: duration / length as f64,
            length,
            now: 0,
            step: vec![0; stable.len()],
            started: vec![0; stable.len()],
        }
    }

    /// The time at the current tick (s); at the block's end exactly the end it was given.
    pub fn time(&self) -> f64 {
        if self.finished() {
            self.end_time
        } else {
            self.start_time + self.now as f64 * self.tick
        }
    }

    /// The time at the block's end (s).
    pub fn end(&self) -> f64 {
        self.end_time
    }

    /// Whether every particle has reached the block's end.
    pub fn finished(&self) -> bool {
        self.now == self.length
    }

    /// Particle i's current step (s).
    pub fn step_of(&self, i: usize) -> f64 {
        self.step[i] as f64 * self.tick
    }

    /// How far particle i is into its current step (s).
    pub fn elapsed(&self, i: usize) -> f64 {
        (self.now - self.started[i]) as f64 * self.tick
    }

    /// Whether particle i's step ends at the current tick.
    pub fn ends_now(&self, i: usize) -> bool {
        self.started[i] + self.step[i] == self.now
    }

    /// The longest step a particle may start at the current tick: the largest power of two
    /// that divides it (the whole block at its start), so that the step ends on the
    /// hierarchy. It never reaches past the block's end: a tick k·2^j (k odd) before the
    /// power-of-two end 2^L has (k + 1)·2^j ≤ 2^L.
    fn aligned(&self) -> u64 {
        if self.now == 0 {
            self.length
        } else {
            1u64 << self.now.trailing_zeros()
        }
    }

    /// Starts particle i's next step at the current tick: the longest power of two of ticks
    /// within `stable` (s), within four times `neighbour_step` (the shortest step among its
    /// neighbours, in ticks) and aligned. None if even one tick is too long.
    pub fn start_step(&mut self, i: usize, stable: f64, neighbour_step: u64) -> Option<()> {
        let ticks = stable / self.tick;
        if !(ticks >= 1.0) {
            return None;
        }
        let own = 1u64 << (ticks.log2().floor() as u32).min(62);
        let limit = neighbour_step.saturating_mul(NEIGHBOUR_STEP_RATIO);
        let step = own.min(limit.max(1)).min(self.aligned());
        // a power of two below the cap: the cap itself may not be one
        self.step[i] = 1u64 << (63 - step.leading_zeros());
        self.started[i] = self.now;
        Some(())
    }

    /// Keeps the steps of the particles `kept` (ascending), in that order: the others have
    /// left the simulation.
    pub fn keep_only(&mut self, kept: &[usize]) {
        self.step = kept.iter().map(|&i| self.step[i]).collect();
        self.started = kept.iter().map(|&i| self.started[i]).collect();
    }

    /// Ends particle i's step at the current tick (it was woken by a neighbour's short step).
    /// Returns the step's old and new lengths (s).
    pub fn end_early(&mut self, i: usize) -> (f64, f64) {
        let old = self.step_of(i);
        self.step[i] = self.now - self.started[i];
        (old, self.step_of(i))
    }

    /// Particle i's step in ticks.
    pub fn ticks_of(&self, i: usize) -> u64 {
        self.step[i]
    }

    /// Whether particle i's step is more than the limiter allows over a neighbour's step of
    /// `neighbour_step` ticks (`u64::MAX` where it has no neighbours: no limit).
    pub fn exceeds_limit(&self, i: usize, neighbour_step: u64) -> bool {
        self.step[i] > neighbour_step.saturating_mul(NEIGHBOUR_STEP_RATIO)
    }

    /// The particles whose steps could make a neighbour's exceed the limiter: those more than
    /// [`NEIGHBOUR_STEP_RATIO`] times shorter than the longest step, in index order.
    pub fn possible_limiters(&self) -> impl Iterator<Item = usize> + '_ {
        let longest = self.step.iter().copied().max().unwrap_or(0);
        (0..self.step.len())
            .filter(move |&i| self.step[i].saturating_mul(NEIGHBOUR_STEP_RATIO) < longest)
    }

    /// Whether particle i's step exceeds the limiter's (see [`Self::exceeds_limit`]) and it
    /// has begun (it can end at the current tick).
    pub fn must_wake(&self, i: usize, neighbour_step: u64) -> bool {
        self.exceeds_limit(i, neighbour_step) && self.now > self.started[i]
    }

    /// Advances to the next tick at which some particle's step ends; returns the time passed
    /// (s).
    pub fn advance(&mut self) -> f64 {
        let next = self
            .started
            .iter()
            .zip(&self.step)
            .map(|(s, d)| s + d)
            .min()
            .unwrap_or(self.length);
        let passed = (next - self.now) as f64 * self.tick;
        self.now = next;
        passed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Steps nest: a particle that starts at a tick takes the longest power of two that
    /// divides it, so a particle on a long step and one on a short step meet again at the
    /// long step's end.
    #[test]
    fn steps_are_powers_of_two_aligned_to_the_hierarchy() {
        let mut block = BlockSteps::new(0.0, &[1.0, 8.0], 1024, 100.0);
        assert_eq!(block.length, 8 << DEEPEST);
        block.start_step(0, 1.0, u64::MAX).unwrap();
        block.start_step(1, 8.0, u64::MAX).unwrap();
        assert_eq!(block.step_of(1), 8.0);
        assert_eq!(block.step_of(0), 1.0);
        let passed = block.advance();
        assert_eq!(passed, 1.0);
        assert!(block.ends_now(0) && !block.ends_now(1));
        // at tick 1 (of 8) a particle may start at most a step of 1
        block.start_step(0, 8.0, u64::MAX).unwrap();
        assert_eq!(block.step_of(0), 1.0);
        block.advance();
        block.start_step(0, 8.0, u64::MAX).unwrap();
        assert_eq!(block.step_of(0), 2.0);
        block.advance();
        block.start_step(0, 8.0, u64::MAX).unwrap();
        assert_eq!(block.step_of(0), 4.0);
        block.advance();
        assert!(block.finished() && block.ends_now(0) && block.ends_now(1));
        assert_eq!(block.time(), 8.0);
    }

    /// The limiter caps a step at four times the neighbours' shortest; a long step is woken by
    /// a neighbour more than four times shorter, and ends at the current tick.
    #[test]
    fn the_limiter_keeps_neighbours_within_a_factor_four() {
        let mut block = BlockSteps::new(0.0, &[1.0, 64.0], 1024, 1000.0);
        let one = block.length >> 6;
        block.start_step(0, 1.0, u64::MAX).unwrap();
        block.start_step(1, 64.0, one).unwrap();
        assert_eq!(block.step_of(1), 4.0);
        block.start_step(1, 64.0, u64::MAX).unwrap();
        assert_eq!(block.step_of(1), 64.0);
        // a step that has not begun cannot end early
        assert!(!block.must_wake(1, one));
        block.advance();
        assert!(block.must_wake(1, one));
        assert!(!block.must_wake(1, 16 * one));
        // a particle without neighbours has no limit
        assert!(!block.must_wake(1, u64::MAX));
        assert_eq!(block.end_early(1), (64.0, 1.0));
        assert!(block.ends_now(1));
    }

    /// A step woken part-way ends at the current tick, as long as it has run since it started
    /// (here a step of 2 started at tick 2, woken at tick 3).
    /// Steps of 1, 4, 8, 16 and 64: only those more than four times shorter than the longest
    /// (1, 4 and 8; 16 · 4 = 64 is not shorter) can make a neighbour's step exceed the
    /// limiter; with every step equal, none.
    #[test]
    fn possible_limiters_are_the_steps_four_times_shorter_than_the_longest() {
        let steps = [1.0, 4.0, 8.0, 16.0, 64.0];
        let mut block = BlockSteps::new(0.0, &steps, 1024, 1000.0);
        for (i, &dt) in steps.iter().enumerate() {
            block.start_step(i, dt, u64::MAX).unwrap();
        }
        assert_eq!(block.possible_limiters().collect::<Vec<_>>(), [0, 1, 2]);
        let mut even = BlockSteps::new(0.0, &[2.0; 3], 1024, 1000.0);
        for i in 0..3 {
            even.start_step(i, 2.0, u64::MAX).unwrap();
        }
        assert_eq!(even.possible_limiters().count(), 0);
    }

    #[test]
    fn a_woken_step_is_as_long_as_it_has_run() {
        let mut block = BlockSteps::new(0.0, &[1.0, 64.0], 1024, 1000.0);
        let one = block.length >> 6;
        block.start_step(0, 1.0, u64::MAX).unwrap();
        block.start_step(1, 2.0, u64::MAX).unwrap();
        block.advance();
        block.start_step(0, 1.0, u64::MAX).unwrap();
        block.end_early(1);
        block.start_step(1, 2.0, u64::MAX).unwrap();
        assert_eq!(block.step_of(1), 1.0, "at tick 1 steps are at most 1 long");
        block.advance();
        block.start_step(0, 1.0, u64::MAX).unwrap();
        block.start_step(1, 2.0, u64::MAX).unwrap();
        assert_eq!(block.step_of(1), 2.0);
        block.advance();
        assert_eq!(block.time(), 3.0);
        assert!(block.must_wake(1, one / 8));
        assert_eq!(block.end_early(1), (2.0, 1.0));
        assert!(block.ends_now(1));
    }

    /// The last block fits its end: steps shrink, never grow, and the block ends there.
    #[test]
    fn the_last_block_ends_at_the_end() {
        for end in [0.3, 1.0, 2.5, 7.9] {
            let mut block = BlockSteps::new(0.0, &[1.0, 8.0], 1024, end);
            for i in 0..2 {
                block.start_step(i, [1.0, 8.0][i], u64::MAX).unwrap();
                assert!(block.step_of(i) <= [1.0, 8.0][i]);
            }
            while !block.finished() {
                block.advance();
                for i in 0..2 {
                    if block.ends_now(i) && !block.finished() {
                        block.start_step(i, [1.0, 8.0][i], u64::MAX).unwrap();
                    }
                }
            }
            assert_eq!(block.time(), end);
        }
    }

    /// When particle 1 leaves, particle 2 becomes particle 1 and keeps its own step and its
    /// start: a step of 2 started at time 2, beside particle 1's step of 8 started at 0.
    #[test]
    fn the_steps_of_the_particles_that_stay_follow_them() {
        let mut block = BlockSteps::new(0.0, &[1.0, 8.0, 2.0], 1024, 1000.0);
        for (i, dt) in [1.0, 8.0, 2.0].into_iter().enumerate() {
            block.start_step(i, dt, u64::MAX).unwrap();
        }
        block.advance();
        block.start_step(0, 1.0, u64::MAX).unwrap();
        block.advance();
        for i in [0, 2] {
            block.start_step(i, [1.0, 8.0, 2.0][i], u64::MAX).unwrap();
        }
        block.advance();
        assert_eq!((block.step_of(1), block.elapsed(1)), (8.0, 3.0));
        assert_eq!((block.step_of(2), block.elapsed(2)), (2.0, 1.0));
        block.keep_only(&[0, 2]);
        assert_eq!((block.step_of(1), block.elapsed(1)), (2.0, 1.0));
        assert_eq!((block.step_of(0), block.elapsed(0)), (1.0, 1.0));
        assert!(block.ends_now(0) && !block.ends_now(1));
    }
}
