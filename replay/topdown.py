"""The top-down picture of the field (matplotlib, no OpenGL).

Every player is a disc in its team's color (left blue, right red) with its
uniform number beside it and a tick along its heading; a fallen player (torso
up axis z below 0.5) gets a black cross. The ball is an orange disc drawn
larger than life. When the log holds them, each player's role target is a
small cross joined to the player by a dashed line (the role assignment).
A trail shows player and ball paths over a time window.

The picture maps the field frame linearly to pixels (see `TopDown.pixel`), so
a position in the log can be checked against a pixel of the image.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from models import field
from replay.poses import Replay

TEAM_COLORS = {"L": (0.15, 0.35, 0.9), "R": (0.9, 0.2, 0.15)}  # as models.robot.TEAM_RGBA
GRASS = (0.2, 0.55, 0.2)
BALL_COLOR = (1.0, 0.5, 0.0)
PLAYER_RADIUS = 0.35  # m, drawn disc
BALL_DRAW_RADIUS = 0.2  # m, drawn (the ball's real radius is 0.042 m)
HEADING_LENGTH = 0.7  # m, from the player's center
MARGIN = 1.5  # m of grass around the field lines


class TopDown:
    """A reusable top-down figure: the field is drawn once, players and ball per call.

    width: image width (pixels); the height follows the field's aspect.
    """

    def __init__(self, width: int = 1200) -> None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.x0, self.x1 = -field.HALF_LENGTH - MARGIN, field.HALF_LENGTH + MARGIN
        self.y0, self.y1 = -field.HALF_WIDTH - MARGIN, field.HALF_WIDTH + MARGIN
        self.width = int(width)
        self.height = int(round(self.width * (self.y1 - self.y0) / (self.x1 - self.x0)))
        dpi = 100
        self.fig = Figure(figsize=(self.width / dpi, self.height / dpi), dpi=dpi, facecolor=GRASS)
        self.canvas = FigureCanvasAgg(self.fig)
        ax = self.fig.add_axes((0, 0, 1, 1))
        ax.set_xlim(self.x0, self.x1)
        ax.set_ylim(self.y0, self.y1)
        ax.set_axis_off()
        ax.set_facecolor(GRASS)
        self.ax = ax
        self.scale = self.width / (self.x1 - self.x0)  # pixels per meter
        self._draw_field()
        self._dynamic: list = []

    def pixel(self, x: float | np.ndarray, y: float | np.ndarray) -> np.ndarray:
        """(..., 2) pixel (column, row) of field point(s) (m), row 0 at the top (+y)."""
        col = (np.asarray(x) - self.x0) / (self.x1 - self.x0) * self.width
        row = (self.y1 - np.asarray(y)) / (self.y1 - self.y0) * self.height
        return np.stack([col, row], axis=-1)

    def _draw_field(self) -> None:
        from matplotlib.collections import LineCollection
        from matplotlib.patches import Rectangle

        lw = max(1.0, 0.05 * self.scale * 72 / 100)  # 5 cm lines, in points
        segs = field.FIELD_LINES[:, :, :2]
        self.ax.add_collection(LineCollection(segs, colors="white", linewidths=lw, zorder=1))
        for sx in (-1, 1):
            x = sx * field.HALF_LENGTH
            self.ax.add_patch(Rectangle((x if sx > 0 else x - field.GOAL_DEPTH, -field.GOAL_WIDTH / 2),
                                        field.GOAL_DEPTH, field.GOAL_WIDTH, facecolor=(0.85, 0.85, 0.85),
                                        edgecolor="white", linewidth=lw, zorder=1))

    def _points(self, meters: float) -> float:
        """Marker size (points^2 for scatter) of a disc `meters` in radius."""
        diameter_pt = 2 * meters * self.scale * 72 / self.fig.dpi
        return diameter_pt ** 2

    def draw(self, replay: Replay, frame: int, trail: tuple[int, int] | None = None,
             title: bool = True) -> np.ndarray:
        """Draw frame `frame` (and paths over frames trail[0]..trail[1]); return RGB (h, w, 3) uint8."""
        for artist in self._dynamic:
            artist.remove()
        self._dynamic = []
        ax, add = self.ax, self._dynamic.append
        pos = replay.positions(frame)[:, :2]
        heading = replay.headings(frame)
        fallen = replay.fallen(frame)
        targets = replay.targets(frame)
        colors = np.array([TEAM_COLORS.get(s, (0.7, 0.7, 0.7)) for s in replay.sides])
        if trail is not None:
            idx = np.arange(max(trail[0], 0), min(trail[1], len(replay) - 1) + 1)
            paths = replay.positions(idx)[:, :, :2]  # (F, n, 2)
            for k in range(len(replay.players)):
                (line,) = ax.plot(paths[:, k, 0], paths[:, k, 1], color=colors[k], alpha=0.6,
                                  linewidth=1.2, zorder=2)
                add(line)
            b = replay.ball(idx)
            (line,) = ax.plot(b[:, 0], b[:, 1], color=BALL_COLOR, linewidth=1.2, linestyle="--", zorder=2)
            add(line)
        have = ~np.isnan(targets).any(axis=1)
        if have.any():
            from matplotlib.collections import LineCollection
            segs = np.stack([pos[have], targets[have]], axis=1)
            lc = LineCollection(segs, colors=colors[have], linewidths=1.0, linestyles="--", alpha=0.8,
                                zorder=3)
            ax.add_collection(lc)
            add(lc)
            add(ax.scatter(targets[have, 0], targets[have, 1], marker="x", s=self._points(0.2),
                           c=colors[have], linewidths=1.5, zorder=3))
        tip = pos + HEADING_LENGTH * np.stack([np.cos(heading), np.sin(heading)], axis=1)
        from matplotlib.collections import LineCollection
        ticks = LineCollection(np.stack([pos, tip], axis=1), colors="black", linewidths=1.5, zorder=4)
        ax.add_collection(ticks)
        add(ticks)
        add(ax.scatter(pos[:, 0], pos[:, 1], s=self._points(PLAYER_RADIUS), c=colors, edgecolors="black",
                       linewidths=0.8, zorder=5))
        if fallen.any():
            add(ax.scatter(pos[fallen, 0], pos[fallen, 1], marker="x", s=self._points(PLAYER_RADIUS),
                           c="black", linewidths=2.0, zorder=6))
        fs = max(6.0, 0.45 * self.scale * 72 / self.fig.dpi)
        for k, u in enumerate(replay.unums):
            add(ax.text(pos[k, 0] + PLAYER_RADIUS * 0.9, pos[k, 1] + PLAYER_RADIUS * 0.9, str(u),
                        color="white", fontsize=fs, fontweight="bold", ha="left", va="bottom", zorder=7))
        ball = replay.ball(frame)
        add(ax.scatter([ball[0]], [ball[1]], s=self._points(BALL_DRAW_RADIUS), c=[BALL_COLOR],
                       edgecolors="black", linewidths=0.6, zorder=8))
        if title:
            clock, score, mode = replay.status(frame)
            add(ax.text(0.5, 1 - 0.2 * MARGIN / (self.y1 - self.y0), f"{clock}    {score}    {mode}",
                        transform=ax.transAxes, ha="center", va="top", color="white",
                        fontsize=1.2 * fs, zorder=9))
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[:, :, :3].copy()


def save_topdown(replay: Replay, out: str | os.PathLike, at: float, trail: float | None = None,
                 start: float | None = None, width: int = 1200) -> int:
    """Write the top-down PNG of the frame at game time `at` (s); with `trail` (s), or
    `start` (s), draw paths from `start` (default `at - trail`) to `at`. Returns the frame."""
    from PIL import Image

    from replay.video import _save_png
    i = replay.frame_at(at)
    window = None
    if trail is not None or start is not None:
        t0 = start if start is not None else at - float(trail)
        window = (replay.frame_at(t0), i)
    img = TopDown(width).draw(replay, i, window)
    _save_png(Image.fromarray(img), Path(out))
    return i
