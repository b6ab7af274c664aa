//! Each sensor's noise, estimated from the record where it is not given: from the
//! differences of its samples of order 2, 3, 4 and 6, which cancel a smooth signal more the
//! higher their order and keep white noise (`var` of the `k`-th difference is `C(2k, k)
//! sigma^2`: 6 for the second), by their median absolute value so that the record's few sharp
//! features (a step of the drive) do not count, and per block so that the impacts of a
//! clearance record do not either. A signal that rings at a twentieth of the sample rate leaves
//! `(omega h)^k` of its amplitude in the `k`-th difference: at 100 Hz a 5 Hz ring makes the
//! second differences read 23 times the noise and the sixth 1.03 times, so the estimate is
//! that of the first two successive orders that agree ([`estimate`]): white noise reads the
//! same at every order, a smooth signal lower at each higher one.

use telescopic_runtime::Output;

/// Where a sensor's noise figure comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoiseSource {
    /// Given by the user.
    Given,
    /// Estimated from the record's second differences.
    Estimated,
    /// The record shows no noise (synthetic): [`NOISE_FLOOR`] of the sensor's range.
    Floor,
}

impl NoiseSource {
    /// One word for reports.
    pub fn word(self) -> &'static str {
        match self {
            NoiseSource::Given => "given",
            NoiseSource::Estimated => "estimated",
            NoiseSource::Floor => "none measured: 1e-6 of the range",
        }
    }
}

/// The weight of a noise-free sensor: this share of its range. An estimate below it counts
/// as none (a synthetic record's differences of high order see its printed digits: 1e-9 of
/// the range); a sensor quieter than that needs its noise given.
pub const NOISE_FLOOR: f64 = 1e-6;

/// Median absolute deviation to the standard deviation of a normal distribution.
const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;

/// The noise of `samples` (its unit): given, else estimated, else the floor.
pub fn noise_of(output: Output, samples: &[f64], given: &[(Output, f64)]) -> (f64, NoiseSource) {
    if let Some(&(_, sigma)) = given.iter().find(|(o, _)| *o == output) {
        return (sigma, NoiseSource::Given);
    }
    let floor = floor_of(samples);
    match above_floor(samples, floor) {
        Some(estimated) => (estimated, NoiseSource::Estimated),
        None => (floor, NoiseSource::Floor),
    }
}

/// [`NOISE_FLOOR`] of the range of `samples` (their unit).
fn floor_of(samples: &[f64]) -> f64 {
    let (low, high) = samples
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    NOISE_FLOOR * (high - low).max(f64::MIN_POSITIVE)
}

/// The estimate of `samples`' noise where it shows above `floor`: below it the differences
/// see the record's printed digits, not a sensor.
fn above_floor(samples: &[f64], floor: f64) -> Option<f64> {
    let estimated = estimate(samples);
    (estimated > floor).then_some(estimated)
}

/// The noise of a recorded drive force (N), when it shows above [`NOISE_FLOOR`] of its
/// range: a force held between switches reads none. The model is driven by the force as
/// recorded, so the sensors' response to this noise is in their residuals.
pub fn force_noise(force: &[f64]) -> Option<f64> {
    above_floor(force, floor_of(force))
}

/// Parses `SENSOR=SIGMA,...` (`kappa_1_0=1e-4,tip_rel=1e-4`): noise figures given.
///
/// # Errors
/// [`crate::Error::Option`] naming the entry: not an output, not a positive number, given
/// twice.
pub fn parse_noise(text: &str) -> crate::Result<Vec<(Output, f64)>> {
    let bad = |entry: &str, rule: &str| {
        crate::Error::option(crate::OptionName::Noise, format!("{entry}: {rule}"))
    };
    let mut out: Vec<(Output, f64)> = Vec::new();
    for entry in text.split(',').map(str::trim).filter(|e| !e.is_empty()) {
        let (name, sigma) = entry
            .split_once('=')
            .ok_or_else(|| bad(entry, "give SENSOR=SIGMA, e.g. kappa_1_0=1e-4"))?;
        let output: Output = name
            .trim()
            .parse()
            .map_err(|rule: String| bad(entry, &rule))?;
        let sigma = sigma
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|s| s.is_finite() && *s > 0.0)
            .ok_or_else(|| bad(entry, "SIGMA must be a positive number (the sensor's unit)"))?;
        if out.iter().any(|(o, _)| *o == output) {
            return Err(bad(entry, "the sensor is given twice"));
        }
        out.push((output, sigma));
    }
    Ok(out)
}

