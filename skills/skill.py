"""The skill description language of UT Austin Villa (dissertation section 8.2.6).

A skill is a sequence of keyframes; a keyframe sets (``settar``) or shifts
(``inctar``) joint target angles and then waits (``wait``) so that the joints
can reach them. Example (``getup_front.skl``)::

    # comments start with '#' or '//'
    STARTSKILL GETUP_FRONT
    STARTSTATE
        settar lae1 -90 rae1 -90 lle4 $knee end   # degrees
        inctar lle3 5 end
        wait 0.2 end                               # seconds ('end' optional here)
    ENDSTATE
    ENDSKILL
    REFLECTSKILL KICK_LEFT KICK_RIGHT             # mirror a skill of the file

Joints are named by the league's *effector* names (``he1 he2``, ``lae1-4``,
``rae1-4``, ``lle1-7``, ``rle1-7``); UT's ``EFF_H1``, ``EFF_LA1``, ``EFF_LL1``
... are accepted as aliases. ``setTarget``/``increaseTarget`` (the
dissertation's spelling) are aliases of ``settar``/``inctar``. Keywords are
case-insensitive. Toe joints (``lle7``/``rle7``) are ignored on robots without
toes.

Values are arithmetic expressions over numbers and ``$parameters`` with
``+ - * /`` and parentheses, e.g. ``(2 * $kick_knee) - 5``. Angles are in
degrees and waits in seconds, as UT writes them; they are converted to SI once,
when the skill is bound to its parameters. A parameter's unit is that of the
slot it is used in ("deg" for joint values, "s" for waits), so
`SkillSource.schema` feeds `skills.params.load_params` directly. Inside an
expression, numbers added to or subtracted from a parameter are in the slot's
unit and factors are plain numbers (``2 * $a`` doubles the angle ``$a``).

A syntax error, an unknown joint, keyword or parameter raises
`skills.params.ParamError` whose message is ``file:line: ... 'word'``.

Reflection (left skill -> right skill) swaps l/r joints and negates the roll
and yaw joints (``he1``, ``ae2``, ``ae3``, ``ae4``, ``le2``, ``le6``); pitch
joints and the hip yaw-pitch ``le1`` keep their sign, as this robot's axes
mirror in the torso's x-z plane.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from models import nao
from skills.params import UNITS, ParamError, PathLike, load_params, strip_comment

# Effector names -> perceptor (joint) names, and UT's aliases.
_EFFECTOR = {"he1": "hj1", "he2": "hj2"}
_EFFECTOR.update({f"{s}{k}e{i}": f"{s}{k}j{i}" for s in "lr" for k, n in (("a", 4), ("l", 7))
                  for i in range(1, n + 1)})
_UT_ALIAS = {"eff_h1": "hj1", "eff_h2": "hj2"}
_UT_ALIAS.update({f"eff_{s}{k}{i}": f"{s}{k}j{i}" for s in "lr" for k, n in (("a", 4), ("l", 7))
                  for i in range(1, n + 1)})
JOINT_NAMES: dict[str, str] = {**_EFFECTOR, **_UT_ALIAS}  # lower-case file name -> joint name

MIRROR_NEGATED = frozenset({"hj1", "laj2", "raj2", "laj3", "raj3", "laj4", "raj4",
                            "llj2", "rlj2", "llj6", "rlj6"})

_KEYWORDS = {
    "startskill": "startskill", "endskill": "endskill", "startstate": "startstate",
    "endstate": "endstate", "settar": "settar", "settarget": "settar", "inctar": "inctar",
    "increasetarget": "inctar", "wait": "wait", "end": "end", "reflectskill": "reflectskill",
}

_TOKEN = re.compile(r"\s*(?:(\$?[A-Za-z_][A-Za-z0-9_]*)|((?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|([()+\-*/]))")


def mirror_joint(name: str) -> tuple[str, float]:
    """The joint that mirrors `name` (perceptor name) and the sign of its angle."""
    if name[0] in "lr" and name[1:] in ("aj1", "aj2", "aj3", "aj4") + tuple(f"lj{i}" for i in range(1, 8)):
        other = ("r" if name[0] == "l" else "l") + name[1:]
    else:
        other = name
    return other, (-1.0 if name in MIRROR_NEGATED else 1.0)


def mirror_angles(angles: np.ndarray, names: list[str]) -> np.ndarray:
    """Mirror a joint-angle vector (rad, order of `names`) in the torso's x-z plane."""
    index = {n: i for i, n in enumerate(names)}
    out = np.empty_like(np.asarray(angles, dtype=float))
    for i, n in enumerate(names):
        other, sign = mirror_joint(n)
        out[index[other]] = sign * angles[i]
    return out


