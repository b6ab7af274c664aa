//! Explicit Runge-Kutta methods from their Butcher tableaus: Dormand-Prince 5(4) and DOP853
//! (adaptive, embedded error estimates, first-same-as-last) and classical RK4 (fixed step).
//!
//! Hand-written rather than taken from a crate: the driver must redo a step with any length
//! from the same start (event location with full order) and restart at every contact
//! switch, thousands of times per run; the crates we looked at (diffsol, ode_solvers) own
//! the time loop instead.

use super::combine::combine;
use super::extension::{Dop853Extension, EXTRA_STAGES};
use super::{Settings, StepFailure, Stepper, System, error_norm};

/// A Butcher tableau, with the embedded error weights of an adaptive pair.
pub struct Tableau {
    /// Nodes `c_i`.
    pub c: &'static [f64],
    /// Lower-triangular `a_ij`, row by row (row `i` has `i` entries).
    pub a: &'static [&'static [f64]],
    /// Weights `b_i` of the propagated solution.
    pub b: &'static [f64],
    /// How the local error is estimated.
    pub error: ErrorEstimate,
    /// True when the last stage is evaluated at `(t + h, y1)` (first same as last).
    pub fsal: bool,
    /// Order for step-size control.
    pub order: u32,
    /// The method has a continuous extension ([`super::extension`]).
    pub extension: bool,
}

/// The local error estimate of an explicit method.
pub enum ErrorEstimate {
    /// Fixed step: no estimate.
    None,
    /// `h sum_i e_i k_i` with `e_i = b_i - bhat_i` of an embedded pair.
    Embedded(&'static [f64]),
    /// DOP853 (Hairer, Norsett & Wanner): 5th- and 3rd-order differences `e5`, `e3`
    /// combined as `err5^2 / sqrt(err5^2 + 0.01 err3^2)`, which stays reliable for large
    /// steps where the 5th-order estimate alone is too optimistic.
    Dop853 {
        /// Weights of the 5th-order difference.
        e5: &'static [f64],
        /// Weights of the 3rd-order difference.
        e3: &'static [f64],
    },
}

/// Dormand-Prince 5(4) weights (the last entry belongs to the first-same-as-last stage).
const DOPRI5_B: [f64; 7] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
    0.0,
];

/// Dormand & Prince (1980), the 5(4) pair with 5th-order propagation.
pub const DOPRI5: Tableau = Tableau {
    c: &[0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0],
    a: &[
        &[],
        &[1.0 / 5.0],
        &[3.0 / 40.0, 9.0 / 40.0],
        &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
        &[
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
        ],
        &[
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
        ],
        DOPRI5_B.split_at(6).0,
    ],
    b: &DOPRI5_B,
    error: ErrorEstimate::Embedded(&[
        71.0 / 57600.0,
        0.0,
        -71.0 / 16695.0,
        71.0 / 1920.0,
        -17253.0 / 339200.0,
        22.0 / 525.0,
        -1.0 / 40.0,
    ]),
    fsal: true,
    order: 4,
    extension: false,
};

/// DOP853's 8th-order weights (the last entry belongs to the first-same-as-last stage).
#[allow(clippy::excessive_precision)]
const DOP853_B: [f64; 13] = [
    5.42937341165687622380535766363e-2,
    0.0,
    0.0,
    0.0,
    0.0,
    4.45031289275240888144113950566,
    1.89151789931450038304281599044,
    -5.8012039600105847814672114227,
    3.1116436695781989440891606237e-1,
    -1.52160949662516078556178806805e-1,
    2.01365400804030348374776537501e-1,
    4.47106157277725905176885569043e-2,
    0.0,
];

/// DOP853's 3rd-order error weights: `b` minus the 3rd-order weights `bhh`.
#[allow(clippy::excessive_precision)]
const DOP853_E3: [f64; 12] = {
    let mut e = [0.0; 12];
    let mut i = 0;
    while i < 12 {
        e[i] = DOP853_B[i];
        i += 1;
    }
    e[0] -= 0.244094488188976377952755905512;
    e[8] -= 0.733846688281611857341361741547;
    e[11] -= 0.0220588235294117647058823529412;
    e
};

