//! Matrices as lists of rows: the layout of the JSON files (linear models, controllers).

use telescopic_runtime::nalgebra::DMatrix;

/// The rows of `m`, row-major.
pub(crate) fn to_rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}

/// The matrix of `rows`, which must all have the same length (and, when `shape` is given,
/// form a `rows x columns` matrix).
///
/// # Errors
/// A message saying what is wrong with the rows, for the caller to prefix with the matrix's
/// name.
pub(crate) fn from_rows(
    rows: &[Vec<f64>],
    shape: Option<(usize, usize)>,
) -> Result<DMatrix<f64>, String> {
    let ncols = rows.first().map_or(0, Vec::len);
    if rows.iter().any(|r| r.len() != ncols) {
        return Err("has rows of different lengths".into());
    }
    if let Some((r, c)) = shape
        && (rows.len(), ncols) != (r, c)
    {
        return Err(format!("is {} x {ncols}, expected {r} x {c}", rows.len()));
    }
    Ok(DMatrix::from_row_iterator(
        rows.len(),
        ncols,
        rows.iter().flatten().copied(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_round_trip_and_bad_shapes_are_named() {
        let m = DMatrix::from_row_slice(2, 3, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        let rows = to_rows(&m);
        assert_eq!(rows, vec![vec![1.0, 2.0, 3.0], vec![4.0, 5.0, 6.0]]);
        assert_eq!(from_rows(&rows, Some((2, 3))).unwrap(), m);
        assert_eq!(
            from_rows(&rows, Some((3, 2))).unwrap_err(),
            "is 2 x 3, expected 3 x 2"
        );
        let ragged = vec![vec![1.0], vec![1.0, 2.0]];
        assert_eq!(
            from_rows(&ragged, None).unwrap_err(),
            "has rows of different lengths"
        );
    }
}
