"""The league's network protocol (rcssserver3d): S-expressions in length-prefixed frames.

Both directions carry one message per frame: a 4-byte big-endian length, then that
many bytes of ASCII S-expressions. The server sends a percept every cycle; the
agent answers with effector commands. This module has both halves and no sockets:

- `parse_sexp`: bounded S-expression parser (depth, size); bad input is a
  `ProtocolError`, never anything else.
- `encode_frame` / `FrameReader`: the framing, with oversized frames refused.
- `format_percept` / `PerceptParser`: a `Percept` as the league writes it, and back.
- `format_action` / `parse_agent_message` / `parse_action`: the agent's side.

Units and axes on the wire follow rcssserver3d: angles in degrees (joint angles,
gyro rate in deg/s, polar angles of vision, hear direction, beam rotation);
vectors in SimSpark's body axes (x right, y forward, z up); hinge effectors take
a target angular velocity in rad/s (the value goes to ODE's motor velocity
unchanged: UT Austin Villa's and FC Portugal's agents send rad/s, capped at
6.1395 rad/s = 351.77 deg/s by hingejoint.rsg). Inside the project everything
is SI in the project's axes (x forward, y left, z up; `models.nao.to_project`).

What the league sends that we approximate or leave out:

- FRP (force resistance): the league sends the contact's center of pressure `c`
  and the full force vector `f` in the foot's frame; our sensors only know the
  normal force under each sole, so we send c = the sole's center (0, 0, -0.01)
  and f = (0, 0, N). A parser reads the normal force back as f's z component.
  Like the league, a foot without contact (zero force) sends no FRP.
- GS: the league names unum and team side only in the first percept after
  `init`; we do the same (`first=True`) and always send the score (sl, sr).
- hear: rcssserver3d 0.7 writes `(hear TEAM TIME self|DIR MSG)`; older servers
  left out TEAM. We write the 0.7 form; the parser reads both (no TEAM: ours).
- `Percept.warnings` (why a say was dropped) has no league message: not sent.
- No `(mypos ...)`/`(ballpos ...)` ground-truth extras, no AgentState (battery,
  temperature), no TouchPerceptor.
"""

from __future__ import annotations

import functools
import math
import re
import struct
from dataclasses import dataclass, field

import numpy as np

from models import nao
from models.messages import SEEN_PARTS, Action, HeardMessage, Percept, Vision

MAX_DEPTH = 8  # the league's messages nest 4 deep ((See (P (head (pol ..)))))
MAX_MESSAGE = 1 << 20  # bytes of one message (frame) from the server
MAX_AGENT_MESSAGE = 1 << 16  # bytes of one message from an agent (about 600 are typical)
HEADER = struct.Struct(">I")

SCENE_PATH = "rsg/agent/nao/nao_hetero.rsg"


class ProtocolError(ValueError):
    """A malformed or oversized message; the text says what is wrong."""


# ----------------------------------------------------------------- S-expressions

_TOKEN = re.compile(r"[()]|[^\s()]+")
_SPACE_ONLY = re.compile(r"\s*")

Sexp = list  # a list of str atoms and nested lists


def parse_sexp(text: str | bytes, max_depth: int = MAX_DEPTH, max_size: int = MAX_MESSAGE) -> list[Sexp]:
    """The top-level lists of `text`, e.g. "(a 1)(b (c 2))" -> [["a", "1"], ["b", ["c", "2"]]].

    Atoms are any run of characters other than whitespace and parentheses.
    Raises ProtocolError for non-ASCII bytes, unbalanced parentheses, an atom
    outside any list, nesting deeper than `max_depth`, or more than `max_size`
    characters.
    """
    if isinstance(text, (bytes, bytearray, memoryview)):
        if len(text) > max_size:
            raise ProtocolError(f"message of {len(text)} bytes is over the limit of {max_size}")
        try:
            text = bytes(text).decode("ascii")
        except UnicodeDecodeError as exc:
            raise ProtocolError(f"non-ASCII byte at offset {exc.start}") from None
    elif not isinstance(text, str):
        raise ProtocolError(f"expected str or bytes, got {type(text).__name__}")
    if len(text) > max_size:
        raise ProtocolError(f"message of {len(text)} characters is over the limit of {max_size}")
    top: list[Sexp] = []
    stack: list[Sexp] = []
    cur: Sexp | None = None
    for tok in _TOKEN.findall(text):
        if tok == "(":
            if len(stack) >= max_depth:
                raise ProtocolError(f"nesting deeper than {max_depth}")
            new: Sexp = []
            if cur is not None:
                cur.append(new)
                stack.append(cur)
            else:
                top.append(new)
                stack.append(None)  # type: ignore[arg-type]  # marks the top level
            cur = new
        elif tok == ")":
            if cur is None:
                raise ProtocolError("unbalanced ')'")
            cur = stack.pop()
        elif cur is None:
            raise ProtocolError(f"atom {tok[:20]!r} outside any list")
        else:
            cur.append(tok)
    if cur is not None:
        raise ProtocolError(f"{len(stack)} unclosed '('")
    return top


