#!/usr/bin/env python3
"""High-precision reference solutions of the free rigid body  ->  refs.json, refs.txt

Integrates, for each scene (I, m0, q0), the 7-dimensional system
    m'  = m x Omega,             Omega = (m1/I1, m2/I2, m3/I3)      (Euler, body frame)
    q'  = 1/2 q (x) (0, Omega)   Hamilton product, q = (w,x,y,z) maps body -> space
and reports m(t), q(t) at t = 1, 10, 100.

Two independent integrators are run (in parallel, 2 processes):
  A  mpmath.odefun (mpmath's Taylor-series solver; Taylor coefficients from
     finite differences at very high internal precision), mp.dps = 40,
     degree 45 (default 63; 45 is ~2x faster, same accuracy).
  B  own Taylor-series integrator at mp.dps = 60: exact Taylor coefficients of the
     (bilinear) vector field from Cauchy-product recurrences, order 60, step size
     from the decay of the last two coefficients (Jorba-Zou rule, tail < 1e-58).
  C  same as B but mp.dps = 50, order 44, tail < 1e-48 (different steps/order).
Stored values are those of run B, written with 34 significant digits.

Accuracy is certified by (i) the agreement A vs B and C vs B (reported as
-log10 of the max abs difference, per scene; |m| normalised, |q| = 1), and
(ii) conservation in B of |m|^2, E = 1/2 sum m_i^2/I_i, pi = R(q) m and |q| = 1,
plus, for scene "talk", comparison with externally given 20-digit values of m.
Inputs given as decimals are converted exactly (fractions.Fraction) and then
rounded once at the working precision (talk: I_i = J_j + J_k done exactly).

Usage:  python3 make_refs.py          (needs mpmath; gmpy2 optional, ~3x faster)
"""
import json, sys, time
from fractions import Fraction as Fr
from multiprocessing import Pool
import mpmath
from mpmath import mp, mpf

TIMES = [1, 10, 100]
J_TALK = ["0.9218", "0.7382", "0.1763"]
_J = [Fr(s) for s in J_TALK]
SCENES = [  # name, I, m0, q0   (exact rationals / decimal strings)
    ("talk", [_J[1] + _J[2], _J[0] + _J[2], _J[0] + _J[1]], ["0.4165", "0.9072", "0.0588"], ["1", "0", "0", "0"]),
    ("hv", ["0.6", "0.8", "1.0"], ["1.8", "0.4", "-0.9"], ["1", "0", "0", "0"]),
    ("symmetric_top", ["1.0", "1.0", "2.0"], ["0.3", "0.4", "1.2"], ["1", "0", "0", "0"]),
    ("near_separatrix", ["1.0", "2.0", "3.0"], ["1e-3", "1.0", "1e-3"], ["1", "0", "0", "0"]),
    ("flat_plate", ["1.0", "2.0", "3.0"], ["0.6", "-0.5", "0.7"], ["1", "0", "0", "0"]),
    ("fast_spinner", ["2.0", "2.5", "4.0"], ["0.05", "-0.03", "40.0"], ["1", "0", "0", "0"]),
    ("sphere", ["1.5", "1.5", "1.5"], ["0.3", "-0.2", "0.9"], ["1", "0", "0", "0"]),
    ("asteroid", ["0.35", "0.9", "1.0"], ["0.6", "0.5", "0.45"],
     ["0.9238795325112867", "0.0", "0.3826834323650898", "0.0"]),
]
TALK_CHECK = {1: ["0.40963676823852457273", "0.91216486689156377454", "-0.0097213021655047406612"],
              10: ["0.82717281856790628525", "-0.096647426825883589630", "-0.55352139354352065378"],
              100: ["0.66653809997201721994", "0.62577581339461293974", "0.40505940632949599801"]}
RUNS = {"A": dict(dps=40, method="odefun", degree=45),
        "B": dict(dps=60, method="taylor", order=60, eps="1e-58"),
        "C": dict(dps=50, method="taylor", order=44, eps="1e-48")}
NDIG = 34


def mpq(x):  # exact rational / decimal string -> mpf at current precision
    x = Fr(x)
    return mpf(x.numerator) / x.denominator


