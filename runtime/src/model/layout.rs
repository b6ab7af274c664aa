//! Sizes and index layout of a model's coordinates, and the names of its outputs.
//!
//! Coordinates `q` are stacked section by section: section `k`'s modes `i = 1..=N_k` sit at
//! `offset(k) + i - 1`. In the computing coordinates of [`crate::model`], index 0 is the
//! vehicle position and the rest keep their place.

use crate::model::output::Output;
/// One contact point: overlap `k` (the inner section, `2..=n`) and point `j` (`0..n_c`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// The inner section `k` (1-based, `>= 2`); the outer one is `k - 1`.
    pub overlap: usize,
    /// Point index `j`, `0..n_c`; `j = 0` is the foot of section `k`.
    pub point: usize,
    /// Position `s_j = j / (n_c - 1)` along the overlap (0 at the foot of `k`, 1 at the top
    /// of `k - 1`).
    pub fraction: f64,
}

/// Sizes and offsets of a model.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Layout {
    modes: Vec<usize>,
    offsets: Vec<usize>,
    contact_points: usize,
}

impl Layout {
    /// Layout for the given modes per section and contact points per overlap.
    ///
    /// # Panics
    /// If there are no sections, a section has no modes, or `contact_points < 2` with more
    /// than one section.
    pub fn new(modes: &[usize], contact_points: usize) -> Self {
        assert!(
            !modes.is_empty() && modes.iter().all(|&m| m >= 1),
            "every section needs a mode"
        );
        assert!(
            modes.len() == 1 || contact_points >= 2,
            "at least two contacts per overlap"
        );
        let offsets = modes
            .iter()
            .scan(0, |acc, &m| {
                let o = *acc;
                *acc += m;
                Some(o)
            })
            .collect();
        Self {
            modes: modes.to_vec(),
            offsets,
            contact_points,
        }
    }

    /// Number of sections `n`.
    pub fn sections(&self) -> usize {
        self.modes.len()
    }

    /// Modes per section `N_k`.
    pub fn modes(&self) -> &[usize] {
        &self.modes
    }

    /// Number of generalized coordinates `sum N_k`.
    pub fn dof(&self) -> usize {
        self.modes.iter().sum()
    }

    /// Size of the first-order state `[q, qd]`.
    pub fn state_len(&self) -> usize {
        2 * self.dof()
    }

    /// Index of the first coordinate of section `k` (1-based).
    pub fn offset(&self, k: usize) -> usize {
        self.offsets[k - 1]
    }

    /// Index of mode `i` of section `k` (both 1-based).
    pub fn index(&self, k: usize, i: usize) -> usize {
        self.offsets[k - 1] + i - 1
    }

    /// Contact points per overlap `n_c`.
    pub fn contacts_per_overlap(&self) -> usize {
        self.contact_points
    }

    /// Number of contact points in the model, `(n - 1) n_c`.
    pub fn contact_count(&self) -> usize {
        (self.sections() - 1) * self.contact_points
    }

    /// All contact points, overlap by overlap (`c = (k - 2) n_c + j`).
    pub fn contacts(&self) -> impl Iterator<Item = ContactPoint> + '_ {
        let nc = self.contact_points;
        (2..=self.sections()).flat_map(move |k| {
            (0..nc).map(move |j| ContactPoint {
                overlap: k,
                point: j,
                fraction: j as f64 / (nc - 1) as f64,
            })
        })
    }

    /// Output names (docs/model.md section 5): `vehicle`, `tip_rel`, `top1_rel`, then `xi_k_j`
    /// and `f_k_j` for every contact, then `drive_force` when the vehicle motion is
    /// prescribed.
    pub fn output_names(&self, prescribed_motion: bool) -> Vec<String> {
        self.outputs(prescribed_motion)
            .iter()
            .map(Output::to_string)
            .collect()
    }

    /// The outputs of a run of this layout, in the order of [`Layout::output_names`].
    pub fn outputs(&self, prescribed_motion: bool) -> Vec<Output> {
        let mut outputs = vec![Output::Vehicle, Output::TipRel, Output::TopRel(1)];
        outputs.extend(self.contacts().map(|c| Output::Gap {
            overlap: c.overlap,
            point: c.point,
        }));
        outputs.extend(self.contacts().map(|c| Output::ContactForce {
            overlap: c.overlap,
            point: c.point,
        }));
        if prescribed_motion {
            outputs.push(Output::DriveForce);
        }
        outputs
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_and_names() {
        let l = Layout::new(&[5, 4, 3], 2);
        assert_eq!(l.dof(), 12);
        assert_eq!(l.index(2, 1), 5);
        assert_eq!(l.index(3, 3), 11);
        assert_eq!(l.contact_count(), 4);
        let names = l.output_names(false);
        assert_eq!(&names[3..7], ["xi_2_0", "xi_2_1", "xi_3_0", "xi_3_1"]);
        assert_eq!(names.len(), 3 + 8);
    }
}