# ------------------------------------------------------------------------- frames


def encode_frame(payload: str | bytes, max_size: int = MAX_MESSAGE) -> bytes:
    """payload with its 4-byte big-endian length in front."""
    if isinstance(payload, str):
        payload = payload.encode("ascii")
    if len(payload) > max_size:
        raise ProtocolError(f"frame of {len(payload)} bytes is over the limit of {max_size}")
    return HEADER.pack(len(payload)) + payload


class FrameReader:
    """Splits a byte stream into frames; holds at most one frame's bytes.

    `feed(data)` returns the frames completed by `data`. A header announcing more
    than `max_size` bytes raises ProtocolError (the stream cannot be resynchronized
    after that: close the connection).
    """

    def __init__(self, max_size: int = MAX_MESSAGE) -> None:
        self.max_size = max_size
        self._buf = bytearray()

    def feed(self, data: bytes) -> list[bytes]:
        buf = self._buf
        buf += data
        out = []
        while len(buf) >= 4:
            (n,) = HEADER.unpack_from(buf)
            if n > self.max_size:
                raise ProtocolError(f"frame of {n} bytes announced, over the limit of {self.max_size}")
            if len(buf) < 4 + n:
                break
            out.append(bytes(buf[4:4 + n]))
            del buf[:4 + n]
        return out

    @property
    def pending(self) -> int:
        """Bytes held for an incomplete frame."""
        return len(self._buf)


# ------------------------------------------------------------------------ numbers

_DEG = 180.0 / math.pi
_RAD = math.pi / 180.0


def _fmt(digits: int | None):
    """A formatter of one float: fixed `digits` decimals, or shortest exact (None)."""
    if digits is None:
        return repr
    spec = f".{digits}f"
    return lambda v: format(v, spec)


def _num(text, what: str) -> float:
    if not isinstance(text, str):
        raise ProtocolError(f"{what}: expected a number")
    try:
        v = float(text)
    except ValueError:
        raise ProtocolError(f"{what}: expected a number, got {text[:20]!r}") from None
    return v


def _int(text, what: str) -> int:
    if not isinstance(text, str):
        raise ProtocolError(f"{what}: expected a whole number")
    try:
        return int(text)
    except ValueError:
        raise ProtocolError(f"{what}: expected a whole number, got {text[:20]!r}") from None


def _to_simspark(v: np.ndarray) -> np.ndarray:
    """Project axes (x forward, y left, z up) -> SimSpark (x right, y forward, z up)."""
    return np.array([-v[1], v[0], v[2]], dtype=float)


def _from_simspark(x: float, y: float, z: float) -> np.ndarray:
    return np.array([y, -x, z])


FOOT_NAMES = {"lfoot": "lf", "rfoot": "rf", "ltoe": "lf1", "rtoe": "rf1"}  # sole -> FRP name
SOLE_Z = -0.01  # m, the sole's center below the foot's center (the foot box is 0.02 high)


def _sole_names(robot_type: int) -> list[str]:
    return ["lfoot", "rfoot"] + (["ltoe", "rtoe"] if nao.robot_type(robot_type).toe else [])


