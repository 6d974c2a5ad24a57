"""The motor model (models/robot.py): velocity servos with a force limit that, at the
limit, push steadily instead of flipping between +limit and -limit every substep."""

import mujoco
import numpy as np
import pytest

from models.messages import Action
from optimization.robot import new_robot

WALK_S = 3.0  # s of full-speed forward walking measured, after 1 s of getting going


@pytest.mark.parametrize("robot_type", [0, 3])
def test_leg_motors_at_their_force_limit_do_not_chatter(robot_type, monkeypatch):
    """Walking forward at full speed, no leg motor spends more than 5% of the 5 ms
    substeps at its force limit with the sign flipped since the substep before. With an
    armature of 0.01 kg m^2 the ankle rolls did so in 60-80% of substeps (the feet
    bounced off the ground and 23 of 100 walk-course runs fell)."""
    tr, mo = new_robot(robot_type, np.random.default_rng([robot_type, 5]))
    m = tr.world.model
    p = tr.world.players[0]
    legs = np.array([a for a, n in zip(p.actuators, (m.actuator(int(a)).name for a in p.actuators))
                     if "le" in n.split("/")[-1]])
    limit = m.actuator_forcerange[legs, 1]
    forces: list[np.ndarray] = []
    step = mujoco.mj_step

    def recording_step(model, data):
        step(model, data)
        forces.append(data.actuator_force[legs].copy())

    cycles = round((1.0 + WALK_S) / 0.02)
    for c in range(cycles):
        if c == round(1.0 / 0.02):
            monkeypatch.setattr(mujoco, "mj_step", recording_step)
        pc = tr.percepts()[0]
        tr.step({0: Action(mo.walk_step(pc, 1.0, 0.0, 0.0))})
        assert tr.world.torso_up()[0] > 0.8, f"fell at {tr.world.time:.2f} s"
    f = np.array(forces)
    at_limit = np.abs(f[1:]) >= 0.999 * limit
    flipped = np.sign(f[1:]) != np.sign(f[:-1])
    # Within a cycle the command holds: a flip there is the servo's, not the controller's.
    within = (np.arange(1, len(f)) % tr.world.substeps != 0)[:, None]
    chatter = np.mean(at_limit & flipped & within, axis=0)
    worst = int(np.argmax(chatter))
    assert chatter[worst] < 0.05, f"{m.actuator(int(legs[worst])).name}: {chatter[worst]:.0%} of substeps"
