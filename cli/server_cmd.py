"""`soccer server`: our world and referee behind the league's agent protocol (TCP)."""

from __future__ import annotations

import argparse
import logging
from pathlib import Path

from cli.args import check_writable, checked, half_time, seed

_port = checked(int, "port must be a whole number", lambda n: 0 <= n <= 65535, "port must be 0 to 65535")
_players = checked(int, "players must be a whole number", lambda n: 1 <= n <= 22, "players must be 1 to 22")
_interval = checked(int, "interval must be a whole number", lambda n: 1 <= n <= 1000,
                    "interval must be 1 to 1000 cycles")
_seconds = checked(float, "expected a number of seconds", lambda v: 0 < v <= 3600,
                   "seconds must be positive and at most 3600")

HELP = """\
Agents connect to HOST:PORT and speak rcssserver3d's agent protocol: 4-byte
big-endian length frames of S-expressions; (scene rsg/agent/nao/nao_hetero.rsg
TYPE), (init (unum N)(teamname NAME)), hinge effectors in rad/s, (beam X Y ROT),
(say MSG), (syn). The first team to init plays left. The match starts when
--players agents have joined (or --wait seconds after the first did).

  soccer server --players 2 --sync --half-time 10 --out result.json &
  soccer agent --team A --unum 1 --type 0 & soccer agent --team B --unum 1 --type 0
"""


def register(subparsers) -> dict:
    """Add `server` to the `soccer` command."""
    p = subparsers.add_parser("server", help="our world behind the league's agent protocol",
                              description=__doc__, epilog=HELP,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1)")
    p.add_argument("--port", type=_port, default=3100, help="agent port (default 3100)")
    p.add_argument("--sync", action="store_true",
                   help="agentSyncMode: step as soon as every agent sent (syn) (default: real time)")
    p.add_argument("--timeout", type=_seconds, default=1.0, metavar="SECONDS",
                   help="sync mode: longest wait for the agents' answers per cycle (default 1)")
    p.add_argument("--players", type=_players, default=22, metavar="N",
                   help="start when N agents have joined (default 22)")
    p.add_argument("--wait", type=_seconds, metavar="SECONDS",
                   help="start this long after the first agent joined, even with fewer")
    p.add_argument("--half-time", type=half_time, default=300.0, metavar="SECONDS",
                   help="game seconds per half (default 300)")
    p.add_argument("--seed", type=seed, default=0, help="random seed (default 0)")
    p.add_argument("--monitor-port", type=_port, metavar="PORT",
                   help="serve rcssserver3d's monitor protocol (RoboViz) here, e.g. 3200 (default: off)")
    p.add_argument("--monitor-interval", type=_interval, default=1, metavar="CYCLES",
                   help="cycles between monitor updates (default 1: 50 Hz)")
    p.add_argument("--out", type=Path, help="write the result as JSON here")
    p.add_argument("--log", type=Path, help="write the match log (.npz) here")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return {"server": cmd_server}


def cmd_server(args: argparse.Namespace) -> int:
    from server.files import write_json
    from server.log import write_log
    from server.netserver import NetServer

    if args.out:
        check_writable(args.out, "--out")
    if args.log:
        check_writable(args.log, "--log")
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(message)s")
    srv = NetServer(args.host, args.port, sync=args.sync, half_time=args.half_time, seed=args.seed,
                    players=args.players, wait=args.wait, timeout=args.timeout,
                    record=args.log is not None, monitor_port=args.monitor_port,
                    monitor_interval=args.monitor_interval)
    host, port = srv.address
    print(f"listening on {host}:{port} for {args.players} agents"
          f" ({'sync' if args.sync else 'real-time'} mode)", flush=True)
    if srv.monitor is not None:
        print(f"monitor port {srv.monitor.address[0]}:{srv.monitor.address[1]}", flush=True)
    srv.join()
    m = srv.build()
    print(f"playing {m.team_names[0]} {list(m.lineup.left)} vs {m.team_names[1]} {list(m.lineup.right)}",
          flush=True)
    result = srv.run(progress=not args.quiet).to_dict()
    if args.out:
        write_json(args.out, result)
    if args.log:
        write_log(m.match_log(), args.log)
    crashed = [e for e in result["events"] if e["kind"] == "agent_crashed"]
    print(f"{m.team_names[0]} {result['score']['L']} : {result['score']['R']} {m.team_names[1]}"
          f"   ({result['game_time']:.0f} game s in {result['wall_time']:.0f} s, seed {args.seed},"
          f" {len(crashed)} agents crashed)")
    return 0
