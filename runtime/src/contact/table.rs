//! Contact vectors of moving telescopic positions, tabulated once per scene in time.
//!
//! With moving positions every right-hand side evaluates the shape functions at the moving
//! contact points: exponentials, sines and cosines, measured at ~60 % of a case-study run
//! with dop853. The positions are known functions of time, so the contact vectors `g_c(t)`
//! are too. A [`ContactTable`] samples them and their time derivatives `gd_c(t)` on a uniform
//! grid over the interval where positions move and interpolates by cubic Hermite polynomials
//! in `t`; `gd` is the derivative of that cubic. Before and after the interval the positions
//! are constant and the end nodes hold the exact values (`gd = 0` there).
//!
//! The grid is not guessed: it starts at [`START_INTERVALS`] intervals and is refined until, in
//! every interval, `g` at the midpoint (where a cubic Hermite interpolant's error peaks) and
//! `gd` at `1/2 - 1/(2 sqrt 3)` (where its derivative's error peaks) match the exact
//! evaluation to [`G_TOLERANCE`] and [`GD_TOLERANCE`] of the largest entry; a failed check
//! jumps to the grid the interpolants' orders predict, and a halving of the step keeps the
//! nodes and takes the check's exact midpoints as the new ones (no evaluation repeated). Hand-written: it is a few lines of Hermite
//! interpolation of a vector-valued function with a known derivative plus this error check,
//! which no interpolation crate provides.

use crate::profile::Profile;

/// Largest error of interpolated `g` allowed, relative to the largest `|g|` entry (the
/// contact stiffness term `c g g^T` then carries ~2e-12 of itself; 1e-13 would double the
/// table and its build time for case-study).
pub const G_TOLERANCE: f64 = 1e-12;
/// Largest error of interpolated `gd` allowed, relative to the largest `|gd|` entry. `gd`
/// enters only through the contact damping, `d gd . z`: with case-study's numbers
/// (`d = 1000 N s/m`, `|gd| <= ~1 /s`, `c |g| ~ 2.4e8 N/m`) an error of 1e-8 of it is ~4e-14
/// of the contact spring force, below `g`'s own tolerance.
pub const GD_TOLERANCE: f64 = 1e-8;
/// Intervals of the first grid tried.
pub const START_INTERVALS: usize = 64;
/// Most intervals tried before giving up on the table (the exact evaluation is used then).
pub const MAX_INTERVALS: usize = 1 << 18;

/// Where a cubic Hermite interpolant's derivative error peaks in a unit interval (it peaks
/// at `1 - s` too, with the same size where the 4th derivative is nearly constant over an
/// interval; one point keeps the check at two evaluations per interval).
const DERIVATIVE_CHECK: f64 = 0.211_324_865_405_187_1;

/// The exact `g` and `gd` at a table's intervals' midpoints, interval after interval: the
/// nodes a halving adds.
#[derive(Debug, Default)]
struct Midpoints {
    g: Vec<f64>,
    gd: Vec<f64>,
}

/// What a [`ContactTable`] stores: its grid, the columns that vary, the constant ones' values,
/// and the varying columns' `g` and `gd` node after node.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactTableParts {
    /// First node's time (s).
    pub start: f64,
    /// Grid step (s).
    pub step: f64,
    /// Number of intervals (nodes: one more).
    pub intervals: usize,
    /// The columns that change in time (indices into the full vectors), ascending.
    pub varying: Vec<usize>,
    /// The full `g` with the constant columns' values (0 at the varying ones).
    pub constant_g: Vec<f64>,
    /// `g` of the varying columns, node after node.
    pub g: Vec<f64>,
    /// `gd` (1/s) of the varying columns, node after node.
    pub gd: Vec<f64>,
}

/// Contact vectors `g` and their time derivatives `gd` on a uniform time grid: the
/// [`ContactTableParts`] it stores, and the interpolation errors measured when it was built.
#[derive(Debug, Clone)]
pub struct ContactTable {
    data: ContactTableParts,
    error_g: f64,
    error_gd: f64,
}

