//! Test support for the six-stage tableaus (ESDIRK and the additive pair): the full Butcher
//! matrix from its strictly lower part and diagonal, and the products the order conditions
//! are written in.

/// The full Butcher matrix: `lower` below the diagonal, `diagonal` on it from the second
/// stage on.
pub(crate) fn full(lower: &[[f64; 5]; 6], diagonal: f64) -> [[f64; 6]; 6] {
    let mut a = [[0.0; 6]; 6];
    for i in 0..6 {
        a[i][..5].copy_from_slice(&lower[i]);
        if i > 0 {
            a[i][i] = diagonal;
        }
    }
    a
}

/// `x . y`.
pub(crate) fn dot(x: &[f64; 6], y: &[f64; 6]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

/// `a x`.
pub(crate) fn mul(a: &[[f64; 6]; 6], x: &[f64; 6]) -> [f64; 6] {
    std::array::from_fn(|i| dot(&a[i], x))
}
