"""The table of src/mv_pre_series.rs: Hairer and Vilmart's series for the modified moments
(docs/MATH.md §5) re-expanded in the variables that do not cancel on a rod.

The series `s(C, H)`, `d(C, H)` (degrees 1 to 4) is taken as in src/mv_pre.rs's former
table and docs/MATH.md §5, with the moments scaled so that the largest is 1. Substituting
`H = X + C` (`X = H - C / I_max`) and expanding gives the coefficient of `X^j C^(k-j)` as a
rational function of the moments; each is factored, and the numerator is written as a
polynomial in `e = I_min` and `dl = 1 - I_mid` (with `I_max = 1`), the denominator as
`K e^k I_mid^k`. A valid body has `0 <= dl <= e <= 1`, and every numerator's monomials have
total degree at least `k - j`, so the terms are of one size and do not cancel.

The check at the end evaluates every term in floating point from the table and compares it
with the original series in 50-digit arithmetic on rods, flat bodies and ordinary bodies.

Usage:  python3 make_series_table.py > /tmp/table.rs   (needs sympy and mpmath; a few seconds)
"""
import sys
from math import comb

import mpmath as mp
import sympy as sp

i1, i2, i3 = sp.symbols("i1 i2 i3", positive=True)
e, dl = sp.symbols("e dl")


def original(i1, i2, i3):
    """The series' coefficients in C and H: S[k-1][a] multiplies H^(k-a) C^a (likewise D)."""
    d = i1 * i2 * i3
    sig = lambda k: i1**k + i2**k + i3**k
    tau = lambda b, c: (i2**b + i3**b) / i1**c + (i3**b + i1**b) / i2**c + (i1**b + i2**b) / i3**c
    s1, s2, s3_, s4 = sig(1), sig(2), sig(3), sig(4)
    sm1, sm2, sm3, sm4 = sig(-1), sig(-2), sig(-3), sig(-4)
    t11, t21, t12 = tau(1, 1), tau(2, 1), tau(1, 2)
    t31, t22, t13 = tau(3, 1), tau(2, 2), tau(1, 3)
    d2, d3, d4 = d * d, d * d * d, d * d * d * d
    S = [[-sm1 / 3, s1 / (6 * d)],
         [(3 * s1 + 2 * d * sm2) / (60 * d), (1 - t11) / (30 * d), (s2 - d * sm1) / (30 * d2)],
         [(15 - d * sm3 - 2 * t11) / (630 * d), (53 * s2 + (6 * t12 - 100 * sm1) * d) / (2520 * d2),
          (9 * s1 + 10 * d * sm2 - 6 * t21) / (420 * d2), (4 * d + 17 * s3_ - 15 * d * t11) / (2520 * d3)],
         [(2 * d2 * sm4 + 5 * d * t12 - 171 * d * sm1 + 159 * s2) / (45360 * d2),
          (137 * d * sm2 - d * t13 + 3 * s1 - 69 * t21) / (11340 * d2),
          (26 * d * t22 + 55 * s3_ + 204 * d - 50 * d2 * sm3 - 59 * d * t11) / (7560 * d3),
          (-77 * t31 + 75 * d * t12 + 214 * s2 - 240 * d * sm1) / (22680 * d3),
          (62 * s4 - 94 * d * t21 + 66 * d2 * sm2 + 81 * d * s1) / (45360 * d4)]]
    D = [[s1 / (6 * d), -1 / (3 * d)],
         [-(9 + t11) / (60 * d), (6 * d * sm1 - s2) / (60 * d2), -s1 / (60 * d2)],
         [(9 * d * sm1 + d * t12 - 11 * s2) / (1260 * d2), (47 * s1 + 13 * t21 - 38 * d * sm2) / (2520 * d2),
          (s3_ + 2 * d * t11 - 85 * d) / (1260 * d3), (34 * d * sm1 - 19 * s2) / (2520 * d3)],
         [(165 * s1 - d * t13 - 9 * t21 - 145 * d * sm2) / (45360 * d2),
          (67 * s3_ - 735 * d - 15 * d * t22 + 87 * d * t11 + 34 * d2 * sm3) / (22680 * d3),
          (125 * d * sm1 - 5 * t31 - 130 * s2 + 4 * d * t12) / (7560 * d3),
          (54 * d * s1 - s4 + 218 * d * t21 - 426 * d2 * sm2) / (45360 * d4),
          (60 * d * t11 - 61 * s3_ - 247 * d) / (45360 * d4)]]
    return S, D


