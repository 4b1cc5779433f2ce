import json

import numpy as np
import pytest
from sequence_settings import sequence_config

from seasonloop.ablations.training_season_records import (
    read_learner_intervals,
    read_learner_records,
    read_not_fitted,
    write_ablation,
)
from seasonloop.ablations.training_seasons import (
    AblationRun,
    plan_ablation,
    reusable_label,
    run_ablation,
    write_learner_record,
)
from seasonloop.data.ground_truth import aligned_truth
from seasonloop.evaluation.context import EvaluationContext
from seasonloop.params.settings import EvaluateConfig, SequenceConfig, StatisticsConfig
from seasonloop.reporting.model_sections import training_seasons_section
from seasonloop.reporting.replicates import first_to_last
from seasonloop.reporting.summary import percent_cell

SEASONS4 = ["summer", "spring", "fall", "winter"]
STUDY_SETS = [["summer"], ["summer", "winter"], ["summer", "winter", "spring"], ["summer", "winter", "spring", "fall"]]
PAIRS = ["summer-fall", "summer-spring", "spring-fall", "winter-summer", "winter-fall", "winter-spring"]


def matching_settings(extra_metrics: tuple[str, ...] = ()) -> tuple[EvaluateConfig, SequenceConfig]:
    """The ablation tests' evaluation: summer-fall, Euclidean, single-image matching."""
    evaluate = EvaluateConfig(
        pairs=("summer-fall",),
        metric="euclidean",
        extra_metrics=extra_metrics,
        confidence="ratio",
        ratio_exclusion=0,
        tolerance_frames=0,
        tolerance_m=10.0,
        matchers=("single",),
    )
    return evaluate, sequence_config(v_min=0.8, v_max=1.2, v_steps=3, window=2)


def test_all_seasons_keep_the_study_plan():
    plan = plan_ablation(["summer", "spring", "fall", "winter"], "summer-fall", STUDY_SETS, PAIRS)
    assert plan.pair == ("summer", "fall") and plan.season_sets == STUDY_SETS and not plan.notes
    assert plan.labels == ["summer", "summer+winter", "summer+winter+spring", "summer+winter+spring+fall"]


def test_a_summer_winter_subset_adapts_pair_and_lists():
    plan = plan_ablation(["summer", "winter"], "summer-fall", STUDY_SETS, PAIRS)
    assert plan.pair == ("winter", "summer")  # the first of evaluate.pairs present
    assert plan.season_sets == [["summer"], ["summer", "winter"]]
    assert plan.skipped is None
    assert any("using winter-summer" in note for note in plan.notes)


def test_no_study_pair_present_uses_the_seasons_in_order():
    plan = plan_ablation(["spring", "summer"], "summer-fall", [["summer"], ["fall"]], ["winter-fall"])
    assert plan.pair == ("spring", "summer") and plan.season_sets == [["summer"]]


def test_one_season_is_skipped_with_a_reason():
    plan = plan_ablation(["summer"], "summer-fall", STUDY_SETS, PAIRS)
    assert plan.pair is None and plan.season_sets == []
    assert "two seasons" in plan.skipped


def test_no_usable_training_list_is_skipped():
    plan = plan_ablation(["summer", "fall"], "summer-fall", [["winter"]], PAIRS)
    assert plan.skipped and "ablation.training_seasons" in plan.skipped


def test_unknown_names_are_errors():
    with pytest.raises(ValueError, match="ablation.training_seasons: unknown traverse 'autumn'"):
        plan_ablation(["summer", "fall"], "summer-fall", [["autumn"]], PAIRS)
    with pytest.raises(ValueError, match="ablation.pair"):
        plan_ablation(["summer", "fall"], "summer_fall", STUDY_SETS, PAIRS)


class MeanLearner:
    """Describes an image by its row means; remembers what it was fitted on."""

    fitted_on: list[int] = []
    places: list = []

    def fit(self, images, progress=False, places=None, traverses=None):
        MeanLearner.fitted_on.append(len(images))
        MeanLearner.places.append(places)
        return {"converged": True, "n_iter": len(images), "n_components": 4}  # fit info, as a learner's

    def how_fit_ended(self, info):
        return {key: info[key] for key in ("converged", "n_iter")}

    def describe(self, images, batch_size=1024):
        return images.mean(axis=2)


