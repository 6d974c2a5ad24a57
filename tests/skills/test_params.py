"""Parameter files: format, units, overrides, prefixed sets and error messages."""

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from skills.params import ParamError, load_param_sets, load_params, parse_params

SCHEMA = {"walk_height": "mm", "max_step_size_angle": "rad", "tilt": "deg", "phase_length": "s", "gain": "1"}


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_units_converted_once_at_load(tmp_path):
    p = write(tmp_path, "a.txt", "walk_height\t175\nmax_step_size_angle 1.22\ntilt\t90\n"
                                 "phase_length\t0.38\ngain\t2\n")
    v = load_params([p], SCHEMA)
    assert v["walk_height"] == pytest.approx(0.175)
    assert v["max_step_size_angle"] == pytest.approx(1.22)
    assert v["tilt"] == pytest.approx(math.pi / 2)
    assert v["phase_length"] == pytest.approx(0.38)
    assert v["gain"] == 2.0


def test_comments_and_blank_lines(tmp_path):
    p = write(tmp_path, "a.txt", "# a comment\n\n// another\nwalk_height\t175 # mm\ngain 3 // x\n   \n")
    assert load_params(p, SCHEMA) == pytest.approx({"walk_height": 0.175, "gain": 3.0})


def test_later_files_override_earlier(tmp_path):
    a = write(tmp_path, "a.txt", "walk_height\t175\ngain\t1\n")
    b = write(tmp_path, "b.txt", "walk_height\t200\n")
    v = load_params([a, b], SCHEMA)
    assert v["walk_height"] == pytest.approx(0.2)
    assert v["gain"] == 1.0
    assert load_params([b, a], SCHEMA)["walk_height"] == pytest.approx(0.175)


def test_defaults_fill_unset_names(tmp_path):
    a = write(tmp_path, "a.txt", "gain\t1\n")
    v = load_params([a], SCHEMA, defaults={"walk_height": 0.18})
    assert v == {"walk_height": 0.18, "gain": 1.0}


def test_prefixed_sets_share_a_schema(tmp_path):
    a = write(tmp_path, "a.txt", "walk_height\t175\nsprint_walk_height\t190\nsprint_gain\t4\n")
    sets = load_param_sets([a], SCHEMA, ["", "sprint_"])
    assert sets[""] == pytest.approx({"walk_height": 0.175})
    assert sets["sprint_"] == pytest.approx({"walk_height": 0.19, "gain": 4.0})
    only = write(tmp_path, "b.txt", "sprint_walk_height\t190\n")
    assert load_params(only, SCHEMA, prefix="sprint_") == pytest.approx({"walk_height": 0.19})


@pytest.mark.parametrize("text, line, word", [
    ("gain\t1\nwalk_hieght\t175\n", 2, "walk_hieght"),  # unknown name
    ("gain\t1\n\nwalk_height\t17x5\n", 3, "17x5"),  # malformed value
    ("walk_height\n", 1, "walk_height"),  # missing value
    ("# c\nwalk_height\t175 mm\n", 2, "mm"),  # extra word
    ("gain\tnan\n", 1, "nan"),  # not finite
])
def test_errors_name_file_line_and_word(tmp_path, text, line, word):
    p = write(tmp_path, "bad.txt", text)
    with pytest.raises(ParamError) as e:
        load_params([p], SCHEMA)
    assert f"bad.txt:{line}:" in str(e.value)
    assert repr(word) in str(e.value)
    assert e.value.line == line
    assert isinstance(e.value, ValueError)


def test_unknown_name_in_second_file_names_that_file(tmp_path):
    a = write(tmp_path, "a.txt", "gain\t1\n")
    b = write(tmp_path, "b.txt", "gain\t2\n\n\nsprint_gain\t3\n")
    with pytest.raises(ParamError, match=r"b\.txt:4: unknown parameter 'sprint_gain'"):
        load_params([a, b], SCHEMA)


def test_unknown_unit_in_schema_is_a_programming_error(tmp_path):
    a = write(tmp_path, "a.txt", "gain\t1\n")
    with pytest.raises(ValueError, match="unknown unit"):
        load_params([a], {"gain": "furlong"})


@given(st.floats(allow_nan=False, allow_infinity=False, width=64), st.sampled_from(["\t", " ", " \t "]))
def test_any_finite_value_round_trips(value, sep):
    (e,) = parse_params(f"walk_height{sep}{value!r}\n")
    assert e.value == value and e.name == "walk_height" and e.line == 1


def test_a_types_own_file_follows_the_shared_one_only_where_it_exists(tmp_path):
    from skills.params import with_type_file

    shared = tmp_path / "walk.params"
    shared.write_text("x\t1\n")
    (tmp_path / "walk_type3.params").write_text("x\t2\n")
    assert with_type_file(shared, 3) == [str(shared), str(tmp_path / "walk_type3.params")]
    assert with_type_file(shared, 1) == [str(shared)]
    assert with_type_file(shared, None) == [str(shared)]
