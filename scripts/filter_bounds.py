#!/usr/bin/env python3
"""Derives the semi-static filter constants used in predicates/src/filters.h.

Model (Higham, "Accuracy and Stability of Numerical Algorithms", ch. 2; the same
forward analysis as Meyer & Pion's FPG and Geogram's PCK): IEEE-754 binary64, round
to nearest, u = 2^-53.  Every leaf is a rounded coordinate difference d~ = fl(p - q)
with |d~| <= M (M = max |d~| over the call) and |d~ - d| <= u |d~| <= u M.  For every
node we track (m, e): |computed| <= m M^deg and |computed - exact| <= e M^deg.
  sum:     m = (m1 + m2)(1 + u),   e = e1 + e2 + u (m1 + m2)
  product: m = m1 m2 (1 + u),      e = m1 e2 + (m2 + e2) e1 + u m1 m2
The filter returns sign(det~) when |det~| > E M^deg, where E bounds e at the root.
The bound itself is evaluated in floating point as fl(E * M * ... * M) with deg
multiplications, each rounding down by at most a factor (1 - u), so the constant we
store is E (1 + u)^(deg + 1) rounded up to 3 significant digits.  Underflow and
overflow are excluded by the range check on M done in the filter (see filters.h).
Run: python3 scripts/filter_bounds.py
"""
from fractions import Fraction as Fr
import math

u = Fr(1, 2**53)

def leaf():
    return (Fr(1), u)

def add(a, b):
    (m1, e1), (m2, e2) = a, b
    return ((m1 + m2) * (1 + u), e1 + e2 + u * (m1 + m2))

def mul(a, b):
    (m1, e1), (m2, e2) = a, b
    return (m1 * m2 * (1 + u), m1 * e2 + (m2 + e2) * e1 + u * m1 * m2)

sub = add  # same bounds

def orient2d():
    d = leaf()
    return sub(mul(d, d), mul(d, d)), 2

def minor2():
    d = leaf()
    return sub(mul(d, d), mul(d, d))

def orient3d():
    d = leaf()
    m = minor2()
    t = mul(d, m)
    return add(add(t, t), t), 3

def incircle():
    d = leaf()
    lift = add(mul(d, d), mul(d, d))
    t = mul(lift, minor2())
    return add(add(t, t), t), 4

def insphere():
    d = leaf()
    m2 = minor2()
    m3 = add(sub(mul(d, m2), mul(d, m2)), mul(d, m2))
    lift = add(add(mul(d, d), mul(d, d)), mul(d, d))
    t = mul(lift, m3)
    return add(sub(t, t), sub(t, t)), 5

def compare_distance3d():
    d = leaf()
    sq = add(add(mul(d, d), mul(d, d)), mul(d, d))
    return sub(sq, sq), 2

def compare_distance2d():
    d = leaf()
    sq = add(mul(d, d), mul(d, d))
    return sub(sq, sq), 2

for name, f in [("orient2d", orient2d), ("orient3d", orient3d),
                ("incircle", incircle), ("insphere", insphere),
                ("compare_distance2d", compare_distance2d),
                ("compare_distance3d", compare_distance3d)]:
    (m, e), deg = f()
    stored = e * (1 + u) ** (deg + 1)
    # round up to 3 significant digits
    x = float(stored)
    exp10 = math.floor(math.log10(x))
    mant = math.ceil(x / 10**exp10 * 100) / 100
    print(f"{name:18s} deg {deg}  E = {float(e):.6e} = {float(e/u):.4f} u"
          f"   store {mant:.2f}e{exp10}   max |det~| <= {float(m):.3f} M^{deg}")

# Dynamic bounds of the 2D bisector predicates (predicates/src/bisector2d.h): the filter
# computes, beside each value, its magnitude mag~ (the same polynomial on absolute values of
# the rounded leaves) and decides when |value~| > K mag~. With k the number of roundings on
# a monomial's path (leaf difference 1, sum 1 + k(operand), product 1 + k(l) + k(r)),
# |value~ - value| <= gamma_k mag; mag~ loses a factor (1 + u) per rounding of its own
# evaluation (kmag) and the exact leaves exceed the rounded ones by at most 1 / (1 - u)
# each (deg of them); two more roundings: K * mag~ and one to spare. Underflow is kept
# below 2^-73 mag by the filter's test mag >= 2^-1000 (1 + S), inside the slack.
def gamma(k):
    return k * u / (1 - k * u)

def round_up_3(x):
    exp10 = math.floor(math.log10(x))
    return math.ceil(x / 10**exp10 * 100) / 100 * 10**exp10

for name, k, kmag, deg in [("bisector N, A (deg 4)", 11, 7, 4),
                           ("bisector E (deg 2)", 4, 2, 2)]:
    need = gamma(k) * (1 + u) ** (kmag + 2) / (1 - u) ** deg
    stored = round_up_3(float(need))
    slack = (Fr(stored) - need) / need
    assert slack > Fr(1, 2**60)
    print(f"{name:18s} k {k:2d}  K = {float(need):.6e} = {float(need/u):.4f} u"
          f"   store {stored:.2e}   slack {float(slack) * 100:.2f} %")

# Norm-product bounds of the 3D bisector predicates (predicates/src/bisector3d.h): the
# filter decides when |value~| > K P~, P the product of the L-infinity norms of the
# rounded leaf vectors that bounds each of the `count` monomials of the expression tree.
# |value~ - value| <= gamma_k mag (k as above), mag <= count P / (1 - u)^deg (exact leaves
# against rounded ones), P <= P~ (1 + u)^r (r: the roundings of P's own evaluation, counted
# like k with exact leaves: the norms are maxima of absolute values), and two more
# roundings: K * P~ and one to spare.
for name, count, k, r, deg in [("edge N (deg 4)", 9, 13, 5, 4),
                               ("edge E_k (deg 2)", 3, 5, 1, 2),
                               ("facet N' (deg 6)", 54, 21, 9, 6),
                               ("facet m_1 (deg 4)", 18, 12, 3, 4)]:
    need = count * gamma(k) * (1 + u) ** (r + 2) / (1 - u) ** deg
    stored = round_up_3(float(need))
    slack = (Fr(stored) - need) / need
    assert slack > Fr(1, 2**60)
    print(f"{name:18s} k {k:2d}  K = {float(need):.6e} = {float(need/u):.4f} u"
          f"   store {stored:.2e}   slack {float(slack) * 100:.2f} %")

# Circumcenter predicates (predicates/src/circumcenter3d.h), the same norm-product model:
# P = n . (Nv - 2 D u) (deg 6), D (deg 3), and the circumcenter numerator Nv (deg 4) used
# by the enclosure (a bound on |Nv~ - Nv|, not a sign decision: it carries the same
# factors).
for name, count, k, r, deg in [("circumcenter P (deg 6)", 36, 20, 8, 6),
                               ("circumcenter D (deg 3)", 6, 8, 2, 3),
                               ("circumcenter Nv (deg 4)", 6, 12, 5, 4)]:
    need = count * gamma(k) * (1 + u) ** (r + 2) / (1 - u) ** deg
    stored = round_up_3(float(need))
    slack = (Fr(stored) - need) / need
    assert slack > Fr(1, 2**60)
    print(f"{name:18s} k {k:2d}  K = {float(need):.6e} = {float(need/u):.4f} u"
          f"   store {stored:.2e}   slack {float(slack) * 100:.2f} %")
