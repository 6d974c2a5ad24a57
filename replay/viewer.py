"""MuJoCo's interactive viewer on a match log: play, pause and seek.

Keys: space plays or pauses; right and left arrows seek 1 s (5 s with page up and
page down); home and end jump to the log's ends; `[` and `]` halve or double the
playback speed. The viewer needs a display; without one `view` raises
`NoDisplay` before touching OpenGL.
"""

from __future__ import annotations

import time

from replay.gl import RenderError, has_display
from replay.poses import Replay

# GLFW key codes (as passed to the viewer's key callback).
KEY_SPACE, KEY_RIGHT, KEY_LEFT = 32, 262, 263
KEY_PAGE_UP, KEY_PAGE_DOWN, KEY_HOME, KEY_END = 266, 267, 268, 269
KEY_LEFT_BRACKET, KEY_RIGHT_BRACKET = 91, 93
SEEK_SMALL = 1.0  # s of server time
SEEK_LARGE = 5.0


class NoDisplay(RenderError):
    """The interactive viewer was asked for where no display exists."""


class Playback:
    """Which log frame to show, as a function of wall time and the user's keys.

    Time here is server time (s) from the log's first frame; `frame_rate` is the
    log's frames per second.
    """

    def __init__(self, n_frames: int, frame_rate: float = 50.0, playing: bool = True) -> None:
        self.n = n_frames
        self.rate = frame_rate
        self.playing = playing
        self.speed = 1.0
        self.position = 0.0  # s into the log
        self._wall: float | None = None

    @property
    def end(self) -> float:
        return (self.n - 1) / self.rate

    def tick(self, wall: float) -> int:
        """Advance to wall-clock time `wall` (s) and return the frame to show."""
        if self.playing and self._wall is not None:
            self.position = min(self.end, self.position + (wall - self._wall) * self.speed)
            if self.position >= self.end:
                self.playing = False
        self._wall = wall
        return self.frame

    @property
    def frame(self) -> int:
        return int(round(self.position * self.rate))

    def seek(self, seconds: float) -> None:
        self.position = min(self.end, max(0.0, self.position + seconds))

    def key(self, code: int) -> None:
        """React to a key (GLFW code)."""
        if code == KEY_SPACE:
            if not self.playing and self.position >= self.end:
                self.position = 0.0
            self.playing = not self.playing
        elif code == KEY_RIGHT:
            self.seek(SEEK_SMALL)
        elif code == KEY_LEFT:
            self.seek(-SEEK_SMALL)
        elif code == KEY_PAGE_UP:
            self.seek(SEEK_LARGE)
        elif code == KEY_PAGE_DOWN:
            self.seek(-SEEK_LARGE)
        elif code == KEY_HOME:
            self.position = 0.0
        elif code == KEY_END:
            self.position = self.end
        elif code == KEY_LEFT_BRACKET:
            self.speed = max(0.125, self.speed / 2)
        elif code == KEY_RIGHT_BRACKET:
            self.speed = min(8.0, self.speed * 2)


def view(replay: Replay) -> None:
    """Open MuJoCo's viewer on `replay` and play it until the window closes."""
    if not has_display():
        raise NoDisplay("no display (DISPLAY is not set): the viewer needs a screen; "
                        "render a video instead (soccer render LOG --out match.mp4)")
    import mujoco.viewer

    rate = (len(replay) - 1) / replay.duration if replay.duration > 0 else 50.0
    play = Playback(len(replay), rate)
    replay.set_frame(0)
    with mujoco.viewer.launch_passive(replay.model, replay.data, key_callback=play.key,
                                      show_left_ui=False, show_right_ui=False) as v:
        v.cam.distance, v.cam.azimuth, v.cam.elevation = 20.0, 90.0, -35.0
        shown = -1
        while v.is_running():
            i = play.tick(time.monotonic())
            if i != shown:
                with v.lock():
                    replay.set_frame(i)
                shown = i
            clock, score, mode = replay.status(i)
            state = "" if play.playing else "  (paused)"
            v.set_texts((None, None, f"{clock}  {score}  {mode}",
                         f"x{play.speed:g}{state}  space: play/pause, arrows: seek"))
            v.sync()
            time.sleep(1 / 60)