def setup(scene):
    name, I, m0, q0 = scene
    I, m0, q0 = [mpq(v) for v in I], [mpq(v) for v in m0], [mpq(v) for v in q0]
    nq = mpmath.sqrt(mpmath.fsum(v * v for v in q0))
    return I, m0, [v / nq for v in q0]


def rhs(I, y):
    m1, m2, m3, w, x, yy, z = y
    a, b, c = m1 / I[0], m2 / I[1], m3 / I[2]
    return [m2 * c - m3 * b, m3 * a - m1 * c, m1 * b - m2 * a,
            (-x * a - yy * b - z * c) / 2, (w * a + yy * c - z * b) / 2,
            (w * b + z * a - x * c) / 2, (w * c + x * b - yy * a) / 2]


def taylor_step(I, y, N):
    """Taylor coefficients c[0..N] (each a 7-list) of the solution through y."""
    c = [list(y)]
    O = [[y[k] / I[k] for k in range(3)]]
    fd = mp.fdot
    for n in range(N):
        C, Om = c[:n + 1], O[n::-1]  # pairs (c[j], O[n-j])
        col = lambda k: [cj[k] for cj in C]
        ocol = lambda k: [o[k] for o in Om]
        M1, M2, M3, W, X, Y, Z = (col(k) for k in range(7))
        A, B, Cc = ocol(0), ocol(1), ocol(2)
        s = mpf(1) / (n + 1)
        h = s / 2
        new = [(fd(M2, Cc) - fd(M3, B)) * s, (fd(M3, A) - fd(M1, Cc)) * s, (fd(M1, B) - fd(M2, A)) * s,
               -fd(X + Y + Z, A + B + Cc) * h, fd(W + Y + Z, A + Cc + [-v for v in B]) * h,
               fd(W + Z + X, B + A + [-v for v in Cc]) * h, fd(W + X + Y, Cc + B + [-v for v in A]) * h]
        c.append(new)
        O.append([new[k] / I[k] for k in range(3)])
    return c


def run_taylor(I, y, times, N, eps):
    t, out = mpf(0), []
    scale = [max(1, max(abs(v) for v in y[:3])), mpf(1)]  # |m|, |q| are conserved
    for T in times:
        while t < T:
            c = taylor_step(I, y, N)
            h = mpf(10)
            for j in (N - 1, N):  # Jorba-Zou step size from the last two terms
                for g, (lo, hi) in enumerate(((0, 3), (3, 7))):
                    nrm = max(abs(v) for v in c[j][lo:hi])
                    if nrm:
                        h = min(h, (eps * scale[g] / nrm) ** (mpf(1) / j))
            h = min(h, T - t)
            y = [mpmath.polyval([cj[k] for cj in reversed(c)], h) for k in range(7)]
            t += h
        out.append(y)
    return out


def task(args):
    si, run = args
    cfg = RUNS[run]
    mp.dps = cfg["dps"]
    I, m0, q0 = setup(SCENES[si])
    t0 = time.time()
    if cfg["method"] == "odefun":
        F = mpmath.odefun(lambda t, y: rhs(I, y), 0, m0 + q0, degree=cfg["degree"])
        res = [F(T) for T in TIMES]
    else:
        res = run_taylor(I, m0 + q0, TIMES, cfg["order"], mpf(cfg["eps"]))
    return si, run, [[mpmath.nstr(v, 60) for v in y] for y in res], time.time() - t0


def qmul(p, q):
    return [p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
            p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
            p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
            p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0]]


def rotate(q, v):  # R(q) v = q (0,v) q*
    return qmul(qmul(q, [0] + list(v)), [q[0], -q[1], -q[2], -q[3]])[1:]


def lg(x):
    return float(-mpmath.log10(x)) if x else float("inf")


