//! `rigid3-lab soak`: a long run with attitude and the max relative drift of the invariants
//! so far at every decade of steps.
//!
//! The invariants are evaluated in f64 from the state after every step (also for an f32 run):
//! `|m|^2` and `E` relative to their initial values, `R(q) m` as `|R(q) m - R(q0) m0| /
//! |R(q0) m0|`. Evaluating every step costs about as much as an `Mv` step in f32 (a few ns;
//! 10^8 steps take well under a minute on the 2-core machine), so nothing is sampled.

use crate::forced_methods::{make_forced, needs_exact_drift, ForceSpec, FORCED_METHODS};
use crate::methods::make;
use crate::propagate::{max_abs, unit_of, worse};
use rigid3::{Body, Real, State};
use serde::Serialize;
use std::time::Instant;

/// The drift at one checkpoint.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Checkpoint {
    /// Steps taken.
    pub steps: u64,
    /// Max relative drift of `|m|^2` over steps `1..=steps`.
    pub casimir: f64,
    /// Max relative drift of the energy.
    pub energy: f64,
    /// Max of `|R(q) m - R(q0) m0| / |R(q0) m0|`.
    pub spatial: f64,
}

/// A soak run.
#[derive(Clone, Debug, Serialize)]
pub struct Soak {
    /// Method name.
    pub method: String,
    /// "f64" or "f32".
    pub precision: &'static str,
    /// Step size.
    pub h: f64,
    /// Principal moments.
    pub inertia: [f64; 3],
    /// Initial momentum.
    pub m0: [f64; 3],
    /// Initial attitude.
    pub q0: [f64; 4],
    /// Constant rotor momentum (a gyrostat through the forced step), if any.
    pub rotor: Option<[f64; 3]>,
    /// Steps taken.
    pub steps: u64,
    /// Wall time of the run, s.
    pub seconds: f64,
    /// At 10, 100, ... steps and at the last step.
    pub checkpoints: Vec<Checkpoint>,
    /// The error that stopped the run early, if any.
    pub error: Option<String>,
}

/// The checkpoints of a run of `n` steps: the powers of ten up to `n`, and `n`.
pub fn checkpoints(n: u64) -> Vec<u64> {
    let mut v = Vec::new();
    let mut d = 10u64;
    while d <= n {
        v.push(d);
        match d.checked_mul(10) {
            Some(x) => d = x,
            None => break,
        }
    }
    if n > 0 && v.last() != Some(&n) {
        v.push(n);
    }
    v
}

