//! Measured orders of the forced methods against the mpmath references of the forced scenes
//! (`lab/refs/forced_refs.json`): `mv` (the kick–drift–kick around `Mv`, order 2), `forced4`
//! (McLachlan's composition, 4), `forced6` (Kahan–Li's, 6), the same two over the order-10
//! `PreMv` drift (`forced4-pre10`, `forced6-pre10`; the latter not on the Lagrange top, whose
//! near-exact drift leaves no asymptotic range above the floor), Blanes–Moan's Nyström
//! splittings `nystrom4-pre10` (4) and `nystrom6-pre6` (6), and Chin's force-gradient splitting
//! `fg4-pre10` (4) (these three on the scenes without rotor), built by the lab's registry
//! `make_forced`, at `T = 10`, with attitude.
//!
//! The error is `forced_work::error`: `max(|dm| / |m_ref|, |dq|)` (`q` up to sign). Each order is
//! the least-squares slope of `log error` against `log h` over three halvings of `h`, and each
//! of the two consecutive ratios must give the order too (the asymptotic range). The step
//! counts keep every error at least 1e-12 (the smallest is 3.1e-12), far above the floor where
//! f64 round-off of a run to `T = 10` takes over (forced6 flattens at 1e-14..1e-13 for
//! `h < 1/50`; the references themselves are good to 30 digits), the Lagrange top (spin
//! `Omega_3 = 4`) with twice the steps of the others.
//!
//! `cargo test -p rigid3-lab --test forced_orders -- --nocapture` prints the table.

use rigid3::State;
use rigid3_lab::forced_methods::{make_forced, needs_exact_drift};
use rigid3_lab::forced_work::{error, ForcedScene};

const T_END: f64 = 10.0;

/// Scenes, and whether each is the fast spinner (twice the steps).
const SCENES: [(&str, bool); 6] = [
    ("heavy_top", false),
    ("lagrange_top", true),
    ("gravity_gradient", false),
    ("body_torque", false),
    ("gyrostat", false),
    ("satellite", false),
];

/// Method, nominal order, step counts at `T = 10` (for the slow scenes).
const METHODS: [(&str, f64, [usize; 3]); 8] = [
    ("mv", 2.0, [160, 320, 640]),
    ("forced4", 4.0, [160, 320, 640]),
    ("forced6", 6.0, [80, 160, 320]),
    ("forced4-pre10", 4.0, [40, 80, 160]),
    ("forced6-pre10", 6.0, [20, 40, 80]),
    ("nystrom4-pre10", 4.0, [80, 160, 320]),
    ("nystrom6-pre6", 6.0, [20, 40, 80]),
    ("fg4-pre10", 4.0, [80, 160, 320]),
];

/// The step counts of `method` on scene `name`: the method's, doubled for the fast spinner,
/// except where a Nystrom splitting's small error constants put the doubled counts under the
/// 1e-12 floor (the Lagrange top) or its largest step is not yet asymptotic (the gravity
/// gradient at 20 steps: local order 6.26).
fn step_counts(method: &str, name: &str, base: [usize; 3], fast: bool) -> [usize; 3] {
    match (method, name) {
        ("nystrom4-pre10", "lagrange_top") => base,
        ("nystrom6-pre6", "gravity_gradient") => base.map(|n| 2 * n),
        ("forced6-pre10", "gyrostat") => [12, 24, 48],
        _ => base.map(|n| if fast { 2 * n } else { n }),
    }
}

fn error_after(method: &str, sc: &ForcedScene, n: usize) -> f64 {
    let body = rigid3::Body::<f64>::from_inertia(sc.inertia).unwrap();
    let mut a = make_forced(method, body, sc.t_end / n as f64, &sc.spec).unwrap();
    let mut s = State::new(sc.m0, sc.q0);
    for k in 0..n {
        a.step_state(&mut s)
            .unwrap_or_else(|e| panic!("{method} on {}: step {k} of {n}: {e}", sc.name));
    }
    error(sc, s.m, s.q)
}

#[test]
fn measured_orders_against_the_mpmath_references() {
    println!("measured orders at T = {T_END} against lab/refs/forced_refs.json (error = max(|dm|/|m|, |dq|))");
    println!(
        "{:>16} {:>8} {:>6} {:>18} {:>8} {:>8}   errors",
        "scene", "method", "order", "steps", "local1", "local2"
    );
    let mut bad = Vec::new();
    for (name, fast) in SCENES {
        let sc = ForcedScene::from_reference(name, T_END).expect("reference scene");
        for (method, nominal, base) in METHODS {
            if needs_exact_drift(method) && sc.spec.rotor.is_some() {
                // no Nystrom splitting with a rotor: the registry refuses it
                let body = rigid3::Body::<f64>::from_inertia(sc.inertia).unwrap();
                assert!(make_forced(method, body, 0.1, &sc.spec).is_none());
                continue;
            }
            if (method, name) == ("forced6-pre10", "lagrange_top") {
                // the near-exact drift of the symmetric top leaves this composition
                // pre-asymptotic down to 3e-9 (local orders 6.77, then 6.10 from 64 steps), and
                // two halvings of order 6 divide the error by 4096: its third count falls under
                // the 1e-12 floor (5.1e-13 at 256 steps); forced6 is measured here instead
                continue;
            }
            let ns = step_counts(method, name, base, fast);
            let e = ns.map(|n| error_after(method, &sc, n));
            // h halves from one count to the next
            let local = [(e[0] / e[1]).log2(), (e[1] / e[2]).log2()];
            let order = (e[0] / e[2]).log2() / 2.0;
            println!(
                "{name:>16} {method:>8} {order:>6.3} {:>18} {:>8.3} {:>8.3}   {:.2e} {:.2e} {:.2e}",
                format!("{ns:?}"),
                local[0],
                local[1],
                e[0],
                e[1],
                e[2]
            );
            let ok = (order - nominal).abs() <= 0.15
                && local.iter().all(|p| (p - nominal).abs() <= 0.15)
                && e[2] >= 1e-12;
            if !ok {
                bad.push(format!("{name} {method}: {order:.3} {local:?} {e:?}"));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "orders off nominal or errors too small: {bad:#?}"
    );
}
