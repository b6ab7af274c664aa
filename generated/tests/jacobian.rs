//! The generated Jacobian against central differences of the generated right-hand side, in
//! fixed contact branches (away from the kinks of the law), for every generated model.

use telescopic_runtime::{
    ContactLaw, ContactState, Drive, ForceFlow, ModelParams, Profile, SectionParams, ShapedProfile,
};

fn params(
    modes: &[usize],
    flow: ForceFlow,
    clearance: f64,
    moving: bool,
    motion: bool,
    contacts: usize,
) -> ModelParams {
    let n = modes.len();
    ModelParams {
        damping: Default::default(),
        basis: Default::default(),
        sections: modes
            .iter()
            .enumerate()
            .map(|(k, &m)| SectionParams {
                length: 1.35,
                mass_per_length: 15.7 / (1.0 + k as f64),
                bending_stiffness: 6972.0 / (1.0 + k as f64),
                modes: m,
            })
            .collect(),
        vehicle_mass: 100.0,
        load_mass: 17.897,
        gravity: 9.81,
        force_flow: flow,
        contact_points: contacts,
        contact: ContactLaw {
            stiffness: 2.375e8,
            damping: 1000.0,
            clearance,
        },
        positions: (1..n)
            .map(|_| {
                if moving {
                    Profile::Shaped(ShapedProfile::Smoothstep {
                        start: 0.0,
                        end: 12.0,
                        from: 0.35,
                        to: 1.15,
                    })
                } else {
                    Profile::Constant(1.0)
                }
            })
            .collect(),
        drive: if motion {
            Drive::Motion(Profile::Shaped(ShapedProfile::Smoothstep {
                start: 0.0,
                end: 6.0,
                from: 0.0,
                to: 3.0,
            }))
        } else {
            Drive::Force(Profile::Constant(100.0))
        },
    }
}

#[test]
fn generated_jacobians_match_central_differences() {
    let cases = [
        params(&[5, 5], ForceFlow::Cable, 0.0, false, false, 3),
        params(&[4, 4], ForceFlow::Cable, 0.01, true, false, 2),
        params(&[4, 4, 4], ForceFlow::Cable, 0.005, false, false, 2),
        params(&[3, 4], ForceFlow::External, 0.0, true, true, 2),
    ];
    for p in cases {
        let model = telescopic_generated::prepare(&p)
            .expect("listed in models.toml")
            .unwrap();
        let key = telescopic_runtime::configuration_key(&p);
        let n2 = 2 * model.dof();
        let nc = model.layout().contact_count();
        for (trial, t) in [0.5, 5.0, 9.0].into_iter().enumerate() {
            let y: Vec<f64> = (0..n2)
                .map(|i| {
                    4e-3 * (((i * 37 + trial * 11) % 17) as f64 / 8.0 - 1.0)
                        + if i == 0 { 6.0 } else { 0.0 }
                })
                .collect();
            let (mut xi, mut xid) = (vec![0.0; nc], vec![0.0; nc]);
            model.contact_gaps(t, &y, &mut xi, &mut xid);
            let states: Vec<ContactState> = xi.iter().map(|&x| p.contact.state(x)).collect();
            telescopic_runtime::analysis::check::jacobian_against_differences(
                model.as_ref(),
                t,
                &y,
                &states,
            )
            .unwrap_or_else(|e| panic!("{key}: {e}"));
        }
    }
}
