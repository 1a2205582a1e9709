//! Four lanes of `f32` at once: the contact solver works on four contacts of one colour
//! together (Box2D v3's idea), with SSE where the target has it (every x86-64) and
//! plain arrays elsewhere (wasm32). Where an x86-64 processor has AVX, the solve joins
//! two batches into eight lanes ([`avx`]), and where it has AVX-512 four into sixteen
//! ([`avx512`]); it is written once, for any [`Lane`] type.
//!
//! All give the same bits as scalar `f32` code doing the same operations lane by lane:
//! every operation here is one IEEE-754 operation per lane (`+ - * /`, `sqrt`, compare,
//! select), with no fused multiply-add and no reordering, so a lane computes exactly
//! what the scalar formula it mirrors computes. [`F4::max`] is defined
//! as SSE's `maxps` is (`a > b ? a : b`), on both paths, so that the two agree even on
//! ±0 and NaN.
//!
//! The `unsafe` here is of three kinds, each stated once where it is used:
//! - intrinsics, which need their instruction set: SSE and SSE2 are the x86-64
//!   baseline (asserted at compile time; `sse!`), AVX and AVX-512 run only in functions
//!   reached after `is_x86_feature_detected!` said yes (`avx!`, `avx512!`: debug builds
//!   check the detection at every operation);
//! - `gather` and `scatter`, which read and write vectors through a pointer: the caller
//!   passes the array's length, and debug builds check every index against it, and
//!   that the lanes a scatter writes name distinct vectors;
//! - the `ZERO` constants, made by `transmute` (intrinsics are not `const`), whose
//!   sizes the compiler checks.
//!
//! The tests at the end run every one of these paths against plain scalar code (the
//! AVX and AVX-512 ones where the processor has them); `cargo test --lib wide` runs
//! them with the debug checks on.

/// Four `f32` lanes.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct F4(imp::Raw);

/// Four lanes of true or false, the result of a comparison of [`F4`]s.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct M4(imp::Raw);

impl Default for F4 {
    fn default() -> Self {
        Self::ZERO
    }
}

#[cfg(target_arch = "x86_64")]
mod imp {
    //! SSE, which every x86-64 processor has.
    use std::arch::x86_64::*;

    pub type Raw = __m128;

    // Every x86-64 processor has SSE and SSE2, and the compiler assumes them for this
    // target: `sse!` rests on it, checked here when the crate is compiled.
    const _: () = assert!(cfg!(target_feature = "sse2"), "x86-64 is built with SSE2");

    /// Runs SSE or SSE2 intrinsics that take and give registers only, never a pointer
    /// (arithmetic, comparisons, shuffles, casts): the one thing that makes them
    /// `unsafe` is that the processor must have the instructions.
    macro_rules! sse {
        ($e:expr) => {{
            // SAFETY: the intrinsics in `$e` need SSE or SSE2, which the x86-64
            // baseline has (asserted above at compile time), and touch no memory.
            unsafe { $e }
        }};
    }

