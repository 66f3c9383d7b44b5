//! The seeded generator the tests draw their random points from: SplitMix64 (Steele, Lea &
//! Flood 2014, "Fast splittable pseudorandom number generators"), the same sequence in every
//! test binary. The draws shared by several tests are here; a test module with a draw of its own
//! adds it in a private `impl Rng` block under a name no other module uses.

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

    /// Uniform in [0, 1), 53 random bits.
    pub fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi], drawn in f64 and rounded to f32.
    pub fn f(&mut self, lo: f64, hi: f64) -> f32 {
        (lo + (hi - lo) * self.unit()) as f32
    }

    /// Uniform in [lo, hi), 24 random bits in f32 arithmetic.
    pub fn f32(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next() >> 40) as f32 / (1u64 << 24) as f32)
    }
}
