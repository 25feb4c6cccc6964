//! Gaussian smoothing of per-frame signals: an exact port of the R `smoother`
//! package that RMoCap uses (its window formula and zeroed tails), a cleaner
//! variant whose kernel is renormalised at the edges, and paths smoothed with
//! their ends extended by point reflection.

use glam::DVec3;

/// The Gaussian window of R `smoother` (`makeWindow` in `smth.gaussian`),
/// normalised to sum 1: for `k` in `0..window_len`, with `hw = window_len / 2`
/// (not rounded) and `m = k - trunc(hw)`, the weight is `e^(-0.5 (alpha m / hw)²)`.
///
/// `window_len` must be at least 1.
pub fn r_gaussian_kernel(window_len: usize, alpha: f64) -> Vec<f64> {
    let hw = (window_len as f64 / 2.0).abs();
    let alpha = alpha.abs();
    // R's `as.integer` truncates; `hw` is positive so `as` does the same.
    let hw_int = hw as i64;
    let weights: Vec<f64> = (0..window_len)
        .map(|k| {
            let m = k as i64 - hw_int;
            let t = alpha * m as f64 / hw;
            // R evaluates `e^k` with `e = exp(1)` through C `pow`, and `x^2` as `x * x`;
            // doing the same (through the `libm` crate, so every target agrees)
            // keeps the kernel within an ulp of R's.
            libm::pow(std::f64::consts::E, -0.5 * (t * t))
        })
        .collect();
    // R's `sum` accumulates in long double; a compensated sum gets the same
    // correctly rounded total for these few positive terms.
    let total = compensated_sum(&weights);
    weights.into_iter().map(|w| w / total).collect()
}

/// Neumaier's compensated sum: close to the correctly rounded sum of `values`.
fn compensated_sum(values: &[f64]) -> f64 {
    let mut sum = 0.0_f64;
    let mut compensation = 0.0_f64;
    for &v in values {
        let t = sum + v;
        if sum.abs() >= v.abs() {
            compensation += (sum - t) + v;
        } else {
            compensation += (v - t) + sum;
        }
        sum = t;
    }
    sum + compensation
}

/// The window length, in samples, that R `smoother` derives from `window`
/// for a signal of `len` samples (`.determineWindowLength`): a `window` strictly
/// between 0 and 1 is a fraction of `len`, anything else a count; the result is
/// `trunc(max(|w|, 1))`. Errors when it is not shorter than the signal, as R does.
pub fn r_window_length(len: usize, window: f64) -> Result<usize, String> {
    let mut w = window;
    if w > 0.0 && w < 1.0 {
        // The same f64 product as R's `w * l`: with `window = 100 / n` it is
        // 100 for most `n` but 99.99999999999999 (so 99 samples) for some.
        w *= len as f64;
    }
    // R's `max` propagates NaN (and then fails); Rust's `f64::max` would drop it.
    let w = if w.is_nan() { w } else { w.abs().max(1.0) };
    if !w.is_finite() || w >= i32::MAX as f64 {
        return Err(format!("smoothing window {window} gives no usable window length"));
    }
    let window_len = w as usize;
    if len <= window_len {
        return Err(format!(
            "a smoothing window of {window_len} samples needs more than {window_len} frames, found {len}"
        ));
    }
    Ok(window_len)
}

/// Exactly what RMoCap computes with R
/// `smoother::smth.gaussian(x, window = window_fraction, alpha = alpha, tails = FALSE)`
/// followed by `zz[is.na(zz)] <- 0`.
///
/// With `w` = [`r_window_length`]`(x.len(), window_fraction)`, `left = w / 2`
/// (integer division) and `right = w - left`, output `i` (0-based) is
/// `Σ_k x[i - left + k] · kernel[k]` over the [`r_gaussian_kernel`] for
/// `left <= i < len - right`, and 0 elsewhere (R's NA tails; when `left` is 0,
/// R's `1:0` also blanks the first sample, and so do we).
///
/// Errors when the window is not shorter than `x`, or is not finite.
pub fn smooth_r_gaussian(x: &[f64], window_fraction: f64, alpha: f64) -> Result<Vec<f64>, String> {
    let n = x.len();
    let window_len = r_window_length(n, window_fraction)?;
    let kernel = r_gaussian_kernel(window_len, alpha);
    let left = window_len / 2;
    let right = window_len - left;
    let mut out = vec![0.0; n];
    // R renormalises the kernel where it overhangs the signal, but those
    // outputs are exactly the tails it then replaces by NA (then 0), so only
    // the full-window middle is computed.
    for (i, y) in out.iter_mut().enumerate().take(n - right).skip(left) {
        let data = &x[i - left..i - left + window_len];
        // Sequential sum, as R's `%*%` (BLAS dgemv) on a 1-row matrix.
        *y = data.iter().zip(&kernel).fold(0.0, |acc, (d, k)| acc + d * k);
    }
    if left == 0 {
        out[0] = 0.0;
    }
    Ok(out)
}