    #[inline(always)]
    pub fn splat(x: f32) -> Raw {
        sse!(_mm_set1_ps(x))
    }
    #[inline(always)]
    pub fn from_array(a: [f32; 4]) -> Raw {
        // Four f32, lane 0 first, are what `__m128` holds: a plain cast, no pointer.
        bytemuck::cast(a)
    }
    #[inline(always)]
    pub fn to_array(x: Raw) -> [f32; 4] {
        bytemuck::cast(x)
    }
    #[inline(always)]
    pub fn add(a: Raw, b: Raw) -> Raw {
        sse!(_mm_add_ps(a, b))
    }
    #[inline(always)]
    pub fn sub(a: Raw, b: Raw) -> Raw {
        sse!(_mm_sub_ps(a, b))
    }
    #[inline(always)]
    pub fn mul(a: Raw, b: Raw) -> Raw {
        sse!(_mm_mul_ps(a, b))
    }
    #[inline(always)]
    pub fn div(a: Raw, b: Raw) -> Raw {
        sse!(_mm_div_ps(a, b))
    }
    #[inline(always)]
    pub fn neg(a: Raw) -> Raw {
        sse!(_mm_xor_ps(a, _mm_set1_ps(-0.0)))
    }
    #[inline(always)]
    pub fn sqrt(a: Raw) -> Raw {
        sse!(_mm_sqrt_ps(a))
    }
    #[inline(always)]
    pub fn max(a: Raw, b: Raw) -> Raw {
        sse!(_mm_max_ps(a, b))
    }
    #[inline(always)]
    pub fn gt(a: Raw, b: Raw) -> Raw {
        sse!(_mm_cmpgt_ps(a, b))
    }
    #[inline(always)]
    pub fn eq(a: Raw, b: Raw) -> Raw {
        sse!(_mm_cmpeq_ps(a, b))
    }
    #[inline(always)]
    pub fn and(a: Raw, b: Raw) -> Raw {
        sse!(_mm_and_ps(a, b))
    }
    #[inline(always)]
    pub fn or(a: Raw, b: Raw) -> Raw {
        sse!(_mm_or_ps(a, b))
    }
    #[inline(always)]
    pub fn select(mask: Raw, a: Raw, b: Raw) -> Raw {
        sse!(_mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b)))
    }
    #[inline(always)]
    pub fn bits(mask: Raw) -> u32 {
        sse!(_mm_movemask_ps(mask)) as u32
    }
    #[inline(always)]
    pub fn mask_from(bits: [bool; 4]) -> Raw {
        let lane = |on: bool| if on { f32::from_bits(u32::MAX) } else { 0.0 };
        sse!(_mm_setr_ps(lane(bits[0]), lane(bits[1]), lane(bits[2]), lane(bits[3])))
    }

    /// The x, y and z of the four vectors at `points[i]`: each read as its 8 bytes of x
    /// and y and its 4 of z (never beyond the vector), then transposed.
    ///
    /// # Safety
    /// Every pointer must point at a readable `[f32; 3]`.
    #[inline(always)]
    pub unsafe fn gather(points: [*const f32; 4]) -> [Raw; 3] {
        debug_assert!(points.iter().all(|p| p.is_aligned()), "each vector's f32 aligned");
        // SAFETY: each pointer is a readable `[f32; 3]` (the caller's promise): the
        // unaligned 8-byte read covers its x and y, `_mm_load_ss` (an aligned f32
        // read, checked above in debug builds) its z at `add(2)`; the rest is SSE2 on
        // registers (the x86-64 baseline).
        unsafe {
            let pair = |p: *const f32| _mm_cvtsi64_si128(std::ptr::read_unaligned(p as *const i64));
            let xy01 = _mm_castsi128_ps(_mm_unpacklo_epi64(pair(points[0]), pair(points[1])));
            let xy23 = _mm_castsi128_ps(_mm_unpacklo_epi64(pair(points[2]), pair(points[3])));
            let x = _mm_shuffle_ps::<0b10_00_10_00>(xy01, xy23);
            let y = _mm_shuffle_ps::<0b11_01_11_01>(xy01, xy23);
            let z = |i: usize| _mm_load_ss(points[i].add(2));
            let z = _mm_movelh_ps(_mm_unpacklo_ps(z(0), z(1)), _mm_unpacklo_ps(z(2), z(3)));
            [x, y, z]
        }
    }

    /// Writes lane `i` of x, y and z to `points[i]` for each bit `i` set in `lanes`.
    ///
    /// # Safety
    /// Every pointer whose lane is set must point at a writable `[f32; 3]` that nothing
    /// else reads or writes meanwhile.
    #[inline(always)]
    pub unsafe fn scatter(points: [*mut f32; 4], lanes: u32, [x, y, z]: [Raw; 3]) {
        let xy01 = sse!(_mm_castps_si128(_mm_unpacklo_ps(x, y)));
        let xy23 = sse!(_mm_castps_si128(_mm_unpackhi_ps(x, y)));
        let pairs = sse!([xy01, _mm_unpackhi_epi64(xy01, xy01), xy23, _mm_unpackhi_epi64(xy23, xy23)]);
        let zs = sse!([
            _mm_cvtss_f32(z),
            _mm_cvtss_f32(_mm_shuffle_ps::<0b01_01_01_01>(z, z)),
            _mm_cvtss_f32(_mm_movehl_ps(z, z)),
            _mm_cvtss_f32(_mm_shuffle_ps::<0b11_11_11_11>(z, z)),
        ]);
        for i in 0..4 {
            if lanes & (1 << i) != 0 {
                debug_assert!(points[i].is_aligned(), "each vector's f32 aligned");
                // SAFETY: lane `i` is set, so `points[i]` is a writable `[f32; 3]` no one
                // else touches meanwhile (the caller's promise): 8 bytes of x and y
                // written unaligned, then its z (aligned, checked above in debug
                // builds); `_mm_cvtsi128_si64` is SSE2 on a register.
                unsafe {
                    std::ptr::write_unaligned(points[i] as *mut i64, _mm_cvtsi128_si64(pairs[i]));
                    *points[i].add(2) = zs[i];
                }
            }
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod imp {
    //! Plain arrays, lane by lane; masks are lanes of all ones or all zeros, as in SSE.
    pub type Raw = [f32; 4];

    #[inline(always)]
    fn map(a: Raw, f: impl Fn(f32) -> f32) -> Raw {
        [f(a[0]), f(a[1]), f(a[2]), f(a[3])]
    }
    #[inline(always)]
    fn zip(a: Raw, b: Raw, f: impl Fn(f32, f32) -> f32) -> Raw {
        [f(a[0], b[0]), f(a[1], b[1]), f(a[2], b[2]), f(a[3], b[3])]
    }
    #[inline(always)]
    fn lane(on: bool) -> f32 {
        if on { f32::from_bits(u32::MAX) } else { 0.0 }
    }
    #[inline(always)]
    fn bitwise(a: Raw, b: Raw, f: impl Fn(u32, u32) -> u32) -> Raw {
        zip(a, b, |x, y| f32::from_bits(f(x.to_bits(), y.to_bits())))
    }

    #[inline(always)]
    pub fn splat(x: f32) -> Raw {
        [x; 4]
    }
    #[inline(always)]
    pub fn from_array(a: [f32; 4]) -> Raw {
        a
    }
    #[inline(always)]
    pub fn to_array(x: Raw) -> [f32; 4] {
        x
    }
    #[inline(always)]
    pub fn add(a: Raw, b: Raw) -> Raw {
        zip(a, b, |x, y| x + y)
    }
    #[inline(always)]
    pub fn sub(a: Raw, b: Raw) -> Raw {
        zip(a, b, |x, y| x - y)
    }
    #[inline(always)]
    pub fn mul(a: Raw, b: Raw) -> Raw {
        zip(a, b, |x, y| x * y)
    }
    #[inline(always)]
    pub fn div(a: Raw, b: Raw) -> Raw {
        zip(a, b, |x, y| x / y)
    }
    #[inline(always)]
    pub fn neg(a: Raw) -> Raw {
        map(a, |x| -x)
    }
    #[inline(always)]
    pub fn sqrt(a: Raw) -> Raw {
        map(a, f32::sqrt)
    }
    #[inline(always)]
    pub fn max(a: Raw, b: Raw) -> Raw {
        zip(a, b, |x, y| if x > y { x } else { y })
    }
    #[inline(always)]
    pub fn gt(a: Raw, b: Raw) -> Raw {
        zip(a, b, |x, y| lane(x > y))
    }
    #[inline(always)]
    pub fn eq(a: Raw, b: Raw) -> Raw {
        zip(a, b, |x, y| lane(x == y))
    }
    #[inline(always)]
    pub fn and(a: Raw, b: Raw) -> Raw {
        bitwise(a, b, |x, y| x & y)
    }
    #[inline(always)]
    pub fn or(a: Raw, b: Raw) -> Raw {
        bitwise(a, b, |x, y| x | y)
    }
    #[inline(always)]
    pub fn select(mask: Raw, a: Raw, b: Raw) -> Raw {
        [0, 1, 2, 3].map(|i| if mask[i].to_bits() != 0 { a[i] } else { b[i] })
    }
    #[inline(always)]
    pub fn bits(mask: Raw) -> u32 {
        (0..4).map(|i| u32::from(mask[i].to_bits() >> 31) << i).sum()
    }
    #[inline(always)]
    pub fn mask_from(bits: [bool; 4]) -> Raw {
        bits.map(lane)
    }

    /// The x, y and z of the four vectors at `points[i]`.
    ///
    /// # Safety
    /// Every pointer must point at a readable `[f32; 3]`.
    #[inline(always)]
    pub unsafe fn gather(points: [*const f32; 4]) -> [Raw; 3] {
        debug_assert!(points.iter().all(|p| p.is_aligned()), "each vector's f32 aligned");
        // SAFETY: each pointer is a readable `[f32; 3]` (the caller's promise), so its
        // elements 0, 1 and 2 may be read.
        unsafe { [0, 1, 2].map(|k| points.map(|p| *p.add(k))) }
    }

    /// Writes lane `i` of x, y and z to `points[i]` for each bit `i` set in `lanes`.
    ///
    /// # Safety
    /// Every pointer whose lane is set must point at a writable `[f32; 3]` that nothing
    /// else reads or writes meanwhile.
    #[inline(always)]
    pub unsafe fn scatter(points: [*mut f32; 4], lanes: u32, [x, y, z]: [Raw; 3]) {
        for i in 0..4 {
            if lanes & (1 << i) != 0 {
                debug_assert!(points[i].is_aligned(), "each vector's f32 aligned");
                // SAFETY: lane `i` is set, so `points[i]` is a writable `[f32; 3]` that
                // no one else touches meanwhile (the caller's promise).
                unsafe {
                    *points[i] = x[i];
                    *points[i].add(1) = y[i];
                    *points[i].add(2) = z[i];
                }
            }
        }
    }
}

impl F4 {
    /// All lanes +0.
    pub const ZERO: Self = Self::from_lanes_const(0.0);

    const fn from_lanes_const(x: f32) -> Self {
        // A const splat (the intrinsics are not `const`).
        // SAFETY: `[f32; 4]` and `__m128` are both 16 bytes of four f32 lanes, lane 0
        // first (`transmute` checks the sizes when compiling), and every bit pattern is
        // a valid `__m128` (plain data, as bytemuck's `Pod` says).
        Self(unsafe { std::mem::transmute::<[f32; 4], imp::Raw>([x; 4]) })
    }

    /// `x` in every lane.
    #[inline(always)]
    #[must_use]
    pub fn splat(x: f32) -> Self {
        Self(imp::splat(x))
    }

    /// The four lanes, lane 0 first.
    #[inline(always)]
    #[must_use]
    pub fn new(lanes: [f32; 4]) -> Self {
        Self(imp::from_array(lanes))
    }

    /// The four lanes as an array, lane 0 first.
    #[inline(always)]
    #[must_use]
    pub fn to_array(self) -> [f32; 4] {
        imp::to_array(self.0)
    }

    /// Square root of each lane (IEEE, correctly rounded, as `f32::sqrt`).
    #[inline(always)]
    #[must_use]
    pub fn sqrt(self) -> Self {
        Self(imp::sqrt(self.0))
    }

    /// Per lane `if self > other { self } else { other }` (SSE's `maxps`).
    #[inline(always)]
    #[must_use]
    pub fn max(self, other: Self) -> Self {
        Self(imp::max(self.0, other.0))
    }

    /// Per lane `self > other`.
    #[inline(always)]
    #[must_use]
    pub fn gt(self, other: Self) -> M4 {
        M4(imp::gt(self.0, other.0))
    }

    /// Per lane `self == other` (false for NaN).
    #[inline(always)]
    #[must_use]
    pub fn eq(self, other: Self) -> M4 {
        M4(imp::eq(self.0, other.0))
    }
}

impl M4 {
    /// A mask from four booleans, lane 0 first.
    #[inline(always)]
    #[must_use]
    pub fn new(lanes: [bool; 4]) -> Self {
        Self(imp::mask_from(lanes))
    }

    /// Per lane: `a` where the mask is true, else `b` (bit for bit).
    #[inline(always)]
    #[must_use]
    pub fn select(self, a: F4, b: F4) -> F4 {
        F4(imp::select(self.0, a.0, b.0))
    }

    /// Lane `i` true sets bit `i`.
    #[inline(always)]
    #[must_use]
    pub fn bits(self) -> u32 {
        imp::bits(self.0)
    }

    /// True where both are.
    #[inline(always)]
    #[must_use]
    pub fn and(self, other: Self) -> Self {
        Self(imp::and(self.0, other.0))
    }

    /// True where either is.
    #[inline(always)]
    #[must_use]
    pub fn or(self, other: Self) -> Self {
        Self(imp::or(self.0, other.0))
    }
}

macro_rules! lane_op {
    ($trait:ident, $method:ident, $f:path) => {
        impl std::ops::$trait for F4 {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                Self($f(self.0, other.0))
            }
        }
    };
}
lane_op!(Add, add, imp::add);
lane_op!(Sub, sub, imp::sub);
lane_op!(Mul, mul, imp::mul);
lane_op!(Div, div, imp::div);

impl std::ops::Neg for F4 {
    type Output = Self;
    /// Flips each lane's sign bit, as `-x` on `f32` does (not `0 - x`).
    #[inline(always)]
    fn neg(self) -> Self {
        Self(imp::neg(self.0))
    }
}

/// Lanes of `f32` that the contact solve is written for: [`F4`] everywhere, and
/// [`F8`](avx::F8) inside functions compiled for AVX. Every operation is one IEEE-754
/// operation per lane, so a lane computes the same bits whatever the width.
pub trait Lane:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
    + std::ops::Neg<Output = Self>
{
    /// The result of comparing lanes.
    type Mask: Mask<Self>;
    /// One particle index per lane.
    type Index: Copy + AsRef<[u32]>;
    /// All lanes +0.
    const ZERO: Self;
    /// `x` in every lane.
    fn splat(x: f32) -> Self;
    /// Square root of each lane, correctly rounded.
    fn sqrt(self) -> Self;
    /// Per lane `if self > other { self } else { other }`.
    fn max(self, other: Self) -> Self;
    /// Per lane `self > other`.
    fn gt(self, other: Self) -> Self::Mask;
    /// Per lane `self == other`.
    fn eq(self, other: Self) -> Self::Mask;
    /// Lane `i` holds `base[indices[i]]`, from an array of `len` vectors.
    ///
    /// # Safety
    /// As [`V4::gather`], for every index.
    unsafe fn gather(base: *const glam::Vec3, len: usize, indices: Self::Index) -> V<Self>;
    /// Writes lane `i` to `base[indices[i]]`, in an array of `len` vectors, for each bit
    /// `i` set in `lanes`.
    ///
    /// # Safety
    /// As [`V4::scatter`], for every lane set.
    unsafe fn scatter(value: V<Self>, base: *mut glam::Vec3, len: usize, indices: Self::Index, lanes: u32);
}

/// Lanes of true or false for a [`Lane`] type `L`.
pub trait Mask<L>: Copy {
    /// Lane `i` true where bit `i` of `bits` is set.
    fn from_bits(bits: u32) -> Self;
    /// Per lane: `a` where true, else `b` (bit for bit).
    fn select(self, a: L, b: L) -> L;
    /// Lane `i` true sets bit `i`.
    fn bits(self) -> u32;
    /// True where both are.
    fn and(self, other: Self) -> Self;
    /// True where either is.
    fn or(self, other: Self) -> Self;
}

/// Lanes made of two halves of a narrower [`Lane`] type: eight of two fours
/// ([`F8`](avx::F8), AVX) and sixteen of two eights ([`F16`](avx512::F16), AVX-512). The
/// solve joins batches of one colour with it and splits their impulses back.
#[cfg(target_arch = "x86_64")]
pub(crate) trait Joined: Lane {
    /// The half.
    type Half: Lane;
    /// The lanes of `low`, then those of `high`.
    fn join(low: Self::Half, high: Self::Half) -> Self;
    /// The first half of the lanes, and the second.
    fn halves(self) -> (Self::Half, Self::Half);
    /// The indices of `low`'s lanes, then those of `high`'s.
    fn join_indices(low: <Self::Half as Lane>::Index, high: <Self::Half as Lane>::Index) -> Self::Index;
    /// The first half of the indices, and the second.
    fn split_indices(indices: Self::Index) -> (<Self::Half as Lane>::Index, <Self::Half as Lane>::Index);
}

/// Two halves' arrays of indices as one, and back.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn concat<const HALF: usize, const ALL: usize>(low: [u32; HALF], high: [u32; HALF]) -> [u32; ALL] {
    std::array::from_fn(|i| if i < HALF { low[i] } else { high[i - HALF] })
}

