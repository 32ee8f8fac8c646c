//! The `rigid3-lab propagate` command end to end: JSON output against the reference
//! solution, invariants, and errors reported for bad input.

mod common;

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

/// `propagate` with `mv` on a small body, before the step, the duration and the extras.
const MV_BASE: [&str; 7] = [
    "propagate",
    "--method",
    "mv",
    "--inertia",
    "1,1.5,2",
    "--m0",
    "0.3,-0.6,1.1",
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
    // DMV's error at t = 10 on the talk's case is 0.51 h^2 (docs/MATH.md §2)
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
    // a positive moment that f32 cannot hold is named as such, not as "not positive"
    let (ok, out) = lab(&[
        "propagate",
        "--method",
        "mv",
        "--inertia",
        "1e-50,2e-50,2.5e-50",
        "--m0",
        "1,2,3",
        "--h",
        "0.1",
        "--t",
        "1",
        "--f32",
    ]);
    assert!(!ok && out.contains("rounds to zero in f32"), "{out}");
    // the body and the initial momentum have no defaults: a missing one is named
    for (args, flag) in [
        (["--inertia", "1,2,3"], "--m0"),
        (["--m0", "1,2,3"], "--inertia"),
    ] {
        let mut all = vec!["propagate", "--method", "mv", "--h", "0.1", "--t", "1"];
        all.extend_from_slice(&args);
        let (ok, out) = lab(&all);
        assert!(
            !ok && out.contains("required") && out.contains(flag),
            "{out}"
        );
    }
}

/// Input that used to hang (no bound on the step count), run silently (NaN, a negative
/// duration run forwards) or fail with a misleading message is refused up front, naming the
/// flag; nothing runs.
#[test]
fn propagate_refuses_bad_numbers_naming_the_flag() {
    let base = MV_BASE;
    for (extra, want) in [
        (&["--h", "0", "--t", "1"][..], "--h must be nonzero"),
        (&["--h", "0.1", "--t", "inf"], "--t must be finite"),
        (&["--h", "1e-300", "--t", "1"], "more than 1e10"),
        (&["--h", "nan", "--t", "1"], "--h must be finite"),
        (&["--h", "0.1", "--t", "nan"], "--t must be finite"),
        (&["--h", "0.1", "--t", "-1"], "--t is a duration"),
        (
            &["--h", "0.1", "--t", "1", "--q0", "0,0,0,0"],
            "--q0 must be a finite nonzero",
        ),
        (
            &["--h", "0.1", "--t", "1", "--rotor", "nan,0,0"],
            "--rotor must be finite",
        ),
        (
            &["--h", "0.1", "--t", "1", "--rotor", "1e10,0,0"],
            "refused the rotor",
        ),
        (
            &[
                "--h",
                "0.1",
                "--t",
                "1",
                "--gravity",
                "1",
                "--com",
                "nan,0,0",
            ],
            "--com must be finite",
        ),
        (
            &["--h", "1e300", "--t", "1e300", "--f32"],
            "--h must be finite and within f32's range",
        ),
        (
            &["--h", "1e-50", "--t", "1e-45", "--f32"],
            "--h must be nonzero in f32",
        ),
    ] {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        let (ok, out) = lab(&args);
        assert!(!ok && out.contains(want), "{extra:?}: {out}");
        assert!(!out.contains("NaN"), "{extra:?}: {out}");
    }
}

/// A quaternion given off the unit sphere is the attitude it points to: the invariants are
/// those of the normalised state the run starts from (before, `R(q) m` of the raw input made
/// a conserving run report a drift of 1.7e-2), and the run is that of the unit input.
#[test]
fn propagate_normalises_q0() {
    let run = |q0: &str| propagate_json("mv", &["--q0", q0]);
    let raw = run("0.9,0.1,-0.3,0.2");
    let n = (0.81f64 + 0.01 + 0.09 + 0.04).sqrt();
    let unit = format!("{},{},{},{}", 0.9 / n, 0.1 / n, -0.3 / n, 0.2 / n);
    let norm = run(&unit);
    let drift = raw["spatial_momentum_drift"].as_f64().unwrap();
    assert!(drift < 1e-14, "R(q) m drift {drift:e}");
    let (a, b) = (m_of(&raw), m_of(&norm));
    for k in 0..3 {
        assert!((a[k] - b[k]).abs() < 1e-14, "{a:?} {b:?}");
    }
    // a direction at any scale (review: 1e200 and 1e-170 were refused as zero)
    let unit = run("1,0,0,0");
    for q0 in ["1e200,0,0,0", "1e-170,0,0,0"] {
        assert_eq!(run(q0)["q"], unit["q"], "{q0}");
    }
}

