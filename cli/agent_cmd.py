"""`soccer agent`: one of our agents (any team factory) as a client of a league server."""

from __future__ import annotations

import argparse
import logging

from cli import teams
from cli.args import checked, robot_type, seed
from server.protocol import TEAM_NAME

_port = checked(int, "port must be a whole number", lambda n: 1 <= n <= 65535, "port must be 1 to 65535")
_unum = checked(int, "unum must be a whole number", lambda n: 0 <= n <= 11, "unum must be 0 (any) to 11")


def _team_name(value: str) -> str:
    if not TEAM_NAME.match(value):
        raise argparse.ArgumentTypeError(f"team name must be 1 to 32 of A-Z a-z 0-9 _ . -, not {value!r}")
    return value


def register(subparsers) -> dict:
    p = subparsers.add_parser("agent", help="play one robot on a league server (ours or rcssserver3d)",
                              description=__doc__)
    p.add_argument("--host", default="127.0.0.1", help="server address (default 127.0.0.1)")
    p.add_argument("--port", type=_port, default=3100, help="agent port (default 3100)")
    p.add_argument("--team", type=_team_name, required=True, metavar="NAME", help="team name")
    p.add_argument("--unum", type=_unum, default=0, metavar="N", help="uniform number (0: any free)")
    p.add_argument("--type", type=robot_type, default=0, dest="robot_type", metavar="T",
                   help="robot type 0-4 (default 0)")
    p.add_argument("--team-impl", default="villa", metavar="TEAM",
                   help="villa (default), posture, villa:VARIANT or package.module:factory")
    p.add_argument("--seed", type=seed, default=0, help="the agent's random seed (default 0)")
    p.add_argument("--timeout", type=float, default=30.0, metavar="SECONDS",
                   help="give up when the server is silent this long (default 30)")
    return {"agent": cmd_agent}


def cmd_agent(args: argparse.Namespace) -> int:
    from server.netclient import run_agent

    factory = teams.factory(args.team_impl)
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(message)s")
    try:
        res = run_agent(args.host, args.port, args.team, args.unum, args.robot_type, factory,
                        seed=args.seed, timeout=args.timeout)
    except OSError as exc:
        print(f"soccer agent: cannot reach {args.host}:{args.port}: {exc}")
        return 1
    print(f"{args.team} {res.side}{res.unum}: {res.cycles} cycles, last {res.last_mode} at"
          f" {res.last_time:.2f} s ({res.reason})")
    return 0
