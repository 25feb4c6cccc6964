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
}
