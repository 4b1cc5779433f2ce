"""Ground truth as data: aligned, positions and matrix truths, the metrics under each, the split
of traverses that are not aligned, positions files, truth matrices and precomputed descriptors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from seasonloop.data.ground_truth import PairTruth, aligned_truth, matrix_truth, position_truth
from seasonloop.data.ground_truth_files import matrix_between, read_matrix
from seasonloop.data.positions import (
    PositionFiles,
    at_times,
    degrees_to_metres,
    for_files,
    read_table,
    season_positions,
)
from seasonloop.data.season_split import by_matrix, by_position, distance_to_track, split_seasons
from seasonloop.evaluation.metrics import evaluate_pair, evaluate_truth, pr_curve, truth_matches
from seasonloop.models.core.learner import PlaceRows
from seasonloop.models.precomputed import PrecomputedDescriptors
from seasonloop.params.settings import SplitConfig


def noisy_distances(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.random((n, n)) + np.where(np.eye(n, dtype=bool), 0.0, 0.3) * rng.random((n, n))


@pytest.mark.parametrize("tolerance", [0, 1, 3])
def test_positions_derived_from_aligned_frames_give_the_aligned_numbers(tolerance):
    places = np.array([3, 4, 5, 6, 9, 10, 11, 20, 21, 22, 23])
    distances = noisy_distances(len(places))
    aligned_metrics, aligned_pr = evaluate_pair(distances, places, places, tolerance, "ratio", 2)
    # 21 m per place; the tolerance in metres covers the same places
    positions = 21.0 * places[:, None]
    truth = position_truth(positions, positions, places, places, 21.0 * tolerance + 1.0)
    metrics, pr = evaluate_truth(distances, truth, "ratio", 2)
    assert metrics == aligned_metrics
    pd.testing.assert_frame_equal(pr, aligned_pr)


def test_position_truth_takes_the_nearest_as_exact_and_counts_queries_without_a_match():
    database = np.array([[0.0], [20.0], [40.0], [60.0]])
    queries = np.array([[19.0], [41.0], [500.0]])
    truth = position_truth(database, queries, np.arange(4), np.arange(3), 10.0)
    assert truth.correct.tolist() == [[False, True, False, False], [False, False, True, False], [False] * 4]
    assert truth.exact.tolist() == [1, 2, -1] and truth.n_without_match == 1


def test_queries_without_a_match_are_wrong_and_not_positives():
    # query 2 has no correct database place: matched, it is a false positive; it is no positive
    truth = PairTruth(
        "positions",
        np.arange(3),
        np.arange(3),
        np.array([[1, 0, 0], [0, 1, 0], [0, 0, 0]], dtype=bool),
        np.array([0, 1, -1]),
    )
    distances = np.array([[0.1, 0.9, 0.9], [0.9, 0.2, 0.9], [0.9, 0.9, 0.3]])
    metrics, pr = evaluate_truth(distances, truth)
    assert metrics["fraction_correct"] == pytest.approx(2 / 3)
    # the two positives are found before the third, wrong match is accepted: recall reaches 1
    assert pr["recall"].tolist() == [0.5, 1.0, 1.0] and pr["precision"].tolist()[-1] == pytest.approx(2 / 3)
    assert metrics["auc_pr_vpr_tutorial"] <= metrics["fraction_correct"] * 3 / 2
    recall, _ = pr_curve(np.array([3.0, 2.0, 1.0]), np.array([True, True, False]), np.array([True, True, False]))
    assert recall.tolist() == [0.5, 1.0, 1.0]


def test_matrix_truth_takes_the_test_block_and_never_picks_soft_cells():
    hard = np.zeros((6, 5), bool)  # (database places, query places)
    hard[np.arange(5), np.arange(5)] = True
    soft = hard.copy()
    soft[4, 1] = True  # database place 4 is near query place 1
    truth = matrix_truth(hard, soft, np.array([1, 2, 4]), np.array([1, 2, 4]), "x.npz")
    assert truth.correct.tolist() == [[True, False, False], [False, True, False], [False, False, True]]
    assert truth.ignored is not None and truth.ignored[0].tolist() == [False, False, True]
    # query place 1 is closest to database place 4 (a soft cell): it is skipped, not counted wrong
    distances = np.array([[0.5, 0.9, 0.1], [0.9, 0.2, 0.9], [0.9, 0.9, 0.3]])
    metrics, _ = evaluate_truth(distances, truth)
    assert metrics["fraction_correct"] == 1.0


def test_a_pair_truth_survives_saving(tmp_path):
    truth = aligned_truth(np.arange(4), np.arange(4), 1)
    truth.save(tmp_path / "t.npz")
    loaded = PairTruth.load(tmp_path / "t.npz")
    assert loaded.kind == "aligned" and np.array_equal(loaded.correct, truth.correct) and loaded.ignored is None
    with pytest.raises(FileNotFoundError, match="rerun the ground_truth stage"):
        PairTruth.load(tmp_path / "missing.npz")


def test_positions_files_are_read_checked_and_converted(tmp_path):
    good = tmp_path / "summer.csv"
    good.write_text("name,lat,lon\n2.png,63.0,10.0\n1.png,63.001,10.0\n")
    coordinates, names = read_table(good, ["lat", "lon"], "name")
    assert coordinates.shape == (2, 2) and list(names) == ["2.png", "1.png"]
    metres = degrees_to_metres(coordinates, ("lat", "lon"), good)
    # 0.001 degree of latitude at 63 degrees north is 111.4 m on the WGS84 ellipsoid
    assert np.linalg.norm(metres[1] - metres[0]) == pytest.approx(111.4, abs=0.1)
    files = [tmp_path / "1.png", tmp_path / "2.png"]
    assert for_files(coordinates, names, files, good)[0, 0] == pytest.approx(63.001)
    with pytest.raises(ValueError, match="no position for 1 frames"):
        for_files(coordinates, names, [*files, tmp_path / "3.png"], good)
    with pytest.raises(ValueError, match=r"2 positions for 3 frames"):
        for_files(coordinates, None, [*files, tmp_path / "3.png"], good)
    with pytest.raises(ValueError, match="no column 'x'"):
        read_table(good, ["x", "y"], None)
    bad = tmp_path / "fall.csv"
    bad.write_text("x,y\n1,2\nnan,3\nabc,4\n")
    with pytest.raises(ValueError, match=r"fall.csv: 2 rows with a missing, non-numeric or infinite coordinate"):
        read_table(bad, ["x", "y"], None)
    with pytest.raises(FileNotFoundError, match="positions file not found"):
        read_table(tmp_path / "winter.csv", ["x"], None)
    with pytest.raises(ValueError, match=r"positions cover 0-10 s, but frames are kept from 0 to 12 s"):
        at_times(np.zeros((2, 1)), np.array([0.0, 10.0]), np.array([0.0, 12.0]), good)


def test_season_positions_of_a_video_are_interpolated_at_the_kept_samples(tmp_path):
    (tmp_path / "summer.csv").write_text("time_s,distance_m\n0,0\n10,100\n")
    files = PositionFiles(tmp_path, ("distance_m",), "metres", "time_s")
    positions = season_positions("video", files, "summer", 4, 1.0, 2, [])
    assert positions[:, 0].tolist() == [0.0, 20.0, 40.0, 60.0]


def test_truth_matrices_are_checked(tmp_path):
    np.savez(tmp_path / "summer-fall.npz", hard=np.eye(3, 4, dtype=bool))
    hard, soft = read_matrix(tmp_path / "summer-fall.npz", 3, 4)
    assert hard.shape == (3, 4) and soft is None
    assert matrix_between(tmp_path, "fall", "summer", 4, 3).shape == (4, 3)
    with pytest.raises(ValueError, match=r"'hard' has shape \(3, 4\), expected .* = \(4, 4\)"):
        read_matrix(tmp_path / "summer-fall.npz", 4, 4)
    np.savez(tmp_path / "summer-winter.npz", soft=np.eye(3, dtype=bool))
    with pytest.raises(ValueError, match="no array 'hard'"):
        read_matrix(tmp_path / "summer-winter.npz", 3, 3)
    np.savez(tmp_path / "spring-fall.npz", hard=np.full((2, 2), 0.5))
    with pytest.raises(ValueError, match="must be boolean"):
        read_matrix(tmp_path / "spring-fall.npz", 2, 2)
    with pytest.raises(FileNotFoundError, match="the split maps every season onto summer's places"):
        matrix_between(tmp_path, "summer", "spring", 3, 3)


def test_traverses_at_different_speeds_share_their_test_stretches():
    # summer: 1 m per frame over 0..599 m; fall: 2 m per frame from 100 m, standing at 300 m for 20 frames
    summer = np.arange(600.0)[:, None]
    fall = np.concatenate([np.arange(100.0, 300.0, 2.0), np.full(20, 300.0), np.arange(302.0, 600.0, 2.0)])[:, None]
    positions = {"summer": summer, "fall": fall}
    mapped = by_position(positions, "summer", max_distance_m=2.0)
    stats = {
        "summer_brightness": np.full(600, 100.0),
        "summer_change": np.full(600, 5.0),
        "fall_brightness": np.full(len(fall), 100.0),
        "fall_change": np.where(np.diff(fall[:, 0], prepend=-1.0) == 0, 0.0, 5.0),
    }
    config = SplitConfig(
        section_length=100, test_fraction=0.2, gap=5, folds=1, dark_threshold=40, stop_threshold=1.0, test_every={}
    )
    splits = split_seasons(stats, ["summer", "fall"], config, mapped)
    test_stretch = summer[splits.splits["summer"].test, 0]
    fall_test, fall_train = fall[splits.splits["fall"].test, 0], fall[splits.splits["fall"].train, 0]
    blocks = [(start, start + 20) for start in range(80, 600, 100)]
    assert all(any(a <= p < b for a, b in blocks) for p in fall_test)
    # no fall training frame lies on a test stretch or within its gap
    assert not any(a - 5 <= p < b + 5 for p in fall_train for a, b in blocks)
    # the stop at 300 m (standing still in fall) leaves that place out of every season's test set
    assert 300.0 not in fall_test and 300.0 not in test_stretch
    assert splits.to_json()["seasons"]["fall"]["n_places"] == len(fall)


def test_a_truth_matrix_maps_a_season_to_the_middle_of_its_true_reference_places():
    truth = np.zeros((5, 3), bool)
    truth[[0, 1, 2], 0] = True
    truth[[3], 1] = True
    assert by_matrix(truth, "m").tolist() == [1, 3, -1]


def test_precomputed_descriptors_are_looked_up_by_place(tmp_path):
    np.save(tmp_path / "summer.npy", np.arange(20, dtype=np.float32).reshape(10, 2))
    learner = PrecomputedDescriptors({"dir": str(tmp_path)})
    learner.fit(np.zeros((2, 4, 4), np.uint8), progress=False)
    images = np.zeros((3, 4, 4), np.uint8)
    described = learner.describe_places(images, PlaceRows("summer", np.array([0, 4, 9]), 10))
    assert described.tolist() == [[0, 1], [8, 9], [18, 19]]
    with pytest.raises(ValueError, match=r"summer.npy: 10 rows of descriptors for the 12 frames of season 'summer'"):
        learner.describe_places(images, PlaceRows("summer", np.array([0, 4, 9]), 12))
    with pytest.raises(FileNotFoundError, match="no precomputed descriptors for season 'fall'"):
        learner.describe_places(images, PlaceRows("fall", np.array([0]), 10))
    with pytest.raises(ValueError, match="describe a season's places, not new images"):
        learner.describe(images)
    np.save(tmp_path / "winter.npy", np.full((10, 2), np.nan))
    with pytest.raises(ValueError, match="NaN or infinite descriptors at 1 test places"):
        learner.describe_places(images[:1], PlaceRows("winter", np.array([3]), 10))


def test_the_schema_knows_every_kind_of_ground_truth():
    from seasonloop.data.ground_truth_kinds import TRUTH_KINDS, truth_kind
    from seasonloop.registries.choices import check_choice

    # data.ground_truth is checked against the registry itself; vpr_bench builds matrix truths from VPR-Bench's file
    for kind in TRUTH_KINDS:
        check_choice({"data": {"ground_truth": kind}}, "data.ground_truth")
    with pytest.raises(
        ValueError, match=r"data\.ground_truth: unknown value 'gps' \(known: aligned, positions, matrix, vpr_bench\)"
    ):
        check_choice({"data": {"ground_truth": "gps"}}, "data.ground_truth")
    assert [kind.name for kind in TRUTH_KINDS.values() if kind.aligned] == ["aligned"]
    with pytest.raises(ValueError, match="data.ground_truth: unknown kind 'gps'"):
        truth_kind("gps")


def test_a_new_kind_of_ground_truth_is_one_class_and_one_registry_line(monkeypatch):
    # the class and its TRUTH_KINDS entry are all params.yaml's check and the pipeline read
    import yaml

    from seasonloop.data import ground_truth_kinds
    from seasonloop.registries.choices import check_whole

    class SameFrames(ground_truth_kinds.Aligned):
        name = "same_frames"

    monkeypatch.setitem(ground_truth_kinds.TRUTH_KINDS, "same_frames", SameFrames())
    params = yaml.safe_load((Path(__file__).resolve().parents[1] / "params.yaml").read_text())
    params["data"]["ground_truth"] = "same_frames"
    check_whole(params)
    assert ground_truth_kinds.truth_kind("same_frames").aligned


def test_recall_at_n_leaves_out_queries_without_a_correct_place():
    # VPR_Tutorial's recallAtK discards queries without a true match: three matchable queries, all
    # matched right, and a fourth with no correct place give recall@1 1.0 (fraction correct 0.75)
    correct = np.zeros((4, 4), dtype=bool)
    correct[[0, 1, 2], [0, 1, 2]] = True
    truth = PairTruth("positions", np.arange(4), np.arange(4), correct, np.array([0, 1, 2, -1]))
    distances = np.full((4, 4), 0.9)
    distances[np.arange(4), np.arange(4)] = [0.1, 0.2, 0.3, 0.4]
    metrics, _ = evaluate_truth(distances, truth)
    assert metrics["fraction_correct"] == 0.75
    assert metrics["recall_at_1"] == metrics["recall_at_5"] == 1.0
    # the area in VPR_Tutorial's convention is bounded by recall@1 (both over matchable queries)
    assert metrics["auc_pr_vpr_tutorial"] <= metrics["recall_at_1"]


def test_a_query_whose_places_are_all_soft_is_a_wrong_match_at_the_lowest_confidence():
    # VPR_Tutorial sets soft cells to the lowest similarity: such a query's best match is a soft
    # cell, not in the hard truth, at the lowest confidence of all
    hard = np.eye(3, dtype=bool)
    hard[2, 2] = False
    soft = hard.copy()
    soft[:, 2] = True  # every database place is soft for query place 2
    truth = matrix_truth(hard, soft, np.arange(3), np.arange(3), "x.npz")
    distances = np.array([[0.1, 0.9, 0.9], [0.9, 0.2, 0.9], [0.05, 0.05, 0.05]])
    metrics, pr = evaluate_truth(distances, truth)
    assert metrics["fraction_correct"] == pytest.approx(2 / 3)
    assert pr["precision"].tolist() == [1.0, 1.0, pytest.approx(2 / 3)]
    assert np.isfinite(metrics["auc_pr_vpr_tutorial"])


def test_an_all_soft_query_under_sequence_distances_with_infinite_cells_gets_the_largest_finite_one():
    # SeqSLAM's distance matrices hold +inf where no window fits: "the lowest confidence" is then
    # minus the largest finite distance, not -inf (which made auc_pr_vpr_tutorial refuse the pair)
    hard = np.eye(3, dtype=bool)
    hard[2, 2] = False
    soft = hard.copy()
    soft[:, 2] = True
    truth = matrix_truth(hard, soft, np.arange(3), np.arange(3), "x.npz")
    distances = np.array([[0.1, 0.9, np.inf], [0.9, 0.2, np.inf], [0.05, 0.05, np.inf]])
    metrics, pr = evaluate_truth(distances, truth)
    assert metrics["fraction_correct"] == pytest.approx(2 / 3)
    assert np.isfinite(metrics["auc_pr_vpr_tutorial"])
    _, confidence, _ = truth_matches(distances, truth)
    assert confidence[2] == -0.9


def test_example_matches_skip_soft_cells_as_the_metrics_do():
    from seasonloop.evaluation.outcomes import QueryOutcomes
    from seasonloop.evaluation.records import block_records
    from seasonloop.reporting.examples import outcome_examples

    hard = np.eye(3, dtype=bool)
    soft = hard.copy()
    soft[2, 0] = True  # database place 2 is near query place 0: neither right nor wrong
    truth = matrix_truth(hard, soft, np.arange(3), np.arange(3), "x.npz")
    distances = np.array([[0.5, 0.9, 0.1], [0.9, 0.2, 0.9], [0.9, 0.9, 0.3]])
    metrics, _ = evaluate_truth(distances, truth)
    outcomes = QueryOutcomes.from_records(block_records(distances, truth, "distance", 0), truth, "distance")
    examples = outcome_examples(outcomes, truth, n=3)
    assert metrics["fraction_correct"] == 1.0
    assert all(example.correct for example in examples) and examples[-1].match == 0


def test_a_season_sampled_between_the_reference_places_stays_on_its_track():
    # reference every 21 m (the synthetic route at 1 fps), the other season half a frame later:
    # 10.5 m from every reference place, yet on the track; tolerance 10 m (params.yaml's)
    reference = np.c_[21.0 * np.arange(600), np.zeros(600)]
    between = reference + [10.5, 0.0]
    mapped = by_position({"summer": reference, "fall": between}, "summer", max_distance_m=10.0)
    assert (mapped["summer"] == np.arange(600)).all()
    # the last lies 10.5 m past the reference's end: off its track
    assert (mapped["fall"][:-1] >= 0).all() and mapped["fall"][-1] == -1
    assert (np.abs(mapped["fall"][:-1] - np.arange(599)) <= 1).all()
    noisy = between + np.random.default_rng(0).normal(0.0, 1.0, between.shape)
    kept = by_position({"summer": reference, "fall": noisy}, "summer", max_distance_m=10.0)["fall"] >= 0
    assert kept[:-1].all()


def test_the_distance_to_a_track_follows_its_segments_round_a_corner():
    track = np.array([[0.0, 0.0], [100.0, 0.0], [100.0, 100.0]])  # long segments, a right angle
    points = np.array([[50.0, 3.0], [103.0, 50.0], [110.0, -10.0], [50.0, 50.0], [-4.0, 0.0]])
    distances = distance_to_track(track, points, within=20.0)
    assert distances[:3] == pytest.approx([3.0, 3.0, np.hypot(10.0, 10.0)])
    assert distances[3] > 20.0 and distances[4] == pytest.approx(4.0)
    assert distance_to_track(track[:1], points[:1], within=20.0) == pytest.approx([np.hypot(50.0, 3.0)])


def test_frames_beyond_the_reference_route_belong_to_no_place():
    # fall runs 300 m past summer's end: those frames are no place of summer's (-1), not all
    # piled onto its last place, which lies in a test block
    summer, fall = np.arange(600.0)[:, None], np.arange(900.0)[:, None]
    mapped = by_position({"summer": summer, "fall": fall}, "summer", max_distance_m=10.0)
    assert (mapped["fall"][:610] >= 0).all() and (mapped["fall"][610:] == -1).all()
    stats = {
        f"{s}_{k}": np.full(n, v)
        for s, n in (("summer", 600), ("fall", 900))
        for k, v in (("brightness", 100.0), ("change", 5.0))
    }
    config = SplitConfig(
        section_length=100, test_fraction=0.2, gap=5, folds=1, dark_threshold=40, stop_threshold=1.0, test_every={}
    )
    fall_split = split_seasons(stats, ["summer", "fall"], config, mapped).splits["fall"]
    assert fall[fall_split.test, 0].max() < 610 and len(fall_split.test) == 120 + 10
    with pytest.raises(ValueError, match="max_distance_m"):
        by_position({"summer": summer}, "summer", max_distance_m=-1.0)


def test_one_matrix_per_pair_of_seasons_serves_both_directions(tmp_path):
    from seasonloop.evaluation.pair_ground_truth import each_truth

    hard = np.eye(4, 5, dtype=bool)  # (summer places, fall places)
    soft = hard | np.eye(4, 5, k=1, dtype=bool)
    np.savez(tmp_path / "summer-fall.npz", hard=hard, soft=soft)
    split = {"seasons": {"summer": {"n_places": 4, "test": [0, 1, 3]}, "fall": {"n_places": 5, "test": [0, 1, 2, 4]}}}
    evaluate = None  # a matrix truth reads no tolerance
    truths = dict(each_truth("matrix", split, ["summer", "fall"], evaluate, tmp_path, tmp_path))
    forward, backward = truths["summer", "fall"], truths["fall", "summer"]
    np.testing.assert_array_equal(backward.correct, forward.correct.T)
    np.testing.assert_array_equal(backward.ignored, forward.ignored.T)
    three = {"seasons": {**split["seasons"], "spring": split["seasons"]["fall"]}}
    with pytest.raises(FileNotFoundError, match="nor spring-fall.npz.*spring queries against the fall database"):
        dict(each_truth("matrix", three, ["fall", "spring"], evaluate, tmp_path, tmp_path))


def test_bad_positions_matrices_and_descriptors_are_one_line_errors(tmp_path):
    from pathlib import Path

    names = pd.Series(["a.png", "b.png", "a.png"])
    with pytest.raises(ValueError, match=r"pos.csv: image name 'a.png' on 2 rows"):
        for_files(np.zeros((3, 2)), names, [Path("a.png"), Path("b.png")], Path("pos.csv"))
    np.save(tmp_path / "array.npy", np.eye(3, dtype=bool))
    (tmp_path / "array.npy").rename(tmp_path / "summer-fall.npz")
    with pytest.raises(ValueError, match=r"summer-fall.npz: not an .npz archive"):
        read_matrix(tmp_path / "summer-fall.npz", 3, 3)
    np.savez(tmp_path / "whole.npz", hard=np.eye(300, dtype=bool))
    (tmp_path / "cut.npz").write_bytes((tmp_path / "whole.npz").read_bytes()[:500])
    with pytest.raises(ValueError, match=r"cut.npz: cannot read the ground-truth matrix"):
        read_matrix(tmp_path / "cut.npz", 300, 300)
    descriptors = tmp_path / "descriptors"
    descriptors.mkdir()
    np.savez(descriptors / "archive.npz", x=np.zeros((4, 2)))
    (descriptors / "archive.npz").rename(descriptors / "summer.npy")
    np.save(descriptors / "fall.npy", np.zeros((4, 2), dtype=np.complex64))
    learner = PrecomputedDescriptors({"dir": str(descriptors)})
    learner.fit(np.zeros((2, 4, 4), np.uint8), progress=False)
    images = np.zeros((2, 4, 4), np.uint8)
    with pytest.raises(ValueError, match=r"summer.npy: cannot read descriptors \(an .npz archive"):
        learner.describe_places(images, PlaceRows("summer", np.array([0, 1]), 4))
    with pytest.raises(ValueError, match=r"fall.npy: expected a 2-D real-valued .* complex64"):
        learner.describe_places(images, PlaceRows("fall", np.array([0, 1]), 4))


def test_degrees_become_metres_that_keep_true_distances_along_nordland():
    from pyproj import Geod

    geod = Geod(ellps="WGS84")
    # a route from Trondheim to Bodo; two points 20.00 m apart east-west at Bodo, two 20.00 m
    # apart north-south at Trondheim (the old plane about the mean latitude made the first 21.08 m)
    east, north, _ = geod.fwd(14.40, 67.28, 90.0, 20.0)
    lon_s, lat_s, _ = geod.fwd(10.39, 63.43, 0.0, 20.0)
    route = np.array([[63.43, 10.39], [lat_s, lon_s], [67.28, 14.40], [north, east]])
    metres = degrees_to_metres(route, ("lat", "lon"), "summer.csv")
    assert np.linalg.norm(metres[1] - metres[0]) == pytest.approx(20.0, abs=1e-6)
    assert np.linalg.norm(metres[3] - metres[2]) == pytest.approx(20.0, abs=1e-6)
    # the whole route: the chord under a 450 km geodesic is (d / R)^2 / 24 shorter (0.02%)
    _, _, length = geod.inv(10.39, 63.43, 14.40, 67.28)
    assert np.linalg.norm(metres[2] - metres[0]) == pytest.approx(length * (1 - (length / 6.371e6) ** 2 / 24), rel=2e-5)
    with pytest.raises(ValueError, match=r"\['lon', 'lat'\] is longitude first"):
        degrees_to_metres(route[:, ::-1], ("lon", "lat"), "summer.csv")
    with pytest.raises(ValueError, match="summer.csv: .*are the columns swapped"):
        degrees_to_metres(np.array([[150.0, 60.0]]), ("lat", "lon"), "summer.csv")


@pytest.mark.parametrize(
    "start, bearing, steps",
    [
        ((65.0, 179.985), 90.0, 100),  # east across +-180 at Nordland's latitude (2 km, 19% west of it)
        ((-0.0001, 179.999), 45.0, 50),  # north-east across the equator and +-180 at once
        ((89.9995, 0.0), 0.0, 20),  # over the North Pole
    ],
)
def test_twenty_metre_steps_read_twenty_metres_anywhere_on_earth(start, bearing, steps):
    from pyproj import Geod

    geod = Geod(ellps="WGS84")
    lon, lat, az = [start[1]], [start[0]], bearing
    for _ in range(steps):
        next_lon, next_lat, back = geod.fwd(lon[-1], lat[-1], az, 20.0)
        lon.append(next_lon)
        lat.append(next_lat)
        az = back + 180.0  # keep going the same way along the geodesic
    route = np.c_[lat, lon]
    metres = degrees_to_metres(route, ("latitude", "longitude"), "x.csv")
    assert np.linalg.norm(np.diff(metres, axis=0), axis=1) == pytest.approx(np.full(steps, 20.0), abs=1e-6)


def test_a_forty_degree_equatorial_route_keeps_local_distances_everywhere_along_it():
    from pyproj import Geod

    geod = Geod(ellps="WGS84")
    starts = np.linspace(-20.0, 20.0, 9)  # a 4,450 km route: UTM's one zone was ~7% off at its ends
    ends = np.array([geod.fwd(lon, 0.0, 90.0, 20.0)[0] for lon in starts])
    metres = degrees_to_metres(np.c_[np.zeros(18), np.r_[starts, ends]], ("lat", "lon"), "x.csv")
    assert np.linalg.norm(metres[9:] - metres[:9], axis=1) == pytest.approx(np.full(9, 20.0), abs=1e-6)


def test_degree_columns_must_be_named_as_degrees():
    with pytest.raises(ValueError, match=r"data.position_columns: \['y', 'x'\] are not named as degrees"):
        degrees_to_metres(np.array([[10.0, 63.0]]), ("y", "x"), "x.csv")
    for columns in (("lat", "lon"), ("Latitude", "Longitude"), ("lat", "lng")):
        degrees_to_metres(np.array([[63.0, 10.0]]), columns, "x.csv")


def test_video_positions_in_degrees_are_interpolated_in_metres_across_180(tmp_path):
    from pyproj import Geod

    # two rows 20 m apart east-west astride +-180: the kept sample half way lies between them,
    # not (as degrees interpolated linearly would put it) half way round the Earth at 0 degrees
    geod = Geod(ellps="WGS84")
    west = (65.0, 179.9998)
    east_lon, east_lat, _ = geod.fwd(west[1], west[0], 90.0, 20.0)
    assert east_lon < 0
    (tmp_path / "summer.csv").write_text(f"time_s,lat,lon\n0,{west[0]},{west[1]}\n2,{east_lat},{east_lon}\n")
    files = PositionFiles(tmp_path, ("lat", "lon"), "degrees", "time_s")
    positions = season_positions("video", files, "summer", 3, 1.0, 1, [])
    steps = np.linalg.norm(np.diff(positions, axis=0), axis=1)
    assert steps == pytest.approx([10.0, 10.0], abs=1e-3)


def test_vpr_bench_ground_truth_reads_as_the_reference_by_query_matrix(tmp_path):
    from seasonloop.data.ground_truth_files import pair_matrix, read_vpr_bench

    # VPR-Bench's Nordland: query i correct at references 10i-1 .. 10i+1 (query 0 at 0 and 1)
    rows = np.empty((3, 2), dtype=object)
    for i in range(3):
        rows[i, 0], rows[i, 1] = i, np.arange(max(0, 10 * i - 1), 10 * i + 2)
    path = tmp_path / "ground_truth_new.npy"
    np.save(path, rows, allow_pickle=True)
    hard = read_vpr_bench(path, 30, 3)
    assert hard.shape == (30, 3) and hard.sum(axis=0).tolist() == [2, 3, 3]
    assert np.flatnonzero(hard[:, 2]).tolist() == [19, 20, 21]
    forward, _, _ = pair_matrix(tmp_path, "ref", "query", 30, 3, "x", vpr_bench=("ref", "query"))
    backward, _, _ = pair_matrix(tmp_path, "query", "ref", 3, 30, "x", vpr_bench=("ref", "query"))
    assert np.array_equal(forward, hard) and np.array_equal(backward, hard.T)
    # a row with an empty reference list: a query without a correct place
    empty = rows.copy()
    empty[1, 1] = []
    np.save(tmp_path / "empty.npy", empty, allow_pickle=True)
    assert read_vpr_bench(tmp_path / "empty.npy", 30, 3).sum(axis=0).tolist() == [2, 0, 3]
    # a reference list that is not indices: one line naming the file and row
    empty[1, 1] = ["a", "b"]
    np.save(tmp_path / "names.npy", empty, allow_pickle=True)
    with pytest.raises(ValueError, match=r"names.npy: row 1: reference indices \['a', 'b'\] are not integers"):
        read_vpr_bench(tmp_path / "names.npy", 30, 3)
    with pytest.raises(
        ValueError, match=r"ground_truth_new.npy: row 2: reference indices .* beyond the 20 reference places"
    ):
        read_vpr_bench(path, 20, 3)
    with pytest.raises(ValueError, match=r"row 2: query index 2 is not one of the 2 query places"):
        read_vpr_bench(path, 30, 2)
    rows[1, 0] = 0
    np.save(path, rows, allow_pickle=True)
    with pytest.raises(ValueError, match="query 0 on two rows"):
        read_vpr_bench(path, 30, 3)
    with pytest.raises(FileNotFoundError, match="VPR-Bench ground truth not found"):
        read_vpr_bench(tmp_path / "missing.npy", 30, 3)
    with pytest.raises(ValueError, match="holds the pair ref-query only, not ref-other"):
        pair_matrix(tmp_path, "ref", "other", 30, 3, "x", vpr_bench=("ref", "query"))


def test_positions_read_from_image_names_as_gmberton_writes_them(tmp_path):
    from seasonloop.data.positions import positions_in_names

    folder = tmp_path / "queries"
    folder.mkdir()
    names = ["@0547312.58@7032515.21@33@W@.jpg", "@0547330.00@7032515.21@33@W@.jpg", "@0547348.5@7032520@.jpg"]
    files = [folder / name for name in names]
    assert positions_in_names(files).tolist() == [
        [547312.58, 7032515.21],
        [547330.0, 7032515.21],
        [547348.5, 7032520.0],
    ]
    frames = PositionFiles(tmp_path, ("x", "y"), "metres", None, in_names=True)
    assert season_positions("frames", frames, "queries", 2, 1.0, 2, files).tolist()[1] == [547348.5, 7032520.0]
    with pytest.raises(ValueError, match=r"0001.jpg: no UTM position in its name"):
        positions_in_names([folder / "0001.jpg"])
    with pytest.raises(ValueError, match="image_names needs data.source: frames"):
        season_positions("video", frames, "queries", 2, 1.0, 1, [])
