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

#[cfg(test)]
mod tests {
    use super::*;

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
