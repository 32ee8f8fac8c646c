#!/usr/bin/env python3
"""High-precision reference solutions of the forced rigid body  ->  forced_refs.json, forced_refs.txt

Integrates, for each scene (I, m0, q0, torque, rotor), the 7-dimensional system of
src/forced.rs's module docs
    m'  = m x Omega + tau(t, q),     Omega = I^-1 (m - h_r)          (body frame)
    q'  = 1/2 q (x) (0, Omega)       Hamilton product, q = (w,x,y,z) maps body -> space
with the body-frame torques of src/torque.rs, written here from their definitions
(not from the Rust code), with R(q) v = q (0, v) q*:
    gravity (heavy top)  tau = MG (Gamma x chi),  Gamma = R(q)^T e_z
                         (potential MG <R(q) chi, e_z>)
    gravity gradient     tau = 3K (r x I r),      r = R(q)^T (cos N t, sin N t, 0)
                         (potential 3K/2 r . I r)
    body torque          tau_i = A_i cos(W_i t + P_i)
and reports m(t), q(t) at t = 1, 2, 5, 10.

Two independent integrators are run (2 processes):
  A  mpmath.odefun (mpmath's Taylor-series solver), mp.dps = 40, degree 40.
  B  own Gauss-Legendre collocation, s = 10 stages (order 20, A-stable, conserves |q|^2
     exactly), mp.dps = 45, stage equations by fixed-point iteration to 1e-43, fixed step
     h = 1/10 (run B1) and h = 1/20 (run B2). Richardson check: |B1 - B2| estimates the
     error of B1; the error of B2 is 2^20 times smaller.
Stored values are those of run B2, written with 34 significant digits.

The script asserts: A vs B2 agree to >= 25 digits and B1 vs B2 to >= 28 digits (max abs
difference of m / max(1, |m0|) and of q, over all stored times), per scene; it also reports
the conserved quantities where the scene has them (heavy top: e_z . R(q) m and the total
energy; gyrostat: |m|^2, R(q) m and the energy 1/2 (m - h_r) . I^-1 (m - h_r); gravity
gradient, whose potential turns about e_z at the orbit rate N: the Jacobi integral
1/2 (m - h_r) . I^-1 (m - h_r) + V(t, q) - N e_z . R(q) m; |q| = 1). These certify that each
torque is the one of its potential, with the sign and frame of src/torque.rs's docs.

Inputs given as decimals are converted exactly (fractions.Fraction) and then rounded once
at the working precision; q0 is normalised at the working precision. The talk's body is
I_i = J_j + J_k with J = (0.9218, 0.7382, 0.1763), done exactly.

Usage:  python3 make_forced_refs.py      (needs mpmath; 5.5 min on 2 cores without gmpy2)
"""
import json, time
from fractions import Fraction as Fr
from multiprocessing import Pool
import mpmath
from mpmath import mp, mpf

TIMES = [1, 2, 5, 10]
NDIG = 34
_J = [Fr(s) for s in ["0.9218", "0.7382", "0.1763"]]
TALK_I = [str(_J[1] + _J[2]), str(_J[0] + _J[2]), str(_J[0] + _J[1])]
TALK_M0 = ["0.4165", "0.9072", "0.0588"]
ID = ["1", "0", "0", "0"]
GG = dict(k="1", n="1")
PERIODIC = dict(amplitude=["0.1", "-0.05", "0.08"], freq=["1.3", "0.7", "2.1"], phase=["0", "0.5", "1"])
# name, I, m0, q0, forcing (rotor, gravity (mg, com), gravity_gradient (k, n), body_torque)
SCENES = [
    ("heavy_top", ["1", "1.5", "2"], ["0.3", "-0.6", "1.1"],
     ["0.9238795325112867", "0.3826834323650898", "0", "0"],
     dict(gravity=dict(mg="1", com=["0.2", "-0.1", "0.5"]))),
    ("lagrange_top", ["2", "2", "1"], ["0.1", "-0.2", "4"], ["cos15", "sin15", "0", "0"],
     dict(gravity=dict(mg="1", com=["0", "0", "0.5"]))),
    ("gravity_gradient", ["1.2", "1.5", "1.9"], ["0.1", "1.2", "-0.2"], ID,
     dict(gravity_gradient=GG)),
    ("body_torque", TALK_I, TALK_M0, ID, dict(body_torque=PERIODIC)),
    ("gyrostat", TALK_I, TALK_M0, ID, dict(rotor=["0.2", "-0.1", "0.3"])),
    ("satellite", ["1.2", "1.5", "1.9"], ["0.1", "1.2", "-0.2"], ID,
     dict(gravity_gradient=GG, rotor=["0", "0.3", "0"])),
]
RUNS = {"A": dict(dps=40, method="odefun", degree=40),
        "B1": dict(dps=45, method="gauss-legendre", stages=10, h="1/10", tol="1e-43"),
        "B2": dict(dps=45, method="gauss-legendre", stages=10, h="1/20", tol="1e-43")}