@functools.cache
def _joint_names(robot_type: int) -> tuple[str, ...]:
    """Perceptor names in the league's order (cached: `nao.joints` builds the link table)."""
    return tuple(nao.joint_names(robot_type))


@functools.cache
def _effector_names(robot_type: int) -> tuple[str, ...]:
    return tuple(j.effector for j in nao.joints(robot_type))


@functools.cache
def _soles(robot_type: int) -> tuple[str, ...]:
    return tuple(_sole_names(robot_type))


# ------------------------------------------------------------------------ percepts


def _pol(row, f) -> str:
    return f"(pol {f(float(row[0]))} {f(float(row[1]) * _DEG)} {f(float(row[2]) * _DEG)})"


def format_vision(v: Vision, team: str, opponent: str, digits: int | None = 2) -> str:
    """The See expression of a vision percept (polar: m, deg, deg)."""
    f = _fmt(digits)
    parts = ["(See"]
    for name, row in zip(v.landmark_names, v.landmarks):
        parts.append(f" ({name} {_pol(row, f)})")
    if v.ball is not None:
        parts.append(f" (B {_pol(v.ball, f)})")
    n = len(v.players)
    k = 0
    ours, unums, kinds = v.player_ours.tolist(), v.player_unum.tolist(), v.player_part.tolist()
    while k < n:  # consecutive parts of one robot form one P
        o, u = ours[k], unums[k]
        parts.append(f" (P (team {team if o else opponent}) (id {u})")
        while k < n and ours[k] == o and unums[k] == u:
            parts.append(f" ({SEEN_PARTS[kinds[k]]} {_pol(v.players[k], f)})")
            k += 1
        parts.append(")")
    for a, b in v.lines:
        parts.append(f" (L {_pol(a, f)} {_pol(b, f)})")
    parts.append(")")
    return "".join(parts)


def format_percept(p: Percept, team: str = "left", opponent: str = "right", first: bool = False,
                   digits: int | None = 2) -> str:
    """One percept as rcssserver3d writes it.

    `team`/`opponent` are the team names seen on other robots (P) and in hear;
    `first` adds the unum and side to GS, as the league does once after init;
    `digits` is the number of decimals (the league writes 2; None: exact).
    Order: time, GS, hear, GYR, ACC, head HJ, See, other HJ, FRP (the league's
    scene graph order; parsers must not depend on it).
    """
    f = _fmt(digits)
    out = [f"(time (now {f(float(p.time))}))(GS "]
    if first:
        out.append(f"(unum {p.unum}) (team {'left' if p.side == 'L' else 'right'}) ")
    out.append(f"(sl {p.score_left}) (sr {p.score_right}) (t {f(float(p.game_time))}) (pm {p.play_mode}))")
    for h in p.heard:
        speaker = opponent if h.team == "theirs" else team
        where = "self" if h.team == "self" else f(h.direction * _DEG)
        out.append(f"(hear {speaker} {f(float(h.time))} {where} {h.text})")
    g = (_to_simspark(p.gyro) * _DEG).tolist()
    a = _to_simspark(p.accel).tolist()
    out.append(f"(GYR (n torso) (rt {f(g[0])} {f(g[1])} {f(g[2])}))"
               f"(ACC (n torso) (a {f(a[0])} {f(a[1])} {f(a[2])}))")
    names = _joint_names(p.robot_type)
    deg = (np.asarray(p.joints, dtype=float) * _DEG).tolist()
    hj = [f"(HJ (n {n}) (ax {f(d)}))" for n, d in zip(names, deg)]
    out.extend(hj[:2])
    if p.vision is not None:
        out.append(format_vision(p.vision, team, opponent, digits))
    out.extend(hj[2:])
    for sole, force in zip(_soles(p.robot_type), np.asarray(p.foot_forces, dtype=float).tolist()):
        if force != 0.0:
            out.append(f"(FRP (n {FOOT_NAMES[sole]}) (c {f(0.0)} {f(0.0)} {f(SOLE_Z)})"
                       f" (f {f(0.0)} {f(0.0)} {f(force)}))")
    return "".join(out)


