//! Rolling spheres turned by their spin: each orientation by the exact rotation of a
//! constant spin over the step, with the arithmetic spelled out so that every target
//! (x86-64 with or without AVX, wasm) gives the same bits.

use glam::{Quat, Vec3};

use super::store::Particles;

impl Particles {
    /// Gives a store read from an old snapshot (made before spheres could roll) its
    /// rotation arrays: every particle a point mass at rest.
    pub(crate) fn fill_missing_rotation(&mut self) {
        let n = self.ids.len();
        if self.inverse_inertia.is_empty() && self.angular_velocity.is_empty() && self.orientation.is_empty()
        {
            self.inverse_inertia.resize(n, 0.0);
            self.angular_velocity.resize(n, Vec3::ZERO);
            self.orientation.resize(n, Quat::IDENTITY);
        }
        if self.rolling.is_empty() {
            self.rolling.extend(self.inverse_inertia.iter().map(|&i| i != 0.0));
        }
    }

    /// Turns every rolling, awake sphere by its angular velocity over `dt` (the exact
    /// rotation for a constant spin; the step's contacts change the spin, not this).
    ///
    /// The arithmetic is spelled out in scalars (see [`turned`]) so that the same step gives
    /// the same bits on every target: glam's `Quat` product is SIMD on x86-64 and scalar on
    /// wasm, and `sin`/`cos` come from different libraries there, and orientation is part
    /// of the state hash that the browser build is checked against.
    pub(crate) fn turn(&mut self, dt: f32) {
        // Each sphere turns on its own: threads change nothing but the time.
        if self.len() >= PARALLEL_TURN {
            use rayon::prelude::*;
            let spins =
                self.angular_velocity.par_chunks(TURN_CHUNK).zip(self.inverse_inertia.par_chunks(TURN_CHUNK));
            self.orientation
                .par_chunks_mut(TURN_CHUNK)
                .zip(spins)
                .for_each(|(q, (w, inertia))| turn_run(q, w, inertia, dt));
        } else {
            turn_run(&mut self.orientation, &self.angular_velocity, &self.inverse_inertia, dt);
        }
    }
}

/// Particles from which [`Particles::turn`] runs on several threads.
const PARALLEL_TURN: usize = 4096;
/// Particles a task of [`Particles::turn`] takes at a time.
const TURN_CHUNK: usize = 2048;