/// Samples per block of [`estimate`].
const BLOCK: usize = 500;

/// Which of the blocks' estimates is taken, from the lowest (a quantile).
const BLOCK_QUANTILE: f64 = 0.25;

/// The orders of the differences [`estimate`] takes the least of, with their coefficients.
const DIFFERENCES: [&[f64]; 4] = [
    &[1.0, -2.0, 1.0],
    &[1.0, -3.0, 3.0, -1.0],
    &[1.0, -4.0, 6.0, -4.0, 1.0],
    &[1.0, -6.0, 15.0, -20.0, 15.0, -6.0, 1.0],
];

/// Two orders whose estimates agree within this ratio see white noise (a smooth signal
/// reads lower at every higher order; over 500 samples two orders' estimates of white
/// noise scatter by up to 25 %).
const ORDERS_AGREE: f64 = 1.3;

/// The white-noise standard deviation of `samples`, 0 when none shows: per order of
/// `DIFFERENCES`, the estimate per block of 500 samples and of those the lower quartile,
/// so that stretches of impacts (whose sharp motion survives the differences) do not count
/// (a record shorter than two blocks is one block); then the first two successive orders
/// that agree within `ORDERS_AGREE`, the lesser of the two. White noise reads the same at
/// every order (the quartile of blocks about 4 % low); a smooth signal's leak falls with
/// the order, and a record where no two orders agree (a noise-free, synthetic one) has no
/// noise to show.
pub fn estimate(samples: &[f64]) -> f64 {
    let by_order: Vec<f64> = DIFFERENCES
        .iter()
        .map(|coefficients| estimate_of_order(samples, coefficients))
        .collect();
    by_order
        .windows(2)
        .find(|pair| {
            pair[1] > 0.0 && pair[0] <= ORDERS_AGREE * pair[1] && pair[1] <= ORDERS_AGREE * pair[0]
        })
        .map_or(0.0, |pair| pair[0].min(pair[1]))
}

/// [`estimate`] from the differences with `coefficients`.
fn estimate_of_order(samples: &[f64], coefficients: &[f64]) -> f64 {
    if samples.len() < 2 * BLOCK {
        return block_estimate(samples, coefficients);
    }
    let mut blocks: Vec<f64> = samples
        .chunks(BLOCK)
        .map(|block| block_estimate(block, coefficients))
        .collect();
    let k = ((blocks.len() - 1) as f64 * BLOCK_QUANTILE).round() as usize;
    let (_, quantile, _) = blocks.select_nth_unstable_by(k, f64::total_cmp);
    *quantile
}