/// Dormand & Prince's 8(5,3) pair DOP853 (Hairer, Norsett & Wanner, Solving ODEs I, 1993):
/// 12 stages plus the first-same-as-last evaluation, 8th-order propagation.
// the published digits, kept as printed (rounded to f64 by the compiler)
#[allow(clippy::excessive_precision)]
pub const DOP853: Tableau = Tableau {
    c: &[
        0.0,
        0.0526001519587677318785587544488,
        0.0789002279381515978178381316732,
        0.11835034190722739672675719751,
        0.28164965809277260327324280249,
        1.0 / 3.0,
        0.25,
        4.0 / 13.0,
        127.0 / 195.0,
        0.6,
        6.0 / 7.0,
        1.0,
        1.0,
    ],
    a: &[
        &[],
        &[5.26001519587677318785587544488e-2],
        &[
            1.97250569845378994544595329183e-2,
            5.91751709536136983633785987549e-2,
        ],
        &[
            2.95875854768068491816892993775e-2,
            0.0,
            8.87627564304205475450678981324e-2,
        ],
        &[
            2.41365134159266685502369798665e-1,
            0.0,
            -8.84549479328286085344864962717e-1,
            9.24834003261792003115737966543e-1,
        ],
        &[
            3.7037037037037037037037037037e-2,
            0.0,
            0.0,
            1.70828608729473871279604482173e-1,
            1.25467687566822425016691814123e-1,
        ],
        &[
            3.7109375e-2,
            0.0,
            0.0,
            1.70252211019544039314978060272e-1,
            6.02165389804559606850219397283e-2,
            -1.7578125e-2,
        ],
        &[
            3.70920001185047927108779319836e-2,
            0.0,
            0.0,
            1.70383925712239993810214054705e-1,
            1.07262030446373284651809199168e-1,
            -1.53194377486244017527936158236e-2,
            8.27378916381402288758473766002e-3,
        ],
        &[
            6.24110958716075717114429577812e-1,
            0.0,
            0.0,
            -3.36089262944694129406857109825,
            -8.68219346841726006818189891453e-1,
            2.75920996994467083049415600797e1,
            2.01540675504778934086186788979e1,
            -4.34898841810699588477366255144e1,
        ],
        &[
            4.77662536438264365890433908527e-1,
            0.0,
            0.0,
            -2.48811461997166764192642586468,
            -5.90290826836842996371446475743e-1,
            2.12300514481811942347288949897e1,
            1.52792336328824235832596922938e1,
            -3.32882109689848629194453265587e1,
            -2.03312017085086261358222928593e-2,
        ],
        &[
            -9.3714243008598732571704021658e-1,
            0.0,
            0.0,
            5.18637242884406370830023853209,
            1.09143734899672957818500254654,
            -8.14978701074692612513997267357,
            -1.85200656599969598641566180701e1,
            2.27394870993505042818970056734e1,
            2.49360555267965238987089396762,
            -3.0467644718982195003823669022,
        ],
        &[
            2.27331014751653820792359768449,
            0.0,
            0.0,
            -1.05344954667372501984066689879e1,
            -2.00087205822486249909675718444,
            -1.79589318631187989172765950534e1,
            2.79488845294199600508499808837e1,
            -2.85899827713502369474065508674,
            -8.87285693353062954433549289258,
            1.23605671757943030647266201528e1,
            6.43392746015763530355970484046e-1,
        ],
        DOP853_B.split_at(12).0,
    ],
    b: &DOP853_B,

    error: ErrorEstimate::Dop853 {
        e5: &[
            0.01312004499419488073250102996,
            0.0,
            0.0,
            0.0,
            0.0,
            -1.225156446376204440720569753,
            -0.4957589496572501915214079952,
            1.664377182454986536961530415,
            -0.3503288487499736816886487290,
            0.3341791187130174790297318841,
            0.08192320648511571246570742613,
            -0.02235530786388629525884427845,
        ],
        e3: &DOP853_E3,
    },
    fsal: true,
    order: 7,
    extension: true,
};

/// The classical fourth-order Runge-Kutta method.
pub const RK4: Tableau = Tableau {
    c: &[0.0, 0.5, 0.5, 1.0],
    a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    error: ErrorEstimate::None,
    fsal: false,
    order: 4,
    extension: false,
};

