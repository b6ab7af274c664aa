//! The few dense operations of the extended filter on small row-major matrices: product,
//! matrix exponential and the inverse of a symmetric positive definite matrix.
//!
//! Hand-written rather than nalgebra's: the emitted C controller repeats them operation for
//! operation so that it computes the library's force to the last bit, which needs one
//! documented summation order (nalgebra's kernels block and vectorize their sums, and its
//! exponential picks its Padé degree by norm estimates). The sizes are a few tens.

/// `c = a b` for `a` (`rows x inner`) and `b` (`inner x cols`), row-major.
pub fn multiply(a: &[f64], b: &[f64], c: &mut [f64], rows: usize, inner: usize, cols: usize) {
    product(a, b, c, [rows, inner, cols], [cols, 1]);
}

/// `c = a b^T` for `a` (`rows x inner`) and `b` (`cols x inner`), row-major.
pub fn multiply_transposed(
    a: &[f64],
    b: &[f64],
    c: &mut [f64],
    rows: usize,
    inner: usize,
    cols: usize,
) {
    product(a, b, c, [rows, inner, cols], [1, inner]);
}

/// `c = a B` (`[rows, inner, cols]`), the factor's entry `(k, col)` at
/// `b[k * strides[0] + col * strides[1]]`: `b` itself or a transposed one, summed in one order.
fn product(
    a: &[f64],
    b: &[f64],
    c: &mut [f64],
    [rows, inner, cols]: [usize; 3],
    strides: [usize; 2],
) {
    for r in 0..rows {
        for col in 0..cols {
            let mut s = 0.0;
            for k in 0..inner {
                s += a[r * inner + k] * b[k * strides[0] + col * strides[1]];
            }
            c[r * cols + col] = s;
        }
    }
}

/// Degree of the Taylor polynomial of [`exponential`]: with the scaled matrix's 1-norm at
/// most [`SCALED_NORM`], the remainder is below `0.5^13 / 13! = 2e-14` of it.
pub const TAYLOR_DEGREE: usize = 12;

/// The 1-norm the matrix is halved below before its Taylor polynomial.
pub const SCALED_NORM: f64 = 0.5;

/// Most halvings (a 1-norm up to `2^1100` covers every finite double).
pub const MAX_HALVINGS: usize = 1100;

/// `out = exp(a)` (`n x n`) by scaling and squaring of a Taylor polynomial in Horner form;
/// `t1`, `t2` are scratch of the same size. Returns false (and leaves `out` unspecified) when
/// `a` is not finite.
pub fn exponential(a: &[f64], n: usize, out: &mut [f64], t1: &mut [f64], t2: &mut [f64]) -> bool {
    let mut norm = 0.0_f64;
    for col in 0..n {
        let mut s = 0.0;
        for r in 0..n {
            s += a[r * n + col].abs();
        }
        if !s.is_finite() {
            return false;
        }
        norm = norm.max(s);
    }
    let mut halvings = 0;
    let mut scale = 1.0;
    while norm > SCALED_NORM && halvings < MAX_HALVINGS {
        norm *= 0.5;
        scale *= 0.5;
        halvings += 1;
    }
    // t1 = the scaled matrix; out = I + t1 / 12, then out = I + t1 out / k for k = 11 .. 1
    for i in 0..n * n {
        t1[i] = a[i] * scale;
    }
    for r in 0..n {
        for col in 0..n {
            let identity = if r == col { 1.0 } else { 0.0 };
            out[r * n + col] = identity + t1[r * n + col] / TAYLOR_DEGREE as f64;
        }
    }
    for k in (1..TAYLOR_DEGREE).rev() {
        multiply(t1, out, t2, n, n, n);
        for r in 0..n {
            for col in 0..n {
                let identity = if r == col { 1.0 } else { 0.0 };
                out[r * n + col] = identity + t2[r * n + col] / k as f64;
            }
        }
    }
    for _ in 0..halvings {
        multiply(out, out, t2, n, n, n);
        out[..n * n].copy_from_slice(&t2[..n * n]);
    }
    true
}