# ------------------------------------------------------------------------- tokens


@dataclass(frozen=True)
class Token:
    text: str
    kind: str  # "word", "param", "number", "op"
    line: int


def tokenize(text: str, path: PathLike | None = None) -> list[Token]:
    """Split a skill file into tokens, comments removed."""
    out = []
    for n, raw in enumerate(text.splitlines(), start=1):
        line = strip_comment(raw)
        pos = 0
        while pos < len(line):
            if line[pos:].strip() == "":
                break
            m = _TOKEN.match(line, pos)
            if m is None:
                bad = line[pos:].split()[0]
                raise ParamError(path, n, "unexpected characters", bad)
            word, number, op = m.groups()
            if word is not None:
                out.append(Token(word, "param" if word[0] == "$" else "word", n))
            elif number is not None:
                out.append(Token(number, "number", n))
            else:
                out.append(Token(op, "op", n))
            pos = m.end()
    return out


# -------------------------------------------------------------------- expressions


@dataclass(frozen=True)
class Expr:
    """A value of a skill file: an expression tree in the file's units."""

    op: str  # "num", "par", "neg", "+", "-", "*", "/"
    value: float = 0.0
    name: str = ""
    args: tuple[Expr, ...] = ()
    token: Token | None = None

    def params(self) -> Iterable[Expr]:
        """The parameter leaves of the tree."""
        if self.op == "par":
            yield self
        for a in self.args:
            yield from a.params()

    def evaluate(self, params: Mapping[str, float], scale: float, path: PathLike | None) -> float:
        """The SI value: numbers in the slot's unit are multiplied by `scale`, parameters are SI."""
        v, const = self._eval(params, scale, path)
        return v * scale if const else v

    def _eval(self, params: Mapping[str, float], scale: float, path) -> tuple[float, bool]:
        # Returns (value, is_constant); a constant's unit is decided by its context.
        if self.op == "num":
            return self.value, True
        if self.op == "par":
            if self.name not in params:
                raise ParamError(path, self.token.line, "parameter not set", "$" + self.name)
            return params[self.name], False
        if self.op == "neg":
            v, c = self.args[0]._eval(params, scale, path)
            return -v, c
        (a, ca), (b, cb) = (x._eval(params, scale, path) for x in self.args)
        if self.op in "+-":
            if ca != cb:  # a number beside a parameter carries the slot's unit
                a, b = (a * scale if ca else a), (b * scale if cb else b)
            return (a + b if self.op == "+" else a - b), ca and cb
        if not (ca or cb):
            raise ParamError(path, self.token.line, "product or ratio of two parameters", self.token.text)
        if self.op == "*":
            return a * b, ca and cb
        if b == 0.0:
            raise ParamError(path, self.token.line, "division by zero", self.token.text)
        if ca and not cb:
            raise ParamError(path, self.token.line, "division by a parameter", self.token.text)
        return a / b, ca and cb


