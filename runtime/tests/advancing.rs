//! The integration advanced piece by piece ([`Integrator`]) is the same run as one call of
//! `simulate` over the span: the same samples to the last bit, the same counts; stopping
//! at each contact switch and going on changes nothing; a held input set between pieces
//! acts from the time it is set.

use std::sync::atomic::{AtomicU64, Ordering};
use telescopic_runtime::integrate::{Integrator, Stop};
use telescopic_runtime::nalgebra::{DMatrix, DVector};
use telescopic_runtime::{
    AssembledModel, ContactState, Method, Model, ModelParams, Scene, Settings, TimeSpan,
    rest_state, simulate,
};

type Samples = Vec<(f64, Vec<f64>)>;

fn scene(name: &str, end: f64) -> (Scene, AssembledModel) {
    let mut scene = Scene::load(format!("../scenes/{name}.toml").as_ref(), &[]).unwrap();
    scene.time.end = end;
    let model = AssembledModel::new(&scene.params).unwrap();
    (scene, model)
}

/// One `simulate` call over the span.
fn whole(model: &dyn Model, span: &TimeSpan, method: Method) -> (Samples, u64, u64) {
    let mut samples = Vec::new();
    let stats = simulate(
        model,
        &rest_state(model, span.start),
        span,
        method,
        &Settings::default(),
        &mut |t, y, _| samples.push((t, y.to_vec())),
        None,
    )
    .unwrap();
    (samples, stats.steps, stats.switches)
}

/// The same span in pieces of `every` samples, stopping at every switch when asked.
fn in_pieces(
    model: &dyn Model,
    span: &TimeSpan,
    method: Method,
    every: usize,
    stop_on_switch: bool,
) -> (Samples, u64, u64, usize) {
    let y0 = rest_state(model, span.start);
    let mut run = Integrator::new(model, &y0, span, method, &Settings::default()).unwrap();
    run.stop_on_switch(stop_on_switch);
    let mut samples = Vec::new();
    let mut stops = 0;
    let pieces = ((span.end - span.start) / span.sample).round() as usize / every;
    for k in 1..=pieces {
        let t = span.start + (k * every) as f64 * span.sample;
        loop {
            let stop = run
                .advance_to(t, &mut |t, y, _| samples.push((t, y.to_vec())))
                .unwrap();
            match stop {
                Stop::Reached => break,
                Stop::Switch(at) => {
                    assert!(at < t && (at - run.time()).abs() == 0.0, "{at} {t}");
                    stops += 1;
                }
                Stop::Stopped(_) => unreachable!("no progress callback"),
            }
        }
        assert_eq!(run.time(), t);
    }
    let stats = run.stats();
    (samples, stats.steps, stats.switches, stops)
}

#[test]
fn a_run_advanced_in_ticks_is_the_whole_run_bit_for_bit() {
    for (name, method) in [
        ("adams-clearance", Method::Dop853),
        ("case-study-no-clearance", Method::Imex),
        ("case-study", Method::Dop853Imex),
    ] {
        let (scene, model) = scene(name, 0.6);
        let span = scene.time;
        let (expected, steps, switches) = whole(&model, &span, method);
        let (got, got_steps, got_switches, _) = in_pieces(&model, &span, method, 1, false);
        assert_eq!(got.len(), expected.len(), "{name}");
        assert!(got == expected, "{name}: samples differ");
        assert_eq!((got_steps, got_switches), (steps, switches), "{name}");
    }
}

#[test]
fn stopping_at_every_contact_switch_and_going_on_changes_nothing() {
    let (scene, model) = scene("adams-clearance", 0.5);
    let span = scene.time;
    let (expected, _, switches) = whole(&model, &span, Method::Dop853);
    assert!(switches > 10, "the scene rattles: {switches} switches");
    let (got, _, got_switches, stops) = in_pieces(&model, &span, Method::Dop853, 50, true);
    assert!(got == expected);
    assert_eq!(got_switches, switches);
    // a switch that lands exactly on a piece's end is not a stop of its own
    assert!(
        stops as u64 <= switches && stops as u64 + 20 >= switches,
        "{stops} stops for {switches} switches"
    );
}

/// `base` with a force added at the vehicle's coordinate, held in a cell the caller sets
/// between pieces (the model is shared with the run, so the input is set through it).
struct HeldForce<'a> {
    base: &'a AssembledModel,
    force: AtomicU64,
    inverse_mass: DMatrix<f64>,
}

