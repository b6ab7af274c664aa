//! The first-order right-hand side and its Jacobian: finite differences, momentum and power
//! balances, and contact gaps against the paper-basis displacement field.

mod common;

use common::Rng;
use nalgebra::DVector;
use telescopic_runtime::{
    AssembledModel, ContactLaw, ContactState, Drive, ForceFlow, Model, ModelParams, Profile,
    SectionKind, SectionParams, SectionShapes, ShapedProfile,
};

fn ramp() -> Profile {
    Profile::Shaped(ShapedProfile::Smoothstep {
        start: 0.0,
        end: 12.0,
        from: 0.35,
        to: 1.15,
    })
}

/// A set of configurations covering the code paths: fixed and moving positions, clearance,
/// three sections, prescribed motion, force flows.
fn configurations() -> Vec<(&'static str, ModelParams)> {
    let sec = |l: f64, ra: f64, ei: f64, modes: usize| SectionParams {
        length: l,
        mass_per_length: ra,
        bending_stiffness: ei,
        modes,
    };
    let base = common::rig([5, 5]);
    let moving = ModelParams {
        sections: vec![sec(1.35, 7.85, 1743.0, 4), sec(1.35, 7.85, 1743.0, 4)],
        contact_points: 2,
        contact: ContactLaw {
            clearance: 0.01,
            ..base.contact
        },
        positions: vec![ramp()],
        ..base.clone()
    };
    let three = ModelParams {
        sections: vec![
            sec(1.35, 15.7, 6972.0, 4),
            sec(1.35, 11.775, 3486.0, 5),
            sec(1.35, 7.85, 1743.0, 3),
        ],
        contact_points: 2,
        contact: ContactLaw {
            clearance: 0.005,
            ..base.contact
        },
        positions: vec![Profile::Constant(1.0), ramp()],
        force_flow: ForceFlow::External,
        ..base.clone()
    };
    let motion = ModelParams {
        drive: Drive::Motion(Profile::Shaped(ShapedProfile::Smoothstep {
            start: 0.0,
            end: 4.0,
            from: 0.0,
            to: 2.0,
        })),
        ..moving.clone()
    };
    vec![
        ("fixed, linear law", base),
        ("moving, clearance", moving),
        ("three sections", three),
        ("prescribed motion", motion),
    ]
}

fn random_state(model: &AssembledModel, rng: &mut Rng, amplitude: f64) -> Vec<f64> {
    let n = model.dof();
    let mut y: Vec<f64> = (0..2 * n).map(|_| amplitude * rng.next()).collect();
    y[0] = 7.0 + rng.next(); // the vehicle far from the origin, as in the scenes
    y
}

fn states_of(model: &AssembledModel, t: f64, y: &[f64]) -> Vec<ContactState> {
    let nc = model.layout().contact_count();
    let (mut xi, mut xid) = (vec![0.0; nc], vec![0.0; nc]);
    model.contact_gaps(t, y, &mut xi, &mut xid);
    xi.iter()
        .map(|&x| model.params().contact.state(x))
        .collect()
}