#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn halve<const HALF: usize, const ALL: usize>(all: [u32; ALL]) -> ([u32; HALF], [u32; HALF]) {
    (std::array::from_fn(|i| all[i]), std::array::from_fn(|i| all[HALF + i]))
}

#[cfg(target_arch = "x86_64")]
impl<L: Joined> V<L> {
    /// The lanes of `low`, then those of `high`.
    #[inline(always)]
    #[must_use]
    pub fn join(low: V<L::Half>, high: V<L::Half>) -> Self {
        Self { x: L::join(low.x, high.x), y: L::join(low.y, high.y), z: L::join(low.z, high.z) }
    }

    /// The first half of the lanes, and the second.
    #[inline(always)]
    #[must_use]
    pub fn halves(self) -> (V<L::Half>, V<L::Half>) {
        let ((x0, x1), (y0, y1), (z0, z1)) = (self.x.halves(), self.y.halves(), self.z.halves());
        (V { x: x0, y: y0, z: z0 }, V { x: x1, y: y1, z: z1 })
    }
}

impl Lane for F4 {
    type Mask = M4;
    type Index = [u32; 4];
    const ZERO: Self = F4::ZERO;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        F4::splat(x)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        F4::sqrt(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        F4::max(self, other)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> M4 {
        F4::gt(self, other)
    }
    #[inline(always)]
    fn eq(self, other: Self) -> M4 {
        F4::eq(self, other)
    }
    #[inline(always)]
    unsafe fn gather(base: *const glam::Vec3, len: usize, indices: [u32; 4]) -> V4 {
        // SAFETY: the caller's promise is `V4::gather`'s.
        unsafe { V4::gather(base, len, indices) }
    }
    #[inline(always)]
    unsafe fn scatter(value: V4, base: *mut glam::Vec3, len: usize, indices: [u32; 4], lanes: u32) {
        // SAFETY: the caller's promise is `V4::scatter`'s.
        unsafe { value.scatter(base, len, indices, lanes) }
    }
}

impl Mask<F4> for M4 {
    #[inline(always)]
    fn from_bits(bits: u32) -> Self {
        M4::new([0, 1, 2, 3].map(|i| bits & (1 << i) != 0))
    }
    #[inline(always)]
    fn select(self, a: F4, b: F4) -> F4 {
        M4::select(self, a, b)
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        M4::bits(self)
    }
    #[inline(always)]
    fn and(self, other: Self) -> Self {
        M4::and(self, other)
    }
    #[inline(always)]
    fn or(self, other: Self) -> Self {
        M4::or(self, other)
    }
}

/// 3-vectors, one per lane: the lanes' x, y and z apart. Its operations are glam's
/// `Vec3` formulas written out, in glam's order, so each lane equals what glam computes
/// for that lane's vector.
#[derive(Clone, Copy, Debug, Default)]
pub struct V<L> {
    pub x: L,
    pub y: L,
    pub z: L,
}

/// Four 3-vectors.
pub type V4 = V<F4>;

impl<L: Lane> V<L> {
    /// All lanes the zero vector (+0).
    pub const ZERO: Self = Self { x: L::ZERO, y: L::ZERO, z: L::ZERO };