def test_a_whole_route_leaves_out_lists_that_hold_the_query_traverse():
    # split.test_fraction 1: every place is a test place, so a list with the pair's query is left out
    plan = plan_ablation(SEASONS4, "winter-summer", STUDY_SETS, PAIRS, whole_route=True)
    assert plan.skipped is not None and "one is left at most (none)" in plan.skipped
    sets = [["spring"], ["spring", "fall"], ["spring", "fall", "summer"]]
    plan = plan_ablation(SEASONS4, "winter-summer", sets, PAIRS, whole_route=True)
    assert plan.skipped is None and plan.labels == ["spring", "spring+fall"]
    assert plan.notes == [
        "ablation.training_seasons: spring+fall+summer left out: summer is the query traverse, and "
        "split.test_fraction 1 trains on every place"
    ]
    # two traverses, a reference and its queries: one training set, nothing to compare
    plan = plan_ablation(["ref", "query"], "ref-query", [["ref"], ["ref", "query"]], ["ref-query"], whole_route=True)
    assert plan.skipped == (
        "skipped: it compares training sets, and with split.test_fraction 1 and query the query traverse "
        "one is left at most (ref)"
    )


def pair_context(test, evaluate, sequence) -> EvaluationContext:
    """summer-fall's six aligned test places, as the stage builds them."""
    truth = aligned_truth(np.arange(6), np.arange(6), 0)
    return EvaluationContext(
        test,
        {("summer", "fall"): truth},
        [("summer", "fall")],
        evaluate,
        sequence,
        StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05),
        1024,
    )


def five_places_twice(seasons):
    """A training set where every season shows the same 5 places, each twice (original and augmented
    copy): (images, their places, their traverses)."""
    places = np.tile(np.repeat(np.arange(5), 2), len(seasons))
    return np.zeros((10 * len(seasons), 4, 8)), places, np.repeat(np.arange(len(seasons)), 10)


def test_run_ablation_fits_a_fresh_learner_per_list(tmp_path):
    plan = plan_ablation(
        ["summer", "fall", "winter"], "summer-fall", [["summer"], ["summer", "winter"]], ["summer-fall"]
    )
    rng = np.random.default_rng(0)
    test = {"summer": rng.random((6, 4, 8))}
    test["fall"] = test["summer"] + rng.normal(0, 0.01, (6, 4, 8))
    evaluate, sequence = matching_settings(extra_metrics=("cityblock",))
    made = []

    def new_learner():
        made.append(1)
        return MeanLearner()

    MeanLearner.fitted_on, MeanLearner.places = [], []
    run = run_ablation(plan, {"mean": new_learner}, five_places_twice, pair_context(test, evaluate, sequence))
    fraction_correct, intervals = run.fraction_correct, run.intervals
    assert len(made) == 2 and MeanLearner.fitted_on == [10, 20]
    # how each fit ended is kept per training-season list
    assert run.fits == {
        "mean": {"summer": {"converged": True, "n_iter": 10}, "summer+winter": {"converged": True, "n_iter": 20}}
    }
    # the place ids reach fit: an auto-encoder then validates on places it never trains on
    assert [None if places is None else list(places) for places in MeanLearner.places] == [
        list(five_places_twice(["summer"])[1]),
        list(five_places_twice(["summer", "winter"])[1]),
    ]
    # one series per distance, named as the tables' rows
    assert list(fraction_correct) == ["mean", "mean@cityblock"]
    assert list(fraction_correct["mean"]) == list(fraction_correct["mean@cityblock"]) == ["summer", "summer+winter"]
    assert fraction_correct["mean"]["summer"] == 1.0
    # each fraction correct with its interval: every query right, so [1, 1]
    assert list(intervals) == ["mean", "mean@cityblock"]
    assert intervals["mean"]["summer"] == {
        "low": None,
        "high": None,
        "reason": "not enough queries (6 on a route, fewer than 49)",
    }
    write_ablation(plan, fraction_correct, tmp_path / "record.json", tmp_path / "figure.png", intervals)
    record = json.loads((tmp_path / "record.json").read_text())
    assert record == {
        "fraction_correct": fraction_correct,
        "intervals": intervals,
        "notes": [],
        "pair": "summer-fall",
        "season_sets": ["summer", "summer+winter"],
    }
    assert (tmp_path / "figure.png").read_bytes().startswith(b"\x89PNG")