/// Turns each rolling sphere of a run (orientations `q`, spins `w`, inverse inertias)
/// by its spin over `dt`: [`turned`], with the sines and cosines of eight spheres at a
/// time in AVX's `f64` lanes where the processor has it (the same operations on each,
/// so the same bits).
fn turn_run(q: &mut [Quat], w: &[Vec3], inverse_inertia: &[f32], dt: f32) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: `turn_run_avx` needs AVX, and the processor has it (checked just above).
        unsafe { turn_run_avx(q, w, inverse_inertia, dt) };
        return;
    }
    for ((q, &w), &inverse_inertia) in q.iter_mut().zip(w).zip(inverse_inertia) {
        if inverse_inertia != 0.0 && w != Vec3::ZERO {
            *q = turned(*q, w * dt);
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn turn_run_avx(q: &mut [Quat], w: &[Vec3], inverse_inertia: &[f32], dt: f32) {
    // Up to eight spheres waiting for their sines: index, turn, angle, reduced half angle.
    let mut waiting = [(0usize, Vec3::ZERO, 0.0f32, 0.0f64); 8];
    let mut count = 0;
    for (i, (&w, &inverse_inertia)) in w.iter().zip(inverse_inertia).enumerate() {
        if inverse_inertia == 0.0 || w == Vec3::ZERO {
            continue;
        }
        let turn = w * dt;
        let angle = turn.length();
        if angle == 0.0 {
            continue; // see `turned`
        }
        waiting[count] = (i, turn, angle, reduced_half_angle(angle));
        count += 1;
        if count == 8 {
            let x = waiting.map(|(.., x)| x);
            let (sin, cos) = half_angle_sin_cos_avx([x[0], x[1], x[2], x[3]], [x[4], x[5], x[6], x[7]]);
            for (k, &(i, turn, angle, _)) in waiting.iter().enumerate() {
                q[i] = rotated(q[i], turn, angle, sin[k], cos[k]);
            }
            count = 0;
        }
    }
    for &(i, turn, angle, x) in &waiting[..count] {
        let (sin, cos) = sin_cos_series(x);
        q[i] = rotated(q[i], turn, angle, sin, cos);
    }
}

/// [`sin_cos_series`] of eight reduced half angles at once, in two of AVX's four `f64`
/// lanes: each lane the same operations in the same order, so the same bits. The two
/// chains of the Horner rule are independent, so the processor runs them side by side
/// (each step waits for the one before: with one chain of four, the turn of a forming
/// pile of 100,000 spheres took 2.05 to 2.1 ms a step on one thread).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn half_angle_sin_cos_avx(low: [f64; 4], high: [f64; 4]) -> ([f32; 8], [f32; 8]) {
    use std::arch::x86_64::*;
    // Four f64, lane 0 first, are what `__m256d` holds: a plain cast, no pointer.
    let (x, y): (__m256d, __m256d) = (bytemuck::cast(low), bytemuck::cast(high));
    let (x2, y2) = (_mm256_mul_pd(x, x), _mm256_mul_pd(y, y));
    let one = _mm256_set1_pd(1.0);
    let (mut sin_x, mut cos_x, mut sin_y, mut cos_y) = (one, one, one, one);
    for k in (1..=11).rev() {
        let (sin_factor, cos_factor) = series_factors(f64::from(k));
        let (sin_factor, cos_factor) = (_mm256_set1_pd(sin_factor), _mm256_set1_pd(cos_factor));
        sin_x = _mm256_sub_pd(one, _mm256_mul_pd(_mm256_mul_pd(x2, sin_factor), sin_x));
        sin_y = _mm256_sub_pd(one, _mm256_mul_pd(_mm256_mul_pd(y2, sin_factor), sin_y));
        cos_x = _mm256_sub_pd(one, _mm256_mul_pd(_mm256_mul_pd(x2, cos_factor), cos_x));
        cos_y = _mm256_sub_pd(one, _mm256_mul_pd(_mm256_mul_pd(y2, cos_factor), cos_y));
    }
    let halves = |a: __m256d, b: __m256d| -> [f32; 8] {
        let (a, b): ([f64; 4], [f64; 4]) = (bytemuck::cast(a), bytemuck::cast(b));
        std::array::from_fn(|k| if k < 4 { a[k] as f32 } else { b[k - 4] as f32 })
    };
    (halves(_mm256_mul_pd(x, sin_x), _mm256_mul_pd(y, sin_y)), halves(cos_x, cos_y))
}

/// `q` turned by the rotation vector `turn` (axis × angle, rad), renormalised: the
/// product (cos ½θ, sin ½θ · axis) · q written out component by component in a fixed
/// order, with [`half_angle_sin_cos`] in place of the platform's `sin_cos`, so every
/// target rounds it alike.
fn turned(q: Quat, turn: Vec3) -> Quat {
    let angle = turn.length();
    if angle == 0.0 {
        // A spin so slow that its step's turn squares to nothing (|ω dt| < 1e-19 rad).
        return q;
    }
    let (sin, cos) = half_angle_sin_cos(angle);
    rotated(q, turn, angle, sin, cos)
}

/// The product of [`turned`], given the sine and cosine of half of `angle = |turn|`.
#[inline(always)]
fn rotated(q: Quat, turn: Vec3, angle: f32, sin: f32, cos: f32) -> Quat {
    let s = sin / angle;
    let (ax, ay, az, aw) = (turn.x * s, turn.y * s, turn.z * s, cos);
    let (bx, by, bz, bw) = (q.x, q.y, q.z, q.w);
    let x = aw * bx + ax * bw + (ay * bz - az * by);
    let y = aw * by + ay * bw + (az * bx - ax * bz);
    let z = aw * bz + az * bw + (ax * by - ay * bx);
    let w = aw * bw - (ax * bx + ay * by + az * bz);
    let length = (((x * x + y * y) + z * z) + w * w).sqrt();
    Quat::from_xyzw(x / length, y / length, z / length, w / length)
}

/// sin and cos of half of `angle` (rad), from a reduction to [−π, π] and Taylor
/// series in f64 (terms to the 22nd/23rd power: under 1e-10 at π, far below f32's
/// resolution). Only IEEE basic operations, so the bits are the same everywhere.
fn half_angle_sin_cos(angle: f32) -> (f32, f32) {
    sin_cos_series(reduced_half_angle(angle))
}

/// Half of `angle`, brought into [−π, π] (f64).
#[inline(always)]
fn reduced_half_angle(angle: f32) -> f64 {
    let tau = std::f64::consts::TAU;
    let half = f64::from(angle) * 0.5;
    half - tau * (half / tau).round()
}

/// sin and cos of `x` in [−π, π], from their Taylor series by Horner's rule.
#[inline(always)]
fn sin_cos_series(x: f64) -> (f32, f32) {
    let x2 = x * x;
    let (mut sin, mut cos) = (1.0f64, 1.0f64);
    // Horner from the highest term down: sin x = x(1 − x²/(2·3)(1 − x²/(4·5)(…))).
    for k in (1..=11).rev() {
        let (sin_factor, cos_factor) = series_factors(f64::from(k));
        sin = 1.0 - x2 * sin_factor * sin;
        cos = 1.0 - x2 * cos_factor * cos;
    }
    ((x * sin) as f32, cos as f32)
}

/// The factors of the `k`th step of [`sin_cos_series`]'s Horner rule, `1 / (2k (2k +
/// 1))` for the sine and `1 / ((2k − 1) 2k)` for the cosine: constants, so the compiler
/// works them out (correctly rounded, as at run time) and each step multiplies where it
/// divided. (The turn of a forming pile of 100,000 rolling spheres took 2.3 ms a step
/// on one thread with the 22 divisions, 2.05 to 2.1 with the factors; the Horner rule's
/// chain of dependent operations is most of what is left. The orientations came out
/// with the same bits: every state hash stayed as it was.)
#[inline(always)]
fn series_factors(k: f64) -> (f64, f64) {
    (1.0 / ((2.0 * k) * (2.0 * k + 1.0)), 1.0 / ((2.0 * k - 1.0) * (2.0 * k)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    /// A run of spheres turned eight at a time (AVX's f64 lanes, where the processor
    /// has them) comes out bit for bit as each turned alone, including the spheres
    /// left over after the last four and those that do not turn. (Under Miri, which
    /// runs it for the AVX path's sake, 103 spheres.)
    #[test]
    fn turning_a_run_equals_turning_each_alone() {
        let n = if cfg!(miri) { 103 } else { 1003 };
        let q0: Vec<Quat> = (0..n)
            .map(|i| Quat::from_xyzw(0.3 + i as f32 * 1e-3, -0.5, 0.1, 0.8 - i as f32 * 2e-4).normalize())
            .collect();
        let w: Vec<Vec3> = (0..n)
            .map(|i| {
                let f = i as f32;
                if i % 11 == 0 {
                    Vec3::ZERO
                } else {
                    Vec3::new((f * 0.37).sin(), (f * 0.11).cos(), (f * 0.05).sin()) * (1e-6 + f * f * 0.01)
                }
            })
            .collect();
        let inertia: Vec<f32> = (0..n).map(|i| if i % 13 == 5 { 0.0 } else { 2.5 }).collect();
        let dt = 1.0 / 60.0;
        let mut q = q0.clone();
        turn_run(&mut q, &w, &inertia, dt);
        for i in 0..n {
            let expected =
                if inertia[i] != 0.0 && w[i] != Vec3::ZERO { turned(q0[i], w[i] * dt) } else { q0[i] };
            assert_eq!(
                q[i].to_array().map(f32::to_bits),
                expected.to_array().map(f32::to_bits),
                "sphere {i}"
            );
        }
        assert!((0..n).filter(|&i| q[i] != q0[i]).count() > n * 3 / 4, "most spheres turned");
    }

    /// The portable sin/cos and quaternion turn agree with the platform's (std and
    /// glam) to f32 resolution, over small, large and wrapped-around angles.
    #[test]
    #[cfg_attr(miri, ignore = "no unsafe code, and Miri's sin and cos are deliberately inexact")]
    fn the_portable_turn_agrees_with_glam() {
        let q = Quat::from_xyzw(0.3, -0.5, 0.1, 0.8).normalize();
        // A turn too small to square (the spin of a sphere all but at rest) leaves q.
        assert_eq!(turned(q, Vec3::new(1e-25, 0.0, 0.0)), q);
        assert!(turned(q, Vec3::new(1e-18, 1e-30, 0.0)).is_finite());
        for i in 0..2000 {
            let angle = (i as f32) * 0.013 - 5.0 + if i % 7 == 0 { 1000.0 } else { 0.0 };
            let (sin, cos) = half_angle_sin_cos(angle);
            let (s, c) = (f64::from(angle) * 0.5).sin_cos();
            assert!((f64::from(sin) - s).abs() < 2e-7 && (f64::from(cos) - c).abs() < 2e-7, "{angle}");
            if angle != 0.0 {
                let turn = Vec3::new(0.6, 0.0, -0.8) * angle;
                let ours = turned(q, turn);
                let glam = (Quat::from_scaled_axis(turn) * q).normalize();
                let apart = (Vec4::from(ours) - Vec4::from(glam))
                    .length()
                    .min((Vec4::from(ours) + Vec4::from(glam)).length());
                assert!(apart < 1e-5, "{angle}: {ours} vs {glam}");
            }
        }
    }
}
