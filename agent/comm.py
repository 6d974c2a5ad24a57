"""Team messages: the fields of Table 8.1 packed into at most 20 say characters.

Quantize-and-pack: every field becomes an unsigned integer of a fixed number of
bits, the bits are appended into one integer (most significant first), and the
integer is written in base 92 with the 92 characters the server allows
(0x21..0x7E less '(' and ')'): 20 characters carry 130 bits (UT Austin Villa
uses base 85 and 128 bits). Coordinates are in the team frame (own goal at -x),
which every teammate shares.

Layout (bits):

====================  ====  ==========================================================
field                 bits  range, resolution
====================  ====  ==========================================================
check                 10    keyed CRC-32 of the rest of the message, low 10 bits
time stamp            6     (server time / 20 ms) mod 64 of the cycle it was said
uniform number        4     1..11
self x, y             10+10 x in [-16, 16) step 1/32 m; y in [-11, 11) step 22/1024 m
self heading          6     [-pi, pi) step 5.625 deg
flags                 4     ball seen, fallen, not localized, role vote follows
ball x, y             10+10 (if ball seen) as self x, y
role vote             22    (if flagged) permutation of 10 roles, Lehmer code (10! < 2^22)
optional sections     ...   3-bit tag then payload, in this priority, while they fit:
  1 kick target       16    x 8 bits step 1/8 m; y 7 bits step 22/128 m; behind ball 1
  2 teammate          24    unum 4; x, y 8 bits each (1/8 m, 22/256 m); heading 4 (22.5 deg)
  3 opponent          25    as teammate plus fallen 1
  4 robot type        3     0..4
  0 end               3     (or the bits run out)
====================  ====  ==========================================================

Against Table 8.1: the fallen and not-localized flags take 1 bit each instead
of 5-bit tags, the role assignment vector (10 x 5 bits there) is sent as a
permutation in 22 bits, and 16 bits buy the team/time check. The always-sent
header is 50 bits; with the ball (20), a vote (22) and a kick (19) a message
holds 111 bits, and the remaining 19 are too few for a player report (27), which
then waits for a message without a vote or kick.

Values are quantized to the centers of their bins (clamped into range), so a
quantized message round-trips exactly. Decoding returns None for anything that
is not one of our messages: wrong length or alphabet, a value out of range, a
bad check, a time stamp that does not match the cycle it was heard in, or a
message from the other team.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass, field, replace

from models.geometry import wrap
from models.messages import HeardMessage
from models.rules import CYCLE, SAY_ALPHABET, SAY_MAX_LENGTH, TEAM_SIZE

ALPHABET = "".join(sorted(SAY_ALPHABET))
BASE = len(ALPHABET)  # 92
_DIGIT = {c: i for i, c in enumerate(ALPHABET)}
BITS = int(SAY_MAX_LENGTH * math.log2(BASE))  # 130
KEY = b"mujoco-villa-3d"  # mixed into the check: other codecs' messages fail it

CHECK_BITS = 10
TIME_BITS = 6
TAG_BITS = 3
TAG_END, TAG_KICK, TAG_TEAMMATE, TAG_OPPONENT, TAG_TYPE = range(5)
VOTE_ROLES = 10
VOTE_BITS = 22
MAX_DELAY_CYCLES = 2  # a message may be heard up to this many cycles after it was said


@dataclass(frozen=True)
class Quantity:
    """A real value in [lo, hi) stored in `bits` bits (bin centers)."""

    lo: float
    hi: float
    bits: int

    @property
    def step(self) -> float:
        return (self.hi - self.lo) / (1 << self.bits)

    def index(self, v: float) -> int:
        i = int(math.floor((v - self.lo) / self.step))
        return min(max(i, 0), (1 << self.bits) - 1)

    def value(self, i: int) -> float:
        return self.lo + (i + 0.5) * self.step

    def quantize(self, v: float) -> float:
        return self.value(self.index(v))


X10 = Quantity(-16.0, 16.0, 10)
Y10 = Quantity(-11.0, 11.0, 10)
X8 = Quantity(-16.0, 16.0, 8)
Y8 = Quantity(-11.0, 11.0, 8)
Y7 = Quantity(-11.0, 11.0, 7)
ANGLE6 = Quantity(-math.pi, math.pi, 6)
ANGLE4 = Quantity(-math.pi, math.pi, 4)


@dataclass(frozen=True)
class PlayerReport:
    """Where the sender sees another robot (team frame; m, m, rad)."""

    unum: int
    x: float
    y: float
    heading: float
    fallen: bool = False  # sent for opponents only


@dataclass(frozen=True)
class KickTarget:
    """Where the sender is about to kick the ball (team frame, m)."""

    x: float
    y: float
    behind_ball: bool = False


@dataclass(frozen=True)
class TeamMessage:
    """The content of one say message (Table 8.1), team frame, SI units."""

    unum: int
    x: float
    y: float
    heading: float
    ball: tuple[float, float] | None = None
    fallen: bool = False
    not_localized: bool = False
    role_vote: tuple[int, ...] | None = None  # permutation of range(10)
    kick: KickTarget | None = None
    teammates: tuple[PlayerReport, ...] = ()
    opponents: tuple[PlayerReport, ...] = ()
    robot_type: int | None = None
    time: float = 0.0  # s, server time of the cycle it is said in (not sent beyond the stamp)
    extra: dict = field(default_factory=dict, compare=False, repr=False)


# ---------------------------------------------------------------- bit packing


class _Writer:
    def __init__(self) -> None:
        self.value = 0
        self.used = 0

    def put(self, v: int, bits: int) -> None:
        assert 0 <= v < (1 << bits)
        self.value = (self.value << bits) | v
        self.used += bits


class _Reader:
    def __init__(self, value: int, bits: int) -> None:
        self.value = value
        self.left = bits

    def get(self, bits: int) -> int:
        if bits > self.left:
            raise ValueError("message too short")
        self.left -= bits
        return (self.value >> self.left) & ((1 << bits) - 1)


def _lehmer(perm: tuple[int, ...]) -> int:
    items = list(range(len(perm)))
    code = 0
    for p in perm:
        i = items.index(p)
        code = code * len(items) + i
        items.pop(i)
    return code


def _unlehmer(code: int, n: int) -> tuple[int, ...]:
    digits = []
    for base in range(1, n + 1):
        digits.append(code % base)
        code //= base
    if code:
        raise ValueError("role vote out of range")
    items = list(range(n))
    return tuple(items.pop(d) for d in reversed(digits))


def _check(payload: int, payload_bits: int) -> int:
    raw = payload.to_bytes((payload_bits + 7) // 8, "big")
    return zlib.crc32(KEY + raw) & ((1 << CHECK_BITS) - 1)


def _stamp(time: float) -> int:
    return int(round(time / CYCLE)) % (1 << TIME_BITS)


def _report_bits(kind: int) -> int:
    return TAG_BITS + (4 + 8 + 8 + 4 + (1 if kind == TAG_OPPONENT else 0))


def quantize(msg: TeamMessage) -> TeamMessage:
    """The message as the receiver will see it: values on their bins, optional
    sections that do not fit left out, `time` kept."""
    _, sent = _encode(msg)
    return sent


def encode(msg: TeamMessage) -> str:
    """The say text (20 characters of the allowed alphabet) for a message; optional
    sections that do not fit are left out (see `quantize`)."""
    return _encode(msg)[0]


def _validate(msg: TeamMessage) -> None:
    if not 1 <= msg.unum <= TEAM_SIZE:
        raise ValueError(f"uniform number {msg.unum} outside 1..{TEAM_SIZE}")
    if msg.role_vote is not None and sorted(msg.role_vote) != list(range(VOTE_ROLES)):
        raise ValueError(f"role vote must be a permutation of range({VOTE_ROLES})")
    for r in msg.teammates + msg.opponents:
        if not 1 <= r.unum <= TEAM_SIZE:
            raise ValueError(f"reported uniform number {r.unum} outside 1..{TEAM_SIZE}")
    if msg.robot_type is not None and not 0 <= msg.robot_type <= 4:
        raise ValueError(f"robot type {msg.robot_type} outside 0..4")


def _encode(msg: TeamMessage) -> tuple[str, TeamMessage]:
    _validate(msg)
    w = _Writer()
    w.put(_stamp(msg.time), TIME_BITS)
    w.put(msg.unum, 4)
    w.put(X10.index(msg.x), 10)
    w.put(Y10.index(msg.y), 10)
    w.put(ANGLE6.index(wrap(msg.heading)), 6)
    for flag in (msg.ball is not None, msg.fallen, msg.not_localized, msg.role_vote is not None):
        w.put(int(flag), 1)
    ball = None
    if msg.ball is not None:
        ix, iy = X10.index(msg.ball[0]), Y10.index(msg.ball[1])
        w.put(ix, 10)
        w.put(iy, 10)
        ball = (X10.value(ix), Y10.value(iy))
    if msg.role_vote is not None:
        w.put(_lehmer(tuple(msg.role_vote)), VOTE_BITS)
    room = BITS - CHECK_BITS
    kick = None
    if msg.kick is not None and w.used + TAG_BITS + 16 <= room:
        k = msg.kick
        ix, iy = X8.index(k.x), Y7.index(k.y)
        w.put(TAG_KICK, TAG_BITS)
        w.put(ix, 8)
        w.put(iy, 7)
        w.put(int(k.behind_ball), 1)
        kick = KickTarget(X8.value(ix), Y7.value(iy), bool(k.behind_ball))
    sent_reports: dict[int, list[PlayerReport]] = {TAG_TEAMMATE: [], TAG_OPPONENT: []}
    for tag, reports in ((TAG_TEAMMATE, msg.teammates), (TAG_OPPONENT, msg.opponents)):
        for r in reports:
            if w.used + _report_bits(tag) > room:
                break
            ix, iy, ih = X8.index(r.x), Y8.index(r.y), ANGLE4.index(wrap(r.heading))
            w.put(tag, TAG_BITS)
            w.put(r.unum, 4)
            w.put(ix, 8)
            w.put(iy, 8)
            w.put(ih, 4)
            fallen = False
            if tag == TAG_OPPONENT:
                fallen = bool(r.fallen)
                w.put(int(fallen), 1)
            sent_reports[tag].append(PlayerReport(r.unum, X8.value(ix), Y8.value(iy),
                                                  ANGLE4.value(ih), fallen))
    robot_type = None
    if msg.robot_type is not None and w.used + TAG_BITS + 3 <= room:
        w.put(TAG_TYPE, TAG_BITS)
        w.put(msg.robot_type, 3)
        robot_type = msg.robot_type
    payload_bits = room
    payload = w.value << (room - w.used)  # zero padding reads as TAG_END
    value = (_check(payload, payload_bits) << payload_bits) | payload
    digits = []
    for _ in range(SAY_MAX_LENGTH):
        value, d = divmod(value, BASE)
        digits.append(ALPHABET[d])
    text = "".join(reversed(digits))
    sent = TeamMessage(
        unum=msg.unum, x=X10.quantize(msg.x), y=Y10.quantize(msg.y),
        heading=ANGLE6.quantize(wrap(msg.heading)), ball=ball, fallen=bool(msg.fallen),
        not_localized=bool(msg.not_localized),
        role_vote=None if msg.role_vote is None else tuple(msg.role_vote), kick=kick,
        teammates=tuple(sent_reports[TAG_TEAMMATE]), opponents=tuple(sent_reports[TAG_OPPONENT]),
        robot_type=robot_type, time=msg.time)
    return text, sent


def decode(text: str, heard_time: float | None = None) -> TeamMessage | None:
    """The message in a say text, or None if it is not a valid message of this codec.

    heard_time (s): the server time the message was heard at; when given, the
    message's stamp must be 1 to MAX_DELAY_CYCLES cycles (or 0) before it. The
    returned message's `time` is the cycle it was said in (heard_time minus the
    delay), or 0 when heard_time is None.
    """
    if not isinstance(text, str) or len(text) != SAY_MAX_LENGTH:
        return None
    value = 0
    for ch in text:
        d = _DIGIT.get(ch)
        if d is None:
            return None
        value = value * BASE + d
    if value >> BITS:
        return None
    payload_bits = BITS - CHECK_BITS
    payload = value & ((1 << payload_bits) - 1)
    if value >> payload_bits != _check(payload, payload_bits):
        return None
    try:
        msg = _parse(_Reader(payload, payload_bits))
    except ValueError:
        return None
    if heard_time is None:
        return msg
    now = int(round(heard_time / CYCLE))
    stamp = msg.extra["stamp"]
    for delay in range(0, MAX_DELAY_CYCLES + 1):
        if (now - delay) % (1 << TIME_BITS) == stamp:
            return replace(msg, time=round((now - delay) * CYCLE, 6))
    return None


def _parse(r: _Reader) -> TeamMessage:
    stamp = r.get(TIME_BITS)
    unum = r.get(4)
    if not 1 <= unum <= TEAM_SIZE:
        raise ValueError("bad uniform number")
    x, y, h = X10.value(r.get(10)), Y10.value(r.get(10)), ANGLE6.value(r.get(6))
    has_ball, fallen, not_localized, has_vote = (bool(r.get(1)) for _ in range(4))
    ball = (X10.value(r.get(10)), Y10.value(r.get(10))) if has_ball else None
    vote = _unlehmer(r.get(VOTE_BITS), VOTE_ROLES) if has_vote else None
    kick = None
    mates: list[PlayerReport] = []
    opps: list[PlayerReport] = []
    robot_type = None
    last_tag = 0
    while r.left >= TAG_BITS:
        tag = r.get(TAG_BITS)
        if tag == TAG_END:
            if r.value & ((1 << r.left) - 1):
                raise ValueError("bits after the end tag")
            break
        if tag < last_tag or (tag == last_tag and tag in (TAG_KICK, TAG_TYPE)):
            raise ValueError("sections out of order")
        last_tag = tag
        if tag == TAG_KICK:
            kick = KickTarget(X8.value(r.get(8)), Y7.value(r.get(7)), bool(r.get(1)))
        elif tag in (TAG_TEAMMATE, TAG_OPPONENT):
            u = r.get(4)
            if not 1 <= u <= TEAM_SIZE:
                raise ValueError("bad reported uniform number")
            px, py, ph = X8.value(r.get(8)), Y8.value(r.get(8)), ANGLE4.value(r.get(4))
            if tag == TAG_TEAMMATE:
                mates.append(PlayerReport(u, px, py, ph))
            else:
                opps.append(PlayerReport(u, px, py, ph, bool(r.get(1))))
        elif tag == TAG_TYPE:
            robot_type = r.get(3)
            if robot_type > 4:
                raise ValueError("bad robot type")
        else:
            raise ValueError("unknown section")
    else:
        if r.left and r.value & ((1 << r.left) - 1):
            raise ValueError("trailing bits")
    return TeamMessage(unum=unum, x=x, y=y, heading=h, ball=ball, fallen=fallen,
                       not_localized=not_localized, role_vote=vote, kick=kick, teammates=tuple(mates),
                       opponents=tuple(opps), robot_type=robot_type, extra={"stamp": stamp})


def decode_heard(heard: HeardMessage) -> TeamMessage | None:
    """A heard message decoded if it comes from a teammate and is valid, else None."""
    if heard.team != "ours":
        return None
    return decode(heard.text, heard.time)


def may_speak(unum: int, time: float, team_size: int = TEAM_SIZE) -> bool:
    """The rotating time slot: whether player `unum` may say something in the cycle at
    `time` (s). The team speaks every other cycle (a listener hears one teammate per
    two cycles) and the turn passes by uniform number: 1, 2, ..., team_size, 1, ..."""
    cycle = int(round(time / CYCLE))
    return cycle % 2 == 0 and (cycle // 2) % team_size == unum - 1
