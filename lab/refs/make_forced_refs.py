#!/usr/bin/env python3
"""High-precision reference solutions of the FORCED rigid body  ->  forced_refs.json

For each scene (I, m0, q0, torques, rotor) integrates the 7-dimensional system
    m'  = m x Omega + tau(t, q),   Omega = I^-1 (m - h_r)       (body frame, m total momentum)
    q'  = 1/2 q (x) (0, Omega)     Hamilton product, q = (w,x,y,z) maps body -> space
with the torques of rigid3::torque (same formulas, written out here independently):
    gravity          tau = MG (Gamma x chi),  Gamma = R(q)^T e_z
    gravity gradient tau = 3 K (r x I r),     r = R(q)^T (cos N t, sin N t, 0)
    body torque      tau_i = A_i cos(W_i t + P_i)
and reports m(t), q(t) at t = 1 and t = 10.

Two independent integrators (run in parallel, 2 processes):
  A  mpmath.odefun (mpmath's Taylor-series solver), mp.dps = 40, degree 45;
  B  our own 8-stage Gauss-Legendre collocation (order 16; nodes from the roots of the
     shifted Legendre polynomial, coefficients from the simplifying conditions C(8)), step
     1/80, stages solved by fixed-point iteration to 1e-50, mp.dps = 60.
Stored values are B's, with 34 significant digits. The script stops with an error unless A
and B agree to at least 25 digits in every component (|m| normalised, q unit) and B keeps
|q| = 1 to 40 digits; it reports the agreement per scene (forced_refs.txt).

Usage:  python3 make_forced_refs.py     (needs mpmath; about a minute per scene)
"""
import json, sys, time
from multiprocessing import Pool
import mpmath
from mpmath import mp, mpf

TIMES = [1, 10]
NDIG = 34
AGREE_DIGITS = 25
TALK_I = ["0.9145", "1.0981", "1.66"]     # I_i = J_j + J_k of J = (0.9218, 0.7382, 0.1763)
TALK_M0 = ["0.4165", "0.9072", "0.0588"]
ID = ["1", "0", "0", "0"]

# name, I, m0, q0, spec (rotor, gravity (MG, chi), gravity gradient (K, N), body torque (A, W, P))
SCENES = [
    ("heavy_top", ["1", "1.5", "2"], ["0.3", "-0.6", "1.1"],
     ["0.9238795325112867", "0.3826834323650898", "0", "0"],
     dict(gravity=("1", ["0.2", "-0.1", "0.5"]))),
    ("lagrange_top", ["2", "2", "1"], ["0.1", "-0.2", "4"], ["C15", "S15", "0", "0"],
     dict(gravity=("1", ["0", "0", "0.5"]))),
    ("gravity_gradient", ["1.2", "1.5", "1.9"], ["0.1", "1.2", "-0.2"], ID,
     dict(gravity_gradient=("1", "1"))),
    ("body_torque", TALK_I, TALK_M0, ID,
     dict(body_torque=(["0.1", "-0.05", "0.08"], ["1.3", "0.7", "2.1"], ["0", "0.5", "1"]))),
    ("gyrostat", TALK_I, TALK_M0, ID, dict(rotor=["0.2", "-0.1", "0.3"])),
    ("satellite", ["1.2", "1.5", "1.9"], ["0.1", "1.2", "-0.2"], ID,
     dict(gravity_gradient=("1", "1"), rotor=["0", "0.3", "0"])),
]
RUNS = {"A": dict(dps=40, method="odefun", degree=45),
        "B": dict(dps=60, method="gauss", stages=8, steps_per_unit=80, tol="1e-50")}


def num(x):
    if x == "C15":
        return mpmath.cos(mpmath.pi / 12)
    if x == "S15":
        return mpmath.sin(mpmath.pi / 12)
    return mpf(x)


