//! The small dense solvers of the camera's calibrations: symmetric
//! eigenvectors (cyclic Jacobi), linear solves (Cholesky for positive
//! definite systems, Gaussian elimination for the rest), and one
//! Levenberg–Marquardt minimiser of a sum of squared residuals.
//!
//! They are written here rather than pulled in: the problems have at most a
//! few dozen unknowns, and the core must build for wasm lean.
//!
//! The minimiser has one damping policy, Marquardt's (see [`minimise`]),
//! for the board's calibration and the four floor corners' alike: the
//! rules are about the arithmetic of a damped Gauss–Newton step, not about
//! either problem.

/// Eigenvalues and eigenvectors (`vectors[i*n..(i+1)*n]` belongs to
/// `values[i]`) of the symmetric `n × n` matrix `a` (row major), by cyclic
/// Jacobi rotations.
pub fn symmetric_eigen(a: &[f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut a = a.to_vec();
    let mut v = vec![0.0; n * n];
    for i in 0..n {
        v[i * n + i] = 1.0;
    }
    let scale = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    for _ in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i * n + j].powi(2))
            .sum();
        if off.is_nan() || off.sqrt() <= 1e-15 * scale {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = a[p * n + q];
                if apq == 0.0 {
                    continue;
                }
                let theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let (akp, akq) = (a[k * n + p], a[k * n + q]);
                    a[k * n + p] = c * akp - s * akq;
                    a[k * n + q] = s * akp + c * akq;
                }
                for k in 0..n {
                    let (apk, aqk) = (a[p * n + k], a[q * n + k]);
                    a[p * n + k] = c * apk - s * aqk;
                    a[q * n + k] = s * apk + c * aqk;
                }
                for k in 0..n {
                    let (vkp, vkq) = (v[k * n + p], v[k * n + q]);
                    v[k * n + p] = c * vkp - s * vkq;
                    v[k * n + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    let values = (0..n).map(|i| a[i * n + i]).collect();
    // Columns of v are the eigenvectors; hand them out as rows.
    let vectors = (0..n).flat_map(|i| (0..n).map(move |k| (i, k))).map(|(i, k)| v[k * n + i]).collect();
    (values, vectors)
}

/// `x` with `a x = b` for a symmetric positive definite `a` (row major,
/// `n × n`), by Cholesky; `None` when `a` is not positive definite.
pub fn solve_positive(a: &[f64], b: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let sum: f64 = a[i * n + j] - (0..j).map(|k| l[i * n + k] * l[j * n + k]).sum::<f64>();
            if i == j {
                if sum.is_nan() || sum <= 0.0 {
                    return None;
                }
                l[i * n + i] = sum.sqrt();
            } else {
                l[i * n + j] = sum / l[j * n + j];
            }
        }
    }
    let mut y = vec![0.0; n];
    for i in 0..n {
        y[i] = (b[i] - (0..i).map(|k| l[i * n + k] * y[k]).sum::<f64>()) / l[i * n + i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        x[i] = (y[i] - (i + 1..n).map(|k| l[k * n + i] * x[k]).sum::<f64>()) / l[i * n + i];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// `x` with `a x = b` for `a` (row major, `n × n`), by Gaussian elimination
/// with partial pivoting; `None` when `a` is singular to working precision
/// (a pivot below 1e-14 of the largest diagonal entry).
pub fn solve_pivoting(a: &[f64], b: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut a: Vec<Vec<f64>> = (0..n).map(|i| a[i * n..(i + 1) * n].to_vec()).collect();
    let mut b = b[..n].to_vec();
    let scale = (0..n).map(|i| a[i][i].abs()).fold(0.0, f64::max);
    for col in 0..n {
        let pivot = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        let size = a[pivot][col].abs();
        if size.is_nan() || size <= 1e-14 * scale {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let (above, below) = a.split_at_mut(col + 1);
        let pivot_row = &above[col];
        for (offset, row) in below[..n - col - 1].iter_mut().enumerate() {
            let factor = row[col] / pivot_row[col];
            for (value, pivot_value) in row[col..n].iter_mut().zip(&pivot_row[col..n]) {
                *value -= factor * pivot_value;
            }
            b[col + 1 + offset] -= factor * b[col];
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let known: f64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - known) / a[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// A least-squares problem for [`minimise`]: a state, its residuals, the
/// normal equations of their linearisation, and a step.
pub trait LeastSquares {
    /// What is being fitted: a vector of unknowns, or a pose moved on its
    /// manifold.
    type State: Clone;
    /// The number of unknowns of a step.
    fn unknowns(&self) -> usize;
    /// The residuals at `state`; `None` where they cannot be evaluated (a
    /// point behind the camera, a focal length that is not positive): a
    /// step there is refused.
    fn residuals(&self, state: &Self::State) -> Option<Vec<f64>>;
    /// `(JᵀJ, Jᵀr)` at `state` with its `residuals` `r`, `JᵀJ` row major.
    fn normal_equations(&self, state: &Self::State, residuals: &[f64]) -> (Vec<f64>, Vec<f64>);
    /// `state` moved by a step `delta` of the unknowns.
    fn moved(&self, state: &Self::State, delta: &[f64]) -> Self::State;
}

/// The damping of the first step: a tenth of a percent of the curvature,
/// nearly Gauss–Newton, since both calibrations start from a closed-form
/// answer already near the least.
const FIRST_DAMPING: f64 = 1e-3;

/// After a better step the damping is divided by this, after a worse one
/// (or a damped system that cannot be solved) multiplied by it: Marquardt's
/// factor ten, so that a few tries span the many decades between a
/// Gauss–Newton step and a short gradient step.
const DAMPING_FACTOR: f64 = 10.0;

/// The damping is never divided below this: at 1e-12 of the curvature the
/// step is the Gauss–Newton step to working precision.
const LEAST_DAMPING: f64 = 1e-12;

/// The damping at which a worse step ends the minimisation: the step is
/// then a millionth of a millionth of a gradient step, below what `f64` can
/// still move the state by.
const MOST_DAMPING: f64 = 1e12;

/// Each diagonal entry is damped in proportion to itself plus this fraction
/// of the largest (Marquardt's scaling, kept off zero): an unknown the
/// residuals do not see still gets a damped, finite step, and the damped
/// system stays positive definite for Cholesky.
const DIAGONAL_FLOOR: f64 = 1e-12;

/// A better step that lowers the cost by no more than this fraction of it
/// ends the minimisation: the cost is then settled to about the last four
/// of `f64`'s sixteen digits.
const LEAST_GAIN: f64 = 1e-12;

/// At most this many linearisations (each followed by as many damped tries
/// as it takes to find a better step): both calibrations converge in tens.
const MOST_LINEARISATIONS: usize = 200;

/// Levenberg–Marquardt on the sum of the squared residuals of `problem`
/// from `start`: the state reached and its residuals; `None` when the
/// residuals at `start` cannot be evaluated. One policy for every fit: the
/// damped normal equations solved by Cholesky, the damping ÷10 after a
/// better step and ×10 after a worse one (or a system that cannot be
/// solved) from 1e-3, until a better step gains no more than 1e-12 of the
/// cost, the damping reaches 1e12, or 200 linearisations.
pub fn minimise<P: LeastSquares>(problem: &P, start: P::State) -> Option<(P::State, Vec<f64>)> {
    let n = problem.unknowns();
    let cost_of = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>();
    let mut state = start;
    let mut r = problem.residuals(&state)?;
    let mut cost = cost_of(&r);
    let mut lambda = FIRST_DAMPING;
    let (mut jtj, mut jtr) = problem.normal_equations(&state, &r);
    let mut linearisations = 1;
    loop {
        let mut damped = jtj.clone();
        let largest = (0..n).map(|i| jtj[i * n + i]).fold(0.0, f64::max);
        for i in 0..n {
            damped[i * n + i] += lambda * (jtj[i * n + i] + DIAGONAL_FLOOR * largest);
        }
        let negative: Vec<f64> = jtr.iter().map(|x| -x).collect();
        let better = solve_positive(&damped, &negative, n).and_then(|delta| {
            let trial = problem.moved(&state, &delta);
            let trial_r = problem.residuals(&trial)?;
            let trial_cost = cost_of(&trial_r);
            (trial_cost < cost).then_some((trial, trial_cost, trial_r))
        });
        match better {
            Some((trial, trial_cost, trial_r)) => {
                let gain = (cost - trial_cost) / cost.max(1e-300);
                (state, cost, r) = (trial, trial_cost, trial_r);
                lambda = (lambda / DAMPING_FACTOR).max(LEAST_DAMPING);
                if gain.is_nan() || gain <= LEAST_GAIN || linearisations >= MOST_LINEARISATIONS {
                    break;
                }
                linearisations += 1;
                (jtj, jtr) = problem.normal_equations(&state, &r);
            }
            None => {
                lambda *= DAMPING_FACTOR;
                if lambda.is_nan() || lambda >= MOST_DAMPING {
                    break;
                }
            }
        }
    }
    Some((state, r))
}

/// A problem whose state is a vector of unknowns moved by adding the step,
/// its Jacobian by central differences of `residuals` (which writes into
/// the vector it is given).
pub struct CentralDifferences<F> {
    pub unknowns: usize,
    pub residuals: F,
}

impl<F: Fn(&[f64], &mut Vec<f64>)> LeastSquares for CentralDifferences<F> {
    type State = Vec<f64>;

    fn unknowns(&self) -> usize {
        self.unknowns
    }

    fn residuals(&self, params: &Vec<f64>) -> Option<Vec<f64>> {
        let mut r = Vec::new();
        (self.residuals)(params, &mut r);
        Some(r)
    }

    fn normal_equations(&self, params: &Vec<f64>, r: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (n, m) = (self.unknowns, r.len());
        let (mut plus, mut minus) = (Vec::new(), Vec::new());
        let mut jacobian = vec![0.0; m * n];
        let mut probe = params.to_vec();
        for j in 0..n {
            let step = 1e-6 * params[j].abs().max(1e-2);
            probe[j] = params[j] + step;
            (self.residuals)(&probe, &mut plus);
            probe[j] = params[j] - step;
            (self.residuals)(&probe, &mut minus);
            probe[j] = params[j];
            for i in 0..m {
                jacobian[i * n + j] = (plus[i] - minus[i]) / (2.0 * step);
            }
        }
        let mut jtj = vec![0.0; n * n];
        let mut jtr = vec![0.0; n];
        for i in 0..m {
            let row = &jacobian[i * n..(i + 1) * n];
            for a in 0..n {
                jtr[a] += row[a] * r[i];
                for b in 0..n {
                    jtj[a * n + b] += row[a] * row[b];
                }
            }
        }
        (jtj, jtr)
    }

    fn moved(&self, params: &Vec<f64>, delta: &[f64]) -> Vec<f64> {
        params.iter().zip(delta).map(|(p, d)| p + d).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPD: [f64; 9] = [4.0, 1.0, 0.5, 1.0, 3.0, 0.25, 0.5, 0.25, 2.0];

    #[test]
    fn both_solves_agree_and_eigenvectors_are_eigenvectors() {
        let b = [1.0, -2.0, 0.5];
        let x = solve_positive(&SPD, &b, 3).unwrap();
        let y = solve_pivoting(&SPD, &b, 3).unwrap();
        for i in 0..3 {
            let ax: f64 = (0..3).map(|k| SPD[i * 3 + k] * x[k]).sum();
            assert!((ax - b[i]).abs() < 1e-12 && (x[i] - y[i]).abs() < 1e-12);
        }
        let singular = [1.0, 2.0, 2.0, 4.0];
        assert_eq!(solve_positive(&singular, &[1.0, 1.0], 2), None);
        assert_eq!(solve_pivoting(&singular, &[1.0, 1.0], 2), None);
        let (values, vectors) = symmetric_eigen(&SPD, 3);
        for (i, value) in values.iter().enumerate() {
            let v = &vectors[i * 3..i * 3 + 3];
            for row in 0..3 {
                let av: f64 = (0..3).map(|k| SPD[row * 3 + k] * v[k]).sum();
                assert!((av - value * v[row]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn the_minimiser_fits_a_curve() {
        // y = 2 e^(−0.7 x), sampled without noise.
        let xs: Vec<f64> = (0..12).map(|i| i as f64 * 0.5).collect();
        let problem = CentralDifferences {
            unknowns: 2,
            residuals: |p: &[f64], out: &mut Vec<f64>| {
                out.clear();
                out.extend(xs.iter().map(|&x| p[0] * libm::exp(p[1] * x) - 2.0 * libm::exp(-0.7 * x)));
            },
        };
        let (fitted, r) = minimise(&problem, vec![1.0, 0.0]).unwrap();
        assert!((fitted[0] - 2.0).abs() < 1e-6 && (fitted[1] + 0.7).abs() < 1e-6, "{fitted:?}");
        assert!(r.iter().all(|x| x.abs() < 1e-6));
    }
}
