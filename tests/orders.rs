//! `PreMv::new` and `RetimedMv::new` refuse an order they do not provide (issue 13).

use rigid3::{Body, Integrator, PreMv, RetimedMv, StepError};

#[test]
fn invalid_orders_are_refused_not_rounded() {
    let body = Body::<f64>::from_mass_matrix([0.9218, 0.7382, 0.1763]).unwrap();
    for order in 0u8..=12 {
        let valid = matches!(order, 2 | 4 | 6 | 8 | 10);
        match PreMv::new(body, 0.1, order) {
            Ok(p) => {
                assert!(valid, "order {order} accepted");
                assert_eq!(p.order(), order);
            }
            Err(e) => {
                assert!(!valid, "order {order} refused");
                assert_eq!(e, StepError::InvalidOrder);
            }
        }
        assert_eq!(RetimedMv::new(body, 0.1, order).is_ok(), valid);
    }
    for order in [u8::MAX, 11, 100] {
        assert_eq!(
            PreMv::new(body, 0.1, order).err(),
            Some(StepError::InvalidOrder)
        );
    }
    // an order-2 PreMv is Mv
    let mut a = PreMv::new(body, 0.1, 2).unwrap();
    let mut b = rigid3::Mv::new(body, 0.1);
    let (mut ma, mut mb) = ([0.4165, 0.9072, 0.0588], [0.4165, 0.9072, 0.0588]);
    a.step(&mut ma).unwrap();
    b.step(&mut mb).unwrap();
    assert_eq!(ma, mb);
}