impl ContactTable {
    /// Tabulates `exact(t, g, gd)` (contact vectors and their time derivatives at `t`, s;
    /// `width` entries each) over the interval where `positions` move. `None` when no
    /// position moves, when a moving profile has a kink in its rate (piecewise-linear: `gd`
    /// jumps), or when [`MAX_INTERVALS`] do not reach the tolerances.
    pub fn build(
        positions: &[Profile],
        width: usize,
        exact: impl FnMut(f64, &mut [f64], &mut [f64]),
    ) -> Option<Self> {
        Self::build_to(positions, width, (G_TOLERANCE, GD_TOLERANCE), exact)
    }

    /// As [`ContactTable::build`] to the tolerances `(g, gd)`, relative to the largest
    /// entries: for contact vectors that are only twice continuously differentiable in time
    /// (a contact point crossing a spline knot), where [`G_TOLERANCE`] would need a grid
    /// thousands of times finer.
    pub fn build_to(
        positions: &[Profile],
        width: usize,
        (g_tolerance, gd_tolerance): (f64, f64),
        mut exact: impl FnMut(f64, &mut [f64], &mut [f64]),
    ) -> Option<Self> {
        let moving: Vec<&Profile> = positions.iter().filter(|p| !p.is_constant()).collect();
        if moving.is_empty() || !moving.iter().all(|p| p.has_continuous_rate()) {
            return None;
        }
        let breakpoints: Vec<f64> = moving.iter().flat_map(|p| p.breakpoints()).collect();
        let start = breakpoints.iter().copied().fold(f64::INFINITY, f64::min);
        let end = breakpoints
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        if end.partial_cmp(&start) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let mut table = ContactTable::sample(start, end, START_INTERVALS, width, &mut exact);
        let mut midpoints = Midpoints::default();
        loop {
            let (error_g, error_gd) = table.check(&mut exact, &mut midpoints);
            if error_g <= g_tolerance && error_gd <= gd_tolerance {
                table.error_g = error_g;
                table.error_gd = error_gd;
                table.drop_constant_columns();
                return Some(table);
            }
            // the errors go as step^4 (g) and step^3 (gd): jump to the grid they predict
            // (with 10 % to spare), at least one halving
            let intervals = table.data.intervals;
            let factor = (error_g / g_tolerance)
                .powf(0.25)
                .max((error_gd / gd_tolerance).powf(1.0 / 3.0));
            let wanted = (1.1 * factor * intervals as f64).min(2.0 * MAX_INTERVALS as f64);
            let next = (wanted.ceil() as usize).max(2 * intervals);
            if next > MAX_INTERVALS {
                return None;
            }
            // a halving keeps every node and takes the check's midpoints as the new ones
            table = match next == 2 * intervals {
                true => table.halved(&midpoints),
                false => ContactTable::sample(start, end, next, width, &mut exact),
            };
        }
    }

    /// The exact values on `intervals` uniform intervals of `[start, end]`.
    fn sample(
        start: f64,
        end: f64,
        intervals: usize,
        width: usize,
        exact: &mut impl FnMut(f64, &mut [f64], &mut [f64]),
    ) -> Self {
        let mut table = ContactTable {
            data: ContactTableParts {
                start,
                step: (end - start) / intervals as f64,
                intervals,
                varying: (0..width).collect(),
                constant_g: vec![0.0; width],
                g: vec![0.0; (intervals + 1) * width],
                gd: vec![0.0; (intervals + 1) * width],
            },
            error_g: f64::NAN,
            error_gd: f64::NAN,
        };
        for i in 0..=intervals {
            let t = table.node_time(i);
            exact(
                t,
                &mut table.data.g[i * width..(i + 1) * width],
                &mut table.data.gd[i * width..(i + 1) * width],
            );
        }
        table
    }