def main():
    T0 = time.time()
    tasks = [(si, r) for r in ("A", "B", "C") for si in range(len(SCENES))]
    tasks.sort(key=lambda a: (a[1] != "A", SCENES[a[0]][0] != "fast_spinner"))  # slowest first
    res = {}
    with Pool(2) as pool:
        for si, run, ys, dt in pool.imap_unordered(task, tasks):
            res[si, run] = ys
            print(f"  {SCENES[si][0]:16s} run {run}  {dt:7.1f} s", flush=True)
    mp.dps = 60
    out, lines, worst = [], [], {}
    lines.append(__doc__.strip().splitlines()[0])
    for si, scene in enumerate(SCENES):
        name = scene[0]
        I, m0, q0 = setup(scene)
        E0 = mpmath.fsum(m0[k] ** 2 / I[k] for k in range(3)) / 2
        C0 = mpmath.fsum(v * v for v in m0)
        pi0 = rotate(q0, m0)
        msc = mpmath.sqrt(C0)
        Y = {r: [[mpf(v) for v in y] for y in res[si, r]] for r in RUNS}
        inv = dict(E=0, C=0, pi=0, q=0)
        agree = dict(A=mpf(0), C=mpf(0))
        for i, y in enumerate(Y["B"]):
            m, q = y[:3], y[3:]
            inv["E"] = max(inv["E"], abs(mpmath.fsum(m[k] ** 2 / I[k] for k in range(3)) / 2 - E0) / E0)
            inv["C"] = max(inv["C"], abs(mpmath.fsum(v * v for v in m) - C0) / C0)
            inv["pi"] = max(inv["pi"], max(abs(a - b) for a, b in zip(rotate(q, m), pi0)) / msc)
            inv["q"] = max(inv["q"], abs(mpmath.fsum(v * v for v in q) - 1))
            for r in agree:
                d = [abs(a - b) / (msc if k < 3 else 1) for k, (a, b) in enumerate(zip(Y[r][i], y))]
                agree[r] = max(agree[r], max(d))
        lines.append(f"\n[{name}]  I={[mpmath.nstr(v, 20) for v in I]}  m0={[mpmath.nstr(v, 20) for v in m0]}")
        lines.append("  conservation in run B, -log10 rel. error: "
                     + "  ".join(f"{k}:{lg(v):.1f}" for k, v in inv.items()))
        lines.append(f"  agreement digits (max abs diff, m/|m|, q):  A(odefun,dps40) vs B: {lg(agree['A']):.1f}"
                     f"   C(taylor,dps50) vs B: {lg(agree['C']):.1f}")
        worst[name] = (min(lg(v) for v in inv.values()), lg(agree["A"]), lg(agree["C"]))
        for i, T in enumerate(TIMES):
            lines.append(f"  t={T:<4d} m = " + " ".join(mpmath.nstr(v, NDIG) for v in Y["B"][i][:3]))
            lines.append(f"         q = " + " ".join(mpmath.nstr(v, NDIG) for v in Y["B"][i][3:]))
        if name == "talk":
            for i, T in enumerate(TIMES):
                d = max(abs(a - mpf(b)) for a, b in zip(Y["B"][i][:3], TALK_CHECK[T]))
                lines.append(f"  talk check t={T}: max |m - given| = {mpmath.nstr(d, 3)}")
        s = lambda v, n=NDIG: mpmath.nstr(v, n, min_fixed=-mpmath.inf, max_fixed=mpmath.inf)
        entry = {"name": name, "inertia": [s(v, 40) for v in I], "m0": [s(v, 40) for v in m0],
                 "q0": [s(v, 40) for v in q0], "t": TIMES,
                 "m": [[s(v) for v in y[:3]] for y in Y["B"]], "q": [[s(v) for v in y[3:]] for y in Y["B"]],
                 "energy": s(E0, 40), "casimir": s(C0, 40)}
        if name == "talk":
            entry["mass_matrix_J"] = J_TALK
        out.append(entry)
    meta = {"generator": "make_refs.py", "mpmath": mpmath.__version__, "backend": mpmath.libmp.BACKEND,
            "runs": RUNS, "stored_run": "B", "conventions": "m' = m x Omega; q' = 1/2 q*(0,Omega); pi = R(q) m"}
    with open("refs.json", "w") as f:
        json.dump({"meta": meta, "scenes": out}, f, indent=1)
    lines.append("\nsummary (min conservation digits, agreement A-B digits, C-B digits):")
    for k, v in worst.items():
        lines.append(f"  {k:16s} {v[0]:6.1f} {v[1]:6.1f} {v[2]:6.1f}")
    lines.append(f"\ntotal wall time {time.time() - T0:.1f} s (backend {mpmath.libmp.BACKEND})")
    with open("refs.txt", "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
