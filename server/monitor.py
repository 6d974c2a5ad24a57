"""The league's monitor port (rcssserver3d's 3200): a live scene graph for RoboViz.

A monitor connects over TCP and gets the same 4-byte big-endian length frames as
agents. Each frame is three S-expressions, the "legacy" (pre-RSMP) format RoboViz
reads (`rv.comm.rcssserver.MessageParser`):

1. the game state, a list of `(name value)` pairs: in a monitor's first frame the
   field's measures, the rules, `(play_modes ...)` (RoboViz maps the play_mode
   index through this list), the team names, time, half, score and play mode; in
   later frames only time, half, play mode and score;
2. the scene graph header, `(RSG 0 1)` for a full graph or `(RDS 0 1)` for a delta;
3. the scene graph: a list of nodes `(nd TYPE ...)`. The full graph declares two
   lights, the field and the goals, the ball and one top-level node per robot
   whose children are the robot's body parts, each a transform node
   `(nd TRF (SLT m00 m10 m20 0 m01 m11 m21 0 m02 m12 m22 0 x y z 1) ...)` (the
   4x4 world transform, column-major) holding the part's mesh: the standard Nao
   meshes RoboViz ships (models/naobody.obj, naohead.obj, [lr]upperarm.obj,
   [lr]lowerarm.obj, [lr]thigh.obj, [lr]shank.obj, [lr]foot.obj, the ball's
   soccerball.obj) or SimSpark's primitives for the joints. RoboViz finds a robot
   as the top-level node holding a mesh with the materials `matNum<unum>` and
   `matLeft`/`matRight`. A delta repeats the graph's shape with `(nd)` for nodes
   that did not change and `(nd (SLT ...))` for a transform with a new matrix.

Transforms are in the league's frame (the project's world frame: x toward the
right team's goal, y left, z up; meters) and a body part's axes are SimSpark's
(x right, y forward, z up), so a robot standing at the origin facing +x has the
rotation columns (0 -1 0), (1 0 0), (0 0 1).

Monitor commands (RoboViz's server controls) are read and some applied between
cycles: `(kickOff Left|Right)`, `(playMode NAME)`, `(ball (pos X Y Z) [(vel X Y
Z)])`, `(dropBall)`, `(reqfullstate)` (the next frame is a full graph); `(init)`
and others are ignored. A monitor that sends malformed input gets it logged and
skipped; an oversized frame (over `MAX_MONITOR_MESSAGE`) drops the monitor, and a
monitor that does not read is skipped (its frames are not queued beyond
`MAX_MONITOR_OUTGOING`) until it catches up. No monitor connected costs one
`select` per update; no monitor port costs nothing.
"""

from __future__ import annotations

import logging
import select
import socket

import mujoco
import numpy as np

from models import field, nao
from models.rules import FREE_KICK_DISTANCE, GOAL_PAUSE, PlayMode
from server.connection import Connection
from server.protocol import ProtocolError, encode_frame, parse_sexp

log = logging.getLogger(__name__)

MAX_MONITOR_MESSAGE = 1 << 12  # bytes of one command from a monitor (RoboViz's are < 100)
MAX_MONITOR_OUTGOING = 1 << 21  # bytes of unsent frames before updates to a monitor are skipped
MAX_ACCEPTS = 8  # new monitors accepted per update

# rcssserver3d's play mode list, in its order: the game state's play_mode is an index into it.
MONITOR_PLAY_MODES = (
    "BeforeKickOff", "KickOff_Left", "KickOff_Right", "PlayOn", "KickIn_Left", "KickIn_Right",
    "corner_kick_left", "corner_kick_right", "goal_kick_left", "goal_kick_right",
    "offside_left", "offside_right", "GameOver", "Goal_Left", "Goal_Right",
    "free_kick_left", "free_kick_right", "direct_free_kick_left", "direct_free_kick_right",
    "pass_left", "pass_right",
)
MODE_INDEX = {PlayMode(name): k for k, name in enumerate(MONITOR_PLAY_MODES)
              if name in PlayMode._value2member_map_}