def mpq(x):  # exact rational / decimal string -> mpf at the current precision
    if x == "cos15":
        return mpmath.cos(mpmath.pi / 12)
    if x == "sin15":
        return mpmath.sin(mpmath.pi / 12)
    x = Fr(x)
    return mpf(x.numerator) / x.denominator


def qmul(p, q):
    return [p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
            p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
            p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
            p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0]]


def conj(q):
    return [q[0], -q[1], -q[2], -q[3]]


def rotate(q, v):  # R(q) v = q (0,v) q*   (body -> space)
    return qmul(qmul(q, [0] + list(v)), conj(q))[1:]


def unrotate(q, v):  # R(q)^T v = q* (0,v) q   (space -> body)
    return qmul(qmul(conj(q), [0] + list(v)), q)[1:]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


class Scene:
    """A scene's data at the current working precision."""

    def __init__(self, spec):
        self.name, I, m0, q0, f = spec
        self.I = [mpq(v) for v in I]
        self.m0 = [mpq(v) for v in m0]
        q0 = [mpq(v) for v in q0]
        nq = mpmath.sqrt(mpmath.fsum(v * v for v in q0))
        self.q0 = [v / nq for v in q0]
        self.rotor = [mpq(v) for v in f.get("rotor", ["0", "0", "0"])]
        g = f.get("gravity")
        self.gravity = (mpq(g["mg"]), [mpq(v) for v in g["com"]]) if g else None
        g = f.get("gravity_gradient")
        self.gg = (mpq(g["k"]), mpq(g["n"])) if g else None
        p = f.get("body_torque")
        self.periodic = tuple([mpq(v) for v in p[k]] for k in ("amplitude", "freq", "phase")) if p else None

    def torque(self, t, q):
        tau = [mpf(0)] * 3
        if self.gravity:
            mg, chi = self.gravity
            gamma = unrotate(q, [0, 0, 1])
            tau = [a + mg * b for a, b in zip(tau, cross(gamma, chi))]
        if self.gg:
            k, n = self.gg
            r = unrotate(q, [mpmath.cos(n * t), mpmath.sin(n * t), 0])
            ir = [a * b for a, b in zip(self.I, r)]
            tau = [a + 3 * k * b for a, b in zip(tau, cross(r, ir))]
        if self.periodic:
            A, W, P = self.periodic
            tau = [a + A[i] * mpmath.cos(W[i] * t + P[i]) for i, a in enumerate(tau)]
        return tau

    def potential(self, t, q):
        v = mpf(0)
        if self.periodic:
            return None
        if self.gravity:
            mg, chi = self.gravity
            v += mg * rotate(q, chi)[2]
        if self.gg:
            k, n = self.gg
            r = unrotate(q, [mpmath.cos(n * t), mpmath.sin(n * t), 0])
            v += 3 * k / 2 * mpmath.fsum(a * b * b for a, b in zip(self.I, r))
        return v

    def rhs(self, t, y):
        m, q = y[:3], y[3:]
        om = [(m[i] - self.rotor[i]) / self.I[i] for i in range(3)]
        mdot = [a + b for a, b in zip(cross(m, om), self.torque(t, q))]
        qdot = [v / 2 for v in qmul(q, [0] + om)]
        return mdot + qdot


