"""The server's hot loops, compiled with numba: the vision model's geometry, the
search of the contact list for ball touches, the body sensors (gyro,
accelerometer, sole forces) and the referee's per-cycle bookkeeping of fallen
players and crowded penalty areas.

All are plain loops over small arrays, run every (vision) cycle or substep, where
numpy's per-call cost dominated: the array version of the vision geometry took
0.66 ms a vision cycle for 22 players, this one about 0.08 ms; right after a
physics step, with cold caches, each interpreted numpy call costs several times
its warm price, so one compiled call per job pays twice. `server.vision`
draws the noise and builds the percepts; `camera_views` only answers "what does
each camera see, and where".
"""

from __future__ import annotations

import math

import numpy as np

from models.jit import njit


@njit
def _polar(x: float, y: float, z: float, out: np.ndarray, k: int) -> None:
    h2 = x * x + y * y
    out[k, 0] = math.sqrt(h2 + z * z)
    out[k, 1] = math.atan2(y, x)
    out[k, 2] = math.atan2(z, math.sqrt(h2))


@njit
def _noisy(pol: np.ndarray, k: int, noise: np.ndarray, j: int, sigma: np.ndarray) -> None:
    """Row k of `pol` (distance, horizontal, vertical) with noise: the distance times
    (1 + sigma[0] n0), the angles plus sigma[1] n1 and sigma[2] n2, n = noise[j:j + 3]."""
    pol[k, 0] *= 1.0 + sigma[0] * noise[j]
    pol[k, 1] += sigma[1] * noise[j + 1]
    pol[k, 2] += sigma[2] * noise[j + 2]


@njit
def camera_views(points: np.ndarray, nobj: int, not_own: np.ndarray, cam: np.ndarray,
                 rot: np.ndarray, calib: np.ndarray, tan_half: float, noise: np.ndarray,
                 start: int, sigma: np.ndarray, cam_left: np.ndarray, obj_left: np.ndarray):
    """What m cameras see of `points` (P, 3; world frame), with noise: the first
    `nobj` rows are objects, the rest field-line end points in pairs (a0, b0, a1, b1, ...).

    cam (m, 3) camera positions, rot (m, 3, 3) camera axes as columns, calib (m, 3)
    calibration offsets (camera frame), not_own (m, nobj) objects each camera may see,
    cam_left (m,) and obj_left (nobj,) the sides (True: left) of each camera and object.
    noise: standard normal draws, used in order from index `start`, three per polar
    point seen (`_noisy`, relative sigma on distance, sigmas in rad on the angles).

    Returns (obj_col, obj_pol, obj_ours, obj_end, line_pol, line_end, used): for each
    camera in turn, the columns of the objects inside the cone (ascending), their noisy
    polar coordinates (distance m, horizontal and vertical angle rad) and whether the
    object's side is the camera's; then the visible parts of the lines clipped to the
    cone, (n, 2, 3) polar. The ends are cumulative: camera i's objects are rows
    obj_end[i - 1]:obj_end[i] (0 for i = 0), its lines likewise. `used`: how many
    noise draws were taken.
    """
    m = cam.shape[0]
    nlines = (points.shape[0] - nobj) // 2
    t2 = tan_half * tan_half
    obj_col = np.empty(m * nobj, np.int64)
    obj_pol = np.empty((m * nobj, 3))
    obj_ours = np.empty(m * nobj, np.bool_)
    obj_end = np.zeros(m, np.int64)
    line_pol = np.empty((m * nlines, 2, 3))
    line_end = np.zeros(m, np.int64)
    ends = np.empty((2, 3))
    f = np.empty((2, 4))
    n = 0
    nl = 0
    u = start
    for i in range(m):
        r = rot[i]
        cx, cy, cz = cam[i, 0], cam[i, 1], cam[i, 2]
        for k in range(nobj):
            if not not_own[i, k]:
                continue
            dx, dy, dz = points[k, 0] - cx, points[k, 1] - cy, points[k, 2] - cz
            x = dx * r[0, 0] + dy * r[1, 0] + dz * r[2, 0] + calib[i, 0]
            y = dx * r[0, 1] + dy * r[1, 1] + dz * r[2, 1] + calib[i, 1]
            z = dx * r[0, 2] + dy * r[1, 2] + dz * r[2, 2] + calib[i, 2]
            if abs(y) <= tan_half * x and z * z <= t2 * (x * x + y * y):
                obj_col[n] = k
                obj_ours[n] = obj_left[k] == cam_left[i]
                _polar(x, y, z, obj_pol, n)
                _noisy(obj_pol, n, noise, u, sigma)
                u += 3
                n += 1
        obj_end[i] = n
        for j in range(nlines):
            for e in range(2):
                p = nobj + 2 * j + e
                dx, dy, dz = points[p, 0] - cx, points[p, 1] - cy, points[p, 2] - cz
                for c in range(3):
                    ends[e, c] = dx * r[0, c] + dy * r[1, c] + dz * r[2, c] + calib[i, c]
                x, y, z = ends[e, 0], ends[e, 1], ends[e, 2]
                # Signed distances to the four planes of the view pyramid (inside >= 0).
                f[e, 0] = tan_half * x - y
                f[e, 1] = tan_half * x + y
                f[e, 2] = tan_half * x - z
                f[e, 3] = tan_half * x + z
            t0, t1 = 0.0, 1.0
            visible = True
            for q in range(4):
                fa, fb = f[0, q], f[1, q]
                if fa < 0.0 and fb < 0.0:
                    visible = False
                    break
                if fa < 0.0:  # enters through this plane
                    t0 = max(t0, fa / (fa - fb))
                elif fb < 0.0:  # leaves through it
                    t1 = min(t1, fa / (fa - fb))
            if not visible or t0 >= t1:
                continue
            for e, t in ((0, t0), (1, t1)):
                x = ends[0, 0] + t * (ends[1, 0] - ends[0, 0])
                y = ends[0, 1] + t * (ends[1, 1] - ends[0, 1])
                z = ends[0, 2] + t * (ends[1, 2] - ends[0, 2])
                _polar(x, y, z, line_pol[nl], e)
                _noisy(line_pol[nl], e, noise, u, sigma)
                u += 3
            nl += 1
        line_end[i] = nl
    return obj_col[:n], obj_pol[:n], obj_ours[:n], obj_end, line_pol[:nl], line_end, u - start


