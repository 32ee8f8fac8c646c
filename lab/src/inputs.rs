//! Checks of the CLI's numbers before a run (`propagate`, `soak`): every number finite (and
//! within f32's range for an f32 run), a step that is not zero in the run's precision, a
//! bounded step count, and the initial attitude as a unit quaternion. Each refusal names its
//! flag.

/// The most steps a run takes (a larger count is a typo, not a run: `1e10` `Mv` steps take
/// about five minutes).
pub const MAX_STEPS: f64 = 1e10;

/// `Err` naming the first flag with a number that is not finite (or, with `f32`, not finite
/// once rounded to f32).
pub fn check_finite(named: &[(&str, &[f64])], f32: bool) -> Result<(), String> {
    let range = if f32 { " and within f32's range" } else { "" };
    for (flag, values) in named {
        if !values
            .iter()
            .all(|&x| x.is_finite() && (!f32 || (x as f32).is_finite()))
        {
            return Err(format!("--{flag} must be finite{range}"));
        }
    }
    Ok(())
}

/// `Err` naming the first flag whose nonzero value rounds to zero as a whole in f32 (`--m0
/// 1e-50,0,0 --f32` ran as a body at rest with exit 0, found by an analyst's trial); a tiny
/// entry beside larger ones rounds like any other (refusing it refused ordinary runs, found
/// in review). Called after the checks of `--inertia` and `--h`, whose own messages say more.
pub fn check_underflow(named: &[(&str, &[f64])], f32: bool) -> Result<(), String> {
    for (flag, values) in named {
        let nonzero = values.iter().any(|&x| x != 0.0);
        if f32 && nonzero && values.iter().all(|&x| x as f32 == 0.0) {
            return Err(format!(
                "--{flag} is nonzero but rounds to zero in f32 (below 7e-46)"
            ));
        }
    }
    Ok(())
}

/// `Err` when a positive moment of inertia rounds to zero in f32 (the body's own check would
/// call it "not positive", which the flag's value is not).
pub fn check_inertia_range(inertia: &[f64], f32: bool) -> Result<(), String> {
    if f32 && inertia.iter().any(|&x| x > 0.0 && x as f32 == 0.0) {
        return Err("--inertia has a moment that rounds to zero in f32 (below 7e-46)".into());
    }
    Ok(())
}

/// `h` nonzero in the run's precision (a step that rounds to zero in f32 stands still).
pub fn check_step(h: f64, f32: bool) -> Result<(), String> {
    if h == 0.0 || (f32 && h as f32 == 0.0) {
        return Err(format!(
            "--h must be nonzero{} (a negative h runs backwards)",
            if f32 { " in f32" } else { "" }
        ));
    }
    Ok(())
}

/// `steps` within [`MAX_STEPS`].
pub fn check_steps(steps: f64, what: &str) -> Result<(), String> {
    if steps <= MAX_STEPS {
        Ok(())
    } else {
        Err(format!(
            "{what} is {steps:e} steps, more than {MAX_STEPS:e}: take fewer or larger steps"
        ))
    }
}

/// `q` as a unit quaternion (a unit one to round-off is kept bit for bit), its length taken
/// with the components scaled by the largest (so `1e-170` or `1e200` components are a
/// direction like any other); `Err` for a zero or non-finite `q`.
pub fn unit_quaternion(q: [f64; 4]) -> Result<[f64; 4], String> {
    let s = q.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if !(s > 0.0 && s.is_finite() && q.iter().all(|x| x.is_finite())) {
        return Err("--q0 must be a finite nonzero quaternion w,x,y,z".into());
    }
    let n2 = q.iter().map(|x| x * x).sum::<f64>();
    if (n2 - 1.0).abs() <= 4.0 * f64::EPSILON {
        return Ok(q);
    }
    let scaled = q.map(|x| x / s);
    let n = scaled.iter().map(|x| x * x).sum::<f64>().sqrt();
    Ok(scaled.map(|x| x / n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternions_are_normalised_at_any_scale_and_unit_ones_kept() {
        let q = [1.0, 0.0, 0.0, 0.0];
        assert_eq!(unit_quaternion(q), Ok(q));
        let h = core::f64::consts::FRAC_1_SQRT_2;
        for scale in [1e-170, 1e-3, 3.0, 1e200] {
            let u = unit_quaternion([scale, scale, 0.0, 0.0]).unwrap();
            assert!(
                (u[0] - h).abs() < 4e-16 && (u[1] - h).abs() < 4e-16,
                "{scale}: {u:?}"
            );
        }
        assert!(unit_quaternion([0.0; 4]).is_err());
        assert!(unit_quaternion([f64::NAN, 1.0, 0.0, 0.0]).is_err());
        assert!(unit_quaternion([f64::INFINITY, 1.0, 0.0, 0.0]).is_err());
    }

    #[test]
    fn steps_that_stand_still_or_never_end_are_refused() {
        assert!(check_step(0.0, false).is_err());
        assert!(check_step(1e-50, false).is_ok());
        assert!(check_step(1e-50, true).is_err());
        assert!(check_inertia_range(&[1e-50, 1.0, 1.0], false).is_ok());
        assert!(check_inertia_range(&[1e-50, 1.0, 1.0], true).is_err());
        // a non-positive moment is the body's to refuse, with its own message
        assert!(check_inertia_range(&[-1.0, 0.0, 1e-40], true).is_ok());
        assert!(check_steps(1e10, "x").is_ok());
        assert!(check_steps(1.5e10, "x").is_err());
        assert!(check_steps(f64::NAN, "x").is_err());
        assert!(check_finite(&[("a", &[1.0, 2.0]), ("b", &[1e39])], false).is_ok());
        assert_eq!(
            check_finite(&[("a", &[1.0, 2.0]), ("b", &[1e39])], true),
            Err("--b must be finite and within f32's range".to_string())
        );
    }
}
