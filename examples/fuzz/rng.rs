//! A small, fast, seedable generator: every case is a pure function of `(seed, case)`.

/// xorshift64*, seeded per case.
pub struct Rng(u64);

impl Rng {
    /// The generator of case `case` of run `seed`.
    pub fn new(seed: u64, case: u64) -> Rng {
        let mut r = Rng((seed ^ 0x9e37_79b9_7f4a_7c15)
            .wrapping_mul(case.wrapping_add(0x2545_f491_4f6c_dd1d))
            | 1);
        for _ in 0..4 {
            r.bits();
        }
        r
    }

    /// The next 64 random bits.
    pub fn bits(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// A number in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.bits() % n.max(1) as u64) as usize
    }

    /// True with probability `1 / n`.
    pub fn one_in(&mut self, n: usize) -> bool {
        self.below(n) == 0
    }

    /// One item of a non-empty slice.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }

    /// A uniform number in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.bits() >> 11) as f64 / (1u64 << 53) as f64
    }
}