/// Gaussian smoothing without R's zeroed tails: each output is the weighted
/// mean of the samples within `window_samples / 2` (rounded down) on either
/// side, with weights `exp(-0.5 (d / sigma)²)` at distance `d` samples and
/// `sigma = window_samples / (2 alpha)` — the same bell as
/// [`smooth_r_gaussian`], but centred on the sample. Near the ends the part of
/// the kernel that overhangs the signal is dropped and the rest renormalised,
/// so a constant signal stays constant everywhere.
///
/// Returns `x` unchanged when the window is under 2 samples or `alpha` is not
/// a positive finite number (there is then nothing to smooth with).
pub fn smooth_gaussian_clean(x: &[f64], window_samples: f64, alpha: f64) -> Vec<f64> {
    let n = x.len();
    let sigma = window_samples / (2.0 * alpha);
    if !(window_samples >= 2.0 && sigma.is_finite() && sigma > 0.0) || n == 0 {
        return x.to_vec();
    }
    // `window_samples >= 2` and finite, so at least 1; capped by the signal
    // length since a longer kernel would only be truncated anyway.
    let half = ((window_samples / 2.0) as usize).min(n - 1);
    let kernel: Vec<f64> = (0..=2 * half)
        .map(|k| {
            let d = (k as f64 - half as f64) / sigma;
            libm::exp(-0.5 * d * d)
        })
        .collect();
    let full_sum: f64 = kernel.iter().sum();
    (0..n)
        .map(|i| {
            // Kernel index k covers sample i + k - half.
            let k_start = half.saturating_sub(i);
            let k_end = (2 * half + 1).min(n + half - i);
            let first_sample = i + k_start - half;
            let weights = &kernel[k_start..k_end];
            let data = &x[first_sample..first_sample + weights.len()];
            let dot: f64 = data.iter().zip(weights).map(|(d, w)| d * w).sum();
            if weights.len() == kernel.len() { dot / full_sum } else { dot / weights.iter().sum::<f64>() }
        })
        .collect()
}

/// A path smoothed by a Gaussian of standard deviation `sigma_samples`
/// (kernel out to 2.5 sigma, as [`smooth_gaussian_clean`] weighs it). Before
/// smoothing, each end is extended by its point reflection (`2 p[0] - p[k]`),
/// so a body moving in a straight line at constant speed keeps exactly that
/// speed up to the first and last frame; the renormalised kernel alone would
/// slow it there. `stride` paths are interleaved frame by frame in `points`
/// (point `k` of frame `f` at `f * stride + k`) and each is smoothed on its own.
pub fn smooth_paths(points: &[DVec3], stride: usize, sigma_samples: f64) -> Vec<DVec3> {
    let alpha = 2.5;
    let window = 2.0 * alpha * sigma_samples;
    let mut out = points.to_vec();
    let n = points.len().checked_div(stride).unwrap_or(0);
    if n < 2 || window.is_nan() || window < 2.0 {
        return out;
    }
    let half = ((window / 2.0) as usize).min(n - 1);
    for k in 0..stride {
        for axis in 0..3 {
            let at = |f: usize| points[f * stride + k][axis];
            let mut series = Vec::with_capacity(n + 2 * half);
            series.extend((1..=half).rev().map(|d| 2.0 * at(0) - at(d)));
            series.extend((0..n).map(at));
            series.extend((1..=half).map(|d| 2.0 * at(n - 1) - at(n - 1 - d)));
            for (f, v) in smooth_gaussian_clean(&series, window, alpha)[half..half + n].iter().enumerate() {
                out[f * stride + k][axis] = *v;
            }
        }
    }
    out
}

