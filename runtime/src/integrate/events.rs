//! Contact-switch events: which branch of the clearance law each contact is in, and the
//! switch functions whose sign change marks a band-edge crossing.
//!
//! For contact `c` with gap `xi` and half band `h = l_S/2` the switch function is
//!
//! ```text
//! Upper: xi - h        Lower: -h - xi        Free: h - |xi|
//! ```
//!
//! positive while the contact stays in its branch, zero on the band edge. On a crossing the
//! new branch's function is the negative of the old one at the same edge, so a contact
//! switched where the old function is just below zero starts its new branch just above zero:
//! the same crossing is never found twice, and every event moves time forward.

use crate::contact::{ContactLaw, ContactState};
use crate::model::Model;

/// The branch of every contact, and scratch space for gaps.
#[derive(Debug, Clone)]
pub struct ContactTracker {
    law: ContactLaw,
    states: Vec<ContactState>,
    xi: Vec<f64>,
    xi_dot: Vec<f64>,
    values: Vec<f64>,
}

impl ContactTracker {
    /// Branches taken from the gaps of state `y` at time `t`.
    pub fn new(model: &dyn Model, t: f64, y: &[f64]) -> Self {
        let nc = model.layout().contact_count();
        let law = model.params().contact;
        let mut tracker = ContactTracker {
            law,
            states: vec![ContactState::Free; nc],
            xi: vec![0.0; nc],
            xi_dot: vec![0.0; nc],
            values: vec![0.0; nc],
        };
        model.contact_gaps(t, y, &mut tracker.xi, &mut tracker.xi_dot);
        for (s, &x) in tracker.states.iter_mut().zip(&tracker.xi) {
            *s = law.state(x);
        }
        tracker
    }

    /// True when the law has no band (`l_S = 0`): no events, no fixed branches.
    pub fn is_linear(&self) -> bool {
        self.law.is_linear()
    }

    /// The branches to hold fixed in the right-hand side (`None` for the linear law).
    #[inline]
    pub fn fixed_states(&self) -> Option<&[ContactState]> {
        if self.is_linear() {
            None
        } else {
            Some(&self.states)
        }
    }

    /// Presses every contact against its upper guide (closed contacts; for stability and
    /// linearization studies).
    pub fn press_all(&mut self) {
        self.states.fill(ContactState::Upper);
    }

    /// True when some contact carries force: a branch other than free, or the linear law
    /// (`l_S = 0`, every contact always in force).
    #[inline]
    pub fn any_closed(&self) -> bool {
        self.is_linear() || self.states.iter().any(|&s| s != ContactState::Free)
    }

    /// How many contacts are in a closed branch (upper or lower).
    pub fn closed_count(&self) -> usize {
        self.states
            .iter()
            .filter(|&&s| s != ContactState::Free)
            .count()
    }

    /// Current branches.
    pub fn states(&self) -> &[ContactState] {
        &self.states
    }

    /// Switch function of a contact in `state` at gap `xi` (m).
    pub fn switch_value(&self, state: ContactState, xi: f64) -> f64 {
        let h = self.law.half_band();
        match state {
            ContactState::Upper => xi - h,
            ContactState::Lower => -h - xi,
            ContactState::Free => h - xi.abs(),
        }
    }

    /// The smallest switch function over all contacts at `(t, y)` (m): negative when some
    /// contact has left its branch. `+inf` for the linear law or no contacts.
    pub fn min_switch_value(&mut self, model: &dyn Model, t: f64, y: &[f64]) -> f64 {
        if self.is_linear() || self.states.is_empty() {
            return f64::INFINITY;
        }
        model.contact_gaps(t, y, &mut self.xi, &mut self.xi_dot);
        let mut min = f64::INFINITY;
        for c in 0..self.states.len() {
            let v = self.switch_value(self.states[c], self.xi[c]);
            self.values[c] = v;
            min = min.min(v);
        }
        min
    }

    /// Rate of change (m/s) of the switch function of a contact in `state` at gap `xi` (m)
    /// moving at `xi_dot` (m/s).
    pub fn switch_rate(state: ContactState, xi: f64, xi_dot: f64) -> f64 {
        match state {
            ContactState::Upper => xi_dot,
            ContactState::Lower => -xi_dot,
            ContactState::Free => -xi.signum() * xi_dot,
        }
    }

