"""The kicks (dissertation 8.2.7): the interface every kick offers and the registry of
a robot type's shipped kicks.

* `skills.kicks.spec`: `KickSpec` (where the ball must lie, where it goes, how far)
  and the `KickSkill` protocol; the frames are described there;
* `skills.kicks.keyframe`: keyframe kicks (``kick.skl`` with the sets of ``kick.params``);
* `skills.kicks.ik`: inverse-kinematics kicks on Hermite splines (``ikkick.params``);
* here: `all_kicks`, every shipped kick of a robot type by name.

The kick modules import only `skills.kicks.spec`; this module imports them.
"""

from __future__ import annotations

from collections.abc import Iterable

from skills.kicks.ik import ik_kicks
from skills.kicks.keyframe import keyframe_kicks
from skills.kicks.spec import KickSkill, KickSpec
from skills.params import PathLike


def all_kicks(robot_type: int, keyframe_params: Iterable[PathLike] = (),
              ik_params: Iterable[PathLike] = ()) -> dict[str, KickSkill]:
    """Every shipped kick of a robot type by name: the keyframe kicks (`skills.kicks.keyframe`)
    and the inverse-kinematics kicks (`skills.kicks.ik`); parameter files given here
    override the shipped values (e.g. a CMA-ES result)."""
    kicks: dict[str, KickSkill] = dict(keyframe_kicks(robot_type, keyframe_params))
    for name, kick in ik_kicks(robot_type, ik_params).items():
        if name in kicks:
            raise ValueError(f"kick {name!r} is both a keyframe and an IK kick")
        kicks[name] = kick
    return kicks


__all__ = ["KickSkill", "KickSpec", "all_kicks"]