class _Parser:
    def __init__(self, tokens: list[Token], path: PathLike | None) -> None:
        self.tokens, self.path, self.i = tokens, path, 0
        self.last_line = tokens[-1].line if tokens else 1

    def peek(self) -> Token | None:
        return self.tokens[self.i] if self.i < len(self.tokens) else None

    def next(self, what: str) -> Token:
        t = self.peek()
        if t is None:
            raise ParamError(self.path, self.last_line, f"file ends where {what} was expected")
        self.i += 1
        return t

    def error(self, t: Token, message: str) -> ParamError:
        return ParamError(self.path, t.line, message, t.text)

    def keyword(self, t: Token) -> str | None:
        return _KEYWORDS.get(t.text.lower()) if t.kind == "word" else None

    def expect(self, kw: str) -> Token:
        t = self.next(kw)
        if self.keyword(t) != kw:
            raise self.error(t, f"expected {kw!r}, found")
        return t

    def name(self, what: str) -> Token:
        t = self.next(what)
        if t.kind != "word" or self.keyword(t):
            raise self.error(t, f"expected {what}, found")
        return t

    # expr := term (("+"|"-") term)*; term := unary (("*"|"/") unary)*;
    # unary := "-" unary | "+" unary | number | $param | "(" expr ")"
    def expr(self) -> Expr:
        e = self.term()
        while (t := self.peek()) is not None and t.kind == "op" and t.text in "+-":
            self.i += 1
            e = Expr(t.text, args=(e, self.term()), token=t)
        return e

    def term(self) -> Expr:
        e = self.unary()
        while (t := self.peek()) is not None and t.kind == "op" and t.text in "*/":
            self.i += 1
            e = Expr(t.text, args=(e, self.unary()), token=t)
        return e

    def unary(self) -> Expr:
        t = self.next("a value")
        if t.kind == "op" and t.text == "-":
            return Expr("neg", args=(self.unary(),), token=t)
        if t.kind == "op" and t.text == "+":
            return self.unary()
        if t.kind == "number":
            return Expr("num", value=float(t.text), token=t)
        if t.kind == "param":
            if len(t.text) < 2:
                raise self.error(t, "empty parameter name")
            return Expr("par", name=t.text[1:], token=t)
        if t.kind == "op" and t.text == "(":
            e = self.expr()
            close = self.next("')'")
            if close.text != ")":
                raise self.error(close, "expected ')', found")
            return e
        raise self.error(t, "expected a number or $parameter, found")


# ------------------------------------------------------------------------ skills


@dataclass(frozen=True)
class Keyframe:
    """One key frame in SI: joint targets set or shifted (rad, by joint name), then a wait (s)."""

    set: dict[str, float] = field(default_factory=dict)
    inc: dict[str, float] = field(default_factory=dict)
    wait: float = 0.0


@dataclass(frozen=True)
class Skill:
    """A bound skill: keyframes with SI values, played by `SkillPlayer`."""

    name: str
    keyframes: tuple[Keyframe, ...]

    @property
    def duration(self) -> float:
        """Sum of the waits (s)."""
        return sum(k.wait for k in self.keyframes)

    def reflected(self, name: str) -> Skill:
        """The mirror image of this skill (left <-> right), named `name`."""
        def mirror(d: dict[str, float]) -> dict[str, float]:
            out = {}
            for j, v in d.items():
                other, sign = mirror_joint(j)
                out[other] = sign * v
            return out
        return Skill(name, tuple(replace(k, set=mirror(k.set), inc=mirror(k.inc)) for k in self.keyframes))


@dataclass(frozen=True)
class _Op:
    kind: str  # "set" or "inc"
    joint: str
    expr: Expr


@dataclass(frozen=True)
class _State:
    ops: tuple[_Op, ...]
    wait: Expr | None


