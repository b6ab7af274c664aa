//! Every generated model against the quadrature-assembled model of the runtime: `M`, `K`,
//! `b`, contact vectors and their rates, right-hand side and Jacobian, at several states,
//! times and telescopic positions. Two independent paths: closed-form 512-bit integrals,
//! Symbolica and emitted code vs Gauss-Legendre quadrature and generic code.

use nalgebra::DMatrix;
use telescopic_codegen::{DriveKind, ForceFlow, ModelConfig, ModelList, Positions};
use telescopic_generated::{CONFIGURATIONS, prepare};
use telescopic_runtime::configuration_key as key_for;
use telescopic_runtime::{
    AssembledModel, Basis, ContactLaw, ContactState, Drive, Model, ModelParams, Profile,
    SectionParams, ShapedProfile, StructuralDamping,
};

fn configs() -> Vec<ModelConfig> {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/models.toml")).unwrap();
    toml::from_str::<ModelList>(&text).unwrap().model
}

/// Structural damping in the template's code path by variant: none, modal, Rayleigh.
fn damping_of(variant: usize, positions: &[Profile]) -> StructuralDamping {
    match variant {
        0 => StructuralDamping::None,
        1 => StructuralDamping::Modal {
            ratios: vec![0.03, 0.01, 0.05],
            positions: positions.iter().map(|p: &Profile| p.value(0.0)).collect(),
        },
        _ => StructuralDamping::Rayleigh {
            alpha: 0.4,
            beta: 2e-4,
        },
    }
}

/// A configuration with static correction shapes fits only the geometry its knots come
/// from: the shipped scene it was generated for, at its size, whose parameters give it.
fn scene_params_for(c: &ModelConfig, variant: usize) -> ModelParams {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let Ok(scene) = telescopic_runtime::Scene::load(&path, &[]) else {
            continue;
        };
        let mut p = scene.params;
        if p.sections.len() != c.sections() {
            continue;
        }
        p.basis = telescopic_runtime::Basis::ModesAndStatic;
        for (s, &m) in p.sections.iter_mut().zip(&c.modes) {
            s.modes = m;
        }
        if telescopic_runtime::config_of(&p) == *c {
            p.damping = damping_of(variant, &p.positions);
            p.vehicle_mass += 10.0 * variant as f64;
            return p;
        }
    }
    panic!("no shipped scene has the static knots of {}", c.key())
}

