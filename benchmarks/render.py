"""Rendering benchmark: 3D frames per second at 640x480, top-down pictures per second,
and the match log's size in bytes per simulated minute for 22 robots.

    python -m benchmarks.render                 # records a posture match (about 10 s)
    python -m benchmarks.render --log m.npz     # or uses a given log
    python -m benchmarks.render --json out.json

The 3D figures are for replay only: set a frame's qpos, forward kinematics,
render offscreen without shadows or multisampling, read the pixels back.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from benchmarks.machine import machine
from replay import gl
from replay.poses import Replay, load
from replay.topdown import TopDown
from replay.video import CameraRig, Overlay, render_video
from server.log import write_log


def record(half_time: float, seed: int) -> Path:
    """Record a full 11 v 11 posture match to a temporary log; return its path."""
    from agent.posture import PostureAgent
    from server.match import Match

    m = Match(PostureAgent, PostureAgent, half_time=half_time, seed=seed, record=True)
    m.run()
    path = Path(tempfile.mkdtemp(prefix="render-bench-")) / "match.npz"
    write_log(m.match_log(), path)
    return path


def log_size(path: Path, replay: Replay) -> dict:
    """Bytes of the log file and of its raw qpos per simulated minute (server time)."""
    minutes = len(replay) * 0.02 / 60
    raw = replay.log.qpos.nbytes + replay.log.targets.nbytes
    return {"frames": len(replay), "players": len(replay.players), "nq": int(replay.model.nq),
            "file_bytes": path.stat().st_size,
            "bytes_per_simulated_minute": round(path.stat().st_size / minutes),
            "raw_bytes_per_simulated_minute": round(raw / minutes)}


def bench_3d(replay: Replay, frames: np.ndarray, size=(640, 480), camera="broadcast",
             shadows=False, samples=0, overlay=False, slices=12, stacks=8) -> tuple[float, float]:
    """(frames per second, CPU ms per frame, all threads) of set-pose + render + read-back
    (+ overlay)."""
    w, h = size
    rig = CameraRig(replay, camera, w / h)
    text = Overlay(w, h) if overlay else None
    with gl.OffscreenRenderer(replay.model, w, h, shadows=shadows, samples=samples, slices=slices,
                              stacks=stacks) as r:
        for i in frames[:5]:  # warm up (llvmpipe compiles shaders on first use)
            r.render(replay.set_frame(int(i)), rig.update(int(i)))
        t, c = time.perf_counter(), time.process_time()
        for i in frames:
            img = r.render(replay.set_frame(int(i)), rig.update(int(i)))
            if text is not None:
                text.draw(img, replay.status(int(i)))
        n = len(frames)
        return n / (time.perf_counter() - t), (time.process_time() - c) / n * 1e3


def bench_topdown(replay: Replay, frames: np.ndarray, width=1200) -> tuple[float, float]:
    """(pictures per second redrawing one figure, CPU ms per picture, seconds for the first
    picture including the figure's setup)."""
    t = time.perf_counter()
    td = TopDown(width)
    td.draw(replay, int(frames[0]))
    first = time.perf_counter() - t
    t, c = time.perf_counter(), time.process_time()
    for i in frames:
        td.draw(replay, int(i))
    n = len(frames)
    return n / (time.perf_counter() - t), (time.process_time() - c) / n * 1e3, first


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--log", type=Path, help="match log to use (default: record a posture match)")
    ap.add_argument("--half-time", type=float, default=10.0, help="of the recorded match (game s)")
    ap.add_argument("--frames", type=int, default=100, help="frames per 3D measurement")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", type=Path, help="also write the figures here")
    args = ap.parse_args(argv)

    path = args.log or record(args.half_time, args.seed)
    replay = load(path)
    out: dict = {"machine": machine(), "load_average": list(os.getloadavg()), "log": log_size(path, replay)}
    s = out["log"]
    print(f"log: {s['frames']} frames, {s['players']} players, nq {s['nq']}: "
          f"{s['bytes_per_simulated_minute'] / 1e6:.2f} MB per simulated minute compressed "
          f"({s['raw_bytes_per_simulated_minute'] / 1e6:.2f} MB raw)")

    rng = np.random.default_rng(args.seed)
    start = int(rng.integers(0, max(1, len(replay) - args.frames)))
    frames = np.arange(start, min(len(replay), start + args.frames))

    ok, why = gl.available()
    if ok:
        out["backend"] = why
        runs = {"3d_640x480": {}, "3d_640x480_overlay": {"overlay": True},
                "3d_640x480_top_camera": {"camera": "top"},
                "3d_640x480_mujoco_tessellation": {"slices": 28, "stacks": 16},
                "3d_640x480_shadows": {"shadows": True},
                "3d_640x480_msaa4": {"samples": 4}}
        print(f"{'':32s} {'fps':>7s} {'CPU ms/frame':>13s}")
        for name, kw in runs.items():
            fps, cpu = bench_3d(replay, frames, **kw)
            out[name] = {"fps": round(fps, 1), "cpu_ms_per_frame": round(cpu, 1)}
            print(f"{name:32s} {fps:7.1f} {cpu:13.1f}")
        video = Path(tempfile.mkdtemp(prefix="render-bench-")) / "clip.mp4"
        t0, t1 = float(replay.log.game_time[frames[0]]), float(replay.log.game_time[frames[-1]])
        try:
            t = time.perf_counter()
            n = render_video(replay, video, start=t0, end=t1, fps=50)
            out["mp4_end_to_end_fps"] = round(n / (time.perf_counter() - t), 1)
            print(f"{'mp4_end_to_end':32s} {out['mp4_end_to_end_fps']:7.1f}  (incl. context, overlay, "
                  f"encoding; {video.stat().st_size / max(n, 1) / 1e3:.1f} kB/frame)")
        except gl.RenderError as exc:
            print(f"mp4: skipped ({exc})")
    else:
        print(f"3D: skipped ({why})")
    fps, cpu, first = bench_topdown(replay, frames[: max(10, args.frames // 4)])
    out["topdown_1200"] = {"fps": round(fps, 1), "cpu_ms_per_frame": round(cpu, 1),
                           "first_s": round(first, 3)}
    print(f"{'topdown_1200':32s} {fps:7.1f} {cpu:13.1f}  (first picture incl. figure setup {first:.2f} s)")
    out["load_average_after"] = list(os.getloadavg())
    print(f"load average before {out['load_average'][0]:.1f}, after {out['load_average_after'][0]:.1f} "
          f"on {out['machine']['cores']} cores")
    if args.json:
        args.json.write_text(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
