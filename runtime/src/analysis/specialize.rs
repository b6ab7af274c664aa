//! Shortcuts a scene allows, picked by the runtime without being asked and named in the run
//! summary: constant contact vectors, the linear law without events, no prestress, exact
//! stepping.

use crate::analysis::accuracy::{
    DEFAULT_ACCURACY_M, Resolve, SceneKind, cheapest, plan_for_accuracy,
};
use crate::integrate::Method;
use crate::integrate::exact::{exact_tail_start, lti_obstacle};
use crate::model::Model;
use crate::model::params::{ForceFlow, ModelParams};
use crate::scene::TimeSpan;

/// A shortcut a run takes (or could take), named in its summary.
#[derive(Debug, Clone, PartialEq)]
pub enum Specialization {
    /// The telescopic positions are constant: the contact vectors are computed once.
    FixedPositions,
    /// Moving positions with the contact vectors tabulated in time.
    TabulatedContacts {
        /// The table's span `(start, end)` (s).
        span: (f64, f64),
        /// Its intervals.
        intervals: usize,
        /// Their length (s).
        step: f64,
        /// Entries that move, of `width`.
        moving: usize,
        /// Entries of the contact vectors.
        width: usize,
        /// The checked interpolation error of `g` and of its rate (relative).
        errors: (f64, f64),
    },
    /// `l_S = 0`: the linear contact law, no switch events.
    LinearContactLaw,
    /// No prestress terms: gravity off (`true`) or force flow none.
    NoPrestress {
        /// Whether gravity is off (else the force flow is none).
        gravity_off: bool,
    },
    /// Linear time-invariant between contact switches with a piecewise-constant force: exact
    /// stepping, taken by `method` exact or available to it.
    ExactStepping {
        /// The run's method.
        method: Method,
    },
    /// The positions come to rest at `from` (s): exact stepping of the rest, taken when the
    /// run hands over (`taken`) or available.
    ExactTail {
        /// When the positions come to rest (s).
        from: f64,
        /// Whether the run steps exactly from there.
        taken: bool,
        /// The run's method.
        method: Method,
    },
}

impl Specialization {
    /// Whether the shortcut is exact stepping (which a controlled run never takes).
    pub fn is_exact_stepping(&self) -> bool {
        matches!(
            self,
            Specialization::ExactStepping { .. } | Specialization::ExactTail { .. }
        )
    }
}

impl std::fmt::Display for Specialization {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Specialization::FixedPositions => {
                f.write_str("fixed positions: contact vectors are constants, computed once")
            }
            Specialization::TabulatedContacts {
                span: (start, end),
                intervals,
                step,
                moving,
                width,
                errors: (error_g, error_gd),
            } => write!(
                f,
                "moving positions: contact vectors tabulated on [{start}, {end}] s ({intervals} \
                 intervals of {:.3} ms, {moving} of {width} entries moving; checked error \
                 {error_g:.1e} of g, {error_gd:.1e} of its rate)",
                1e3 * step
            ),
            Specialization::LinearContactLaw => {
                f.write_str("l_S = 0: linear contact law, no switch events")
            }
            Specialization::NoPrestress { gravity_off } => {
                let why = if *gravity_off {
                    "gravity off"
                } else {
                    "force flow none"
                };
                write!(f, "{why}: no prestress terms")
            }
            Specialization::ExactStepping { method } => {
                let how = if *method == Method::Exact {
                    "exact stepping (method exact)".to_string()
                } else {
                    format!("exact stepping would apply (method exact or auto; this run: {method})")
                };
                write!(
                    f,
                    "linear time-invariant between contact switches with a piecewise-constant \
                     force: {how}"
                )
            }
            Specialization::ExactTail {
                from,
                taken,
                method,
            } => {
                let how = if *taken {
                    "exact stepping of the rest (method auto)".to_string()
                } else {
                    format!(
                        "exact stepping of the rest would apply (this run: {method} throughout)"
                    )
                };
                write!(
                    f,
                    "positions at rest from t = {from} s: linear time-invariant from there, {how}"
                )
            }
        }
    }
}