/// Point `f` of the `k`-th of the `stride` paths interleaved in `points` (as
/// in [`smooth_paths`]) smoothed by a Gaussian of `sigma_samples`, out to 2.5
/// of them, the path's ends extended by point reflection. One frame at a
/// time, for widths that change from frame to frame.
pub fn smoothed_point(points: &[DVec3], stride: usize, k: usize, f: usize, sigma_samples: f64) -> DVec3 {
    let last = points.len() / stride - 1;
    let at = |g: i64| -> DVec3 {
        let point = |g: usize| points[g * stride + k];
        match usize::try_from(g) {
            Err(_) => 2.0 * point(0) - point(g.unsigned_abs().min(last as u64) as usize),
            Ok(g) if g > last => 2.0 * point(last) - point((2 * last).saturating_sub(g)),
            Ok(g) => point(g),
        }
    };
    let half = (2.5 * sigma_samples) as i64;
    let (mut sum, mut weights) = (DVec3::ZERO, 0.0);
    for d in -half..=half {
        // `libm`, not the platform's `exp`: the browser and the CLI weigh
        // to the same bit.
        let t = d as f64 / sigma_samples;
        let w = libm::exp(-0.5 * t * t);
        sum += at(f as i64 + d) * w;
        weights += w;
    }
    sum / weights
}

