"""Seeing a match: replay, video and pictures from match logs.

A match log (`server.log`) holds the scene's MJCF and the whole `qpos` of every
20 ms cycle. Replaying never runs physics: a frame's `qpos` is copied into
`MjData` and forward kinematics (`mj_kinematics`) places every body.

Modules:
  * `poses`: `Replay`, a log with its MuJoCo model, frame lookup by game time and
    vectorized player poses (field frame) straight from `qpos`;
  * `topdown`: the top-down field picture (matplotlib, no OpenGL);
  * `gl`: offscreen OpenGL contexts (EGL, OSMesa, GLFW) and `OffscreenRenderer`;
  * `video`: cameras, the score overlay and MP4, GIF and PNG-frame output;
  * `viewer`: MuJoCo's interactive viewer with play, pause and seek.
"""

from replay.poses import Replay, load

__all__ = ["Replay", "load"]