    /// `Vec3::dot`: `(x·x') + (y·y') + (z·z')`, summed left to right.
    #[inline(always)]
    #[must_use]
    pub fn dot(self, other: Self) -> L {
        (self.x * other.x) + (self.y * other.y) + (self.z * other.z)
    }

    /// `Vec3::cross`, with glam's products and their order.
    #[inline(always)]
    #[must_use]
    pub fn cross(self, other: Self) -> Self {
        Self {
            x: self.y * other.z - other.y * self.z,
            y: self.z * other.x - other.z * self.x,
            z: self.x * other.y - other.x * self.y,
        }
    }

    /// Each lane's vector times that lane's scalar.
    #[inline(always)]
    #[must_use]
    pub fn scale(self, s: L) -> Self {
        Self { x: self.x * s, y: self.y * s, z: self.z * s }
    }

    /// Per lane: `a` where the mask is true, else `b`.
    #[inline(always)]
    #[must_use]
    pub fn select(mask: L::Mask, a: Self, b: Self) -> Self {
        Self { x: mask.select(a.x, b.x), y: mask.select(a.y, b.y), z: mask.select(a.z, b.z) }
    }
}

impl V4 {
    /// Lane `i`'s vector.
    #[inline(always)]
    #[must_use]
    pub fn lanes(self) -> [glam::Vec3; 4] {
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        [0, 1, 2, 3].map(|i| glam::Vec3::new(x[i], y[i], z[i]))
    }

    /// Lane `i` holds `base[indices[i]]`.
    ///
    /// # Safety
    /// `base` must point at an array of `len` vectors, readable for the call, and every
    /// index must be below `len` (debug builds check the indices).
    #[inline(always)]
    #[must_use]
    pub unsafe fn gather(base: *const glam::Vec3, len: usize, indices: [u32; 4]) -> Self {
        debug_assert!(indices.iter().all(|&i| (i as usize) < len), "{indices:?} within {len} vectors");
        // `Vec3` is `#[repr(C)] { x, y, z }`: three f32 in a row.
        // SAFETY: each index is below `len` (the caller's promise, checked above in
        // debug builds), so `base.add(i)` stays in the array and is a readable
        // `[f32; 3]`, which is what `imp::gather` asks.
        let [x, y, z] = unsafe { imp::gather(indices.map(|i| base.add(i as usize) as *const f32)) };
        Self { x: F4(x), y: F4(y), z: F4(z) }
    }

    /// Writes lane `i` to `base[indices[i]]` for each bit `i` set in `lanes`.
    ///
    /// # Safety
    /// `base` must point at an array of `len` vectors; for each lane set, `indices[i]`
    /// must be below `len`, its vector writable for the call and read or written by
    /// nothing else meanwhile; the lanes set must name distinct indices. Debug builds
    /// check the indices.
    #[inline(always)]
    pub unsafe fn scatter(self, base: *mut glam::Vec3, len: usize, indices: [u32; 4], lanes: u32) {
        debug_assert!(
            (0..4).filter(|&i| lanes & (1 << i) != 0).all(|i| (indices[i] as usize) < len
                && (0..i).all(|j| lanes & (1 << j) == 0 || indices[j] != indices[i])),
            "lanes {lanes:#b} of {indices:?}: distinct and within {len} vectors"
        );
        let points = indices.map(|i| base.wrapping_add(i as usize) as *mut f32);
        // SAFETY: each lane set names its own vector of the array (below `len`, distinct:
        // the caller's promise, checked above in debug builds), writable and untouched
        // by others meanwhile, which is what `imp::scatter` asks; unset lanes' pointers
        // are not used.
        unsafe { imp::scatter(points, lanes, [self.x.0, self.y.0, self.z.0]) }
    }

    /// The vectors of four lanes, lane 0 first.
    #[inline(always)]
    #[must_use]
    pub fn new(v: [glam::Vec3; 4]) -> Self {
        Self {
            x: F4::new([v[0].x, v[1].x, v[2].x, v[3].x]),
            y: F4::new([v[0].y, v[1].y, v[2].y, v[3].y]),
            z: F4::new([v[0].z, v[1].z, v[2].z, v[3].z]),
        }
    }
}

impl<L: Lane> std::ops::Add for V<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }
}

impl<L: Lane> std::ops::Sub for V<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }
}