/// `soak` checks its numbers too, naming the flag (review: `--h 0` ran silently, `--h nan` and
/// an f32 overflow stopped with a message naming none, `--steps 1e14` ran without end).
#[test]
fn soak_refuses_bad_numbers_naming_the_flag() {
    for (extra, want) in [
        (&["--h", "0"][..], "--h must be nonzero"),
        (&["--h", "nan"], "--h must be finite"),
        (
            &["--m0", "1e39,1,1", "--f32"],
            "--m0 must be finite and within f32's range",
        ),
        (&["--q0", "0,0,0,0"], "--q0 must be a finite nonzero"),
        (
            &["--inertia", "1e-50,2e-50,2.5e-50", "--f32"],
            "--inertia has a moment that rounds to zero in f32",
        ),
        (
            &["--m0", "1e-50,1e-50,0", "--f32"],
            "--m0 is nonzero but rounds to zero in f32",
        ),
    ] {
        let mut args = vec!["soak", "--method", "mv", "--steps", "100"];
        args.extend_from_slice(extra);
        let (ok, out) = lab(&args);
        assert!(!ok && out.contains(want), "{extra:?}: {out}");
    }
    let (ok, out) = lab(&["soak", "--method", "mv", "--steps", "100000000000000"]);
    assert!(!ok && out.contains("--steps is 1e14 steps"), "{out}");
}

/// A gravity gradient whose nadir turns (`N != 0`) conserves the Jacobi integral
/// `E - N e_z . R(q) m`, not the total energy: the CLI reports both, the first as the drift.
/// The oracle is the integral recomputed here from the JSON state and the scene's formulas
/// (`tau = 3K (r x I r)`, `V = 3K/2 r . I r`, `r = R(q)^T (cos Nt, sin Nt, 0)`).
#[test]
fn propagate_reports_the_jacobi_integral_of_a_turning_gravity_gradient() {
    let (k, n, inertia) = (0.5f64, 0.3f64, [1.0f64, 1.5, 2.0]);
    let json = |method: &str| {
        run_json(&[
            "propagate",
            "--method",
            method,
            "--gravity-gradient",
            "0.5,0.3",
            "--inertia",
            "1,1.5,2",
            "--m0",
            "0.3,-0.6,1.1",
            "--q0",
            "0.9,0.1,-0.3,0.2",
            "--h",
            "0.01",
            "--t",
            "20",
            "--json",
        ])
    };
    for method in ["mv", "forced4", "rk4"] {
        let v = json(method);
        let j_drift = v["jacobi_integral_drift"].as_f64().unwrap();
        let e_change = v["total_energy_drift"].as_f64().unwrap();
        // order 2 and 4 at h = 0.01: the Jacobi integral is kept to the method's error (the
        // symplectic ones without drift), while the total energy moves by tens of percent
        assert!(j_drift < 1e-5, "{method}: Jacobi {j_drift:e}");
        assert!(
            e_change > 1e-2,
            "{method}: total energy change {e_change:e}"
        );
        let m = m_of(&v);
        let q: Vec<f64> = v["q"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let t = v["t"].as_f64().unwrap();
        // R(q) and r = R(q)^T (cos Nt, sin Nt, 0)
        let r_mat = common::rotation([q[0], q[1], q[2], q[3]]);
        let d = [(n * t).cos(), (n * t).sin(), 0.0];
        let r: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| r_mat[j][i] * d[j]).sum())
            .collect();
        let kinetic: f64 = (0..3).map(|i| 0.5 * m[i] * m[i] / inertia[i]).sum();
        let pz: f64 = (0..3).map(|j| r_mat[2][j] * m[j]).sum();
        let potential: f64 = 1.5 * k * (0..3).map(|i| inertia[i] * r[i] * r[i]).sum::<f64>();
        let total = v["total_energy"].as_f64().unwrap();
        let jacobi = v["jacobi_integral"].as_f64().unwrap();
        assert!(
            (total - (kinetic + potential)).abs() < 1e-12,
            "{method}: {total}"
        );
        assert!(
            (jacobi - (total - n * pz)).abs() < 1e-12,
            "{method}: {jacobi}"
        );
    }
}

