//! Bending moments and stresses at stations: a single section as a cantilever under a static
//! tip force (analytic `M(x) = F (l - x)`) and under its own weight (the inertial load of a
//! steady acceleration, `q (l - x)^2 / 2`), the generated model's moments against the
//! assembled model's, stresses as `M / W`, and the documented refusals.

mod common;

use telescopic::run::models::ModelChoice;
use telescopic::run::stress::{Station, StressEnvelope};
use telescopic::run::{Column, SimulationOptions, simulate_scene};
use telescopic::runtime::{Output, Sensor};
use telescopic::{Error, Scene, Silent};

/// A single section on a vehicle pushed by a constant force; heavily damped (zeta = 0.5) so
/// that after 4 s it bends quasi-statically under the inertia of the steady acceleration.
fn pushed_cantilever(extra: &[String]) -> Scene {
    let mut o = vec!["sections.damping_ratio=0.5".to_string()];
    o.extend_from_slice(extra);
    common::single_section("pushed-cantilever", "force = 200.0", 4.0, 0.001, &o)
}

/// The relative errors of the final moments at `fractions` of the length against the
/// analytic static moment `-a (m_L (l - x) + rhoA (l - x)^2 / 2)`, `a = F / m_total`, and the
/// relative error of `EI w''` at the foot from the strain-gauge output `kappa_1_0`.
fn static_moment_errors(
    modes: usize,
    density: f64,
    load: f64,
    fractions: &[f64],
) -> (Vec<f64>, f64) {
    let scene = pushed_cantilever(&[
        format!("sections.modes={modes}"),
        format!("sections.density={density}"),
        format!("masses.load={load}"),
    ]);
    let l = scene.params.sections[0].length;
    let stations: Vec<Station> = fractions
        .iter()
        .map(|f| Station {
            section: 1,
            x: f * l,
        })
        .collect();
    let options = SimulationOptions {
        stations: stations.clone(),
        ..SimulationOptions::default()
    };
    let sim = simulate_scene(&scene, &options, &Silent).unwrap();
    let rho_a = scene.params.sections[0].mass_per_length;
    let a = 200.0 / scene.params.total_mass();
    let last = sim.trajectory.rows.last().unwrap();
    let want = |x: f64| -a * (load * (l - x) + rho_a * (l - x).powi(2) / 2.0);
    let summed = stations
        .iter()
        .map(|s| last[sim.trajectory.index_of(s.moment()).unwrap()] / want(s.x) - 1.0)
        .collect();
    let ei = scene.params.sections[0].bending_stiffness;
    let curvature = ei * last[sim.trajectory.index("kappa_1_0").unwrap()] / want(0.0) - 1.0;
    (summed, curvature)
}

#[test]
fn the_moment_by_force_summation_is_the_cantilevers_static_moment_where_the_curvature_is_not() {
    let fractions = [0.0, 0.25, 0.5, 0.75];
    // a tip force alone (the section nearly massless), then the section's own load alone
    for (what, density, load) in [("tip force", 1.0, 5.0), ("own weight", 7850.0, 0.0)] {
        let (five, curvature_five) = static_moment_errors(5, density, load, &fractions);
        let (twenty, curvature_twenty) = static_moment_errors(20, density, load, &fractions);
        eprintln!(
            "{what}: relative errors at x/l = {fractions:?}: 5 modes {five:?}, 20 modes \
             {twenty:?}; EI w'' at the foot: 5 modes {curvature_five:.4}, 20 modes \
             {curvature_twenty:.4}"
        );
        // in a steady acceleration the inertial load is uniform, which the translation holds
        // exactly: equilibrium gives the moment whatever the modes (the heavy damping leaves
        // 1e-5 of dynamics after 4 s)
        for (e, modes) in five.iter().zip([5; 4]).chain(twenty.iter().zip([20; 4])) {
            assert!(e.abs() < 1e-4, "{what}: {modes} modes: {e}");
        }
        // the curvature of the series converges slowest exactly at the foot
        assert!(
            curvature_five.abs() > 0.01 && curvature_twenty.abs() < curvature_five.abs() / 3.0,
            "{what}: EI w'' at the foot {curvature_five}, {curvature_twenty}"
        );
    }
}

#[test]
fn generated_and_assembled_moments_agree_and_stresses_are_moment_over_modulus() {
    let over = [
        "time.end=0.5".to_string(),
        "sections.height=0.04".to_string(),
    ];
    let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &over).unwrap();
    let stations = Station::parse_list("1:0,1:0.3,1:0.2,2:0.675,2:1.2").unwrap();
    let run = |model| {
        let options = SimulationOptions {
            stations: stations.clone(),
            model,
            ..SimulationOptions::default()
        };
        simulate_scene(&scene, &options, &Silent).unwrap()
    };
    let (generated, assembled) = (run(ModelChoice::Generated), run(ModelChoice::Assembled));
    assert!(generated.model.contains("generated"), "{}", generated.model);
    let w = 2.0 * 0.83e-8 / 0.04;
    for s in &stations {
        let a = generated.trajectory.column_of(s.moment()).unwrap();
        let b = assembled.trajectory.column_of(s.moment()).unwrap();
        let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let worst = a
            .iter()
            .zip(&b)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
        eprintln!(
            "{}: max |M| {scale:.4e} N m, generated vs assembled {worst:.2e}",
            s.moment_name()
        );
        assert!(scale > 1.0, "{}: the section bends", s.moment_name());
        assert!(
            worst < 1e-7 * scale,
            "{}: {worst} of {scale}",
            s.moment_name()
        );
        let stress = generated.trajectory.column_of(s.stress()).unwrap();
        for (m, sigma) in a.iter().zip(&stress) {
            assert!((sigma - m / w).abs() <= 1e-12 * (m / w).abs().max(1.0));
        }
    }
    // the envelope is the largest stress of any station at any time
    let envelope = StressEnvelope::of(&generated.trajectory).unwrap();
    let largest = stations
        .iter()
        .flat_map(|s| generated.trajectory.column_of(s.stress()).unwrap())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    assert_eq!(envelope.max_abs_stress, largest);
    // and it names the station and the time where that stress stands
    let column = generated
        .trajectory
        .index_of(envelope.station.stress())
        .unwrap();
    let row = generated
        .trajectory
        .rows
        .iter()
        .find(|r| r[0] == envelope.t)
        .unwrap();
    assert_eq!(row[column], envelope.stress);
    assert!(
        generated.summary().contains("stress envelope"),
        "{}",
        generated.summary()
    );
    // a section modulus given directly
    let over = [
        "time.end=0.1".to_string(),
        "sections.section_modulus=[1e-6, 2e-6]".to_string(),
    ];
    let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &over).unwrap();
    assert_eq!(scene.section_moduli(), Some(vec![1e-6, 2e-6]));
}