# A body part's rotation in SimSpark's axes = its MuJoCo body rotation (project axes) @ TO_SIMSPARK.
TO_SIMSPARK = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
# The Nao body and head meshes (and the field) are modeled y-up: x -> -x, y -> z, z -> y.
MESH_Y_UP = "(nd TRF (SLT -1 0 0 0 0 0 1 0 0 1 0 0 0 0 0 1)"
SLT_FORMAT = "%.4f %.4f %.4f 0 %.4f %.4f %.4f 0 %.4f %.4f %.4f 0 %.4f %.4f %.4f 1"
IDENTITY = "(SLT 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1)"


def _mesh(model: str, scale: float, materials: str, y_up: bool = False) -> str:
    node = (f"(nd StaticMesh (setVisible 1) (load models/{model}) (sSc {scale:g} {scale:g} {scale:g})"
            f" (resetMaterials {materials}))")
    return f"{MESH_Y_UP}{node})" if y_up else node


def _primitive(load: str, scale: str, material: str) -> str:
    return f"(nd SMN (setVisible 1) (load {load}) (sSc {scale}) (sMat {material}))"


def part_nodes(link: str, side: str, unum: int) -> str:
    """The mesh node(s) under a body part's transform node."""
    team = "matLeft" if side == "L" else "matRight"
    num = f"matNum{unum}"
    if link == "torso":
        return _mesh("naobody.obj", 0.1, f"{num} {team} naoblack naowhite", y_up=True)
    if link == "head":
        return _mesh("naohead.obj", 0.1, f"{team} naoblack naogrey naowhite", y_up=True)
    if link == "neck":
        return _primitive("StdCapsule 0.015 0.08", "1 1 1", "matDarkGrey")
    kind = link[1:]
    if kind in ("shoulder", "elbow", "hip1", "hip2"):
        return _primitive("StdUnitSphere", "0.01 0.01 0.01", "matYellow")
    if kind == "ankle":
        return _primitive("StdUnitSphere", "0.01 0.01 0.01", "matRed")
    if kind == "toe":
        return _primitive("StdUnitBox", f"0.08 {nao.TOE_LENGTH:g} 0.02", "matGrey")
    scale = {"upperarm": 0.07, "lowerarm": 0.05, "thigh": 0.07, "shank": 0.08, "foot": 0.08}[kind]
    mats = {"upperarm": f"{team} naoblack naowhite", "lowerarm": f"{team} naowhite",
            "thigh": f"{num} {team} naowhite" if link[0] == "r" else f"{team} naowhite",
            "shank": f"{team} naoblack naowhite", "foot": f"{team} naowhite"}[kind]
    return _mesh(f"{link}.obj", scale, mats)


def part_order(robot_type: int) -> list[str]:
    """A robot's body parts in the order of its monitor node's children (rcssserver3d's)."""
    toe = nao.robot_type(robot_type).toe
    arm = ["shoulder", "upperarm", "elbow", "lowerarm"]
    leg = ["hip1", "hip2", "thigh", "shank", "ankle", "foot"] + (["toe"] if toe else [])
    return (["torso", "neck", "head"] + [f"r{k}" for k in arm] + [f"l{k}" for k in arm]
            + [f"r{k}" for k in leg] + [f"l{k}" for k in leg])