@njit
def ball_touchers(geom: np.ndarray, ball: int, owner: np.ndarray, out: np.ndarray) -> int:
    """Owners (player indices, `owner[geom]` >= 0) of the geoms in contact with geom
    `ball` (geom: MjData's contact geom pairs, (ncon, 2)), one per contact, written to
    `out` (at most its length); returns how many."""
    n = 0
    for k in range(geom.shape[0]):
        if geom[k, 0] == ball:
            o = owner[geom[k, 1]]
        elif geom[k, 1] == ball:
            o = owner[geom[k, 0]]
        else:
            continue
        if o >= 0 and n < out.shape[0]:
            out[n] = o
            n += 1
    return n


@njit
def fallen_rules(xpos: np.ndarray, xmat: np.ndarray, torso: np.ndarray, standing_z: np.ndarray,
                 fallen: np.ndarray, down_since: np.ndarray, unsteady_since: np.ndarray,
                 down_limit: np.ndarray, unsteady_limit: np.ndarray, now: float,
                 thresholds: tuple[float, float, float], new_falls: np.ndarray,
                 late: np.ndarray) -> tuple[int, int]:
    """The referee's fallen-player bookkeeping for one cycle, in place.

    xpos, xmat: MjData's body positions and orientations; torso: each player's torso
    body; standing_z: torso heights (m) above which a player stands; thresholds:
    (down, standing) on the z of the torso's up axis. Updates `fallen` (down, and
    then until the player stands again: a getup that sits up and leans forward
    into its stand is one fall), `down_since` and `unsteady_since` (s, NaN while
    up or standing); writes the players that fell this cycle to `new_falls` and those down
    or not standing longer than their limits to `late`. Returns how many of each.
    """
    down_z, standing_up_z = thresholds
    nf = nl = 0
    for i in range(torso.shape[0]):
        up = xmat[torso[i], 8]
        down = up < down_z
        if down and not fallen[i]:
            new_falls[nf] = i
            nf += 1
        standing = up > standing_up_z and xpos[torso[i], 2] > standing_z[i]
        fallen[i] = down or (fallen[i] and not standing)
        if not down:
            down_since[i] = np.nan
        elif np.isnan(down_since[i]):
            down_since[i] = now
        if standing:
            unsteady_since[i] = np.nan
        elif np.isnan(unsteady_since[i]):
            unsteady_since[i] = now
        if now - down_since[i] >= down_limit[i] or now - unsteady_since[i] >= unsteady_limit[i]:
            late[nl] = i
            nl += 1
    return nf, nl


