use rigid3::{Body, Integrator, Mv};
use std::time::Instant;
fn main() {
    let body = Body::<f64>::from_mass_matrix([0.9218, 0.7382, 0.1763]).unwrap();
    let mut mv = Mv::new(body, 0.1);
    let mut m = [0.4165, 0.9072, 0.0588];
    for _ in 0..3 {
        let t = Instant::now();
        for _ in 0..10_000_000 {
            let _ = mv.step(std::hint::black_box(&mut m));
        }
        println!("{:.1} ns/step", t.elapsed().as_nanos() as f64 / 1e7);
    }
}
