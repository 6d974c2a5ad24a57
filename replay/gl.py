"""Offscreen OpenGL for rendering match logs without a screen.

`mujoco.Renderer` takes its OpenGL backend from `MUJOCO_GL` when `mujoco` is
first imported, so a process that imported `mujoco` before choosing (a test
run, a notebook, the match runner) could not render headless. This module
instead builds the context itself from MuJoCo's own backend classes
(`mujoco.egl`, `mujoco.osmesa`, `mujoco.glfw`) and drives the same calls the
Renderer makes (`mjv_updateScene`, `mjr_render`, `mjr_readPixels`).

Backends are tried in this order: the one `MUJOCO_GL` names (only that one), else
EGL, OSMesa and, where a display exists, GLFW. PyOpenGL binds one platform per
process, so after a failed EGL attempt OSMesa can only work in a new process.
"""

from __future__ import annotations

import ctypes.util
import os
import sys

import mujoco
import numpy as np

INSTALL_HINT = (
    "install an offscreen OpenGL: EGL (Debian/Ubuntu: apt-get install libegl1 libgl1-mesa-dri; "
    "then MUJOCO_GL=egl) or OSMesa (apt-get install libosmesa6; then MUJOCO_GL=osmesa)")


class RenderError(RuntimeError):
    """Rendering cannot be done on this machine or to this output (not the log's fault)."""


class GLUnavailable(RenderError):
    """No offscreen OpenGL context can be made; the message says what to install."""


def has_display() -> bool:
    """Whether a window can be opened (X11 or Wayland on Linux; always elsewhere)."""
    if sys.platform.startswith("linux"):
        return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
    return True


def backends() -> list[str]:
    """Backends to try, best first."""
    chosen = os.environ.get("MUJOCO_GL", "").strip().lower()
    if chosen in ("egl", "osmesa", "glfw"):
        return [chosen]
    out = ["egl", "osmesa"] if sys.platform.startswith("linux") else []
    if has_display():
        out.append("glfw")
    return out


def _library_missing(backend: str) -> str | None:
    """Why `backend` cannot work here, if a shared library it needs is not installed."""
    if backend == "egl" and ctypes.util.find_library("EGL") is None:
        return "libEGL not found"
    if backend == "osmesa" and ctypes.util.find_library("OSMesa") is None:
        return "libOSMesa not found"
    return None


def _context(backend: str, width: int, height: int):
    """An offscreen context of `backend` (max size in pixels), or raise."""
    missing = _library_missing(backend)
    if missing:
        raise OSError(missing)
    if backend == "egl":
        from mujoco.egl import GLContext
    elif backend == "osmesa":
        from mujoco.osmesa import GLContext
    else:
        from mujoco.glfw import GLContext
    ctx = GLContext(width, height)
    if backend == "glfw" and not getattr(ctx, "_context", None):
        raise OSError("GLFW could not open a hidden window")
    ctx.make_current()
    return ctx


_working: str | None = None


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def gl_context(width: int, height: int):
    """A current offscreen OpenGL context at least `width` x `height` pixels.

    Raises GLUnavailable naming every backend tried, why it failed and what to install.
    """
    global _working
    order = backends()
    if _working in order:
        order = [_working] + [b for b in order if b != _working]
    reasons = []
    for backend in order:
        try:
            ctx = _context(backend, width, height)
        except Exception as exc:  # noqa: BLE001  (any backend failure means: try the next)
            reasons.append(f"{backend}: {_first_line(exc)}")
            continue
        _working = backend
        return ctx
    tried = "; ".join(reasons) or "no backend for this platform"
    raise GLUnavailable(f"no offscreen OpenGL ({tried}); {INSTALL_HINT}")


def available() -> tuple[bool, str]:
    """(True, backend) if an offscreen context can be made here, else (False, reason)."""
    try:
        ctx = gl_context(16, 16)
    except GLUnavailable as exc:
        return False, str(exc)
    ctx.free()
    return True, str(_working)