    /// This table on half its step: its nodes, and between them the exact values at its
    /// intervals' midpoints (from [`ContactTable::check`]).
    fn halved(&self, midpoints: &Midpoints) -> Self {
        let w = self.data.varying.len();
        let intervals = 2 * self.data.intervals;
        let mut g = Vec::with_capacity((intervals + 1) * w);
        let mut gd = Vec::with_capacity((intervals + 1) * w);
        for i in 0..self.data.intervals {
            g.extend_from_slice(&self.data.g[i * w..(i + 1) * w]);
            gd.extend_from_slice(&self.data.gd[i * w..(i + 1) * w]);
            g.extend_from_slice(&midpoints.g[i * w..(i + 1) * w]);
            gd.extend_from_slice(&midpoints.gd[i * w..(i + 1) * w]);
        }
        let last = self.data.intervals * w;
        g.extend_from_slice(&self.data.g[last..last + w]);
        gd.extend_from_slice(&self.data.gd[last..last + w]);
        ContactTable {
            data: ContactTableParts {
                start: self.data.start,
                step: 0.5 * self.data.step,
                intervals,
                varying: self.data.varying.clone(),
                constant_g: self.data.constant_g.clone(),
                g,
                gd,
            },
            error_g: f64::NAN,
            error_gd: f64::NAN,
        }
    }

    /// Largest errors of `g` at the intervals' midpoints and of `gd` where a cubic Hermite
    /// interpolant's derivative error peaks, each relative to its largest node entry; the
    /// exact values at the midpoints are kept in `midpoints`.
    fn check(
        &self,
        exact: &mut impl FnMut(f64, &mut [f64], &mut [f64]),
        midpoints: &mut Midpoints,
    ) -> (f64, f64) {
        let w = self.data.varying.len();
        let g_scale = max_abs(&self.data.g).max(f64::MIN_POSITIVE);
        let gd_scale = max_abs(&self.data.gd).max(f64::MIN_POSITIVE);
        let (mut g_exact, mut gd_exact) = (vec![0.0; w], vec![0.0; w]);
        let (mut g_table, mut gd_table) = (vec![0.0; w], vec![0.0; w]);
        let (mut error_g, mut error_gd) = (0.0_f64, 0.0_f64);
        midpoints.g.clear();
        midpoints.gd.clear();
        for i in 0..self.data.intervals {
            let t0 = self.node_time(i);
            let t = t0 + 0.5 * self.data.step;
            exact(t, &mut g_exact, &mut gd_exact);
            self.interpolate(t, &mut g_table, &mut gd_table);
            error_g = error_g.max(max_difference(&g_exact, &g_table) / g_scale);
            midpoints.g.extend_from_slice(&g_exact);
            midpoints.gd.extend_from_slice(&gd_exact);
            let t = t0 + DERIVATIVE_CHECK * self.data.step;
            exact(t, &mut g_exact, &mut gd_exact);
            self.interpolate(t, &mut g_table, &mut gd_table);
            error_gd = error_gd.max(max_difference(&gd_exact, &gd_table) / gd_scale);
        }
        (error_g, error_gd)
    }

    /// Interpolated contact vectors `g` and time derivatives `gd` (per s) at `t` (s);
    /// allocation-free. Outside the tabulated interval the end nodes' values.
    #[inline]
    pub fn interpolate(&self, t: f64, g: &mut [f64], gd: &mut [f64]) {
        self.interpolate_rows(t, g.len(), |_| true, g, gd);
    }