    /// Switch function (m) and its rate (m/s) of every contact at `(t, y)`, into `values`
    /// and `rates` (one entry per contact). Nothing for the linear law.
    pub fn switch_functions(
        &mut self,
        model: &dyn Model,
        t: f64,
        y: &[f64],
        values: &mut [f64],
        rates: &mut [f64],
    ) {
        if self.is_linear() || self.states.is_empty() {
            return;
        }
        model.contact_gaps(t, y, &mut self.xi, &mut self.xi_dot);
        for c in 0..self.states.len() {
            values[c] = self.switch_value(self.states[c], self.xi[c]);
            rates[c] = Self::switch_rate(self.states[c], self.xi[c], self.xi_dot[c]);
        }
    }

    /// The smallest switch function over all contacts at `(t, y)` (m) and the rate (m/s) of
    /// the contact it belongs to; `(+inf, 0)` for the linear law or no contacts.
    pub fn min_switch_value_and_rate(
        &mut self,
        model: &dyn Model,
        t: f64,
        y: &[f64],
    ) -> (f64, f64) {
        let min = self.min_switch_value(model, t, y);
        if !min.is_finite() {
            return (min, 0.0);
        }
        let c = (0..self.states.len())
            .find(|&c| self.values[c] == min)
            .unwrap_or(0);
        (
            min,
            Self::switch_rate(self.states[c], self.xi[c], self.xi_dot[c]),
        )
    }

    /// Moves every contact whose switch function is negative at `(t, y)` to the branch its
    /// gap is in; returns how many switched.
    pub fn switch(&mut self, model: &dyn Model, t: f64, y: &[f64]) -> u64 {
        if self.min_switch_value(model, t, y) >= 0.0 {
            return 0;
        }
        let mut switched = 0;
        for c in 0..self.states.len() {
            if self.values[c] < 0.0 {
                let h = self.law.half_band();
                let xi = self.xi[c];
                // the gap is past the edge it crossed, so the new branch is unambiguous
                self.states[c] = match self.states[c] {
                    ContactState::Free if xi > 0.0 => ContactState::Upper,
                    ContactState::Free => ContactState::Lower,
                    _ if xi.abs() <= h => ContactState::Free,
                    // jumped across the whole band within one step
                    _ if xi > 0.0 => ContactState::Upper,
                    _ => ContactState::Lower,
                };
                switched += 1;
            }
        }
        switched
    }
}

/// A crossing of a switch function inside `[lo, hi]`, by Illinois (regula falsi with
/// halving): `p(lo) = p_lo >= 0 > p(hi) = p_hi` on entry; returns the end of the final
/// bracket where `p < 0`, within `tol` of the crossing. Every point `p` is called at that
/// turns out negative becomes the new `hi` (callers keep the state they computed there).
/// [`newton_in_bracket`] without a derivative.
pub(crate) fn illinois(
    p: &mut dyn FnMut(f64) -> f64,
    lo: (f64, f64),
    hi: (f64, f64),
    tol: f64,
) -> f64 {
    newton_in_bracket(&mut |x| (p(x), f64::NAN), lo, hi, f64::NAN, tol, 0.0)
}