/// Runs `method` in precision `T` for `steps` steps with attitude; with a `rotor`, the
/// gyrostat through the forced step of `method` (crate::forced_methods), whose energy is
/// `1/2 (m - h_r) . I^-1 (m - h_r)` (`|m|^2` and `R(q) m` as without).
pub fn soak<T: Real + 'static>(
    method: &str,
    inertia: [f64; 3],
    m0: [f64; 3],
    q0: [f64; 4],
    h: f64,
    steps: u64,
    rotor: Option<[f64; 3]>,
) -> Result<Soak, String> {
    // the numbers checked before the run, each refusal naming its flag (crate::inputs); the
    // attitude the run starts from is the unit one (the invariants are those of the state
    // stepped, not of a quaternion the integrator normalises on its first step)
    let f32 = T::EPSILON.to_f64() > 1e-10;
    crate::inputs::check_finite(&[("inertia", &inertia), ("m0", &m0), ("h", &[h])], f32)?;
    if let Some(r) = rotor {
        crate::inputs::check_finite(&[("rotor", &r)], f32)?;
    }
    crate::inputs::check_inertia_range(&inertia, f32)?;
    crate::inputs::check_step(h, f32)?;
    crate::inputs::check_underflow(&[("m0", &m0)], f32)?;
    if let Some(r) = rotor {
        crate::inputs::check_underflow(&[("rotor", &r)], f32)?;
    }
    crate::inputs::check_steps(steps as f64, "--steps")?;
    let q0 = crate::inputs::unit_quaternion(q0)?;
    let body = Body::<T>::from_inertia(inertia.map(T::from_f64)).map_err(|e| e.to_string())?;
    let mut it = match rotor {
        None => make(method, body, T::from_f64(h)).ok_or_else(|| {
            if needs_exact_drift(method) {
                format!("'{method}' splits a torque, and soak runs none: it runs the free methods, and the forced ones with --rotor, which this one cannot take")
            } else if FORCED_METHODS.contains(&method) {
                format!("'{method}' is a forced method: soak runs it with --rotor")
            } else {
                format!("unknown method '{method}' (see `rigid3-lab methods`)")
            }
        })?,
        Some(r) => {
            let spec = ForceSpec {
                rotor: Some(r),
                ..ForceSpec::default()
            };
            make_forced(method, body, T::from_f64(h), &spec)
                .ok_or_else(|| crate::forced_methods::refusal(method, &spec))?
        }
    };
    let precision = if T::EPSILON.to_f64() > 1e-10 {
        "f32"
    } else {
        "f64"
    };
    let mut s = State::new(m0.map(T::from_f64), q0.map(T::from_f64));
    // the invariants of the state as stored in T, evaluated in f64 in units where the start's
    // largest component and largest 1 / I_i are near one (powers of two: nothing rounds, and
    // the relative drifts are those of the caller's units): unscaled, |m|^2 of a momentum of
    // 1e200 overflowed and of 1e-200 underflowed, and the drifts read 0 with exit 0 (found
    // by an external check)
    let m_unit = unit_of(max_abs(m0));
    let inv_i = body.inertia().map(|x| 1.0 / x.to_f64());
    let i_unit = unit_of(max_abs(inv_i));
    let inv_i = inv_i.map(|x| x * i_unit);
    // the rotor the integrator steps: in f32 the f64 value rounded (unrounded, the reported
    // energy took in the difference, 5 % of it on a cubesat, found in review)
    let h_r = rotor
        .unwrap_or([0.0; 3])
        .map(|x| T::from_f64(x).to_f64() * m_unit);
    let wide = |s: &State<T>| {
        let m = s.m.map(|x| x.to_f64() * m_unit);
        let c = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
        let n = [m[0] - h_r[0], m[1] - h_r[1], m[2] - h_r[2]];
        let e = 0.5 * (n[0] * n[0] * inv_i[0] + n[1] * n[1] * inv_i[1] + n[2] * n[2] * inv_i[2]);
        let p = State::new(m, s.q.map(Real::to_f64)).spatial_momentum();
        (c, e, p)
    };
    let (c0, e0, p0) = wide(&s);
    let pn = (p0[0] * p0[0] + p0[1] * p0[1] + p0[2] * p0[2]).sqrt();
    let (c_scale, e_scale, p_scale) = (
        1.0 / c0.abs().max(f64::MIN_POSITIVE),
        1.0 / e0.abs().max(f64::MIN_POSITIVE),
        1.0 / pn.max(f64::MIN_POSITIVE),
    );
    let marks = checkpoints(steps);
    let mut out = Vec::with_capacity(marks.len());
    let (mut dc, mut de, mut dp) = (0.0f64, 0.0f64, 0.0f64);
    let mut taken = 0u64;
    let mut error = None;
    let t0 = Instant::now();
    'run: for &mark in &marks {
        while taken < mark {
            if let Err(e) = it.step_state(&mut s) {
                error = Some(e.to_string());
                break 'run;
            }
            taken += 1;
            let (c, e, p) = wide(&s);
            dc = worse(dc, (c - c0).abs() * c_scale);
            de = worse(de, (e - e0).abs() * e_scale);
            let d = [p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]];
            dp = worse(
                dp,
                (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() * p_scale,
            );
        }
        out.push(Checkpoint {
            steps: taken,
            casimir: dc,
            energy: de,
            spatial: dp,
        });
    }
    // a drift f64 cannot hold (a state that overflowed in the scaled units) is the run's
    // error, named, as `propagate` does
    if error.is_none() && !(dc.is_finite() && de.is_finite() && dp.is_finite()) {
        error = Some("a drift is not finite (the invariants overflow f64)".to_string());
    }
    if error.is_some() && out.last().map(|c| c.steps) != Some(taken) {
        out.push(Checkpoint {
            steps: taken,
            casimir: dc,
            energy: de,
            spatial: dp,
        });
    }
    Ok(Soak {
        method: method.to_string(),
        precision,
        h,
        inertia,
        m0,
        q0,
        rotor,
        steps: taken,
        seconds: t0.elapsed().as_secs_f64(),
        checkpoints: out,
        error,
    })
}

/// Prints a soak run as a table.
pub fn print(r: &Soak) {
    println!(
        "soak: {} {}, h = {}, {} steps (t = {}), {:.2} s; I = {:?}, m0 = {:?}, q0 = {:?}{}",
        r.method,
        r.precision,
        r.h,
        r.steps,
        r.steps as f64 * r.h,
        r.seconds,
        r.inertia,
        r.m0,
        r.q0,
        r.rotor.map_or(String::new(), |h| format!(
            ", rotor {h:?} (E the gyrostat's)"
        ))
    );
    println!("max relative drift over the run so far (invariants in f64 from the state)");
    println!(
        "{:>12} {:>12} {:>12} {:>12}",
        "steps", "|m|^2", "E", "R(q)m"
    );
    for c in &r.checkpoints {
        println!(
            "{:>12} {:>12.3e} {:>12.3e} {:>12.3e}",
            c.steps, c.casimir, c.energy, c.spatial
        );
    }
    if let Some(e) = &r.error {
        println!("stopped: {e}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checkpoints_are_the_decades_and_the_end() {
        assert_eq!(checkpoints(10_000), vec![10, 100, 1000, 10_000]);
        assert_eq!(checkpoints(2500), vec![10, 100, 1000, 2500]);
        assert_eq!(checkpoints(7), vec![7]);
        assert!(checkpoints(0).is_empty());
    }
}