    /// As [`ContactTable::interpolate`], but only the rows (consecutive blocks of `row_len`
    /// entries: one contact's vector each) for which `wanted(row)` holds; the other rows of
    /// `g` and `gd` are left as they are. A right-hand side needs only the closed contacts'.
    /// A `row_len` of 0 counts as 1.
    #[inline]
    pub fn interpolate_rows(
        &self,
        t: f64,
        row_len: usize,
        wanted: impl Fn(usize) -> bool,
        g: &mut [f64],
        gd: &mut [f64],
    ) {
        let row_len = row_len.max(1);
        let s = ((t - self.data.start) / self.data.step).clamp(0.0, self.data.intervals as f64);
        let i = (s as usize).min(self.data.intervals - 1);
        let u = s - i as f64;
        let h = self.data.step;
        let v = 1.0 - u;
        // cubic Hermite basis and its derivative in u
        let (h00, h10, h01, h11) = (
            (1.0 + 2.0 * u) * v * v,
            u * v * v,
            u * u * (3.0 - 2.0 * u),
            -u * u * v,
        );
        let (d00, d10, d01, d11) = (
            -6.0 * u * v,
            v * (1.0 - 3.0 * u),
            6.0 * u * v,
            u * (3.0 * u - 2.0),
        );
        let w = self.data.varying.len();
        let (g0, g1) = self.data.g[i * w..(i + 2) * w].split_at(w);
        let (s0, s1) = self.data.gd[i * w..(i + 2) * w].split_at(w);
        let (d00, d01) = (d00 / h, d01 / h);
        // one pass for the constant entries (no library copy and fill for these few)
        let rows = g
            .chunks_mut(row_len)
            .zip(gd.chunks_mut(row_len))
            .zip(self.data.constant_g.chunks(row_len));
        for (row, ((g_row, gd_row), constant)) in rows.enumerate() {
            if wanted(row) {
                for ((gk, gdk), &c) in g_row.iter_mut().zip(gd_row.iter_mut()).zip(constant) {
                    *gk = c;
                    *gdk = 0.0;
                }
            }
        }
        // the varying columns are ascending: their row advances with them
        let (mut row, mut row_end) = (0, row_len);
        let nodes = g0.iter().zip(g1).zip(s0.iter().zip(s1));
        for (&k, ((&a0, &a1), (&b0, &b1))) in self.data.varying.iter().zip(nodes) {
            while k >= row_end {
                row += 1;
                row_end += row_len;
            }
            if wanted(row) {
                g[k] = h00 * a0 + h01 * a1 + h * (h10 * b0 + h11 * b1);
                gd[k] = d00 * a0 + d01 * a1 + d10 * b0 + d11 * b1;
            }
        }
    }

    /// Stores only the columns that change: a contact point fixed on its section (the foot
    /// of the inner section, the top of the outer one) has constant entries there and
    /// `gd = 0`; case-study has half its columns so. Bitwise constant only: a column that
    /// varies by rounding stays tabulated.
    fn drop_constant_columns(&mut self) {
        let (w, nodes) = (self.data.varying.len(), self.data.intervals + 1);
        let varying: Vec<usize> = (0..w)
            .filter(|&k| {
                (0..nodes).any(|i| {
                    self.data.g[i * w + k] != self.data.g[k] || self.data.gd[i * w + k] != 0.0
                })
            })
            .collect();
        self.data.constant_g = (0..w)
            .map(|k| {
                if varying.contains(&k) {
                    0.0
                } else {
                    self.data.g[k]
                }
            })
            .collect();
        let keep = |data: &[f64]| -> Vec<f64> {
            (0..nodes)
                .flat_map(|i| varying.iter().map(move |&k| data[i * w + k]))
                .collect()
        };
        self.data.g = keep(&self.data.g);
        self.data.gd = keep(&self.data.gd);
        self.data.varying = varying;
    }

    /// The stored data, for a file or another language to rebuild the same interpolant.
    pub fn parts(&self) -> ContactTableParts {
        self.data.clone()
    }

    /// The table of `parts` (as [`ContactTable::parts`] gave them); interpolates exactly as
    /// the table they came from.
    ///
    /// # Errors
    /// A message naming the part whose size or values do not fit.
    pub fn from_parts(parts: ContactTableParts) -> Result<Self, String> {
        let ContactTableParts {
            start,
            step,
            intervals,
            ref varying,
            ref constant_g,
            ref g,
            ref gd,
        } = parts;
        let full = constant_g.len();
        if !(start.is_finite() && step.is_finite() && step > 0.0 && intervals >= 1) {
            return Err(format!(
                "needs a finite start, a step > 0 and at least one interval (got start {start}, \
                 step {step}, {intervals} intervals)"
            ));
        }
        if varying.windows(2).any(|w| w[0] >= w[1]) || varying.iter().any(|&k| k >= full) {
            return Err(format!(
                "`varying` must be ascending column indices below {full}"
            ));
        }
        let values = (intervals + 1) * varying.len();
        if g.len() != values || gd.len() != values {
            return Err(format!(
                "`g` and `gd` need {values} entries each ({} nodes of {} columns); got {} and {}",
                intervals + 1,
                varying.len(),
                g.len(),
                gd.len()
            ));
        }
        if [constant_g, g, gd]
            .iter()
            .any(|v| v.iter().any(|x| !x.is_finite()))
        {
            return Err("its values must be finite".into());
        }
        Ok(ContactTable {
            data: parts,
            error_g: f64::NAN,
            error_gd: f64::NAN,
        })
    }

