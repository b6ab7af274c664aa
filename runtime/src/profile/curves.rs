//! Curves the profiles are made of: the quintic smoothstep, the monotone cubic through
//! knots, and a factor changing along a smoothstep over a span.

/// `(value, rate, acceleration)` at `t` of the quintic smoothstep from `from` at `start` to
/// `to` at `end` (s): `from + (to - from)(10u^3 - 15u^4 + 6u^5)`, constant outside.
pub fn smoothstep((from, to): (f64, f64), (start, end): (f64, f64), t: f64) -> (f64, f64, f64) {
    let span = end - start;
    if t <= start {
        (from, 0.0, 0.0)
    } else if t >= end {
        (to, 0.0, 0.0)
    } else {
        let u = (t - start) / span;
        let jump = to - from;
        let s = u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
        let ds = 30.0 * u * u * (1.0 - u) * (1.0 - u);
        let dds = 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u);
        (
            from + jump * s,
            jump * ds / span,
            jump * dds / (span * span),
        )
    }
}

/// `(value, rate, acceleration)` at `t` of the monotone cubic through `(times, values)`
/// ([`crate::ShapedProfile::PiecewiseCubic`]).
pub fn monotone_cubic(times: &[f64], values: &[f64], t: f64) -> (f64, f64, f64) {
    let n = times.len();
    let i = times.partition_point(|&ti| ti <= t);
    if i == 0 {
        return (values[0], 0.0, 0.0);
    }
    if i == n {
        return (values[n - 1], 0.0, 0.0);
    }
    let secant = |k: usize| (values[k + 1] - values[k]) / (times[k + 1] - times[k]);
    // Fritsch-Butland slope at knot k: zero at the ends and at an extremum
    let slope = |k: usize| {
        if k == 0 || k == n - 1 {
            return 0.0;
        }
        let (a, b) = (secant(k - 1), secant(k));
        if a * b <= 0.0 {
            0.0
        } else {
            2.0 * a * b / (a + b)
        }
    };
    let (t0, h) = (times[i - 1], times[i] - times[i - 1]);
    let (y0, y1, m0, m1) = (values[i - 1], values[i], slope(i - 1), slope(i));
    let u = (t - t0) / h;
    // Hermite basis and its derivatives in u
    let (h00, h10, h01, h11) = (
        (1.0 + 2.0 * u) * (1.0 - u) * (1.0 - u),
        u * (1.0 - u) * (1.0 - u),
        u * u * (3.0 - 2.0 * u),
        u * u * (u - 1.0),
    );
    let (d00, d10, d01, d11) = (
        6.0 * u * u - 6.0 * u,
        3.0 * u * u - 4.0 * u + 1.0,
        6.0 * u - 6.0 * u * u,
        3.0 * u * u - 2.0 * u,
    );
    let (s00, s10, s01, s11) = (12.0 * u - 6.0, 6.0 * u - 4.0, 6.0 - 12.0 * u, 6.0 * u - 2.0);
    (
        h00 * y0 + h10 * h * m0 + h01 * y1 + h11 * h * m1,
        (d00 * y0 + d10 * h * m0 + d01 * y1 + d11 * h * m1) / h,
        (s00 * y0 + s10 * h * m0 + s01 * y1 + s11 * h * m1) / (h * h),
    )
}

/// `(f, f', f'')` of the factor going from `early` to `late` over `[start, end]` (s): `early`
/// throughout for an empty span.
pub fn stretch_factor([early, late]: [f64; 2], [start, end]: [f64; 2], t: f64) -> (f64, f64, f64) {
    if end <= start {
        return (early, 0.0, 0.0);
    }
    smoothstep((early, late), (start, end), t)
}
