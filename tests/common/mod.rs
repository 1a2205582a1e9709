//! Helpers shared by the test binaries that include this module (`mod common;`).

/// A small deterministic generator (SplitMix64): a failing case of a fuzz or soak run
/// is found again by its seed and number.
pub struct Random(pub u64);

#[allow(dead_code, reason = "each test binary uses the draws it needs")]
impl Random {
    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    /// Uniform in [0, 1].
    pub fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / ((1u64 << 24) - 1) as f32
    }
}
