//! The quadrature-assembled Galerkin matrices: converged quadrature, orthogonality of the
//! modes, closed-form integrals, and the change to computing coordinates against the
//! paper-basis matrices of docs/model.md section 4.

mod common;

use approx::assert_relative_eq;
use nalgebra::DMatrix;
use telescopic_runtime::model::quadrature::SectionQuadrature;
use telescopic_runtime::{
    AssembledModel, Model, ModelParams, SectionKind, SectionParams, SectionShapes,
    paper_section_matrices,
};

fn section(modes: usize) -> SectionParams {
    common::rig_section(modes)
}

/// The rig with a different upper section, to break the symmetry of the two.
fn two_sections(modes: [usize; 2], gravity: f64, vehicle: f64, load: f64) -> ModelParams {
    let mut p = common::rig(modes);
    p.sections[1] = SectionParams {
        length: 1.1,
        mass_per_length: 5.0,
        bending_stiffness: 900.0,
        modes: modes[1],
    };
    ModelParams {
        damping: Default::default(),
        basis: Default::default(),
        gravity,
        vehicle_mass: vehicle,
        load_mass: load,
        ..p
    }
}

/// Largest off-diagonal entry relative to the diagonal entries it couples.
fn off_diagonal(m: &DMatrix<f64>, skip: &[(usize, usize)]) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 0..m.nrows() {
        for j in 0..m.ncols() {
            if i != j && !skip.contains(&(i, j)) && !skip.contains(&(j, i)) {
                let scale = (m[(i, i)].abs() * m[(j, j)].abs())
                    .sqrt()
                    .max(f64::MIN_POSITIVE);
                worst = worst.max(m[(i, j)].abs() / scale);
            }
        }
    }
    worst
}

#[test]
fn quadrature_is_converged_for_mode_30() {
    // n = ceil(beta_max) + 16 points against twice as many
    let s = section(30);
    for kind in [SectionKind::GuidedFree, SectionKind::FreeFree] {
        let shapes = SectionShapes::new(kind, 30, s.length);
        let n = SectionQuadrature::points_for(shapes.max_beta());
        let coarse = SectionQuadrature::with_points(s.length, n);
        let fine = SectionQuadrature::with_points(s.length, 2 * n);
        for f in shapes.functions() {
            for g in shapes.functions() {
                for d in 0..=2u8 {
                    let a = coarse.integrate(|x| f.eval(x, d) * g.eval(x, d) * (1.0 + x));
                    let b = fine.integrate(|x| f.eval(x, d) * g.eval(x, d) * (1.0 + x));
                    let scale = (f.wavenumber().max(1.0) * g.wavenumber().max(1.0)).powi(d as i32)
                        * s.length;
                    assert!(
                        (a - b).abs() <= 1e-13 * scale,
                        "{kind:?} {} {} d={d}: {a} vs {b}",
                        f.index(),
                        g.index()
                    );
                }
            }
        }
    }
}

#[test]
fn free_free_modes_have_closed_form_norms() {
    // With the printed normalisation: int phi^2 = l and int phi''^2 = kap^4 l for i >= 3;
    // the rigid modes give int 1 = l, int x^2 = l^3/3, int x = l^2/2.
    let s = SectionParams {
        modes: 30,
        ..section(30)
    };
    let (m, k) = paper_section_matrices(
        &SectionParams {
            mass_per_length: 1.0,
            bending_stiffness: 1.0,
            ..s
        },
        SectionKind::FreeFree,
        (0.0, 0.0),
    );
    let l = s.length;
    assert_relative_eq!(m[(0, 0)], l, max_relative = 1e-13);
    assert_relative_eq!(m[(1, 1)], l.powi(3) / 3.0, max_relative = 1e-13);
    assert_relative_eq!(m[(0, 1)], l * l / 2.0, max_relative = 1e-13);
    let shapes = SectionShapes::new(SectionKind::FreeFree, 30, l);
    for (i, f) in shapes.functions().iter().enumerate().skip(2) {
        assert_relative_eq!(m[(i, i)], l, max_relative = 1e-12);
        assert_relative_eq!(k[(i, i)], f.wavenumber().powi(4) * l, max_relative = 1e-12);
    }
}