def setup(scene):
    name, I, m0, q0, spec = scene
    s = {}
    if "rotor" in spec:
        s["rotor"] = [num(v) for v in spec["rotor"]]
    if "gravity" in spec:
        s["gravity"] = (num(spec["gravity"][0]), [num(v) for v in spec["gravity"][1]])
    if "gravity_gradient" in spec:
        s["gg"] = tuple(num(v) for v in spec["gravity_gradient"])
    if "body_torque" in spec:
        s["bt"] = tuple([num(v) for v in part] for part in spec["body_torque"])
    # q0 given to 16 digits is unit only to 1e-16: start from the unit quaternion nearest it
    q = [num(v) for v in q0]
    n = mpmath.sqrt(sum(v * v for v in q))
    return [num(v) for v in I], [num(v) for v in m0], [v / n for v in q], s


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def rt_times(q, n):
    """R(q)^T n, R(q) the rotation of the unit quaternion q = (w, x, y, z)."""
    w, x, y, z = q
    R = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    return [R[0][i] * n[0] + R[1][i] * n[1] + R[2][i] * n[2] for i in range(3)]


def rhs(I, s, t, y):
    m, q = y[:3], y[3:]
    h = s.get("rotor", [0, 0, 0])
    om = [(m[i] - h[i]) / I[i] for i in range(3)]
    tau = [mpf(0)] * 3
    if "gravity" in s:
        mg, chi = s["gravity"]
        g = cross(rt_times(q, [0, 0, 1]), chi)
        tau = [tau[i] + mg * g[i] for i in range(3)]
    if "gg" in s:
        k, n = s["gg"]
        r = rt_times(q, [mpmath.cos(n * t), mpmath.sin(n * t), 0])
        g = cross(r, [I[i] * r[i] for i in range(3)])
        tau = [tau[i] + 3 * k * g[i] for i in range(3)]
    if "bt" in s:
        a, w, p = s["bt"]
        tau = [tau[i] + a[i] * mpmath.cos(w[i] * t + p[i]) for i in range(3)]
    dm = cross(m, om)
    dm = [dm[i] + tau[i] for i in range(3)]
    w_, x, y_, z = q
    a, b, c = om
    dq = [(-x * a - y_ * b - z * c) / 2, (w_ * a + y_ * c - z * b) / 2,
          (w_ * b + z * a - x * c) / 2, (w_ * c + x * b - y_ * a) / 2]
    return dm + dq


def gauss_tableau(s):
    """Nodes, weights and matrix of the s-stage Gauss-Legendre method at the current precision."""
    # shifted Legendre P_s(2x - 1): coefficients from the explicit sum
    coeffs = [mpmath.binomial(s, k) * mpmath.binomial(s + k, k) * (-1) ** (s - k) for k in range(s + 1)]
    roots = mpmath.polyroots(list(reversed(coeffs)), maxsteps=200, extraprec=200)
    c = sorted(mpmath.re(r) for r in roots)
    V = mpmath.matrix(s, s)
    for k in range(s):
        for j in range(s):
            V[k, j] = c[j] ** k
    b = mpmath.lu_solve(V, mpmath.matrix([mpf(1) / (k + 1) for k in range(s)]))
    A = []
    for i in range(s):
        row = mpmath.lu_solve(V, mpmath.matrix([c[i] ** (k + 1) / (k + 1) for k in range(s)]))
        A.append([row[j] for j in range(s)])
    return c, [b[j] for j in range(s)], A


