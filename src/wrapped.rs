//! Models that wrap another (a controller's, an observer's, a held drive force's) pass most of
//! the [`Model`](telescopic_runtime::Model) interface through unchanged; this macro writes
//! those methods once. The wrapper provides `fn wrapped(&self) -> &dyn Model` and writes the
//! methods it changes (`params`, `rhs`, ...) itself.

/// The pass-through methods of a wrapping model: layout, matrices, drive vector, contact
/// geometry and gaps, displacement.
macro_rules! pass_through_model {
    () => {
        fn layout(&self) -> &telescopic_runtime::Layout {
            self.wrapped().layout()
        }
        fn mass_matrix(&self) -> &telescopic_runtime::nalgebra::DMatrix<f64> {
            self.wrapped().mass_matrix()
        }
        fn stiffness_matrix(&self) -> &telescopic_runtime::nalgebra::DMatrix<f64> {
            self.wrapped().stiffness_matrix()
        }
        fn damping_matrix(&self) -> Option<&telescopic_runtime::nalgebra::DMatrix<f64>> {
            self.wrapped().damping_matrix()
        }
        fn drive_vector(&self) -> &telescopic_runtime::nalgebra::DVector<f64> {
            self.wrapped().drive_vector()
        }
        fn contact_vectors(
            &self,
            t: f64,
            g: &mut telescopic_runtime::nalgebra::DMatrix<f64>,
            gdot: &mut telescopic_runtime::nalgebra::DMatrix<f64>,
        ) {
            self.wrapped().contact_vectors(t, g, gdot)
        }
        fn contact_vectors_at(
            &self,
            positions: &[f64],
            rates: &[f64],
            g: &mut telescopic_runtime::nalgebra::DMatrix<f64>,
            gdot: &mut telescopic_runtime::nalgebra::DMatrix<f64>,
        ) {
            self.wrapped().contact_vectors_at(positions, rates, g, gdot)
        }
        fn contact_table(&self) -> Option<&telescopic_runtime::ContactTable> {
            self.wrapped().contact_table()
        }
        fn contact_gaps(&self, t: f64, y: &[f64], xi: &mut [f64], xi_dot: &mut [f64]) {
            self.wrapped().contact_gaps(t, y, xi, xi_dot)
        }
        fn displacement(&self, section: usize, x: f64, z: &[f64]) -> f64 {
            self.wrapped().displacement(section, x, z)
        }
    };
}

pub(crate) use pass_through_model;