def _static_scene() -> str:
    """Lights, field and goals (never updated)."""
    y_up = "(SLT -1 0 0 0 0 0 1 0 0 1 0 0 0 0 0 1)"
    goal_mesh = "(SLT 0 1 0 0 0 0 1 0 1 0 0 0 0.3 0 -0.4 1)"
    gx = field.HALF_LENGTH + field.GOAL_DEPTH / 2
    gz = field.GOAL_HEIGHT / 2
    goal_scale = (f"{field.GOAL_WIDTH + 0.08:g} {field.GOAL_HEIGHT + 0.08:g}"
                  f" {field.GOAL_DEPTH + 0.08:g}")
    return (
        f"(nd TRF (SLT 1 0 0 0 0 1 0 0 0 0 1 0 -10 10 10 1)"
        f"(nd Light (setDiffuse 1 1 1 1) (setAmbient 0.8 0.8 0.8 1) (setSpecular 0.1 0.1 0.1 1)))"
        f"(nd TRF (SLT 1 0 0 0 0 1 0 0 0 0 1 0 10 -10 10 1)"
        f"(nd Light (setDiffuse 1 1 1 1) (setAmbient 0 0 0 1) (setSpecular 0.1 0.1 0.1 1)))"
        f"(nd TRF {y_up}(nd StaticMesh (setVisible 1) (load models/naosoccerfield.obj)"
        f" (sSc {field.FIELD_LENGTH / 12:g} 1 {field.FIELD_WIDTH / 8:g})"
        f" (resetMaterials None_rcs-naofield.png)))"
        f"(nd TRF (SLT 1 0 0 0 0 1 0 0 0 0 1 0 {-gx:g} 0 {gz:g} 1)(nd TRF {goal_mesh}"
        f"(nd StaticMesh (setVisible 1) (setTransparent) (load models/leftgoal.obj)"
        f" (sSc {goal_scale}) (resetMaterials grey_naogoalnet.png yellow))))"
        f"(nd TRF (SLT -1 0 0 0 0 -1 0 0 0 0 1 0 {gx:g} 0 {gz:g} 1)(nd TRF {goal_mesh}"
        f"(nd StaticMesh (setVisible 1) (setTransparent) (load models/rightgoal.obj)"
        f" (sSc {goal_scale}) (resetMaterials grey_naogoalnet.png sky-blue white))))"
    )


STATIC_NODES = 5  # top-level nodes of _static_scene


class MonitorScene:
    """The scene graph of one World: which bodies the dynamic nodes follow, and the
    full and delta messages."""

    def __init__(self, world) -> None:
        m = world.model
        self.world = world
        # The world's xpos/xmat are from the start of the last physics substep; the monitor
        # runs the kinematics of the current qpos on its own MjData (the world's stays as is).
        self._data = mujoco.MjData(m)
        ids: list[int] = [world.ball_body]
        robots: list[list[int]] = []
        full = [_static_scene(),
                f"(nd TRF (SLT %s)(nd StaticMesh (setVisible 1) (load models/soccerball.obj)"
                f" (sSc {field.BALL_RADIUS:g} {field.BALL_RADIUS:g} {field.BALL_RADIUS:g})"
                f" (resetMaterials soccerball_rcs-soccerball.png)))"]
        delta = ["(nd)" * STATIC_NODES, "(nd (SLT %s))"]
        for p in world.players:
            prefix = f"{p.side}{p.unum}/"
            parts = part_order(p.robot_type)
            body = [m.body(prefix + name).id for name in parts]
            robots.append(body)
            ids.extend(body)
            full.append(f"(nd TRF {IDENTITY}"
                        + "".join(f"(nd TRF (SLT %s){part_nodes(name, str(p.side), p.unum)})"
                                  for name in parts) + ")")
            delta.append("(nd" + "(nd (SLT %s))" * len(parts) + ")")
        self.body_ids = np.array(ids)
        self.robot_bodies = robots
        self.n_dynamic = len(ids)
        # Rotation fix per dynamic node: the ball keeps its own axes, robot parts go to SimSpark's.
        self._fix = np.stack([np.eye(3)] + [TO_SIMSPARK] * (len(ids) - 1))
        # One format string per message; 12 numbers (4 decimals: 0.1 mm) per transform.
        self._full = "(" + "".join(full).replace("%s", SLT_FORMAT) + ")"
        self._delta = "(" + "".join(delta).replace("%s", SLT_FORMAT) + ")"

    def transforms(self) -> np.ndarray:
        """(n_dynamic, 12): each node's rotation columns then translation (league frame)."""
        d = self._data
        d.qpos[:] = self.world.data.qpos
        mujoco.mj_kinematics(self.world.model, d)
        ids = self.body_ids
        rot = d.xmat[ids].reshape(-1, 3, 3) @ self._fix
        out = np.empty((len(ids), 12))
        out[:, 0:9] = rot.transpose(0, 2, 1).reshape(-1, 9)  # column-major
        out[:, 9:12] = d.xpos[ids]
        return out

    def values(self) -> tuple[float, ...]:
        """The numbers of every dynamic node's SLT, in message order."""
        return tuple(self.transforms().ravel().tolist())

    def graph(self, full: bool, values: tuple[float, ...] | None = None) -> str:
        """The scene graph header and graph, full or delta."""
        values = self.values() if values is None else values
        return ("(RSG 0 1)" + self._full % values) if full else ("(RDS 0 1)" + self._delta % values)


