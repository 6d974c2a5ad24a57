"""`soccer render` and `soccer view`: video, pictures and the interactive viewer
from a match log (the `replay` package)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from cli.args import checked

EXIT_USAGE = 2
EXIT_ENVIRONMENT = 1  # rendering impossible here (no OpenGL, no encoder), not the user's input

RENDER_HELP = """\
Outputs, by --out:
  NAME.mp4          3D video (H.264 through imageio-ffmpeg)
  NAME.gif          3D video as an animated GIF
  DIR               a directory of numbered PNG frames of the 3D video
  NAME.png --at T   the top-down field picture at game time T (matplotlib, no OpenGL);
                    with --camera, a 3D picture from that camera instead
Times (--from, --to, --at) are game time in seconds, the clock drawn on the frames.
Headless machines render 3D through EGL or OSMesa (MUJOCO_GL=egl|osmesa picks one).

examples:
  soccer render match.npz --out match.mp4 --from 30 --to 60
  soccer render match.npz --out goal.gif --camera ball --fps 10 --size 320x240
  soccer render match.npz --out field.png --at 42 --trail 10
"""


_seconds = checked(float, "expected seconds", lambda v: v >= 0, "seconds must not be negative")
_fps = checked(float, "expected frames per second", lambda v: 0 < v <= 50,
               "fps must be above 0 and at most 50 (the log rate)")


def _size(value: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in value.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must be WIDTHxHEIGHT, e.g. 640x480, not {value!r}") from None
    if not (16 <= w <= 4096 and 16 <= h <= 4096) or w % 2 or h % 2:
        raise argparse.ArgumentTypeError(f"size must be even numbers of pixels from 16 to 4096, not {value}")
    return w, h


def register(subparsers) -> dict:
    """Add `render` and `view` to the `soccer` command's subparsers."""
    r = subparsers.add_parser("render", help="video or pictures of a match log",
                              description="Render a match log (soccer match --log) to a video or a picture.",
                              epilog=RENDER_HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("log", type=Path, help="match log (.npz)")
    r.add_argument("--out", type=Path, required=True, help="output: .mp4, .gif, .png or a directory")
    r.add_argument("--camera", default=None, metavar="NAME",
                   help="broadcast (default), top, ball or follow:PLAYER (e.g. follow:L7)")
    r.add_argument("--from", dest="start", type=_seconds, metavar="SECONDS", help="start (game time)")
    r.add_argument("--to", dest="end", type=_seconds, metavar="SECONDS", help="end (game time)")
    r.add_argument("--at", type=_seconds, metavar="SECONDS", help="moment of a .png picture (game time)")
    r.add_argument("--trail", type=_seconds, nargs="?", const=10.0, metavar="SECONDS",
                   help="picture: paths over the SECONDS before --at (default 10), or from --from")
    r.add_argument("--fps", type=_fps, default=25.0, help="video frames per second (default 25)")
    r.add_argument("--size", type=_size, default=None, metavar="WxH",
                   help="image size (default 640x480 for 3D, 1200 wide for the picture)")
    r.add_argument("--shadows", action="store_true", help="draw shadows (slow without a GPU)")
    r.add_argument("--quiet", action="store_true", help="no progress bar")

    v = subparsers.add_parser("view", help="watch a match log in MuJoCo's viewer (needs a display)",
                              description="Open MuJoCo's interactive viewer on a match log: space plays "
                                          "or pauses, arrows seek 1 s, page up/down 5 s, [ ] change speed.")
    v.add_argument("log", type=Path, help="match log (.npz)")
    return {"render": cmd_render, "view": cmd_view}


def _error(command: str, message: str, code: int) -> int:
    print(f"soccer {command}: error: {message}", file=sys.stderr)
    return code


def gl_env_problem() -> str | None:
    """What is wrong when MUJOCO_GL names a backend whose library is missing (importing
    mujoco would then fail with a PyOpenGL traceback), else None."""
    import ctypes.util
    import os

    want = os.environ.get("MUJOCO_GL", "").strip().lower()
    needs = {"egl": ("EGL", "libegl1 libgl1-mesa-dri"), "osmesa": ("OSMesa", "libosmesa6")}
    if want in needs and ctypes.util.find_library(needs[want][0]) is None:
        lib, debian = needs[want]
        return (f"MUJOCO_GL={want} but lib{lib} is not installed (Debian/Ubuntu: apt-get install {debian}); "
                "install it, or unset MUJOCO_GL to let the renderer choose")
    return None


def cmd_render(args: argparse.Namespace) -> int:
    problem = gl_env_problem()
    if problem:
        return _error("render", problem, EXIT_ENVIRONMENT)
    from replay.gl import RenderError
    from server.log import LogError

    try:
        return _render(args)
    except LogError as exc:
        return _error("render", str(exc), EXIT_USAGE)
    except RenderError as exc:
        return _error("render", str(exc), EXIT_ENVIRONMENT)
    except ValueError as exc:
        return _error("render", str(exc), EXIT_USAGE)


def _render(args: argparse.Namespace) -> int:
    from replay.poses import load
    from replay.video import output_kind, parse_camera, render_still, render_video

    kind = output_kind(args.out)
    if kind == "png" and args.at is None:
        raise ValueError(f"{args.out}: a .png picture needs --at SECONDS (for PNG frames give a directory)")
    if kind != "png" and (args.at is not None or args.trail is not None):
        raise ValueError("--at and --trail are for a .png picture; use --from/--to for a video")
    if args.start is not None and args.end is not None and args.end < args.start:
        raise ValueError(f"--to {args.end} is before --from {args.start}")
    from cli.args import check_writable
    check_writable(args.out, "--out", directory=kind == "frames")
    replay = load(args.log)
    if args.camera is not None:
        parse_camera(args.camera, replay.players)
    if kind == "png" and args.camera is None:
        from replay.topdown import save_topdown
        width = args.size[0] if args.size else 1200
        i = save_topdown(replay, args.out, args.at, trail=args.trail,
                         start=args.start if args.trail is not None else None, width=width)
        print(f"wrote the top-down picture at game time {replay.log.game_time[i]:.2f} s to {args.out}")
        return 0
    size = args.size or (640, 480)
    camera = args.camera or "broadcast"
    if kind == "png":
        i = render_still(replay, args.out, args.at, camera, size, args.shadows)
        print(f"wrote a {camera} picture at game time {replay.log.game_time[i]:.2f} s to {args.out}")
        return 0
    n = render_video(replay, args.out, camera, args.start, args.end, args.fps, size, args.shadows,
                     progress=not args.quiet)
    print(f"wrote {n} frames ({n / args.fps:.1f} s at {args.fps:g} fps, {camera} camera) to {args.out}")
    return 0


def cmd_view(args: argparse.Namespace) -> int:
    from replay.gl import has_display
    from server.log import LogError

    if not has_display():  # before reading the log: the answer does not depend on it
        return _error("view", "no display (DISPLAY is not set): the viewer needs a screen; "
                      f"render a video instead: soccer render {args.log} --out match.mp4", EXIT_USAGE)
    from replay.poses import load
    from replay.viewer import view
    try:
        view(load(args.log))
    except LogError as exc:
        return _error("view", str(exc), EXIT_USAGE)
    return 0
