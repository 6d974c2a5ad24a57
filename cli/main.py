"""The `soccer` command: matches, robot models and scenes, rendering and
replay of match logs, and CMA-ES optimization jobs."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from cli import teams
from cli.args import OutputError, check_writable, checked, half_time, robot_type, seed
from optimization.executor import one_thread

EXIT_USAGE = 2


class UsageError(Exception):
    """A bad command-line value; printed as one line, exit code 2."""


_team_sizes = checked(int, "team size must be a whole number", lambda n: 1 <= n <= 11,
                      "team size must be 1 to 11")
_robot_type = robot_type


def _types(value: str) -> tuple[int, ...]:
    out = tuple(_robot_type(v.strip()) for v in value.split(",") if v.strip())
    if not 1 <= len(out) <= 11:
        raise argparse.ArgumentTypeError(f"a line-up has 1 to 11 robot types, got {len(out)}")
    return out


COMMANDS = {}


class Parser(argparse.ArgumentParser):
    """argparse that reports a bad option in one line (with a hint) and exits 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    ap = Parser(prog="soccer", description=__doc__)
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=Parser)

    m = sub.add_parser("match", help="play one headless match and print the score")
    m.add_argument("--home", default="villa", help=f"left team ({', '.join(teams.names())}; default villa)")
    m.add_argument("--away", default="villa", help="right team (default villa)")
    m.add_argument("--half-time", type=half_time, default=300.0, metavar="SECONDS",
                   help="game seconds per half (default 300)")
    m.add_argument("--seed", type=seed, default=0, help="random seed (default 0)")
    m.add_argument("--home-size", type=_team_sizes, default=11, metavar="N")
    m.add_argument("--away-size", type=_team_sizes, default=11, metavar="N")
    m.add_argument("--out", type=Path, help="write the result as JSON here")
    m.add_argument("--log", type=Path, help="write the match log (.npz) here")
    m.add_argument("--quiet", action="store_true", help="no progress bar")
    m.add_argument("--view", action="store_true", help="replay the match in MuJoCo's viewer afterwards")

    mo = sub.add_parser("model", help="write one robot's MJCF")
    mo.add_argument("--type", type=_robot_type, default=0, dest="robot_type")
    mo.add_argument("--out", type=Path, required=True)

    sc = sub.add_parser("scene", help="write a whole line-up's MJCF")
    sc.add_argument("--home", type=_team_sizes, default=11, metavar="N",
                    help="players of the left team (1..11)")
    sc.add_argument("--away", type=_team_sizes, default=11, metavar="N")
    sc.add_argument("--home-types", type=_types, metavar="T,T,...",
                    help="robot types of the left team, comma separated (overrides --home)")
    sc.add_argument("--away-types", type=_types, metavar="T,T,...")
    sc.add_argument("--out", type=Path, required=True)
    for module in _plugins():
        COMMANDS.update(module.register(sub))
    return ap


# Subcommands that live beside the packages they drive (render, batch, optimize).
# Each module has register(subparsers) -> {name: handler(args) -> exit code}.
PLUGINS = ("cli.render_cmd", "cli.batch_cmd", "cli.optimize_cmd", "cli.server_cmd",
           "cli.agent_cmd")


def _plugins() -> list:
    """The plugin modules; a missing one is an ImportError, never a silent skip."""
    import importlib
    return [importlib.import_module(name) for name in PLUGINS]


def cmd_match(args: argparse.Namespace) -> int:
    from server.files import write_json
    from server.log import write_log
    from server.match import Match, lineup_for

    left = teams.factory(args.home)
    right = teams.factory(args.away)
    if args.out:
        check_writable(args.out, "--out")
    if args.log:
        check_writable(args.log, "--log")
    if args.view:
        from replay.gl import has_display
        if not has_display():
            raise UsageError("--view needs a display (DISPLAY is not set); use --log and soccer render")
    lineup = lineup_for(left, right, args.home_size, args.away_size, (args.home, args.away))
    match = Match(left, right, lineup, half_time=args.half_time, seed=args.seed,
                  record=args.log is not None or args.view, team_names=(args.home, args.away))
    result = match.run(progress=not args.quiet).to_dict()
    if args.out:
        write_json(args.out, result)
    if args.log:
        write_log(match.match_log(), args.log)
    s = result["stats"]
    print(f"{args.home} {result['score']['L']} : {result['score']['R']} {args.away}"
          f"   ({result['game_time']:.0f} game s in {result['wall_time']:.0f} s,"
          f" {result['real_time_factor']:.1f}x real time, seed {args.seed})")
    print(f"{'':12s}{'possession':>12s}{'touches':>10s}{'falls':>8s}")
    for team, name in (("L", args.home), ("R", args.away)):
        print(f"{name[:12]:12s}{100 * s[team]['possession_share']:11.0f}%"
              f"{s[team]['ball_touches']:10d}{s[team]['falls']:8d}")
    goals = [e for e in result["events"] if e["kind"] == "goal"]
    for e in goals:
        who = f" by {e['team']}{e['player']}" if e["player"] else ""
        print(f"  goal {e['time']:7.2f} s  {e['team']}{who}")
    if args.view:
        from replay.poses import Replay
        from replay.viewer import view
        view(Replay(match.match_log()))
    return 0


def cmd_model(args: argparse.Namespace) -> int:
    from models.robot import robot_mjcf
    from server.files import write_text
    check_writable(args.out, "--out")
    write_text(args.out, robot_mjcf(args.robot_type))
    print(f"wrote robot type {args.robot_type} to {args.out}")
    return 0


def cmd_scene(args: argparse.Namespace) -> int:
    from models.scene import Lineup, scene_mjcf
    from server.files import write_text
    left = args.home_types or Lineup.default(args.home, 1).left
    right = args.away_types or Lineup.default(1, args.away).right
    lineup = Lineup(tuple(left), tuple(right))
    check_writable(args.out, "--out")
    write_text(args.out, scene_mjcf(lineup))
    print(f"wrote a {len(left)} vs {len(right)} scene to {args.out}")
    return 0


def main(argv: list[str] | None = None) -> int:
    COMMANDS.update(match=cmd_match, model=cmd_model, scene=cmd_scene)
    args = build_parser().parse_args(argv)
    one_thread()  # a match or a worker per core: BLAS thread pools would only spin against them
    try:
        return COMMANDS[args.command](args)
    except (UsageError, teams.UnknownTeam, OutputError, ValueError) as exc:
        print(f"soccer {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
