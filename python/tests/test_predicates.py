"""The vectorised predicates against exact rational arithmetic (fractions.Fraction), on
random and on exactly degenerate input (where a floating-point determinant is unreliable)."""

from fractions import Fraction

import numpy as np
import pytest

import voroclip


def sign(x):
    return (x > 0) - (x < 0)


def det(m):
    m = [row[:] for row in m]
    n, d = len(m), Fraction(1)
    for c in range(n):
        p = next((r for r in range(c, n) if m[r][c] != 0), None)
        if p is None:
            return Fraction(0)
        if p != c:
            m[c], m[p] = m[p], m[c]
            d = -d
        d *= m[c][c]
        for r in range(c + 1, n):
            f = m[r][c] / m[c][c]
            for k in range(c, n):
                m[r][k] -= f * m[c][k]
    return d


def F(p):
    return [Fraction(float(x)) for x in p]


def ref_orient2d(a, b, c):
    a, b, c = F(a), F(b), F(c)
    return sign(det([[a[0] - c[0], a[1] - c[1]], [b[0] - c[0], b[1] - c[1]]]))


def ref_incircle(a, b, c, d):
    rows = []
    for p in (a, b, c):
        p, q = F(p), F(d)
        x, y = p[0] - q[0], p[1] - q[1]
        rows.append([x, y, x * x + y * y])
    return sign(det(rows))


def ref_orient3d(a, b, c, d):
    d = F(d)
    return sign(det([[x - y for x, y in zip(F(p), d)] for p in (a, b, c)]))


def ref_insphere(a, b, c, d, e):
    e = F(e)
    rows = []
    for p in (a, b, c, d):
        v = [x - y for x, y in zip(F(p), e)]
        rows.append(v + [sum(x * x for x in v)])
    return sign(det(rows))


def near_degenerate(rng, n, k, dim):
    # k points per row on a common line / circle / plane / sphere, rounded to doubles, then
    # nudged by an ulp or not: the signs the float determinants get wrong.
    base = rng.random((n, dim))
    pts = [base]
    for _ in range(k - 1):
        t = rng.random((n, 1))
        pts.append(base + t * (rng.random((1, dim)) - 0.5))
    return [np.nextafter(p, p + rng.integers(-1, 2, p.shape)) for p in pts]


@pytest.mark.parametrize("name,dim,nargs,ref", [
    ("orient2d", 2, 3, ref_orient2d), ("incircle", 2, 4, ref_incircle),
    ("orient3d", 3, 4, ref_orient3d), ("insphere", 3, 5, ref_insphere),
])
def test_predicates_match_exact_arithmetic(name, dim, nargs, ref):
    rng = np.random.default_rng(5)
    f = getattr(voroclip, name)
    args = [rng.random((300, dim)) for _ in range(nargs)]
    out = f(*args)
    assert out.dtype == np.int8 and out.shape == (300,)
    assert out.tolist() == [ref(*(a[i] for a in args)) for i in range(300)]
    # Integer points: many exact zeros.
    args = [rng.integers(0, 3, (300, dim)).astype(float) for _ in range(nargs)]
    out = f(*args)
    expected = [ref(*(a[i] for a in args)) for i in range(300)]
    assert out.tolist() == expected and 0 in expected
    # Collinear / coplanar points, then moved by an ulp.
    if name in ("orient2d", "orient3d"):
        args = near_degenerate(rng, 300, nargs, dim)
        assert f(*args).tolist() == [ref(*(a[i] for a in args)) for i in range(300)]


def test_broadcast_one_point():
    rng = np.random.default_rng(2)
    b = rng.random((50, 2))
    c = rng.random((50, 2))
    a = np.array([0.5, 0.5])
    assert voroclip.orient2d(a, b, c).tolist() == [ref_orient2d(a, b[i], c[i]) for i in range(50)]


def test_bad_shapes_and_nan():
    with pytest.raises(voroclip.Error, match=r"b: expected an \(n, 2\) array"):
        voroclip.orient2d(np.zeros((3, 2)), np.zeros((3, 3)), np.zeros((3, 2)))
    with pytest.raises(voroclip.Error, match="3 points, the other arguments have 4"):
        voroclip.orient2d(np.zeros((4, 2)), np.zeros((3, 2)), np.zeros((4, 2)))
    with pytest.raises(voroclip.Error, match="not a finite number"):
        voroclip.orient3d(np.zeros((2, 3)), np.ones((2, 3)), np.full((2, 3), np.nan),
                          np.zeros((2, 3)))