fn run_json(args: &[&str]) -> serde_json::Value {
    let (ok, out) = lab(args);
    assert!(ok, "{out}");
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

#[test]
fn loop_cost_json_has_every_method_precision_and_regime() {
    let v = run_json(&["loop-cost", "--json", "--steps", "2000"]);
    let rows = v["rows"].as_array().expect("rows");
    let regimes = ["fixed", "jitter", "corrected", "torque"];
    let find = |method: &str, precision: &str, regime: &str| {
        let hits: Vec<&serde_json::Value> = rows
            .iter()
            .filter(|r| {
                r["method"] == method && r["precision"] == precision && r["regime"] == regime
            })
            .collect();
        assert_eq!(hits.len(), 1, "{method} {precision} {regime}");
        hits[0].clone()
    };
    for precision in ["f64", "f32"] {
        for method in ["mv", "pre-mv4", "pre-mv10", "retimed-mv", "splitting"] {
            for regime in regimes {
                let r = find(method, precision, regime);
                let ns = r["ns_per_step"].as_f64().unwrap();
                let ratio = r["ratio_to_fixed"].as_f64().unwrap();
                assert!(ns > 0.0 && ns.is_finite(), "{r}");
                assert!(ratio > 0.0 && ratio.is_finite(), "{r}");
                if regime == "fixed" {
                    assert_eq!(ratio, 1.0);
                }
            }
        }
    }
    // 4 regimes x 4 methods x 2 precisions, and the splitting's 4 x 2
    assert_eq!(rows.len(), 4 * 4 * 2 + 4 * 2);
    assert!(rows
        .iter()
        .all(|r| regimes.contains(&r["regime"].as_str().unwrap())));
}

fn drifts(v: &serde_json::Value) -> Vec<(u64, [f64; 3])> {
    v["checkpoints"]
        .as_array()
        .expect("checkpoints")
        .iter()
        .map(|c| {
            (
                c["steps"].as_u64().unwrap(),
                [
                    c["casimir"].as_f64().unwrap(),
                    c["energy"].as_f64().unwrap(),
                    c["spatial"].as_f64().unwrap(),
                ],
            )
        })
        .collect()
}

#[test]
fn soak_reports_growing_drift_at_every_decade() {
    let v = run_json(&["soak", "--json", "--method", "mv", "--steps", "10000"]);
    let c = drifts(&v);
    let steps: Vec<u64> = c.iter().map(|x| x.0).collect();
    assert_eq!(steps, vec![10, 100, 1000, 10_000]);
    for k in 1..c.len() {
        for i in 0..3 {
            assert!(c[k].1[i] >= c[k - 1].1[i], "{c:?}");
        }
    }
    let last = c.last().unwrap().1;
    assert!(last.iter().all(|&d| (0.0..=1e-12).contains(&d)), "{last:?}");
    assert_eq!(v["precision"], "f64");
    assert!(v["error"].is_null());
}

#[test]
fn soak_takes_the_scene_the_precision_and_the_end() {
    let v = run_json(&[
        "soak",
        "--json",
        "--method",
        "hv-dmv",
        "--f32",
        "--steps",
        "2500",
        "--h",
        "0.1",
        "--inertia",
        "0.9145,1.0981,1.66",
        "--m0",
        "0.4165,0.9072,0.0588",
        "--q0",
        "1,0,0,0",
    ]);
    assert_eq!(v["precision"], "f32");
    assert_eq!(v["h"], 0.1);
    let c = drifts(&v);
    assert_eq!(
        c.iter().map(|x| x.0).collect::<Vec<_>>(),
        vec![10, 100, 1000, 2500]
    );
    assert!(c.last().unwrap().1.iter().all(|&d| d < 1e-4), "{c:?}");
    let (ok, out) = lab(&["soak", "--method", "nope", "--steps", "10"]);
    assert!(!ok && out.contains("unknown method"), "{out}");
}

/// `soak --rotor`: the gyrostat through the forced step, its energy
/// `1/2 (m - h_r) . I^-1 (m - h_r)` (oracle: the conservation laws; in f64 the forced step
/// holds `|m|^2` and `R(q) m` to round-off and keeps the energy to its splitting error,
/// bounded; the free body's energy, which a gyrostat does not keep, would move by the wheels'
/// share), and names its refusals.
#[test]
fn soak_takes_a_rotor_and_reports_the_gyrostats_energy() {
    let v = run_json(&[
        "soak",
        "--json",
        "--method",
        "mv",
        "--steps",
        "20000",
        "--rotor",
        "0.3,-0.2,0.35",
    ]);
    assert_eq!(v["rotor"][2], 0.35);
    let last = drifts(&v).last().unwrap().1;
    assert!(last[0] <= 1e-13 && last[2] <= 1e-13, "{last:?}");
    assert!(last[1] <= 1e-6, "{last:?}");
    let (ok, out) = lab(&[
        "soak", "--method", "mv", "--steps", "10", "--rotor", "1,nan,0",
    ]);
    assert!(!ok && out.contains("rotor"), "{out}");
    let (ok, out) = lab(&["soak", "--method", "mv", "--steps", "10", "--rotor", "1,0"]);
    assert!(!ok && out.contains("--rotor"), "{out}");
    let (ok, out) = lab(&[
        "soak",
        "--method",
        "nystrom4-pre10",
        "--steps",
        "10",
        "--rotor",
        "1,0,0",
    ]);
    assert!(!ok && out.contains("no rotor"), "{out}");
    let (ok, out) = lab(&[
        "soak", "--method", "nope", "--steps", "10", "--rotor", "1,0,0",
    ]);
    assert!(!ok && out.contains("unknown method"), "{out}");
}

#[test]
fn propagate_runs_the_nystrom_and_force_gradient_splittings_and_refuses_them_a_rotor() {
    // the heavy top of lab/refs/forced_refs.json, 100 steps to T = 10, against its reference
    let scene = rigid3_lab::forced_work::ForcedScene::from_reference("heavy_top", 10.0).unwrap();
    let csv = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:e}"))
            .collect::<Vec<_>>()
            .join(",")
    };
    let (inertia, m0, q0) = (csv(&scene.inertia), csv(&scene.m0), csv(&scene.q0));
    let (mg, com) = scene.spec.gravity.unwrap();
    let (mg, com) = (format!("{mg:e}"), csv(&com));
    let args = |method: &'static str, rotor: bool| {
        let mut a = vec![
            "propagate",
            "--method",
            method,
            "--h",
            "0.1",
            "--t",
            "10",
            "--json",
        ]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>();
        for (k, v) in [
            ("--inertia", &inertia),
            ("--m0", &m0),
            ("--q0", &q0),
            ("--gravity", &mg),
            ("--com", &com),
        ] {
            a.push(k.into());
            a.push(v.clone());
        }
        if rotor {
            a.extend(["--rotor".to_string(), "0,0.3,0".to_string()]);
        }
        a
    };
    // about 2e-10 at order 4 and under 1e-12 at order 6 (h = 0.1); Chin's two-drift
    // force-gradient splitting about 4e-8
    for (method, bound) in [
        ("nystrom4-pre10", 1e-9),
        ("nystrom6-pre10", 1e-9),
        ("fg4-pre10", 1e-6),
    ] {
        let a = args(method, false);
        let (ok, out) = lab(&a.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(ok, "{out}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let m = m_of(&v);
        let err = (0..3)
            .map(|i| (m[i] - scene.m_ref[i]).abs())
            .fold(0.0, f64::max);
        assert!(err < bound, "{method}: {err:e}");
        assert!(v["total_energy"].as_f64().is_some(), "{out}");
        let a = args(method, true);
        let (ok, out) = lab(&a.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(!ok && out.contains("takes no rotor"), "{out}");
    }
}

/// A forced method's name without any force runs the method on the free body: the
/// composition of order 4 keeps `|m|^2` and the energy (no torque) and lands on `exact`'s
/// state to its order (h = 0.1, T = 10: within 1e-5, where `mv` is 1e-2 off); the report
/// names the forced method and `methods` lists the forced names.
#[test]
fn a_forced_method_runs_without_forces_and_is_listed() {
    let f4 = propagate_json("forced4", &[]);
    let ex = m_of(&propagate_json("exact", &[]));
    let mv = m_of(&propagate_json("mv", &[]));
    let (a, b) = (m_of(&f4), ex);
    let dist = |x: [f64; 3], y: [f64; 3]| {
        ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt()
    };
    assert!(dist(a, b) < 1e-5, "forced4 {a:?} exact {b:?}");
    assert!(
        dist(mv, b) > 1e-3,
        "mv {mv:?}: the comparison must tell the orders apart"
    );
    for key in ["casimir_drift", "energy_drift"] {
        let d = f4[key].as_f64().unwrap();
        assert!(d < 1e-13, "{key} {d}");
    }
    let mut args = vec!["propagate", "--method", "fg4-pre6", "--h", "0.1"];
    args.extend_from_slice(&TALK);
    let (ok, out) = lab(&args);
    assert!(ok && out.contains("force-gradient"), "{out}");
    let (ok, out) = lab(&["methods"]);
    assert!(ok, "{out}");
    for name in ["forced4", "forced6-pre6", "nystrom4-pre10", "fg4-pre6"] {
        assert!(out.contains(name), "{name} not listed: {out}");
    }
}

/// A reader that closes the pipe early (`rigid3-lab demo | head -c 10`) ends the run quietly
/// with status 141, as SIGPIPE would [the exit status and stderr]: `println!` on the closed
/// pipe panicked with a backtrace and status 101 (found by a trial of the CLI); a status of
/// success hid a failed run's error (found in review).
#[test]
fn a_closed_pipe_ends_the_run_quietly() {
    use std::io::Read;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_rigid3-lab"))
        .arg("demo")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 10];
    child.stdout.take().unwrap().read_exact(&mut first).unwrap();
    // the pipe's read end is dropped here: the lab's next writes fail
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(141), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// A run whose invariants f64 cannot represent is a failure with the reason, not `null`s with
/// exit code 0; and the energy that f64 can hold is reported where `m^2` alone overflows
/// (found by an external check: a splitting step of `1e300` exited 0 with `"error": null`,
/// and `m` and `I` of `1e200` gave `"energy": null` and a spatial drift of 0). Oracle: the
/// energy of the unscaled run times `1e200` (the motion is the same).
#[test]
fn propagate_fails_where_the_invariants_overflow_and_scales_the_energy() {
    let (ok, out) = lab(&[
        "propagate",
        "--method",
        "splitting",
        "--inertia",
        "1,1.5,2",
        "--m0",
        "0.3,-0.6,1.1",
        "--h",
        "1e300",
        "--t",
        "1e300",
        "--gravity",
        "1",
        "--com",
        "0,0,1",
        "--json",
    ]);
    assert!(!ok, "{out}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("json");
    let error = v["error"].as_str().unwrap_or_default();
    assert!(
        error.contains("not representable") && error.contains("energy"),
        "{out}"
    );
    let scaled = |s: &str| {
        let (ok, out) = lab(&[
            "propagate",
            "--method",
            "mv",
            "--inertia",
            &format!("1{s},1.5{s},2{s}"),
            "--m0",
            &format!("1{s},-2{s},1{s}"),
            "--q0",
            "1,0,0,0",
            "--h",
            "0.1",
            "--t",
            "1",
            "--json",
        ]);
        (
            ok,
            serde_json::from_str::<serde_json::Value>(&out).expect("json"),
            out,
        )
    };
    let (ok1, one, out1) = scaled("");
    assert!(ok1, "{out1}");
    let (ok_big, big, out_big) = scaled("e200");
    // |m|^2 is about 6e400: not representable, said so
    assert!(!ok_big, "{out_big}");
    assert!(
        big["error"]
            .as_str()
            .unwrap_or_default()
            .contains("casimir"),
        "{out_big}"
    );
    let (e1, e_big) = (
        one["energy"].as_f64().unwrap(),
        big["energy"].as_f64().unwrap(),
    );
    assert!((e_big / 1e200 / e1 - 1.0).abs() < 1e-14, "{e1} {e_big}");
    let drift = big["spatial_momentum_drift"].as_f64().unwrap();
    assert!(drift > 0.0 && drift < 1e-14, "{out_big}");
}

/// A list flag given twice is refused (it was concatenated: `--inertia 1 --inertia 1.5
/// --inertia 2` ran as `1,1.5,2`, and `--rotor 1,1,1 --rotor 2,2,2` failed with a wrong
/// reason; found by an external check).
#[test]
fn propagate_refuses_a_list_flag_given_twice() {
    for (flag, a, b) in [
        ("--inertia", "1", "1.5,2"),
        ("--m0", "0.3,-0.6,1.1", "0.3,-0.6,1.1"),
        ("--rotor", "1,1,1", "2,2,2"),
        ("--com", "0", "0,1"),
        ("--gravity-gradient", "1", "2"),
    ] {
        let mut args = MV_BASE.to_vec();
        args.extend_from_slice(&["--h", "0.1", "--t", "1"]);
        if flag == "--com" {
            args.extend_from_slice(&["--gravity", "1"]);
        }
        args.extend_from_slice(&[flag, a, flag, b]);
        let (ok, out) = lab(&args);
        assert!(
            !ok && out.contains("cannot be used multiple times"),
            "{flag}: {out}"
        );
    }
}

/// `propagate` and `soak` at scales where `|m|^2` underflows or overflows f64: the drifts are
/// those of the same motion at unit scale (computed in scaled units), and an invariant that
/// lost its digits is a failure naming it, not a `0` with exit code 0 (found by an external
/// check: both reported every drift as 0 at `|m|` of `1e-200`, and `soak` at `1e200` too).
/// Oracle: the unit-scale run (`m -> lambda m`, `h -> h / lambda` is the same motion).
#[test]
fn drifts_are_those_of_the_unit_scale_run_at_every_scale() {
    let run = |sub: &str, m: &str, h: &str, t: &str| {
        let mut args = vec![
            sub,
            "--method",
            "rk4",
            "--inertia",
            "1,1.5,2",
            "--m0",
            m,
            "--h",
            h,
            "--json",
        ];
        if sub == "propagate" {
            args.extend_from_slice(&["--t", t, "--q0", "1,0,0,0"]);
        } else {
            args.extend_from_slice(&["--steps", "1000"]);
        }
        let (ok, out) = lab(&args);
        (
            ok,
            serde_json::from_str::<serde_json::Value>(&out).expect("json"),
            out,
        )
    };
    let (ok, unit, out) = run("propagate", "0.3,-0.6,1.1", "0.5", "500");
    assert!(ok, "{out}");
    for (m, h, t) in [
        ("3e-201,-6e-201,1.1e-200", "5e199", "5e202"),
        ("3e199,-6e199,1.1e200", "5e-201", "5e-198"),
    ] {
        let (ok, v, out) = run("propagate", m, h, t);
        for key in ["casimir_drift", "energy_drift", "spatial_momentum_drift"] {
            let (a, b) = (v[key].as_f64().unwrap(), unit[key].as_f64().unwrap());
            assert!(
                a > 0.0 && (a / b - 1.0).abs() < 1e-6,
                "{key}: {a} vs {b}: {out}"
            );
        }
        // |m|^2 is 1.7e-400 or 1.7e400: not a number f64 holds, and said so
        let error = v["error"].as_str().unwrap_or_default();
        assert!(!ok && error.contains("casimir"), "{out}");
    }
    let (ok, unit, out) = run("soak", "0.3,-0.6,1.1", "0.5", "");
    assert!(ok, "{out}");
    let last = |v: &serde_json::Value| v["checkpoints"].as_array().unwrap().last().unwrap().clone();
    let unit = last(&unit);
    for (m, h) in [
        ("3e-201,-6e-201,1.1e-200", "5e199"),
        ("3e199,-6e199,1.1e200", "5e-201"),
    ] {
        let (ok, v, out) = run("soak", m, h, "");
        assert!(ok, "{out}");
        let c = last(&v);
        for key in ["casimir", "energy", "spatial"] {
            let (a, b) = (c[key].as_f64().unwrap(), unit[key].as_f64().unwrap());
            assert!(
                a > 0.0 && (a / b - 1.0).abs() < 1e-6,
                "soak {key}: {a} vs {b}: {out}"
            );
        }
    }
}

/// Refusals an analyst's trial found missing or misleading: a work-precision time without
/// references (it printed a table of "-" and exit 0), an unknown forced scene, soak's forced
/// and free names (real methods were called unknown), zero soak steps (an empty table, exit
/// 0), an f32 momentum that underflows (ran as a body at rest), and a torque angle past the
/// torque models' sine (reported as a non-finite state).
#[test]
fn refusals_name_what_is_wrong() {
    for (args, want) in [
        (
            &["work-precision", "--t", "5"][..],
            "--t must be a reference time",
        ),
        (&["forced-work", "--scene", "foo"], "scenes: heavy_top"),
        (
            &["soak", "--method", "forced4", "--steps", "10"],
            "'forced4' is a forced method: soak runs it with --rotor",
        ),
        (
            &[
                "soak", "--method", "exact", "--steps", "10", "--rotor", "0.1,0,0",
            ],
            "'exact' has no forced step",
        ),
        (
            &[
                "soak",
                "--method",
                "fg4-pre10",
                "--steps",
                "10",
                "--rotor",
                "0.1,0,0",
            ],
            "needs the free body's exact flow",
        ),
        (
            &["soak", "--method", "mv", "--steps", "0"],
            "--steps must be at least 1",
        ),
    ] {
        let (ok, out) = lab(args);
        assert!(!ok && out.contains(want), "{args:?}: {out}");
    }
    // propagate in f32: a momentum that underflows, and a torque angle past the sine
    for (extra, want) in [
        (
            &["--m0", "1e-50,0,0"][..],
            "--m0 is nonzero but rounds to zero in f32",
        ),
        (
            &[
                "--m0",
                "1,1,1",
                "--body-torque",
                "1,1,1",
                "--torque-freq",
                "1e7,0,0",
            ],
            "past the torque models' sine",
        ),
    ] {
        let mut args = MV_BASE[..5].to_vec();
        args.extend_from_slice(&["--h", "0.1", "--t", "1", "--f32"]);
        args.extend_from_slice(extra);
        let (ok, out) = lab(&args);
        assert!(!ok && out.contains(want), "{extra:?}: {out}");
    }
    // a tiny entry beside larger ones is ordinary rounding, not a refusal (review)
    let mut args = MV_BASE[..5].to_vec();
    args.extend_from_slice(&["--h", "0.1", "--t", "1", "--f32", "--m0", "1,1e-50,0"]);
    let (ok, out) = lab(&args);
    assert!(ok, "{out}");
    // the same soak names run where they belong
    for args in [
        &[
            "soak", "--method", "forced4", "--steps", "10", "--rotor", "0.1,0,0",
        ][..],
        &["soak", "--method", "exact", "--steps", "10"],
    ] {
        let (ok, out) = lab(args);
        assert!(ok, "{args:?}: {out}");
    }
}