def game_state(match, full: bool) -> str:
    """The game state expression of a Match (see the module's docstring)."""
    ref = match.referee
    mode = MODE_INDEX[ref.mode]
    now = (f"(time {ref.game_time:.2f})(half {ref.half})(score_left {ref.score['L']})"
           f"(score_right {ref.score['R']})(play_mode {mode})")
    if not full:
        return f"({now})"
    left, right = match.team_names
    return (f"((FieldLength {field.FIELD_LENGTH:g})(FieldWidth {field.FIELD_WIDTH:g})(FieldHeight 40)"
            f"(GoalWidth {field.GOAL_WIDTH:g})(GoalDepth {field.GOAL_DEPTH:g})"
            f"(GoalHeight {field.GOAL_HEIGHT:g})(BorderSize 0)(FreeKickDistance {FREE_KICK_DISTANCE:g})"
            f"(CenterCircleRadius {field.CENTER_CIRCLE_RADIUS:g})"
            f"(PenaltyAreaLength {field.PENALTY_DEPTH:g})(PenaltyAreaWidth {field.PENALTY_WIDTH:g})"
            f"(AgentRadius 0.4)(BallRadius {field.BALL_RADIUS:g})(BallMass {field.BALL_MASS:g})"
            f"(RuleGoalPauseTime {GOAL_PAUSE:g})(RuleHalfTime {match.half_time:g})"
            f"(play_modes {' '.join(MONITOR_PLAY_MODES)})(team_left {left})(team_right {right})"
            f"{now})")


class MonitorClient(Connection):
    """One monitor connection."""

    def __init__(self, sock: socket.socket, addr) -> None:
        super().__init__(sock, addr, MAX_MONITOR_MESSAGE)
        self.needs_full = True
        self.commands: list[list] = []
        self.skipped = 0

    @property
    def name(self) -> str:
        return f"monitor {self.addr[0]}:{self.addr[1]}"

    def close(self, why: str) -> None:
        if self.closed is None:
            log.info("%s closed: %s", self.name, why)
        super().close(why)

    def send(self, frame: bytes) -> bool:
        """Queue a frame unless too much is unsent already (then it is skipped)."""
        if self.closed:
            return False
        if len(self.out) > MAX_MONITOR_OUTGOING:
            self.skipped += 1
            return False
        self.out += frame
        self.flush()
        return True

    def receive(self) -> None:
        for f in self.read_frames():
            try:
                self.commands.extend(parse_sexp(f, max_size=MAX_MONITOR_MESSAGE))
            except ProtocolError as exc:
                self.error(f"malformed command: {exc}")


def _vec(items, key: str) -> tuple[float, float, float] | None:
    for it in items:
        if isinstance(it, list) and it and it[0] == key:
            if len(it) != 4 or not all(isinstance(v, str) for v in it[1:]):
                raise ValueError(f"({key} X Y Z) expected")
            v = tuple(float(x) for x in it[1:])
            if not all(np.isfinite(v)) or max(abs(x) for x in v) > 100:
                raise ValueError(f"{key} out of range")
            return v  # type: ignore[return-value]
    return None


