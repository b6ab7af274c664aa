//! The derived matrices against the quadrature-assembled model of the runtime: two
//! independent paths (closed-form 512-bit integrals + Symbolica vs Gauss-Legendre in f64).

use std::collections::HashMap;
use telescopic_codegen::{DriveKind, ForceFlow, ModelConfig, Positions, derive};
use telescopic_runtime::{
    AssembledModel, ContactLaw, Drive, Model, ModelParams, Profile, SectionParams,
};

fn params(config: &ModelConfig) -> (ModelParams, HashMap<String, f64>) {
    let n = config.sections();
    let mut env = HashMap::new();
    let mut sections = Vec::new();
    for k in 1..=n {
        let s = SectionParams {
            length: 1.35 - 0.1 * k as f64,
            mass_per_length: 7.85 + k as f64,
            bending_stiffness: 1743.0 * (1.0 + 0.3 * k as f64),
            modes: config.modes[k - 1],
        };
        env.insert(format!("l_{k}"), s.length);
        env.insert(format!("rho_a_{k}"), s.mass_per_length);
        env.insert(format!("ei_{k}"), s.bending_stiffness);
        sections.push(s);
    }
    env.insert("m_t".into(), 100.0);
    env.insert("m_l".into(), 17.897);
    env.insert("g".into(), 9.81);
    let p = ModelParams {
        damping: Default::default(),
        basis: Default::default(),
        sections,
        vehicle_mass: 100.0,
        load_mass: 17.897,
        gravity: 9.81,
        force_flow: match config.force_flow {
            ForceFlow::Cable => telescopic_runtime::ForceFlow::Cable,
            ForceFlow::External => telescopic_runtime::ForceFlow::External,
            ForceFlow::None => telescopic_runtime::ForceFlow::None,
        },
        contact_points: config.contacts,
        contact: ContactLaw {
            stiffness: 2.375e8,
            damping: 1000.0,
            clearance: 0.0,
        },
        positions: vec![Profile::Constant(0.9); n - 1],
        drive: Drive::Force(Profile::Constant(100.0)),
    };
    (p, env)
}

#[test]
fn derived_matrices_match_the_assembled_model() {
    for (modes, flow, with_static) in [
        (vec![3, 4], ForceFlow::Cable, false),
        (vec![5, 5], ForceFlow::External, false),
        (vec![4, 3, 3], ForceFlow::Cable, false),
        (vec![12], ForceFlow::Cable, false),
        // the static correction shapes: exact integrals and Gram-Schmidt in 512 bits against
        // quadrature and Householder QR in f64
        (vec![3, 4], ForceFlow::Cable, true),
        (vec![6, 6], ForceFlow::None, true),
        (vec![4, 3, 3], ForceFlow::External, true),
    ] {
        let mut config = ModelConfig {
            modes: modes.clone(),
            contacts: 3,
            force_flow: flow,
            clearance: false,
            positions: Positions::Fixed,
            drive: DriveKind::Force,
            static_knots: None,
        };
        let (mut p, mut env) = params(&config);
        if with_static {
            p.basis = telescopic_runtime::Basis::ModesAndStatic;
            config.static_knots = telescopic_runtime::config_of(&p).static_knots;
        }
        let d = derive(&config).unwrap();
        for c in &d.constants {
            env.insert(c.name.clone(), c.value);
        }
        let lookup = |s: &str| *env.get(s).unwrap_or_else(|| panic!("no value for {s}"));
        let model = AssembledModel::new(&p).unwrap();
        for (name, entries, reference) in [
            ("M", &d.mass, model.mass_matrix()),
            ("K", &d.stiffness, model.stiffness_matrix()),
        ] {
            let scale = reference.abs().max();
            let mut derived = nalgebra::DMatrix::zeros(config.dof(), config.dof());
            for ((i, j), e) in entries {
                derived[(*i, *j)] = e.eval(&lookup, &[]);
                derived[(*j, *i)] = derived[(*i, *j)];
            }
            let diff = (&derived - reference).abs().max();
            // with corrections, the f64 side's QR of functions near the modes' span loses
            // digits to the Gram matrix's condition (measured up to 1.1e-12 of the scale)
            let tolerance = if with_static { 1e-11 } else { 1e-12 };
            assert!(
                diff <= tolerance * scale,
                "{modes:?} {flow:?} (static {with_static}): {name} differs by {diff:e} (scale {scale:e})"
            );
        }
    }
}
