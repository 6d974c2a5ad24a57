"""Named parameters <-> the CMA-ES vector, and UT-style parameter files."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from optimization.paramvec import ParamSpace, load_values, param_set, write_param_file
from skills.params import ParamError
from skills.walk import WalkParams, default_param_files, load_walk_sets


def test_vector_maps_to_named_values_in_file_units():
    base = load_values(["go_to_target", "sprint"], 0)
    height_m = load_walk_sets(default_param_files(0))["go_to_target"].walk_height
    height = 1000.0 * height_m  # mm, as the file writes it
    assert base["go_to_target"]["walk_height"] == pytest.approx(height)
    space = ParamSpace.build(base, {"sprint": ("walk_height", "phase_length")})
    assert space.keys == (("sprint", "walk_height"), ("sprint", "phase_length"))
    v = space.values(np.array([1.0, 0.5]))  # type 0's sprint phase_length lies 2 ms above its bound
    spec_h, spec_p = param_set("sprint").spec("walk_height"), param_set("sprint").spec("phase_length")
    assert v["sprint"]["walk_height"] == pytest.approx(base["sprint"]["walk_height"] + spec_h.sigma)
    assert v["sprint"]["phase_length"] == pytest.approx(base["sprint"]["phase_length"] + 0.5 * spec_p.sigma)
    assert v["go_to_target"] == base["go_to_target"]  # frozen set untouched
    assert space.named(np.zeros(2)) == pytest.approx({"sprint_walk_height": base["sprint"]["walk_height"],
                                                      "sprint_phase_length": base["sprint"]["phase_length"]})


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(-50, 50), min_size=3, max_size=3))
def test_values_stay_within_bounds(z):
    space = ParamSpace.build(load_values(["go_to_target"], 0),
                             {"go_to_target": ("walk_height", "fraction_moving", "phase_length")})
    x = space.vector(np.array(z))
    assert np.all(x >= space.lower) and np.all(x <= space.upper)


def test_best_file_is_read_by_the_walk_loader(tmp_path):
    base = load_values(["go_to_target", "sprint"], 0)
    space = ParamSpace.build(base, {"sprint": ("max_step_size_x",), "go_to_target": ("phase_length",)})
    values = space.values(np.array([2.0, 1.0]))
    path = tmp_path / "best.txt"
    write_param_file(path, values, "a header\nof two lines")
    sets = load_walk_sets([*default_param_files(0), path])
    assert sets["sprint"].max_step_size_x == pytest.approx(values["sprint"]["max_step_size_x"] * 1e-3)
    assert sets["go_to_target"].phase_length == pytest.approx(values["go_to_target"]["phase_length"])
    assert sets["sprint"].phase_length == pytest.approx(base["sprint"]["phase_length"])
    # And the optimizer's own loader reads it back exactly (6 significant digits).
    again = load_values(["go_to_target", "sprint"], 0, [path])
    assert again["sprint"]["max_step_size_x"] == pytest.approx(values["sprint"]["max_step_size_x"], rel=1e-5)


def test_unknown_parameter_names_file_and_line(tmp_path):
    p = tmp_path / "bad.txt"
    p.write_text("walk_height\t180\nwalk_hieght\t170\n")
    with pytest.raises(ParamError, match=r"bad.txt:2: unknown parameter 'walk_hieght'"):
        load_values(["go_to_target"], 0, [p])


def test_named_specs_are_learned_only_when_named():
    base = load_values(["go_to_target"], 0)
    everything = ParamSpace.build(base, {"go_to_target": None})
    assert ("go_to_target", "joint_kp") not in everything.keys and everything.dim == 27
    named = ParamSpace.build(base, {"go_to_target": ("joint_kp", "walk_height")})
    assert named.keys == (("go_to_target", "joint_kp"), ("go_to_target", "walk_height"))
    assert named.x0[0] == pytest.approx(base["go_to_target"]["joint_kp"])
    assert named.scale[0] == param_set("go_to_target").spec("joint_kp").sigma
    steep = ParamSpace.build(base, {"go_to_target": ("swing_steepness",)})  # the engine's own 10
    assert steep.x0[0] == WalkParams().swing_steepness


def test_selection_errors():
    base = load_values(["go_to_target"], 0)
    with pytest.raises(KeyError, match="no parameter"):
        ParamSpace.build(base, {"go_to_target": ("nonsense",)})
    with pytest.raises(KeyError, match="does not use"):
        ParamSpace.build(base, {"sprint": None})
