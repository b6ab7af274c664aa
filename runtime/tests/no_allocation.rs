//! The per-call path of a model allocates nothing: right-hand side, Jacobian, gaps and
//! outputs are called under a counting global allocator. (One test in this binary, so no
//! other test thread allocates meanwhile.)

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use telescopic_runtime::{
    AssembledModel, ContactLaw, Drive, ForceFlow, Model, ModelParams, Profile, ShapedProfile,
    rest_state,
};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn per_call_methods_do_not_allocate() {
    let sec = common::rig_section(6);
    for (positions, drive) in [
        (
            Profile::Constant(1.15),
            Drive::Force(Profile::Constant(100.0)),
        ),
        (
            Profile::Shaped(ShapedProfile::Smoothstep {
                start: 0.0,
                end: 12.0,
                from: 0.35,
                to: 1.15,
            }),
            Drive::Motion(Profile::Shaped(ShapedProfile::Smoothstep {
                start: 0.0,
                end: 4.0,
                from: 0.0,
                to: 2.0,
            })),
        ),
    ] {
        let params = ModelParams {
            sections: vec![sec, sec, sec],
            vehicle_mass: 100.0,
            load_mass: 17.897,
            gravity: 9.81,
            force_flow: ForceFlow::Cable,
            contact_points: 3,
            contact: ContactLaw {
                stiffness: 2.375e8,
                damping: 1000.0,
                clearance: 0.01,
            },
            positions: vec![Profile::Constant(1.0), positions],
            drive,
        };
        let model = AssembledModel::new(&params).unwrap();
        let n = model.dof();
        let mut y = rest_state(&model, 0.0);
        y.iter_mut()
            .enumerate()
            .for_each(|(i, v)| *v += 1e-3 * ((i * 7919 % 13) as f64 - 6.0));
        let mut ydot = vec![0.0; 2 * n];
        let mut jac = nalgebra::DMatrix::zeros(2 * n, 2 * n);
        let nc = model.layout().contact_count();
        let (mut xi, mut xid) = (vec![0.0; nc], vec![0.0; nc]);
        let mut out = vec![0.0; model.output_names().len()];
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        for step in 0..100 {
            let t = 0.05 * step as f64;
            model.rhs(t, &y, None, &mut ydot);
            model.jacobian(t, &y, None, &mut jac);
            model.contact_gaps(t, &y, &mut xi, &mut xid);
            model.outputs(t, &y, &ydot, &mut out);
        }
        let after = ALLOCATIONS.load(Ordering::SeqCst);
        assert_eq!(
            after - before,
            0,
            "{} allocations in 100 calls of each",
            after - before
        );
        assert!(ydot.iter().all(|v| v.is_finite()));
    }
}