def gauss_legendre(s):
    """Butcher tableau (A, b, c) of the s-stage Gauss-Legendre method at the working precision."""
    with mp.workdps(mp.dps + 30):
        x = []
        for i in range(s):  # Newton on P_s from the usual asymptotic guesses
            z = mpmath.cos(mpmath.pi * (i + mpf(3) / 4) / (s + mpf(1) / 2))
            for _ in range(100):
                p0, p1 = mpf(1), z  # P_0, P_1 -> P_{s-1}, P_s by the three-term recurrence
                for k in range(2, s + 1):
                    p0, p1 = p1, ((2 * k - 1) * z * p1 - (k - 1) * p0) / k
                dz = p1 / (s * (z * p1 - p0) / (z * z - 1))
                z -= dz
                if abs(dz) < mpf(10) ** (-mp.dps + 3):
                    break
            x.append(z)
        assert all(abs(a - b) > mpf("1e-3") for i, a in enumerate(x) for b in x[:i]), "distinct nodes"
        c = sorted((1 + v) / 2 for v in x)
        V = mpmath.matrix([[c[j] ** k for j in range(s)] for k in range(s)])  # V[k][j] = c_j^k
        b = mpmath.lu_solve(V, mpmath.matrix([mpf(1) / (k + 1) for k in range(s)]))
        A = []
        for i in range(s):
            a = mpmath.lu_solve(V, mpmath.matrix([c[i] ** (k + 1) / (k + 1) for k in range(s)]))
            A.append([+a[j] for j in range(s)])
        return A, [+b[j] for j in range(s)], [+v for v in c]


def run_gl(sc, times, s, h, tol):
    A, b, c = gauss_legendre(s)
    n, y, out, iters = 0, list(sc.m0) + list(sc.q0), [], 0
    K = None
    for T in times:
        nT = int(mpmath.nint(T / h))
        assert abs(nT * h - T) < mpf(10) ** (-mp.dps + 5)
        while n < nT:
            t = n * h
            if K is None:
                K = [sc.rhs(t, y)] * s
            for it in range(200):
                Y = [[y[k] + h * mp.fdot(A[i], [Kj[k] for Kj in K]) for k in range(7)] for i in range(s)]
                Kn = [sc.rhs(t + c[i] * h, Y[i]) for i in range(s)]
                d = max(abs(a - bb) for Ki, Kni in zip(K, Kn) for a, bb in zip(Ki, Kni))
                K = Kn
                if d * h < tol:
                    break
            else:
                raise RuntimeError("stage iteration does not converge")
            iters += it + 1
            y = [y[k] + h * mp.fdot(b, [Kj[k] for Kj in K]) for k in range(7)]
            n += 1  # the next step's stage iteration starts from this step's stage derivatives
        out.append(y)
    return out, iters


def task(args):
    si, run = args
    cfg = RUNS[run]
    mp.dps = cfg["dps"]
    sc = Scene(SCENES[si])
    t0 = time.time()
    info = ""
    if cfg["method"] == "odefun":
        F = mpmath.odefun(sc.rhs, 0, sc.m0 + sc.q0, degree=cfg["degree"])
        res = [F(T) for T in TIMES]
    else:
        res, iters = run_gl(sc, TIMES, cfg["stages"], mpq(cfg["h"]), mpf(cfg["tol"]))
        info = f"  ({iters} stage iterations)"
    return si, run, [[mpmath.nstr(v, 60) for v in y] for y in res], time.time() - t0, info


def lg(x):
    return float(-mpmath.log10(x)) if x else float("inf")


