"""The leg IK in plain Python: the reference `skills._kernels.solve_leg` follows line
for line (tests compare them bit for bit)."""

from __future__ import annotations

import math

import numpy as np

from models.geometry import wrap
from skills.ik import LIMIT_TOL
from skills.kinematics import LegGeometry


def solve_leg_py(g: LegGeometry, foot_pos, foot_rpy, target: str = "sole") -> tuple[np.ndarray, bool]:
    """`solve_leg` in Python: the reference the compiled one follows line for line."""
    r, p, y = foot_rpy.tolist() if isinstance(foot_rpy, np.ndarray) else map(float, foot_rpy)
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    # Foot orientation R = Rz(y) Ry(p) Rx(r), row-major.
    r00, r01, r02 = cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr
    r10, r11, r12 = sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr
    r20, r21, r22 = -sp, cp * sr, cp * cr

    (hipx, hipy, hipz), tilt, hx, hz, kx, kz, (ox, oy, oz), lo, up = g.consts
    lh2, lk2, den, q4_0, ct, st = g.derived
    px, py, pz = foot_pos.tolist() if isinstance(foot_pos, np.ndarray) else map(float, foot_pos)
    if target == "sole":
        px -= r00 * ox + r01 * oy + r02 * oz
        py -= r10 * ox + r11 * oy + r12 * oz
        pz -= r20 * ox + r21 * oy + r22 * oz
    elif target != "ankle":
        raise ValueError(f"target must be 'sole' or 'ankle', not {target!r}")
    # Hip -> ankle, then in the foot frame: u = R^T d.
    dx, dy, dz = px - hipx, py - hipy, pz - hipz
    ux = r00 * dx + r10 * dy + r20 * dz
    uy = r01 * dx + r11 * dy + r21 * dz
    uz = r02 * dx + r12 * dy + r22 * dz

    reachable = True
    L = math.sqrt(ux * ux + uy * uy + uz * uz)
    if L > g.reach_max or L < g.reach_min:
        reachable = False
        if L < 1e-12:  # no direction: put the ankle straight below the hip
            ux, uy, uz, L = 0.0, 0.0, -1.0, 1.0
        Lc = min(max(L, g.reach_min), g.reach_max)
        ux, uy, uz, L = ux * Lc / L, uy * Lc / L, uz * Lc / L, Lc

    # 1. Knee: |Ry(q4) h + k| = L. With psi(v) = atan2(v_x, -v_z) (angle from straight
    # down, forward positive), Ry(a) lowers psi by a.
    c = (L * L - lh2 - lk2) / den
    q4 = q4_0 - math.acos(min(1.0, max(-1.0, c)))

    # 2. Ankle: Rx(q6) u = Ry(q5) w, w = Ry(q4) h + k lies in the x-z plane.
    # Two roll branches put u in the x-z plane, below (z = -|u_yz|) or above the ankle;
    # take the one inside (or nearest) the ankle roll limits.
    q6 = math.atan2(-uy, -uz)
    ryz = math.hypot(uy, uz)
    q6b = (q6 + math.pi + math.pi) % (2.0 * math.pi) - math.pi  # _wrap, inline
    lo5, up5 = lo[5], up[5]
    if max(lo5 - q6b, q6b - up5, 0.0) < max(lo5 - q6, q6 - up5, 0.0):  # _excess, inline
        q6, ryz = q6b, -ryz
    c4, s4 = math.cos(q4), math.sin(q4)
    wx = c4 * hx + s4 * hz + kx
    wz = -s4 * hx + c4 * hz + kz
    q5 = wrap(math.atan2(wx, -wz) - math.atan2(ux, ryz))

    # 3. Hip: M = R Rx(-q6) Ry(q4 + q5) = R1(q1) Rx(q2) Ry(-q3); N = Rx(-tilt) M.
    c6, s6 = math.cos(q6), math.sin(q6)
    c45, s45 = math.cos(q4 + q5), math.sin(q4 + q5)
    # A = R Rx(-q6): columns a0 = R[:,0], a1 = c6 R[:,1] - s6 R[:,2], a2 = s6 R[:,1] + c6 R[:,2].
    a01, a02 = c6 * r01 - s6 * r02, s6 * r01 + c6 * r02
    a11, a12 = c6 * r11 - s6 * r12, s6 * r11 + c6 * r12
    a21, a22 = c6 * r21 - s6 * r22, s6 * r21 + c6 * r22
    # M = A Ry(q45): m0 = c a0 - s a2, m1 = a1, m2 = s a0 + c a2.
    m00, m01, m02 = c45 * r00 - s45 * a02, a01, s45 * r00 + c45 * a02
    m10, m11, m12 = c45 * r10 - s45 * a12, a11, s45 * r10 + c45 * a12
    m20, m21, m22 = c45 * r20 - s45 * a22, a21, s45 * r20 + c45 * a22
    # N = Rx(-tilt) M: row 0 unchanged; row1 = ct M1 + st M2; row2 = -st M1 + ct M2.
    n00, n02 = m00, m02
    n01 = m01
    n10, n11, n12 = ct * m10 + st * m20, ct * m11 + st * m21, ct * m12 + st * m22
    n21 = -st * m11 + ct * m21
    # N = Ry(a) Rx(b) Ry(g): N11 = cos b, row 1 = (sb sg, cb, -sb cg), column 1 = (sa sb, cb, ca sb).
    sb_abs = math.hypot(n01, n21)
    b = math.atan2(sb_abs, n11)
    # Pick the sign of b whose hip roll q2 = b + tilt is inside (or nearest) the limits.
    lo1, up1, bp, bm = lo[1], up[1], b + tilt, -b + tilt
    sgn = 1.0 if max(lo1 - bp, bp - up1, 0.0) <= max(lo1 - bm, bm - up1, 0.0) else -1.0
    b *= sgn
    if sb_abs > 1e-9 or n11 < 0.0:
        q1 = math.atan2(sgn * n01, sgn * n21)
        gam = math.atan2(sgn * n10, -sgn * n12)
    else:  # hip roll axis aligned with the yaw-pitch axis: only q1 + gamma is defined
        q1 = 0.0
        gam = math.atan2(n02, n00)
    q = (q1, b + tilt, -gam, q4, q5, q6)
    qc = [min(max(a, lo[i]), up[i]) for i, a in enumerate(q)]
    if reachable:
        for a, c in zip(q, qc):
            if abs(a - c) > LIMIT_TOL:
                reachable = False
                break
    return np.array(qc), reachable
