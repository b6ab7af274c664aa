//! Each sensor's unknown offset (a strain gauge's zero, an encoder's reference): fitted as
//! a constant of its own, or zero.

/// What becomes of each sensor's unknown offset (a strain gauge's zero, an encoder's
/// reference).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Offsets {
    /// Each sensor's offset is a free constant of the fit, eliminated in closed form (the
    /// mean of its residual): the record's mean level carries no information.
    #[default]
    Fitted,
    /// The record is zeroed as the model is: the mean level is fitted too.
    Zero,
}

crate::named::named_enum!(Offsets, "an offsets choice", {
    Fitted => "fitted",
    Zero => "zero",
});

impl Offsets {
    /// The constants fitted beside the free values for `sensors` sensors.
    pub fn count(self, sensors: usize) -> usize {
        match self {
            Offsets::Fitted => sensors,
            Offsets::Zero => 0,
        }
    }
}

/// The offset of a sensor whose model samples are `p` and record `y`.
pub fn offset_of(p: &[f64], y: &[f64], offsets: Offsets) -> f64 {
    match offsets {
        Offsets::Fitted => p.iter().zip(y).map(|(p, y)| p - y).sum::<f64>() / p.len() as f64,
        Offsets::Zero => 0.0,
    }
}