    /// Number of columns that change in time (of the vectors' full width).
    pub fn varying_columns(&self) -> usize {
        self.data.varying.len()
    }

    /// Entries of `g` (and of `gd`) in all.
    pub fn full_width(&self) -> usize {
        self.data.constant_g.len()
    }

    /// Number of grid intervals.
    pub fn intervals(&self) -> usize {
        self.data.intervals
    }

    /// Grid step (s).
    pub fn step(&self) -> f64 {
        self.data.step
    }

    /// The tabulated interval `(start, end)` (s).
    pub fn span(&self) -> (f64, f64) {
        (self.data.start, self.node_time(self.data.intervals))
    }

    /// Largest checked errors of `g` and `gd`, each relative to its largest entry.
    pub fn checked_errors(&self) -> (f64, f64) {
        (self.error_g, self.error_gd)
    }

    fn node_time(&self, i: usize) -> f64 {
        self.data.start + i as f64 * self.data.step
    }
}

fn max_abs(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m, v| m.max(v.abs()))
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::ShapedProfile;

    fn smoothstep(start: f64, end: f64) -> Profile {
        Profile::Shaped(ShapedProfile::Smoothstep {
            start,
            end,
            from: 0.35,
            to: 1.15,
        })
    }

    /// A vector-valued function of a moving position like a contact vector: oscillating and
    /// growing shapes of `a(t)`, and its exact time derivative.
    fn shapes_of(p: &Profile) -> impl Fn(f64, &mut [f64], &mut [f64]) + '_ {
        move |t, g, gd| {
            let (a, rate) = (p.value(t), p.rate(t));
            for (k, (g, gd)) in g.iter_mut().zip(gd.iter_mut()).enumerate() {
                let kap = 2.0 + 3.0 * k as f64;
                *g = (kap * a).cos() + (kap * (a - 1.35)).exp();
                *gd = (-kap * (kap * a).sin() + kap * (kap * (a - 1.35)).exp()) * rate;
            }
        }
    }

    /// [`shapes_of`] with the columns `still` held at their values (`gd = 0` there).
    fn with_still_columns<'a>(
        p: &'a Profile,
        still: &'a [(usize, f64)],
    ) -> impl Fn(f64, &mut [f64], &mut [f64]) + 'a {
        let moving = shapes_of(p);
        move |t, g, gd| {
            moving(t, g, gd);
            for &(k, v) in still {
                (g[k], gd[k]) = (v, 0.0);
            }
        }
    }

    #[test]
    fn interpolation_meets_its_tolerances_between_the_checked_points() {
        let p = smoothstep(0.0, 12.0);
        let exact = shapes_of(&p);
        let table = ContactTable::build(std::slice::from_ref(&p), 4, &exact).expect("a table");
        let (mut g, mut gd, mut ge, mut gde) = ([0.0; 4], [0.0; 4], [0.0; 4], [0.0; 4]);
        let (mut worst_g, mut worst_gd) = (0.0_f64, 0.0_f64);
        // 7919 points (prime, so not aligned with the checked ones), plus both sides outside
        for j in 0..=7919 {
            let t = -1.0 + 14.0 * j as f64 / 7919.0;
            table.interpolate(t, &mut g, &mut gd);
            exact(t, &mut ge, &mut gde);
            worst_g = worst_g.max(max_difference(&g, &ge));
            worst_gd = worst_gd.max(max_difference(&gd, &gde));
        }
        // the check looks where the errors of a cubic Hermite interpolant peak; elsewhere they
        // may exceed it a little, not by a factor 2
        let (scale_g, scale_gd) = (max_abs(&table.data.g), max_abs(&table.data.gd));
        assert!(
            worst_g <= 2.0 * G_TOLERANCE * scale_g,
            "g off by {worst_g:e}"
        );
        assert!(
            worst_gd <= 2.0 * GD_TOLERANCE * scale_gd,
            "gd off by {worst_gd:e}"
        );
        assert!(
            table.intervals() > START_INTERVALS,
            "the check refined the grid"
        );
    }

    #[test]
    fn a_halved_table_is_the_table_sampled_on_the_finer_grid() {
        let p = smoothstep(0.0, 12.0);
        let mut exact = shapes_of(&p);
        let coarse = ContactTable::sample(0.0, 12.0, 96, 4, &mut exact);
        let mut midpoints = Midpoints::default();
        coarse.check(&mut exact, &mut midpoints);
        let halved = coarse.halved(&midpoints);
        let fine = ContactTable::sample(0.0, 12.0, 192, 4, &mut exact);
        assert_eq!(
            (halved.data.intervals, halved.data.step),
            (fine.data.intervals, fine.data.step)
        );
        // the midpoints' times may differ from the finer nodes' by a rounding of t
        let scale = max_abs(&fine.data.g).max(max_abs(&fine.data.gd));
        assert!(max_difference(&halved.data.g, &fine.data.g) <= 1e-13 * scale);
        assert!(max_difference(&halved.data.gd, &fine.data.gd) <= 1e-13 * scale);
    }

    #[test]
    fn constant_columns_are_exact_and_not_stored() {
        let p = smoothstep(0.0, 12.0);
        // columns 1 and 3 hold still (a contact point fixed on its section)
        let exact = with_still_columns(&p, &[(1, 0.75), (3, -2.5)]);
        let table = ContactTable::build(std::slice::from_ref(&p), 4, &exact).expect("a table");
        assert_eq!(table.varying_columns(), 2);
        let (mut g, mut gd, mut ge, mut gde) = ([9.0; 4], [9.0; 4], [0.0; 4], [0.0; 4]);
        for j in 0..=997 {
            let t = 12.0 * j as f64 / 997.0;
            table.interpolate(t, &mut g, &mut gd);
            exact(t, &mut ge, &mut gde);
            assert_eq!((g[1], gd[1], g[3], gd[3]), (0.75, 0.0, -2.5, 0.0));
            for k in [0, 2] {
                assert!(
                    (g[k] - ge[k]).abs() <= 2.0 * G_TOLERANCE * 2.0,
                    "g[{k}] at {t}"
                );
                assert!(
                    (gd[k] - gde[k]).abs() <= 2.0 * GD_TOLERANCE * 20.0,
                    "gd[{k}] at {t}"
                );
            }
        }
    }

    #[test]
    fn rows_interpolate_as_the_whole_and_leave_the_others() {
        let p = smoothstep(0.0, 12.0);
        // three rows of two; in row 1 one column holds still, row 2 holds still entirely
        let exact = with_still_columns(&p, &[(3, 0.75), (4, -2.5), (5, 4.0)]);
        let table = ContactTable::build(std::slice::from_ref(&p), 6, exact).expect("a table");
        let (mut whole, mut whole_d) = ([0.0; 6], [0.0; 6]);
        for j in 0..=97 {
            let t = -0.5 + 13.0 * j as f64 / 97.0;
            table.interpolate(t, &mut whole, &mut whole_d);
            for wanted_rows in [[true, false, true], [false, true, false], [true; 3]] {
                let (mut g, mut gd) = ([9.0; 6], [7.0; 6]);
                table.interpolate_rows(t, 2, |r| wanted_rows[r], &mut g, &mut gd);
                for k in 0..6 {
                    let (want_g, want_gd) = if wanted_rows[k / 2] {
                        (whole[k], whole_d[k])
                    } else {
                        (9.0, 7.0)
                    };
                    assert_eq!((g[k], gd[k]), (want_g, want_gd), "entry {k} at {t}");
                }
            }
        }
    }

    #[test]
    fn no_table_without_motion_or_with_kinks() {
        let f = |_: f64, g: &mut [f64], gd: &mut [f64]| {
            g.fill(1.0);
            gd.fill(0.0)
        };
        assert!(ContactTable::build(&[Profile::Constant(0.5)], 2, f).is_none());
        let kinked = Profile::Shaped(ShapedProfile::PiecewiseLinear {
            times: vec![0.0, 1.0],
            values: vec![0.4, 0.6],
        });
        assert!(ContactTable::build(&[kinked], 2, f).is_none());
    }
}