class OffscreenRenderer:
    """Renders a model's scene to RGB arrays in an offscreen buffer.

    width, height: image size (pixels); shadows: draw shadows (slow in software
    GL); samples: multisample anti-aliasing samples (0 is about 2.5x faster
    with llvmpipe); slices, stacks: tessellation of spheres and capsules
    (MuJoCo's defaults 28 and 16 cost llvmpipe about 1.5x the CPU time).
    Changes `model.vis` (offscreen buffer size, samples, tessellation).
    """

    def __init__(self, model: mujoco.MjModel, width: int, height: int, shadows: bool = False,
                 samples: int = 0, slices: int = 12, stacks: int = 8) -> None:
        self.model = model
        self.width, self.height = int(width), int(height)
        self.shadows = shadows
        g = model.vis.global_
        g.offwidth = max(int(g.offwidth), self.width)
        g.offheight = max(int(g.offheight), self.height)
        model.vis.quality.offsamples = int(samples)
        model.vis.quality.numslices = int(slices)
        model.vis.quality.numstacks = int(stacks)
        self._ctx = gl_context(self.width, self.height)
        self.scene = mujoco.MjvScene(model, maxgeom=model.ngeom + 500)
        self.option = mujoco.MjvOption()
        self.perturb = mujoco.MjvPerturb()
        try:
            self._con = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_150)
        except Exception as exc:  # noqa: BLE001
            self._ctx.free()
            raise GLUnavailable(f"OpenGL context without a usable framebuffer ({_first_line(exc)}); "
                                f"{INSTALL_HINT}") from None
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._con)
        self._rect = mujoco.MjrRect(0, 0, self.width, self.height)
        self._rgb = np.empty((self.height, self.width, 3), dtype=np.uint8)

    def update(self, data: mujoco.MjData, camera: mujoco.MjvCamera) -> None:
        """Build the scene of `data`'s current poses as seen by `camera`."""
        mujoco.mjv_updateScene(self.model, data, self.option, self.perturb, camera,
                               mujoco.mjtCatBit.mjCAT_ALL, self.scene)
        self.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = self.shadows

    def render(self, data: mujoco.MjData, camera: mujoco.MjvCamera) -> np.ndarray:
        """(height, width, 3) uint8 image, top row first, of `data` seen by `camera`."""
        if self._con is None:
            raise RuntimeError("render after close")
        self._ctx.make_current()
        self.update(data, camera)
        mujoco.mjr_render(self._rect, self.scene, self._con)
        mujoco.mjr_readPixels(self._rgb, None, self._rect, self._con)
        return np.flipud(self._rgb).copy()

    def project(self, points: np.ndarray) -> np.ndarray:
        """(..., 2) pixel (column, row) of world points (..., 3) (m) in the last rendered
        image; NaN behind the camera."""
        cam = self.scene.camera[0]
        pos, fwd, up = (np.asarray(v, dtype=float) for v in (cam.pos, cam.forward, cam.up))
        right = np.cross(fwd, up)
        rel = np.asarray(points, dtype=float) - pos
        depth = rel @ fwd
        depth = np.where(depth > 1e-9, depth, np.nan)
        near = cam.frustum_near
        half_h = (cam.frustum_top - cam.frustum_bottom) / 2
        half_w = half_h * self.width / self.height
        xs = (rel @ right) / depth * near
        ys = (rel @ up) / depth * near
        col = (xs - (cam.frustum_center - half_w)) / (2 * half_w) * self.width
        row = (cam.frustum_top - ys) / (cam.frustum_top - cam.frustum_bottom) * self.height
        return np.stack([col, row], axis=-1)

    def close(self) -> None:
        """Free the OpenGL resources."""
        if self._con is not None:
            self._ctx.make_current()
            self._con.free()
            self._con = None
            self._ctx.free()

    def __enter__(self) -> OffscreenRenderer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