/// The estimate of one block: the median absolute difference with `coefficients`, scaled
/// by the noise's share (the root of the squared coefficients' sum); 0 when the block is
/// too short for one difference.
fn block_estimate(samples: &[f64], coefficients: &[f64]) -> f64 {
    let mut differences: Vec<f64> = samples
        .windows(coefficients.len())
        .map(|w| {
            w.iter()
                .zip(coefficients)
                .map(|(y, c)| y * c)
                .sum::<f64>()
                .abs()
        })
        .collect();
    if differences.is_empty() {
        return 0.0;
    }
    let gain = coefficients.iter().map(|c| c * c).sum::<f64>().sqrt();
    let middle = differences.len() / 2;
    let (_, median, _) = differences.select_nth_unstable_by(middle, f64::total_cmp);
    MAD_TO_SIGMA * *median / gain
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    /// White noise on a smooth signal (a 2 Hz sine at 1 kHz with a step) is found within
    /// 8 % over 5000 samples, also when a tenth of the record rattles.
    #[test]
    fn the_noise_of_a_smooth_signal_is_found() {
        let normal = Normal::new(0.0, 1e-4).unwrap();
        for seed in 0..3 {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let samples: Vec<f64> = (0..5000)
                .map(|i| {
                    let t = i as f64 * 1e-3;
                    let step = if i > 2500 { 0.5 } else { 0.0 };
                    (2.0 * std::f64::consts::PI * 2.0 * t).sin() * 0.01
                        + step
                        + normal.sample(&mut rng)
                })
                .collect();
            let sigma = estimate(&samples);
            assert!((sigma / 1e-4 - 1.0).abs() < 0.08, "seed {seed}: {sigma}");
            // impacts: a 200 Hz ring of 1 mm over the record's last 500 samples
            let mut rattling = samples.clone();
            for (i, v) in rattling.iter_mut().enumerate().skip(4500) {
                *v += 1e-3 * (i as f64 * 1e-3 * 2.0 * std::f64::consts::PI * 200.0).sin();
            }
            let sigma = estimate(&rattling);
            assert!(
                (sigma / 1e-4 - 1.0).abs() < 0.08,
                "seed {seed}, rattling: {sigma}"
            );
        }
        let (sigma, source) = noise_of(Output::TipRel, &[0.0; 30], &[]);
        assert_eq!(source, NoiseSource::Floor);
        assert!(sigma > 0.0);
    }

    /// A force held between switches (a drive's bang-bang) reads no noise; the same force
    /// read with 1 N of noise reads it within 10 %.
    #[test]
    fn a_held_force_reads_no_noise_and_a_noisy_one_its_noise() {
        let held: Vec<f64> = (0..5000)
            .map(|i| if (i / 300) % 2 == 0 { 100.0 } else { -100.0 })
            .collect();
        assert_eq!(force_noise(&held), None);
        let normal = Normal::new(0.0, 1.0).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let noisy: Vec<f64> = held.iter().map(|f| f + normal.sample(&mut rng)).collect();
        let read = force_noise(&noisy).expect("noise read");
        assert!((read - 1.0).abs() < 0.1, "{read} N");
    }

    /// A ring at a twentieth of the sample rate (5 Hz at 100 Hz, decaying, 1000 times the
    /// noise): the second differences alone read it 23 times high; the orders that agree
    /// find the noise within 25 % over 500 samples; the same ring without noise shows none.
    #[test]
    fn the_noise_under_a_ring_near_the_sample_rate_is_found() {
        let normal = Normal::new(0.0, 1e-3).unwrap();
        for seed in 0..5 {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let samples: Vec<f64> = (0..500)
                .map(|i| {
                    let t = i as f64 * 1e-2;
                    (2.0 * std::f64::consts::PI * 5.0 * t).sin() * (-0.2 * t).exp()
                        + normal.sample(&mut rng)
                })
                .collect();
            let second = estimate_of_order(&samples, DIFFERENCES[0]);
            assert!(second > 10e-3, "seed {seed}: {second}");
            let sigma = estimate(&samples);
            assert!((sigma / 1e-3 - 1.0).abs() < 0.25, "seed {seed}: {sigma}");
        }
        let clean: Vec<f64> = (0..500)
            .map(|i| (2.0 * std::f64::consts::PI * 5.0 * i as f64 * 1e-2).sin())
            .collect();
        assert_eq!(estimate(&clean), 0.0);
        let (_, source) = noise_of(Output::TipRel, &clean, &[]);
        assert_eq!(source, NoiseSource::Floor);
    }
}
