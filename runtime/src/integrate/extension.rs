//! DOP853's continuous extension (Hairer, Norsett & Wanner, Solving ODEs I, 1993, II.6 and
//! the code `dop853.f`): three more stages after an accepted step give a polynomial of
//! order 7 through the step, so a state anywhere inside it costs a polynomial evaluation.
//!
//! The driver locates a contact closing from a state where every contact is open on it
//! instead of by trial steps (a trial is a whole step of 12 right-hand sides, and a search
//! took 2.6 of them; the extension takes 3). Where every contact is open the right-hand side
//! is smooth across the step and the extension lies within a thousandth of the tolerance of
//! a trial step's state; while a closed contact rings it does not (docs/benchmarks.md), so
//! the driver uses it only from all-open states.
//!
//! Hand-written for the reason the steppers are (the crates own the time loop); the
//! coefficients are the published ones.

use super::combine::combine;

/// Nodes of the three extra stages (fractions of the step).
const C: [f64; 3] = [0.1, 0.2, 7.0 / 9.0];

/// Rows of the extra stages' `a_ij` over the step's 13 stages (the last one `f(t + h, y1)`)
/// and the extra stages before them.
#[allow(clippy::excessive_precision)]
const A: [&[f64]; 3] = [
    &[
        5.61675022830479523392909219681e-2,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        2.53500210216624811088794765333e-1,
        -2.46239037470802489917441475441e-1,
        -1.24191423263816360469010140626e-1,
        1.5329179827876569731206322685e-1,
        8.20105229563468988491666602057e-3,
        7.56789766054569976138603589584e-3,
        -8.298e-3,
    ],
    &[
        3.18346481635021405060768473261e-2,
        0.0,
        0.0,
        0.0,
        0.0,
        2.83009096723667755288322961402e-2,
        5.35419883074385676223797384372e-2,
        -5.49237485713909884646569340306e-2,
        0.0,
        0.0,
        -1.08347328697249322858509316994e-4,
        3.82571090835658412954920192323e-4,
        -3.40465008687404560802977114492e-4,
        1.41312443674632500278074618366e-1,
    ],
    &[
        -4.28896301583791923408573538692e-1,
        0.0,
        0.0,
        0.0,
        0.0,
        -4.69762141536116384314449447206,
        7.68342119606259904184240953878,
        4.06898981839711007970213554331,
        3.56727187455281109270669543021e-1,
        0.0,
        0.0,
        0.0,
        -1.39902416515901462129418009734e-3,
        2.9475147891527723389556272149,
        -9.15095847217987001081870187138,
    ],
];

/// Weights `d` of the four highest coefficients of the extension over all 16 stages.
#[allow(clippy::excessive_precision)]
const D: [[f64; 16]; 4] = [
    [
        -0.84289382761090128651353491142e+01,
        0.0,
        0.0,
        0.0,
        0.0,
        0.56671495351937776962531783590,
        -0.30689499459498916912797304727e+01,
        0.23846676565120698287728149680e+01,
        0.21170345824450282767155149946e+01,
        -0.87139158377797299206789907490,
        0.22404374302607882758541771650e+01,
        0.63157877876946881815570249290,
        -0.88990336451333310820698117400e-01,
        0.18148505520854727256656404962e+02,
        -0.91946323924783554000451984436e+01,
        -0.44360363875948939664310572000e+01,
    ],
    [
        0.10427508642579134603413151009e+02,
        0.0,
        0.0,
        0.0,
        0.0,
        0.24228349177525818288430175319e+03,
        0.16520045171727028198505394887e+03,
        -0.37454675472269020279518312152e+03,
        -0.22113666853125306036270938578e+02,
        0.77334326684722638389603898808e+01,
        -0.30674084731089398182061213626e+02,
        -0.93321305264302278729567221706e+01,
        0.15697238121770843886131091075e+02,
        -0.31139403219565177677282850411e+02,
        -0.93529243588444783865713862664e+01,
        0.35816841486394083752465898540e+02,
    ],
    [
        0.19985053242002433820987653617e+02,
        0.0,
        0.0,
        0.0,
        0.0,
        -0.38703730874935176555105901742e+03,
        -0.18917813819516756882830838328e+03,
        0.52780815920542364900561016686e+03,
        -0.11573902539959630126141871134e+02,
        0.68812326946963000169666922661e+01,
        -0.10006050966910838403183860980e+01,
        0.77771377980534432092869265740,
        -0.27782057523535084065932004339e+01,
        -0.60196695231264120758267380846e+02,
        0.84320405506677161018159903784e+02,
        0.11992291136182789328035130030e+02,
    ],
    [
        -0.25693933462703749003312586129e+02,
        0.0,
        0.0,
        0.0,
        0.0,
        -0.15418974869023643374053993627e+03,
        -0.23152937917604549567536039109e+03,
        0.35763911791061412378285349910e+03,
        0.93405324183624310003907691704e+02,
        -0.37458323136451633156875139351e+02,
        0.10409964950896230045147246184e+03,
        0.29840293426660503123344363579e+02,
        -0.43533456590011143754432175058e+02,
        0.96324553959188282948394950600e+02,
        -0.39177261675615439165231486172e+02,
        -0.14972683625798562581422125276e+03,
    ],
];

