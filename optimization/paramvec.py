"""Named parameter sets and the CMA-ES vector that stands for the optimized ones.

Parameters are optimized in the units of the parameter files (UT style:
millimeters, radians, seconds), never in SI, so that a learned file reads like
a hand-written one. A `ParamSetDef` describes one named set (a walk set, later
a getup or kick skill): its file prefix, the schema of every name it may hold
(name -> unit, `skills.params.UNITS`), and for the names worth optimizing a
`ParamSpec` with the initial standard deviation and hard bounds, both in file
units.

`ParamSpace` maps the CMA-ES vector z to named values: parameter i is
``x0_i + scale_i * z_i``; CMA-ES starts at z = 0 with sigma S, so parameter
i starts with standard deviation ``S * scale_i`` (scales are the specs'
sigmas). Bounds are passed to CMA-ES in z units.

Values of all sets are kept as ``{set name: {parameter name: value}}`` in file
units ("values"); `write_param_file` writes them as a UT-style file that the
set's loader reads (for walk sets, `skills.walk.load_walk_sets`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from optimization.getup import getup_param_set
from optimization.kick import approach_param_set, kick_param_set, shipped_kick_sets
from optimization.types import ParamSetDef, ParamSpec, Values
from server.files import write_text
from skills.params import ParamError, PathLike, read_entries
from skills.walk import WALK_SCHEMA, WALK_SETS, WalkParams, default_param_files

# Walk parameters CMA-ES tunes (27, as UT's Table 8.2 set), sigma and bounds in file units
# (mm, rad, s, 1). The bounds keep the engine valid (fractions in (0, 1], a leg that reaches).
WALK_SPECS: tuple[ParamSpec, ...] = (
    ParamSpec("max_step_size_x", 10.0, 5.0, 150.0),
    ParamSpec("max_step_size_y", 8.0, 5.0, 120.0),
    ParamSpec("max_step_size_angle", 0.15, 0.1, 2.0),
    ParamSpec("shift_amount", 4.0, 0.0, 60.0),
    ParamSpec("walk_height", 8.0, 130.0, 240.0),  # types 1 and 3 stand at 216 and 233 mm; past a
    # leg's reach (type 0: 203 mm hip to ankle) the IK clamps it
    ParamSpec("step_height", 4.0, 5.0, 60.0),
    ParamSpec("fraction_still", 0.05, 0.0, 0.5),
    ParamSpec("fraction_on_ground", 0.05, 0.0, 0.5),
    ParamSpec("fraction_moving", 0.05, 0.3, 1.0),
    ParamSpec("fraction_in_air", 0.05, 0.3, 1.0),
    ParamSpec("phase_length", 0.03, 0.15, 0.6),
    ParamSpec("default_com_pos_x", 5.0, -40.0, 40.0),
    ParamSpec("pid_step_size_x", 0.01, 0.005, 0.5),
    ParamSpec("pid_step_size_y", 0.01, 0.005, 0.5),
    ParamSpec("pid_step_size_rot", 0.01, 0.005, 0.5),
    ParamSpec("max_normal_com_error", 2.0, 0.0, 50.0),
    ParamSpec("max_acceptable_com_error", 2.0, 0.0, 80.0),
    ParamSpec("fwd_offset", 2.0, -30.0, 30.0),
    ParamSpec("fwd_offset_factor", 0.1, -2.0, 2.0),
    ParamSpec("swing_ankle_offset", 0.03, -0.5, 0.5),
    ParamSpec("pid_tilt", 0.05, -1.0, 1.0),
    ParamSpec("pid_roll", 0.05, -1.0, 1.0),
    ParamSpec("pid_com_x", 0.1, 0.0, 3.0),
    ParamSpec("pid_com_y", 0.1, 0.0, 3.0),
    ParamSpec("pid_com_z", 0.1, -1.0, 1.0),
    ParamSpec("pid_arm_x", 0.1, -2.0, 2.0),
    ParamSpec("pid_arm_y", 0.1, -2.0, 2.0),
)

# The engine's additions to UT's set, learned only when a task names them: the joint
# controller's gain (1/s), the forward swing's steepness and the ankles' gyro damping.
WALK_NAMED_SPECS: tuple[ParamSpec, ...] = (
    ParamSpec("joint_kp", 3.0, 5.0, 60.0),
    ParamSpec("swing_steepness", 1.5, 2.0, 30.0),
    ParamSpec("gyro_pitch", 0.005, -0.1, 0.1),
    ParamSpec("gyro_pitch_walk", 0.005, -0.1, 0.1),
    ParamSpec("gyro_roll", 0.01, -0.2, 0.2),
)


def _walk_set(name: str, prefix: str) -> ParamSetDef:
    engine = WalkParams()  # the engine's own values of the named specs under the files (all unit "1")
    return ParamSetDef(name=name, prefix=prefix, schema=WALK_SCHEMA, specs=WALK_SPECS,
                       defaults=default_param_files, inherit=None if not prefix else "go_to_target",
                       named_specs=WALK_NAMED_SPECS,
                       start={s.name: float(getattr(engine, s.name)) for s in WALK_NAMED_SPECS})


# Every parameter set a task may use, by name. Getup and kick skills add theirs here
# (schema from skills.skill.SkillSource.schema, prefix from the skill's parameter file).
PARAM_SETS: dict[str, ParamSetDef] = {n: _walk_set(n, p) for n, p in WALK_SETS.items()}

# The analytic test problems' coordinates (optimization.task.AnalyticTask): x0 .. x15, start 0.
ANALYTIC_NAMES = tuple(f"x{i}" for i in range(16))
PARAM_SETS["analytic"] = ParamSetDef(
    name="analytic", prefix="analytic_", schema={n: "1" for n in ANALYTIC_NAMES},
    specs=tuple(ParamSpec(n, 1.0) for n in ANALYTIC_NAMES), start={n: 0.0 for n in ANALYTIC_NAMES})


# The getup skills' sets, "getup_front" (front_*) and "getup_back" (back_*): optimization.getup.
PARAM_SETS.update({n: getup_param_set(n) for n in ("getup_front", "getup_back")})

# The keyframe kick sets of the shipped kick files ("kick", "long_kick", "kick_5m", ...):
# optimization.kick.
PARAM_SETS.update({n: kick_param_set(n) for n in shipped_kick_sets()})
# The ball approach's set "approach" (approach_*, skills/data/approach.params): optimization.kick.
PARAM_SETS["approach"] = approach_param_set()


def param_set(name: str) -> ParamSetDef:
    try:
        return PARAM_SETS[name]
    except KeyError:
        raise KeyError(f"unknown parameter set {name!r}; sets are {', '.join(PARAM_SETS)}") from None


def walk_sets(values: Values) -> dict[str, WalkParams]:
    """WalkParams (SI) for every walk set, from values in file units; sets missing
    from `values` take go-to-target's."""
    base = WalkParams.from_values(param_set("go_to_target").to_si(values["go_to_target"]))
    out = {}
    for name in WALK_SETS:
        out[name] = (WalkParams.from_values(param_set(name).to_si(values[name]), base)
                     if name in values and name != "go_to_target" else base)
    return out