#[test]
fn jacobian_matches_central_differences() {
    let mut rng = Rng(0x9e3779b97f4a7c15);
    for (name, p) in configurations() {
        let model = AssembledModel::new(&p).unwrap();
        for trial in 0..4 {
            let t = 1.0 + 2.5 * trial as f64;
            let y = random_state(&model, &mut rng, 4e-3);
            // fix the branches: the law is then smooth and differences are meaningful
            let states = states_of(&model, t, &y);
            telescopic_runtime::analysis::check::jacobian_against_differences(
                &model, t, &y, &states,
            )
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }
}

#[test]
fn total_momentum_changes_at_the_drive_force() {
    // row 0 of M zdd is the rate of total momentum; contacts are internal forces
    let mut rng = Rng(42);
    for (name, p) in configurations()
        .into_iter()
        .filter(|(_, p)| matches!(p.drive, Drive::Force(_)))
    {
        let model = AssembledModel::new(&p).unwrap();
        let n = model.dof();
        for _ in 0..5 {
            let y = random_state(&model, &mut rng, 1e-2);
            let mut ydot = vec![0.0; 2 * n];
            model.rhs(3.0, &y, None, &mut ydot);
            let rate: f64 = model
                .mass_matrix()
                .row(0)
                .iter()
                .zip(&ydot[n..])
                .map(|(a, b)| a * b)
                .sum();
            let biggest_force = model.stiffness_matrix().abs().max() * 1e-2 + 2.4e8 * 1e-2;
            assert!(
                (rate - 100.0).abs() < 1e-11 * biggest_force,
                "{name}: dp/dt = {rate}"
            );
        }
    }
}

#[test]
fn power_balance_with_fixed_positions() {
    // d/dt (kinetic + elastic + contact springs) = F u' - sum D(xi) xi'^2 with fixed a_k
    let mut rng = Rng(7);
    let (name, p) = configurations().remove(0);
    for clearance in [0.0, 0.002] {
        let p = ModelParams {
            contact: ContactLaw {
                clearance,
                ..p.contact
            },
            ..p.clone()
        };
        let model = AssembledModel::new(&p).unwrap();
        let n = model.dof();
        let nc = model.layout().contact_count();
        for _ in 0..5 {
            let y = random_state(&model, &mut rng, 5e-3);
            let mut ydot = vec![0.0; 2 * n];
            model.rhs(0.5, &y, None, &mut ydot);
            let z = DVector::from_column_slice(&y[..n]);
            let zd = DVector::from_column_slice(&y[n..]);
            let zdd = DVector::from_column_slice(&ydot[n..]);
            let (mut xi, mut xid) = (vec![0.0; nc], vec![0.0; nc]);
            model.contact_gaps(0.5, &y, &mut xi, &mut xid);
            let law = p.contact;
            let spring_power: f64 = xi
                .iter()
                .zip(&xid)
                .map(|(&x, &v)| law.force(x, 0.0).force * v)
                .sum();
            let dissipation: f64 = xi
                .iter()
                .zip(&xid)
                .map(|(&x, &v)| law.force(x, v).d_rate * v * v)
                .sum();
            let de_dt = zd.dot(&(model.mass_matrix() * &zdd))
                + z.dot(&(model.stiffness_matrix() * &zd))
                + spring_power;
            let expected = 100.0 * zd[0] - dissipation;
            let scale =
                zd.dot(&(model.mass_matrix() * &zdd)).abs() + dissipation + spring_power.abs();
            assert!(
                (de_dt - expected).abs() < 1e-10 * scale,
                "{name}, l_S = {clearance}: {de_dt} vs {expected}"
            );
        }
    }
}

/// `w_k(x)` from the paper's coordinates `q = T z` and the paper's shape functions directly.
fn paper_displacement(p: &ModelParams, z: &[f64], k: usize, x: f64) -> f64 {
    let shapes: Vec<SectionShapes> = p
        .sections
        .iter()
        .enumerate()
        .map(|(i, s)| SectionShapes::new(SectionKind::of_section(i + 1), s.modes, s.length))
        .collect();
    let offsets: Vec<usize> = p
        .sections
        .iter()
        .scan(0, |a, s| {
            let o = *a;
            *a += s.modes;
            Some(o)
        })
        .collect();
    let mut q = z.to_vec();
    let phi1_0: f64 = shapes[0]
        .functions()
        .iter()
        .skip(1)
        .enumerate()
        .map(|(i, f)| z[i + 1] * f.eval(0.0, 0))
        .sum();
    q[0] = 0.5 * (z[0] - phi1_0);
    for k in 2..=p.sections.len() {
        q[offsets[k - 1]] += z[0];
    }
    shapes[k - 1]
        .functions()
        .iter()
        .enumerate()
        .map(|(i, f)| q[offsets[k - 1] + i] * f.eval(x, 0))
        .sum()
}

#[test]
fn gaps_are_differences_of_the_paper_displacement_field() {
    let mut rng = Rng(99);
    for (name, p) in configurations() {
        let model = AssembledModel::new(&p).unwrap();
        let n = model.dof();
        let nc = model.layout().contact_count();
        for t in [0.0, 3.3, 7.0, 12.5] {
            let y = random_state(&model, &mut rng, 1e-2);
            let (mut xi, mut xid) = (vec![0.0; nc], vec![0.0; nc]);
            model.contact_gaps(t, &y, &mut xi, &mut xid);
            for (c, cp) in model.layout().contacts().enumerate() {
                let k = cp.overlap;
                let a = p.positions[k - 2].value(t);
                let o = p.sections[k - 2].length - a;
                let want = paper_displacement(&p, &y[..n], k, cp.fraction * o)
                    - paper_displacement(&p, &y[..n], k - 1, a + cp.fraction * o);
                assert!(
                    (xi[c] - want).abs() < 1e-13,
                    "{name} t = {t} contact {c}: {} vs {want}",
                    xi[c]
                );
                // the vehicle position itself
                assert!((paper_displacement(&p, &y[..n], 1, 0.0) - y[0]).abs() < 1e-13);
            }
            // xi_dot: the total time derivative, by differences of xi along the motion
            let h = 1e-6;
            let step = |s: f64| {
                let yy: Vec<f64> = (0..n)
                    .map(|j| y[j] + s * y[n + j])
                    .chain(y[n..].iter().copied())
                    .collect();
                let (mut x, mut v) = (vec![0.0; nc], vec![0.0; nc]);
                model.contact_gaps(t + s, &yy, &mut x, &mut v);
                x
            };
            let (xp, xm) = (step(h), step(-h));
            for c in 0..nc {
                let fd = (xp[c] - xm[c]) / (2.0 * h);
                assert!(
                    (fd - xid[c]).abs() < 1e-7 * (1.0 + xid[c].abs()),
                    "{name} t = {t}: xi_dot {} vs {fd}",
                    xid[c]
                );
            }
        }
    }
}

#[test]
fn prescribed_motion_reaction_reproduces_the_motion_as_a_force_drive() {
    let mut rng = Rng(5);
    let (_, p) = configurations().remove(3);
    let held = AssembledModel::new(&p).unwrap();
    let n = held.dof();
    for t in [0.7, 2.0, 3.1] {
        let y = random_state(&held, &mut rng, 2e-3);
        let mut ydot = vec![0.0; 2 * n];
        held.rhs(t, &y, None, &mut ydot);
        let Drive::Motion(s) = &p.drive else {
            unreachable!()
        };
        assert_eq!(ydot[n], s.acceleration(t));
        let mut out = vec![0.0; held.output_names().len()];
        held.outputs(t, &y, &ydot, &mut out);
        let reaction = *out.last().unwrap();
        // the same state driven by that force must accelerate identically
        let forced = AssembledModel::new(&ModelParams {
            drive: Drive::Force(Profile::Constant(reaction)),
            ..p.clone()
        })
        .unwrap();
        let mut ydot_f = vec![0.0; 2 * n];
        forced.rhs(t, &y, None, &mut ydot_f);
        let scale = ydot[n..].iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        for j in n..2 * n {
            assert!(
                (ydot[j] - ydot_f[j]).abs() < 1e-9 * scale,
                "t = {t}, row {j}: {} vs {}",
                ydot[j],
                ydot_f[j]
            );
        }
    }
}

#[test]
fn outputs_follow_the_definitions() {
    let (_, p) = configurations().remove(1);
    let model = AssembledModel::new(&p).unwrap();
    let n = model.dof();
    let mut rng = Rng(11);
    let y = random_state(&model, &mut rng, 1e-2);
    let mut ydot = vec![0.0; 2 * n];
    model.rhs(2.0, &y, None, &mut ydot);
    let names = model.output_names();
    let mut out = vec![0.0; names.len()];
    model.outputs(2.0, &y, &ydot, &mut out);
    let get = |name: &str| out[names.iter().position(|x| x == name).unwrap()];
    let w = |k: usize, x: f64| paper_displacement(&p, &y[..n], k, x);
    assert!((get("vehicle") - w(1, 0.0)).abs() < 1e-13);
    assert!((get("tip_rel") - (w(2, 1.35) - w(1, 0.0))).abs() < 1e-13);
    assert!((get("top1_rel") - (w(1, 1.35) - w(1, 0.0))).abs() < 1e-13);
    let (xi, f) = (get("xi_2_1"), get("f_2_1"));
    assert_eq!(
        f == 0.0,
        xi.abs() <= 0.005,
        "force only outside the band: xi {xi}, f {f}"
    );
}