/// An explicit Runge-Kutta method with its stage storage.
pub struct ExplicitRk {
    tableau: &'static Tableau,
    rtol: f64,
    atol: f64,
    stages: Vec<Vec<f64>>,
    scratch: Vec<f64>,
    err: Vec<f64>,
    err3: Vec<f64>,
    /// The continuous extension's coefficients, for a tableau that has one.
    extension: Option<Dop853Extension>,
}

impl ExplicitRk {
    /// The method of `tableau` for a state of length `n`; `settings` give the tolerances
    /// of an embedded pair.
    pub fn new(tableau: &'static Tableau, n: usize, settings: &Settings) -> Self {
        let extra_stages = if tableau.extension { EXTRA_STAGES } else { 0 };
        ExplicitRk {
            tableau,
            rtol: settings.rtol,
            atol: settings.atol,
            stages: vec![vec![0.0; n]; tableau.c.len() + extra_stages],
            scratch: vec![0.0; n],
            err: vec![0.0; n],
            err3: vec![0.0; n],
            extension: tableau.extension.then(|| Dop853Extension::new(n)),
        }
    }
}

impl Stepper for ExplicitRk {
    fn order(&self) -> u32 {
        self.tableau.order
    }

    fn step(
        &mut self,
        sys: &mut System,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
        y1: &mut [f64],
    ) -> Result<f64, StepFailure> {
        let tab = self.tableau;
        let s = tab.c.len();
        self.stages[0].copy_from_slice(f0);
        let last = if tab.fsal { s - 1 } else { s };
        for i in 1..last {
            combine(&mut self.scratch, Some(y), h, tab.a[i], &self.stages);
            sys.rhs(t + tab.c[i] * h, &self.scratch, &mut self.stages[i]);
        }
        combine(y1, Some(y), h, tab.b, &self.stages);
        if tab.fsal {
            sys.rhs(t + h, y1, &mut self.stages[s - 1]);
        }
        match tab.error {
            ErrorEstimate::None => Ok(0.0),
            ErrorEstimate::Embedded(e) => {
                combine(&mut self.err, None, h, e, &self.stages);
                Ok(error_norm(&self.err, y, y1, self.rtol, self.atol))
            }
            ErrorEstimate::Dop853 { e5, e3 } => {
                combine(&mut self.err, None, h, e5, &self.stages);
                combine(&mut self.err3, None, h, e3, &self.stages);
                let n = y.len() as f64;
                let sum5 = n * error_norm(&self.err, y, y1, self.rtol, self.atol).powi(2);
                let sum3 = n * error_norm(&self.err3, y, y1, self.rtol, self.atol).powi(2);
                let deno = sum5 + 0.01 * sum3;
                Ok(if deno > 0.0 {
                    sum5 / (n * deno).sqrt()
                } else {
                    0.0
                })
            }
        }
    }

    fn pi_beta(&self) -> f64 {
        // Hairer's defaults: 0.04 for dopri5 (case-study at rtol 1e-6: rejected steps 45k ->
        // 34k, rhs evaluations -3 %), 0 for dop853 (measured: -6 % rhs on case-study but +9 %
        // on adams-clearance with 0.04); fixed-step tableaus have no estimate to control
        match self.tableau.error {
            ErrorEstimate::Embedded(_) => 0.04,
            ErrorEstimate::Dop853 { .. } | ErrorEstimate::None => 0.0,
        }
    }

    fn end_derivative(&self) -> Option<&[f64]> {
        self.tableau
            .fsal
            .then(|| self.stages[self.tableau.c.len() - 1].as_slice())
    }

    fn prepare_extension(
        &mut self,
        sys: &mut System,
        t: f64,
        y: &[f64],
        y1: &[f64],
        h: f64,
    ) -> bool {
        let Some(extension) = self.extension.as_mut() else {
            return false;
        };
        extension.prepare(
            &mut |t, y, ydot| sys.rhs(t, y, ydot),
            t,
            y,
            y1,
            h,
            &mut self.stages,
        );
        true
    }

