import pytest

from seasonloop.ablation import plan_ablation

STUDY_SETS = [["summer"], ["summer", "winter"], ["summer", "winter", "spring"], ["summer", "winter", "spring", "fall"]]
PAIRS = ["summer-fall", "summer-spring", "spring-fall", "winter-summer", "winter-fall", "winter-spring"]


def test_all_seasons_keep_the_study_plan():
    plan = plan_ablation(["summer", "spring", "fall", "winter"], "summer-fall", STUDY_SETS, PAIRS)
    assert plan.pair == ("summer", "fall") and plan.season_sets == STUDY_SETS and not plan.notes
    assert plan.labels == ["summer", "summer+winter", "summer+winter+spring", "summer+winter+spring+fall"]


def test_a_summer_winter_subset_adapts_pair_and_lists():
    plan = plan_ablation(["summer", "winter"], "summer-fall", STUDY_SETS, PAIRS)
    assert plan.pair == ("winter", "summer")          # the first of evaluate.pairs present
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
    with pytest.raises(ValueError, match="ablation.training_seasons: unknown season 'autumn'"):
        plan_ablation(["summer", "fall"], "summer-fall", [["autumn"]], PAIRS)
    with pytest.raises(ValueError, match="ablation.pair"):
        plan_ablation(["summer", "fall"], "summer_fall", STUDY_SETS, PAIRS)