@njit
def penalty_area_rules(xpos: np.ndarray, torso: np.ndarray, own_sign: np.ndarray,
                       area: tuple[float, float, float], area_since: np.ndarray, now: float,
                       inside: np.ndarray) -> int:
    """Who is in their own penalty area, for the illegal-defense rule, in place.

    area: (half field length, penalty area depth, penalty area half width), m;
    own_sign: the sign of x in each player's own half. Sets `area_since` (s, NaN
    while outside) and `inside`; returns how many players are inside.
    """
    half_length, depth, half_width = area
    n = 0
    for i in range(torso.shape[0]):
        x, y = xpos[torso[i], 0], xpos[torso[i], 1]
        inside[i] = abs(y) < half_width and x * own_sign[i] > half_length - depth and abs(x) <= half_length
        if inside[i]:
            n += 1
            if np.isnan(area_since[i]):
                area_since[i] = now
        else:
            area_since[i] = np.nan
    return n


@njit
def _ray_hits_box(pos: np.ndarray, mat: np.ndarray, size: np.ndarray, origin: np.ndarray,
                  direction: np.ndarray) -> bool:
    """Whether the ray origin + t direction (t >= 0, world frame) meets the box of
    half-sizes `size` centered at `pos` with axes the columns of `mat` (row-major 9)."""
    t0, t1 = 0.0, math.inf
    for a in range(3):
        o = (mat[a] * (origin[0] - pos[0]) + mat[3 + a] * (origin[1] - pos[1])
             + mat[6 + a] * (origin[2] - pos[2]))
        v = mat[a] * direction[0] + mat[3 + a] * direction[1] + mat[6 + a] * direction[2]
        if v == 0.0:
            if abs(o) > size[a]:
                return False
            continue
        lo, hi = (-size[a] - o) / v, (size[a] - o) / v
        if lo > hi:
            lo, hi = hi, lo
        t0, t1 = max(t0, lo), min(t1, hi)
        if t0 > t1:
            return False
    return True


@njit
def body_sensors(xmat: np.ndarray, cvel: np.ndarray, acc: np.ndarray, torso: np.ndarray,
                 gravity: np.ndarray, geom_body: np.ndarray,
                 con_geom: np.ndarray, con_pos: np.ndarray, con_frame: np.ndarray,
                 con_efc: np.ndarray, con_dim: np.ndarray, efc_force: np.ndarray,
                 sole_of_body: np.ndarray, sole_site: np.ndarray, site_xpos: np.ndarray,
                 site_xmat: np.ndarray, site_size: np.ndarray, sole_slot: np.ndarray,
                 out: np.ndarray) -> None:
    """Every player's gyro, accelerometer and sole forces, as MuJoCo's gyro and touch
    sensors give them, from the state of the last forward pass (MjData as an
    `mj_step` leaves it: positions, velocities and contact forces of the step's
    start), without MuJoCo's sensor stage.

    The IMU site sits at the torso's origin with the torso's axes, so the gyro is
    the torso's angular velocity (world `cvel`) in the torso frame and the
    accelerometer the origin's linear acceleration `acc` (n, 3; world frame, the
    cycle's mean from `World.root_acc`) minus gravity, in the torso frame. A sole's
    force is the sum of the normal forces (N) of its body's contacts whose ray along
    the normal, into the body, meets the sole's site box (MuJoCo's touch rule); a
    pyramidal contact's normal force is the sum of its facet forces.

    out (n, 10), per player: gyro (rad/s), accelerometer (m/s^2), then sole forces
    in `sole_slot` order (columns 6-9).
    """
    n = torso.shape[0]
    for i in range(n):
        b = torso[i]
        for a in range(3):
            out[i, a] = xmat[b, a] * cvel[b, 0] + xmat[b, 3 + a] * cvel[b, 1] + xmat[b, 6 + a] * cvel[b, 2]
            out[i, 3 + a] = (xmat[b, a] * (acc[i, 0] - gravity[0]) + xmat[b, 3 + a] * (acc[i, 1] - gravity[1])
                             + xmat[b, 6 + a] * (acc[i, 2] - gravity[2]))
        for c in range(6, out.shape[1]):
            out[i, c] = 0.0
    ray = np.empty(3)
    for k in range(con_geom.shape[0]):
        adr = con_efc[k]
        if adr < 0:
            continue
        s0 = sole_of_body[geom_body[con_geom[k, 0]]]
        s1 = sole_of_body[geom_body[con_geom[k, 1]]]
        if s0 < 0 and s1 < 0:
            continue
        f = efc_force[adr]
        for j in range(1, 2 * (con_dim[k] - 1)):  # none for a frictionless contact
            f += efc_force[adr + j]
        if f <= 0.0:
            continue
        for side in range(2):
            s = s0 if side == 0 else s1
            if s < 0:
                continue
            sign = 1.0 if side == 0 else -1.0  # the normal points from geom 0 to geom 1
            norm = math.sqrt(con_frame[k, 0] ** 2 + con_frame[k, 1] ** 2 + con_frame[k, 2] ** 2)
            for a in range(3):
                ray[a] = sign * con_frame[k, a] / norm
            site = sole_site[s]
            if _ray_hits_box(site_xpos[site], site_xmat[site], site_size[site], con_pos[k], ray):
                out[sole_slot[s, 0], 6 + sole_slot[s, 1]] += f


