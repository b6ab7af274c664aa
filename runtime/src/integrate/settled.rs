//! Method `dop853-imex`: dop853 while the contacts are open or ringing after a switch, imex
//! over closed contacts whose contact modes have rung down.
//!
//! On a scene with impacts most of the closed time is spent in long closures (the upper
//! section resting on its guide; case-study: contacts closed for 7.9 of 12 s, over 80 % of
//! that in closures longer than 0.1 s). There an explicit method is held at the stable step of
//! the 3.6-4.5 kHz contact mode although the motion is the beams' 0.5-20 Hz, while imex steps
//! over the contact mode; across the impacts and the rattles between them the contact mode
//! rings and must be resolved, and there dop853 is the cheaper of the two (every switch would
//! restart imex, and its L-stable part would damp the ringing that sets the restitution).
//!
//! This stepper runs dop853 from every switch and drive discontinuity on, and hands over to
//! imex once a contact is closed and [`QUIET_STEPS`] accepted dop853 steps in a row, each at
//! least half its closed-contact step cap, had a scaled error below [`QUIET_ERROR`]: at that
//! step the error of an explicit method is dominated by the ringing contact mode, so its
//! falling below a tenth of the tolerance says the mode has rung down to where the tolerance
//! no longer sees it. imex then estimates the error of the coordinates only, as it does
//! without clearance (the rates of the rung-down contact modes, which its L-stable part damps,
//! would otherwise set its step). The next switch or drive discontinuity hands back to
//! dop853. Where the contacts never settle (three-section's rattle) it is dop853 step for
//! step.
//!
//! The driver's step-size controller reads the order and PI weight of the part that takes the
//! step; while imex steps, the closed-contact step cap is lifted and the steps count as
//! [`super::RunStats::long_steps`].

use super::explicit::{DOP853, ExplicitRk};
use super::imex::Imex;
use super::{Settings, StepFailure, Stepper, System};

/// dop853 across switches, imex over settled closed contacts.
pub struct SettledSteps {
    explicit: ExplicitRk,
    implicit: Imex,
    /// dop853's step cap with closed contacts (s, [`super::stability::closed_contact_step_cap`]):
    /// steps at least half of it count.
    cap: f64,
    /// dop853's last step, when a contact was closed: its length (s) and scaled error.
    last: Option<(f64, f64)>,
    /// Consecutive accepted dop853 steps near the cap with a contact closed and an error
    /// below [`QUIET_ERROR`].
    quiet: u32,
    /// imex takes the steps.
    on_implicit: bool,
}

/// dop853's scaled error at its stable step below which a closed contact's mode counts as
/// rung down.
pub const QUIET_ERROR: f64 = 0.1;

/// Consecutive quiet steps before imex takes over.
pub const QUIET_STEPS: u32 = 4;

impl SettledSteps {
    /// For `dof` coordinates with the run's tolerances; `cap` is dop853's step cap with closed
    /// contacts (s); `longest_step` the run's longest step (s: the output sample interval, or
    /// `Settings::longest_step`).
    pub fn new(dof: usize, settings: &Settings, cap: f64, longest_step: f64) -> Self {
        SettledSteps {
            explicit: ExplicitRk::new(&DOP853, 2 * dof, settings),
            implicit: Imex::new(dof, settings, longest_step).with_coordinates_error(),
            cap,
            last: None,
            quiet: 0,
            on_implicit: false,
        }
    }

    fn active(&self) -> &dyn Stepper {
        if self.on_implicit {
            &self.implicit
        } else {
            &self.explicit
        }
    }
}

impl Stepper for SettledSteps {
    fn order(&self) -> u32 {
        self.active().order()
    }

    fn step(
        &mut self,
        sys: &mut System,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
        y1: &mut [f64],
    ) -> Result<f64, StepFailure> {
        // imex's storage is made on the run's first step, not at the hand-over
        self.implicit.prepare(sys);
        if !self.on_implicit && self.quiet >= QUIET_STEPS && sys.tracker.any_closed() {
            self.on_implicit = true;
        }
        if self.on_implicit {
            return self.implicit.step(sys, t, y, f0, h, y1);
        }
        let err = self.explicit.step(sys, t, y, f0, h, y1)?;
        self.last = sys.tracker.any_closed().then_some((h, err));
        Ok(err)
    }

    fn end_derivative(&self) -> Option<&[f64]> {
        self.active().end_derivative()
    }

    fn accepted(&mut self) {
        if self.on_implicit {
            return;
        }
        self.quiet = match self.last {
            Some((h, err)) if h >= 0.5 * self.cap && err < QUIET_ERROR => self.quiet + 1,
            _ => 0,
        };
    }

    fn restart(&mut self) {
        self.quiet = 0;
        self.last = None;
        self.on_implicit = false;
    }

    fn pi_beta(&self) -> f64 {
        self.active().pi_beta()
    }

    fn growth_limit(&self) -> f64 {
        self.active().growth_limit()
    }

    fn over_contact_modes(&self) -> bool {
        self.on_implicit
    }

    fn prepare_extension(
        &mut self,
        sys: &mut System,
        t: f64,
        y: &[f64],
        y1: &[f64],
        h: f64,
    ) -> bool {
        !self.on_implicit && self.explicit.prepare_extension(sys, t, y, y1, h)
    }

    fn extension_state(&self, theta: f64, out: &mut [f64]) {
        self.explicit.extension_state(theta, out);
    }
}