def test_write_ablation_of_a_skipped_plan(tmp_path):
    plan = plan_ablation(["summer"], "summer-fall", [["summer"]], ["summer-fall"])
    write_ablation(plan, None, tmp_path / "record.json", tmp_path / "figure.png")
    assert json.loads((tmp_path / "record.json").read_text()) == {"skipped": plan.skipped}
    assert (tmp_path / "figure.png").is_file()


def found(fraction_correct: dict) -> AblationRun:
    """run_ablation's result with these fractions correct (no intervals, no fit records)."""
    return AblationRun(fraction_correct, {}, {})


def test_learner_records_combine_into_the_ablation_record(tmp_path):
    # one record per learner (one stage each), read back into what write_ablation writes
    seasons = ["summer", "spring", "fall", "winter"]
    plan = plan_ablation(seasons, "summer-fall", [["summer"], ["summer", "winter"]], ["summer-fall"])
    write_learner_record(plan, "pca", found({"pca": {"summer": 0.5, "summer+winter": 0.75}}), tmp_path / "pca.json")
    ica = {"ica": {"summer+winter": 0.625, "summer": 0.25}, "ica@cityblock": {"summer": 0.125, "summer+winter": 0.5}}
    write_learner_record(plan, "ica", found(ica), tmp_path / "ica.json")
    combined = read_learner_records(plan, ["pca", "ica"], tmp_path, tmp_path / "eval")
    assert combined == {
        "pca": {"summer": 0.5, "summer+winter": 0.75},
        "ica": {"summer": 0.25, "summer+winter": 0.625},
        "ica@cityblock": {"summer": 0.125, "summer+winter": 0.5},
    }
    # a record of another plan (other seasons lists) is stale: one clear line, not a wrong figure
    other = plan_ablation(seasons, "summer-fall", [["summer"]], ["summer-fall"])
    with pytest.raises(ValueError, match="pca.json: written for another ablation plan"):
        read_learner_records(other, ["pca"], tmp_path, tmp_path / "eval")
    with pytest.raises(FileNotFoundError, match="training_seasons_fit@fae"):
        read_learner_records(plan, ["fae"], tmp_path, tmp_path / "eval")
    skipped = plan_ablation(["summer"], "summer-fall", [["summer"]], ["summer-fall"])
    write_learner_record(skipped, "pca", None, tmp_path / "skipped.json")
    assert json.loads((tmp_path / "skipped.json").read_text())["skipped"].startswith("skipped:")


def test_a_reused_label_is_not_refitted_and_is_read_from_the_pipelines_evaluation(tmp_path):
    # the pipeline's learner is fitted on train.seasons: the ablation's list of the same seasons
    # is that learner, so its value is evaluate@<learner>'s fraction correct on the plan's pair
    seasons = ["summer", "spring", "fall", "winter"]
    plan = plan_ablation(seasons, "summer-fall", [["summer"], ["summer", "winter"]], ["summer-fall"])
    assert reusable_label(plan, ["winter", "summer"], True, True) == "summer+winter"
    assert reusable_label(plan, ["winter", "summer"], False, True) is None  # not a pipeline learner
    assert reusable_label(plan, ["winter", "summer"], True, False) is None  # pair not evaluated
    assert reusable_label(plan, seasons, True, True) is None  # no list of these seasons
    series = {"pca": {"summer": 0.5}, "pca@cityblock": {"summer": 0.25}}
    write_learner_record(plan, "pca", found(series), tmp_path / "pca.json", reused="summer+winter")
    with pytest.raises(FileNotFoundError, match="evaluate@pca"):
        read_learner_records(plan, ["pca"], tmp_path, tmp_path / "eval")
    (tmp_path / "eval" / "pca").mkdir(parents=True)
    (tmp_path / "eval" / "pca" / "summer-fall.json").write_text(json.dumps({"fraction_correct": 0.875}))
    # each distance's value from its own evaluation file
    (tmp_path / "eval" / "pca" / "summer-fall@cityblock.json").write_text(json.dumps({"fraction_correct": 0.625}))
    assert read_learner_records(plan, ["pca"], tmp_path, tmp_path / "eval") == {
        "pca": {"summer": 0.5, "summer+winter": 0.875},
        "pca@cityblock": {"summer": 0.25, "summer+winter": 0.625},
    }