/// Eight lanes with AVX: two batches of four contacts solved side by side.
///
/// Only x86-64 processors with AVX run this code: an [`F8`](avx::F8) is made and used
/// only inside functions compiled with `#[target_feature(enable = "avx")]`, which are
/// called only after `is_x86_feature_detected!("avx")` said yes (the contact solve's
/// `solve_batches` and `warm_start_batches`). Each operation is the 256-bit form of
/// the SSE one [`F4`] uses (the same IEEE operation in every lane; `max` and the
/// comparisons with SSE's semantics), so lanes 0–3 and 4–7 give exactly what two
/// [`F4`]s give.
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx {
    use std::arch::x86_64::*;

    use super::{F4, Joined, Lane, M4, Mask, V, V4};

    /// Whether this processor has AVX: what every `avx!` rests on.
    #[inline(always)]
    fn detected() -> bool {
        std::arch::is_x86_feature_detected!("avx")
    }

    /// Runs AVX intrinsics that take and give registers only, never a pointer.
    macro_rules! avx {
        ($e:expr) => {{
            debug_assert!(detected(), "an eight-lane value on a processor without AVX");
            // SAFETY: the intrinsics in `$e` need AVX, and these values exist only
            // inside functions compiled for AVX that are called after
            // `is_x86_feature_detected!("avx")` said yes (the module's note; debug
            // builds check it above); none of them touches memory.
            unsafe { $e }
        }};
    }

    /// Eight `f32` lanes.
    #[derive(Clone, Copy, Debug)]
    #[repr(transparent)]
    pub struct F8(__m256);

    /// Eight lanes of true or false.
    #[derive(Clone, Copy, Debug)]
    #[repr(transparent)]
    pub struct M8(__m256);

    impl Joined for F8 {
        type Half = F4;
        #[inline(always)]
        fn join(low: F4, high: F4) -> Self {
            Self(avx!(_mm256_set_m128(high.0, low.0)))
        }
        #[inline(always)]
        fn halves(self) -> (F4, F4) {
            avx!((F4(_mm256_castps256_ps128(self.0)), F4(_mm256_extractf128_ps::<1>(self.0))))
        }
        #[inline(always)]
        fn join_indices(low: [u32; 4], high: [u32; 4]) -> [u32; 8] {
            super::concat(low, high)
        }
        #[inline(always)]
        fn split_indices(indices: [u32; 8]) -> ([u32; 4], [u32; 4]) {
            super::halve(indices)
        }
    }

    impl F8 {
        /// The register.
        #[inline(always)]
        pub(crate) fn raw(self) -> __m256 {
            self.0
        }

        /// From a register.
        #[inline(always)]
        pub(crate) fn from_raw(raw: __m256) -> Self {
            Self(raw)
        }
    }

    impl M8 {
        /// Lanes 0–3 from `low`, 4–7 from `high`.
        #[inline(always)]
        #[must_use]
        pub fn join(low: M4, high: M4) -> Self {
            Self(avx!(_mm256_set_m128(high.0, low.0)))
        }
    }

    macro_rules! avx_op {
        ($trait:ident, $method:ident, $f:ident) => {
            impl std::ops::$trait for F8 {
                type Output = Self;
                #[inline(always)]
                fn $method(self, other: Self) -> Self {
                    Self(avx!($f(self.0, other.0)))
                }
            }
        };
    }
    avx_op!(Add, add, _mm256_add_ps);
    avx_op!(Sub, sub, _mm256_sub_ps);
    avx_op!(Mul, mul, _mm256_mul_ps);
    avx_op!(Div, div, _mm256_div_ps);

    impl std::ops::Neg for F8 {
        type Output = Self;
        /// Flips each lane's sign bit.
        #[inline(always)]
        fn neg(self) -> Self {
            Self(avx!(_mm256_xor_ps(self.0, _mm256_set1_ps(-0.0))))
        }
    }

    impl Lane for F8 {
        type Mask = M8;
        type Index = [u32; 8];
        // SAFETY: `[f32; 8]` and `__m256` are both 32 bytes of eight f32 lanes (the sizes
        // checked by `transmute` when compiling), and every bit pattern is a valid
        // `__m256`; making the constant runs no AVX instruction.
        const ZERO: Self = Self(unsafe { std::mem::transmute::<[f32; 8], __m256>([0.0; 8]) });
        #[inline(always)]
        fn splat(x: f32) -> Self {
            Self(avx!(_mm256_set1_ps(x)))
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            Self(avx!(_mm256_sqrt_ps(self.0)))
        }
        #[inline(always)]
        fn max(self, other: Self) -> Self {
            // `vmaxps` is `maxps` on eight lanes: `a > b ? a : b`.
            Self(avx!(_mm256_max_ps(self.0, other.0)))
        }
        #[inline(always)]
        fn gt(self, other: Self) -> M8 {
            // Ordered: false where either is NaN, as SSE's `cmpgtps`.
            M8(avx!(_mm256_cmp_ps::<_CMP_GT_OQ>(self.0, other.0)))
        }
        #[inline(always)]
        fn eq(self, other: Self) -> M8 {
            M8(avx!(_mm256_cmp_ps::<_CMP_EQ_OQ>(self.0, other.0)))
        }
        #[inline(always)]
        unsafe fn gather(base: *const glam::Vec3, len: usize, indices: [u32; 8]) -> V<Self> {
            let (low, high) = Self::split_indices(indices);
            // SAFETY: the caller's promise (`V4::gather`'s), for all eight indices.
            unsafe { V::<F8>::join(V4::gather(base, len, low), V4::gather(base, len, high)) }
        }
        #[inline(always)]
        unsafe fn scatter(value: V<Self>, base: *mut glam::Vec3, len: usize, indices: [u32; 8], lanes: u32) {
            debug_assert!(
                (0..8)
                    .filter(|&i| lanes & (1 << i) != 0)
                    .all(|i| (0..i).all(|j| lanes & (1 << j) == 0 || indices[j] != indices[i])),
                "lanes {lanes:#b} of {indices:?} name distinct vectors"
            );
            let ((low, high), (first, last)) = (Self::split_indices(indices), value.halves());
            // SAFETY: the caller's promise (`V4::scatter`'s), for every lane set: each
            // half's lanes are distinct and within `len` (checked by each half in debug
            // builds), and no lane of one half names a vector of the other (checked
            // above).
            unsafe {
                first.scatter(base, len, low, lanes & 0xF);
                last.scatter(base, len, high, lanes >> 4);
            }
        }
    }

    impl Mask<F8> for M8 {
        #[inline(always)]
        fn from_bits(bits: u32) -> Self {
            M8::join(M4::from_bits(bits & 0xF), M4::from_bits(bits >> 4))
        }
        #[inline(always)]
        fn select(self, a: F8, b: F8) -> F8 {
            // The masks are whole lanes of ones or zeros, so the sign bit `blendv`
            // reads decides as the whole lane would.
            F8(avx!(_mm256_blendv_ps(b.0, a.0, self.0)))
        }
        #[inline(always)]
        fn bits(self) -> u32 {
            avx!(_mm256_movemask_ps(self.0) as u32)
        }
        #[inline(always)]
        fn and(self, other: Self) -> Self {
            Self(avx!(_mm256_and_ps(self.0, other.0)))
        }
        #[inline(always)]
        fn or(self, other: Self) -> Self {
            Self(avx!(_mm256_or_ps(self.0, other.0)))
        }
    }
}