@njit
def hearing_choices(cycle: int, said: np.ndarray, left: np.ndarray, pos: np.ndarray,
                    heading: np.ndarray, next_cycle: np.ndarray, period: int, reach: float,
                    pool: np.ndarray, at: int, speaker: np.ndarray, direction: np.ndarray) -> int:
    """Which message each listener hears: for listener j and slot 0 (own team) or 1 (the
    other team), speaker[j, slot] is the speaker heard (-1: none) and direction[j, slot]
    its horizontal direction (rad, torso frame of j, in [-pi, pi]).

    said (n,) who spoke, left (n,) sides, pos (n, 3) torso positions and heading (n,) torso
    yaws (world frame); next_cycle (n, 2) the first cycle each slot may hear again, updated
    in place. Among several candidates in reach (ascending index) one is drawn with numpy's
    `Generator.integers(k)` method (Lemire's, on 32-bit draws) from the raw 32-bit draws
    pool[at:]. Returns the new `at`, or -1 when the pool ran out (nothing was changed then
    but speaker and direction).
    """
    n = said.shape[0]
    cands = np.empty(n, np.int64)
    heard_at = np.full((n, 2), -1, np.int64)
    u = at
    for j in range(n):
        for slot in range(2):
            speaker[j, slot] = -1
            if cycle < next_cycle[j, slot]:
                continue
            k = 0
            for s in range(n):
                if said[s] and s != j and (left[s] == left[j]) == (slot == 0):
                    dx, dy = pos[s, 0] - pos[j, 0], pos[s, 1] - pos[j, 1]
                    if math.sqrt(dx * dx + dy * dy) <= reach:
                        cands[k] = s
                        k += 1
            if k == 0:
                continue
            pick = 0
            if k > 1:  # Generator.integers(k): random_bounded_uint64_fill's Lemire branch
                rng = np.uint64(k - 1)
                excl = rng + np.uint64(1)
                while True:
                    if u >= pool.shape[0]:
                        return -1
                    m = np.uint64(pool[u]) * excl
                    u += 1
                    left_over = m & np.uint64(0xFFFFFFFF)
                    if left_over >= excl or left_over >= (np.uint64(0xFFFFFFFF) - rng) % excl:
                        break
                pick = np.int64(m >> np.uint64(32))
            s = cands[pick]
            a = math.atan2(pos[s, 1] - pos[j, 1], pos[s, 0] - pos[j, 0]) - heading[j]
            if abs(a) > math.pi:  # math.remainder(a, 2 pi) for |a| <= 2 pi, exactly (Sterbenz)
                a -= math.copysign(2.0 * math.pi, a)
            speaker[j, slot] = s
            direction[j, slot] = a
            heard_at[j, slot] = cycle + period
    for j in range(n):
        for slot in range(2):
            if heard_at[j, slot] >= 0:
                next_cycle[j, slot] = heard_at[j, slot]
    return u
