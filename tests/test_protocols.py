"""The pieces the field's Nordland protocols need (docs/other-datasets.md): an image list keeping the
listed frames, a whole route tested (split.test_fraction 1) with learners trained on other seasons,
and one season's test places sampled every k-th (split.test_every), with the checks that keep them
honest."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml

from seasonloop.data.datasets import season_part
from seasonloop.data.extract import extract_seasons
from seasonloop.data.frames import read_image_list, sample_video
from seasonloop.data.season_split import split_seasons
from seasonloop.data.split import make_split, split_masks
from seasonloop.data.synthetic import render_route
from seasonloop.evaluation.pair_ground_truth import each_truth
from seasonloop.params.seasons import SEASONS
from seasonloop.params.settings import EvaluateConfig, ExtractConfig, SplitConfig
from seasonloop.preset import composed_params
from seasonloop.registries.choices import check_whole
from tools.repository import dvc, merge
from tools.small_runs import TINY
from workspaces import make_workspace

REPO = Path(__file__).resolve().parents[1]
EXTRACT = ExtractConfig(fps=1.0, height=6, width=8, trim_to_shortest=False, max_offset=0)


@pytest.fixture
def params():
    return yaml.safe_load((REPO / "params.yaml").read_text())


def numbered_frames(folder: Path, numbers) -> None:
    """Nordland's names (images-00202.png), each frame's gray level its own number."""
    folder.mkdir(parents=True)
    for number in numbers:
        cv2.imwrite(str(folder / f"images-{number:05d}.png"), np.full((12, 16, 3), number % 250, np.uint8))


def test_an_image_list_keeps_the_listed_frames_in_place_order(tmp_path):
    for season in ("summer", "winter"):
        numbered_frames(tmp_path / season, range(10))
    # Patch-NetVLAD's lines carry folders; blank lines are skipped; the list's order is not the places'
    (tmp_path / "list.txt").write_text("./nordland/summer/images-00007.png\n\nimages-00002.png\nimages-00003.png\n")
    assert read_image_list(tmp_path / "list.txt") == ["images-00007.png", "images-00002.png", "images-00003.png"]
    sources = {season: {"kind": "frames", "path": str(tmp_path / season)} for season in ("summer", "winter")}
    out = tmp_path / "out"
    out.mkdir()
    record = extract_seasons(sources, ["summer", "winter"], EXTRACT, 1, {}, out, image_list=tmp_path / "list.txt")
    assert record["n_places"] == 3 and record["listed_frames"] == {"summer": [2, 3, 7], "winter": [2, 3, 7]}
    assert np.load(out / "summer.npy")[:, 0, 0, 0].tolist() == [2, 3, 7]
    assert "list.txt keeps 3 a season" in record["pairing"]


def test_an_image_list_naming_a_missing_frame_stops_with_the_file_and_folder(tmp_path):
    numbered_frames(tmp_path / "summer", range(5))
    numbered_frames(tmp_path / "winter", [0, 1, 2, 4])
    (tmp_path / "list.txt").write_text("images-00001.png\nimages-00003.png\n")
    sources = {season: {"kind": "frames", "path": str(tmp_path / season)} for season in ("summer", "winter")}
    with pytest.raises(ValueError, match=r"list.txt: 1 listed images are not in .*winter \(first: images-00003.png\)"):
        extract_seasons(
            sources, ["summer", "winter"], EXTRACT, 1, {}, tmp_path, aligned=False, image_list=tmp_path / "list.txt"
        )
    (tmp_path / "empty.txt").write_text("\n\n")
    with pytest.raises(ValueError, match="empty.txt: the image list names no image"):
        read_image_list(tmp_path / "empty.txt")
    videos = {"summer": {"kind": "video", "path": str(tmp_path / "summer.mp4")}}
    with pytest.raises(ValueError, match="data.image_list: names frame files, but a season's source is a video"):
        extract_seasons(videos, ["summer"], EXTRACT, 1, {}, tmp_path, image_list=tmp_path / "list.txt")


def test_a_whole_route_test_tests_and_trains_on_every_place():
    test_block, gap, train = split_masks(50, 10, 1, 3)
    assert test_block.all() and train.all() and not gap.any()
    tunnel = np.zeros(50, bool)
    tunnel[5] = True
    split = make_split(50, 10, 1, 3, tunnel, np.zeros(50, bool))
    # tunnels and stops still leave the test set (a protocol's cleaned list has none left)
    assert 5 not in split.test and len(split.test) == 49 and len(split.train) == 50


def test_every_kth_test_place_of_one_season_only():
    split = make_split(100, 50, 0.4, 2, np.zeros(100, bool), np.zeros(100, bool), {"summer": 10})
    assert split.test.tolist() == list(range(30, 50)) + list(range(80, 100))
    assert split.season("summer").test.tolist() == [30, 40, 80, 90]
    assert split.season("winter").test.tolist() == split.test.tolist()
    written = json.loads(json.dumps(split.to_json()))
    assert season_part(written, "summer", "test").tolist() == [30, 40, 80, 90]
    assert season_part(written, "winter", "test").tolist() == split.test.tolist()
    with pytest.raises(ValueError, match=r"split.test_every.summer: no test place of summer is a multiple of 1000"):
        make_split(100, 50, 0.4, 2, np.zeros(100, bool), np.zeros(100, bool), {"summer": 1000}).season("summer")


def test_vpr_bench_queries_are_correct_at_the_reference_and_one_frame_either_side():
    # VPR-Bench's Nordland: query i (the summer frame 10i) is correct at references 10i-1 .. 10i+1
    split = make_split(60, 60, 1, 0, np.zeros(60, bool), np.zeros(60, bool), {"summer": 10})
    evaluate = EvaluateConfig(("winter-summer",), "cosine", (), "distance", 10, 1, 10.0, ("single",))
    truth = dict(each_truth("aligned", split.to_json(), ["winter", "summer"], evaluate, Path(), Path()))
    pair = truth[("winter", "summer")]
    assert pair.query_places.tolist() == [0, 10, 20, 30, 40, 50] and len(pair.database_places) == 60
    assert [np.flatnonzero(row).tolist() for row in pair.correct[:2]] == [[0, 1], [9, 10, 11]]


def test_seasons_that_are_not_aligned_sample_their_own_test_places():
    stats = {
        f"{season}_{kind}": np.full(40, 100.0) for season in ("summer", "fall") for kind in ("brightness", "change")
    }
    config = SplitConfig(
        section_length=40,
        test_fraction=0.5,
        gap=2,
        folds=1,
        dark_threshold=40,
        stop_threshold=1.0,
        test_every={"fall": 4},
    )
    split = split_seasons(stats, ["summer", "fall"], config, {"summer": np.arange(40), "fall": np.arange(40)})
    assert split.season("fall").test.tolist() == [20, 24, 28, 32, 36]
    assert split.season("summer").test.tolist() == list(range(20, 40))


def test_a_whole_route_tests_every_frame_those_without_a_reference_place_too():
    # VPR-Bench's queries without a correct reference are evaluated (a miss), not left out
    stats = {f"{season}_{kind}": np.full(10, 100.0) for season in ("ref", "query") for kind in ("brightness", "change")}
    config = SplitConfig(
        section_length=10, test_fraction=1, gap=0, folds=1, dark_threshold=0, stop_threshold=0, test_every={}
    )
    placed = {"ref": np.arange(10), "query": np.array([0, 1, 2, -1, 4, 5, 6, 7, 8, 9])}
    split = split_seasons(stats, ["ref", "query"], config, placed)
    assert split.season("query").test.tolist() == list(range(10))
    partial = SplitConfig(
        section_length=10, test_fraction=0.5, gap=0, folds=1, dark_threshold=0, stop_threshold=0, test_every={}
    )
    assert 3 not in split_seasons(stats, ["ref", "query"], partial, placed).season("query").test.tolist()


def test_a_whole_route_trains_on_a_database_traverse_never_on_a_query_one(params):
    # every place tested and trained on: the map (a database traverse) may be learned, the queries not
    params["split"]["test_fraction"] = 1
    with pytest.raises(
        ValueError,
        match=r"^train.seasons: fall, spring, summer is the query traverse of summer-fall, summer-spring, winter-summer",
    ):
        check_whole(params)
    protocol = copy.deepcopy(params)
    protocol["train"]["seasons"] = ["spring", "fall"]
    protocol["evaluate"]["pairs"] = ["winter-summer"]
    protocol["report"]["example_pair"] = "winter-summer"
    protocol["cae_widths"]["pairs"] = ["winter-summer"]
    protocol["ablation"]["pair"] = "winter-summer"
    protocol["ablation"]["training_seasons"] = [["spring"], ["spring", "fall"]]
    check_whole(protocol)
    protocol["train"]["seasons"] = ["winter"]  # the database traverse: the map
    check_whole(protocol)
    elsewhere = copy.deepcopy(params)  # learners fitted by another run train on nothing here
    elsewhere["train"]["fitted"] = "elsewhere"
    check_whole(elsewhere)
    for key, value, message in (
        ("report.example_pair", "spring-fall", "train.seasons: fall is the query traverse of spring-fall"),
        ("cae_widths.pairs", ["fall-winter"], "train.seasons: winter is the query traverse of fall-winter"),
    ):
        bad = copy.deepcopy(protocol)
        bad["train"]["seasons"] = ["spring", "fall"] if key == "report.example_pair" else ["winter"]
        section, name = key.split(".")
        bad[section][name] = value
        with pytest.raises(ValueError, match=message):
            check_whole(bad)


def test_sampled_test_places_leave_no_sequence_to_match(params):
    params["split"]["test_every"] = {"summer": 10}
    with pytest.raises(ValueError, match=r"split.test_every.summer: every 10th place leaves no sequence to match"):
        check_whole(params)
    params["evaluate"]["matchers"] = ["single"]
    check_whole(params)
    params["split"]["test_fraction"] = 0.9
    with pytest.raises(ValueError, match=r"split.test_fraction: expected a number in \(0, 0.5\] or 1"):
        check_whole(params)


# ---- end to end: both presets on the synthetic route written as Nordland's frame folders ----------

PROTOCOL_SECONDS = 300
# the presets' learners at the tests' size (tests/workspaces.py's TINY), two of them
PROTOCOL_SIZES = {
    **{key: TINY[key] for key in ("extract", "pca", "pca_whiten", "ica", "ica_bovw", "fae", "cae")},
    "learners": ["raw_patchnorm", "pca"],
    "cae_widths": {"widths": []},  # skipped, as in tests/workspaces.py's SMALL
}


def nordland_folders(folder: Path) -> list[int]:
    """folder/<season>/images-NNNNN.png for the four seasons of the synthetic route (1 fps) and
    folder/cleanImageNames.txt listing the frames outside its tunnels and stops; returns the
    listed frame numbers."""
    videos = folder / "videos"
    layout = render_route(videos, list(SEASONS), PROTOCOL_SECONDS, 1, 128, 72, seed=5, progress=False)
    clean = np.flatnonzero(~(layout.in_tunnel() | layout.stopped())[:PROTOCOL_SECONDS])
    for season in SEASONS:
        (folder / season).mkdir(parents=True)
        for number, frame in enumerate(sample_video(videos / f"{season}.mp4", 1, 72, 128, progress=False)):
            cv2.imwrite(str(folder / season / f"images-{number:05d}.png"), frame)
    names = [f"./nordland/{SEASONS[0]}/images-{number:05d}.png" for number in clean]
    (folder / "cleanImageNames.txt").write_text("\n".join(names) + "\n")
    return clean.tolist()


def use_preset(root: Path, preset: str, frames: Path) -> None:
    params = composed_params(preset, REPO / "params.yaml", REPO / "presets")
    params = merge(params, {**PROTOCOL_SIZES, "data": {"frames_dir": str(frames)}})
    (root / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))


@pytest.mark.e2e
def test_the_vpr_bench_and_patch_netvlad_presets_run_on_nordland_shaped_folders(tmp_path):
    listed = nordland_folders(tmp_path / "nordland")
    root = make_workspace(tmp_path / "repo", {})
    use_preset(root, "vpr_bench_nordland", tmp_path / "nordland")
    # both runs up to the evaluation, what they check (a single-matcher run with fewer queries than
    # database places goes through the report in tests/test_field_layouts.py's VPR-Bench test)
    result = dvc(root, "repro", "evaluate@raw_patchnorm", "evaluate@pca")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    frames = json.loads((root / "data/frames/frames.json").read_text())
    assert frames["listed_frames"]["winter"] == listed and frames["n_places"] == len(listed)
    # the learners saw spring and fall only, every listed place of each (and its augmented copy)
    fit = json.loads((root / "metrics/fit/pca.json").read_text())
    assert fit["train_seasons"] == ["spring", "fall"] and fit["n_train_images"] == 2 * 2 * len(listed)
    pair = json.loads((root / "metrics/ground_truth.json").read_text())["pairs"]["winter-summer"]
    # every 10th list position a query, each correct at its own reference and one either side
    assert pair["n_database"] == len(listed) and pair["n_queries"] == len(range(0, len(listed), 10))
    assert pair["n_without_match"] == 0 and 2.5 < pair["mean_correct_per_query"] <= 3
    for learner in ("raw_patchnorm", "pca"):
        metrics = json.loads((root / f"metrics/eval/{learner}/winter-summer.json").read_text())
        assert metrics["recall_at_1"] <= metrics["recall_at_5"] <= metrics["recall_at_10"]
        assert metrics["recall_at_1"] > 3 * pair["mean_correct_per_query"] / pair["n_database"]
    assert not (root / "metrics/eval/pca/winter-summer+seq.json").exists()

    use_preset(root, "patchnetvlad_nordland", tmp_path / "nordland")
    result = dvc(root, "repro", "evaluate@raw_patchnorm", "evaluate@pca")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    pair = json.loads((root / "metrics/ground_truth.json").read_text())["pairs"]["summer-winter"]
    assert pair["n_database"] == pair["n_queries"] == len(listed)
    # within 7 list positions: 15 correct references away from the route's ends
    assert 13 < pair["mean_correct_per_query"] <= 15
    metrics = json.loads((root / "metrics/eval/raw_patchnorm/summer-winter.json").read_text())
    assert metrics["recall_at_1"] > 3 * pair["mean_correct_per_query"] / pair["n_database"]
