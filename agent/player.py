"""One villa player: percept -> world model -> team decision -> role -> body -> Action.

The pipeline of ../shared/DESIGN.md's team layer. Every cycle the world model
folds in the percept; the decision layer (`agent.strategy`, pure functions of
a `TeamView` snapshot) says who takes the ball, votes a role mapping and picks
where to kick; the player's role turns that into one skill request
(`agent.requests`); the body (`agent.body.Body`) plays it. The team message
carries the player's vote and, on the ball, its kick target.

Frames: the team frame (own goal at -x; m, rad) throughout.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from agent import comm
from agent import strategy as st
from agent.body import Body
from agent.requests import Dive, Dribble, Kick, SkillRequest, Stand, WalkTo
from agent.teamconfig import VILLA, TeamConfig
from agent.worldmodel import WorldModel
from formations import marking
from formations.delaunay import Formation
from formations.voting import VoteWindow
from models import field as fld
from models.messages import Action, Percept
from models.rules import TEAM_SIZE, PlayMode
from skills.walk import DATA as SKILL_DATA
from skills.walk import WalkParams, default_param_files, load_walk_sets

PM = PlayMode
BEAM_MODES = (PM.BEFORE_KICK_OFF, PM.GOAL_LEFT, PM.GOAL_RIGHT)
KICK_OFFS = (PM.KICK_OFF_LEFT, PM.KICK_OFF_RIGHT)
GOAL_KICKS = (PM.GOAL_KICK_LEFT, PM.GOAL_KICK_RIGHT)
MATE_MEMORY = 3.0  # s a teammate counts as known after it was last seen or heard
OPPONENT_MEMORY = 4.0  # s, likewise an opponent
BALL_MEMORY = 6.0  # s: an older ball estimate is no ball
KICK_TARGET_MEMORY = 3.0  # s a heard kick target is run to
RETARGET = 1.0  # s between choices of how to move the ball while dribbling
KICK_PLAN_TIME = 15.0  # s a kick target is kept while the ball stays put (the approach restarts on a new one)
KICKOFF_HANDOFF = 8.0  # s after our kickoff in which its taker leaves the ball to the others
RESTART_HURRY = 9.0  # s into our restart (of the league's 15) after which the ball is dribbled
REPLAN_MOVE = 0.5  # m the ball moves before the on-ball player plans again
DECIDE_PERIOD = 0.1  # s between team decisions (the body plays the last request between)
KICKOFF_ANGLE = math.radians(44.0)  # the kickoff pass goes this far to the side (ik_45_out)
KICKOFF_KICKS = ("ik_45_out_left", "ik_45_out_right")


def _type_files(files: tuple[str, ...], robot_type: int) -> list[Path]:
    """A team's extra parameter files for a robot type (paths, or names in skills/data):
    a file named for each type ("{type}") that this type lacks is skipped; any other
    missing file is an error."""
    out = []
    for name in files:
        path = Path(name.format(type=robot_type))
        if not path.exists():
            path = SKILL_DATA / path
        if path.exists():
            out.append(path)
        elif "{type}" not in name:
            raise FileNotFoundError(f"parameter file {name!r}: not found (nor in {SKILL_DATA})")
    return out


def _walk_sets(files: tuple[str, ...], robot_type: int) -> dict[str, WalkParams] | None:
    """The walk sets of a robot type with a team's `walk_files` loaded after the shipped
    ones (None: the shipped sets)."""
    extra = _type_files(files, robot_type)
    return load_walk_sets(default_param_files(robot_type) + extra) if extra else None


def _formation(name: str) -> Formation:
    path = Path(name)
    if not path.exists():
        path = Path(__file__).resolve().parent.parent / "formations" / "data" / name
    return Formation.load(path)


class Player:
    """A villa team player (`side` 'L'/'R', shirt number `unum`)."""

    def __init__(self, side: str, unum: int, robot_type: int, seed: int = 0,
                 config: TeamConfig = VILLA) -> None:
        self.side = side
        self.unum = unum
        self.robot_type = robot_type
        self.config = config
        self.world = WorldModel(side, unum, seed=seed)
        files = robot_type in config.file_types
        self.body = Body(robot_type, config.kick_box,
                         config.sprint_within if robot_type in config.sprint_types else None,
                         _walk_sets(config.walk_files if files else (), robot_type),
                         _type_files(config.kick_files if files else (), robot_type), config.dribble_set,
                         config.dribble_funnel, config.dribble_hold, config.turn_ramp, config.sprint_from,
                         config.ball_focus, config.goalie_head and unum == st.GOALIE)
        self.formation = _formation(config.formation)
        self.votes = VoteWindow(TEAM_SIZE)
        self.vote: tuple[int, ...] | None = None  # this player's own role mapping
        self.mapping: tuple[int, ...] | None = None  # the mapping it follows (the team's vote)
        self.role = "goalie" if unum == st.GOALIE else "unknown"
        self.request: SkillRequest = Stand()
        self._beamed_for: tuple[str, float] | None = None
        self._mode: PlayMode | None = None
        self._mode_since = 0.0
        self._heard_kicks: dict[int, tuple[float, tuple[float, float]]] = {}
        self._kick: tuple[float, np.ndarray, Kick | Dribble] | None = None  # (time, ball then, request)
        self.distances = sorted({round(k.spec.distance, 1) for k in self.body.kicks.values()})
        self.on_ball_since: float | None = None  # s: when this player last became the on-ball player
        self._race: bool | None = None  # this possession started as a race (dribble_cone_lead)
        self._decided: float | None = None  # s, time of the last decision
        self._kickoff_taker: int | None = None  # our last kickoff's taker ...
        self._kickoff_until = -math.inf  # s: ... who leaves the ball to the others until then
        self._marked: np.ndarray | None = None  # opponents marked at the last decision
        self._selection = None  # the roles marking replaced at the last decision

    # ----------------------------------------------------------------- the cycle

    def act(self, percept: Percept) -> Action:
        self.world.update(percept, self.body.odometry)
        mode = PlayMode(percept.play_mode)
        if mode != self._mode:
            self._mode, self._mode_since = mode, percept.time
        self._listen(percept.time)
        beam = self._beam(mode, percept)
        if beam is not None:
            v = self.body.execute(Stand(), percept, self.world)
            return Action(joint_velocities=v, beam=beam)
        if self._decided is None or percept.time - self._decided >= DECIDE_PERIOD - 1e-9 \
                or self._mode_since == percept.time:
            self.request = self.decide(self.view(mode))
            self._decided = percept.time
        v = self.body.execute(self.request, percept, self.world)
        say = self._say() if self.config.communication else None
        x, y, _ = self.world.pose
        return Action(joint_velocities=v, say=say, annotations={"pose": (float(x), float(y))})

    def view(self, mode: PlayMode) -> st.TeamView:
        """This player's snapshot of the world for the decision layer."""
        w = self.world
        t = w.time
        mates = []
        isfinite = math.isfinite
        for u, o in enumerate(w.teammates, 1):
            if u == self.unum or t - max(o.last_seen, o.last_heard) > MATE_MEMORY:
                continue
            x, y = o.position[:2].tolist()
            if isfinite(x):  # known
                mates.append(st.Mate(u, x, y, o.heading if isfinite(o.heading) else 0.0, o.fallen))
        opps, fallen = [], []
        for o in w.opponents:
            if t - max(o.last_seen, o.last_heard) <= OPPONENT_MEMORY:
                xy = o.position[:2].tolist()
                if isfinite(xy[0]):
                    opps.append(xy)
                    fallen.append(o.fallen)
        ball = None
        b = w.ball
        if w.ball_filter.initialized and t - max(b.last_seen, b.last_heard) < BALL_MEMORY:
            ball = w.ball_filter.position
        kicks = tuple((u, tgt) for u, (when, tgt) in self._heard_kicks.items()
                      if t - when < KICK_TARGET_MEMORY)
        team = mode.team
        return st.TeamView(
            unum=self.unum, time=t, mode=mode, ours=None if team is None else team == self.side,
            pose=tuple(w.pose.tolist()), fallen=w.fallen or self.body.down, ball=ball,
            ball_velocity=w.ball_filter.velocity if ball is not None else np.zeros(2),
            mates=tuple(mates), opponents=np.array(opps).reshape(-1, 2),
            opponents_fallen=np.array(fallen, dtype=bool), kick_targets=kicks)

    # ------------------------------------------------------------------ deciding

    def decide(self, view: st.TeamView) -> SkillRequest:
        """The skill request of this cycle (the team decision, then the role)."""
        if view.mode == PM.GAME_OVER:
            return Stand()
        if view.mode in BEAM_MODES:  # beamed facing the center: wait for the kickoff
            self._not_on_ball()
            return Stand()
        if view.ball is None:
            self._not_on_ball()
            return Stand(heading=view.pose[2] + 1.0)  # turn to find the ball
        on_ball = self._on_ball(view)
        targets = self._targets(view)
        if self.unum == st.GOALIE:
            self.role = "goalie"
            return self._on_ball_request(view) if on_ball == self.unum else self._goalie(view)
        obstacles = st.role_obstacles(view, on_ball) if self.config.path_cost else None
        self.vote = st.assign_roles(view, targets, self.config.assignment, on_ball,
                                    nearest_stopper=self.config.nearest_stopper, obstacles=obstacles)
        mapping = self.votes.winner(self.vote) if self.config.voting else self.vote
        self.mapping = mapping
        role = st.FIELD_ROLES[mapping[self.unum - 2]]
        if self.config.all_ball:
            role = "onBall"
        self.role = role
        if role == "onBall" and on_ball is not None and on_ball != self.unum and not self.config.voting:
            role = "supporter"
        if role == "onBall":
            return self._on_ball_request(view)
        self._not_on_ball()
        return self._position(view, targets[st.FIELD_ROLES.index(role)])

    def _targets(self, view: st.TeamView) -> np.ndarray:
        """(10, 2) positions of FIELD_ROLES: the formation's, with marking positions in
        place of some roles when opponents threaten our goal (chapter 7.3)."""
        targets = st.role_positions(self.formation, view.ball, self.config.formation_shift)
        if not self.config.marking or len(view.opponents) == 0:
            return targets
        marked = self._marked
        if marked is not None and len(marked) != len(view.opponents):
            marked = None
        plan = marking.plan(targets, st.FIELD_ROLES, view.opponents, view.ball, marked=marked,
                            previous=self._selection)
        self._marked, self._selection = plan.marked, plan.selection
        return plan.targets

    def _on_ball(self, view: st.TeamView) -> int | None:
        after_kickoff = view.mode not in KICK_OFFS and view.time < self._kickoff_until
        exclude = self._kickoff_taker if after_kickoff else None
        on_ball = st.on_ball_player(view, exclude)
        if view.mode in KICK_OFFS and view.ours:
            self._kickoff_taker = on_ball  # who plays our kickoff: not the next touch (the rules)
            self._kickoff_until = view.time + KICKOFF_HANDOFF
        return on_ball

    def _not_on_ball(self) -> None:
        self._kick = None
        self.on_ball_since = None
        self._race = None

    def _on_ball_request(self, view: st.TeamView) -> SkillRequest:
        """On the ball: keep away at their restarts, else kick or dribble."""
        if self.on_ball_since is None:
            self.on_ball_since = view.time
        ball = view.ball
        if view.ours is False and view.mode != PM.PLAY_ON:
            self._kick = None
            spot = st.keep_away(np.array(view.pose[:2]), ball)
            return WalkTo(*self._clip(spot), heading=self._face(spot, ball))
        if not self.config.kicks and not self.config.dribble:
            return Stand()  # a team that may not play the ball (a broken baseline for tests)
        if view.mode in KICK_OFFS:
            return self._kickoff(view)
        if (view.ours and view.mode != PM.PLAY_ON and view.time - self._mode_since > RESTART_HURRY
                and self.config.dribble and not self.body.busy):  # the restart's time runs out: touch it now
            return Dribble(tuple(st.dribble_target(view, finish=self.config.dribble_finish)))
        if self.body.busy and self._kick is not None:
            return self._kick[2]
        if self._kick is not None and float(np.hypot(*(self._kick[1] - ball))) < REPLAN_MOVE:
            age = view.time - self._kick[0]
            if age < (KICK_PLAN_TIME if isinstance(self._kick[2], Kick) else RETARGET):
                return self._kick[2]
        req = self._ball_plan(view)
        self._kick = (view.time, ball.copy(), req)
        return req

    def _ball_plan(self, view: st.TeamView) -> Kick | Dribble:
        ball = view.ball
        cfg = self.config
        dribble = cfg.dribble and (not cfg.kicks or st.opponent_near_ball(view, cfg.dribble_near))
        if self._race is None:  # judged once a possession: a target that flips makes it line up again
            lead = cfg.dribble_cone_lead
            self._race = lead is None or st.opponent_may_reach_first(view, lead)
        cone = cfg.dribble_cone if self._race else 0.0  # free: straight at the goal
        if dribble and view.mode == PM.PLAY_ON:
            return self._dribble(view, cone)
        reach = max(self.distances)
        shot = st.shot_target(ball, view.opponents, reach)
        if shot is not None:
            need = float(np.hypot(*(shot - ball)))
            names = tuple(n for n, k in self.body.kicks.items() if k.spec.distance >= need)
            return Kick((float(shot[0]), float(shot[1])), names)
        if not cfg.passes and cfg.dribble and view.mode == PM.PLAY_ON:
            return self._dribble(view, cone)
        mates = np.array([(m.x, m.y) for m in view.mates]).reshape(-1, 2)
        target, dist = st.pass_target(ball, self.distances, view.opponents, mates)
        names = tuple(n for n, k in self.body.kicks.items() if abs(k.spec.distance - dist) < 0.15)
        return Kick((float(target[0]), float(target[1])), names)

    def _dribble(self, view: st.TeamView, cone: float) -> Dribble:
        """A dribble toward the goal, its line turned by the team's dribble cone (rad)."""
        cfg = self.config
        fade = st.CONE_FADE if cfg.dribble_cone_fade is None else cfg.dribble_cone_fade
        target = st.dribble_target(view, cone, cfg.dribble_cone_inward, fade, cfg.dribble_finish)
        return Dribble(tuple(target))

    def _kickoff(self, view: st.TeamView) -> SkillRequest:
        """Our kickoff: a short pass to the side the fewest opponents guard (D.2.3), or with
        `TeamConfig.kickoff` "deep" the longest kick deep toward their goal (`deep_kick_target`)."""
        if self._kick is not None:
            return self._kick[2]
        ball = view.ball
        if self.config.kickoff == "deep":
            reach = max(k.spec.distance for k in self.body.kicks.values())
            names = tuple(n for n, k in self.body.kicks.items() if k.spec.distance > reach - 0.5)
            best = st.deep_kick_target(ball, view.opponents, reach)
        else:
            names = tuple(n for n in KICKOFF_KICKS if n in self.body.kicks)
            best, best_gap = None, -math.inf
            for sign in (1.0, -1.0):
                t = ball + 3.0 * np.array([math.cos(KICKOFF_ANGLE), sign * math.sin(KICKOFF_ANGLE)])
                gap = float(np.min(np.hypot(*(view.opponents - t).T))) if len(view.opponents) else math.inf
                if gap > best_gap:
                    best, best_gap = t, gap
        req = Kick((float(best[0]), float(best[1])), names or tuple(self.body.kicks))
        self._kick = (view.time, ball.copy(), req)
        return req

    def _goalie(self, view: st.TeamView) -> SkillRequest:
        dive = st.dive_for(view.ball, view.ball_velocity, view.pose)
        if dive is not None and view.mode == PM.PLAY_ON:
            return Dive(dive)
        x, y, h = st.goalie_position(view.ball)
        return WalkTo(x, y, heading=h)

    def _position(self, view: st.TeamView, target: np.ndarray) -> SkillRequest:
        """Walk to a role position: run to a teammate's announced kick target when this
        player's position is the nearest to it, keep off the ball's path, keep the
        rules' distances at restarts, and walk round other players."""
        ball = view.ball
        target = np.asarray(target, dtype=float)
        if self.config.kick_anticipation and view.kick_targets and view.mode == PM.PLAY_ON:
            _, kt = view.kick_targets[-1]
            kt = np.asarray(kt, dtype=float)
            target = self._anticipate(view, target, kt)
        if view.mode in KICK_OFFS or view.mode == PM.BEFORE_KICK_OFF:
            target = st.own_half(target)
        if view.ours is False and view.mode != PM.PLAY_ON:
            target = st.keep_away(target, ball)
            if view.mode in GOAL_KICKS:
                target[0] = min(target[0], fld.HALF_LENGTH - fld.PENALTY_DEPTH - 0.8)
        target = np.array(self._clip(target))
        goal = target
        if self.config.collision_avoidance:
            mates = np.array([(m.x, m.y) for m in view.mates]).reshape(-1, 2)
            goal = st.avoid(view.pose, target, np.concatenate((mates, view.opponents)))
        return WalkTo(float(goal[0]), float(goal[1]), heading=st.facing(view.pose, target, ball))

    def _anticipate(self, view: st.TeamView, target: np.ndarray, kick_target: np.ndarray) -> np.ndarray:
        """Kick anticipation (D.2.2): the player whose position is nearest the kick
        target goes there; the others step off the ball's path."""
        mine = float(np.hypot(*(target - kick_target)))
        me = np.array(view.pose[:2])
        others = [float(np.hypot(m.x - kick_target[0], m.y - kick_target[1])) for m in view.mates
                  if m.unum != st.GOALIE]
        if not others or float(np.hypot(*(me - kick_target))) <= min(others) + 1e-9 or mine < 1.0:
            return kick_target.copy()
        a, b = view.ball, kick_target
        ab = b - a
        s = float(np.clip((target - a) @ ab / max(float(ab @ ab), 1e-9), 0.0, 1.0))
        off = target - (a + s * ab)
        d = float(np.hypot(*off))
        if d < 1.0:
            n = np.array([-ab[1], ab[0]]) / max(float(np.hypot(*ab)), 1e-9)
            side = 1.0 if float(off @ n) >= 0 else -1.0
            target = a + s * ab + side * n * 1.0
        return target

    @staticmethod
    def _clip(p: np.ndarray) -> tuple[float, float]:
        return (min(max(float(p[0]), -fld.HALF_LENGTH + 0.2), fld.HALF_LENGTH - 0.2),
                min(max(float(p[1]), -fld.HALF_WIDTH + 0.2), fld.HALF_WIDTH - 0.2))

    @staticmethod
    def _face(p: np.ndarray, ball: np.ndarray) -> float:
        return math.atan2(float(ball[1] - p[1]), float(ball[0] - p[0]))

    # ---------------------------------------------------------- beams and talk

    def _beam(self, mode: PlayMode, percept: Percept) -> tuple[float, float, float] | None:
        """Before a kickoff: the beam to this player's kickoff position, once per mode."""
        if mode not in BEAM_MODES or self._beamed_for == (mode.value, self._mode_since):
            return None
        self._beamed_for = (mode.value, self._mode_since)
        if mode == PM.BEFORE_KICK_OFF:
            kicks_off = "L" if percept.game_time <= 0.0 else "R"
        else:
            kicks_off = "R" if mode == PM.GOAL_LEFT else "L"
        x, y, h = self.kickoff_position(kicks_off == self.side)
        self.world.beamed(x, y, h)
        self.body.beamed()
        self._not_on_ball()
        return x, y, h

    def kickoff_position(self, our_kickoff: bool) -> tuple[float, float, float]:
        """Where this player stands at a kickoff (team frame): the formation for the ball
        on the center spot, in our half; the on-ball role behind the ball at ours."""
        if self.unum == st.GOALIE:
            return st.GOALIE_LINE, 0.0, 0.0
        taker = st.KICKOFF_TAKER if self.config.kickoff == "pass" else st.KICKOFF_TAKER_BACK
        x, y = st.kickoff_positions(self.formation, our_kickoff, taker)[(self.unum - 2) % len(st.FIELD_ROLES)]
        return float(x), float(y), math.atan2(-y, -x)  # facing the center spot

    def _listen(self, now: float) -> None:
        for msg in self.world.heard:
            if msg.role_vote is not None and self.config.voting:
                self.votes.receive(msg.unum, msg.role_vote)
            if msg.kick is not None:
                self._heard_kicks[msg.unum] = (now, (msg.kick.x, msg.kick.y))

    def _say(self) -> str | None:
        if not comm.may_speak(self.unum, self.world.time):
            return None
        vote = self.vote if self.unum != st.GOALIE else None
        kick = None
        if self._kick is not None and isinstance(self._kick[2], Kick):
            kick = comm.KickTarget(*self._kick[2].target)
        if vote is not None and self.config.voting:
            self.votes.receive(self.unum, vote)
        return self.world.say(robot_type=self.robot_type, role_vote=vote, kick=kick)


def villa(side: str, unum: int, robot_type: int, seed: int = 0) -> Player:
    """The villa team's agent factory."""
    return Player(side, unum, robot_type, seed)


__all__ = ["Player", "villa"]
