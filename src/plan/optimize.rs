//! The optimizer of a plan: Nelder-Mead over a few bounded parameters.
//!
//! Why Nelder-Mead: the objective (the worst cycle time over the robust set) is read off
//! nonlinear runs with contact switches, so it has no useful gradient and small steps in
//! it (a sample, a switch); each evaluation costs a run per plant, so the method must need
//! few. Nelder-Mead uses values only, moves the simplex with 1 or 2 evaluations per
//! iteration, and tolerates the steps. Hand-written (40 lines) because the crates that have
//! it (argmin, for one) bring a framework for one loop.

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

/// Minimizes `f` over the box `bounds` from `start` with at most `budget` evaluations;
/// points outside the box are clamped into it.
pub fn nelder_mead(
    f: &mut dyn FnMut(&[f64]) -> f64,
    start: &[f64],
    bounds: &[(f64, f64)],
    budget: usize,
) -> Optimum {
    let clamp = |x: Vec<f64>| -> Vec<f64> {
        x.iter()
            .zip(bounds)
            .map(|(&v, &(lo, hi))| v.clamp(lo, hi))
            .collect()
    };
    let n = start.len();
    let mut evaluations = 0;
    let mut eval = |x: &[f64], evaluations: &mut usize| {
        *evaluations += 1;
        f(x)
    };
    // the first simplex: the start and a step of a tenth of each range along each axis
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
    let x0 = clamp(start.to_vec());
    let f0 = eval(&x0, &mut evaluations);
    simplex.push((x0.clone(), f0));
    for i in 0..n {
        let mut x = x0.clone();
        let step = 0.1 * (bounds[i].1 - bounds[i].0);
        x[i] = if x[i] + step <= bounds[i].1 {
            x[i] + step
        } else {
            x[i] - step
        };
        let fx = eval(&x, &mut evaluations);
        simplex.push((x, fx));
    }
    while evaluations < budget {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let worst = simplex[n].clone();
        let centroid: Vec<f64> = (0..n)
            .map(|i| simplex[..n].iter().map(|p| p.0[i]).sum::<f64>() / n as f64)
            .collect();
        let toward = |t: f64| -> Vec<f64> {
            clamp(
                (0..n)
                    .map(|i| centroid[i] + t * (worst.0[i] - centroid[i]))
                    .collect(),
            )
        };
        let reflected = toward(-1.0);
        let fr = eval(&reflected, &mut evaluations);
        if fr < simplex[0].1 {
            let expanded = toward(-2.0);
            let fe = eval(&expanded, &mut evaluations);
            simplex[n] = if fe < fr {
                (expanded, fe)
            } else {
                (reflected, fr)
            };
        } else if fr < simplex[n - 1].1 {
            simplex[n] = (reflected, fr);
        } else {
            let contracted = toward(0.5);
            let fc = eval(&contracted, &mut evaluations);
            if fc < worst.1 {
                simplex[n] = (contracted, fc);
            } else {
                // shrink toward the best
                let best = simplex[0].0.clone();
                for p in simplex.iter_mut().skip(1) {
                    let x = clamp((0..n).map(|i| best[i] + 0.5 * (p.0[i] - best[i])).collect());
                    let fx = eval(&x, &mut evaluations);
                    *p = (x, fx);
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    Optimum {
        x: simplex[0].0.clone(),
        value: simplex[0].1,
        evaluations,
    }
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
}
