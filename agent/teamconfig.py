"""The villa team's switches: one team, configured (variants for ablations are configs).

Each field names one component of the strategy ("Positioning to Win" section 6
turns them off one at a time). Distances in m, times in s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

# The go-to-target sets learned with the stand free (issue 47; skills/data/walk_fast_type*.txt,
# every type), the sprint sets learned from their stands (walk_fast_sprint_type*.txt, types 1-4)
# and the keyframe kicks' settings for that stand (kick_fast_type*.params, type 0).
FAST_WALK_FILES = ("walk_fast_type{type}.txt", "walk_fast_sprint_type{type}.txt")
FAST_KICK_FILES = ("kick_fast_type{type}.params",)
# Seven robots of type 0 (the goalie and uniform numbers 2-7: the on-ball, supporting, forward
# and middle roles at the kickoff), type 2 at the backs and type 3 on the wings (MacAlpine's
# dissertation 4.2.4: UT Austin Villa played seven of its best type).
MOSTLY_TYPE_0 = (0, 0, 0, 0, 0, 0, 0, 2, 2, 3, 3)
GOALIE_4 = (4,) + MOSTLY_TYPE_0[1:]  # the same with a goalie of type 4 (villa:Goalie4)
KICKOFFS = ("pass", "walkup", "deep")  # TeamConfig.kickoff


@dataclass(frozen=True)
class TeamConfig:
    """How the villa team plays. The defaults are the full team."""

    formation: str = "default.formation"  # a file in formations/data/ or a path
    assignment: str = "mmd-msd2"  # a `formations.scram.METHODS` name, or "static"
    voting: bool = True  # follow the team's voted role mapping, not one's own
    communication: bool = True  # say and hear team messages
    collision_avoidance: bool = True  # D.1.2 when walking to a position
    all_ball: bool = False  # every field player goes to the ball
    # May kick in play (a free on-ball player kicks when no opponent is within dribble_near);
    # kickoffs and our other restarts are kicked either way. Off: villa:DribbleOnly beat the
    # kicking team (villa:Kicks) by +0.93 +- 0.16 goals over 40 full games
    # (benchmarks/results/dribbleonly-vs-villa/).
    kicks: bool = False
    dribble: bool = True  # may dribble
    dribble_set: str = "go_to_target"  # the walk set a dribble walks through the ball with
    # rad a dribble in play may turn from the goal toward the approach ... 60 deg: villa:DribbleCone
    # beat villa without it (villa:NoCone) by +0.30 +- 0.09 goals over 80 full games
    # (benchmarks/results/dribblecone-vs-villa/), but scores about 1.2 fewer against posture.
    dribble_cone: float = math.radians(60.0)
    dribble_cone_lead: float | None = None  # ... only when, as the player takes the ball on, an
    # opponent is within its distance to the ball plus this (m): a race; held for the possession
    dribble_cone_inward: bool = False  # the cone never turns toward the touchline on the ball's side
    # m from their goal: no cone within the first, all of it beyond the second (None: strategy.CONE_FADE)
    dribble_cone_fade: tuple[float, float] | None = None
    # Line a dribble up walking round the ball and into its line (Body._funnel), not stopping at
    # a spot behind it: villa:Funnel beat villa without it (villa:NoFunnel) by +0.43 +- 0.12
    # goals over 40 full games (benchmarks/results/funnel-vs-villa/).
    dribble_funnel: bool = True
    # Near their goal, aim the dribble past a blocker and center a ball beside the goal first
    # (strategy.dribble_target's `finish`): villa:Finish beat posture by +5.19 +- 0.16 over 16
    # full games against villa's +4.63 +- 0.20 (2.0 outs a game against 5.5; Welch p 0.04) and
    # was even with villa, +0.00 +- 0.06 over 40 (benchmarks/results/finish-vs-*/).
    dribble_finish: bool = True
    # Push a dribble gently so that the ball stays near: (lead m, brake m, step gain a cycle),
    # walking toward `lead` m past the ball, slowing within `brake` m of that point, the walk's
    # step sizes following at `gain` a cycle (agent.body.Body's dribble_hold). None: 0.8 m past
    # the ball, braking within 0.5 m, the dribble set's own gain.
    dribble_hold: tuple[float, float, float] | None = None
    dribble_near: float = 2.0  # m: dribble (not kick) when an opponent is this close to the ball (D.2.1)
    passes: bool = True  # may pass in play (else a free player dribbles unless a shot is open)
    marking: bool = True  # mark attackers when the opponents have the ball
    kick_anticipation: bool = True  # run to where a teammate's kick will land
    # Our kickoff: "pass", a short pass to the side (D.2.3), meant to be kicked from where the
    # taker is beamed; in fact the approach's first step nudges the ball 1-1.5 m straight ahead
    # (benchmarks/results/README.md, deepkickoff-vs-villa). "walkup": that pass from
    # KICKOFF_TAKER_BACK, walked up to; villa:WalkupKickoff. "deep": the robot's longest kick
    # toward their goal past the opponents (strategy.deep_kick_target) from KICKOFF_TAKER_BACK
    # (dissertation 4.2.2: UT Austin Villa's kickoff when it did not try to score); villa:DeepKickoff.
    kickoff: str = "pass"
    kick_box: float = 1.0  # the kicks' stopping boxes scaled by this (wider: quicker, less exact)
    formation_shift: float = 0.0  # m added to every formation x (+: offensive, -: defensive)
    nearest_stopper: bool = False  # the supporter role goes to the nearest field player first (PtW 6)
    path_cost: bool = False  # role costs walk round the ball and the on-ball player (PtW 6)
    # deg: the sprint set toward a target this straight ahead (A.1.4) for sprint_types (None:
    # never). villa:FastSprint beat villa without it (villa:NoSprint) by +0.21 +- 0.07 goals over
    # 80 full games, territory +1.4 +- 0.3 m (benchmarks/results/fastsprint-vs-villa/).
    sprint_within: float | None = 15.0
    sprint_types: tuple[int, ...] = (1, 2, 3, 4)  # type 0's sprint set was no faster than its go-to-target
    sprint_from: float = 0.0  # sprint once stepping forward at this fraction of go-to-target's longest step
    # m: the player asked to dribble or kick keeps its head on the ball within this (None: within
    # 1 m, as every field player; dissertation 8.2.1), elsewhere it scans the field.
    ball_focus: float | None = None
    goalie_head: bool = False  # the goalie's head always on the ball (dissertation 8.2.1)
    # Turn input per second the team's walk may grow by (agent.body.Body's turn_ramp; 0: at once).
    turn_ramp: float = 0.0
    # Walk parameter files loaded after a type's shipped ones, "{type}" standing for the robot
    # type (files in skills/data or paths; a type without its file keeps the shipped walk).
    # The fast sets: those of types 0 and 1 beat villa without them (villa:SlowWalk) by +0.25 +-
    # 0.08 goals over 40 full games, territory +3.9 +- 0.5 m (benchmarks/results/fastwalk-vs-villa-dec7/);
    # types 2-4's then beat that team (villa:FastWalk01) by +0.28 +- 0.09, territory +2.1 +- 0.5 m
    # (benchmarks/results/fastwalk234-vs-villa/).
    walk_files: tuple[str, ...] = FAST_WALK_FILES
    kick_files: tuple[str, ...] = FAST_KICK_FILES  # likewise, keyframe kick parameter files
    file_types: tuple[int, ...] = (0, 1, 2, 3, 4)  # the robot types that load walk_files and kick_files
    # The robot types the team plays, uniform numbers 1-11 (None: 0-4 in turn, the goalie type 0),
    # within the league's rule (models.rules.robot_types_problem), as a league agent names its type.
    # MOSTLY_TYPE_0 beat types 0-4 in turn (villa:InTurn) by +0.23 +- 0.09 goals over 40 full
    # games, 8 wins, 31 draws, 1 loss (benchmarks/results/mostlytype0-vs-villa/).
    robot_types: tuple[int, ...] | None = MOSTLY_TYPE_0

    def __post_init__(self) -> None:
        if self.kickoff not in KICKOFFS:
            raise ValueError(f"TeamConfig.kickoff {self.kickoff!r}: one of {', '.join(KICKOFFS)}")


VILLA = TeamConfig()
_NO_SPRINT = TeamConfig(sprint_within=None, robot_types=None)  # villa before it sprinted


def _shipped_walk(*walk_files: str) -> TeamConfig:
    """The team on the shipped walk sets and kicks with `walk_files` after them, not
    sprinting, types 0-4 in turn: the walk variants measured before the fast sets shipped."""
    return TeamConfig(walk_files=walk_files, kick_files=(), sprint_within=None, robot_types=None)


# "Positioning to Win" section 6's variants of the base team (Table 2), and a few more.
# Names are matched case-insensitively (`variant`); the team spec is `villa:NAME`.
VARIANTS: dict[str, TeamConfig] = {
    "NoCollAvoid": TeamConfig(collision_avoidance=False),
    "AllBall": TeamConfig(all_ball=True),
    "NoTeamwork": TeamConfig(all_ball=True, collision_avoidance=False),
    "NoCommunication": TeamConfig(communication=False, voting=False),
    "Static": TeamConfig(assignment="static"),
    "Defensive": TeamConfig(formation="defensive.formation"),
    "Offensive": TeamConfig(formation="offensive.formation"),
    "Boxes": TeamConfig(formation="boxes.formation"),
    "NearestStopper": TeamConfig(nearest_stopper=True),
    "PathCost": TeamConfig(path_cost=True),
    "PositiveCombo": TeamConfig(formation="offensive.formation", path_cost=True, nearest_stopper=True),
    # not in the paper's table
    "NoVoting": TeamConfig(voting=False),  # communication on, each follows its own mapping
    # The base team until December 5, 2026: kicks in play when no opponent is near the ball.
    "Kicks": TeamConfig(kicks=True, dribble_cone=0.0, dribble_funnel=False),
    "DribbleOnly": TeamConfig(kicks=False, dribble_cone=0.0, dribble_funnel=False),  # the base team then ...
    # ... until December 5, 2026 (the dribble straight at the goal) ...
    "NoCone": TeamConfig(dribble_cone=0.0, dribble_funnel=False),
    "NoFunnel": TeamConfig(dribble_funnel=False),  # ... and then until December 6
    "KickOnly": TeamConfig(kicks=True, dribble=False),
    # In play: a shot when one is open, else dribble. Against villa -0.10 +- 0.22 over 40 full
    # games (benchmarks/results/shotsonly-vs-villa/); against the finishing villa -0.08 +- 0.07,
    # territory -1.6 +- 0.5 m (shotsonly-vs-villa-dec7/).
    "ShotsOnly": TeamConfig(kicks=True, passes=False),
    "WideBox": TeamConfig(kick_box=1.5),  # kicks start from a stance box 1.5x as wide: fewer aligns
    # The shipped sprint sets toward targets within 15 deg, on the shipped walk; not type 2,
    # whose sprint sets fall on the sprint course (changing back to go-to-target): 12 of 16
    # runs with the shipped one.
    "Sprint": TeamConfig(sprint_within=15.0, sprint_types=(0, 1, 3, 4), walk_files=(), kick_files=()),
    # The go-to-target sets learned with the stand free (FAST_WALK_FILES): villa since December
    # 7, 2026. Types 0 and 1's against the team before (SlowWalk) +0.25 +- 0.08 over 40 full
    # games (10:0), territory +3.9 +- 0.5 m, falls 33.6 against 27.0 a game
    # (benchmarks/results/fastwalk-vs-villa-dec7/); types 2-4's against FastWalk01 +0.28 +- 0.09
    # (12:1), territory +2.1 +- 0.5 m, falls 38.0 against 34.2 (fastwalk234-vs-villa/).
    # FastWalk does not sprint: villa until midday December 7, 2026, also named NoSprint.
    "FastWalk": _NO_SPRINT,
    "NoSprint": _NO_SPRINT,
    # only types 0 and 1 on the fast sets: villa that morning
    "FastWalk01": TeamConfig(file_types=(0, 1), sprint_within=None),
    "SlowWalk": _shipped_walk(),  # every type on its shipped walk sets and kicks: villa until then
    # Walks through the ball with a position-to-dribble set learned for a dribble that keeps
    # the ball near (issue 47; optimization/tasks/dribble_walk.task, skills/data/walk_dribble_type*.txt).
    "DribbleWalk": TeamConfig(dribble_set="position_to_dribble", walk_files=("walk_dribble_type{type}.txt",),
                              kick_files=(), sprint_within=None),
    # Walks through the ball with position-to-dribble sets learned from the fast sets' stands
    # (issue 47; optimization/tasks/dribble_walk.task, skills/data/walk_fast_dribble_type*.txt).
    # Fewer dribble falls (benchmarks.dribble: 13 -> 1 in 40 tries, types 0, 1, 2, 4) but
    # +0.00 +- 0.08 over 40 full games against villa (4:4; territory +0.2 +- 0.5 m, falls 39.0
    # against 37.6 a game; benchmarks/results/fastdribble-vs-villa/).
    "FastDribble": TeamConfig(dribble_set="position_to_dribble",
                              walk_files=(*FAST_WALK_FILES, "walk_fast_dribble_type{type}.txt")),
    # Pushes a dribble on gently: toward 0.2 m past the ball (not 0.8), slowing within 0.6 m,
    # the step sizes following at 0.1 a cycle (issue 47: a dribble that keeps the ball near).
    # On the shipped walk the ball stayed nearer (benchmarks.dribble) but -0.08 +- 0.06 over 40
    # full games against that villa (2:5; territory +0.3 +- 0.5 m; benchmarks/results/hold-vs-villa/).
    "Hold": TeamConfig(dribble_hold=(0.2, 0.6, 0.1)),
    # The fast sets with a gentler push still (braking within 0.8 m): the first dribble to keep
    # the ball within 1 m at 0.35 m/s over 10 m (type 0, 3 of 10 tries; benchmarks.dribble).
    # Against villa -0.10 +- 0.08 over 40 full games (4:8; territory -0.6 +- 0.5 m, possession
    # 54%; benchmarks/results/fasthold-vs-villa/).
    "FastHold": TeamConfig(dribble_hold=(0.2, 0.8, 0.1)),
    # The turn input ramped up over 0.5 s (issue 47: fewer falls in open play). Walking to a
    # position, the player turned in place at full input right after walking forward at full
    # input, and type 0 fell there (7 of 20 tries, none ramped; benchmarks.walk's positioning).
    # Against villa +0.01 +- 0.07 over 80 full games (11:10), territory +0.8 +- 0.35 m, falls
    # 33.1 against 38.7 a game (benchmarks/results/turnramp-vs-villa/); against posture +5.47 +-
    # 0.12 over 32 full games, villa +5.28 +- 0.16 (turnramp-vs-posture/, villa-vs-posture-dec7/).
    "TurnRamp": TeamConfig(turn_ramp=2.0),
    # Sprint sets learned from the fast stands (issue 47; skills/data/walk_fast_sprint_type*.txt,
    # optimization/tasks/sprint_course.task), walked toward a target within 15 deg: straight
    # ahead 1.13-1.29x as fast as the go-to-target sets (types 1-4; type 0's was no faster).
    # Against villa +0.21 +- 0.07 over 80 full games (20:3), territory +1.4 +- 0.3 m, falls 43.4
    # against 39.7 a game (benchmarks/results/fastsprint-vs-villa/). villa itself since
    # midday December 7, 2026; the team before is NoSprint.
    "FastSprint": TeamConfig(),
    # Sprinting once the walk steps forward at 0.8 of the go-to-target set's longest step, and
    # not type 1: from a stand, 8 s toward a target 6 m ahead, types 1 and 3 fell in 3 and 4
    # of 6 runs sprinting at once, in none of 8 so; in 40 positioning runs type 1 fell in 16
    # sprinting (13 at speed), 7 not. Against villa -0.05 +- 0.10 over 42 full games (6:8),
    # territory -0.3 +- 0.5 m, falls 42.9 against 46.9 a game (benchmarks/results/sprintatspeed-vs-villa/).
    "SprintAtSpeed": TeamConfig(sprint_from=0.8, sprint_types=(2, 3, 4)),
    # Seven robots of type 0, type 2 at the backs and type 3 on the wings (MOSTLY_TYPE_0): villa
    # itself since December 7, 2026 (afternoon); the team before, types 0-4 in turn, is InTurn.
    "MostlyType0": TeamConfig(),
    "InTurn": TeamConfig(robot_types=None),
    # The goalie of type 4 (toes), which concedes less to a dribble at the goal (benchmarks.clearing
    # --spot attack: 23 against 32% of 260 paired tries); a 4 vs 4 screen +0.03 +- 0.05 over 120.
    "Goalie4": TeamConfig(robot_types=GOALIE_4),
    # TurnRamp, DeepKickoff and Goalie4 together: each tied villa in goals while gaining ground,
    # fewer falls or fewer goals against in its benchmark ("Positioning to Win"'s PositiveCombo
    # idea: small gains that one batch cannot see may add up to one it can). Against villa +0.08
    # +- 0.07 over 40 full games (5:2), territory +1.3 +- 0.5 m, falls 39.6 against 44.7 a game
    # (benchmarks/results/groundcombo-vs-villa/).
    "GroundCombo": TeamConfig(turn_ramp=2.0, kickoff="deep", robot_types=GOALIE_4),
    # The head on the ball within 4 m while going for it (a field player without it scans beyond
    # 1 m and loses a ball it walks to): first touch 4.10-4.60 -> 3.88-4.36 s (benchmarks.firsttouch),
    # but against villa +0.03 +- 0.06 over 80 full games (15:13), territory +0.2 +- 0.4 m
    # (benchmarks/results/ballfocus-vs-villa/).
    "BallFocus": TeamConfig(ball_focus=4.0),
    # The goalie's head always on the ball, as the dissertation's: benchmarks.clearing --spot
    # attack, 60 tries, 16 goals against villa's 17, falls 48 against 35.
    "GoalieHead": TeamConfig(goalie_head=True),
    # Type 0's go-to-target set learned on for a fourth stage (issue 47;
    # skills/data/walk_steady_type0.txt): on its training task runs with a fall 43 -> 17 of 64,
    # but against villa +0.05 +- 0.09 over 40 full games (7:5), territory -1.0 +- 0.4 m, falls
    # 45.8 against 43.1 a game (benchmarks/results/steady0-vs-villa/); 4 vs 4 -0.15 +- 0.06 over 40
    # (screen-4v4/steady0/).
    "Steady0": TeamConfig(walk_files=(*FAST_WALK_FILES, "walk_steady_type{type}.txt")),
    # In play the dribble turns up to 60 deg from the goal toward the side the player comes
    # from, so that it need not go round the ball (issue 47: a quicker first touch): NoFunnel.
    "DribbleCone": TeamConfig(dribble_cone=math.radians(60.0), dribble_funnel=False),
    "DribbleCone30": TeamConfig(dribble_cone=math.radians(30.0), dribble_funnel=False),  # at most 30 deg
    # The same cone only for a possession that starts as a race: an upright opponent no farther
    # from the ball than the player when it becomes the on-ball player; straight at the goal
    # when free. Always (DribbleCone) it scored less against a standing team (posture).
    "DribbleConeHeld": TeamConfig(dribble_cone=math.radians(60.0), dribble_cone_lead=0.0,
                                  dribble_funnel=False),
    # Lines a dribble up without stopping: round the ball walking forward, then into its line
    # facing along it (issue 47: a quicker first touch; benchmarks.firsttouch): villa itself.
    "Funnel": TeamConfig(dribble_funnel=True),
    # The walk experiments below were measured on the shipped walk sets (before the fast sets
    # shipped) and stay on them (_shipped_walk).
    # The go-to-target walk's step size following the request with gain 0.06 a cycle, every
    # type (issue 47: a walk from the stand at speed in a third of a second; walk_quick.txt).
    # It won duels (+0.64 +- 0.13 m a pair) but not games: +0.03 +- 0.07 over 40 full games
    # against villa (benchmarks/results/quickstart-vs-villa/).
    "QuickStart": _shipped_walk("walk_quick.txt"),
    # Balance steps in every walk set (skills/data/walk_balance.txt): fewer falls where robots
    # meet (benchmarks.bump) and in 4 vs 4 games (+0.12 +- 0.05 goals), but -0.07 +- 0.10 over
    # 40 full games against villa (benchmarks/results/balance-vs-villa/).
    "Balance": _shipped_walk("walk_balance.txt"),
    # Softer joints while walking (joint_kp 11 1/s, skills/data/walk_soft.txt): fewer falls
    # when robots walk into each other (benchmarks.bump), a tenth slower forward; but more
    # falls in games and -0.21 +- 0.10 over 24 against villa (benchmarks/results/soft-vs-villa/).
    "Soft": _shipped_walk("walk_soft.txt"),
    # The swing foot lifted 30 mm instead of 40 (skills/data/walk_lowstep.txt): fewer falls
    # when robots walk into each other (benchmarks.bump) and in games (19.9 against 22.8 a
    # game), but +0.03 +- 0.05 over 80 against villa (benchmarks/results/lowstep-vs-villa/).
    "LowStep": _shipped_walk("walk_lowstep.txt"),
    # LowStep's 30 mm step with longer backward and side steps (skills/data/walk_agile*.txt):
    # backward 1.09-1.63x and sideways 1.00-1.33x as fast (issue 47), but +0.08 +- 0.05 over
    # 80 against villa (benchmarks/results/agile-vs-villa/).
    "Agile": _shipped_walk("walk_lowstep.txt", "walk_agile.txt", "walk_agile_type{type}.txt"),
    # A backward step swung after fraction_still, as villa had it until December 6, 2026
    # (skills/data/walk_latebackward.txt): backward 0.11-0.14 m/s instead of 0.23-0.28.
    "LateBackward": _shipped_walk("walk_latebackward.txt"),
    # The swing foot lifted 15 mm in place, 40 at a full step (skills/data/walk_slowlift.txt):
    # a slow walk that goes where it is asked, not backward (issue 47); -0.10 +- 0.07 over 40
    # against villa (benchmarks/results/slowlift-vs-villa/).
    "SlowLift": _shipped_walk("walk_slowlift.txt"),
    # The dribble straight at the goal, lined up with the funnel (villa without its cone): with
    # the early backward swing, going round the ball is as quick as the cone (tests/agent/test_body.py).
    # -0.04 +- 0.14 over 26 against villa, territory -1.48 +- 0.59 m (benchmarks/results/straight-vs-villa/).
    "Straight": TeamConfig(dribble_cone=0.0),
    # The cone turning the dribble only toward the field's long axis: with villa's cone the ball
    # spent a fifth of a villa-villa match within 2 m of a touchline (benchmarks.playstats).
    # -0.15 +- 0.11 over 20 against villa, territory -1.50 +- 0.69 m (benchmarks/results/conein-vs-villa/).
    "ConeIn": TeamConfig(dribble_cone_inward=True),
    # The cone fading out farther from their goal (none within 6 m, all of it beyond 10): against
    # posture villa put the ball over the end line 5.5 times a game, the cone-less villa 2.1.
    # +0.06 +- 0.04 over 80 against villa (8:3), +5.25 +- 0.16 over 8 against posture
    # (benchmarks/results/conefade-vs-villa/, conefade-vs-posture/).
    "ConeFade": TeamConfig(dribble_cone_fade=(6.0, 10.0)),
    # Near their goal the dribble aims past a blocker (the far corners too) and centers a ball
    # beside the goal before pushing it at the mouth: against posture villa put the ball over
    # the end line 5.5 times a game, into the standing goalie or from beside a post. +5.19 +- 0.16
    # over 16 against posture (2.0 outs a game), +0.00 +- 0.06 over 40 against villa (3:3)
    # (benchmarks/results/finish-vs-posture/, finish-vs-villa/; benchmarks.finishing).
    # villa since December 6, 2026 (night); the team before is NoFinish.
    "Finish": TeamConfig(dribble_finish=True),
    "NoFinish": TeamConfig(dribble_finish=False),
    # The kickoff a long kick deep toward their goal (TeamConfig.kickoff "deep"): territory +1.50 +-
    # 0.35 m, goals +0.04 +- 0.07 over 80 against villa (benchmarks/results/deepkickoff-vs-villa/).
    "DeepKickoff": TeamConfig(kickoff="deep"),
    # Villa's kickoff pass kicked as designed, walked up to: goals -0.05 +- 0.11 over 40 against
    # villa, territory +0.53 +- 0.53 m (benchmarks/results/walkupkickoff-vs-villa/).
    "WalkupKickoff": TeamConfig(kickoff="walkup"),
}

# The paper's Table 2, column "UTAustinVilla": goal difference (variant - base) and
# its standard error over 100 ten-minute games.
PAPER_TABLE2: dict[str, tuple[float, float]] = {
    "PositiveCombo": (0.33, 0.07), "Offensive": (0.21, 0.09), "AllBall": (0.09, 0.08),
    "PathCost": (0.07, 0.07), "NearestStopper": (0.01, 0.07), "Defensive": (-0.05, 0.05),
    "Static": (-0.19, 0.07), "NoCollAvoid": (-0.21, 0.08), "NoCommunication": (-0.30, 0.06),
    "NoTeamwork": (-1.10, 0.11), "Boxes": (-1.38, 0.11),
}


class UnknownVariant(KeyError):
    def __str__(self) -> str:
        return str(self.args[0])


def variant_name(name: str) -> str:
    """The canonical spelling of a variant's name (case-insensitive); UnknownVariant
    (one line listing the variants) for none."""
    for known in VARIANTS:
        if known.lower() == name.strip().lower():
            return known
    raise UnknownVariant(f"unknown villa variant {name!r}; variants: {', '.join(VARIANTS)}")


def variant(name: str) -> TeamConfig:
    """The TeamConfig of variant `name` (case-insensitive)."""
    return VARIANTS[variant_name(name)]


__all__ = ["FAST_KICK_FILES", "FAST_WALK_FILES", "MOSTLY_TYPE_0", "PAPER_TABLE2", "VARIANTS", "VILLA",
           "TeamConfig", "UnknownVariant", "variant", "variant_name"]
