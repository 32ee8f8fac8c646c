"""References for Carlson's R_C and R_J at ratios far from one, and Legendre's Pi at large
negative characteristic (tests/elliptic.rs).

Every input is an f32 value (so one table checks both precisions); each reference is mpmath's
value at 40 digits, written with 20 significant digits. Run: python3 lab/refs/make_carlson_refs.py
"""
import random
import struct

import mpmath as mp

mp.mp.dps = 40
random.seed(20261127)


def f32(x):
    return struct.unpack('f', struct.pack('f', x))[0]


def log_uniform(lo, hi):
    return f32(10 ** random.uniform(lo, hi))


rows = []
# R_C(x, y): x / y from 1e-12 to 1e12, and within a few ulps of one
for decade in range(-12, 12):
    for _ in range(8):
        y = log_uniform(-2, 2)
        x = f32(y * 10 ** (decade + random.random()))
        rows.append(('rc', [x, y], mp.elliprc(x, y)))
for k in (1, 2, 5, 100):
    for y in (0.3, 1.0, 7.0):
        y = f32(y)
        for x in (f32(y * (1 + k * 2.0**-23)), f32(y * (1 - k * 2.0**-23))):
            rows.append(('rc', [x, y], mp.elliprc(x, y)))
# R_J(x, y, z, p): p far below all three, far above, and between them (one above, two below)
for decade in range(-13, 13):
    for _ in range(6):
        x, y, z = (log_uniform(-1, 1) for _ in range(3))
        p = log_uniform(decade, decade + 1)
        rows.append(('rj', [x, y, z, p], mp.elliprj(x, y, z, p)))
for decade in range(1, 8):
    for _ in range(4):
        x, y = (log_uniform(decade, decade + 1) for _ in range(2))
        z = log_uniform(-decade - 1, -decade)
        p = log_uniform(-0.5, 0.5)
        rows.append(('rj', [x, y, z, p], mp.elliprj(x, y, z, p)))
        rows.append(('rj', [0.0, y, x, f32(z * 1e-3)], mp.elliprj(0, y, x, f32(z * 1e-3))))

# p out to 1e20 and down to 1e-30 times the others (past the duplication's old cap, f32's
# underflow of 4^-3n and the rounding of e to -1), and review's cases
for decade in list(range(13, 20)) + list(range(-30, -13, 2)):
    for _ in range(3):
        x, y, z = (log_uniform(-1, 1) for _ in range(3))
        p = log_uniform(decade, decade + 1)
        rows.append(('rj', [x, y, z, p], mp.elliprj(x, y, z, p)))
for args in ([0.7, 1.3, 2.1, 1e17], [0.7, 1.3, 2.1, 1e15], [1.0, 1.0, 1.0, 1e-15],
             [5.98e-10, 1e19, 3.43e7, 1e-30], [0.0, 1.0, 2.0, 1e18], [1e-20, 1.0, 3.0, 1e-25],
             # settling at subnormal products unscaled, and refused by a coarse scale
             [1e-30, 1.3e-30, 2.1e-30, 1e-10], [1e-30, 1.3e-30, 2.1e-30, 1.0],
             [1.0, 9.8e-45, 1.0, 5.6e-45], [1e-30, 1.0, 1.0, 1e30], [1e-30, 1e30, 1e30, 1.0],
             # all tiny: a scale larger than f32 has, capped
             [1e-25, 1e-25, 1e-25, 1e-25], [1e-30, 1.3e-30, 2.1e-30, 1e-16]):
    args = [f32(a) for a in args]
    rows.append(('rj', args, mp.elliprj(*args)))

# Pi(n; phi | m) at large negative n (the characteristic of the nearly symmetric body's
# attitude, crate::exact), where F and (n / 3) sin^3 phi R_J cancelled, and at n near one near
# pi / 2, where 1 - n sin^2 phi did; reference by quadrature
# of the defining integral (DLMF 19.2.7), split at the multiples of pi / 2
pi_rng = random.Random(20261128)


def pi_quad(n, phi, m):
    # the integrand peaks at the multiples of pi (width 1 / sqrt(-n)) and, for m near one,
    # at the odd multiples of pi / 2 (width sqrt(1 - m)): split there, geometrically
    with mp.workdps(60):
        n, phi, m = mp.mpf(n), mp.mpf(phi), mp.mpf(m)
        f = lambda t: 1 / ((1 - n * mp.sin(t) ** 2) * mp.sqrt(1 - m * mp.sin(t) ** 2))
        half = mp.pi / 2
        points = {mp.mpf(0), phi}
        widths = {0: 1 / mp.sqrt(-n) if n < 0 else mp.mpf(1),
                  1: min(mp.sqrt(1 - m), mp.sqrt(1 - n) if n > 0 else mp.mpf(1))}
        for k in range(-3, 4):
            centre = k * half
            w = widths[k % 2]
            points.add(centre)
            while w > 0 and w < 0.5:
                points.update((centre - w, centre + w))
                w *= 2
        lo, hi = min(0, phi), max(0, phi)
        ends = sorted(t for t in points if lo <= t <= hi)
        value = mp.quad(f, ends, maxdegree=12)
        value = value if phi >= 0 else -value
        # a second algorithm: mpmath's own Pi (Carlson's forms at 60 digits, where the
        # cancellation of F against the R_J term leaves 45 or more)
        other = mp.ellippi(n, phi, m)
        assert abs(value - other) <= mp.mpf(10) ** -30 * abs(value), (n, phi, m, value, other)
        return value


for decade in range(0, 21, 2):
    for _ in range(4):
        n = -f32(10 ** pi_rng.uniform(decade, decade + 1))
        phi = f32(pi_rng.uniform(-4.0, 4.0))
        m = f32(pi_rng.choice([0.0, pi_rng.uniform(0, 1), 1 - 10 ** pi_rng.uniform(-6, -1)]))
        rows.append(('pi', [n, phi, m], pi_quad(n, phi, m)))
for args in ([-1e6, 1.0, 0.5], [-3e5, 1.0, 0.5], [-2.0, 1.5707963, 0.9], [-1e20, 0.001, 0.3],
             # near pi / 2 with m near one, where 1 - m sin^2 phi cancelled (review)
             [-1e12, 1.5707962, 0.999999], [-1e16, 1.5707962, 0.9999999], [-1e8, 1.5707962, 0.9999999],
             [-1e5, 1.5706964, 0.999], [-3.0, 1.5707962, 0.9999999],
             # n near one near pi / 2, where 1 - n sin^2 phi cancelled (review)
             [0.9999999, 1.5707962, 0.9999999], [0.999, 1.5, 0.5], [0.5, 1.5707962, 0.99],
             [0.99999994, -1.5706, 0.3]):
    args = [f32(a) for a in args]
    rows.append(('pi', args, pi_quad(*args)))

with open('lab/refs/carlson_refs.txt', 'w') as out:
    out.write('# kind inputs... reference (mpmath, 40 digits; lab/refs/make_carlson_refs.py)\n')
    for kind, args, ref in rows:
        out.write(' '.join([kind] + [repr(a) for a in args] + [mp.nstr(ref, 20)]) + '\n')
print(len(rows), 'rows')