    fn extension_state(&self, theta: f64, out: &mut [f64]) {
        if let Some(extension) = &self.extension {
            extension.state(theta, out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The blocked sums equal, bit for bit, a pass per stage over the whole vector (the
    /// straightforward order: `0 + w_0 k_0 + w_1 k_1 + ...`, zero weights skipped, then
    /// `base + h sum`) for every length from 1 to 27, so every mix of blocks of 8, 4 and 1.
    #[test]
    fn blocked_sums_are_the_stage_by_stage_sums_bit_for_bit() {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let weights = DOP853.a[11];
        for n in 1..=27 {
            let stages: Vec<Vec<f64>> = (0..weights.len())
                .map(|_| (0..n).map(|_| next() * 1e3).collect())
                .collect();
            let base: Vec<f64> = (0..n).map(|_| next()).collect();
            let h = 2.7e-4;
            for b in [Some(base.as_slice()), None] {
                let mut expected = vec![0.0; n];
                for (&w, k) in weights.iter().zip(&stages) {
                    if w != 0.0 {
                        for (e, &kj) in expected.iter_mut().zip(k) {
                            *e += w * kj;
                        }
                    }
                }
                for (j, e) in expected.iter_mut().enumerate() {
                    *e = match b {
                        Some(b) => b[j] + h * *e,
                        None => *e * h,
                    };
                }
                let mut out = vec![f64::NAN; n];
                combine(&mut out, b, h, weights, &stages);
                let same = out
                    .iter()
                    .zip(&expected)
                    .all(|(a, e)| a.to_bits() == e.to_bits());
                assert!(same, "n = {n}: {out:?} against {expected:?}");
            }
        }
    }

    /// The continuous extension of DOP853 ([`super::super::extension`]) on the method's own steps.
    mod dop853_extension {
        use super::super::*;
        use crate::integrate::extension::{Dop853Extension, RightHandSide};

        /// One DOP853 step of `y' = f(t, y)` from `(0, y)` over `h`: the end state and the 16
        /// stages (the last three left for the extension).
        fn dop853_step(f: &mut RightHandSide, y: &[f64], h: f64) -> (Vec<f64>, Vec<Vec<f64>>) {
            let n = y.len();
            let mut stages = vec![vec![0.0; n]; 16];
            let mut scratch = vec![0.0; n];
            f(0.0, y, &mut stages[0]);
            for i in 1..12 {
                combine(&mut scratch, Some(y), h, DOP853.a[i], &stages);
                f(DOP853.c[i] * h, &scratch, &mut stages[i]);
            }
            let mut y1 = vec![0.0; n];
            combine(&mut y1, Some(y), h, DOP853.b, &stages);
            f(h, &y1, &mut stages[12]);
            (y1, stages)
        }

        /// The extension's largest error inside a step of `h` on `x'' = -x - 0.3 x' + sin 2t`
        /// against its solution from the accurate reference (very short steps of the method).
        fn interpolation_error(h: f64) -> f64 {
            let mut f = |t: f64, y: &[f64], out: &mut [f64]| {
                out[0] = y[1];
                out[1] = -y[0] - 0.3 * y[1] + (2.0 * t).sin();
            };
            let y0 = [1.0, 0.5];
            let (y1, mut stages) = dop853_step(&mut f, &y0, h);
            let mut extension = Dop853Extension::new(2);
            extension.prepare(&mut f, 0.0, &y0, &y1, h, &mut stages);
            let mut worst: f64 = 0.0;
            for theta in [0.13, 0.37, 0.5, 0.71, 0.94] {
                // the reference: the method itself with 64 steps to t = theta h
                let mut y = y0.to_vec();
                let (mut t, k) = (0.0, 64);
                for _ in 0..k {
                    let dt = theta * h / k as f64;
                    let mut g = |s: f64, y: &[f64], out: &mut [f64]| f(t + s, y, out);
                    y = dop853_step(&mut g, &y, dt).0;
                    t += dt;
                }
                let mut at = [0.0; 2];
                extension.state(theta, &mut at);
                worst = worst.max((at[0] - y[0]).abs().max((at[1] - y[1]).abs()));
            }
            worst
        }

        /// The published coefficients give an extension of order 7 (error `O(h^8)` inside the
        /// step): halving the step divides its error by about 2^8 = 256. One coefficient wrong
        /// in its fourth digit (tried: `d_414` 18.148 -> 18.158) drops the ratio to 1.9.
        #[test]
        fn the_extension_has_order_seven() {
            let (coarse, fine) = (interpolation_error(0.4), interpolation_error(0.2));
            let ratio = coarse / fine;
            assert!(
                coarse < 1e-6 && (150.0..450.0).contains(&ratio),
                "errors {coarse:.3e}, {fine:.3e}: ratio {ratio:.1} (order 7 gives 256)"
            );
        }
    }
}