#[test]
fn modes_are_orthogonal_without_point_masses_and_gravity() {
    for kind in [SectionKind::GuidedFree, SectionKind::FreeFree] {
        let (m, k) = paper_section_matrices(&section(30), kind, (0.0, 0.0));
        // free-free: the rigid modes 1 and x are coupled in M (int x dx != 0), nothing else
        let skip: &[(usize, usize)] = if kind == SectionKind::FreeFree {
            &[(0, 1)]
        } else {
            &[]
        };
        let off_m = off_diagonal(&m, skip);
        assert!(off_m < 1e-12, "{kind:?}: M off-diagonal {off_m:e}");
        // K has zero rows for the rigid modes; scale its elastic part by its diagonal
        let first = if kind == SectionKind::FreeFree { 2 } else { 1 };
        let k_el = k
            .view((first, first), (30 - first, 30 - first))
            .into_owned();
        let off_k = off_diagonal(&k_el, &[]);
        assert!(off_k < 1e-12, "{kind:?}: K off-diagonal {off_k:e}");
        let rigid_rows = k.rows(0, first).abs().max();
        assert!(
            rigid_rows < 1e-9 * k[(29, 29)],
            "{kind:?}: rigid rows of K {rigid_rows:e}"
        );
        if kind == SectionKind::FreeFree {
            assert!(m[(0, 1)].abs() > 0.1, "the rigid modes 1 and x must couple");
        }
    }
}

/// The paper-basis block-diagonal `M`, `K` of docs/model.md section 4 (point masses included)
/// and the map `q = T z` of the computing coordinates, built independently of the model.
fn paper_system(p: &ModelParams) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    let dof: usize = p.sections.iter().map(|s| s.modes).sum();
    let mut m = DMatrix::zeros(dof, dof);
    let mut k = DMatrix::zeros(dof, dof);
    let mut t = DMatrix::identity(dof, dof);
    let mut offset = 0;
    let n = p.sections.len();
    for (k0, s) in p.sections.iter().enumerate() {
        let kind = SectionKind::of_section(k0 + 1);
        let (mk, kk) = paper_section_matrices(s, kind, p.prestress(k0 + 1));
        let shapes = SectionShapes::new(kind, s.modes, s.length);
        let mut mk = mk;
        if k0 == 0 {
            let at0: Vec<f64> = shapes.functions().iter().map(|f| f.eval(0.0, 0)).collect();
            mk += p.vehicle_mass * DMatrix::from_fn(s.modes, s.modes, |i, j| at0[i] * at0[j]);
            // q_{1,1} = (u - sum_{i>=2} q_{1,i} phi_i(0)) / 2
            t[(0, 0)] = 0.5;
            for i in 1..s.modes {
                t[(0, i)] = -0.5 * at0[i];
            }
        } else {
            t[(offset, 0)] = 1.0; // q_{k,1} = z_{k,1} + u
        }
        if k0 == n - 1 {
            let top: Vec<f64> = shapes
                .functions()
                .iter()
                .map(|f| f.eval(s.length, 0))
                .collect();
            mk += p.load_mass * DMatrix::from_fn(s.modes, s.modes, |i, j| top[i] * top[j]);
        }
        m.view_mut((offset, offset), (s.modes, s.modes))
            .copy_from(&mk);
        k.view_mut((offset, offset), (s.modes, s.modes))
            .copy_from(&kk);
        offset += s.modes;
    }
    (m, k, t)
}

#[test]
fn computing_coordinates_are_an_exact_change_of_variables() {
    for (modes, g) in [([5, 5], 9.81), ([4, 7], 0.0), ([12, 3], 9.81)] {
        let p = two_sections(modes, g, 100.0, 17.897);
        let model = AssembledModel::new(&p).unwrap();
        let (m, k, t) = paper_system(&p);
        let m_z = t.transpose() * &m * &t;
        let k_z = t.transpose() * &k * &t;
        let scale_m = m_z.abs().max();
        let scale_k = k_z.abs().max();
        assert!(
            (model.mass_matrix() - &m_z).abs().max() < 1e-12 * scale_m,
            "M for {modes:?}"
        );
        assert!(
            (model.stiffness_matrix() - &k_z).abs().max() < 1e-12 * scale_k,
            "K for {modes:?}"
        );
        // b = T' b_paper with b_paper = phi_{1,i}(0) on section 1's rows
        let shapes = SectionShapes::new(SectionKind::GuidedFree, modes[0], 1.35);
        let mut b = nalgebra::DVector::zeros(m.nrows());
        for (i, f) in shapes.functions().iter().enumerate() {
            b[i] = f.eval(0.0, 0);
        }
        let b_z = t.transpose() * b;
        assert!((model.drive_vector() - b_z).abs().max() < 1e-13);
    }
}

#[test]
fn mass_matrix_carries_the_total_mass_on_the_translation() {
    let p = two_sections([5, 5], 9.81, 100.0, 17.897);
    let model = AssembledModel::new(&p).unwrap();
    assert_relative_eq!(
        model.mass_matrix()[(0, 0)],
        p.total_mass(),
        max_relative = 1e-14
    );
    // the translation stores no elastic or prestress energy
    assert_eq!(model.stiffness_matrix().row(0).abs().max(), 0.0);
}
