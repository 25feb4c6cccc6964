//! Deterministic random numbers for the recordings made in code, without a
//! dependency: the same seed gives the same numbers on every target (the
//! Gaussian goes through `libm`, like the rest of the core).

/// Marsaglia's xorshift64. The state must not be 0 (it would stay 0).
#[derive(Clone, Debug)]
pub struct XorShift64(pub u64);

impl XorShift64 {
    fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }

    /// Uniform in [-1, 1).
    pub fn symmetric(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// Uniform in (0, 1].
    fn unit_open_at_zero(&mut self) -> f64 {
        ((self.next_u64() >> 11) + 1) as f64 / (1u64 << 53) as f64
    }

    /// Standard normal (Box–Muller, one of the pair).
    pub fn gaussian(&mut self) -> f64 {
        let radius = libm::sqrt(-2.0 * libm::log(self.unit_open_at_zero()));
        let angle = std::f64::consts::TAU * self.unit_open_at_zero();
        radius * libm::cos(angle)
    }
}

/// A well-mixed generator state from any number (SplitMix64's output, as
/// Vigna recommends for seeding xorshift): the state is used as it is
/// given, and a small one is poorly mixed for the first draws: from the
/// states 1 to 12 the first [`XorShift64::gaussian`] lies between 6.6
/// deviations below the mean and 6.3 above it, every one but two beyond
/// ±2.4. Never 0 (a xorshift state must not be).
pub fn mixed_state(seed: u64) -> u64 {
    let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    (z ^ (z >> 31)).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_seeds_draw_alike_only_once_mixed() {
        let first = |state: u64| XorShift64(state).gaussian();
        let raw: Vec<f64> = (1..=12).map(first).collect();
        assert!(raw.iter().filter(|g| g.abs() > 2.4).count() >= 10, "{raw:?}");
        let mixed: Vec<f64> = (1..=1000).map(|seed| first(mixed_state(seed))).collect();
        let mean = mixed.iter().sum::<f64>() / mixed.len() as f64;
        let beyond = mixed.iter().filter(|g| g.abs() > 2.4).count();
        assert!(mean.abs() < 0.1 && beyond < 40, "mean {mean}, {beyond} beyond 2.4");
    }

    #[test]
    fn gaussian_has_unit_deviation() {
        let mut rng = XorShift64(0x1234_5678_9ABC_DEF1);
        let n = 200_000;
        let samples: Vec<f64> = (0..n).map(|_| rng.gaussian()).collect();
        let mean = samples.iter().sum::<f64>() / n as f64;
        let variance = samples.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.01 && (variance.sqrt() - 1.0).abs() < 0.01, "{mean} {variance}");
    }
}