class MonitorServer:
    """The monitor port: accepts monitors and sends them the scene every `interval` cycles."""

    def __init__(self, host: str = "127.0.0.1", port: int = 3200, interval: int = 1) -> None:
        if interval < 1:
            raise ValueError(f"interval must be at least 1 cycle, got {interval}")
        self.listener = socket.create_server((host, port))
        self.listener.setblocking(False)
        self.address = self.listener.getsockname()[:2]
        self.interval = interval
        self.clients: list[MonitorClient] = []
        self.scene: MonitorScene | None = None
        self.frames = 0  # updates built

    # ---------------------------------------------------------------- sockets

    def poll(self, match=None) -> None:
        """Accept monitors, read their commands (applied to `match` when given), write."""
        socks = [self.listener] + [c.sock for c in self.clients]
        writers = [c.sock for c in self.clients if c.out]
        try:
            readable, writable, _ = select.select(socks, writers, [], 0)
        except (OSError, ValueError):  # a socket closed under us; drop the closed ones
            readable, writable = [], []
        by_sock = {c.sock: c for c in self.clients}
        for s in readable:
            if s is self.listener:
                for _ in range(MAX_ACCEPTS):
                    try:
                        sock, addr = self.listener.accept()
                    except (BlockingIOError, InterruptedError, OSError):
                        break
                    c = MonitorClient(sock, addr)
                    self.clients.append(c)
                    log.info("%s connected", c.name)
            else:
                by_sock[s].receive()
        for s in writable:
            c = by_sock.get(s)
            if c is not None:
                c.flush()
        for c in self.clients:
            if c.commands:
                cmds, c.commands = c.commands, []
                for cmd in cmds:
                    self._command(c, cmd, match)
        self.clients = [c for c in self.clients if not c.closed]

    def _command(self, c: MonitorClient, cmd: list, match) -> None:
        try:
            head = cmd[0] if cmd and isinstance(cmd[0], str) else None
            if head in ("init", "syn"):
                return
            if head == "reqfullstate":
                c.needs_full = True
                return
            if match is None:
                return
            ref, w = match.referee, match.world
            if head == "kickOff" and len(cmd) == 2 and cmd[1] in ("Left", "Right"):
                side = "L" if cmd[1] == "Left" else "R"
                ref._kickoff(side)
            elif head == "playMode" and len(cmd) == 2 and isinstance(cmd[1], str):
                ref.set_play_mode(PlayMode(cmd[1]))  # ValueError for modes we do not have
            elif head == "ball":
                pos, vel = _vec(cmd[1:], "pos"), _vec(cmd[1:], "vel")
                if pos is not None:
                    w.place_ball(pos[:2], z=max(pos[2], field.BALL_RADIUS))
                if vel is not None:
                    w.set_ball_velocity(vel)
            elif head == "dropBall":
                ref.set_play_mode(PlayMode.PLAY_ON)
            else:
                c.error(f"command ignored: {str(cmd)[:60]}")
        except (ValueError, KeyError, TypeError, IndexError) as exc:
            c.error(f"bad command {str(cmd)[:60]}: {exc}")

    # ---------------------------------------------------------------- updates

    def update(self, match) -> None:
        """After a cycle: accept, read, and send every monitor its frame."""
        if match.cycle % self.interval:
            return
        self.poll(match)
        if not self.clients:
            return
        if self.scene is None or self.scene.world is not match.world:
            self.scene = MonitorScene(match.world)
        self.send(match)

    def send(self, match) -> None:
        scene = self.scene
        values = scene.values()
        full = delta = None
        for c in self.clients:
            if c.needs_full:
                if full is None:
                    full = encode_frame(game_state(match, True) + scene.graph(True, values))
                if c.send(full):
                    c.needs_full = False
            else:
                if delta is None:
                    delta = encode_frame(game_state(match, False) + scene.graph(False, values))
                c.send(delta)
        self.frames += 1

    def close(self) -> None:
        for c in self.clients:
            c.flush()
            c.close("match over")
        self.clients = []
        try:
            self.listener.close()
        except OSError:
            pass