def load_values(set_names: Iterable[str], robot_type: int, files: Sequence[PathLike] = ()) -> Values:
    """Values (file units) of the named sets: their shipped defaults for the robot type,
    then `files` in order (later override earlier). A name in `files` that belongs to
    no registered set raises `ParamError` with its file and line."""
    defs = [param_set(n) for n in set_names]
    paths: list[PathLike] = []
    for d in defs:
        for p in (d.defaults(robot_type) if d.defaults else []):
            if p not in paths:
                paths.append(p)
    entries = read_entries([*paths, *files])
    everything = sorted(PARAM_SETS.values(), key=lambda d: len(d.prefix), reverse=True)
    raw: dict[str, dict[str, float]] = {d.name: {} for d in PARAM_SETS.values()}
    for e in entries.values():
        for d in everything:
            if e.name.startswith(d.prefix) and e.name[len(d.prefix):] in d.schema:
                raw[d.name][e.name[len(d.prefix):]] = e.value
                break
        else:
            raise ParamError(e.path, e.line, "unknown parameter", e.name)
    out: Values = {}

    def resolve(name: str) -> dict[str, float]:
        d = param_set(name)
        base = resolve(d.inherit) if d.inherit else dict(d.start)
        return {**base, **raw[name]}

    for d in defs:
        out[d.name] = resolve(d.name)
    return out


