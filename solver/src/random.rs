//! The one random generator of the project: seeded, so that a sample or a jittered lattice
//! depends on its seed only.

/// SplitMix64 (Steele, Lea & Flood 2014): a small seeded generator, so that a sample depends
/// on its seed only (not on a crate's algorithm choice or the thread count).
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference outputs for seed 1234567 (Rosetta Code, "Pseudo-random numbers/Splitmix64",
    /// from Vigna's splitmix64.c).
    #[test]
    fn gives_the_reference_sequence() {
        let mut rng = SplitMix64::new(1234567);
        let expected: [u64; 5] = [
            6457827717110365317,
            3203168211198807973,
            9817491932198370423,
            4593380528125082431,
            16408922859458223821,
        ];
        for value in expected {
            assert_eq!(rng.next_u64(), value);
        }
    }

    /// Uniform draws lie in [0, 1) and fill it evenly: over 10⁵ draws each fifth holds 20 % of
    /// them within 1.5 % (about five standard deviations of a binomial count, √(n p (1 − p))
    /// = 126 of 20 000), and the first draw is the first output's top 53 bits over 2⁵³.
    #[test]
    fn uniform_draws_fill_the_unit_interval_evenly() {
        let mut rng = SplitMix64::new(987654321);
        let mut counts = [0usize; 5];
        for _ in 0..100_000 {
            let u = rng.uniform();
            assert!((0.0..1.0).contains(&u), "{u}");
            counts[(u * 5.0) as usize] += 1;
        }
        for count in counts {
            assert!(count.abs_diff(20_000) < 300, "{counts:?}");
        }
        let first = SplitMix64::new(1234567).uniform();
        assert_eq!(first, 0.3500795420214081);
    }
}
