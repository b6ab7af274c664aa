//! The stage combination of explicit Runge-Kutta steps, `out = base + h sum_i w_i k_i`,
//! shared by the steppers and the continuous extension.

/// `out = base + h sum_i w_i k_i` (`base` zero when `None`).
pub(crate) fn combine(
    out: &mut [f64],
    base: Option<&[f64]>,
    h: f64,
    weights: &[f64],
    stages: &[Vec<f64>],
) {
    // eight entries at a time (then four, then one), summed over every stage in registers: a
    // pass per stage over the whole vector would store each entry once per stage and wait on
    // those stores. Per entry the sums run in stage order, skipping the tableaus' many zero
    // weights, so the result equals the stage-by-stage sum bit for bit.
    for (b, out_block) in out.chunks_exact_mut(8).enumerate() {
        combine_block::<8>(out_block, 8 * b, base, h, weights, stages);
    }
    let mut start = out.len() / 8 * 8;
    if out.len() - start >= 4 {
        combine_block::<4>(&mut out[start..start + 4], start, base, h, weights, stages);
        start += 4;
    }
    for j in start..out.len() {
        combine_block::<1>(&mut out[j..=j], j, base, h, weights, stages);
    }
}

/// [`combine`] for the `B` entries from `start` on.
#[inline(always)]
fn combine_block<const B: usize>(
    out: &mut [f64],
    start: usize,
    base: Option<&[f64]>,
    h: f64,
    weights: &[f64],
    stages: &[Vec<f64>],
) {
    let mut acc = [0.0; B];
    for (&w, k) in weights.iter().zip(stages) {
        if w != 0.0 {
            for (a, &kj) in acc.iter_mut().zip(&k[start..start + B]) {
                *a += w * kj;
            }
        }
    }
    match base {
        Some(b) => {
            for ((o, &a), &bj) in out.iter_mut().zip(&acc).zip(&b[start..start + B]) {
                *o = bj + h * a;
            }
        }
        None => {
            for (o, &a) in out.iter_mut().zip(&acc) {
                *o = a * h;
            }
        }
    }
}
