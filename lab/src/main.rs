//! `rigid3-lab`: command-line front end of the lab.

use clap::{Parser, Subcommand};
use rigid3::{Body, Real, State};
use rigid3_lab::forced_methods::{
    describe_forced, make_forced, needs_exact_drift, ForceSpec, FORCED_METHODS,
};
use rigid3_lab::inputs;
use rigid3_lab::methods::{describe, make, METHODS};
use rigid3_lab::propagate::{propagate, propagate_forced, Report};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "rigid3-lab", about = "Experiments with the rigid3 integrators")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// parsed once per run: the size of the biggest variant does not matter
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    /// Propagate one initial state with one method and print the final state, the
    /// invariants and their drift.
    Propagate {
        /// Method name (see `rigid3-lab methods`).
        #[arg(long)]
        method: String,
        /// Principal moments of inertia I1,I2,I3.
        #[arg(
            long,
            required = true,
            value_delimiter = ',',
            allow_hyphen_values = true,
            action = clap::ArgAction::Set
        )]
        inertia: Vec<f64>,
        /// Initial body momentum x,y,z.
        #[arg(
            long,
            required = true,
            value_delimiter = ',',
            allow_hyphen_values = true,
            action = clap::ArgAction::Set
        )]
        m0: Vec<f64>,
        /// Initial attitude w,x,y,z (body to space; normalised). Without it a free run is
        /// momentum-only; a forced run always carries the attitude (the identity by default).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true, action = clap::ArgAction::Set)]
        q0: Option<Vec<f64>>,
        /// Step size (nonzero; negative runs backwards).
        #[arg(long, allow_hyphen_values = true)]
        h: f64,
        /// Duration, at least 0 (rounded to the nearest whole number of steps, at most 1e10 of
        /// them, so the run may end a little short of it or past it: the report's t is the time
        /// reached).
        #[arg(long, allow_hyphen_values = true)]
        t: f64,
        /// Compute in f32 instead of f64.
        #[arg(long)]
        f32: bool,
        /// Print JSON.
        #[arg(long)]
        json: bool,
        /// Rotor momentum hx,hy,hz (body frame, constant): a gyrostat. The report's `energy` is
        /// then 1/2 m . I^-1 m of the total momentum m; `total E` is the gyrostat's energy,
        /// 1/2 (m - h_r) . I^-1 (m - h_r), which is conserved.
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true, action = clap::ArgAction::Set)]
        rotor: Option<Vec<f64>>,
        /// Heavy top: M g (torque MG (Gamma x chi), Gamma = R(q)^T e_z); needs --com.
        #[arg(long, allow_hyphen_values = true)]
        gravity: Option<f64>,
        /// Heavy top: centre of mass cx,cy,cz in the body frame.
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true, action = clap::ArgAction::Set)]
        com: Option<Vec<f64>>,
        /// Gravity gradient K,N: tau = 3K (r x I r), r = R(q)^T (cos N t, sin N t, 0); on a
        /// circular orbit K = N^2 (N the orbit's rate). Not checked for sense (a negative K is
        /// taken).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true, action = clap::ArgAction::Set)]
        gravity_gradient: Option<Vec<f64>>,
        /// Body torque amplitudes A1,A2,A3: tau_i(t) = A_i cos(W_i t + P_i).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true, action = clap::ArgAction::Set)]
        body_torque: Option<Vec<f64>>,
        /// Body torque frequencies W1,W2,W3 (default 0: constant).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true, action = clap::ArgAction::Set)]
        torque_freq: Option<Vec<f64>>,
        /// Body torque phases P1,P2,P3 (default 0).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true, action = clap::ArgAction::Set)]
        torque_phase: Option<Vec<f64>>,
    },
    /// List the methods.
    Methods,
    /// The talk's case with every method: errors against the reference and invariant drift.
    Demo,
    /// Table of host time per step from the last `cargo bench --bench steps`.
    BenchTable {
        /// Criterion's output folder.
        #[arg(long, default_value = "target/criterion")]
        dir: std::path::PathBuf,
    },
    /// Work-precision tables (counted ops to reach each error level) on the public scenes.
    WorkPrecision {
        /// Scenes (default: talk and hv).
        #[arg(long, value_delimiter = ',', default_value = "talk,hv")]
        scenes: Vec<String>,
        /// Final time (a reference time: 1, 10 or 100).
        #[arg(long, default_value_t = 10.0)]
        t: f64,
    },
    /// Every chart of the README (figures 1-9, SVG and PNG), then the talk's claims table.
    Figures {
        /// Output folder.
        #[arg(long, default_value = "figures")]
        out: std::path::PathBuf,
    },
    /// The talk's claims next to our measurements, and the headline comparison.
    Claims,
    /// Counted flops per step of every method (the counting `Real`).
    Flops {
        /// Step size (nonzero; negative steps backwards).
        #[arg(long, default_value_t = 0.1, allow_hyphen_values = true)]
        h: f64,
    },
    /// Forced work-precision at T = 10 against the mpmath references (lab/refs/forced_refs.json):
    /// for each error level 1e-4..1e-10, the fewest counted operations of the best rigid3 forced
    /// method and of RK4, the Strang splitting and the midpoint rule, with attitude.
    ForcedWork {
        /// Scene (heavy_top, satellite, gyrostat, lagrange_top, gravity_gradient,
        /// body_torque); default: the three charted ones.
        #[arg(long)]
        scene: Option<String>,
    },
    /// Table of the `loop` bench (`cargo bench -p rigid3-lab --bench loop`): ns per step of
    /// mv, hv-dmv and splitting at h = 0.001, 0.01, 0.1 and the ratios mv/hv-dmv, mv/splitting.
    LoopTable {
        /// Criterion's output folder.
        #[arg(long, default_value = "target/criterion")]
        dir: std::path::PathBuf,
    },
    /// Host ns per step with attitude of mv, pre-mv4, pre-mv10, retimed-mv (and the 5-rotation
    /// splitting)
    /// in f64 and f32 when h, m or the torque change every step: regimes fixed, jitter
    /// (set_step_size with h0 +-5%), corrected (m_i *= 1 + 1e-4 r_i), torque (m += h tau).
    /// Spacecraft of firmware/src/bin/attitude.rs, h0 = 1/200; best of 3 batches after a warm-up.
    LoopCost {
        /// Steps per timed batch.
        #[arg(long, default_value_t = rigid3_lab::loop_cost::DEFAULT_STEPS)]
        steps: usize,
        /// Initial body momentum x,y,z (default: the spacecraft's, |Omega| = 0.13 rad/s; e.g.
        /// 3,40,12 spins it at 0.43 rad/s).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        m0: Option<Vec<f64>>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// A long run with attitude: max relative drift of |m|^2, E and R(q) m so far at every
    /// decade of steps (10, 100, ..., and the last). The invariants are evaluated in f64 from
    /// the state after every step (not sampled; 10^8 f32 mv steps take well under a minute).
    /// Defaults: the README's spacecraft (principal moments 58.84, 95.50, 120.66 kg m^2, from
    /// the inertia tensor of firmware/src/bin/attitude.rs, tumbling at 0.13 rad/s: m0 and q0
    /// printed by `soak --json`), h = 1/200.
    Soak {
        /// Method name: a free method of `rigid3-lab methods`, or with --rotor a forced one.
        #[arg(long)]
        method: String,
        /// Steps (at least 1).
        #[arg(long)]
        steps: u64,
        /// Compute in f32 instead of f64.
        #[arg(long)]
        f32: bool,
        /// Step size.
        #[arg(long, default_value_t = rigid3_lab::scenes::SPACECRAFT_H, allow_hyphen_values = true)]
        h: f64,
        /// Principal moments of inertia I1,I2,I3 (default: the spacecraft's).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        inertia: Option<Vec<f64>>,
        /// Initial body momentum x,y,z (default: the spacecraft's).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        m0: Option<Vec<f64>>,
        /// Initial attitude w,x,y,z, body to space (default: the spacecraft's).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        q0: Option<Vec<f64>>,
        /// Constant rotor momentum hx,hy,hz (body frame): a gyrostat, stepped by the forced
        /// step of the method (`rigid3-lab methods`), E its energy.
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        rotor: Option<Vec<f64>>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
}

/// Output piped into a reader that stops early (`| head`) ends the run with status 141, as a
/// process killed by SIGPIPE does, without a panic report: `println!` panics on a closed pipe
/// (Rust ignores SIGPIPE), which printed a panic and a backtrace (found by a trial of the
/// CLI). Only std's own "failed printing to stdout" panic is taken: a status of success would
/// hide a run that failed after its report (found in review), and every other panic keeps the
/// default report.
fn quiet_on_closed_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.starts_with("failed printing to stdout") && message.contains("Broken pipe") {
            std::process::exit(141);
        }
        default(info);
    }));
}

