//! Statistics of samples that may hold NaN (a frame where nothing was measured).

/// The median of the values that are not NaN: the middle one of an odd
/// count, the mean of the two middle ones of an even count; NaN when every
/// value is NaN or there are none. The summary statistic of `embusen eval`.
pub fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
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
    v.sort_by(f64::total_cmp);
    let at = q.clamp(0.0, 1.0) * (v.len() - 1) as f64;
    let below = at.floor() as usize;
    let above = (below + 1).min(v.len() - 1);
    v[below] + (v[above] - v[below]) * (at - below as f64)
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
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
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