@dataclass
class SkillSource:
    """A parsed skill file, not yet bound to parameter values.

    `schema` maps every ``$parameter`` the file uses to its unit ("deg" or
    "s"); `bind` evaluates every value in SI.
    """

    path: PathLike | None
    skills: dict[str, tuple[_State, ...]]
    reflections: list[tuple[str, str, Token]]
    schema: dict[str, str]

    def bind(self, params: Mapping[str, float] | None = None) -> dict[str, Skill]:
        """Every skill of the file (reflections included) with `params` (SI) substituted."""
        params = params or {}
        out: dict[str, Skill] = {}
        for name, states in self.skills.items():
            frames = []
            for st in states:
                s: dict[str, float] = {}
                inc: dict[str, float] = {}
                for op in st.ops:
                    v = op.expr.evaluate(params, UNITS["deg"], self.path)
                    if op.kind == "set":
                        s[op.joint] = v
                        inc.pop(op.joint, None)
                    elif op.joint in s:
                        s[op.joint] += v
                    else:
                        inc[op.joint] = inc.get(op.joint, 0.0) + v
                wait = 0.0 if st.wait is None else st.wait.evaluate(params, UNITS["s"], self.path)
                if wait < 0:
                    raise ParamError(self.path, st.wait.token.line, "negative wait", f"{wait:g}")
                frames.append(Keyframe(s, inc, wait))
            out[name] = Skill(name, tuple(frames))
        for src, dst, _ in self.reflections:
            out[dst] = out[src].reflected(dst)
        return out


def parse_skills(text: str, path: PathLike | None = None) -> SkillSource:
    """Parse the text of a skill file (see the module docstring for the syntax)."""
    p = _Parser(tokenize(text, path), path)
    skills: dict[str, tuple[_State, ...]] = {}
    reflections: list[tuple[str, str, Token]] = []
    units: dict[str, tuple[str, Token]] = {}

    def note_params(e: Expr, unit: str) -> None:
        for leaf in e.params():
            seen = units.setdefault(leaf.name, (unit, leaf.token))
            if seen[0] != unit:
                raise p.error(leaf.token, f"parameter used as both {seen[0]} and {unit}:")

    while (t := p.peek()) is not None:
        kw = p.keyword(t)
        if kw == "reflectskill":
            p.i += 1
            src, dst = p.name("a skill name"), p.name("a skill name")
            if src.text not in skills:
                raise p.error(src, "reflection of an unknown skill")
            if dst.text in skills or any(dst.text == r[1] for r in reflections):
                raise p.error(dst, "skill defined twice")
            reflections.append((src.text, dst.text, src))
            continue
        if kw != "startskill":
            raise p.error(t, "expected STARTSKILL or REFLECTSKILL, found")
        p.i += 1
        name = p.name("a skill name")
        if name.text in skills:
            raise p.error(name, "skill defined twice")
        states = []
        while True:
            t = p.next("STARTSTATE or ENDSKILL")
            kw = p.keyword(t)
            if kw == "endskill":
                break
            if kw != "startstate":
                raise p.error(t, "expected STARTSTATE or ENDSKILL, found")
            ops: list[_Op] = []
            wait: Expr | None = None
            while True:
                t = p.next("a statement or ENDSTATE")
                kw = p.keyword(t)
                if kw == "endstate":
                    break
                if kw in ("settar", "inctar"):
                    count = 0
                    while True:
                        j = p.next("a joint name or 'end'")
                        if p.keyword(j) == "end":
                            break
                        if j.kind != "word" or j.text.lower() not in JOINT_NAMES:
                            raise p.error(j, "unknown joint")
                        e = p.expr()
                        note_params(e, "deg")
                        ops.append(_Op("set" if kw == "settar" else "inc", JOINT_NAMES[j.text.lower()], e))
                        count += 1
                    if count == 0:
                        raise p.error(j, f"{t.text} without joints before")
                elif kw == "wait":
                    if wait is not None:
                        raise p.error(t, "second wait in one state:")
                    wait = p.expr()
                    note_params(wait, "s")
                    nxt = p.peek()
                    if nxt is not None and p.keyword(nxt) == "end":
                        p.i += 1
                else:
                    raise p.error(t, "unknown statement")
            states.append(_State(tuple(ops), wait))
        skills[name.text] = tuple(states)
    return SkillSource(path, skills, reflections, {n: u for n, (u, _) in units.items()})