def _field(expr: Sexp, what: str) -> dict:
    """{key: [values]} of an expression's (key v ...) members."""
    out = {}
    for item in expr[1:]:
        if isinstance(item, list) and item and isinstance(item[0], str):
            out[item[0]] = item[1:]
    return out


def _vec(values, what: str, n: int = 3) -> list[float]:
    if values is None or len(values) < n:
        raise ProtocolError(f"{what}: expected {n} numbers")
    return [_num(v, what) for v in values[:n]]


def _polar(item, what: str) -> list[float]:
    if not (isinstance(item, list) and len(item) >= 4 and item[0] == "pol"):
        raise ProtocolError(f"{what}: expected (pol d h v)")
    d, h, v = (_num(x, what) for x in item[1:4])
    return [d, h * _RAD, v * _RAD]


class PerceptParser:
    """Reads the server's percepts into `Percept`s for one robot.

    It keeps what the league sends only once (unum, side after init; joint angles
    not repeated) and knows what the agent said at connect time (team name, robot
    type). Unknown expressions are ignored, as agents do; malformed known ones are
    a ProtocolError.
    """

    def __init__(self, team: str, robot_type: int = 0, unum: int = 0, side: str = "L") -> None:
        self.team = team
        self.robot_type = robot_type
        self.unum = unum
        self.side = side
        self.names = _joint_names(robot_type)
        self._index = {n: i for i, n in enumerate(self.names)}
        self.joints = np.zeros(len(self.names))
        self.soles = _sole_names(robot_type)
        self._sole_index = {FOOT_NAMES[s]: i for i, s in enumerate(self.soles)}
        self.time = 0.0
        self.game_time = 0.0
        self.play_mode = "BeforeKickOff"
        self.score = [0, 0]
        self.gyro = np.zeros(3)
        self.accel = np.zeros(3)

    def parse(self, text: str | bytes) -> Percept:
        """The percept of one server message (a ProtocolError when malformed)."""
        exprs = parse_sexp(text)
        forces = np.zeros(len(self.soles))
        vision = None
        heard: list[HeardMessage] = []
        joints = self.joints.copy()
        for e in exprs:
            if not e or not isinstance(e[0], str):
                continue
            tag = e[0]
            if tag == "HJ":
                fd = _field(e, "HJ")
                name = fd.get("n", [None])[0] if fd.get("n") else None
                i = self._index.get(name)  # type: ignore[arg-type]
                if i is not None:
                    joints[i] = _num((fd.get("ax") or [None])[0], f"HJ {name} ax") * _RAD
            elif tag == "time":
                self.time = _num((_field(e, "time").get("now") or [None])[0], "time now")
            elif tag == "GS":
                self._game_state(_field(e, "GS"))
            elif tag == "GYR":
                self.gyro = _from_simspark(*_vec(_field(e, "GYR").get("rt"), "GYR rt")) * _RAD
            elif tag == "ACC":
                self.accel = _from_simspark(*_vec(_field(e, "ACC").get("a"), "ACC a"))
            elif tag == "FRP":
                fd = _field(e, "FRP")
                name = (fd.get("n") or [None])[0]
                i = self._sole_index.get(name)  # type: ignore[arg-type]
                if i is not None:
                    forces[i] = _vec(fd.get("f"), "FRP f")[2]
            elif tag == "See":
                vision = self._see(e)
            elif tag == "hear":
                h = self._hear(e)
                if h is not None:
                    heard.append(h)
        self.joints = joints
        return Percept(
            time=self.time, game_time=self.game_time, play_mode=self.play_mode,
            score_left=self.score[0], score_right=self.score[1], side=self.side, unum=self.unum,
            robot_type=self.robot_type, joints=joints, gyro=self.gyro.copy(), accel=self.accel.copy(),
            foot_forces=forces, vision=vision, heard=tuple(heard))

    def _game_state(self, fd: dict) -> None:
        if "unum" in fd:
            self.unum = _int((fd["unum"] or [None])[0], "GS unum")
        if "team" in fd:
            side = (fd["team"] or [None])[0]
            if side not in ("left", "right"):
                raise ProtocolError(f"GS team must be left or right, got {side!r}")
            self.side = "L" if side == "left" else "R"
        if "sl" in fd:
            self.score[0] = _int((fd["sl"] or [None])[0], "GS sl")
        if "sr" in fd:
            self.score[1] = _int((fd["sr"] or [None])[0], "GS sr")
        if "t" in fd:
            self.game_time = _num((fd["t"] or [None])[0], "GS t")
        if "pm" in fd:
            pm = (fd["pm"] or [None])[0]
            if not isinstance(pm, str):
                raise ProtocolError("GS pm: expected a play mode name")
            self.play_mode = pm

    def _see(self, e: Sexp) -> Vision:
        names, marks, lines = [], [], []
        ours, unums, kinds, players = [], [], [], []
        ball = None
        for item in e[1:]:
            if not (isinstance(item, list) and item and isinstance(item[0], str)):
                continue
            tag = item[0]
            if tag == "B":
                ball = np.array(_polar(item[1] if len(item) > 1 else None, "See B"))
            elif tag == "L":
                if len(item) < 3:
                    raise ProtocolError("See L: expected two (pol ...)")
                lines.append([_polar(item[1], "See L"), _polar(item[2], "See L")])
            elif tag == "P":
                fd = _field(item, "P")
                team = (fd.get("team") or [None])[0]
                unum = _int((fd.get("id") or [None])[0], "See P id")
                for sub in item[1:]:
                    if isinstance(sub, list) and sub and sub[0] in SEEN_PARTS:
                        ours.append(team == self.team)
                        unums.append(unum)
                        kinds.append(SEEN_PARTS.index(sub[0]))
                        players.append(_polar(sub[1] if len(sub) > 1 else None, f"See P {sub[0]}"))
            elif tag[0] in "FG" and len(tag) == 3:
                names.append(tag)
                marks.append(_polar(item[1] if len(item) > 1 else None, f"See {tag}"))
        return Vision(
            landmark_names=tuple(names), landmarks=np.array(marks, dtype=float).reshape(-1, 3),
            ball=ball, lines=np.array(lines, dtype=float).reshape(-1, 2, 3),
            player_ours=np.array(ours, dtype=bool), player_unum=np.array(unums, dtype=np.int64),
            player_part=np.array(kinds, dtype=np.intp),
            players=np.array(players, dtype=float).reshape(-1, 3))

    def _hear(self, e: Sexp) -> HeardMessage | None:
        args = e[1:]
        if len(args) == 3:  # an older server: (hear TIME DIR MSG), no team
            team, args = self.team, args
        elif len(args) == 4:
            team, args = args[0], args[1:]
        else:
            raise ProtocolError(f"hear: expected 3 or 4 values, got {len(args)}")
        t, where, text = args
        if not all(isinstance(x, str) for x in (team, t, where, text)):
            raise ProtocolError("hear: expected atoms")
        t = _num(t, "hear time")
        if where == "self":
            return HeardMessage(t, "self", 0.0, text)
        direction = _num(where, "hear direction") * _RAD
        return HeardMessage(t, "ours" if team == self.team else "theirs", direction, text)