#[test]
fn bad_stations_and_section_moduli_are_refused_by_name() {
    let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &[]).unwrap();
    for (text, rule) in [
        ("3:0", "section 3 does not exist"),
        ("1:1.5", "outside section 1"),
        ("1:-0.1", "outside section 1"),
        ("1:0.5,2:0,1:0.5", "1:0.5 is given twice"),
    ] {
        let options = SimulationOptions {
            stations: Station::parse_list(text).unwrap(),
            ..SimulationOptions::default()
        };
        let e = simulate_scene(&scene, &options, &Silent).unwrap_err();
        assert!(matches!(e, Error::Option { .. }), "{e}");
        assert!(
            e.to_string().contains("SimulationOptions::stations") && e.to_string().contains(rule),
            "{e}"
        );
    }
    for text in ["1", "a:0", "1:x", "1:0;2:0"] {
        let e = Station::parse_list(text).unwrap_err();
        assert!(e.to_string().contains("SECTION:X"), "{e}");
    }
    for (set, field) in [
        ("sections.section_modulus=-1e-6", "sections.section_modulus"),
        ("sections.height=0", "sections.height"),
    ] {
        let e = Scene::load("scenes/adams-linear.toml".as_ref(), &[set.to_string()]).unwrap_err();
        assert!(e.to_string().contains(field), "{e}");
    }
    let both = [
        "sections.height=0.04".to_string(),
        "sections.section_modulus=1e-6".to_string(),
    ];
    let e = Scene::load("scenes/adams-linear.toml".as_ref(), &both).unwrap_err();
    assert!(e.to_string().contains("not both"), "{e}");
}

#[test]
fn stations_are_priced_before_the_run_and_capped() {
    let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &[]).unwrap();
    let budget = 2 * telescopic::run::memory::trajectory_bytes(&scene);
    let with = |count: usize| SimulationOptions {
        stations: (0..count)
            .map(|i| Station {
                section: 1,
                x: 0.9 * i as f64 / count as f64,
            })
            .collect(),
        memory_budget: budget,
        error_estimate: false,
        ..SimulationOptions::default()
    };
    // the same budget takes the run with a few stations and refuses it with many, before
    // any step: the stations' columns count
    assert!(simulate_scene(&scene, &with(2), &Silent).is_ok());
    let e = simulate_scene(&scene, &with(500), &Silent).unwrap_err();
    assert!(
        matches!(&e, Error::OverMemoryBudget { option: Some(o), .. } if o.name() == "SimulationOptions::stations"),
        "{e}"
    );
    assert!(e.to_string().contains("500 stations"), "{e}");
    let e = simulate_scene(&scene, &with(20_000), &Silent).unwrap_err();
    assert!(e.to_string().contains("at most 1000"), "{e}");
}

#[test]
fn a_runs_csv_header_reads_back_as_its_typed_columns() {
    let scene = pushed_cantilever(&["sections.section_modulus=2e-4".to_string()]);
    let stations = Station::parse_list("1:0,1:0.5").unwrap();
    let options = SimulationOptions {
        stations: stations.clone(),
        coordinates: true,
        ..SimulationOptions::default()
    };
    let trajectory = simulate_scene(&scene, &options, &Silent)
        .unwrap()
        .trajectory;
    let mut csv = Vec::new();
    trajectory.write_csv(&mut csv).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert_eq!(header[0], "t");
    let read: Vec<Column> = header[1..]
        .iter()
        .map(|name| Column::parse(name).unwrap_or_else(|| panic!("{name} is no column")))
        .collect();
    assert_eq!(read, trajectory.columns);
    // the run knows what each column is: the model's, the sensors', the stations', the
    // coordinates', in that order
    let dof = read.iter().filter(|c| c.output().is_none()).count();
    assert!(dof > 0);
    assert_eq!(
        &read[read.len() - dof..],
        (0..dof).map(Column::Coordinate).collect::<Vec<_>>()
    );
    for station in &stations {
        let moment = trajectory.index_of(station.moment()).unwrap();
        let stress = trajectory.index_of(station.stress()).unwrap();
        assert!(moment < stress && stress <= read.len() - dof);
        assert_eq!(trajectory.index(&station.moment_name()), Some(moment));
    }
    let sensor = trajectory
        .index_of(Output::Sensor(Sensor::FootCurvature))
        .unwrap();
    assert!(sensor < trajectory.index_of(stations[0].moment()).unwrap());
    assert_eq!(trajectory.index_of(Output::TipRel), Some(2));
}
