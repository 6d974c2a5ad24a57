"""3D video and stills of a match log: cameras, the score overlay and writers.

Output by the file name: `.mp4` (H.264 through the `imageio-ffmpeg` package,
which ships its own ffmpeg), `.gif` (Pillow), or a directory (no suffix) of
numbered PNG frames. Frames are sampled from the 50 Hz log at the output rate
in server time, so a video plays at real speed; replay sets poses only.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import mujoco
import numpy as np

from models import field
from replay.gl import OffscreenRenderer, RenderError
from replay.poses import Replay
from server.files import atomic_path

CAMERAS = ("broadcast", "top", "ball", "follow:PLAYER")
VIDEO_SUFFIXES = (".mp4", ".mkv", ".mov")
MAX_GIF_FRAMES = 1500  # a GIF is held in memory until written (about 0.3 MB a frame at 640x480)
FOLLOW_DISTANCE = 3.5  # m, tracking camera to the followed torso
BALL_DISTANCE = 6.0  # m, tracking camera to the ball
HEADLIGHT_AMBIENT = (0.35, 0.35, 0.35)  # brighter than MuJoCo's default 0.1: no shadows to read
HEADLIGHT_DIFFUSE = (0.5, 0.5, 0.5)
BROADCAST_SMOOTHING = 0.9  # per output frame, of the broadcast camera's pan toward the ball


def parse_camera(spec: str, players: list[str]) -> str:
    """Check a camera name (`broadcast`, `top`, `ball` or `follow:L3`); return it normalized."""
    s = spec.strip()
    if s in ("broadcast", "top", "ball"):
        return s
    if s.startswith("follow:"):
        who = s.split(":", 1)[1].strip().upper()
        if who in players:
            return f"follow:{who}"
        raise ValueError(f"camera {spec!r}: no player {who!r} in this log (players: {', '.join(players)})")
    raise ValueError(f"unknown camera {spec!r}; choose one of {', '.join(CAMERAS)}")


class CameraRig:
    """A named camera that moves with the play (one `MjvCamera`, updated per frame)."""

    def __init__(self, replay: Replay, spec: str, aspect: float) -> None:
        self.replay = replay
        self.spec = parse_camera(spec, replay.players)
        self.cam = mujoco.MjvCamera()
        self._pan: float | None = None
        self._body = -1
        cam = self.cam
        if self.spec == "top":
            cam.type = mujoco.mjtCamera.mjCAMERA_FREE
            fovy = math.radians(replay.model.vis.global_.fovy)
            half_h, half_w = field.HALF_WIDTH + 1.2, field.HALF_LENGTH + 1.2
            cam.distance = max(half_h, half_w / aspect) / math.tan(fovy / 2)
            cam.azimuth, cam.elevation = 90.0, -90.0
            cam.lookat[:] = (0.0, 0.0, 0.0)
        elif self.spec == "broadcast":
            cam.type = mujoco.mjtCamera.mjCAMERA_FREE
            cam.distance, cam.azimuth, cam.elevation = 17.0, 90.0, -28.0
        elif self.spec == "ball":
            cam.type = mujoco.mjtCamera.mjCAMERA_FREE
            cam.distance, cam.azimuth, cam.elevation = BALL_DISTANCE, 90.0, -25.0
        else:
            cam.type = mujoco.mjtCamera.mjCAMERA_FREE
            self._body = int(replay.torso_bodies[replay.players.index(self.spec.split(":", 1)[1])])
            cam.distance, cam.azimuth, cam.elevation = FOLLOW_DISTANCE, 90.0, -20.0

    def update(self, frame: int) -> mujoco.MjvCamera:
        """The camera for `frame` (call in frame order; the broadcast camera pans smoothly)."""
        if self.spec == "broadcast":
            bx, by = self.replay.ball(frame)[:2]
            target = float(np.clip(bx, -field.HALF_LENGTH + 6, field.HALF_LENGTH - 6))
            a = BROADCAST_SMOOTHING
            self._pan = target if self._pan is None else a * self._pan + (1 - a) * target
            self.cam.lookat[:] = (self._pan, float(np.clip(by, -3.0, 3.0)) * 0.5, 0.0)
        elif self.spec == "ball":
            self.cam.lookat[:] = self.replay.ball(frame)
        elif self.spec.startswith("follow:"):
            # Free camera over the body's pose set by Replay.set_frame (exact after any seek,
            # unlike a tracking camera, which only follows displacements).
            x, y, z = self.replay.data.xpos[self._body]
            self.cam.lookat[:] = (x, y, 0.6 * z)
        return self.cam


def _font(size: int):
    from PIL import ImageFont
    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1: a fixed bitmap font
        return ImageFont.load_default()


class Overlay:
    """Draws game clock, score and play mode in a band at the top of a frame."""

    def __init__(self, width: int, height: int) -> None:
        self.band = max(14, height // 16)
        self.font = _font(max(9, int(self.band * 0.7)))
        self.width = width

    def draw(self, image: np.ndarray, texts: tuple[str, str, str]) -> np.ndarray:
        """Return `image` (h, w, 3) uint8 with the band and (clock, score, mode) drawn."""
        from PIL import Image, ImageDraw
        out = image.copy()
        out[:self.band] = (out[:self.band] * 0.35).astype(np.uint8)
        pil = Image.fromarray(out)
        draw = ImageDraw.Draw(pil)
        clock, score, mode = texts
        y = self.band // 2
        pad = max(4, self.width // 80)
        draw.text((pad, y), clock, fill=(255, 255, 255), font=self.font, anchor="lm")
        draw.text((self.width // 2, y), score, fill=(255, 255, 255), font=self.font, anchor="mm")
        draw.text((self.width - pad, y), mode, fill=(255, 230, 120), font=self.font, anchor="rm")
        return np.asarray(pil)


# --------------------------------------------------------------------- writers


class _Mp4Writer:
    def __init__(self, path: Path, fps: float, size: tuple[int, int]) -> None:
        try:
            import imageio_ffmpeg
        except ImportError:
            raise RenderError(
                "MP4 needs the imageio-ffmpeg package (pip install imageio-ffmpeg, or the project's "
                "'render' extra); or write a .gif or a directory of PNG frames") from None
        w, h = size
        if w % 2 or h % 2:
            raise RenderError(f"MP4 needs an even width and height, not {w}x{h}")
        self._gen = imageio_ffmpeg.write_frames(
            str(path), (w, h), fps=fps, codec="libx264", pix_fmt_in="rgb24", pix_fmt_out="yuv420p",
            quality=None, macro_block_size=1, ffmpeg_log_level="error",
            output_params=["-crf", "23", "-preset", "veryfast"])
        self._gen.send(None)

    def write(self, frame: np.ndarray) -> None:
        self._gen.send(np.ascontiguousarray(frame))

    def close(self) -> None:
        self._gen.close()


class _GifWriter:
    def __init__(self, path: Path, fps: float) -> None:
        self.path, self.fps = path, fps
        self._frames: list = []

    def write(self, frame: np.ndarray) -> None:
        from PIL import Image
        img = Image.fromarray(frame)
        self._frames.append(img.quantize(colors=128, method=Image.Quantize.MEDIANCUT))

    def close(self) -> None:
        if self._frames:
            first, rest = self._frames[0], self._frames[1:]
            first.save(self.path, format="GIF", save_all=True, append_images=rest,
                       duration=round(1000 / self.fps), loop=0)


class _PngFrames:
    def __init__(self, directory: Path) -> None:
        directory.mkdir(parents=True, exist_ok=True)
        self.dir = directory
        self.n = 0

    def write(self, frame: np.ndarray) -> None:
        from PIL import Image
        Image.fromarray(frame).save(self.dir / f"frame_{self.n:05d}.png")
        self.n += 1

    def close(self) -> None:
        pass


def output_kind(out: Path) -> str:
    """'video', 'gif', 'png' (one picture) or 'frames' (a directory of PNG frames)."""
    suffix = out.suffix.lower()
    if suffix in VIDEO_SUFFIXES:
        return "video"
    if suffix == ".gif":
        return "gif"
    if suffix == ".png":
        return "png"
    if suffix == "" or out.is_dir():
        return "frames"
    raise ValueError(f"{out}: unknown output type {suffix!r}; use .mp4, .gif, .png or a directory")


@contextmanager
def open_writer(out: Path, fps: float, size: tuple[int, int]) -> Iterator:
    """A frame writer for `out` by its kind; files appear atomically when it closes cleanly."""
    kind = output_kind(out)
    if kind == "frames":
        w = _PngFrames(out)
        yield w
        w.close()
        return
    if kind == "png":
        raise ValueError(f"{out}: one .png is a picture (give --at); for PNG frames give a directory")
    with atomic_path(out) as tmp:
        w = _Mp4Writer(tmp, fps, size) if kind == "video" else _GifWriter(tmp, fps)
        yield w
        w.close()


# --------------------------------------------------------------------- rendering


def render_frames(replay: Replay, frames: np.ndarray, camera: str = "broadcast",
                  size: tuple[int, int] = (640, 480), overlay: bool = True,
                  shadows: bool = False) -> Iterator[np.ndarray]:
    """Yield an RGB image (h, w, 3) uint8 of each log frame in `frames`."""
    w, h = size
    rig = CameraRig(replay, camera, w / h)
    light = replay.model.vis.headlight
    light.ambient[:] = HEADLIGHT_AMBIENT
    light.diffuse[:] = HEADLIGHT_DIFFUSE
    text = Overlay(w, h) if overlay else None
    with OffscreenRenderer(replay.model, w, h, shadows=shadows) as r:
        for i in frames:
            data = replay.set_frame(int(i))
            img = r.render(data, rig.update(int(i)))
            yield text.draw(img, replay.status(int(i))) if text else img


def render_video(replay: Replay, out: str | os.PathLike, camera: str = "broadcast",
                 start: float | None = None, end: float | None = None, fps: float = 25,
                 size: tuple[int, int] = (640, 480), shadows: bool = False,
                 progress: bool = False) -> int:
    """Render game time `start`..`end` (s) of a log to `out` (.mp4, .gif or a directory
    of PNG frames) at `fps`; return the number of frames written."""
    if not 0 < fps <= 50:
        raise ValueError(f"fps must be in (0, 50] (the log has 50 frames a second), not {fps}")
    out = Path(out)
    frames = replay.frames(start, end, fps)
    parse_camera(camera, replay.players)
    if output_kind(out) == "gif" and len(frames) > MAX_GIF_FRAMES:
        raise ValueError(f"a GIF of {len(frames)} frames would be huge (at most {MAX_GIF_FRAMES}); "
                         "write .mp4, or shorten it with --from/--to or a lower --fps")
    bar = None
    if progress:
        import sys

        from tqdm import tqdm
        bar = tqdm(total=len(frames), unit="frame", file=sys.stderr, dynamic_ncols=True)
    n = 0
    try:
        with open_writer(out, fps, size) as writer:
            for img in render_frames(replay, frames, camera, size, shadows=shadows):
                writer.write(img)
                n += 1
                if bar is not None:
                    bar.update(1)
    finally:
        if bar is not None:
            bar.close()
    return n


def render_still(replay: Replay, out: str | os.PathLike, at: float, camera: str = "broadcast",
                 size: tuple[int, int] = (640, 480), shadows: bool = False) -> int:
    """Write one 3D picture (PNG) of the frame at game time `at` (s); return its frame index."""
    from PIL import Image
    i = replay.frame_at(at)
    img = next(render_frames(replay, np.array([i]), camera, size, shadows=shadows))
    _save_png(Image.fromarray(img), Path(out))
    return i


def _save_png(image, out: Path) -> None:
    """Save a PIL image as PNG atomically."""
    with atomic_path(out) as tmp:
        image.save(tmp, format="PNG")
