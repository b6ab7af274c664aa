//! The mode-shape picture: drawn to a file, and its curves are the eigenvectors: each
//! plotted section's deflection equals the mode shape of the assembled model's own eigen
//! analysis (another model, another path) evaluated along the section, and satisfies the
//! eigen problem's scale (largest |w| = 1); contact modes are named as such.

use telescopic::Scene;
use telescopic::analysis::modes::{ModeKind, ModesOptions, compute_modes};
use telescopic::plot::modes::ModeShapeFigure;
use telescopic::run::models::ModelChoice;
use telescopic::runtime::{AssembledModel, Model, modal_analysis};

#[test]
fn the_plotted_shapes_are_the_eigenvectors_and_the_picture_is_drawn() {
    let scene = Scene::load("scenes/test-rig.toml".as_ref(), &[]).unwrap();
    let points = 31;
    let options = ModesOptions {
        shapes: Some(points),
        model: ModelChoice::Generated,
        ..ModesOptions::default()
    };
    let report = compute_modes(&scene, &options).unwrap();
    let figure = ModeShapeFigure::new(&scene, &report).unwrap();
    assert_eq!(figure.modes.len(), 8);
    // the assembled model's own eigenvectors
    let assembled = AssembledModel::new(&scene.params).unwrap();
    let modal = modal_analysis(&assembled, 0.0).unwrap();
    for (i, mode) in figure.modes.iter().enumerate() {
        let v = &modal.shapes[i];
        let w: Vec<Vec<f64>> = mode
            .sections
            .iter()
            .map(|c| {
                let l = scene.params.sections[c.section - 1].length;
                (0..points)
                    .map(|j| {
                        assembled.displacement(
                            c.section,
                            l * j as f64 / (points - 1) as f64,
                            v.as_slice(),
                        )
                    })
                    .collect()
            })
            .collect();
        let peak = w.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()));
        // the sign of an eigenvector is arbitrary
        let first = mode.sections[0]
            .deflections
            .iter()
            .chain(&mode.sections[1].deflections);
        let reference = w.iter().flatten();
        let dot: f64 = first
            .clone()
            .zip(reference.clone())
            .map(|(a, b)| a * b)
            .sum();
        let sign = dot.signum();
        let worst = first
            .zip(reference)
            .map(|(a, b)| (a - sign * b / peak).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-6,
            "mode {}: plotted shape differs from the eigenvector by {worst}",
            i + 1
        );
        let plotted_peak = mode
            .sections
            .iter()
            .flat_map(|c| &c.deflections)
            .fold(0.0_f64, |m, x| m.max(x.abs()));
        assert!((plotted_peak - 1.0).abs() < 1e-12);
        assert!(
            mode.title
                .contains(&format!("{:.4} Hz", modal.frequencies_hz[i])),
            "{}",
            mode.title
        );
    }
    // section 2 stands on section 1 at a_2 = 1.15 m
    assert_eq!(figure.modes[0].sections[1].heights[0], 1.15);
    assert!((figure.height - 2.5).abs() < 1e-12);
    // the 3 kHz modes are the contacts' (their strain energy is in the springs)
    assert_eq!(report.kinds[7], ModeKind::Contact);
    assert!(
        report.contact_energy_shares[7] > 0.9,
        "{:?}",
        report.contact_energy_shares
    );
    assert_eq!(report.kinds[0], ModeKind::Structural);
    assert!(report.contact_energy_shares[0] < 0.1);
    assert!(figure.modes[7].title.contains("contact mode"));
    let dir = std::env::temp_dir().join(format!("telescopic-mode-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("modes.svg");
    figure.save(&path).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(
        svg.contains("f8 = 2999.0175 Hz") && svg.contains("contact mode"),
        "labels in the picture"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