/// A crossing of a switch function inside `[lo, hi]` by Newton's method kept inside the
/// bracket: `p(x)` returns the value and its rate, `p(lo) = p_lo >= 0 > p(hi) = p_hi` on
/// entry, `first` is the first point tried (an estimate of the crossing). Each Newton point
/// is aimed at `p = -value_tol / 2` and pushed `tol / 2` past the predicted crossing, so
/// once the prediction is that good the next point lands past the crossing and within
/// `value_tol` of it, where the search stops, or the bracket closes to `tol` from both
/// sides (`value_tol = 0`: only the bracket ends the search; below the rounding of `p`
/// Newton's points wander about the crossing, so a positive `value_tol` saves the last
/// two or three calls). A point outside the bracket, or a Newton correction that did not at
/// least halve, falls back to Illinois' regula falsi. Returns the end of the final bracket
/// where `p < 0`; every point `p` is called at that turns out negative becomes the new `hi`
/// (callers keep the state they computed there).
pub(crate) fn newton_in_bracket(
    p: &mut dyn FnMut(f64) -> (f64, f64),
    (mut lo, mut p_lo): (f64, f64),
    (mut hi, mut p_hi): (f64, f64),
    first: f64,
    tol: f64,
    value_tol: f64,
) -> f64 {
    let mut x = first;
    let mut last_correction = f64::INFINITY;
    let mut side = 0i8;
    for _ in 0..200 {
        if hi - lo <= tol {
            break;
        }
        if !(x > lo && x < hi) {
            x = hi - p_hi * (hi - lo) / (p_hi - p_lo);
            if !(x > lo && x < hi) {
                x = 0.5 * (lo + hi);
            }
        }
        let (v, rate) = p(x);
        if v < 0.0 && -v <= value_tol {
            return x;
        }
        // Illinois' halving keeps regula falsi from stalling on one side
        if v < 0.0 {
            (hi, p_hi) = (x, v);
            if side == 1 {
                p_lo *= 0.5;
            }
            side = 1;
        } else {
            (lo, p_lo) = (x, v);
            if side == -1 {
                p_hi *= 0.5;
            }
            side = -1;
        }
        let correction = (-0.5 * value_tol - v) / rate;
        if correction.is_finite() && correction.abs() <= 0.5 * last_correction {
            last_correction = correction.abs();
            x += correction + if v < 0.0 { -0.5 * tol } else { 0.5 * tol };
        } else {
            // no trustworthy Newton step: regula falsi on the bracket next
            last_correction = f64::INFINITY;
            x = f64::NAN;
        }
    }
    hi
}

/// The cubic Hermite polynomial on `[0, 1]` with values `f0`, `f1` and scaled slopes `s0`,
/// `s1` (slope times the interval) at its ends.
#[derive(Debug, Clone, Copy)]
pub(crate) struct HermiteCubic {
    f0: f64,
    s0: f64,
    a2: f64,
    a3: f64,
}

impl HermiteCubic {
    pub(crate) fn new(f0: f64, s0: f64, f1: f64, s1: f64) -> Self {
        HermiteCubic {
            f0,
            s0,
            a2: -3.0 * f0 - 2.0 * s0 + 3.0 * f1 - s1,
            a3: 2.0 * f0 + s0 - 2.0 * f1 + s1,
        }
    }

    /// Value at `x` in `[0, 1]`.
    pub(crate) fn value(&self, x: f64) -> f64 {
        ((self.a3 * x + self.a2) * x + self.s0) * x + self.f0
    }

    /// True when it goes below zero strictly inside `(0, 1)`, from its critical points
    /// (both end values non-negative: a double crossing inside the interval).
    pub(crate) fn dips(&self) -> bool {
        // roots of 3 a3 x^2 + 2 a2 x + s0
        let (qa, qb, qc) = (3.0 * self.a3, 2.0 * self.a2, self.s0);
        let mut points = [f64::NAN; 2];
        if qa.abs() <= 1e-300 {
            if qb != 0.0 {
                points[0] = -qc / qb;
            }
        } else {
            let disc = qb * qb - 4.0 * qa * qc;
            if disc >= 0.0 {
                let r = disc.sqrt();
                points = [(-qb - r) / (2.0 * qa), (-qb + r) / (2.0 * qa)];
            }
        }
        points
            .iter()
            .any(|&x| x > 0.0 && x < 1.0 && self.value(x) < 0.0)
    }

    /// Its first root in `(0, 1)` when `f0 >= 0`, or `None` (see [`first_crossing`]).
    pub(crate) fn first_root(&self) -> Option<f64> {
        first_crossing(&mut |x| self.value(x), 1.0, 16, 1e-12)
    }
}