# ------------------------------------------------------------------------- actions


def format_action(a: Action, robot_type: int, syn: bool = True, digits: int | None = 5) -> str:
    """An agent's answer: every hinge effector (rad/s), then beam (m, m, deg), say and syn."""
    f = _fmt(digits)
    effs = _effector_names(robot_type)
    v = np.asarray(a.joint_velocities, dtype=float).tolist()
    out = [f"({e} {f(x)})" for e, x in zip(effs, v)]
    if a.beam is not None:
        x, y, th = (float(b) for b in a.beam)
        out.append(f"(beam {f(x)} {f(y)} {f(th * _DEG)})")
    if a.say is not None:
        out.append(f"(say {a.say})")
    if syn:
        out.append("(syn)")
    return "".join(out)


def format_scene(robot_type: int) -> str:
    return f"(scene {SCENE_PATH} {robot_type})"


def format_init(unum: int, team: str) -> str:
    return f"(init (unum {unum})(teamname {team}))"


@dataclass
class AgentMessage:
    """What one agent message says; `errors` lists the commands that were ignored."""

    scene: tuple[str, int] | None = None  # (rsg path, robot type)
    init: tuple[int, str] | None = None  # (unum, team name)
    velocities: dict[str, float] = field(default_factory=dict)  # effector name -> rad/s
    say: str | None = None
    beam: tuple[float, float, float] | None = None  # m, m, rad (team frame)
    syn: bool = False
    errors: list[str] = field(default_factory=list)


