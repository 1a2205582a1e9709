//! The state hash: a cheap, bit-exact fingerprint of a world's numbers.
//!
//! On the ground floor so that every store can feed its own arrays
//! ([`Particles`](super::Particles), the soft solver's warm start) without reaching up
//! to the snapshot codec.

use glam::Vec3;

/// A 64-bit hash of a state's numbers, fed word by word: each f32 by its bits, so two
/// states hash alike only if they are the same bits (up to collisions). Cheap enough
/// to run after every step: one multiply per word (the mix of `FxHash`, finished with
/// `splitmix64`'s so that nearby states give unlike hashes).
#[derive(Clone, Copy, Debug)]
pub struct StateHasher(u64);

impl Default for StateHasher {
    fn default() -> Self {
        Self(0x243F_6A88_85A3_08D3)
    }
}

impl StateHasher {
    /// Feeds a 64-bit word.
    #[inline]
    pub fn u64(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x517C_C1B7_2722_0A95);
    }

    /// Feeds an f32 by its bits.
    #[inline]
    pub fn f32(&mut self, x: f32) {
        self.u64(u64::from(x.to_bits()));
    }

    /// Feeds an f64 by its bits.
    #[inline]
    pub fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }

    /// Feeds a vector's three components.
    #[inline]
    pub fn vec3(&mut self, v: Vec3) {
        self.u64(u64::from(v.x.to_bits()) | (u64::from(v.y.to_bits()) << 32));
        self.f32(v.z);
    }

    /// The hash.
    #[must_use]
    pub fn finish(self) -> u64 {
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}
