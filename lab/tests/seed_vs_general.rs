//! The talk's explicit 3x3 algorithm (`SeedMv`) against the independent general-N
//! Cardoso–Leite solver (matrix sign function of the 6x6 Hamiltonian), on random bodies,
//! momenta and steps inside the existence region.

use rigid3::{Body, SeedMv, StepError};
mod common;

use common::Rng;
use rigid3_lab::general::{dmv_x3, ClError};

#[test]
fn seed_mv_agrees_with_the_general_solver_on_ten_thousand_random_inputs() {
    let mut rng = Rng(2024);
    let (mut compared, mut beyond, mut degenerate) = (0usize, 0usize, 0usize);
    let (mut worst_x, mut worst_res) = (0.0f64, 0.0f64);
    while compared < 10_000 {
        let j = [
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
            rng.range(0.05, 1.0),
        ];
        let scale = rng.range(0.1, 3.0);
        let m = [
            scale * rng.range(-1.0, 1.0),
            scale * rng.range(-1.0, 1.0),
            scale * rng.range(-1.0, 1.0),
        ];
        let h = rng.range(0.001, 1.5);
        let body = Body::from_mass_matrix(j).unwrap();
        let seed = SeedMv::new(body, h).step_matrix(&m);
        let general = dmv_x3(j, m, h);
        match (seed, general) {
            (Ok(xs), Ok(xg)) => {
                compared += 1;
                for r in 0..3 {
                    for c in 0..3 {
                        worst_x = worst_x.max((xs[r][c] - xg[r][c]).abs());
                    }
                }
                // residuals of the defining equations for the explicit result
                let hat = [
                    [0.0, -h * m[2], h * m[1]],
                    [h * m[2], 0.0, -h * m[0]],
                    [-h * m[1], h * m[0], 0.0],
                ];
                for r in 0..3 {
                    for c in 0..3 {
                        let eq = xs[r][c] * j[c] - j[r] * xs[c][r] - hat[r][c];
                        let id: f64 = (0..3).map(|k| xs[k][r] * xs[k][c]).sum::<f64>()
                            - if r == c { 1.0 } else { 0.0 };
                        worst_res = worst_res.max(eq.abs()).max(id.abs());
                    }
                }
            }
            (Err(StepError::StepTooLarge), Err(ClError::NoSplit)) => beyond += 1,
            (Err(StepError::Degenerate), Ok(_)) => degenerate += 1,
            (s, g) => {
                panic!("disagree on existence: seed {s:?}, general {g:?} (J {j:?} m {m:?} h {h})")
            }
        }
    }
    println!("compared {compared}, both beyond the limit {beyond}, seed degenerate {degenerate}");
    println!("max |X_seed - X_general| = {worst_x:e}, max residual = {worst_res:e}");
    assert!(worst_x <= 1e-12, "{worst_x:e}");
    assert!(worst_res <= 1e-13, "{worst_res:e}");
    assert!(
        degenerate * 1000 <= compared,
        "seed refused {degenerate} of {compared}"
    );
}