/// Parameters of a configuration, with distinct values per section so no symmetry hides an
/// index mistake.
fn params_for(c: &ModelConfig, variant: usize) -> ModelParams {
    if c.static_knots.is_some() {
        return scene_params_for(c, variant);
    }
    let n = c.sections();
    let v = variant as f64;
    let sections = (0..n)
        .map(|k| SectionParams {
            length: 1.35 - 0.05 * k as f64 + 0.01 * v,
            mass_per_length: 15.7 / (1.0 + 0.4 * k as f64),
            bending_stiffness: 6972.0 / (1.0 + k as f64).powi(2),
            modes: c.modes[k],
        })
        .collect();
    let positions: Vec<Profile> = (0..n.saturating_sub(1))
        .map(|k| match c.positions {
            Positions::Fixed => Profile::Constant(0.95 - 0.1 * k as f64 + 0.02 * v),
            Positions::Moving => Profile::Shaped(ShapedProfile::Smoothstep {
                start: 0.0,
                end: 12.0,
                from: 0.35,
                to: 1.15 - 0.1 * k as f64,
            }),
        })
        .collect();
    ModelParams {
        damping: damping_of(variant, &positions),
        sections,
        basis: Default::default(),
        vehicle_mass: 100.0 + 10.0 * v,
        load_mass: 17.897,
        gravity: 9.81,
        force_flow: match c.force_flow {
            ForceFlow::Cable => telescopic_runtime::ForceFlow::Cable,
            ForceFlow::External => telescopic_runtime::ForceFlow::External,
            ForceFlow::None => telescopic_runtime::ForceFlow::None,
        },
        contact_points: c.contacts,
        contact: ContactLaw {
            stiffness: 2.375e8,
            damping: 1000.0,
            clearance: if c.clearance { 0.004 } else { 0.0 },
        },
        positions,
        drive: match c.drive {
            DriveKind::Force => Drive::Force(Profile::Shaped(ShapedProfile::PiecewiseConstant {
                times: vec![0.0, 4.0, 8.0],
                values: vec![100.0, 0.0, -100.0],
            })),
            DriveKind::Motion => Drive::Motion(Profile::Shaped(ShapedProfile::Smoothstep {
                start: 0.0,
                end: 6.0,
                from: 0.0,
                to: 3.0,
            })),
        },
    }
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// Agreement of tabulated and exact contact-vector rates between table nodes: the basis'
/// table tolerance on the rate of its largest entry ([`Basis::table_tolerances`]), with a
/// factor 10 for a time whose own largest entry is smaller.
fn table_rel(c: &ModelConfig) -> f64 {
    let basis = match c.static_knots {
        Some(_) => Basis::ModesAndStatic,
        None => Basis::Modes,
    };
    10.0 * basis.table_tolerances().1
}

/// The least tolerance of a model with static correction shapes: the assembled side
/// orthogonalizes them by a Householder QR in f64 of functions near the modes' span, whose
/// rounding grows with the basis (measured largest differences: 3e-11 at 6 modes per section,
/// 4e-11 at 9, 1.8e-10 at 14, 2.9e-10 at 21); the generated side's are exact. Without them, 0.
fn static_floor(c: &ModelConfig) -> f64 {
    if c.static_knots.is_some() { 1e-9 } else { 0.0 }
}

/// `a` and `b` agree to `rel` (at least `floor`) of their largest entry.
fn assert_close(floor: f64, what: &str, a: &DMatrix<f64>, b: &DMatrix<f64>, rel: f64) {
    let rel = rel.max(floor);
    let scale = b.abs().max().max(a.abs().max());
    let diff = (a - b).abs().max();
    if std::env::var_os("SHOW_DIFFS").is_some() {
        eprintln!("DIFF {:e} {what}", diff / scale);
    }
    assert!(
        diff <= rel * scale,
        "{what}: differs by {diff:e} at scale {scale:e}"
    );
}

#[test]
fn every_listed_configuration_was_generated_and_is_found_by_key() {
    let list = configs();
    assert_eq!(CONFIGURATIONS.len(), list.len());
    for c in &list {
        let p = params_for(c, 0);
        assert_eq!(
            key_for(&p),
            c.key(),
            "the runtime's key must be the generator's"
        );
        assert!(prepare(&p).is_some(), "{} not in the registry", c.key());
    }
}

/// `M`, `K`, `b` and `D_s` of the two models (`variant` 0 has no structural damping).
fn compare_matrices(
    (key, floor): (&str, f64),
    variant: usize,
    generated: &dyn Model,
    assembled: &dyn Model,
) {
    assert_close(
        floor,
        &format!("{key}: M"),
        generated.mass_matrix(),
        assembled.mass_matrix(),
        1e-12,
    );
    assert_close(
        floor,
        &format!("{key}: K"),
        generated.stiffness_matrix(),
        assembled.stiffness_matrix(),
        1e-12,
    );
    assert_eq!(
        generated.drive_vector(),
        assembled.drive_vector(),
        "{key}: b"
    );
    match (generated.damping_matrix(), assembled.damping_matrix()) {
        (None, None) => assert_eq!(variant, 0, "{key}: damping given, none built"),
        (Some(d1), Some(d2)) => assert_close(floor, &format!("{key}: D_s"), d1, d2, 1e-10),
        _ => panic!("{key}: one model has structural damping, the other not"),
    }
}

/// The outputs and the displacements of the two models at `(t, y)`; `rel` is the contact
/// vectors' tolerance there (above 1e-12 between table nodes).
fn compare_outputs(
    (key, floor): (&str, f64),
    p: &ModelParams,
    t: f64,
    y: &[f64],
    rel: f64,
    generated: &dyn Model,
    assembled: &dyn Model,
) {
    let n = assembled.dof();
    let names = assembled.output_names();
    assert_eq!(generated.output_names(), names);
    let mut ydot = vec![0.0; 2 * n];
    assembled.rhs(t, y, None, &mut ydot);
    let (mut o1, mut o2) = (vec![0.0; names.len()], vec![0.0; names.len()]);
    generated.outputs(t, y, &ydot, &mut o1);
    assembled.outputs(t, y, &ydot, &mut o2);
    // between table nodes a contact force c (g . z) carries the 1e-12 of g, and
    // more where g . z is a small difference of larger terms (measured 3e-12)
    // with static correction shapes g agrees to 1e-11 (the f64 QR) or the tables' 1e-9
    // (their splines are only C2 in time, `Basis::table_tolerances`), and a contact force
    // c (g . z) carries it through the cancellation in g . z (measured 5.6e-10)
    let output_rel = match (floor > 0.0, rel > 1e-12) {
        (true, _) => 1e-8,
        (false, true) => 1e-10,
        (false, false) => 1e-12,
    };
    for (i, name) in names.iter().enumerate() {
        let scale = o2[i].abs().max(1e-9);
        assert!(
            (o1[i] - o2[i]).abs()
                <= output_rel * scale.max(o2.iter().fold(0.0_f64, |m, v| m.max(v.abs())) * 1e-3),
            "{key}: output {name}: {} vs {}",
            o1[i],
            o2[i]
        );
    }
    for k in 1..=p.sections.len() {
        let x = 0.37 * p.sections[k - 1].length;
        let (w1, w2) = (
            generated.displacement(k, x, &y[..n]),
            assembled.displacement(k, x, &y[..n]),
        );
        assert!(
            (w1 - w2).abs() <= 1e-12 * w2.abs().max(1.0),
            "{key}: w_{k}: {w1} vs {w2}"
        );
    }
}

#[test]
fn generated_models_agree_with_the_assembled_model() {
    let mut rng = Rng(0x2545f4914f6cdd1d);
    for c in configs() {
        for variant in 0..3 {
            let p = params_for(&c, variant);
            let generated = prepare(&p).unwrap().unwrap();
            let assembled = AssembledModel::exact(&p).unwrap();
            let key = c.key();
            let floor = static_floor(&c);
            let n = assembled.dof();
            let nc = assembled.layout().contact_count();
            compare_matrices((&key, floor), variant, generated.as_ref(), &assembled);
            // moving positions: the generated model interpolates its contact vectors from a
            // table (telescopic_runtime::ContactTable), exact at the nodes (compared to 1e-12
            // there) and within the table's tolerances between them
            let times = [0.0, 2.7, 6.1, 11.5];
            let mut checks: Vec<(f64, f64)> = times.iter().map(|&t| (t, 1e-12)).collect();
            if let Some(table) = generated.contact_table() {
                let (start, _) = table.span();
                let node = |t: f64| start + ((t - start) / table.step()).round() * table.step();
                checks = times.iter().map(|&t| (node(t), 1e-12)).collect();
                checks.extend(times.iter().map(|&t| (t, table_rel(&c))));
            }
            for (t, rel) in checks {
                let (mut g1, mut gd1) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
                let (mut g2, mut gd2) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
                generated.contact_vectors(t, &mut g1, &mut gd1);
                assembled.contact_vectors(t, &mut g2, &mut gd2);
                assert_close(
                    floor,
                    &format!("{key} t = {t}: g"),
                    &g1,
                    &g2,
                    rel.min(1e-11),
                );
                if gd2.abs().max() > 0.0 {
                    assert_close(floor, &format!("{key} t = {t}: gdot"), &gd1, &gd2, rel);
                } else {
                    assert_eq!(gd1.abs().max(), 0.0, "{key}: fixed positions have no gdot");
                }
                let mut y: Vec<f64> = (0..2 * n).map(|_| 3e-3 * rng.next()).collect();
                y[0] = 5.0 + rng.next();
                let (mut xi, mut xid) = (vec![0.0; nc], vec![0.0; nc]);
                assembled.contact_gaps(t, &y, &mut xi, &mut xid);
                let states: Vec<ContactState> = xi.iter().map(|&x| p.contact.state(x)).collect();
                // with a band, also every contact held open (the generated right-hand side
                // then skips the contact vectors and gaps) and all but the first held closed
                let open = vec![ContactState::Free; nc];
                let mut mixed = vec![ContactState::Upper; nc];
                mixed[0] = ContactState::Free;
                let mut branch_sets = vec![None, Some(states.as_slice())];
                if p.contact.clearance > 0.0 {
                    branch_sets.extend([Some(open.as_slice()), Some(mixed.as_slice())]);
                }
                for st in branch_sets {
                    let (mut f1, mut f2) = (vec![0.0; 2 * n], vec![0.0; 2 * n]);
                    generated.rhs(t, &y, st, &mut f1);
                    assembled.rhs(t, &y, st, &mut f2);
                    let (a, b) = (
                        DMatrix::from_column_slice(2 * n, 1, &f1),
                        DMatrix::from_column_slice(2 * n, 1, &f2),
                    );
                    // between table nodes, g's 1e-12 of interpolation error reaches the
                    // accelerations of the highest modes through M^-1 (measured 1.7e-8 of the
                    // largest entry with 6 modes per section)
                    let rhs_rel = if rel > 1e-12 { 1e-7 } else { 1e-12 };
                    assert_close(floor, &format!("{key} t = {t}: rhs"), &a, &b, rhs_rel);
                    let (mut j1, mut j2) =
                        (DMatrix::zeros(2 * n, 2 * n), DMatrix::zeros(2 * n, 2 * n));
                    generated.jacobian(t, &y, st, &mut j1);
                    assembled.jacobian(t, &y, st, &mut j2);
                    assert_close(
                        floor,
                        &format!("{key} t = {t}: Jacobian"),
                        &j1,
                        &j2,
                        rhs_rel,
                    );
                }
                compare_outputs(
                    (&key, floor),
                    &p,
                    t,
                    &y,
                    rel,
                    generated.as_ref(),
                    &assembled,
                );
            }
        }
    }
}

#[test]
fn contact_vectors_at_given_positions_agree_and_match_the_time_path() {
    for c in configs().into_iter().filter(|c| c.sections() > 1) {
        let p = params_for(&c, 1);
        let generated = prepare(&p).unwrap().unwrap();
        let assembled = AssembledModel::exact(&p).unwrap();
        let (n, nc, npos) = (
            assembled.dof(),
            assembled.layout().contact_count(),
            c.sections() - 1,
        );
        let key = c.key();
        let floor = static_floor(&c);
        let at = |m: &dyn telescopic_runtime::Model, a: &[f64], r: &[f64]| {
            let (mut g, mut gd) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
            m.contact_vectors_at(a, r, &mut g, &mut gd);
            (g, gd)
        };
        // positions and speeds the scene never takes: an LPV model is evaluated anywhere
        for (a, r) in [(0.4, 0.0), (0.8, 0.3), (1.2, -0.5)] {
            let positions = vec![a; npos];
            let rates = vec![r; npos];
            let (g1, gd1) = at(generated.as_ref(), &positions, &rates);
            let (g2, gd2) = at(&assembled, &positions, &rates);
            assert_close(floor, &format!("{key}: g at a = {a}"), &g1, &g2, 1e-12);
            assert_close(floor, &format!("{key}: gdot at a = {a}"), &gd1, &gd2, 1e-12);
        }
        // at the scene's own positions they are the time path's vectors
        let t = 5.0;
        let positions: Vec<f64> = p.positions.iter().map(|q| q.value(t)).collect();
        let rates: Vec<f64> = p.positions.iter().map(|q| q.rate(t)).collect();
        let (g1, gd1) = at(&assembled, &positions, &rates);
        let (mut g2, mut gd2) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
        assembled.contact_vectors(t, &mut g2, &mut gd2);
        assert_close(floor, &format!("{key}: g(t) path"), &g1, &g2, 1e-15);
        assert_close(floor, &format!("{key}: gdot(t) path"), &gd1, &gd2, 1e-15);
    }
}