@dataclass(frozen=True)
class ParamSpace:
    """The optimized parameters: (set, name) per vector entry, with start, scale and bounds.

    `base` holds the values of every set the task uses (optimized or frozen),
    file units; `values(z)` returns a copy with the optimized entries replaced.
    """

    keys: tuple[tuple[str, str], ...]
    x0: np.ndarray
    scale: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    base: Mapping[str, Mapping[str, float]]

    @classmethod
    def build(cls, base: Mapping[str, Mapping[str, float]],
              optimize: Mapping[str, Sequence[str] | None]) -> ParamSpace:
        """`optimize`: set name -> parameter names (None: the set's default specs)."""
        keys, x0, scale, lo, hi = [], [], [], [], []
        for set_name, names in optimize.items():
            d = param_set(set_name)
            if set_name not in base:
                raise KeyError(f"set {set_name} is optimized but the task does not use it")
            for n in (names if names else [s.name for s in d.specs]):
                spec = d.spec(n)
                if n not in base[set_name]:
                    raise KeyError(f"parameter {n} of set {set_name} has no starting value")
                keys.append((set_name, n))
                v = float(base[set_name][n])
                x0.append(v)
                scale.append(spec.sigma)
                lo.append(spec.lower)
                hi.append(spec.upper)
        if not keys:
            raise ValueError("nothing to optimize: no parameters selected")
        if len(set(keys)) != len(keys):
            raise ValueError("a parameter is selected twice")
        x0a = np.array(x0)
        lo_a, hi_a = np.array(lo), np.array(hi)
        x0a = np.clip(x0a, lo_a, hi_a)
        frozen = {s: dict(v) for s, v in base.items()}
        return cls(tuple(keys), x0a, np.array(scale), lo_a, hi_a, frozen)

    @property
    def dim(self) -> int:
        return len(self.keys)

    def z_bounds(self) -> tuple[list[float], list[float]]:
        """Lower and upper bounds of z (CMA-ES coordinates); +-inf where unbounded."""
        return (list((self.lower - self.x0) / self.scale), list((self.upper - self.x0) / self.scale))

    def vector(self, z: np.ndarray) -> np.ndarray:
        """Parameter values (file units) of the optimized entries for a CMA-ES point, clipped to bounds."""
        return np.clip(self.x0 + self.scale * np.asarray(z, dtype=float), self.lower, self.upper)

    def values(self, z: np.ndarray) -> Values:
        """Every set's values with the optimized entries taken from z."""
        out = {s: dict(v) for s, v in self.base.items()}
        for (s, n), v in zip(self.keys, self.vector(z)):
            out[s][n] = float(v)
        return out

    def named(self, z: np.ndarray) -> dict[str, float]:
        """The optimized entries as ``{prefix + name: value}`` (file names)."""
        return {param_set(s).prefix + n: float(v) for (s, n), v in zip(self.keys, self.vector(z))}


def format_value(v: float) -> str:
    return f"{v:.6g}"


def write_param_file(path: PathLike, values: Mapping[str, Mapping[str, float]], header: str = "") -> None:
    """Write every set's values as ``prefix+name<TAB>value`` lines (file units), atomically.

    Sets with a prefix are written in full, so the file stands alone after the
    shipped defaults."""
    lines = [f"# {h}" if h else "#" for h in header.splitlines()]
    for set_name, vals in values.items():
        d = param_set(set_name)
        lines.append(f"\n# set {set_name} (prefix {d.prefix!r})" if d.prefix else f"\n# set {set_name}")
        for n in d.schema:
            if n in vals:
                lines.append(f"{d.prefix}{n}\t{format_value(vals[n])}\t# {d.schema[n]}")
    write_text(path, "\n".join(lines) + "\n", fsync=True)