/// The first downward crossing of `p` in `(0, limit]`: `p` is scanned at `points` equal
/// steps for its first negative value (`p(0)` is taken as at least 0), the crossing refined
/// by Illinois to `tol`. `None` when no scanned value is negative.
pub(crate) fn first_crossing(
    p: &mut dyn FnMut(f64) -> f64,
    limit: f64,
    points: usize,
    tol: f64,
) -> Option<f64> {
    let (mut lo, mut p_lo) = (0.0, p(0.0).max(0.0));
    for k in 1..=points {
        let hi = limit * k as f64 / points as f64;
        let p_hi = p(hi);
        if p_hi < 0.0 {
            return Some(illinois(p, (lo, p_lo), (hi, p_hi), tol));
        }
        (lo, p_lo) = (hi, p_hi);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `cos x - 0.3` crosses zero downwards at `acos 0.3` inside `[0, 2]`.
    fn falling(x: f64) -> (f64, f64) {
        (x.cos() - 0.3, -x.sin())
    }

    /// `newton_in_bracket` on [`falling`] over `[0, 2]` from 1.2: the point returned and the
    /// number of calls.
    fn counted_search(tol: f64, value_tol: f64) -> (f64, u32) {
        let mut calls = 0;
        let (lo, hi) = ((0.0, falling(0.0).0), (2.0, falling(2.0).0));
        let x = newton_in_bracket(
            &mut |x| {
                calls += 1;
                falling(x)
            },
            lo,
            hi,
            1.2,
            tol,
            value_tol,
        );
        (x, calls)
    }

    #[test]
    fn newton_in_bracket_closes_on_the_crossing_in_fewer_calls_than_illinois() {
        let root = 0.3_f64.acos();
        let tol = 1e-15;
        let (lo, hi) = ((0.0, falling(0.0).0), (2.0, falling(2.0).0));
        let (x, newton_calls) = counted_search(tol, 0.0);
        assert!(falling(x).0 < 0.0, "the returned end is past the crossing");
        assert!(
            x - root <= 2.0 * tol && x >= root - 1e-16,
            "x - root = {:e}",
            x - root
        );
        let mut illinois_calls = 0;
        let y = illinois(
            &mut |x| {
                illinois_calls += 1;
                falling(x).0
            },
            lo,
            hi,
            tol,
        );
        assert!((y - root).abs() <= 2.0 * tol);
        assert!(
            newton_calls < illinois_calls,
            "newton {newton_calls} calls, illinois {illinois_calls}"
        );
    }

    /// With a value tolerance the search stops at the first point past the crossing whose
    /// value is within it, in fewer calls than closing the bracket to rounding; a point with
    /// a larger value does not stop it.
    #[test]
    fn newton_in_bracket_stops_within_the_value_tolerance_past_the_crossing() {
        let root = 0.3_f64.acos();
        let (exact, n_exact) = counted_search(1e-15, 0.0);
        let (within, n_within) = counted_search(1e-15, 1e-9);
        let v = falling(within).0;
        assert!(v < 0.0 && -v <= 1e-9, "value {v:e} at {within}");
        assert!((exact - root).abs() <= 2e-15);
        assert!(n_within < n_exact, "{n_within} calls against {n_exact}");
        // the first Newton point from 1.2 has |p| ~ 1e-2: it must not stop a search asking 1e-9
        assert!(n_within >= 2);
    }

    #[test]
    fn newton_in_bracket_survives_a_wrong_rate_and_a_bad_first_guess() {
        let root = 0.3_f64.acos();
        let tol = 1e-14;
        // the rate has the wrong sign: every Newton step points away; the bracket decides
        let x = newton_in_bracket(
            &mut |x| (falling(x).0, 1.0),
            (0.0, 0.7),
            (2.0, falling(2.0).0),
            5.0,
            tol,
            0.0,
        );
        assert!(falling(x).0 < 0.0);
        assert!((x - root).abs() <= 2.0 * tol, "x - root = {:e}", x - root);
    }

    #[test]
    fn hermite_cubic_first_root_is_exact_and_dips_are_seen() {
        // f(s) = (s - 0.3)(s - 0.8)(s + 1): positive at 0, roots 0.3 and 0.8 inside
        let f = |s: f64| (s - 0.3) * (s - 0.8) * (s + 1.0);
        let df = |s: f64| (s - 0.8) * (s + 1.0) + (s - 0.3) * (s + 1.0) + (s - 0.3) * (s - 0.8);
        let root = HermiteCubic::new(f(0.0), df(0.0), f(1.0), df(1.0))
            .first_root()
            .expect("a root");
        assert!((root - 0.3).abs() < 1e-11, "root {root}");
        // a cubic that stays positive on (0, 1) has none
        let g = |s: f64| (s - 0.5) * (s - 0.5) + 0.01;
        let dg = |s: f64| 2.0 * (s - 0.5);
        let positive = HermiteCubic::new(g(0.0), dg(0.0), g(1.0), dg(1.0));
        assert_eq!(positive.first_root(), None);
        assert!(!positive.dips());
        // f0 = f1 = 0.01 with slopes -0.2 and +0.2: dips to about -0.04 in between
        assert!(HermiteCubic::new(0.01, -0.2, 0.01, 0.2).dips());
    }
}
