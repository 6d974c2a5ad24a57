import math

from benchmarks.walk import FALL_MOTIONS, ZIGZAG_HALF, by_motion, fall_motion, zigzag


def test_fall_motion_tells_what_the_walk_did_before_a_fall():
    steady = [(0.05, 0.0, False)] * 50
    assert fall_motion(steady) == "steady"
    assert fall_motion([(0.005 * (i % 2), 0.0, False) for i in range(50)]) == "in place"
    assert fall_motion([(0.0, math.radians(9), False)] * 50) == "in place, turning"
    assert fall_motion([(0.06 - 0.001 * i, 0.0, False) for i in range(50)]) == "slowing"
    turn_in = [(0.06 - 0.001 * i, math.radians(0.2 * i), False) for i in range(50)]
    assert fall_motion(turn_in) == "slowing, turning"  # after a waypoint, turning to the next
    assert fall_motion([(0.01 + 0.001 * i, 0.0, False) for i in range(50)]) == "speeding up"
    assert fall_motion([(-0.03, -math.radians(3), False)] * 50) == "steady"  # backward is walking
    assert fall_motion(steady[:-1] + [(0.05, 0.0, True)]) == "getup"
    assert fall_motion([]) == "in place"  # a fall in the first cycle
    assert all(fall_motion(r) in FALL_MOTIONS for r in (steady, turn_in, []))


def test_falls_are_counted_by_motion_over_runs():
    runs = [{"fall_motions": ["slowing", "getup"]}, {"fall_motions": []}, {"fall_motions": ["slowing"]}]
    n = by_motion(runs)
    assert list(n) == list(FALL_MOTIONS)
    assert n["slowing"] == 2 and n["getup"] == 1 and sum(n.values()) == 3


def test_zigzag_swings_the_heading_both_ways_while_walking_forward():
    """Two half periods from the plain stand: the torso turns left, then right,
    and walks on; type 0 does not fall in them."""
    r = zigzag(0, seconds=2.0 * ZIGZAG_HALF)
    assert not r["fell"] and r["fell_at_s"] is None
    assert r["left_deg"] > 10.0 and r["right_deg"] > 10.0
    assert r["distance_m"] > 0.25


def test_positioning_walks_the_benchmarks_own_walk_sets(tmp_path, monkeypatch):
    """The team's positioning walk runs on the files the benchmark measures: steps cut to
    8 mm by an extra parameter file gain far less ground toward the targets."""
    import benchmarks.walk as bw

    short = tmp_path / "short.txt"
    short.write_text("max_step_size_x\t8\nmax_step_size_y\t8\n")
    monkeypatch.setattr(bw, "PARAMS", [])
    plain = bw.positioning(2, runs=2, seconds=8.0)
    monkeypatch.setattr(bw, "PARAMS", [str(short)])
    cut = bw.positioning(2, runs=2, seconds=8.0)
    assert plain["runs"] == 2 and plain["falls"] == 0
    assert cut["gained_m"] < plain["gained_m"] - 0.5
