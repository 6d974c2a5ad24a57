"""A lone robot standing in a trainer world: the start of walk, kick and align trials,
their benchmarks and physics tests."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from models.scene import Lineup
from server.trainer import Trainer
from skills.motion import Motion
from skills.params import PathLike
from skills.walk import WalkEngine, default_param_files, load_walk_sets


def walk_motion(robot_type: int, walk_params: Iterable[PathLike] = ()) -> Motion:
    """A `Motion` walking with the shipped walk sets of `robot_type`, then `walk_params`."""
    return Motion(robot_type, WalkEngine(robot_type,
                                         load_walk_sets([*default_param_files(robot_type), *walk_params])))


def place_standing(tr: Trainer, i: int, mo: Motion, x: float, y: float, heading: float,
                   rng: np.random.Generator | None = None) -> None:
    """Put robot i on its feet at (x, y) facing `heading` (m, rad, world frame) in the
    walk's stand (`mo` reset); with `rng`, its start joints perturbed (sigma 0.01 rad)."""
    q0 = mo.walk.update(0.0, 0.0, 0.0).targets
    mo.reset()
    q0 = np.where(np.isnan(q0), 0.0, q0)
    if rng is not None:
        q0 = q0 + rng.normal(0.0, 0.01, q0.shape)
    tr.world.place_robot(i, x, y, heading, joints=q0)
    tr.world.settle_height(i)


def new_robot(robot_type: int, rng: np.random.Generator | None = None,
              walk_params: Iterable[PathLike] = ()) -> tuple[Trainer, Motion]:
    """A standing robot of `robot_type` at the field's origin facing +x, the ball out of
    the way, and its `Motion` (shipped walk sets, then `walk_params`); with `rng`,
    its start joints perturbed (sigma 0.01 rad)."""
    tr = Trainer(Lineup((robot_type,), ()), vision=False)
    tr.world.place_ball((10.0, 8.0))  # out of the way (it starts on the center spot, under the robot)
    mo = walk_motion(robot_type, walk_params)
    place_standing(tr, 0, mo, 0.0, 0.0, 0.0, rng)
    return tr, mo


__all__ = ["new_robot", "place_standing", "walk_motion"]