_EFFECTORS = frozenset(j.effector for t in range(5) for j in nao.joints(t))
TEAM_NAME = re.compile(r"[A-Za-z0-9_.\-]{1,32}\Z")


def parse_agent_message(text: str | bytes, max_size: int = MAX_AGENT_MESSAGE) -> AgentMessage:
    """Parse one agent message. A message that is no S-expression raises ProtocolError;
    a bad or unknown command inside a good one is skipped and named in `errors`."""
    msg = AgentMessage()
    for e in parse_sexp(text, max_size=max_size):
        if not e or not isinstance(e[0], str):
            msg.errors.append("empty or unnamed command")
            continue
        tag, args = e[0], e[1:]
        try:
            if tag in _EFFECTORS:
                if len(args) != 1:
                    raise ProtocolError(f"({tag} V): expected one velocity")
                v = _num(args[0], tag)
                if not math.isfinite(v):
                    raise ProtocolError(f"({tag} V): velocity must be finite")
                msg.velocities[tag] = v
            elif tag == "syn":
                msg.syn = True
            elif tag == "say":
                if len(args) != 1 or not isinstance(args[0], str):
                    raise ProtocolError("(say MSG): expected one word")
                msg.say = args[0]
            elif tag == "beam":
                if len(args) != 3:
                    raise ProtocolError("(beam X Y ROT): expected three numbers")
                x, y, rot = (_num(a, "beam") for a in args)
                if not all(math.isfinite(b) for b in (x, y, rot)):
                    raise ProtocolError("(beam X Y ROT): numbers must be finite")
                msg.beam = (x, y, rot * _RAD)
            elif tag == "scene":
                if not args or not isinstance(args[0], str):
                    raise ProtocolError("(scene PATH [TYPE]): expected a path")
                t = _int(args[1], "scene type") if len(args) > 1 else 0
                if t not in nao.TYPES:
                    raise ProtocolError(f"(scene PATH TYPE): unknown robot type {t}")
                msg.scene = (args[0], t)
            elif tag == "init":
                fd = _field(e, "init")
                unum = _int((fd.get("unum") or ["0"])[0], "init unum")
                names = fd.get("teamname") or [None]
                team = names[0] if len(names) == 1 else None
                if not isinstance(team, str) or not TEAM_NAME.match(team):
                    raise ProtocolError("(init (unum N)(teamname NAME)): NAME must be 1 to 32 of "
                                        "A-Z a-z 0-9 _ . -")
                if not 0 <= unum <= 11:
                    raise ProtocolError(f"init unum must be 0 (any) to 11, got {unum}")
                msg.init = (unum, team)
            else:
                raise ProtocolError(f"unknown command {tag[:20]!r}")
        except ProtocolError as exc:
            msg.errors.append(str(exc))
    return msg


def velocities(msg: AgentMessage, robot_type: int, previous: np.ndarray | None = None) -> np.ndarray:
    """The joint velocities (rad/s, league order) after `msg`: effectors not named keep
    their previous value, as SimSpark's motors do. Effectors of another robot type
    (lle7 on a type 0) are ignored."""
    effs = _effector_names(robot_type)
    out = np.zeros(len(effs)) if previous is None else np.array(previous, dtype=float)
    if msg.velocities:
        get = msg.velocities.get
        for i, e in enumerate(effs):
            v = get(e)
            if v is not None:
                out[i] = v
    return out


def parse_action(text: str | bytes, robot_type: int, previous: np.ndarray | None = None) -> Action:
    """An agent message as an Action (strict: any bad or unknown command raises ProtocolError).
    Joints it does not name keep `previous` (zeros when None)."""
    msg = parse_agent_message(text)
    if msg.errors:
        raise ProtocolError("; ".join(msg.errors))
    return Action(velocities(msg, robot_type, previous), say=msg.say, beam=msg.beam)
