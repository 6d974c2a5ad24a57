"""Delaunay-triangulation formations (Akiyama and Noda 2008).

A formation is a set of samples, each a ball position and the position of
every named role for that ball position (meters, field frame). For a new
ball position the role positions are interpolated barycentrically inside the
Delaunay triangle of sample ball positions that contains the ball; outside the
convex hull of the samples the nearest sample is used. Roles listed in
`follow` are placed exactly at the ball. All positions are clipped to the
field shrunk by `margin`.

Formation file format (line based, '#' starts a comment, SI units)::

    name default                 # optional
    roles goalie onBall ...      # role names, once, before any sample
    mirror wingLeft wingRight    # left-right partners (optional, repeatable)
    symmetric yes                # add the y -> -y mirror of every sample
    follow onBall                # roles placed exactly at the ball
    margin 0.3                   # meters kept from the field lines
    sample <ball_x> <ball_y>     # starts a sample ...
    <role> <x> <y>               # ... then one line per role

A malformed file raises `FormationFileError` naming the file, the line and the
offending value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay, QhullError

from formations import _kernels
from formations import field as fld

DEFAULT_FORMATION = "default.formation"


class FormationFileError(ValueError):
    """A formation file that cannot be parsed; the message names file and line."""

    def __init__(self, source: str, line: int, message: str, value: object = None):
        text = f"{source}:{line}: {message}"
        if value is not None:
            text += f" (got {value!r})"
        super().__init__(text)
        self.source = source
        self.line = line
        self.value = value


@dataclass
class Formation:
    """Delaunay formation: `balls` (k, 2) samples and `positions` (k, roles, 2), meters."""

    roles: tuple[str, ...]
    balls: np.ndarray
    positions: np.ndarray
    follow: tuple[str, ...] = ()
    margin: float = 0.0
    name: str = "formation"
    mirror: tuple[int, ...] | None = None  # role index of each role's partner if symmetric
    _tri: Delaunay | None = field(default=None, init=False, repr=False)

    def __post_init__(self):
        self.balls = np.asarray(self.balls, dtype=float).reshape(-1, 2)
        self.positions = np.asarray(self.positions, dtype=float).reshape(len(self.balls), len(self.roles), 2)
        if len(self.balls) == 0:
            raise ValueError("a formation needs at least one sample")
        self._tri = None
        if len(self.balls) >= 3:
            try:
                self._tri = Delaunay(self.balls)
            except QhullError:  # all samples collinear: nearest sample only
                self._tri = None
        self._follow = np.array([r in self.follow for r in self.roles], dtype=bool)
        self._mirror_index = None if self.mirror is None else np.array(self.mirror, dtype=np.int64)
        self._lo, self._hi = fld.field_box(self.margin)
        self._indices: dict[tuple[str, ...], np.ndarray] = {}
        self._all_rows = np.arange(len(self.roles), dtype=np.int64)
        self._tables = self._kernel_tables()

    def _kernel_tables(self) -> tuple:
        """The triangulation's arrays `_kernels.formation_positions` walks (empty without one)."""
        tri = self._tri
        if tri is None:
            return (np.zeros(2), np.zeros(2), np.zeros((0, 4)), np.zeros((0, 3), np.intc),
                    np.zeros((0, 3, 2)), np.zeros((0, 3), np.intc), 1.0, 0.0)
        c = np.ascontiguousarray
        return (c(tri.min_bound, dtype=float), c(tri.max_bound, dtype=float),
                c(tri.equations, dtype=float), c(tri.neighbors, dtype=np.intc),
                c(tri.transform, dtype=float), c(tri.simplices, dtype=np.intc),
                float(tri.paraboloid_scale), float(tri.paraboloid_shift))

    @property
    def triangulation(self) -> Delaunay | None:
        return self._tri

    def index(self, role: str) -> int:
        return self.roles.index(role)

    def indices(self, roles: tuple[str, ...]) -> np.ndarray:
        """Role indices (k,) of `roles`, remembered per tuple of names."""
        idx = self._indices.get(roles)
        if idx is None:
            idx = self._indices[roles] = np.array([self.roles.index(r) for r in roles], dtype=np.int64)
        return idx

    def weights(self, ball: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Sample indices and barycentric weights used for `ball` (2,), meters."""
        ball = np.asarray(ball, dtype=float)
        if self._tri is not None:
            s = int(self._tri.find_simplex(ball))
            if s >= 0:
                t = self._tri.transform[s]
                b = t[:2] @ (ball - t[2])
                w = np.array([b[0], b[1], 1.0 - b[0] - b[1]])
                return self._tri.simplices[s], np.clip(w, 0.0, 1.0)
        nearest = int(np.argmin(np.sum((self.balls - ball) ** 2, axis=1)))
        return np.array([nearest]), np.array([1.0])

    def positions_at(self, ball: np.ndarray) -> np.ndarray:
        """(roles, 2) role positions for a ball at `ball` (2,), field frame, meters.

        Inside the samples' hull: the positions of the Delaunay triangle holding
        the ball (`Delaunay.find_simplex`), weighted by its barycentric
        coordinates clipped to [0, 1] and normalized, and exactly a sample's
        positions at the sample; outside: the nearest sample's. Roles in
        `follow` stand at the ball; all are clipped to the field shrunk by
        `margin`. A symmetric formation evaluates balls with y < 0 as the mirror
        image of the ball at -y, so its output is exactly left-right symmetric.
        """
        return self.rows_at(self._all_rows, ball)

    def rows_at(self, rows: np.ndarray, ball: np.ndarray) -> np.ndarray:
        """(len(rows), 2) positions of the roles of indices `rows` (int64) for `ball` (2,), m."""
        bx, by = np.asarray(ball, dtype=float).reshape(2).tolist()
        mirror = self._mirror_index if self._mirror_index is not None else self._all_rows[:0]
        return _kernels.formation_positions(bx, by, rows, mirror, *self._tables, self.balls, self.positions,
                                            self._follow, self._lo, self._hi)

    def position(self, role: str, ball: np.ndarray) -> np.ndarray:
        return self.positions_at(ball)[self.index(role)]

    def as_dict(self, ball: np.ndarray) -> dict[str, np.ndarray]:
        return dict(zip(self.roles, self.positions_at(ball)))

    # ------------------------------------------------------------------
    # Files.

    @classmethod
    def load(cls, path: str | Path) -> Formation:
        path = Path(path)
        return parse(path.read_text(), str(path))

    @classmethod
    def default(cls) -> Formation:
        """The default 11-player formation shipped in formations/data."""
        ref = resources.files("formations").joinpath("data", DEFAULT_FORMATION)
        return parse(ref.read_text(), f"formations/data/{DEFAULT_FORMATION}")

    def dumps(self) -> str:
        """Formation file text (samples as stored, symmetry already expanded)."""
        lines = [f"name {self.name}", "roles " + " ".join(self.roles)]
        if self.follow:
            lines.append("follow " + " ".join(self.follow))
        lines.append(f"margin {self.margin:g}")
        for ball, pos in zip(self.balls, self.positions):
            lines.append(f"sample {ball[0]:.6g} {ball[1]:.6g}")
            for role, p in zip(self.roles, pos):
                lines.append(f"  {role} {p[0]:.6g} {p[1]:.6g}")
        return "\n".join(lines) + "\n"


_YES = {"yes", "true", "1", "on"}
_NO = {"no", "false", "0", "off"}


def _number(tok: str, source: str, line: int, what: str) -> float:
    try:
        x = float(tok)
    except ValueError:
        raise FormationFileError(source, line, f"{what} is not a number", tok) from None
    if not math.isfinite(x):
        raise FormationFileError(source, line, f"{what} is not finite", tok)
    return x


def parse(text: str, source: str = "<string>") -> Formation:
    """Parses formation file `text`; `source` names it in error messages."""
    name = Path(source).stem
    roles: list[str] | None = None
    mirror: dict[str, str] = {}
    symmetric = False
    follow: list[str] = []
    margin = 0.0
    samples: list[tuple[int, tuple[float, float], dict[str, tuple[float, float]]]] = []

    def finish_sample():
        if samples:
            line, _, pos = samples[-1]
            missing = [r for r in roles if r not in pos]
            if missing:
                raise FormationFileError(
                    source, line, "sample does not place every role; missing", missing[0]
                )

    lineno = 0
    for lineno, raw in enumerate(text.splitlines(), start=1):
        body = raw.split("#", 1)[0].strip()
        if not body:
            continue
        tok = body.split()
        key = tok[0]
        if key == "name":
            if len(tok) != 2:
                raise FormationFileError(source, lineno, "'name' takes one word", body)
            name = tok[1]
        elif key == "roles":
            if roles is not None:
                raise FormationFileError(source, lineno, "roles declared twice", body)
            if len(tok) < 2:
                raise FormationFileError(source, lineno, "'roles' needs at least one role", body)
            roles = tok[1:]
            dup = [r for r in roles if roles.count(r) > 1]
            if dup:
                raise FormationFileError(source, lineno, "duplicate role name", dup[0])
        elif key in ("mirror", "follow"):
            if roles is None:
                raise FormationFileError(source, lineno, f"'{key}' before 'roles'", body)
            for r in tok[1:]:
                if r not in roles:
                    raise FormationFileError(source, lineno, "unknown role", r)
            if key == "mirror":
                if len(tok) != 3 or tok[1] == tok[2]:
                    raise FormationFileError(source, lineno, "'mirror' takes two different roles", body)
                for r in tok[1:]:
                    if r in mirror:
                        raise FormationFileError(source, lineno, "role mirrored twice", r)
                mirror[tok[1]], mirror[tok[2]] = tok[2], tok[1]
            else:
                follow.extend(tok[1:])
        elif key == "symmetric":
            if len(tok) != 2 or tok[1].lower() not in _YES | _NO:
                raise FormationFileError(source, lineno, "'symmetric' takes yes or no", body)
            symmetric = tok[1].lower() in _YES
        elif key == "margin":
            if len(tok) != 2:
                raise FormationFileError(source, lineno, "'margin' takes one number", body)
            margin = _number(tok[1], source, lineno, "margin")
            if not 0.0 <= margin < fld.HALF_WIDTH:
                raise FormationFileError(source, lineno, "margin out of range", tok[1])
        elif key == "sample":
            if roles is None:
                raise FormationFileError(source, lineno, "'sample' before 'roles'", body)
            if len(tok) != 3:
                raise FormationFileError(source, lineno, "'sample' takes <ball_x> <ball_y>", body)
            finish_sample()
            ball = (
                _number(tok[1], source, lineno, "ball x"),
                _number(tok[2], source, lineno, "ball y"),
            )
            if not fld.inside_field(np.array(ball)):
                raise FormationFileError(source, lineno, "ball outside the field", body)
            for other_line, other, _ in samples:
                if other == ball:
                    raise FormationFileError(
                        source,
                        lineno,
                        f"ball position repeats the sample of line {other_line}",
                        body,
                    )
            samples.append((lineno, ball, {}))
        else:
            if roles is None or key not in roles:
                raise FormationFileError(source, lineno, "unknown directive or role", key)
            if not samples:
                raise FormationFileError(source, lineno, "role position before any 'sample'", key)
            if len(tok) != 3:
                raise FormationFileError(source, lineno, "role line takes <role> <x> <y>", body)
            pos = samples[-1][2]
            if key in pos:
                raise FormationFileError(source, lineno, "role placed twice in one sample", key)
            p = (_number(tok[1], source, lineno, "x"), _number(tok[2], source, lineno, "y"))
            if not fld.inside_field(np.array(p), margin):
                raise FormationFileError(source, lineno, "role position outside the field", body)
            pos[key] = p
    if roles is None:
        raise FormationFileError(source, max(lineno, 1), "no 'roles' line")
    if not samples:
        raise FormationFileError(source, max(lineno, 1), "no samples")
    finish_sample()

    balls = [s[1] for s in samples]
    positions = [[s[2][r] for r in roles] for s in samples]
    if symmetric:
        seen = set(balls)
        for _, (bx, by), pos in list(samples):
            mb = (bx, -by)
            if mb in seen:
                continue
            seen.add(mb)
            balls.append(mb)
            positions.append([(pos[mirror.get(r, r)][0], -pos[mirror.get(r, r)][1]) for r in roles])
    return Formation(
        roles=tuple(roles),
        balls=np.array(balls),
        positions=np.array(positions),
        follow=tuple(follow),
        margin=margin,
        name=name,
        mirror=tuple(roles.index(mirror.get(r, r)) for r in roles) if symmetric else None,
    )


def default_formation() -> Formation:
    """The default 11-player formation (see formations/data/default.formation)."""
    return Formation.default()