def run_gauss(I, s_, y0, times, stages, per_unit, tol):
    c, b, A = gauss_tableau(stages)
    h = mpf(1) / per_unit
    y, t, out = list(y0), mpf(0), []
    K = [rhs(I, s_, t, y)] * stages
    n_total = int(max(times) * per_unit)
    for n in range(1, n_total + 1):
        for _ in range(200):
            Y = [[y[d] + h * sum(A[i][j] * K[j][d] for j in range(stages)) for d in range(7)]
                 for i in range(stages)]
            Kn = [rhs(I, s_, t + c[i] * h, Y[i]) for i in range(stages)]
            diff = max(abs(Kn[i][d] - K[i][d]) for i in range(stages) for d in range(7))
            K = Kn
            if diff < tol:
                break
        else:
            raise RuntimeError("Gauss stages did not converge")
        y = [y[d] + h * sum(b[j] * K[j][d] for j in range(stages)) for d in range(7)]
        t = n * h
        if n % per_unit == 0 and (n // per_unit) in times:
            out.append(list(y))
    return out


def task(args):
    si, run = args
    cfg = RUNS[run]
    mp.dps = cfg["dps"]
    I, m0, q0, s = setup(SCENES[si])
    t0 = time.time()
    if cfg["method"] == "odefun":
        F = mpmath.odefun(lambda t, y: rhs(I, s, t, y), 0, m0 + q0, degree=cfg["degree"])
        res = [F(T) for T in TIMES]
    else:
        res = run_gauss(I, s, m0 + q0, TIMES, cfg["stages"], cfg["steps_per_unit"], mpf(cfg["tol"]))
    return si, run, [[mpmath.nstr(v, 60) for v in y] for y in res], time.time() - t0


def main():
    jobs = [(si, r) for si in range(len(SCENES)) for r in RUNS]
    with Pool(2) as pool:
        results = pool.map(task, jobs)
    mp.dps = 60
    Y = {}
    for si, run, res, secs in results:
        Y.setdefault(si, {})[run] = ([[mpf(v) for v in y] for y in res], secs)
    out, lines, ok = [], [], True
    for si, (name, I, m0, q0, spec) in enumerate(SCENES):
        (a, ta), (b, tb) = Y[si]["A"], Y[si]["B"]
        worst = mpf(0)
        for ya, yb in zip(a, b):
            scale = mpmath.sqrt(sum(v * v for v in yb[:3]))
            worst = max([worst] + [abs(ya[d] - yb[d]) / scale for d in range(3)]
                        + [abs(ya[d] - yb[d]) for d in range(3, 7)])
        digits = -mpmath.log10(worst) if worst > 0 else mpf(60)
        unit = max(abs(sum(v * v for v in yb[3:]) - 1) for yb in b)
        lines.append(f"{name}: A(odefun, dps 40, {ta:.0f} s) vs B(Gauss 8 stages, dps 60, "
                     f"{tb:.0f} s): {float(digits):.1f} digits; B's |q|^2 - 1: {mpmath.nstr(unit, 3)}")
        if digits < AGREE_DIGITS or unit > mpf("1e-40"):
            ok = False
        _, _, q0n, sp = setup(SCENES[si])
        out.append({
            "name": name, "inertia": [mpmath.nstr(num(v), NDIG) for v in I],
            "m0": [mpmath.nstr(num(v), NDIG) for v in m0],
            "q0": [mpmath.nstr(v, NDIG) for v in q0n],
            "spec": {k: v for k, v in spec.items()},
            "agreement_digits": round(float(digits), 1),
            "states": [{"t": T, "m": [mpmath.nstr(v, NDIG) for v in yb[:3]],
                        "q": [mpmath.nstr(v, NDIG) for v in yb[3:]]} for T, yb in zip(TIMES, b)],
        })
    meta = {"generator": "lab/refs/make_forced_refs.py", "runs": RUNS,
            "equations": "m' = m x I^-1 (m - h_r) + tau(t, q); q' = 1/2 q (x) (0, I^-1 (m - h_r))"}
    with open("forced_refs.json", "w") as f:
        json.dump({"meta": meta, "scenes": out}, f, indent=1)
    with open("forced_refs.txt", "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    if not ok:
        sys.exit(f"the two integrators disagree (fewer than {AGREE_DIGITS} digits) or |q| drifted")


if __name__ == "__main__":
    main()