def main():
    T0 = time.time()
    tasks = [(si, r) for r in ("B2", "A", "B1") for si in range(len(SCENES))]
    res = {}
    with Pool(2) as pool:
        for si, run, ys, dt, info in pool.imap_unordered(task, tasks):
            res[si, run] = ys
            print(f"  {SCENES[si][0]:16s} run {run:2s} {dt:7.1f} s{info}", flush=True)
    mp.dps = 45
    out, lines, summary = [], [], {}
    lines.append(__doc__.strip().splitlines()[0])
    failed = []
    for si, spec in enumerate(SCENES):
        sc = Scene(spec)
        name = sc.name
        Y = {r: [[mpf(v) for v in y] for y in res[si, r]] for r in RUNS}
        msc = max(1, mpmath.sqrt(mpmath.fsum(v * v for v in sc.m0)))
        agree = {}
        for r in ("A", "B1"):
            agree[r] = max(abs(a - b) / (msc if k < 3 else 1)
                           for ya, yb in zip(Y[r], Y["B2"]) for k, (a, b) in enumerate(zip(ya, yb)))
        inv = {}

        def track(key, f):
            v0 = f(0, sc.m0, sc.q0)
            inv[key] = max(abs(f(T, y[:3], y[3:]) - v0) / max(1, abs(v0)) for T, y in zip(TIMES, Y["B2"]))

        track("|q|", lambda t, m, q: mpmath.fsum(v * v for v in q))
        if sc.gravity and not sc.gg and not sc.periodic:
            track("e_z.R(q)m", lambda t, m, q: rotate(q, m)[2])
        if not sc.gravity and not sc.gg and not sc.periodic:
            track("|m|^2", lambda t, m, q: mpmath.fsum(v * v for v in m))
            for k in range(3):
                track(f"(R(q)m)_{k}", lambda t, m, q, k=k: rotate(q, m)[k])
        if sc.gg and not sc.periodic and not sc.gravity:
            # the potential turns about e_z at rate N: the Jacobi integral H - N e_z . R(q) m
            track("jacobi", lambda t, m, q: mpmath.fsum((m[i] - sc.rotor[i]) ** 2 / sc.I[i] for i in range(3)) / 2
                  + sc.potential(t, q) - sc.gg[1] * rotate(q, m)[2])
        if not sc.periodic and not sc.gg:
            track("energy", lambda t, m, q: mpmath.fsum((m[i] - sc.rotor[i]) ** 2 / sc.I[i] for i in range(3)) / 2
                  + sc.potential(t, q))
        lines.append(f"\n[{name}]  I={[mpmath.nstr(v, 20) for v in sc.I]}  m0={[mpmath.nstr(v, 20) for v in sc.m0]}"
                     f"  forcing={spec[4]}")
        if inv:
            lines.append("  conservation in run B2, -log10 rel. error: "
                         + "  ".join(f"{k}:{lg(v):.1f}" for k, v in inv.items()))
        lines.append(f"  agreement digits (max abs diff, m/max(1,|m0|), q):  A(odefun) vs B2: {lg(agree['A']):.1f}"
                     f"   B1(h=1/10) vs B2(h=1/20): {lg(agree['B1']):.1f}")
        summary[name] = (lg(agree["A"]), lg(agree["B1"]), min([lg(v) for v in inv.values()] or [float("inf")]))
        if lg(agree["A"]) < 25 or lg(agree["B1"]) < 28:
            failed.append(name)
        for i, T in enumerate(TIMES):
            lines.append(f"  t={T:<3d} m = " + " ".join(mpmath.nstr(v, NDIG) for v in Y["B2"][i][:3]))
            lines.append("        q = " + " ".join(mpmath.nstr(v, NDIG) for v in Y["B2"][i][3:]))
        s = lambda v, n=NDIG: mpmath.nstr(v, n, min_fixed=-mpmath.inf, max_fixed=mpmath.inf)
        f = spec[4]
        forcing = {"rotor": f.get("rotor"), "gravity": f.get("gravity"),
                   "gravity_gradient": f.get("gravity_gradient"), "body_torque": f.get("body_torque")}
        out.append({"name": name, "inertia": [s(v, 40) for v in sc.I], "m0": [s(v, 40) for v in sc.m0],
                    "q0": [s(v, 40) for v in sc.q0], "forcing": forcing, "t": TIMES,
                    "m": [[s(v) for v in y[:3]] for y in Y["B2"]], "q": [[s(v) for v in y[3:]] for y in Y["B2"]]})
    meta = {"generator": "make_forced_refs.py", "mpmath": mpmath.__version__, "backend": mpmath.libmp.BACKEND,
            "runs": RUNS, "stored_run": "B2",
            "conventions": "m' = m x Omega + tau(t,q), Omega = I^-1 (m - h_r); q' = 1/2 q*(0,Omega); "
                           "gravity tau = mg (R(q)^T e_z) x com; gravity gradient tau = 3k r x I r, "
                           "r = R(q)^T (cos n t, sin n t, 0); body torque tau_i = A_i cos(W_i t + P_i)"}
    with open("forced_refs.json", "w") as fh:
        json.dump({"meta": meta, "scenes": out}, fh, indent=1)
    lines.append("\nsummary (agreement digits A-B2, B1-B2; min conservation digits in B2):")
    for k, v in summary.items():
        lines.append(f"  {k:16s} {v[0]:6.1f} {v[1]:6.1f} {v[2]:6.1f}")
    lines.append(f"\ntotal wall time {time.time() - T0:.1f} s (backend {mpmath.libmp.BACKEND})")
    with open("forced_refs.txt", "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    assert not failed, f"integrators disagree on {failed}"


if __name__ == "__main__":
    main()
