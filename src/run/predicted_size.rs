//! The size [`SimulationOptions::accuracy`](crate::run::SimulationOptions::accuracy)
//! predicts before any run, from the scene's own modes and drive.
//!
//! Each candidate size's modal surrogate ([`telescopic_runtime::analysis::modal_surrogate`])
//! is compared with the largest size's: the largest difference in `tip_rel` over the span
//! stands for the size's truncation error. The candidates are taken by their predicted cost
//! (the square of their coordinates, which the counted work of a run follows), and the first
//! whose estimate is within the bound (the accuracy over the search's margin,
//! [`crate::run::total_accuracy::ESTIMATE_MARGIN`]) is the prediction. The
//! search then runs that size with its companion to confirm it, and refines along its ladder
//! only when the confirmation fails. With clearance there is no prediction: the impacts that
//! set a run's error there are beyond a linear estimate, and the search checks the sizes from
//! the smallest.

use crate::run::sized::ModelSize;
use std::fmt;
use telescopic_runtime::analysis::modal_surrogate::surrogate_tip;
use telescopic_runtime::{AssembledModel, Scene};

/// What the search was told before its first run.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum SizePrediction {
    /// The cheapest size whose surrogate estimate is within the accuracy.
    Predicted {
        /// The size predicted.
        size: ModelSize,
        /// Its surrogate's largest difference in `tip_rel` from the reference's (m).
        estimated_m: f64,
        /// The size the estimate is taken against (the largest there is).
        reference: ModelSize,
    },
    /// No size was predicted, for this reason: the search checks sizes from the smallest.
    Skipped(NoPrediction),
}

/// Why no size was predicted.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum NoPrediction {
    /// The scene has clearance: impacts set its runs' error.
    Clearance,
    /// No candidate's estimate is within the accuracy; the smallest estimate (m).
    NoneWithin(f64),
    /// The surrogate could not be built (the model's or the eigen analysis's error).
    Analysis(String),
}

impl fmt::Display for SizePrediction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SizePrediction::Predicted {
                size,
                estimated_m,
                reference,
            } => write!(
                f,
                "predicted {} {} (its modal surrogate {estimated_m:.1e} m from {} {}'s)",
                size.basis.word(),
                size.modes,
                reference.basis.word(),
                reference.modes
            ),
            SizePrediction::Skipped(NoPrediction::Clearance) => {
                write!(f, "no size predicted (clearance: impacts set the error)")
            }
            SizePrediction::Skipped(NoPrediction::NoneWithin(smallest)) => write!(
                f,
                "no size predicted (the smallest modal surrogate estimate is {smallest:.1e} m)"
            ),
            SizePrediction::Skipped(NoPrediction::Analysis(why)) => {
                write!(f, "no size predicted (the modal surrogate failed: {why})")
            }
        }
    }
}

/// The cheapest size of `candidates` whose surrogate estimate on `scene`, against
/// `reference`'s, is within `bound_m` (m).
///
/// ```
/// use telescopic::run::{ModelSize, SizePrediction, predict_size};
/// use telescopic::runtime::{Basis, Scene};
/// let scene = Scene::load(std::path::Path::new("scenes/adams-linear.toml"), &[]).unwrap();
/// let sizes = [4, 6, 9].map(|modes| ModelSize { basis: Basis::Modes, modes });
/// let reference = ModelSize { basis: Basis::ModesAndStatic, modes: 21 };
/// let prediction = predict_size(&scene, 1e-2, &sizes, reference);
/// assert!(matches!(prediction, SizePrediction::Predicted { .. }));
/// ```
pub fn predict_size(
    scene: &Scene,
    bound_m: f64,
    candidates: &[ModelSize],
    reference: ModelSize,
) -> SizePrediction {
    if !scene.params.contact.is_linear() {
        return SizePrediction::Skipped(NoPrediction::Clearance);
    }
    let reference_tip = match surrogate(scene, reference) {
        Ok(tip) => tip,
        Err(why) => return SizePrediction::Skipped(NoPrediction::Analysis(why)),
    };
    let mut by_cost = candidates.to_vec();
    by_cost.sort_by_cached_key(|size| predicted_cost(scene, *size));
    let mut smallest = f64::INFINITY;
    for size in by_cost {
        let tip = match surrogate(scene, size) {
            Ok(tip) => tip,
            Err(why) => return SizePrediction::Skipped(NoPrediction::Analysis(why)),
        };
        let estimated_m = tip
            .iter()
            .zip(&reference_tip)
            .fold(0.0_f64, |worst, (a, b)| worst.max((a - b).abs()));
        if estimated_m <= bound_m {
            return SizePrediction::Predicted {
                size,
                estimated_m,
                reference,
            };
        }
        smallest = smallest.min(estimated_m);
    }
    SizePrediction::Skipped(NoPrediction::NoneWithin(smallest))
}

/// The square of the coordinates of `size` on `scene`: a run's counted work follows it.
fn predicted_cost(scene: &Scene, size: ModelSize) -> usize {
    let dof = 1 + size.apply(scene).params.coordinates().iter().sum::<usize>();
    dof * dof
}

/// The modal surrogate's `tip_rel` of `size` on `scene` at the scene's samples.
fn surrogate(scene: &Scene, size: ModelSize) -> Result<Vec<f64>, String> {
    let sized = size.apply(scene);
    let model = AssembledModel::exact(&sized.params).map_err(|e| e.to_string())?;
    surrogate_tip(
        &model,
        (scene.time.start, scene.time.end),
        scene.time.sample,
    )
    .map_err(|e| e.to_string())
}
