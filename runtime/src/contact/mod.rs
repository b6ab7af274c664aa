//! The clearance contact law (docs/model.md section 3, the paper's eqs. 11-12): a dead zone of
//! total width `l_S` with a one-sided spring `c` and damper `d` outside it.

pub mod table;

/// Where a contact gap `xi` lies relative to the free band `|xi| <= l_S/2`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ContactState {
    /// `xi < -l_S/2`: pressed against the lower guide.
    Lower,
    /// `|xi| <= l_S/2`: inside the clearance, no force.
    Free,
    /// `xi > l_S/2`: pressed against the upper guide.
    Upper,
}

/// Contact force `f`, and its partial derivatives, at one contact point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactForce {
    /// Force `f` (N): `+f` on the outer section, `-f` on the inner one.
    pub force: f64,
    /// `df/dxi` (N/m).
    pub d_gap: f64,
    /// `df/dxi_dot` (N s/m).
    pub d_rate: f64,
}

/// Parameters of the contact law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLaw {
    /// Contact stiffness `c` (N/m).
    pub stiffness: f64,
    /// Contact damping `d` (N s/m).
    pub damping: f64,
    /// Total clearance `l_S` (m); the free band is `|xi| <= l_S/2`.
    pub clearance: f64,
}

/// Whether a contact of gap `xi` (m) with half clearance `half_band` (m) is closed
/// ([`ContactLaw::is_closed`]; for callers that keep only the band).
pub fn gap_closed(xi: f64, half_band: f64) -> bool {
    half_band == 0.0 || xi.abs() > half_band
}

impl ContactLaw {
    /// Half the clearance, `l_S/2` (m): where the law switches.
    pub fn half_band(&self) -> f64 {
        0.5 * self.clearance
    }

    /// True when `l_S = 0`: the law is linear everywhere and needs no switching.
    pub fn is_linear(&self) -> bool {
        self.clearance == 0.0
    }

    /// Whether a contact of gap `xi` (m) presses against a guide: outside the free band, and
    /// always with `l_S = 0` (the linear law holds everywhere, there is no free band). The
    /// one rule of "closed" for outputs, counts and figures.
    pub fn is_closed(&self, xi: f64) -> bool {
        gap_closed(xi, self.half_band())
    }

    /// The state of gap `xi` (m). With `l_S = 0` there is no free band: `xi = 0` counts as
    /// `Upper` (the linear law holds there too).
    pub fn state(&self, xi: f64) -> ContactState {
        let h = self.half_band();
        if self.is_linear() {
            if xi < 0.0 {
                ContactState::Lower
            } else {
                ContactState::Upper
            }
        } else if xi > h {
            ContactState::Upper
        } else if xi < -h {
            ContactState::Lower
        } else {
            ContactState::Free
        }
    }

    /// Force and partials at gap `xi` (m) and gap rate `xi_dot` (m/s), in the state the gap
    /// is in. See [`ContactLaw::force_in_state`].
    #[inline]
    pub fn force(&self, xi: f64, xi_dot: f64) -> ContactForce {
        self.force_in_state(self.state(xi), xi, xi_dot)
    }

    /// Force and partials with the branch of the law fixed to `state` (integrators with
    /// event location keep the branch fixed between switches, so the right-hand side is
    /// smooth within a step):
    /// `f = c (xi -+ l_S/2) + d xi_dot` outside the band, `0` inside.
    #[inline]
    pub fn force_in_state(&self, state: ContactState, xi: f64, xi_dot: f64) -> ContactForce {
        let h = self.half_band();
        let (c, d) = (self.stiffness, self.damping);
        match state {
            ContactState::Upper => ContactForce {
                force: c * (xi - h) + d * xi_dot,
                d_gap: c,
                d_rate: d,
            },
            ContactState::Lower => ContactForce {
                force: c * (xi + h) + d * xi_dot,
                d_gap: c,
                d_rate: d,
            },
            ContactState::Free => ContactForce {
                force: 0.0,
                d_gap: 0.0,
                d_rate: 0.0,
            },
        }
    }

    /// Potential energy stored in the contact spring at gap `xi` (J).
    pub fn spring_energy(&self, xi: f64) -> f64 {
        let h = self.half_band();
        let pen = if xi > h {
            xi - h
        } else if xi < -h {
            xi + h
        } else {
            0.0
        };
        0.5 * self.stiffness * pen * pen
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(l_s: f64) -> ContactLaw {
        ContactLaw {
            stiffness: 2.0e8,
            damping: 1.0e3,
            clearance: l_s,
        }
    }

    #[test]
    fn dead_zone_matches_the_papers_sign_formula() {
        // eq. 11 and 12 of the paper, written with sign(): an independent form of the law
        let (c, d, l_s) = (2.0e8, 1.0e3, 0.01);
        let paper = |xi: f64, xid: f64| {
            let sg = |v: f64| {
                if v > 0.0 {
                    1.0
                } else if v < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            };
            let fk = c
                * (xi - 0.5 * (xi + l_s / 2.0) * sg(xi + l_s / 2.0)
                    + 0.5 * (xi - l_s / 2.0) * sg(xi - l_s / 2.0));
            let dk = d * (1.0 - 0.5 * sg(xi + l_s / 2.0) + 0.5 * sg(xi - l_s / 2.0));
            fk + dk * xid
        };
        for xi in [-0.02, -0.0051, -0.004, 0.0, 0.003, 0.0051, 0.03] {
            for xid in [-1.0, 0.0, 2.5] {
                let ours = law(l_s).force(xi, xid).force;
                assert!((ours - paper(xi, xid)).abs() <= 1e-9 * paper(xi, xid).abs().max(1.0));
            }
        }
    }

    #[test]
    fn zero_clearance_is_linear_and_band_edges_are_free() {
        let f = law(0.0).force(1e-6, 0.5);
        assert_eq!(f.force, 2.0e8 * 1e-6 + 1.0e3 * 0.5);
        assert_eq!(law(0.0).force(0.0, 0.5).force, 500.0);
        assert_eq!(law(0.01).state(0.005), ContactState::Free);
        assert_eq!(law(0.01).force(-0.005, 3.0).force, 0.0);
        assert_eq!(law(0.01).state(-0.0050001), ContactState::Lower);
    }
}
