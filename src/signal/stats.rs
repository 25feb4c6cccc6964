//! Statistics of samples that may hold NaN (a frame where nothing was measured).

/// The median of the values that are not NaN: the middle one of an odd
/// count, the mean of the two middle ones of an even count; NaN when every
/// value is NaN or there are none. The summary statistic of `embusen eval`.
pub fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => nth_smallest(&mut v, n / 2),
        n => {
            let upper = nth_smallest(&mut v, n / 2);
            0.5 * (largest(&v[..n / 2]) + upper)
        }
    }
}

/// The `q` quantile (0 to 1) of the values that are not NaN, linear between
/// the sorted samples (numpy's default: sample `k` is the `k / (n − 1)`
/// quantile); NaN when there are none. `quantile(v, 0.5)` is [`median`].
pub fn quantile(values: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
    if v.is_empty() || q.is_nan() {
        return f64::NAN;
    }
    let at = q.clamp(0.0, 1.0) * (v.len() - 1) as f64;
    let below = at.floor() as usize;
    let below_value = nth_smallest(&mut v, below);
    let above_value = if below + 1 < v.len() { smallest(&v[below + 1..]) } else { below_value };
    below_value + (above_value - below_value) * (at - below as f64)
}

/// The upper median of the finite values: the middle one of an odd count,
/// the upper of the two middle ones of an even count, so always one of the
/// samples; 0 when none is finite. The translation methods use it for levels
/// (the floor, a foot's flat height), where a level that was really measured
/// is wanted rather than an average of two.
pub fn upper_median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    let middle = v.len() / 2;
    nth_smallest(&mut v, middle)
}

// Order statistics by selection, not by sorting: linear time, and one
// selection's code in the wasm module instead of a sort's.

/// The `k`-th smallest of `v` (from 0), in `f64::total_cmp`'s order; `v` is
/// left with everything before index `k` no larger and everything after it
/// no smaller. `k` must be within `v`.
fn nth_smallest(v: &mut [f64], k: usize) -> f64 {
    *v.select_nth_unstable_by(k, f64::total_cmp).1
}

/// The largest of `v` (not empty) in `f64::total_cmp`'s order.
fn largest(v: &[f64]) -> f64 {
    v.iter().copied().max_by(f64::total_cmp).unwrap_or(f64::NAN)
}

/// The smallest of `v` (not empty) in `f64::total_cmp`'s order.
fn smallest(v: &[f64]) -> f64 {
    v.iter().copied().min_by(f64::total_cmp).unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_of_odd_even_and_empty_samples() {
        assert_eq!(median(&[3.0, f64::NAN, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[f64::NAN]).is_nan());
        assert_eq!(upper_median(&[4.0, 1.0, 3.0, 2.0]), 3.0);
        assert_eq!(upper_median(&[f64::INFINITY, 5.0, f64::NAN]), 5.0);
        assert_eq!(upper_median(&[]), 0.0);
    }

    /// Selection gives what sorting gives, bit for bit, over many samples
    /// with repeats, signed zeros and infinities.
    #[test]
    fn order_statistics_are_the_sorted_samples() {
        let mut seed = 12345_u64;
        for n in 1..60 {
            let v: Vec<f64> = (0..n)
                .map(|_| {
                    seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                    match seed >> 60 {
                        0 => -0.0,
                        1 => 0.0,
                        2 => f64::INFINITY,
                        k => (k as f64 - 8.0) * 0.5,
                    }
                })
                .collect();
            let mut sorted = v.clone();
            sorted.sort_by(f64::total_cmp);
            let expected = if n % 2 == 1 { sorted[n / 2] } else { 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]) };
            assert_eq!(median(&v).to_bits(), expected.to_bits(), "median of {v:?}");
            for q in [0.0, 0.1, 0.25, 0.5, 0.9, 1.0] {
                let at = q * (n - 1) as f64;
                let (below, above) = (at.floor() as usize, (at.floor() as usize + 1).min(n - 1));
                let expected = sorted[below] + (sorted[above] - sorted[below]) * (at - below as f64);
                let got = quantile(&v, q);
                assert!(
                    got.to_bits() == expected.to_bits() || (got.is_nan() && expected.is_nan()),
                    "q {q} of {v:?}"
                );
            }
        }
    }

    #[test]
    fn quantiles_lie_between_the_sorted_samples() {
        let v = [4.0, 1.0, f64::NAN, 3.0, 2.0, 5.0];
        assert_eq!(quantile(&v, 0.0), 1.0);
        assert_eq!(quantile(&v, 1.0), 5.0);
        assert_eq!(quantile(&v, 0.5), median(&v));
        assert!((quantile(&v, 0.9) - 4.6).abs() < 1e-12);
        assert!(quantile(&[], 0.9).is_nan());
    }
}
