//! Fixtures shared by the runtime's integration tests.
#![allow(dead_code)]

use nalgebra::{DMatrix, DVector};
use telescopic_runtime::{
    ContactLaw, Drive, ForceFlow, Method, Model, ModelParams, Profile, RunStats, SectionParams,
    Settings, SimError, TimeSpan, simulate,
};

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
        damping: Default::default(),
        basis: Default::default(),
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

/// An undamped rattle with clearance: the rig without gravity, drive or contact damping,
/// l_S = 4 mm, every elastic coordinate displaced and moving. Energy is a constant of its
/// piecewise-linear motion, so only the located switches can make it drift. The parameters
/// and the initial state (m, m/s) for a model of `dof` coordinates.
pub fn undamped_rattle() -> (ModelParams, impl Fn(usize) -> Vec<f64>) {
    let mut p = rig([5, 5]);
    p.gravity = 0.0;
    p.force_flow = ForceFlow::None;
    p.contact.damping = 0.0;
    p.contact.clearance = 0.004;
    p.drive = Drive::Force(Profile::Constant(0.0));
    let state = |n: usize| {
        let mut y0 = vec![0.0; 2 * n];
        for i in 1..n {
            y0[i] = 4e-3 / (1.0 + 0.3 * i as f64);
            y0[n + i] = 0.08 * if i % 2 == 0 { 1.0 } else { -1.0 };
        }
        y0
    };
    (p, state)
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

/// The exact solution of the linear time-invariant system (fixed positions, `l_S = 0`,
/// constant force): `y_{k+1} = Phi y_k + Gamma` with `[Phi Gamma] = exp([[A, B], [0, 0]] dt)`.
pub fn exact_lti(model: &dyn Model, force: f64, dt: f64, steps: usize) -> Vec<Vec<f64>> {
    let n = model.dof();
    let m = model.mass_matrix();
    let law = model.params().contact;
    let nc = model.layout().contact_count();
    let (mut g, mut gd) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
    model.contact_vectors(0.0, &mut g, &mut gd);
    let ggt = &g * g.transpose();
    let k_eff = model.stiffness_matrix() + law.stiffness * &ggt;
    let damping = law.damping * &ggt;
    let m_inv = m.clone().try_inverse().unwrap();
    // velocities scaled by 1/s (s ~ the largest frequency) keep the exponent's norm near
    // omega_max dt instead of omega_max^2 dt: scaling and squaring then loses far fewer digits
    let stiffness = -&m_inv * &k_eff;
    let s = stiffness.norm().sqrt();
    let mut aug = DMatrix::zeros(2 * n + 1, 2 * n + 1);
    for i in 0..n {
        aug[(i, n + i)] = s;
    }
    aug.view_mut((n, 0), (n, n)).copy_from(&(stiffness / s));
    aug.view_mut((n, n), (n, n))
        .copy_from(&(-&m_inv * &damping));
    let forcing = &m_inv * model.drive_vector() * force / s;
    aug.view_mut((n, 2 * n), (n, 1)).copy_from(&forcing);
    let mut step = (aug * dt).exp();
    // back to unscaled velocities: Phi = D^-1 Phi_s D with D = diag(I, I/s, 1)
    for i in 0..=2 * n {
        for j in 0..=2 * n {
            let row = if (n..2 * n).contains(&i) { s } else { 1.0 };
            let col = if (n..2 * n).contains(&j) {
                1.0 / s
            } else {
                1.0
            };
            step[(i, j)] *= row * col;
        }
    }
    let mut y = DVector::zeros(2 * n + 1);
    y[2 * n] = 1.0;
    let mut out = vec![y.rows(0, 2 * n).iter().copied().collect()];
    for _ in 0..steps {
        y = &step * y;
        out.push(y.rows(0, 2 * n).iter().copied().collect());
    }
    out
}

/// `tip_rel` (m) of state `y`.
pub fn tip_rel(model: &dyn Model, y: &[f64]) -> f64 {
    let mut out = vec![0.0; model.output_names().len()];
    let ydot = vec![0.0; y.len()];
    model.outputs(0.0, y, &ydot, &mut out);
    out[1]
}

/// The span `[0, end]` s sampled every `sample` s.
pub fn span(end: f64, sample: f64) -> TimeSpan {
    TimeSpan {
        start: 0.0,
        end,
        sample,
    }
}

/// `(t, y)` at every sample.
pub type Samples = Vec<(f64, Vec<f64>)>;

/// Runs and collects `(t, y)` at every sample, with the run's statistics.
pub fn run_counted(
    model: &dyn Model,
    y0: &[f64],
    span: &TimeSpan,
    method: Method,
    settings: &Settings,
) -> Result<(Samples, RunStats), SimError> {
    let mut samples = Vec::new();
    let stats = simulate(
        model,
        y0,
        span,
        method,
        settings,
        &mut |t, y, _| samples.push((t, y.to_vec())),
        None,
    )?;
    Ok((samples, stats))
}

/// Runs and collects `(t, y)` at every sample.
pub fn run(
    model: &dyn Model,
    y0: &[f64],
    span: &TimeSpan,
    method: Method,
    settings: &Settings,
) -> Result<Samples, SimError> {
    run_counted(model, y0, span, method, settings).map(|(samples, _)| samples)
}
