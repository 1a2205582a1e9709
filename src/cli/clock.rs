//! Simulated time as people wrote it: a step of 1/240 s prints its fifth step as
//! `0.0208333`, not as the single-precision `0.020833334419876337`.
//!
//! The engine steps with an `f32` time step, which is never exactly 1/240 or 0.01; the
//! times it reports carry that rounding. The command line knows what was meant (a rate
//! in Hz, or a decimal typed after `--dt`) and prints times from that.

/// A time step as the exact fraction of a second it stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    /// Numerator (s).
    pub numerator: u64,
    /// Denominator.
    pub denominator: u64,
}

/// Most decimals a printed time gets.
const MAX_DECIMALS: u32 = 12;

impl Step {
    /// What `dt` stands for: `1/N` when it is the `f32` nearest to a whole rate of `N`
    /// Hz, else the shortest decimal that reads back as `dt` (`0.003` for `--dt 0.003`);
    /// `None` for a step that is not a positive number or needs more than 12 decimals.
    #[must_use]
    pub fn of(dt: f32) -> Option<Self> {
        if !(dt.is_finite() && dt > 0.0) {
            return None;
        }
        let rate = (1.0 / f64::from(dt)).round();
        if (1.0..=1e9).contains(&rate) && (1.0 / rate) as f32 == dt {
            return Some(Self { numerator: 1, denominator: rate as u64 });
        }
        // Rust prints the shortest decimal that reads back as the same f32, never
        // with an exponent.
        let text = dt.to_string();
        let decimals = text.split_once('.').map_or(0, |(_, fraction)| fraction.len() as u32);
        if decimals > MAX_DECIMALS {
            return None;
        }
        let denominator = 10u64.pow(decimals);
        let numerator = (f64::from(dt) * denominator as f64).round() as u64;
        Some(Self { numerator, denominator })
    }

    /// The step in seconds.
    #[must_use]
    pub fn seconds(self) -> f64 {
        self.numerator as f64 / self.denominator as f64
    }

    /// `steps` steps as an exact fraction, reduced: `(numerator, denominator)`.
    #[must_use]
    pub fn times(self, steps: u64) -> (u64, u64) {
        let numerator = self.numerator.saturating_mul(steps);
        let common = gcd(numerator, self.denominator).max(1);
        (numerator / common, self.denominator / common)
    }

    /// Decimals enough to tell each step's time from the next, and no more: exact for
    /// a decimal step, four past the step's first digit for a rate (0.0208333 at 240 Hz).
    #[must_use]
    pub fn decimals(self) -> u32 {
        let mut denominator = self.denominator;
        let mut decimals = 0;
        while denominator > 1 && denominator.is_multiple_of(10) {
            denominator /= 10;
            decimals += 1;
        }
        if denominator == 1 {
            return decimals;
        }
        (self.denominator as f64 / self.numerator as f64).log10().ceil() as u32 + 4
    }

    /// `t` rounded to [`Self::decimals`] places: printed by serde or `{}` it comes out
    /// as that short decimal.
    #[must_use]
    pub fn round(self, t: f64) -> f64 {
        round_to(t, self.decimals())
    }

    /// The time after `steps` steps of this one from `origin` (s), rounded to the
    /// decimals both need: 37 steps of 1/240 s then 2 of 0.1 s is 0.3541667.
    #[must_use]
    pub fn time_from(self, origin: Origin, steps: u64) -> f64 {
        let (c, d) = self.times(steps);
        match origin {
            Origin::Steps(start, done) => {
                // a/b + c/d as one exact fraction, divided once.
                let (a, b) = start.times(done);
                let (a, b, c, d) = (u128::from(a), u128::from(b), u128::from(c), u128::from(d));
                let (numerator, denominator) = (a * d + c * b, b * d);
                let common = gcd128(numerator, denominator).max(1);
                let t = (numerator / common) as f64 / (denominator / common) as f64;
                round_to(t, self.decimals().max(start.decimals()))
            }
            // Seven decimals keep what an f32 step's sum carries of the start.
            Origin::Time(start) => round_to(start + c as f64 / d as f64, self.decimals().max(7)),
        }
    }

    /// The time after `steps` steps from `start` (s), rounded as [`Self::round`] does.
    #[must_use]
    pub fn time_after(self, start: f64, steps: u64) -> f64 {
        let (numerator, denominator) = self.times(steps);
        self.round(start + numerator as f64 / denominator as f64)
    }
}

/// Where the times a run prints start from: a world's time as the steps it took, when
/// they were all one step ([`Step::of`] knows), or else as the world keeps it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Origin {
    /// `u64` steps of this step from 0.
    Steps(Step, u64),
    /// A time (s).
    Time(f64),
}

impl Origin {
    /// The origin of a world at `time` after `steps` steps, taken at `dt` if its time
    /// says so (to the f32 sum's rounding).
    #[must_use]
    pub fn of(dt: f32, time: f64, steps: u64) -> Self {
        if let Some(step) = Step::of(dt) {
            let from_zero = step.seconds() * steps as f64;
            if (from_zero - time).abs() <= 1e-5 * time.max(1.0) {
                return Self::Steps(step, steps);
            }
        }
        Self::Time(time)
    }
}

