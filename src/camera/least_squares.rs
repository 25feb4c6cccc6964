//! The small dense solvers of the camera's calibrations: symmetric
//! eigenvectors (cyclic Jacobi), linear solves (Cholesky for positive
//! definite systems, Gaussian elimination for the rest), and one
//! Levenberg–Marquardt minimiser of a sum of squared residuals.
//!
//! They are written here rather than pulled in: the problems have at most a
//! few dozen unknowns, and the core must build for wasm lean.
//!
//! The minimiser is one loop with its rules as [`Damping`] options: the
//! board's calibration ([`Damping::BOARD`]) and the four floor corners'
//! ([`Damping::FLOOR`]) were tuned apart and are held to their figures
//! (the calibrations' tests and the golden check), so each keeps its own
//! rules rather than sharing one set.

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

/// The rules of [`minimise`]'s damping: how the step is damped, how the
/// damping follows the steps, and when to stop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Damping {
    /// The damping of the first step.
    pub initial: f64,
    /// Each diagonal entry `a_ii` of `JᵀJ` is damped by the damping times
    /// `a_ii` floored so (Marquardt's scaling, kept off zero).
    pub floor: DiagonalFloor,
    /// How a damped step is solved for.
    pub solver: Solver,
    /// After a better step: the damping divided by this, but not below
    /// `least`.
    pub better_divisor: f64,
    pub least: f64,
    /// After a worse step (or a system that cannot be solved, if
    /// `on_singular` says so): how the damping grows.
    pub growth: Growth,
    /// The damping at which to give up after a worse step.
    pub give_up: GiveUp,
    /// What a damped system that cannot be solved does.
    pub on_singular: OnSingular,
    /// When a step ends the minimisation.
    pub converged: Converged,
    /// How many steps at most.
    pub limit: Limit,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DiagonalFloor {
    /// `a_ii + fraction · max_k a_kk`.
    AddFractionOfLargest(f64),
    /// `max(a_ii, least)`.
    AtLeast(f64),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// [`solve_positive`].
    Cholesky,
    /// [`solve_pivoting`].
    Pivoting,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Growth {
    /// Multiplied by this after each worse step.
    Times(f64),
    /// Multiplied by 2, 4, 8, … after worse steps in a row (by 2 again
    /// after a better one).
    Doubling,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GiveUp {
    /// When the damping reaches this value or more.
    AtLeast(f64),
    /// When the damping exceeds this value.
    Above(f64),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnSingular {
    /// Damp more, as after a worse step.
    DampMore,
    /// End the minimisation.
    Stop,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Converged {
    /// A better step that did not lower the cost by more than this
    /// fraction (nor by a fraction that is not a number).
    GainAtMost(f64),
    /// A better step of which every unknown moved by less than
    /// `better`, or a worse one by less than `worse`.
    StepBelow { better: f64, worse: f64 },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    /// At most this many linearisations (each followed by as many damped
    /// tries as it takes to find a better step).
    Linearisations(usize),
    /// At most this many damped tries, better or worse.
    Tries(usize),
}

impl Damping {
    /// The board's calibration (`calibrate`): damping ÷10 / ×10 from 1e-3,
    /// Cholesky, a relative gain of 1e-12 or 200 linearisations.
    pub const BOARD: Damping = Damping {
        initial: 1e-3,
        floor: DiagonalFloor::AddFractionOfLargest(1e-12),
        solver: Solver::Cholesky,
        better_divisor: 10.0,
        least: 1e-12,
        growth: Growth::Times(10.0),
        give_up: GiveUp::AtLeast(1e12),
        on_singular: OnSingular::DampMore,
        converged: Converged::GainAtMost(1e-12),
        limit: Limit::Linearisations(200),
    };

    /// The four floor corners (`floor_rectangle`): damping ÷3 after a
    /// better step, ×2, ×4, ×8, … after worse ones, pivoting, a step below
    /// 1e-15 (1e-14 when worse) or 200 tries.
    pub const FLOOR: Damping = Damping {
        initial: 1e-3,
        floor: DiagonalFloor::AtLeast(1e-12),
        solver: Solver::Pivoting,
        better_divisor: 3.0,
        least: 1e-15,
        growth: Growth::Doubling,
        give_up: GiveUp::Above(1e12),
        on_singular: OnSingular::Stop,
        converged: Converged::StepBelow { better: 1e-15, worse: 1e-14 },
        limit: Limit::Tries(200),
    };
}

/// Levenberg–Marquardt on the sum of the squared residuals of `problem`
/// from `start`, by the rules of `damping`: the state reached and its
/// residuals; `None` when the residuals at `start` cannot be evaluated.
pub fn minimise<P: LeastSquares>(
    problem: &P,
    start: P::State,
    damping: &Damping,
) -> Option<(P::State, Vec<f64>)> {
    let n = problem.unknowns();
    let cost_of = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>();
    let mut state = start;
    let mut r = problem.residuals(&state)?;
    let mut cost = cost_of(&r);
    let mut lambda = damping.initial;
    let mut growth = 2.0;
    let (mut jtj, mut jtr) = problem.normal_equations(&state, &r);
    let (mut linearisations, mut tries) = (1, 0);
    loop {
        if let Limit::Tries(most) = damping.limit
            && tries >= most
        {
            break;
        }
        tries += 1;
        let mut damped = jtj.clone();
        let largest = (0..n).map(|i| jtj[i * n + i]).fold(0.0, f64::max);
        for i in 0..n {
            let scale = match damping.floor {
                DiagonalFloor::AddFractionOfLargest(fraction) => jtj[i * n + i] + fraction * largest,
                DiagonalFloor::AtLeast(least) => jtj[i * n + i].max(least),
            };
            damped[i * n + i] += lambda * scale;
        }
        let negative: Vec<f64> = jtr.iter().map(|x| -x).collect();
        let delta = match damping.solver {
            Solver::Cholesky => solve_positive(&damped, &negative, n),
            Solver::Pivoting => solve_pivoting(&damped, &negative, n),
        };
        let worse = match delta {
            None if damping.on_singular == OnSingular::Stop => break,
            None => true,
            Some(delta) => {
                let trial = problem.moved(&state, &delta);
                let better = problem
                    .residuals(&trial)
                    .map(|trial_r| (cost_of(&trial_r), trial_r))
                    .filter(|(trial_cost, _)| *trial_cost < cost);
                match better {
                    Some((trial_cost, trial_r)) => {
                        let gain = (cost - trial_cost) / cost.max(1e-300);
                        (state, cost, r) = (trial, trial_cost, trial_r);
                        lambda = (lambda / damping.better_divisor).max(damping.least);
                        growth = 2.0;
                        let converged = match damping.converged {
                            Converged::GainAtMost(least) => gain.is_nan() || gain <= least,
                            Converged::StepBelow { better, .. } => delta.iter().all(|d| d.abs() < better),
                        };
                        if converged {
                            break;
                        }
                        if let Limit::Linearisations(most) = damping.limit
                            && linearisations >= most
                        {
                            break;
                        }
                        linearisations += 1;
                        (jtj, jtr) = problem.normal_equations(&state, &r);
                        false
                    }
                    None => {
                        if let Converged::StepBelow { worse, .. } = damping.converged
                            && delta.iter().all(|d| d.abs() < worse)
                        {
                            break;
                        }
                        true
                    }
                }
            }
        };
        if worse {
            match damping.growth {
                Growth::Times(factor) => lambda *= factor,
                Growth::Doubling => {
                    lambda *= growth;
                    growth *= 2.0;
                }
            }
            let give_up = match damping.give_up {
                GiveUp::AtLeast(most) => lambda.is_nan() || lambda >= most,
                GiveUp::Above(most) => lambda > most,
            };
            if give_up {
                break;
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
    fn either_rule_fits_a_curve() {
        // y = 2 e^(−0.7 x), sampled without noise.
        let xs: Vec<f64> = (0..12).map(|i| i as f64 * 0.5).collect();
        let problem = CentralDifferences {
            unknowns: 2,
            residuals: |p: &[f64], out: &mut Vec<f64>| {
                out.clear();
                out.extend(xs.iter().map(|&x| p[0] * libm::exp(p[1] * x) - 2.0 * libm::exp(-0.7 * x)));
            },
        };
        for rules in [Damping::BOARD, Damping::FLOOR] {
            let (fitted, r) = minimise(&problem, vec![1.0, 0.0], &rules).unwrap();
            assert!(
                (fitted[0] - 2.0).abs() < 1e-6 && (fitted[1] + 0.7).abs() < 1e-6,
                "{rules:?}: {fitted:?}"
            );
            assert!(r.iter().all(|x| x.abs() < 1e-6));
        }
    }
}