impl Model for HeldForce<'_> {
    fn layout(&self) -> &telescopic_runtime::Layout {
        self.base.layout()
    }
    fn params(&self) -> &ModelParams {
        self.base.params()
    }
    fn mass_matrix(&self) -> &DMatrix<f64> {
        self.base.mass_matrix()
    }
    fn stiffness_matrix(&self) -> &DMatrix<f64> {
        self.base.stiffness_matrix()
    }
    fn damping_matrix(&self) -> Option<&DMatrix<f64>> {
        self.base.damping_matrix()
    }
    fn drive_vector(&self) -> &DVector<f64> {
        self.base.drive_vector()
    }
    fn contact_vectors(&self, t: f64, g: &mut DMatrix<f64>, gdot: &mut DMatrix<f64>) {
        self.base.contact_vectors(t, g, gdot);
    }
    fn contact_vectors_at(
        &self,
        positions: &[f64],
        rates: &[f64],
        g: &mut DMatrix<f64>,
        gdot: &mut DMatrix<f64>,
    ) {
        self.base.contact_vectors_at(positions, rates, g, gdot);
    }
    fn contact_gaps(&self, t: f64, y: &[f64], xi: &mut [f64], xi_dot: &mut [f64]) {
        self.base.contact_gaps(t, y, xi, xi_dot);
    }
    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
        self.base.rhs(t, y, states, ydot);
        let n = self.dof();
        let force = f64::from_bits(self.force.load(Ordering::Relaxed));
        for i in 0..n {
            ydot[n + i] += self.inverse_mass[(i, 0)] * force;
        }
    }
    fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
        self.base.jacobian(t, y, states, jac);
    }
    fn displacement(&self, section: usize, x: f64, z: &[f64]) -> f64 {
        self.base.displacement(section, x, z)
    }
    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        self.base.outputs(t, y, ydot, out);
    }
}

/// A force held from the middle of the span on: the first half is the run without it to
/// the bit, and at the end the vehicle coordinate's generalized momentum `(M zdot)_0` (the
/// telescope's whole linear momentum along the drive) exceeds the plain run's by the
/// force's impulse (the scene is linear, so the two runs differ by the force's response
/// alone).
#[test]
fn a_held_input_set_between_pieces_acts_from_then_on() {
    let (scene, base) = scene("adams-linear", 0.4);
    let span = scene.time;
    let held = HeldForce {
        base: &base,
        force: AtomicU64::new(0f64.to_bits()),
        inverse_mass: base.mass_matrix().clone().try_inverse().unwrap(),
    };
    let (plain, _, _) = whole(&base, &span, Method::Dopri5);
    let y0 = rest_state(&held, 0.0);
    let mut run = Integrator::new(&held, &y0, &span, Method::Dopri5, &Settings::default()).unwrap();
    let mut samples = Vec::new();
    run.advance_to(0.2, &mut |t, y, _| samples.push((t, y.to_vec())))
        .unwrap();
    let half = samples.len();
    assert!(samples[..] == plain[..half]);
    let force: f64 = 50.0;
    held.force.store(force.to_bits(), Ordering::Relaxed);
    run.input_changed();
    run.advance_to(0.4, &mut |t, y, _| samples.push((t, y.to_vec())))
        .unwrap();
    assert_eq!(samples.len(), plain.len());
    let n = base.dof();
    let momentum = |y: &[f64]| {
        (0..n)
            .map(|j| base.mass_matrix()[(0, j)] * y[n + j])
            .sum::<f64>()
    };
    let extra = momentum(&samples.last().unwrap().1) - momentum(&plain.last().unwrap().1);
    let impulse = force * 0.2;
    assert!(
        (extra - impulse).abs() < 1e-6 * impulse,
        "extra momentum {extra:.9e} N s, impulse {impulse:.9e} N s"
    );
}

#[test]
fn exact_stepping_and_bad_spans_are_refused_with_the_rule() {
    let (scene, model) = scene("adams-linear", 0.1);
    let y0 = rest_state(&model, 0.0);
    let settings = Settings::default();
    let exact = Integrator::new(&model, &y0, &scene.time, Method::Exact, &settings);
    assert!(exact.err().unwrap().to_string().contains("whole spans"));
    let backwards = TimeSpan {
        start: 1.0,
        end: 0.5,
        sample: 1e-3,
    };
    let err = Integrator::new(&model, &y0, &backwards, Method::Dopri5, &settings)
        .err()
        .unwrap();
    assert!(err.to_string().contains("forward"), "{err}");
    let mut run = Integrator::new(&model, &y0, &scene.time, Method::Dopri5, &settings).unwrap();
    let err = run.advance_to(f64::NAN, &mut |_, _, _| {}).unwrap_err();
    assert!(err.to_string().contains("finite"), "{err}");
}
