"""The machine a benchmark ran on, printed with its figures."""

from __future__ import annotations

import os
import platform


def cpu_model() -> str:
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def machine() -> dict:
    """Platform, CPU, core count and the versions of the numeric packages in use."""
    import numpy

    info = {
        "platform": platform.platform(), "cpu": cpu_model(), "cores": os.cpu_count(),
        "python": platform.python_version(), "numpy": numpy.__version__,
    }
    try:
        import mujoco
        info["mujoco"] = mujoco.__version__
    except ImportError:
        pass
    return info