def test_run_ablation_skips_the_reused_label(tmp_path):
    plan = plan_ablation(
        ["summer", "fall", "winter"], "summer-fall", [["summer"], ["summer", "winter"]], ["summer-fall"]
    )
    rng = np.random.default_rng(0)
    test = {"summer": rng.random((6, 4, 8)), "fall": rng.random((6, 4, 8))}
    evaluate, sequence = matching_settings()
    MeanLearner.fitted_on, MeanLearner.places = [], []
    run = run_ablation(
        plan,
        {"mean": MeanLearner},
        five_places_twice,
        pair_context(test, evaluate, sequence),
        skip={"mean": "summer+winter"},
    )
    assert MeanLearner.fitted_on == [10] and list(run.fraction_correct["mean"]) == ["summer"]


def test_how_a_fit_ended_is_the_learners_own_reading_of_its_fit():
    from seasonloop.models.core.lookup import get_learner

    ica = {"converged": True, "gradient": 9e-8, "tol": 1e-7, "n_iter": 300, "solver": "picard"}
    assert get_learner("ica").how_fit_ended(ica) == {"converged": True, "gradient": 9e-8, "tol": 1e-7, "n_iter": 300}
    # the bag of words nests its patch ICA's fit and adds k-means'
    bovw = {"ica": {"converged": False, "n_iter": 400}, "kmeans_n_iter": 3, "n_train_patches": 10}
    ended = get_learner("ica_bovw").how_fit_ended(bovw)
    assert ended == {"ica converged": False, "ica n_iter": 400, "kmeans n_iter": 3}
    assert get_learner("pca").how_fit_ended({"n_components": 4}) == {}


class NeedsTwoTraverses(MeanLearner):
    """A learner that learns from places seen in two traverses (as models/place_cnn.py)."""

    min_traverses = 2


def test_a_set_of_fewer_traverses_than_the_learner_needs_is_not_fitted_and_says_why(tmp_path):
    plan = plan_ablation(
        ["summer", "fall", "winter"], "summer-fall", [["summer"], ["summer", "winter"]], ["summer-fall"]
    )
    rng = np.random.default_rng(0)
    test = {"summer": rng.random((6, 4, 8))}
    test["fall"] = test["summer"] + rng.normal(0, 0.01, (6, 4, 8))
    evaluate, sequence = matching_settings()
    MeanLearner.fitted_on, MeanLearner.places = [], []
    run = run_ablation(plan, {"cnn": NeedsTwoTraverses}, five_places_twice, pair_context(test, evaluate, sequence))
    assert MeanLearner.fitted_on == [20]  # summer+winter only
    assert run.fraction_correct["cnn"]["summer"] is None and run.fraction_correct["cnn"]["summer+winter"] == 1.0
    assert run.not_fitted["cnn"]["summer"].startswith("not fitted: cnn trains on 2 traverses or more")
    assert set(run.intervals["cnn"]) == {"summer+winter"}
    write_learner_record(plan, "cnn", run, tmp_path / "cnn.json")
    assert read_learner_records(plan, ["cnn"], tmp_path, tmp_path / "eval") == run.fraction_correct
    intervals = read_learner_intervals(plan, ["cnn"], tmp_path, tmp_path / "eval")
    not_fitted = read_not_fitted(["cnn"], tmp_path)
    assert not_fitted == run.not_fitted
    write_ablation(plan, run.fraction_correct, tmp_path / "record.json", tmp_path / "figure.png", intervals, not_fitted)
    record = json.loads((tmp_path / "record.json").read_text())
    assert record["not_fitted"] == run.not_fitted and record["fraction_correct"]["cnn"]["summer"] is None
    # the report's table and the docs' read it: n/a, and why beside the table
    section = training_seasons_section(record, tmp_path / "figure.png")
    assert "cnn on summer: not fitted" in str(section)
    assert percent_cell(None) == "n/a"
    # the replicate routes compare its smallest fitted set with its largest (here one: the same)
    assert first_to_last({"0": record})["cnn"] == {"up": 0, "down": 0, "same": 1}