/// `points` (as in [`smooth_paths`]) smoothed by `sigma_samples`, and at each
/// frame `f` where `wider_samples[f]` is wider, by that instead
/// ([`smoothed_point`]).
pub fn smooth_paths_wider_where(
    points: &[DVec3],
    stride: usize,
    sigma_samples: f64,
    wider_samples: &[f64],
) -> Vec<DVec3> {
    let mut out = smooth_paths(points, stride, sigma_samples);
    for (f, &wider) in wider_samples.iter().enumerate().take(points.len() / stride.max(1)) {
        if wider > sigma_samples {
            for k in 0..stride {
                out[f * stride + k] = smoothed_point(points, stride, k, f, wider);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smoothing_a_path_keeps_a_straight_line_to_its_ends() {
        let line: Vec<DVec3> = (0..20).map(|f| DVec3::new(3.0 * f as f64, 1.0, -0.5 * f as f64)).collect();
        let smoothed = smooth_paths(&line, 1, 3.0);
        for (a, b) in line.iter().zip(&smoothed) {
            assert!((*a - *b).length() < 1e-9, "{a} vs {b}");
        }
        // Two interleaved paths are smoothed each on its own; a kink is rounded.
        let kinked: Vec<DVec3> =
            (0..40).flat_map(|f| [DVec3::ZERO, DVec3::splat((f as f64 - 20.0).abs())]).collect();
        let smoothed = smooth_paths(&kinked, 2, 3.0);
        assert!(smoothed.iter().step_by(2).all(|p| *p == DVec3::ZERO));
        assert!(smoothed[2 * 20 + 1].x > 1.0);
        assert_eq!(smooth_paths(&kinked, 2, 0.2), kinked);
    }

    #[test]
    fn a_path_is_smoothed_wider_only_where_asked() {
        // A zigzag: smoothing flattens it, more where wider.
        let zigzag: Vec<DVec3> = (0..40).map(|f| DVec3::new(f as f64, 0.0, (f % 2) as f64)).collect();
        let mut wider = vec![0.0; 40];
        wider[20] = 3.0;
        let smoothed = smooth_paths_wider_where(&zigzag, 1, 1.0, &wider);
        let base = smooth_paths(&zigzag, 1, 1.0);
        for f in (0..40).filter(|&f| f != 20) {
            assert_eq!(smoothed[f], base[f]);
        }
        assert!(
            (smoothed[20].z - 0.5).abs() < (base[20].z - 0.5).abs() / 3.0,
            "{} {}",
            smoothed[20],
            base[20]
        );
        // A straight line keeps to itself at any width, to its ends.
        let line: Vec<DVec3> = (0..30).map(|f| DVec3::new(2.0 * f as f64, 0.0, -f as f64)).collect();
        for f in 0..30 {
            assert!((smoothed_point(&line, 1, 0, f, 4.0) - line[f]).length() < 1e-9);
        }
    }

    #[test]
    fn kernel_sums_to_one_and_is_symmetric_for_odd_length() {
        for len in [1, 2, 5, 99, 100, 101] {
            let k = r_gaussian_kernel(len, 2.5);
            assert_eq!(k.len(), len);
            assert!((k.iter().sum::<f64>() - 1.0).abs() < 1e-14, "len {len}");
        }
        let k = r_gaussian_kernel(99, 2.5);
        for i in 0..99 {
            assert_eq!(k[i], k[98 - i]);
        }
        // Even length: the peak is at index len/2, one past the middle.
        let k = r_gaussian_kernel(100, 2.5);
        let peak = (0..100).max_by(|&a, &b| k[a].total_cmp(&k[b])).unwrap();
        assert_eq!(peak, 50);
        // The edge weight of R's window is e^(-alpha²/2) times the peak.
        assert!((k[0] / k[50] - (-0.5 * 2.5f64 * 2.5).exp()).abs() < 1e-12);
    }

    #[test]
    fn constant_stays_constant_in_the_middle_and_tails_are_zero() {
        let x = vec![3.5; 400];
        let y = smooth_r_gaussian(&x, 100.0 / 400.0, 2.5).unwrap();
        assert!(y[..50].iter().all(|&v| v == 0.0));
        assert!(y[350..].iter().all(|&v| v == 0.0));
        assert!(y[50..350].iter().all(|&v| (v - 3.5).abs() < 1e-12));
    }

    #[test]
    fn window_of_99_when_the_fraction_rounds_down() {
        // (100 / 161) * 161 is 99.99999999999999 in f64, so R uses 99 samples.
        assert_eq!(r_window_length(161, 100.0 / 161.0), Ok(99));
        assert_eq!(r_window_length(2600, 100.0 / 2600.0), Ok(100));
        let x: Vec<f64> = (0..161).map(|i| i as f64).collect();
        let y = smooth_r_gaussian(&x, 100.0 / 161.0, 2.5).unwrap();
        // 99 samples: 49 zeros on the left, 50 on the right; a symmetric
        // kernel leaves a ramp unchanged.
        assert_eq!(y[48], 0.0);
        assert!((y[49] - 49.0).abs() < 1e-9);
        assert!((y[110] - 110.0).abs() < 1e-9);
        assert_eq!(y[111], 0.0);
        // 100 samples: 50 zeros on each side.
        let x: Vec<f64> = (0..300).map(|i| i as f64).collect();
        let y = smooth_r_gaussian(&x, 100.0 / 300.0, 2.5).unwrap();
        assert_eq!(y[49], 0.0);
        assert!(y[50] != 0.0 && y[249] != 0.0);
        assert_eq!(y[250], 0.0);
    }

    #[test]
    fn too_short_for_the_window() {
        assert!(smooth_r_gaussian(&[1.0; 100], 100.0, 2.5).is_err());
        assert!(smooth_r_gaussian(&[1.0; 101], 100.0, 2.5).is_ok());
        assert!(smooth_r_gaussian(&[1.0; 10], f64::NAN, 2.5).is_err());
        assert!(smooth_r_gaussian(&[], 0.5, 2.5).is_err());
    }

    #[test]
    fn window_of_one_sample_copies_but_blanks_both_ends() {
        // A fraction of exactly 1 is taken as a count of 1 sample (R's rule);
        // R's `1:0` then blanks the first sample as well as the last.
        let x = [4.0, 5.0, 6.0, 7.0];
        assert_eq!(smooth_r_gaussian(&x, 1.0, 2.5), Ok(vec![0.0, 5.0, 6.0, 0.0]));
    }

    #[test]
    fn clean_mode_has_no_zeros_at_the_edges() {
        let x = vec![2.0; 300];
        let y = smooth_gaussian_clean(&x, 100.0, 2.5);
        assert!(y.iter().all(|&v| (v - 2.0).abs() < 1e-12));
        // A ramp stays a ramp where the window fits.
        let x: Vec<f64> = (0..300).map(|i| i as f64).collect();
        let y = smooth_gaussian_clean(&x, 100.0, 2.5);
        assert!((y[150] - 150.0).abs() < 1e-9);
        assert!(y[0] > 0.0 && y[299] < 299.0);
        // Degenerate windows leave the signal alone.
        assert_eq!(smooth_gaussian_clean(&x, 1.0, 2.5), x);
        assert_eq!(smooth_gaussian_clean(&x, 100.0, 0.0), x);
        // A window longer than the signal still works.
        assert_eq!(smooth_gaussian_clean(&[1.0, 1.0, 1.0], 100.0, 2.5), vec![1.0; 3]);
    }

    #[test]
    fn clean_matches_r_in_the_middle_for_odd_windows() {
        // Odd R windows are centred, so both smoothers agree away from the ends.
        let x: Vec<f64> = (0..500).map(|i| (i as f64 * 0.1).sin()).collect();
        let r = smooth_r_gaussian(&x, 99.0, 2.5).unwrap();
        let c = smooth_gaussian_clean(&x, 99.0, 2.5);
        for i in 49..450 {
            assert!((r[i] - c[i]).abs() < 1e-12, "{i}: {} vs {}", r[i], c[i]);
        }
    }
}