/// The specializations that apply to `model` over `span` in a run of `method` (with exact
/// stepping from `exact_from`, if set); a shortcut the scene allows but the run does not take
/// is named as available, not as used.
pub fn specializations(
    model: &dyn Model,
    span: &TimeSpan,
    method: Method,
    exact_from: Option<f64>,
) -> Vec<Specialization> {
    let params = model.params();
    let mut found = Vec::new();
    if params.positions.iter().all(|p| p.is_constant()) {
        found.push(Specialization::FixedPositions);
    }
    if let Some(table) = model.contact_table() {
        found.push(Specialization::TabulatedContacts {
            span: table.span(),
            intervals: table.intervals(),
            step: table.step(),
            moving: table.varying_columns(),
            width: table.full_width(),
            errors: table.checked_errors(),
        });
    }
    if params.contact.is_linear() {
        found.push(Specialization::LinearContactLaw);
    }
    if params.force_flow == ForceFlow::None {
        found.push(Specialization::NoPrestress {
            gravity_off: params.gravity == 0.0,
        });
    }
    if lti_obstacle(params).is_none() {
        found.push(Specialization::ExactStepping { method });
    }
    if let Some(from) = exact_tail_start(params, span) {
        found.push(Specialization::ExactTail {
            from,
            taken: exact_from.is_some(),
            method,
        });
    }
    found
}

/// What method `auto` runs on `span`: the method, the time from which exact stepping takes
/// over when the positions come to rest inside the span (`None`: one method throughout), and
/// why; the plan of [`crate::analysis::accuracy::plan_for_accuracy`] at the default accuracy (1e-6 m),
/// whose tolerance is the default one (rtol 1e-6).
pub fn auto_plan(params: &ModelParams, span: &TimeSpan) -> (Method, Option<f64>, String) {
    let plan = plan_for_accuracy(params, span, DEFAULT_ACCURACY_M, Resolve::Displacements)
        .expect("every kind of scene has a measured run within the default accuracy");
    (plan.method, plan.exact_from, plan.to_string())
}

/// The method `auto` stands for on the scene of `params` (at the default accuracy), with the
/// reason.
pub fn auto_method(params: &ModelParams) -> (Method, String) {
    let kind = SceneKind::of(params);
    let row = cheapest(kind, DEFAULT_ACCURACY_M, Resolve::Displacements)
        .expect("every kind of scene has a measured run within the default accuracy");
    (
        Method::from_name(row.method).expect("the table names known methods"),
        format!("{} (for scenes {})", row.method, kind.describe()),
    )
}

#[cfg(test)]
mod specialization_tests {
    use super::*;

    /// A controlled run drops the exact-stepping shortcuts: the variants that say so are the
    /// ones whose phrase names exact stepping, taken or only available.
    #[test]
    fn exact_stepping_is_the_variants_that_name_it() {
        let all = [
            Specialization::FixedPositions,
            Specialization::TabulatedContacts {
                span: (0.0, 12.0),
                intervals: 10,
                step: 1e-3,
                moving: 6,
                width: 16,
                errors: (1e-12, 1e-9),
            },
            Specialization::LinearContactLaw,
            Specialization::NoPrestress { gravity_off: true },
            Specialization::NoPrestress { gravity_off: false },
            Specialization::ExactStepping {
                method: Method::Exact,
            },
            Specialization::ExactStepping {
                method: Method::Dopri5,
            },
            Specialization::ExactTail {
                from: 12.0,
                taken: true,
                method: Method::Dop853Imex,
            },
            Specialization::ExactTail {
                from: 12.0,
                taken: false,
                method: Method::Dopri5,
            },
        ];
        for s in &all {
            assert_eq!(
                s.is_exact_stepping(),
                s.to_string().contains("exact stepping"),
                "{s}"
            );
        }
        assert_eq!(all.iter().filter(|s| s.is_exact_stepping()).count(), 4);
    }
}
