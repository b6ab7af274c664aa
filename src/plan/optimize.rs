//! The optimizer of a plan: argmin's Nelder-Mead over a few bounded parameters, within a
//! budget of evaluations.
//!
//! Why Nelder-Mead: the objective (the worst cycle time over the robust set) is read off
//! nonlinear runs with contact switches, so it has no useful gradient and small steps in
//! it (a sample, a switch); each evaluation costs a run per plant, so the method must need
//! few. Nelder-Mead uses values only, moves the simplex with 1 or 2 evaluations per
//! iteration, and tolerates the steps. argmin has no box constraints and counts iterations,
//! not evaluations: the cost clamps each point into the box and ends the search with an
//! error once the budget is spent, and the best point evaluated is kept here.

use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::neldermead::NelderMead;
use std::cell::RefCell;

/// The best point found and its value, and how many evaluations it took.
#[derive(Debug, Clone, PartialEq)]
pub struct Optimum {
    /// The parameters.
    pub x: Vec<f64>,
    /// The objective there.
    pub value: f64,
    /// Evaluations made.
    pub evaluations: usize,
}

/// An objective: parameters to value.
type Objective<'a> = &'a mut dyn FnMut(&[f64]) -> f64;

/// `f` on the box `bounds` for argmin, at most `budget` times, with the best point so far.
struct BoxedProblem<'a> {
    f: RefCell<Objective<'a>>,
    bounds: &'a [(f64, f64)],
    budget: usize,
    best: &'a RefCell<Optimum>,
}

impl CostFunction for BoxedProblem<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Vec<f64>) -> Result<f64, ArgminError> {
        let mut best = self.best.borrow_mut();
        if best.evaluations >= self.budget {
            return Err(ArgminError::msg("the evaluation budget is spent"));
        }
        let x: Vec<f64> = x
            .iter()
            .zip(self.bounds)
            .map(|(&v, &(lo, hi))| v.clamp(lo, hi))
            .collect();
        let value = (self.f.borrow_mut())(&x);
        best.evaluations += 1;
        if value < best.value {
            best.x = x;
            best.value = value;
        }
        Ok(value)
    }
}

/// Minimizes `f` over the box `bounds` from `start` with at most `budget` evaluations;
/// points outside the box are clamped into it. The first simplex is the start and a step of
/// a tenth of each range along each axis (inward at an upper bound).
pub fn nelder_mead(
    f: &mut dyn FnMut(&[f64]) -> f64,
    start: &[f64],
    bounds: &[(f64, f64)],
    budget: usize,
) -> Optimum {
    let x0: Vec<f64> = start
        .iter()
        .zip(bounds)
        .map(|(&v, &(lo, hi))| v.clamp(lo, hi))
        .collect();
    let mut simplex = vec![x0.clone()];
    for (i, &(lo, hi)) in bounds.iter().enumerate() {
        let step = 0.1 * (hi - lo);
        let mut x = x0.clone();
        x[i] = if x[i] + step <= hi {
            x[i] + step
        } else {
            x[i] - step
        };
        simplex.push(x);
    }
    let best = RefCell::new(Optimum {
        x: x0,
        value: f64::INFINITY,
        evaluations: 0,
    });
    let problem = BoxedProblem {
        f: RefCell::new(f),
        bounds,
        budget,
        best: &best,
    };
    let searched = NelderMead::new(simplex)
        .with_sd_tolerance(0.0)
        .and_then(|solver| {
            Executor::new(problem, solver)
                .configure(|state| state.max_iters(budget as u64))
                .run()
        });
    // an error is the spent budget (or a degenerate simplex): the best point so far stands
    drop(searched);
    best.into_inner()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_minimum_of_a_bowl_inside_its_box_and_on_its_edge() {
        let mut bowl = |x: &[f64]| (x[0] - 0.3).powi(2) + 4.0 * (x[1] - 1.2).powi(2);
        let found = nelder_mead(&mut bowl, &[1.0, 1.0], &[(0.0, 2.0), (0.5, 1.5)], 80);
        assert!(
            (found.x[0] - 0.3).abs() < 1e-3 && (found.x[1] - 1.2).abs() < 1e-3,
            "{found:?}"
        );
        let mut edge = |x: &[f64]| x[0] + (x[1] - 1.0).powi(2);
        let found = nelder_mead(&mut edge, &[1.0, 1.2], &[(0.5, 2.0), (0.5, 1.5)], 80);
        assert!((found.x[0] - 0.5).abs() < 1e-3, "{found:?}");
    }

    #[test]
    fn spends_no_more_than_its_budget_and_keeps_the_best_point_evaluated() {
        let mut calls = Vec::new();
        let mut line = |x: &[f64]| {
            calls.push(x[0]);
            (x[0] - 0.77).abs()
        };
        let found = nelder_mead(&mut line, &[0.2], &[(0.0, 1.0)], 7);
        assert_eq!(found.evaluations, 7);
        assert_eq!(calls.len(), 7);
        assert!(calls.iter().all(|x| (0.0..=1.0).contains(x)), "{calls:?}");
        let nearest = calls
            .iter()
            .copied()
            .min_by(|a, b| (a - 0.77).abs().total_cmp(&(b - 0.77).abs()))
            .unwrap();
        assert_eq!(found.x, vec![nearest]);
        assert_eq!(found.value, (nearest - 0.77).abs());
    }
}