/// `t` rounded to `decimals` places (at most 12).
fn round_to(t: f64, decimals: u32) -> f64 {
    let scale = 10f64.powi(decimals.min(MAX_DECIMALS) as i32);
    let rounded = (t * scale).round() / scale;
    if rounded.is_finite() { rounded } else { t }
}

/// `t` to 7 significant digits, about what an `f32` step carries: for a step too fine
/// for [`Step::of`].
#[must_use]
pub fn to_f32_digits(t: f64) -> f64 {
    format!("{t:.6e}").parse().unwrap_or(t)
}

/// A decimal when it is one (`0.003`), else the fraction (`1/240`, `7/240`).
impl std::fmt::Display for Step {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if !is_power_of_ten(self.denominator) {
            write!(f, "{}/{}", self.numerator, self.denominator)
        } else {
            write!(f, "{}", self.seconds())
        }
    }
}

/// 1, 10, 100, ...
#[must_use]
pub fn is_power_of_ten(mut n: u64) -> bool {
    while n > 1 && n.is_multiple_of(10) {
        n /= 10;
    }
    n == 1
}

fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

fn gcd128(mut a: u128, mut b: u128) -> u128 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rate_in_hz_is_recognised() {
        assert_eq!(Step::of(1.0 / 240.0).unwrap(), Step { numerator: 1, denominator: 240 });
        assert_eq!(Step::of(1.0 / 60.0).unwrap(), Step { numerator: 1, denominator: 60 });
        assert_eq!(Step::of(0.01).unwrap(), Step { numerator: 1, denominator: 100 });
    }

    #[test]
    fn a_typed_decimal_is_kept() {
        assert_eq!(Step::of(0.003).unwrap(), Step { numerator: 3, denominator: 1000 });
        assert_eq!(Step::of(0.0025).unwrap(), Step { numerator: 1, denominator: 400 });
        assert_eq!(Step::of(0.75).unwrap(), Step { numerator: 75, denominator: 100 });
    }

    #[test]
    fn times_print_as_short_decimals() {
        let step = Step::of(1.0 / 240.0).unwrap();
        assert_eq!(step.time_after(0.0, 5).to_string(), "0.0208333");
        assert_eq!(step.time_after(0.0, 240).to_string(), "1");
        assert_eq!(step.time_after(0.0, 240 * 3600 + 1).to_string(), "3600.0041667");
        let step = Step::of(0.01).unwrap();
        assert_eq!(step.time_after(0.0, 30).to_string(), "0.3");
        assert_eq!(Step::of(0.003).unwrap().time_after(0.0, 7).to_string(), "0.021");
        assert_eq!(serde_json::to_string(&step.time_after(0.0, 3)).unwrap(), "0.03");
    }

    #[test]
    fn a_step_too_fine_for_decimals_is_none() {
        assert_eq!(Step::of(1e-20), None);
        assert_eq!(Step::of(0.0), None);
        assert_eq!(Step::of(f32::NAN), None);
        let t = to_f32_digits(f64::from(1e-20f32) * 3.0);
        assert_eq!(serde_json::to_string(&t).unwrap(), "3e-20");
    }

    #[test]
    fn a_step_reads_as_people_write_it() {
        assert_eq!(Step::of(1.0 / 240.0).unwrap().to_string(), "1/240");
        assert_eq!(Step::of(1.0 / 60.0).unwrap().to_string(), "1/60");
        assert_eq!(Step::of(0.01).unwrap().to_string(), "0.01");
        assert_eq!(Step::of(0.003).unwrap().to_string(), "0.003");
        assert_eq!(Step::of(1.0).unwrap().to_string(), "1");
        assert_eq!(Step { numerator: 7, denominator: 240 }.to_string(), "7/240");
    }

    #[test]
    fn times_go_on_from_where_the_world_is_at_another_rate() {
        let start = Origin::of(1.0 / 240.0, f64::from(37.0f32 / 240.0), 37);
        assert_eq!(start, Origin::Steps(Step { numerator: 1, denominator: 240 }, 37));
        let tenth = Step::of(0.1).unwrap();
        assert_eq!(tenth.time_from(start, 0).to_string(), "0.1541667");
        assert_eq!(tenth.time_from(start, 2).to_string(), "0.3541667");
        assert_eq!(Step::of(1.0).unwrap().time_from(start, 2).to_string(), "2.1541667");
        let rate = Step::of(1.0 / 240.0).unwrap();
        assert_eq!(rate.time_from(start, 3), rate.time_after(0.0, 40), "one rate: an unbroken run's times");
        let mixed = Origin::of(0.1, 0.25416667, 38);
        assert_eq!(mixed, Origin::Time(0.25416667));
        assert_eq!(tenth.time_from(mixed, 1).to_string(), "0.3541667");
    }

    #[test]
    fn a_frame_interval_is_an_exact_fraction() {
        assert_eq!(Step::of(1.0 / 240.0).unwrap().times(8), (1, 30));
        assert_eq!(Step::of(0.003).unwrap().times(10), (3, 100));
    }
}