/// `inverse = s^-1` for a symmetric positive definite `s` (`m x m`) through its Cholesky
/// factor `l` (scratch, `m x m`; on return it holds `L^-1`). Returns false when `s` is not
/// positive definite.
// NaN fails every comparison: the negated ones below reject it
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn invert_spd(s: &[f64], m: usize, l: &mut [f64], inverse: &mut [f64]) -> bool {
    l[..m * m].fill(0.0);
    for j in 0..m {
        let mut d = s[j * m + j];
        for k in 0..j {
            d -= l[j * m + k] * l[j * m + k];
        }
        if !(d > 0.0) {
            return false;
        }
        l[j * m + j] = d.sqrt();
        for i in j + 1..m {
            let mut v = s[i * m + j];
            for k in 0..j {
                v -= l[i * m + k] * l[j * m + k];
            }
            l[i * m + j] = v / l[j * m + j];
        }
    }
    // L^-1 (lower), column by column into `inverse`, then back into `l`
    inverse[..m * m].fill(0.0);
    for j in 0..m {
        inverse[j * m + j] = 1.0 / l[j * m + j];
        for i in j + 1..m {
            let mut v = 0.0;
            for k in j..i {
                v += l[i * m + k] * inverse[k * m + j];
            }
            inverse[i * m + j] = -v / l[i * m + i];
        }
    }
    l[..m * m].copy_from_slice(&inverse[..m * m]);
    // s^-1 = L^-T L^-1
    for r in 0..m {
        for c in 0..m {
            let mut v = 0.0;
            for k in r.max(c)..m {
                v += l[k * m + r] * l[k * m + c];
            }
            inverse[r * m + c] = v;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use telescopic_runtime::nalgebra::DMatrix;

    #[test]
    fn the_exponential_of_an_oscillator_is_its_rotation() {
        // exp([[0, w], [-w, 0]] T) = [[cos wT, sin wT], [-sin wT, cos wT]], here with w T
        // far above the scaled norm (many squarings) and a damped variant against nalgebra
        let (w, t) = (2.0 * std::f64::consts::PI * 3600.0, 1e-3);
        let a = [0.0, w * t, -w * t, 0.0];
        let (mut e, mut t1, mut t2) = ([0.0; 4], [0.0; 4], [0.0; 4]);
        assert!(exponential(&a, 2, &mut e, &mut t1, &mut t2));
        let (c, s) = ((w * t).cos(), (w * t).sin());
        for (got, want) in e.iter().zip([c, s, -s, c]) {
            assert!((got - want).abs() < 1e-11, "{got} vs {want}");
        }
        let a = DMatrix::from_row_slice(3, 3, &[-0.3, 1.2, 0.0, -4.0, -0.1, 2.0, 0.5, 0.0, -2.0]);
        let want = a.clone().exp();
        let (mut e, mut t1, mut t2) = ([0.0; 9], [0.0; 9], [0.0; 9]);
        assert!(exponential(
            a.transpose().as_slice(),
            3,
            &mut e,
            &mut t1,
            &mut t2
        ));
        let got = DMatrix::from_row_slice(3, 3, &e);
        assert!((got - want).abs().max() < 1e-13);
        assert!(!exponential(
            &[f64::NAN],
            1,
            &mut [0.0],
            &mut [0.0],
            &mut [0.0]
        ));
    }

    #[test]
    fn the_spd_inverse_inverts_and_refuses_an_indefinite_matrix() {
        let s = [4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0];
        let (mut l, mut inv) = ([0.0; 9], [0.0; 9]);
        assert!(invert_spd(&s, 3, &mut l, &mut inv));
        let mut product = [0.0; 9];
        multiply(&s, &inv, &mut product, 3, 3, 3);
        for r in 0..3 {
            for c in 0..3 {
                let want = if r == c { 1.0 } else { 0.0 };
                assert!((product[r * 3 + c] - want).abs() < 1e-15);
            }
        }
        assert!(!invert_spd(&[1.0, 2.0, 2.0, 1.0], 2, &mut l, &mut inv));
    }
}