fn main() -> ExitCode {
    quiet_on_closed_pipe();
    match Cli::parse().command {
        Command::Propagate {
            method,
            inertia,
            m0,
            q0,
            h,
            t,
            f32,
            json,
            rotor,
            gravity,
            com,
            gravity_gradient,
            body_torque,
            torque_freq,
            torque_phase,
        } => {
            let spec = match force_spec(
                rotor,
                gravity,
                com,
                gravity_gradient,
                body_torque,
                torque_freq,
                torque_phase,
            ) {
                Ok(s) => s,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::FAILURE;
                }
            };
            let (Ok(inertia), Ok(m0)) = (<[f64; 3]>::try_from(inertia), <[f64; 3]>::try_from(m0))
            else {
                eprintln!("error: --inertia and --m0 take three comma-separated numbers");
                return ExitCode::FAILURE;
            };
            let q0 = match q0.map(<[f64; 4]>::try_from) {
                None => None,
                Some(Ok(q)) => Some(q),
                Some(Err(_)) => {
                    eprintln!("error: --q0 takes four comma-separated numbers w,x,y,z");
                    return ExitCode::FAILURE;
                }
            };
            let checked = check_propagate(inertia, m0, q0, h, t, f32, &spec);
            let (q0, steps) = match checked {
                Ok(x) => x,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::FAILURE;
                }
            };
            // a free scene runs the free methods; a forced method's name without any force
            // (forced4, fg4-pre6, ...) runs it with no torque and no rotor
            let free = spec.is_free() && METHODS.contains(&method.as_str());
            let report = match (free, f32) {
                (true, true) => run::<f32>(&method, inertia, m0, q0, h, steps),
                (true, false) => run::<f64>(&method, inertia, m0, q0, h, steps),
                (false, true) => run_forced::<f32>(&method, inertia, m0, q0, h, steps, &spec),
                (false, false) => run_forced::<f64>(&method, inertia, m0, q0, h, steps, &spec),
            };
            match report {
                Ok(mut r) => {
                    // a result whose invariants f64 cannot represent is not a measurement
                    // (a run that overflowed its scale, or a huge one): said, and a failure,
                    // not a `null` in the JSON with exit code 0 (found by an external check)
                    let bad = r.non_finite_fields();
                    if r.error.is_none() && !bad.is_empty() {
                        r.error = Some(format!(
                            "not representable in f64 (overflow, or an underflow that lost the digits) at the end of the run: {}",
                            bad.join(", ")
                        ));
                    }
                    if json {
                        println!("{}", serde_json::to_string_pretty(&r).unwrap_or_default());
                    } else {
                        print_report(&r, !free, !spec.is_free());
                    }
                    if r.error.is_some() {
                        ExitCode::FAILURE
                    } else {
                        ExitCode::SUCCESS
                    }
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::FAILURE
                }
            }
        }
        Command::Methods => {
            println!("free body (propagate without force flags):");
            for m in METHODS {
                println!("  {m:<16} {}", describe(m));
            }
            println!(
                "forced body (propagate with --rotor, --gravity, --gravity-gradient or \
                 --body-torque; a free run of a name found only here takes it with no force):"
            );
            for m in FORCED_METHODS {
                println!("  {m:<16} {}", describe_forced(m));
            }
            ExitCode::SUCCESS
        }
        Command::BenchTable { dir } => {
            if rigid3_lab::bench_table::print(&dir) {
                ExitCode::SUCCESS
            } else {
                eprintln!(
                    "no criterion results under {}: run `cargo bench --bench steps`",
                    dir.display()
                );
                ExitCode::FAILURE
            }
        }
        Command::WorkPrecision { scenes, t } => {
            // the errors are measured against the references, which exist at these times only
            // (any other --t printed a table of "-" and "NOT met", found by an analyst's trial)
            if ![1.0, 10.0, 100.0].contains(&t) {
                eprintln!("error: --t must be a reference time: 1, 10 or 100 (got {t})");
                return ExitCode::FAILURE;
            }
            let mut all = true;
            for name in scenes {
                let Some(scene) = rigid3_lab::refs::scene(&name) else {
                    eprintln!("error: unknown scene '{name}'");
                    return ExitCode::FAILURE;
                };
                all &= rigid3_lab::work_precision::print_table(&scene, t);
                println!();
            }
            println!(
                "target (best PreMv below every baseline at every level, 10x at 1e-10): {}",
                if all { "met" } else { "NOT met" }
            );
            ExitCode::SUCCESS
        }
        Command::Flops { h } => {
            if !h.is_finite() || h == 0.0 {
                eprintln!("error: --h must be finite and nonzero (got {h})");
                return ExitCode::FAILURE;
            }
            rigid3_lab::flops::print_table(h);
            ExitCode::SUCCESS
        }
        Command::Figures { out } => match rigid3_lab::figures::all(&out) {
            Ok((files, measured)) => {
                println!();
                rigid3_lab::claims::print(&measured);
                println!();
                println!(
                    "{} files written to {}/ (fig1..fig9, .svg and .png)",
                    files.len(),
                    out.display()
                );
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        Command::Claims => {
            rigid3_lab::claims::print(&rigid3_lab::claims::measure());
            ExitCode::SUCCESS
        }
        Command::ForcedWork { scene } => {
            let names: Vec<String> = match scene {
                Some(s) => vec![s],
                None => rigid3_lab::forced_work::CHARTED_FORCED_SCENES
                    .iter()
                    .map(|s| s.to_string())
                    .collect(),
            };
            let mut all = true;
            for name in names {
                let Some(sc) = rigid3_lab::forced_work::ForcedScene::from_reference(&name, 10.0)
                else {
                    eprintln!(
                        "error: unknown forced scene '{name}' (scenes: heavy_top, satellite, \
                         gyrostat, lagrange_top, gravity_gradient, body_torque)"
                    );
                    return ExitCode::FAILURE;
                };
                let wins = rigid3_lab::forced_work::print_table(&sc);
                println!(
                    "best rigid3 forced method cheaper than rk4 and splitting at every level: {}\n",
                    if wins { "yes" } else { "no" }
                );
                all &= wins;
            }
            let _ = all;
            ExitCode::SUCCESS
        }
        Command::LoopTable { dir } => {
            if rigid3_lab::bench_table::print_loop(&dir) {
                ExitCode::SUCCESS
            } else {
                eprintln!(
                    "no loop-bench results under {}: run `cargo bench -p rigid3-lab --bench loop`",
                    dir.display()
                );
                ExitCode::FAILURE
            }
        }
        Command::LoopCost { steps, m0, json } => match (if steps == 0 {
            Err("--steps must be at least 1".to_string())
        } else {
            Ok(m0)
        })
        .and_then(|m0| {
            m0.map(|v| {
                <[f64; 3]>::try_from(v)
                    .map_err(|_| "--m0 takes three comma-separated numbers".to_string())
            })
            .transpose()
        })
        .and_then(|m0| rigid3_lab::loop_cost::measure(steps, m0))
        {
            Ok(r) => {
                if json {
                    println!("{}", serde_json::to_string_pretty(&r).unwrap_or_default());
                } else {
                    rigid3_lab::loop_cost::print(&r);
                }
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        Command::Soak {
            method,
            steps,
            f32,
            h,
            inertia,
            m0,
            q0,
            rotor,
            json,
        } => {
            let (si, sm, sq) = rigid3_lab::scenes::spacecraft();
            let parsed = (
                inertia.map_or(Ok(si), <[f64; 3]>::try_from),
                m0.map_or(Ok(sm), <[f64; 3]>::try_from),
                q0.map_or(Ok(sq), <[f64; 4]>::try_from),
                rotor.map(<[f64; 3]>::try_from).transpose(),
            );
            if steps == 0 {
                eprintln!("error: --steps must be at least 1");
                return ExitCode::FAILURE;
            }
            let (Ok(inertia), Ok(m0), Ok(q0), Ok(rotor)) = parsed else {
                eprintln!(
                    "error: --inertia, --m0 and --rotor take three comma-separated numbers, --q0 four"
                );
                return ExitCode::FAILURE;
            };
            let r = if f32 {
                rigid3_lab::soak::soak::<f32>(&method, inertia, m0, q0, h, steps, rotor)
            } else {
                rigid3_lab::soak::soak::<f64>(&method, inertia, m0, q0, h, steps, rotor)
            };
            match r {
                Ok(r) => {
                    if json {
                        println!("{}", serde_json::to_string_pretty(&r).unwrap_or_default());
                    } else {
                        rigid3_lab::soak::print(&r);
                    }
                    if r.error.is_some() {
                        ExitCode::FAILURE
                    } else {
                        ExitCode::SUCCESS
                    }
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::FAILURE
                }
            }
        }
        Command::Demo => {
            rigid3_lab::demo::print_demo();
            ExitCode::SUCCESS
        }
    }
}

/// `propagate`'s inputs checked before anything runs (rigid3_lab::inputs): every number
/// finite (and within f32's range with `--f32`; `q0` is normalised in f64 first), `h`
/// nonzero in the run's precision, `t` at least zero and at most `MAX_STEPS` steps, `q0`
/// nonzero (returned normalised, so the invariants are those of the attitude the run
/// starts from). Returns `q0` and the number of steps.
fn check_propagate(
    inertia: [f64; 3],
    m0: [f64; 3],
    q0: Option<[f64; 4]>,
    h: f64,
    t: f64,
    f32: bool,
    spec: &ForceSpec,
) -> Result<(Option<[f64; 4]>, usize), String> {
    let mut named: Vec<(&str, Vec<f64>)> = vec![
        ("inertia", inertia.to_vec()),
        ("m0", m0.to_vec()),
        ("h", vec![h]),
        ("t", vec![t]),
    ];
    if let Some(r) = spec.rotor {
        named.push(("rotor", r.to_vec()));
    }
    if let Some((mg, com)) = spec.gravity {
        named.push(("gravity", vec![mg]));
        named.push(("com", com.to_vec()));
    }
    if let Some((k, n)) = spec.gravity_gradient {
        named.push(("gravity-gradient", vec![k, n]));
    }
    if let Some((a, w, p)) = spec.body_torque {
        named.push(("body-torque", a.to_vec()));
        named.push(("torque-freq", w.to_vec()));
        named.push(("torque-phase", p.to_vec()));
    }
    let refs: Vec<(&str, &[f64])> = named.iter().map(|(f, v)| (*f, v.as_slice())).collect();
    inputs::check_finite(&refs, f32)?;
    inputs::check_inertia_range(&inertia, f32)?;
    inputs::check_step(h, f32)?;
    // (t is not rounded: the run counts its steps in f64)
    let stepped: Vec<(&str, &[f64])> = refs.iter().copied().filter(|(f, _)| *f != "t").collect();
    inputs::check_underflow(&stepped, f32)?;
    if t < 0.0 {
        return Err(
            "--t is a duration and must be at least 0 (a negative --h runs backwards)".into(),
        );
    }
    let steps = (t / h).abs().round();
    inputs::check_steps(steps, &format!("--t {t:e} at --h {h:e}"))?;
    let q0 = q0.map(inputs::unit_quaternion).transpose()?;
    Ok((q0, steps as usize))
}

fn run<T: Real + 'static>(
    method: &str,
    inertia: [f64; 3],
    m0: [f64; 3],
    q0: Option<[f64; 4]>,
    h: f64,
    steps: usize,
) -> Result<Report, String> {
    let body = Body::<T>::from_inertia(inertia.map(T::from_f64)).map_err(|e| e.to_string())?;
    let mut integrator = make(method, body, T::from_f64(h))
        .ok_or_else(|| format!("unknown method '{method}' (see `rigid3-lab methods`)"))?;
    let s0 = State::new(
        m0.map(T::from_f64),
        q0.unwrap_or([1.0, 0.0, 0.0, 0.0]).map(T::from_f64),
    );
    Ok(propagate(
        method,
        integrator.as_mut(),
        &body,
        s0,
        steps,
        q0.is_some(),
    ))
}

/// The forcing from the CLI's flags.
fn force_spec(
    rotor: Option<Vec<f64>>,
    gravity: Option<f64>,
    com: Option<Vec<f64>>,
    gravity_gradient: Option<Vec<f64>>,
    body_torque: Option<Vec<f64>>,
    torque_freq: Option<Vec<f64>>,
    torque_phase: Option<Vec<f64>>,
) -> Result<ForceSpec, String> {
    let three = |v: Option<Vec<f64>>, flag: &str| -> Result<Option<[f64; 3]>, String> {
        v.map(|v| {
            <[f64; 3]>::try_from(v)
                .map_err(|_| format!("--{flag} takes three comma-separated numbers"))
        })
        .transpose()
    };
    let gravity = match (gravity, three(com, "com")?) {
        (Some(mg), Some(c)) => Some((mg, c)),
        (None, None) => None,
        _ => return Err("--gravity and --com go together".into()),
    };
    let gravity_gradient = match gravity_gradient {
        Some(v) => match v.as_slice() {
            [k, n] => Some((*k, *n)),
            _ => return Err("--gravity-gradient takes K,N".into()),
        },
        None => None,
    };
    let freq = three(torque_freq, "torque-freq")?;
    let phase = three(torque_phase, "torque-phase")?;
    let body_torque = match three(body_torque, "body-torque")? {
        Some(a) => Some((a, freq.unwrap_or([0.0; 3]), phase.unwrap_or([0.0; 3]))),
        None if freq.is_some() || phase.is_some() => {
            return Err("--torque-freq/--torque-phase need --body-torque".into())
        }
        None => None,
    };
    Ok(ForceSpec {
        rotor: three(rotor, "rotor")?,
        gravity,
        gravity_gradient,
        body_torque,
    })
}

fn run_forced<T: Real + 'static>(
    method: &str,
    inertia: [f64; 3],
    m0: [f64; 3],
    q0: Option<[f64; 4]>,
    h: f64,
    steps: usize,
    spec: &ForceSpec,
) -> Result<Report, String> {
    let body = Body::<T>::from_inertia(inertia.map(T::from_f64)).map_err(|e| e.to_string())?;
    // the library takes such a rotor and refuses the steps (the limit is the step's: a
    // flight loop that sets the wheels before the measured dt recovers from one bad dt); a
    // run with a fixed h would only stop at its first step, so the methods built on
    // `Forced` refuse it here, by name (a composition's stages turn by their own lengths,
    // and its run stops at the first step; `rk4` has no turns)
    if let Some(r) = spec.rotor {
        let w2: f64 = (0..3).map(|i| (r[i] / inertia[i]).powi(2)).sum();
        let turns = FORCED_METHODS.contains(&method)
            && !needs_exact_drift(method)
            && !method.starts_with("forced")
            && method != "rk4";
        if turns && h * h * w2 > 64.0 {
            return Err(format!("'{method}' refused the rotor: its half turn per step passes half a revolution (h |I^-1 h_r| > 8)"));
        }
    }
    let mut integrator = make_forced(method, body, T::from_f64(h), spec)
        .ok_or_else(|| rigid3_lab::forced_methods::refusal(method, spec))?;
    let s0 = State::new(
        m0.map(T::from_f64),
        q0.unwrap_or([1.0, 0.0, 0.0, 0.0]).map(T::from_f64),
    );
    Ok(propagate_forced(
        method,
        integrator.as_mut(),
        spec,
        s0,
        steps,
    ))
}