def read_skills(path: PathLike) -> SkillSource:
    """Parse a skill file."""
    with open(path, encoding="utf-8") as f:
        return parse_skills(f.read(), path)


def load_skills(path: PathLike, param_paths: Iterable[PathLike] = (), prefix: str = "",
                defaults: Mapping[str, float] | None = None) -> dict[str, Skill]:
    """Parse a skill file and bind it to parameter files (later files override earlier).

    The parameter files may hold only the file's ``$parameters`` (with
    `prefix`), in the units of their slots: degrees for joint values, seconds
    for waits. `defaults` are SI values for parameters no file sets.
    """
    src = read_skills(path)
    param_paths = list(param_paths)
    params = load_params(param_paths, src.schema, prefix, defaults) if param_paths else dict(defaults or {})
    return src.bind(params)


# ------------------------------------------------------------------------ player


class SkillPlayer:
    """Plays a skill: elapsed time and joint angles in, target angles (rad, league order) out.

    At the first `step` after `reset` the targets start at the current joint
    angles (joints the skill never sets hold their pose); each keyframe is
    applied when its time comes and holds for its wait. Targets are clipped
    to the joint limits. Once `done`, the last targets hold.
    """

    def __init__(self, skill: Skill, robot_type: int) -> None:
        self.skill = skill
        specs = nao.joints(robot_type)
        self.names = [j.name for j in specs]
        index = {n: i for i, n in enumerate(self.names)}
        self.lower = np.array([j.lower for j in specs])
        self.upper = np.array([j.upper for j in specs])
        # Keyframes as index arrays over the league order (unknown joints, e.g. toes, dropped).
        self._frames = []
        for k in skill.keyframes:
            si = [(index[j], v) for j, v in k.set.items() if j in index]
            ii = [(index[j], v) for j, v in k.inc.items() if j in index]
            self._frames.append((np.array([i for i, _ in si], dtype=int), np.array([v for _, v in si]),
                                 np.array([i for i, _ in ii], dtype=int), np.array([v for _, v in ii])))
        self._ends = np.cumsum([k.wait for k in skill.keyframes])
        self.reset()

    def reset(self) -> None:
        """Start over at the next `step`."""
        self._start: float | None = None
        self._applied = 0
        self._targets = np.zeros(len(self.names))
        self._elapsed = 0.0

    @property
    def elapsed(self) -> float:
        """Seconds since the skill started."""
        return self._elapsed

    @property
    def done(self) -> bool:
        """True once every keyframe has been applied and waited for."""
        return self._start is not None and self._applied == len(self._frames) and (
            not len(self._ends) or self._elapsed >= self._ends[-1] - 1e-9)

    @property
    def keyframe(self) -> int:
        """Index of the keyframe being held (the last applied)."""
        return self._applied - 1

    def step(self, time: float, joints: np.ndarray) -> np.ndarray:
        """Targets (rad, league order) at `time` (s); `joints` (rad) seed them at the start.

        The returned array is the player's own; copy it to keep it.
        """
        if self._start is None:
            self._start = time
            self._targets[:] = joints
        self._elapsed = time - self._start
        # Keyframe k starts when keyframe k-1's wait is over.
        while self._applied < len(self._frames) and (
                self._applied == 0 or self._elapsed >= self._ends[self._applied - 1] - 1e-9):
            si, sv, ii, iv = self._frames[self._applied]
            self._targets[si] = sv
            self._targets[ii] += iv
            self._applied += 1
        np.clip(self._targets, self.lower, self.upper, out=self._targets)
        return self._targets


def skill_path(name: str) -> str:
    """Path of a file shipped in `skills/data/`."""
    return os.path.join(os.path.dirname(__file__), "data", name)
