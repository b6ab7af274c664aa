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
pub(crate) fn illinois(
    p: &mut dyn FnMut(f64) -> f64,
    (mut lo, mut p_lo): (f64, f64),
    (mut hi, mut p_hi): (f64, f64),
    tol: f64,
) -> f64 {
    let mut side = 0i8;
    for _ in 0..200 {
        if hi - lo <= tol {
            break;
        }
        let mut x = hi - p_hi * (hi - lo) / (p_hi - p_lo);
        if !(x > lo && x < hi) {
            x = 0.5 * (lo + hi);
        }
        let v = p(x);
        if v < 0.0 {
            hi = x;
            p_hi = v;
            if side == 1 {
                p_lo *= 0.5;
            }
            side = 1;
        } else {
            lo = x;
            p_lo = v;
            if side == -1 {
                p_hi *= 0.5;
            }
            side = -1;
        }
    }
    hi
}