/// The report of a run: `forced_method`, a run of a forced method (its description is the
/// forced one); `with_forces`, a run with a torque or a rotor, whose `|m|^2`, `E` and `R(q) m`
/// change under a torque (their largest relative change is printed, not a drift).
fn print_report(r: &Report, forced_method: bool, with_forces: bool) {
    let what = if forced_method {
        describe_forced(&r.method)
    } else {
        describe(&r.method)
    };
    let change = if with_forces {
        "max rel change"
    } else {
        "max rel drift"
    };
    println!("method   {}  ({what})", r.method);
    println!(
        "h        {}   steps {}   t {}",
        short(r.h),
        r.steps,
        short(r.t)
    );
    println!("m        {:.17e} {:.17e} {:.17e}", r.m[0], r.m[1], r.m[2]);
    if let Some(q) = r.q {
        println!(
            "q        {:.17e} {:.17e} {:.17e} {:.17e}",
            q[0], q[1], q[2], q[3]
        );
    }
    // an invariant whose evaluation overflowed (|m| near 1e200): no number, as in the JSON's
    // null, but its drift where that was measured (in scaled units)
    let value = |x: f64, d: f64| match (x.is_finite(), d.is_finite()) {
        (true, _) => format!("{x:.17e}   {change} {d:.3e}"),
        (false, true) => format!("overflows as evaluated   {change} {d:.3e}"),
        (false, false) => "overflows as evaluated".to_string(),
    };
    println!("energy   {}", value(r.energy, r.energy_drift));
    println!("|m|^2    {}", value(r.casimir, r.casimir_drift));
    if let (Some(p), Some(d)) = (r.spatial_momentum, r.spatial_momentum_drift) {
        println!(
            "R(q) m   {:.17e} {:.17e} {:.17e}   {change} {:.3e}",
            p[0], p[1], p[2], d
        );
    }
    if let (Some(e), Some(d)) = (r.total_energy, r.total_energy_drift) {
        // where the potential turns with the orbit the total energy is not conserved: the
        // Jacobi integral is
        let what = if r.jacobi_integral.is_some() {
            "max rel change"
        } else {
            "max rel drift"
        };
        println!("total E  {e:.17e}   {what} {d:.3e}");
    }
    if let (Some(j), Some(d)) = (r.jacobi_integral, r.jacobi_integral_drift) {
        println!("Jacobi   {j:.17e}   max rel drift {d:.3e}  (E - N e_z . R(q) m)");
    }
    if let Some(e) = &r.error {
        println!("stopped  {e}");
    }
}

/// A number as Rust prints it where that is at most 24 characters (every `f64` of a
/// moderate exponent), else in exponent form (an `h` of `1e-162` printed as a decimal was 165
/// characters).
fn short(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 24 {
        plain
    } else {
        format!("{x:e}")
    }
}