def table():
    S, D = original(i1, i2, i3)
    rows, dens = [], {}
    for fam, Q in ((0, S), (1, D)):
        for k in range(1, 5):
            for j in range(k + 1):  # power of X
                expr = sum(Q[k - 1][a] * comb(k - a, j) for a in range(k - j + 1))
                num, den = sp.fraction(sp.factor(sp.together(expr)))
                sub = {i1: e, i2: 1 - dl, i3: 1}
                N = sp.Poly(sp.expand(num.subs(sub)), e, dl)
                K = sp.simplify(sp.expand(den.subs(sub)) / (e**k * (1 - dl) ** k))
                assert K.is_number
                a = k - j  # power of C
                dens[(fam, k, a)] = int(K)
                for (p, q), c in N.terms():
                    assert c.is_integer and p + q >= a
                    rows.append((fam, k, a, p, q, int(c)))
    rows.sort()
    return rows, dens


def check(rows, dens):
    mp.mp.dps = 50
    cases = [((1e-7, 1, 1), 0.05, (3e-8, -0.6, 1.1)), ((1e-5, 1, 1), 0.05, (3e-6, -0.6, 1.1)),
             ((1e-6, 1, 1 + 1e-6), 0.05, (3e-7, -0.6, 1.1)), ((1e-6, 1 - 1e-6, 1), 0.05, (3e-7, -0.6, 1.1)),
             ((0.9145, 1.0981, 1.66), 0.25, (0.4165, 0.9072, 0.0588)),
             ((58.8396, 95.4957, 120.6647), 0.1, (3, 40, 12)), ((1, 1, 1), 0.1, (1, 2, 3)),
             ((1, 2, 3), 0.2, (1, -1, 1))]
    worst = 0.0
    for I, h, m in cases:
        kap = max(I)
        srt = sorted(I)
        lo, mid, dlt = srt[0] / kap, srt[1] / kap, (kap - srt[1]) / kap
        num = {}
        for fam, k, a, p, q, c in rows:
            num[(fam, k, a)] = num.get((fam, k, a), 0.0) + c * lo**p * dlt**q
        T = {key: v / (dens[key] * (lo * mid) ** key[1]) for key, v in num.items()}
        u = [(x * h / kap) ** 2 for x in m]
        C, X = sum(u) / 2, sum(u[i] * (kap - I[i]) / I[i] for i in range(3)) / 2
        Ie = [mp.mpf(x) / kap for x in I]
        S, D = original(*Ie)
        ue = [(mp.mpf(x) * mp.mpf(h) / kap) ** 2 for x in m]
        Ce, He = sum(ue) / 2, sum(ue[i] / Ie[i] for i in range(3)) / 2
        for fam, Q in ((0, S), (1, D)):
            for k in range(1, 5):
                exact = sum(Q[k - 1][a] * He ** (k - a) * Ce**a for a in range(k + 1))
                mine = sum(T[(fam, k, a)] * C**a * X ** (k - a) for a in range(k + 1))
                worst = max(worst, abs(float((mine - exact) / exact)))
    return worst


if __name__ == "__main__":
    rows, dens = table()
    worst = check(rows, dens)
    print(f"{len(rows)} rows; worst relative error of a term over the check cases: {worst:.2e}",
          file=sys.stderr)
    print(f"const ROWS: [(u8, u8, u8, u8, u8, i16); {len(rows)}] = [")
    for r in rows:
        print("    (%d, %d, %d, %d, %d, %d)," % r)
    print("];")
    print("const DENOMINATORS: [[[i32; 5]; 4]; 2] = [")
    for fam in (0, 1):
        print("    [")
        for k in range(1, 5):
            vals = [dens[(fam, k, a)] for a in range(k + 1)] + [1] * (4 - k)
            print("        [%s]," % ", ".join(str(v) for v in vals))
        print("    ],")
    print("];")
