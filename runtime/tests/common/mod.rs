//! Fixtures shared by the runtime's integration tests.
#![allow(dead_code)]

use telescopic_runtime::{ContactLaw, Drive, ForceFlow, ModelParams, Profile, SectionParams};

/// A section of the paper's test rig (1.35 m, rhoA = 7.85 kg/m, EI = 1743 N m^2).
pub fn rig_section(modes: usize) -> SectionParams {
    SectionParams {
        length: 1.35,
        mass_per_length: 7.85,
        bending_stiffness: 1743.0,
        modes,
    }
}

/// The two-section rig of `adams-linear` with gravity on: m_T = 100 kg, a_2 = 1.15 m,
/// n_c = 3, l_S = 0, F = 100 N.
pub fn rig(modes: [usize; 2]) -> ModelParams {
    ModelParams {
        sections: vec![rig_section(modes[0]), rig_section(modes[1])],
        vehicle_mass: 100.0,
        load_mass: 17.897,
        gravity: 9.81,
        force_flow: ForceFlow::Cable,
        contact_points: 3,
        contact: ContactLaw {
            stiffness: 2.375e8,
            damping: 1000.0,
            clearance: 0.0,
        },
        positions: vec![Profile::Constant(1.15)],
        drive: Drive::Force(Profile::Constant(100.0)),
    }
}

/// Ritz monotonicity: no frequency rose when modes were added.
pub fn assert_not_rising(previous: &[f64], current: &[f64], modes: usize) {
    for (i, (p, f)) in previous.iter().zip(current).enumerate() {
        assert!(
            *f <= p * (1.0 + 1e-12),
            "N = {modes}, f{}: rose from {p} to {f}",
            i + 1
        );
    }
}

/// Deterministic pseudo-random numbers in [-1, 1] (xorshift), so failures reproduce.
pub struct Rng(pub u64);

impl Rng {
    /// The next number in [-1, 1].
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}
