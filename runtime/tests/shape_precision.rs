//! Shape functions in `f64` (cancellation-free forms) against the printed forms evaluated
//! with 512-bit floats (`telescopic_runtime::shape::reference`), roots included.

use telescopic_runtime::shape::reference::{Hp, scaled_error};
use telescopic_runtime::shape::{MAX_MODES, SectionKind, ShapeFunction};

#[test]
fn cancellation_free_forms_are_accurate_to_1e_12_up_to_mode_30() {
    let mut hp = Hp::new();
    let l = 1.35;
    let mut worst: f64 = 0.0;
    let mut worst_printed_high: f64 = 0.0;
    for kind in [SectionKind::GuidedFree, SectionKind::FreeFree] {
        let first_elastic = if kind == SectionKind::GuidedFree {
            2
        } else {
            3
        };
        for i in first_elastic..=MAX_MODES {
            let f = ShapeFunction::new(kind, i, l);
            let beta = hp.root(kind, f.beta());
            // the f64 root is the correctly rounded one (within an ulp)
            let beta_f64 = hp.as_f64(&beta);
            assert!(
                (f.beta() - beta_f64).abs() <= 2.0 * f64::EPSILON * beta_f64,
                "{kind:?} root {i}: {} vs {beta_f64}",
                f.beta()
            );
            for frac in [0.0, 0.1, 0.37, 0.5, 0.77, 0.93, 1.0] {
                let x = frac * l;
                for d in 0..=3u8 {
                    let exact = hp.printed(kind, &beta, l, x, d);
                    let err = scaled_error(f.eval(x, d), exact, f.wavenumber(), d);
                    assert!(
                        err <= 1e-12,
                        "{kind:?} mode {i} x = {x} d = {d}: error {err:e}"
                    );
                    worst = worst.max(err);
                    if i >= 20 {
                        worst_printed_high = worst_printed_high.max(scaled_error(
                            f.eval_printed(x, d),
                            exact,
                            f.wavenumber(),
                            d,
                        ));
                    }
                }
            }
        }
    }
    eprintln!(
        "worst scaled error, cancellation-free: {worst:e}; printed form, modes 20..30: {worst_printed_high:e}"
    );
    // the printed form is not usable there: it loses far more than half the digits
    assert!(
        worst_printed_high > 1e-6,
        "printed form unexpectedly accurate: {worst_printed_high:e}"
    );
}