/// Sixteen lanes with AVX-512: four batches of four contacts solved side by side.
///
/// As [`avx`], one level up: an [`F16`](avx512::F16) is made and used only inside
/// functions compiled with `#[target_feature(enable = "avx512f")]` (and AVX), called
/// only after `is_x86_feature_detected!("avx512f")` said yes. Each operation is the
/// 512-bit form of the one [`F4`] and [`F8`](avx::F8) use (the same IEEE operation in
/// every lane; `max` and the ordered comparisons with SSE's semantics), so lanes 0–7
/// and 8–15 give exactly what two [`F8`](avx::F8)s give. Comparisons give a mask
/// register's sixteen bits, and a select is a masked blend.
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx512 {
    use std::arch::x86_64::*;

    use super::avx::F8;
    use super::{Joined, Lane, Mask, V};

    /// Whether this processor has AVX-512F and VL (and so AVX): what every `avx512!`
    /// rests on.
    #[inline(always)]
    fn detected() -> bool {
        std::arch::is_x86_feature_detected!("avx512f") && std::arch::is_x86_feature_detected!("avx512vl")
    }

    /// Runs AVX-512 (and AVX) intrinsics that take and give registers only, never a
    /// pointer.
    macro_rules! avx512 {
        ($e:expr) => {{
            debug_assert!(detected(), "a sixteen-lane value on a processor without AVX-512");
            // SAFETY: the intrinsics in `$e` need AVX-512F (or AVX), and these values
            // exist only inside functions compiled for AVX-512F and VL that are called
            // after `is_x86_feature_detected!` said yes to both (the module's note;
            // debug builds check it above); none of them touches memory.
            unsafe { $e }
        }};
    }

    /// Sixteen `f32` lanes.
    #[derive(Clone, Copy, Debug)]
    #[repr(transparent)]
    pub struct F16(__m512);

    /// Sixteen lanes of true or false: one bit each.
    #[derive(Clone, Copy, Debug)]
    #[repr(transparent)]
    pub struct M16(__mmask16);

    impl Joined for F16 {
        type Half = F8;
        #[inline(always)]
        fn join(low: F8, high: F8) -> Self {
            let (low, high): (__m256, __m256) = (low.raw(), high.raw());
            Self(avx512!(_mm512_castpd_ps(_mm512_insertf64x4::<1>(
                _mm512_castpd256_pd512(_mm256_castps_pd(low)),
                _mm256_castps_pd(high),
            ))))
        }
        #[inline(always)]
        fn halves(self) -> (F8, F8) {
            let (low, high) = avx512!((
                _mm512_castps512_ps256(self.0),
                _mm512_extractf64x4_pd::<1>(_mm512_castps_pd(self.0))
            ));
            (F8::from_raw(low), F8::from_raw(avx512!(_mm256_castpd_ps(high))))
        }
        #[inline(always)]
        fn join_indices(low: [u32; 8], high: [u32; 8]) -> [u32; 16] {
            super::concat(low, high)
        }
        #[inline(always)]
        fn split_indices(indices: [u32; 16]) -> ([u32; 8], [u32; 8]) {
            super::halve(indices)
        }
    }

    macro_rules! avx512_op {
        ($trait:ident, $method:ident, $f:ident) => {
            impl std::ops::$trait for F16 {
                type Output = Self;
                #[inline(always)]
                fn $method(self, other: Self) -> Self {
                    Self(avx512!($f(self.0, other.0)))
                }
            }
        };
    }
    avx512_op!(Add, add, _mm512_add_ps);
    avx512_op!(Sub, sub, _mm512_sub_ps);
    avx512_op!(Mul, mul, _mm512_mul_ps);
    avx512_op!(Div, div, _mm512_div_ps);

    impl std::ops::Neg for F16 {
        type Output = Self;
        /// Flips each lane's sign bit.
        #[inline(always)]
        fn neg(self) -> Self {
            Self(avx512!(_mm512_castsi512_ps(_mm512_xor_si512(
                _mm512_castps_si512(self.0),
                _mm512_set1_epi32(i32::MIN),
            ))))
        }
    }

    impl Lane for F16 {
        type Mask = M16;
        type Index = [u32; 16];
        // SAFETY: `[f32; 16]` and `__m512` are both 64 bytes of sixteen f32 lanes (the
        // sizes checked by `transmute` when compiling), and every bit pattern is a
        // valid `__m512`; making the constant runs no AVX-512 instruction.
        const ZERO: Self = Self(unsafe { std::mem::transmute::<[f32; 16], __m512>([0.0; 16]) });
        #[inline(always)]
        fn splat(x: f32) -> Self {
            Self(avx512!(_mm512_set1_ps(x)))
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            Self(avx512!(_mm512_sqrt_ps(self.0)))
        }
        #[inline(always)]
        fn max(self, other: Self) -> Self {
            // `vmaxps` on sixteen lanes: `a > b ? a : b`, as SSE's `maxps`.
            Self(avx512!(_mm512_max_ps(self.0, other.0)))
        }
        #[inline(always)]
        fn gt(self, other: Self) -> M16 {
            // Ordered: false where either is NaN, as SSE's `cmpgtps`.
            M16(avx512!(_mm512_cmp_ps_mask::<_CMP_GT_OQ>(self.0, other.0)))
        }
        #[inline(always)]
        fn eq(self, other: Self) -> M16 {
            M16(avx512!(_mm512_cmp_ps_mask::<_CMP_EQ_OQ>(self.0, other.0)))
        }
        #[inline(always)]
        unsafe fn gather(base: *const glam::Vec3, len: usize, indices: [u32; 16]) -> V<Self> {
            let (low, high) = Self::split_indices(indices);
            // SAFETY: the caller's promise (`V4::gather`'s), for all sixteen indices.
            unsafe { V::<F16>::join(F8::gather(base, len, low), F8::gather(base, len, high)) }
        }
        #[inline(always)]
        unsafe fn scatter(value: V<Self>, base: *mut glam::Vec3, len: usize, indices: [u32; 16], lanes: u32) {
            debug_assert!(
                (0..16)
                    .filter(|&i| lanes & (1 << i) != 0)
                    .all(|i| (0..i).all(|j| lanes & (1 << j) == 0 || indices[j] != indices[i])),
                "lanes {lanes:#b} of {indices:?} name distinct vectors"
            );
            let ((low, high), (first, last)) = (Self::split_indices(indices), value.halves());
            // SAFETY: the caller's promise (`V4::scatter`'s), for every lane set: each
            // half's lanes are distinct and within `len` (checked by each half in debug
            // builds), and no lane of one half names a vector of the other (checked
            // above).
            unsafe {
                F8::scatter(first, base, len, low, lanes & 0xFF);
                F8::scatter(last, base, len, high, lanes >> 8);
            }
        }
    }

    impl Mask<F16> for M16 {
        #[inline(always)]
        fn from_bits(bits: u32) -> Self {
            M16(bits as __mmask16)
        }
        #[inline(always)]
        fn select(self, a: F16, b: F16) -> F16 {
            // The blend takes its second operand where the mask's bit is set.
            F16(avx512!(_mm512_mask_blend_ps(self.0, b.0, a.0)))
        }
        #[inline(always)]
        fn bits(self) -> u32 {
            u32::from(self.0)
        }
        #[inline(always)]
        fn and(self, other: Self) -> Self {
            Self(self.0 & other.0)
        }
        #[inline(always)]
        fn or(self, other: Self) -> Self {
            Self(self.0 | other.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Awkward values: signed zeros, tiny, huge, NaN and infinities.
    const ODD: [f32; 12] =
        [0.0, -0.0, 1.0, -1.5, 1e-38, -3e-39, 3.4e38, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 0.1, -7.25];

    fn same(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    /// Every lane operation gives the bits the scalar operation gives, for every pair
    /// of awkward values (max as `a > b ? a : b`).
    #[test]
    fn each_lane_computes_what_scalar_code_computes() {
        for &a in &ODD {
            for &b in &ODD {
                let (x, y) = (F4::new([a, b, a, b]), F4::new([b, a, b, a]));
                let checks: [(F4, [f32; 2]); 6] = [
                    (x + y, [a + b, b + a]),
                    (x - y, [a - b, b - a]),
                    (x * y, [a * b, b * a]),
                    (x / y, [a / b, b / a]),
                    (x.max(y), [if a > b { a } else { b }, if b > a { b } else { a }]),
                    (-x, [-a, -b]),
                ];
                for (wide, scalar) in checks {
                    let lanes = wide.to_array();
                    assert!(
                        same(lanes[0], scalar[0]) && same(lanes[1], scalar[1]),
                        "{a} {b}: {lanes:?} {scalar:?}"
                    );
                }
                assert!(same(x.sqrt().to_array()[0], a.sqrt()));
                assert_eq!(x.gt(y).bits() & 1 != 0, a > b);
                assert_eq!(x.eq(y).bits() & 1 != 0, a == b);
                let picked = x.gt(y).select(x, y).to_array()[0];
                assert!(same(picked, if a > b { a } else { b }));
            }
        }
    }

    /// Dot and cross products equal glam's, lane by lane, to the bit.
    #[test]
    fn vector_products_equal_glams() {
        let vectors: Vec<Vec3> = (0..16)
            .map(|i| {
                let k = |j: usize| {
                    ODD[(i * 5 + j * 7) % ODD.len()] * if (i + j).is_multiple_of(3) { 0.37 } else { -2.0 }
                };
                Vec3::new(k(0), k(1), k(2))
            })
            .collect();
        for pair in vectors.chunks(8) {
            let (a, b) = ([pair[0], pair[1], pair[2], pair[3]], [pair[4], pair[5], pair[6], pair[7]]);
            let (wa, wb) = (V4::new(a), V4::new(b));
            let (dot, cross) = (wa.dot(wb).to_array(), wa.cross(wb).lanes());
            for i in 0..4 {
                assert!(same(dot[i], a[i].dot(b[i])));
                let expected = a[i].cross(b[i]);
                assert!(
                    same(cross[i].x, expected.x)
                        && same(cross[i].y, expected.y)
                        && same(cross[i].z, expected.z)
                );
            }
        }
    }

    /// Gathering four vectors from an array and scattering them back moves the right
    /// bits, lanes not asked for stay as they were, and the last vector of the array is
    /// read without reading past it.
    #[test]
    fn gather_and_scatter_move_whole_vectors() {
        let mut array: Vec<Vec3> =
            (0..7).map(|i| Vec3::new(i as f32, -(i as f32) - 0.5, 100.0 + i as f32)).collect();
        array[2].x = -0.0;
        let indices = [6, 2, 0, 5];
        // SAFETY: every index is below the array's 7 vectors.
        let wide = unsafe { V4::gather(array.as_ptr(), array.len(), indices) };
        let lanes = wide.lanes();
        for (lane, &i) in lanes.iter().zip(&indices) {
            assert_eq!(lane.to_array().map(f32::to_bits), array[i as usize].to_array().map(f32::to_bits));
        }
        let moved = V4::new([Vec3::splat(1.0), Vec3::splat(2.0), Vec3::splat(3.0), Vec3::splat(4.0)]);
        let before = array.clone();
        // SAFETY: as above; lanes 1 and 3 only, distinct.
        unsafe { moved.scatter(array.as_mut_ptr(), array.len(), indices, 0b1010) };
        assert_eq!(array[2], Vec3::splat(2.0));
        assert_eq!(array[5], Vec3::splat(4.0));
        for i in [0, 1, 3, 4, 6] {
            assert_eq!(array[i], before[i]);
        }
    }

    /// Eight AVX lanes compute what two [`F4`]s compute, to the bit, for every
    /// operation the solve uses; joining, halving, gathering and scattering move whole
    /// lanes. Skipped (with a note) on a processor without AVX.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn eight_lanes_equal_two_fours() {
        if !std::arch::is_x86_feature_detected!("avx") {
            eprintln!("no AVX here: the eight-lane path is never taken, nothing to check");
            return;
        }
        // SAFETY: the processor has AVX (checked just above).
        unsafe { eight_lanes_check() }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    fn eight_lanes_check() {
        use avx::{F8, M8};
        let bits = |x: F4| x.to_array().map(f32::to_bits);
        let halves_bits = |x: F8| {
            let (low, high) = x.halves();
            (bits(low), bits(high))
        };
        let mut checked = 0;
        for (k, &a) in ODD.iter().enumerate() {
            let lanes = |shift: usize| F4::new([0, 1, 2, 3].map(|i| ODD[(k + i + shift) % ODD.len()]));
            let (x0, x1, y0, y1) = (lanes(0), lanes(4), F4::splat(a), lanes(7));
            let (x, y) = (F8::join(x0, x1), F8::join(y0, y1));
            let same_as = |wide: F8, low: F4, high: F4| {
                let ((l, h), (el, eh)) = (halves_bits(wide), (bits(low), bits(high)));
                // NaN payloads may differ between operations; everything else is bit for bit.
                let agree = |w: [u32; 4], e: [u32; 4]| {
                    (0..4).all(|i| {
                        w[i] == e[i] || (f32::from_bits(w[i]).is_nan() && f32::from_bits(e[i]).is_nan())
                    })
                };
                agree(l, el) && agree(h, eh)
            };
            assert!(same_as(x + y, x0 + y0, x1 + y1));
            assert!(same_as(x - y, x0 - y0, x1 - y1));
            assert!(same_as(x * y, x0 * y0, x1 * y1));
            assert!(same_as(x / y, x0 / y0, x1 / y1));
            assert!(same_as(-x, -x0, -x1));
            assert!(same_as(Lane::sqrt(x), x0.sqrt(), x1.sqrt()));
            assert!(same_as(Lane::max(x, y), x0.max(y0), x1.max(y1)));
            let (gt, eq) = (Lane::gt(x, y), Lane::eq(x, y));
            assert_eq!(gt.bits(), x0.gt(y0).bits() | x1.gt(y1).bits() << 4);
            assert_eq!(eq.bits(), x0.eq(y0).bits() | x1.eq(y1).bits() << 4);
            assert!(same_as(gt.select(x, y), x0.gt(y0).select(x0, y0), x1.gt(y1).select(x1, y1)));
            let mask = <M8 as Mask<F8>>::from_bits(0b1001_0110);
            assert_eq!(mask.bits(), 0b1001_0110);
            assert_eq!(mask.and(gt).bits(), 0b1001_0110 & gt.bits());
            assert_eq!(mask.or(gt).bits(), 0b1001_0110 | gt.bits());
            checked += 1;
        }
        assert_eq!(checked, ODD.len());
        assert_eq!(halves_bits(<F8 as Lane>::ZERO), ([0; 4], [0; 4]));
        for &a in &ODD {
            let (low, high) = halves_bits(<F8 as Lane>::splat(a));
            assert_eq!((low, high), (bits(F4::splat(a)), bits(F4::splat(a))));
        }

        let mut array: Vec<Vec3> =
            (0..11).map(|i| Vec3::new(i as f32, 0.5 - i as f32, 10.0 * i as f32)).collect();
        let indices = [10, 3, 0, 7, 2, 9, 5, 1];
        // SAFETY: every index is below the array's 11 vectors, and they are distinct.
        let wide = unsafe { F8::gather(array.as_ptr(), array.len(), indices) };
        let (low, high) = wide.halves();
        let read: Vec<Vec3> = low.lanes().into_iter().chain(high.lanes()).collect();
        assert_eq!(read, indices.map(|i| array[i as usize]).to_vec());
        let before = array.clone();
        let moved = V::<F8>::join(V4::new([Vec3::splat(-1.0); 4]), V4::new([Vec3::splat(-2.0); 4]));
        // SAFETY: as above; lanes 0, 1 and 6 only.
        unsafe { F8::scatter(moved, array.as_mut_ptr(), array.len(), indices, 0b0100_0011) };
        for (i, (now, was)) in array.iter().zip(&before).enumerate() {
            let expected = match i {
                10 | 3 => Vec3::splat(-1.0),
                5 => Vec3::splat(-2.0),
                _ => *was,
            };
            assert_eq!(*now, expected, "vector {i}");
        }
    }

    /// Sixteen lanes (AVX-512) compute what two eight-lane halves compute, bit for bit.
    /// Checked where the processor has AVX-512F; elsewhere the path is never taken.
    /// (Miri cannot run it: it has no `_mm512_cmp_ps_mask`; `scripts/miri.sh`.)
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn sixteen_lanes_equal_two_eights() {
        if !(std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl"))
        {
            eprintln!("no AVX-512 here: the sixteen-lane path is never taken, nothing to check");
            return;
        }
        // SAFETY: the processor has AVX-512F and VL, and so AVX (checked just above).
        unsafe { sixteen_lanes_check() }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx512f,avx512vl")]
    fn sixteen_lanes_check() {
        use avx::F8;
        use avx512::{F16, M16};
        let quarter = |x: F8| {
            let (low, high) = x.halves();
            [low.to_array(), high.to_array()]
        };
        let bits16 = |x: F16| {
            let (low, high) = x.halves();
            let [a, b] = quarter(low);
            let [c, d] = quarter(high);
            [a, b, c, d].concat().into_iter().map(f32::to_bits).collect::<Vec<u32>>()
        };
        let bits8x2 = |low: F8, high: F8| {
            let [a, b] = quarter(low);
            let [c, d] = quarter(high);
            [a, b, c, d].concat().into_iter().map(f32::to_bits).collect::<Vec<u32>>()
        };
        // NaN payloads may differ between operations; everything else is bit for bit.
        let agree = |w: Vec<u32>, e: Vec<u32>| {
            w.iter()
                .zip(&e)
                .all(|(&w, &e)| w == e || (f32::from_bits(w).is_nan() && f32::from_bits(e).is_nan()))
        };
        let eight = |k: usize, shift: usize| {
            let lanes = |s: usize| F4::new([0, 1, 2, 3].map(|i| ODD[(k + i + s) % ODD.len()]));
            F8::join(lanes(shift), lanes(shift + 4))
        };
        let mut checked = 0;
        for (k, &a) in ODD.iter().enumerate() {
            let (x0, x1) = (eight(k, 0), eight(k, 5));
            let (y0, y1) = (F8::splat(a), eight(k, 3));
            let (x, y) = (F16::join(x0, x1), F16::join(y0, y1));
            assert!(agree(bits16(x + y), bits8x2(x0 + y0, x1 + y1)));
            assert!(agree(bits16(x - y), bits8x2(x0 - y0, x1 - y1)));
            assert!(agree(bits16(x * y), bits8x2(x0 * y0, x1 * y1)));
            assert!(agree(bits16(x / y), bits8x2(x0 / y0, x1 / y1)));
            assert!(agree(bits16(-x), bits8x2(-x0, -x1)));
            assert!(agree(bits16(Lane::sqrt(x)), bits8x2(Lane::sqrt(x0), Lane::sqrt(x1))));
            assert!(agree(bits16(Lane::max(x, y)), bits8x2(Lane::max(x0, y0), Lane::max(x1, y1))));
            let (gt, eq) = (Lane::gt(x, y), Lane::eq(x, y));
            assert_eq!(gt.bits(), Lane::gt(x0, y0).bits() | Lane::gt(x1, y1).bits() << 8);
            assert_eq!(eq.bits(), Lane::eq(x0, y0).bits() | Lane::eq(x1, y1).bits() << 8);
            let picked = bits8x2(Lane::gt(x0, y0).select(x0, y0), Lane::gt(x1, y1).select(x1, y1));
            assert!(agree(bits16(gt.select(x, y)), picked));
            let mask = <M16 as Mask<F16>>::from_bits(0b1001_0110_0011_1010);
            assert_eq!(mask.bits(), 0b1001_0110_0011_1010);
            assert_eq!(mask.and(gt).bits(), 0b1001_0110_0011_1010 & gt.bits());
            assert_eq!(mask.or(gt).bits(), 0b1001_0110_0011_1010 | gt.bits());
            checked += 1;
        }
        assert_eq!(checked, ODD.len());
    }

    /// Sixteen lanes (AVX-512) are zero or a splat in every lane, and move whole vectors
    /// in and out of an array (gathered, scattered, joined and halved). Checked where
    /// the processor has AVX-512F; elsewhere the path is never taken.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn sixteen_lanes_move_whole_vectors() {
        if !(std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl"))
        {
            eprintln!("no AVX-512 here: the sixteen-lane path is never taken, nothing to check");
            return;
        }
        // SAFETY: the processor has AVX-512F and VL, and so AVX (checked just above).
        unsafe { sixteen_lanes_move_check() }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx512f,avx512vl")]
    fn sixteen_lanes_move_check() {
        use avx::F8;
        use avx512::F16;
        let bits = |x: F16| {
            let (low, high) = x.halves();
            let ((a, b), (c, d)) = (low.halves(), high.halves());
            [a, b, c, d].map(|x| x.to_array().map(f32::to_bits)).concat()
        };
        assert!(bits(<F16 as Lane>::ZERO).iter().all(|&b| b == 0));
        for &a in &ODD {
            assert!(bits(<F16 as Lane>::splat(a)).iter().all(|&b| same(f32::from_bits(b), a)));
        }

        let mut array: Vec<Vec3> =
            (0..19).map(|i| Vec3::new(i as f32, 0.5 - i as f32, 10.0 * i as f32)).collect();
        let indices = [10, 3, 0, 7, 2, 9, 5, 1, 18, 11, 4, 16, 6, 13, 8, 12];
        // SAFETY: every index is below the array's 19 vectors, and they are distinct.
        let wide = unsafe { F16::gather(array.as_ptr(), array.len(), indices) };
        let (low, high) = wide.halves();
        let ((l0, l1), (h0, h1)) = (low.halves(), high.halves());
        let read: Vec<Vec3> = [l0, l1, h0, h1].into_iter().flat_map(V4::lanes).collect();
        assert_eq!(read, indices.map(|i| array[i as usize]).to_vec());
        let before = array.clone();
        let fill = |v: f32| V::<F8>::join(V4::new([Vec3::splat(v); 4]), V4::new([Vec3::splat(v - 0.5); 4]));
        let moved = V::<F16>::join(fill(-1.0), fill(-2.0));
        // SAFETY: as above; lanes 0, 6, 9 and 15 only.
        unsafe {
            F16::scatter(moved, array.as_mut_ptr(), array.len(), indices, 1 | 1 << 6 | 1 << 9 | 1 << 15)
        };
        for (i, (now, was)) in array.iter().zip(&before).enumerate() {
            let expected = match i {
                10 => Vec3::splat(-1.0),
                5 => Vec3::splat(-1.5),
                11 => Vec3::splat(-2.0),
                12 => Vec3::splat(-2.5),
                _ => *was,
            };
            assert_eq!(*now, expected, "vector {i}");
        }
    }

    /// The constant zeros (made by `transmute`) are +0 in every lane, and a splat is
    /// its value in every lane; arrays go in and out of the register lane 0 first.
    #[test]
    fn zeros_splats_and_arrays_fill_every_lane() {
        assert_eq!(F4::ZERO.to_array().map(f32::to_bits), [0; 4]);
        assert_eq!(<F4 as Lane>::ZERO.to_array().map(f32::to_bits), [0; 4]);
        for &a in &ODD {
            assert!(F4::splat(a).to_array().iter().all(|&x| same(x, a)));
        }
        let lanes = [1.0, -0.0, f32::NAN, 3e-39];
        let back = F4::new(lanes).to_array();
        assert!((0..4).all(|i| same(back[i], lanes[i])));
        assert_eq!(V4::ZERO.lanes(), [Vec3::ZERO; 4]);
    }

    #[test]
    fn masks_select_and_combine_lane_by_lane() {
        let m = M4::new([true, false, true, false]);
        assert_eq!(m.bits(), 0b0101);
        let n = M4::new([true, true, false, false]);
        assert_eq!(m.and(n).bits(), 0b0001);
        assert_eq!(m.or(n).bits(), 0b0111);
        let picked = m.select(F4::splat(1.0), F4::splat(-0.0)).to_array();
        assert_eq!(picked.map(f32::to_bits), [1.0f32, -0.0, 1.0, -0.0].map(f32::to_bits));
        assert_eq!(M4::new([false; 4]).bits(), 0);
    }
}