/// A right-hand side `rhs(t, y, ydot)`: `ydot = f(t, y)` (s, state units).
pub type RightHandSide<'a> = dyn FnMut(f64, &[f64], &mut [f64]) + 'a;

/// Right-hand sides the extension costs on top of its step.
pub const EXTRA_STAGES: usize = C.len();

/// The coefficients of DOP853's continuous extension over the last step, and the storage
/// for its extra stages (made once per run).
pub struct Dop853Extension {
    /// `r_1 .. r_8` of `y(t + theta h) = r1 + theta (r2 + (1 - theta)(r3 + theta (r4 + ...)))`.
    coefficients: [Vec<f64>; 8],
    scratch: Vec<f64>,
}

impl Dop853Extension {
    /// Storage for a state of length `n`.
    pub fn new(n: usize) -> Self {
        Dop853Extension {
            coefficients: std::array::from_fn(|_| vec![0.0; n]),
            scratch: vec![0.0; n],
        }
    }

    /// The extension of the step of length `h` (s) from `(t, y)` to `y1`, whose 13 stages
    /// (the last `f(t + h, y1)`) are the first entries of `stages`; the three extra stages
    /// are evaluated with `rhs(t, y, ydot)` into the next entries.
    pub fn prepare(
        &mut self,
        rhs: &mut RightHandSide,
        t: f64,
        y: &[f64],
        y1: &[f64],
        h: f64,
        stages: &mut [Vec<f64>],
    ) {
        for (i, (&c, a)) in C.iter().zip(A).enumerate() {
            combine(&mut self.scratch, Some(y), h, a, stages);
            rhs(t + c * h, &self.scratch, &mut stages[13 + i]);
        }
        let [r1, r2, r3, r4, highest @ ..] = &mut self.coefficients;
        for j in 0..y.len() {
            let step = y1[j] - y[j];
            let slope_start = h * stages[0][j] - step;
            r1[j] = y[j];
            r2[j] = step;
            r3[j] = slope_start;
            r4[j] = step - h * stages[12][j] - slope_start;
        }
        for (r, d) in highest.iter_mut().zip(&D) {
            combine(r, None, h, d, stages);
        }
    }

    /// The state at `t + theta h` (`theta` in `[0, 1]`) into `out`.
    pub fn state(&self, theta: f64, out: &mut [f64]) {
        let [r1, r2, r3, r4, r5, r6, r7, r8] = &self.coefficients;
        let rest = 1.0 - theta;
        for (j, o) in out.iter_mut().enumerate() {
            let high = r5[j] + theta * (r6[j] + rest * (r7[j] + theta * r8[j]));
            *o = r1[j] + theta * (r2[j] + rest * (r3[j] + theta * (r4[j] + rest * high)));
        }
    }
}
