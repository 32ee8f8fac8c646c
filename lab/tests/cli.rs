//! The `rigid3-lab propagate` command end to end: JSON output against the reference
//! solution, invariants, and errors reported for bad input.

use std::process::Command;

fn lab(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_rigid3-lab"))
        .args(args)
        .output()
        .expect("run rigid3-lab");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr),
    )
}

const TALK: [&str; 6] = [
    "--inertia",
    "0.9145,1.0981,1.66",
    "--m0",
    "0.4165,0.9072,0.0588",
    "--t",
    "10",
];

fn propagate_json(method: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["propagate", "--method", method, "--h", "0.1", "--json"];
    args.extend_from_slice(&TALK);
    args.extend_from_slice(extra);
    let (ok, out) = lab(&args);
    assert!(ok, "{out}");
    serde_json::from_str(&out).expect("json")
}

fn m_of(v: &serde_json::Value) -> [f64; 3] {
    let m = v["m"].as_array().unwrap();
    [
        m[0].as_f64().unwrap(),
        m[1].as_f64().unwrap(),
        m[2].as_f64().unwrap(),
    ]
}

#[test]
fn propagate_prints_the_dmv_state_at_t10() {
    let r = propagate_json("seed-mv", &["--q0", "1,0,0,0"]);
    assert_eq!(r["steps"], 100);
    // DMV's error at t = 10 on the talk's case is 0.51 h^2 (MATH.md §2)
    let m10 = [
        0.827_172_818_567_906_3,
        -0.096_647_426_825_883_59,
        -0.553_521_393_543_520_7,
    ];
    let m = m_of(&r);
    let err = ((m[0] - m10[0]).powi(2) + (m[1] - m10[1]).powi(2) + (m[2] - m10[2]).powi(2)).sqrt();
    assert!((err - 0.0051).abs() < 3e-4, "{err}");
    assert!(r["energy_drift"].as_f64().unwrap() < 1e-14);
    assert!(r["spatial_momentum_drift"].as_f64().unwrap() < 1e-14);
    // the general solver is the same map
    let g = propagate_json("general", &[]);
    let mg = m_of(&g);
    for k in 0..3 {
        assert!((m[k] - mg[k]).abs() < 1e-13);
    }
    assert!(g["q"].is_null(), "momentum-only run has no attitude");
}

#[test]
fn propagate_in_f32_is_close_to_f64() {
    let a = m_of(&propagate_json("seed-mv", &[]));
    let b = m_of(&propagate_json("seed-mv", &["--f32"]));
    for k in 0..3 {
        assert!((a[k] - b[k]).abs() < 1e-5);
    }
}

#[test]
fn bad_input_is_reported() {
    let mut args = vec!["propagate", "--method", "nope", "--h", "0.1"];
    args.extend_from_slice(&TALK);
    let (ok, out) = lab(&args);
    assert!(!ok && out.contains("unknown method"));
    let (ok, out) = lab(&[
        "propagate",
        "--method",
        "seed-mv",
        "--inertia",
        "1,1,3",
        "--m0",
        "1,0,0",
        "--h",
        "0.1",
        "--t",
        "1",
    ]);
    assert!(!ok && out.contains("triangle"), "{out}");
    // past the existence limit the run stops with the error, non-zero exit
    let mut args = vec!["propagate", "--method", "seed-mv", "--h", "1.2"];
    args.extend_from_slice(&TALK);
    let (ok, out) = lab(&args);
    assert!(!ok && out.contains("past the method's limit"), "{out}");
}
