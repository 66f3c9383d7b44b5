//! The seeded generator the tests draw their random points from: SplitMix64 (Steele, Lea &
//! Flood 2014, "Fast splittable pseudorandom number generators"), the same sequence in every
//! test binary. Each test file adds the draws it needs (uniform, log-uniform, hard ranges) in
//! its own `impl Rng` block on top of [`Rng::next`].

/// A SplitMix64 state; `Rng(seed)` starts a sequence.
#[derive(Clone, Debug)]
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}
