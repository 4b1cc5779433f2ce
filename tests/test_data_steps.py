"""Unit tests of the data steps on small arrays: sources, preprocessing, split, augmentation."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest

from seasonloop.data.augment import augment_images, augment_training_set
from seasonloop.data.frames import align_frame_files, list_frame_files, natural_key, read_frame_folder, sample_video
from seasonloop.data.preprocess import CONTRASTS, enhance_image_contrast, frame_statistics, to_gray
from seasonloop.data.sources import (
    FRAME_KINDS,
    SOURCES,
    _check_outside_copy,
    check_aligned,
    pair_season_files,
    place_description,
    read_season,
    real_sources,
)
from seasonloop.data.split import detect_stops, detect_tunnels, make_split, section_blocks
from seasonloop.params.seasons import available_pairs, check_seasons
from seasonloop.params.settings import DataConfig

DATA = DataConfig(
    source="frames",
    seasons=("summer",),
    videos_dir="videos",
    video_files={},
    frames_dir="frames",
    frame_step=1,
    offsets={},
    ground_truth="aligned",
    positions_dir="positions",
    position_source="csv",
    position_columns=("x", "y"),
    position_units="metres",
    position_key="",
    ground_truth_dir="ground_truth",
    image_list="",
)


def write_video(path, n_frames, fps=4, size=(48, 32)):
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), fps, size)
    for i in range(n_frames):
        # frame i shows its own index as a flat gray level, so sampling is checkable after compression
        writer.write(np.full((size[1], size[0], 3), 10 * i % 250, np.uint8))
    writer.release()


def test_sample_video_takes_one_frame_per_second(tmp_path):
    path = tmp_path / "v.mp4"
    write_video(path, n_frames=20, fps=4)
    frames = sample_video(path, fps=1, height=8, width=12, progress=False)
    assert frames.shape == (5, 8, 12, 3)
    # sample k is video frame 4k, whose gray level is 40k
    np.testing.assert_allclose(frames[:, 4, 6, 0], 40 * np.arange(5), atol=6)


def test_sample_video_rejects_missing_and_corrupt_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="nothere.mp4"):
        sample_video(tmp_path / "nothere.mp4", 1, 8, 8)
    bad = tmp_path / "bad.mp4"
    bad.write_bytes(b"not a video at all" * 100)
    with pytest.raises(ValueError, match="bad.mp4"):
        sample_video(bad, 1, 8, 8)


def test_frame_folder_reads_sorted_and_rejects_bad(tmp_path):
    folder = tmp_path / "summer"
    folder.mkdir()
    for i in (2, 0, 1):
        cv2.imwrite(str(folder / f"{i:05d}.png"), np.full((20, 30, 3), 50 * i, np.uint8))
    frames = read_frame_folder(folder, 10, 15, progress=False)
    assert frames.shape == (3, 10, 15, 3)
    assert list(frames[:, 0, 0, 0]) == [0, 50, 100]
    (folder / "00003.png").write_bytes(b"garbage")
    with pytest.raises(ValueError, match="00003.png"):
        read_frame_folder(folder, 10, 15, progress=False)
    with pytest.raises(FileNotFoundError, match="winter"):
        real_sources("frames", ["winter"], replace(DATA, frames_dir=str(tmp_path)))
    with pytest.raises(ValueError, match="data.source"):
        real_sources("dropbox", ["summer"], DATA)


def test_source_registry_names_and_errors(tmp_path):
    assert list(SOURCES) == ["synthetic", "videos", "frames"]
    assert all(source.kind in FRAME_KINDS for source in SOURCES.values())
    with pytest.raises(ValueError) as error:
        real_sources("dropbox", ["summer"], DATA)
    assert str(error.value) == "data.source: unknown source 'dropbox' (known: synthetic, videos, frames)"
    with pytest.raises(ValueError, match=r"data\.source: 'synthetic' is rendered.*videos, frames\)$"):
        real_sources("synthetic", ["summer"], DATA)
    with pytest.raises(ValueError, match=r"unknown frame source kind 'tape' \(known: video, frames\)"):
        read_season("tape", tmp_path, 1.0, 4, 6)


def test_every_real_source_locates_its_files_and_they_read(tmp_path):
    write_frames(tmp_path / "frames" / "summer", ["1.png", "2.png", "3.png"])
    write_video(tmp_path / "s.mp4", 8, fps=4)
    data = replace(DATA, frames_dir=str(tmp_path / "frames"), videos_dir=str(tmp_path), video_files={"summer": "s.mp4"})
    for name, source in SOURCES.items():
        if source.locate is None:
            continue  # rendered by the acquire stage
        path = real_sources(name, ["summer"], data)["summer"]
        frames = read_season(source.kind, path, 2.0, 4, 6, progress=False)
        assert frames.shape[1:] == (4, 6, 3) and len(frames) >= 3
        files, line = pair_season_files({"summer": (source.kind, path)})
        assert (files is None) == (FRAME_KINDS[source.kind].list_files is None) and line
        assert place_description({source.kind}, 2.0, 1)
    with pytest.raises(ValueError, match=r"data\.video_files: no file given for season 'winter'"):
        real_sources("videos", ["winter"], data)


def write_frames(folder, names, level=lambda i: 20 * i % 250):
    folder.mkdir(parents=True, exist_ok=True)
    for i, name in enumerate(names):
        cv2.imwrite(str(folder / name), np.full((8, 12, 3), level(i), np.uint8))


def test_frame_files_sort_naturally_and_skip_hidden_files(tmp_path):
    # names as several Nordland releases give them: not zero-padded
    write_frames(tmp_path / "summer", [f"{i}.png" for i in range(1, 13)], level=lambda i: 20 * (i + 1))
    (tmp_path / "summer" / "._3.png").write_bytes(b"macOS resource fork, not an image")
    (tmp_path / "summer" / ".DS_Store").write_bytes(b"x")
    files = list_frame_files(tmp_path / "summer")
    assert [f.name for f in files] == [f"{i}.png" for i in range(1, 13)]
    frames = read_frame_folder(tmp_path / "summer", 4, 6, progress=False)
    assert list(frames[:, 0, 0, 0]) == [20 * i for i in range(1, 13)]  # route order, 10.png after 9.png
    assert sorted(["b10", "b2", "a1"], key=natural_key) == ["a1", "b2", "b10"]


def test_frame_step_keeps_every_kth_place(tmp_path):
    write_frames(tmp_path / "summer", [f"{i}.png" for i in range(10)], level=lambda i: 20 * i)
    frames = read_season("frames", tmp_path / "summer", 1.0, 4, 6, progress=False, frame_step=3)
    assert list(frames[:, 0, 0, 0]) == [0, 60, 120, 180]
    write_video(tmp_path / "v.mp4", 16, fps=4)
    all_samples = read_season("video", tmp_path / "v.mp4", 2.0, 8, 12, progress=False)
    every_other = read_season("video", tmp_path / "v.mp4", 2.0, 8, 12, progress=False, frame_step=2)
    np.testing.assert_array_equal(every_other, all_samples[::2])
    with pytest.raises(ValueError, match="data.frame_step"):
        read_season("frames", tmp_path / "summer", 1.0, 4, 6, frame_step=0)


def test_seasons_sharing_names_are_paired_by_name(tmp_path):
    names = [f"{i}.png" for i in range(1, 12)]
    write_frames(tmp_path / "summer", names)
    write_frames(tmp_path / "winter", names)
    files, line = align_frame_files({s: list_frame_files(tmp_path / s) for s in ("summer", "winter")})
    assert "by file name" in line
    assert [f.name for f in files["summer"]] == [f.name for f in files["winter"]] == names
    # different naming schemes, same count: paired by position
    write_frames(tmp_path / "fall", [f"fall_{i}.png" for i in range(1, 12)])
    files, line = align_frame_files({s: list_frame_files(tmp_path / s) for s in ("summer", "fall")})
    assert "by position" in line and files["fall"][9].name == "fall_10.png"
    # some names shared, one missing: every later place would shift
    write_frames(tmp_path / "spring", names[:4] + names[5:] + ["12.png"])
    with pytest.raises(
        ValueError,
        match=r"(summer/5\.png: no frame of that name in spring|spring/12\.png: no frame of that name in summer)",
    ):
        align_frame_files({s: list_frame_files(tmp_path / s) for s in ("summer", "spring")})


def test_mismatched_season_lengths_are_an_error_unless_trimmed():
    counts = {"summer": 10, "winter": 9}
    with pytest.raises(ValueError, match="winter: 9"):
        check_aligned(counts, False, {"summer": "s.mp4", "winter": "w.mp4"})
    assert check_aligned(counts, True, {"summer": "s.mp4", "winter": "w.mp4"}) == 9


def test_season_checks_name_the_key():
    with pytest.raises(ValueError, match="data.seasons: unknown traverse 'autumn'"):
        check_seasons(["summer", "autumn"], "data.seasons", allowed=["summer", "fall"])
    with pytest.raises(ValueError, match="data.seasons: repeated traverse"):
        check_seasons(["summer", "summer"], "data.seasons")
    assert available_pairs(["summer", "winter"], ["summer-fall", "winter-summer"]) == [("winter", "summer")]


def test_preprocess_shapes_and_contrast():
    rng = np.random.default_rng(0)
    frames = rng.integers(90, 110, (3, 72, 128, 3), dtype=np.uint8)
    gray = to_gray(frames, 32, 64)
    assert gray.shape == (3, 32, 64) and gray.dtype == np.uint8
    for method in ("clahe", "equalize"):
        enhanced = enhance_image_contrast(gray, method, 2.0, 4)
        # a low-contrast image gets its contrast stretched
        assert enhanced.std() > 2 * gray.std()
    with pytest.raises(ValueError, match="preprocess.contrast"):
        enhance_image_contrast(gray, "sharpen", 2.0, 4)
    brightness, change = frame_statistics(np.stack([gray[0], gray[0], gray[1]]))
    assert change[0] == np.inf and change[1] == 0 and change[2] > 0
    np.testing.assert_allclose(brightness[0], gray[0].mean())


@pytest.mark.parametrize("method", list(CONTRASTS))
def test_every_contrast_method_keeps_shape_and_dtype(method):
    gray = np.random.default_rng(1).integers(90, 110, (2, 16, 24), dtype=np.uint8)
    enhanced = enhance_image_contrast(gray, method, 2.0, 4)
    assert enhanced.shape == gray.shape and enhanced.dtype == np.uint8 and enhanced is not gray
    assert enhance_image_contrast(gray[:0], method, 2.0, 4).shape == (0, 16, 24)


def test_an_unknown_contrast_method_is_one_line_naming_the_key_and_the_methods():
    with pytest.raises(ValueError) as error:
        enhance_image_contrast(np.zeros((1, 4, 4), np.uint8), "sharpen", 2.0, 4)
    message = str(error.value)
    assert "\n" not in message and message.startswith("preprocess.contrast: unknown method 'sharpen'")
    assert message.endswith(f"(known: {', '.join(CONTRASTS)})")


def test_split_never_puts_a_test_place_or_its_neighbours_in_training():
    n, gap = 1000, 7
    tunnel = np.zeros(n, bool)
    stop = np.zeros(n, bool)
    tunnel[95:99] = True
    stop[190:195] = True
    split = make_split(n, section_length=100, test_fraction=0.1, gap=gap, tunnel=tunnel, stop=stop)
    train, test = set(split.train), set(split.test)
    assert not train & test
    test_block = set(split.test) | set(split.dropped_tunnel) | set(split.dropped_stop)
    distance = np.abs(np.array(sorted(train))[:, None] - np.array(sorted(test_block))[None, :]).min()
    assert distance > gap
    assert set(split.dropped_tunnel) == set(range(95, 99))
    assert set(split.dropped_stop) == set(range(190, 195))
    assert len(test_block) == 100 and len(section_blocks(n, 100, 0.1)) == 10
    # every place is in exactly one part
    parts = [split.train, split.test, split.gap, split.dropped_tunnel, split.dropped_stop]
    assert sorted(np.concatenate(parts).tolist()) == list(range(n))


def test_tunnel_and_stop_detection_from_statistics():
    brightness = {"summer": np.array([100, 20, 100.0]), "winter": np.array([90, 30, 90.0])}
    assert detect_tunnels(brightness, 40).tolist() == [False, True, False]
    change = {"summer": np.array([np.inf, 5, 0.2]), "winter": np.array([np.inf, 6, 7])}
    assert detect_stops(change, 1.0).tolist() == [False, False, True]


def test_augmentation_keeps_shapes_and_is_reproducible():
    rng = np.random.default_rng(0)
    images = rng.integers(0, 255, (50, 32, 64), dtype=np.uint8)
    first = augment_training_set(images, copies=2, seed=3)
    second = augment_training_set(images, copies=2, seed=3)
    assert first.shape == (150, 32, 64) and first.dtype == np.uint8
    np.testing.assert_array_equal(first, second)
    np.testing.assert_array_equal(first[:50], images)
    assert not np.array_equal(first[50:100], images)
    assert not np.array_equal(augment_training_set(images, 1, seed=4)[50:], first[50:100])


def test_augmentation_shift_and_flip_geometry():
    image = np.arange(4 * 8, dtype=np.uint8).reshape(1, 4, 8)
    flipped = augment_images(image, np.random.default_rng(0), True, 0.0, 0.0)
    unflipped = augment_images(image, np.random.default_rng(0), False, 0.0, 0.0)
    np.testing.assert_array_equal(unflipped, image)
    # with no shift an augmented image is the original or its mirror image
    assert np.array_equal(flipped, image) or np.array_equal(flipped, image[:, :, ::-1])
    shifted = augment_images(np.repeat(image, 200, 0), np.random.default_rng(1), False, 0.3, 0.0)
    # a horizontal shift keeps rows and repeats edge columns (Keras' fill_mode "nearest")
    assert set(np.unique(shifted[:, 0, :])) <= set(image[0, 0])
    assert any(np.array_equal(s[:, :-2], image[0][:, 2:]) for s in shifted)
    with pytest.raises(ValueError, match="augment.width_shift"):
        augment_images(image, np.random.default_rng(0), True, 1.5, 0.0)


def test_detection_finds_the_renderers_tunnels_and_stops():
    """Image-based tunnel and stop detection against the synthetic route's true layout."""
    from seasonloop.data.synthetic import SyntheticRoute

    route = SyntheticRoute(seconds=700, seed=1)
    layout = route.layout
    assert layout.tunnels and layout.stops
    brightness, change = {}, {}
    for season in ("summer", "winter"):
        # one frame per second, as extract_frames takes them, at the preprocessing size
        frames = np.stack([route.frame(season, float(t), 128, 72) for t in range(layout.seconds)])
        brightness[season], change[season] = frame_statistics(to_gray(frames, 32, 64))
    tunnel = detect_tunnels(brightness, dark_threshold=40)
    stop = detect_stops(change, stop_threshold=1.0)
    true_tunnel, true_stop = layout.in_tunnel(), layout.stopped()
    assert (tunnel & true_tunnel).sum() >= 0.9 * true_tunnel.sum()
    assert (tunnel & ~true_tunnel).sum() <= 0.1 * true_tunnel.sum() + 4  # tunnel mouths are dark too
    assert (stop & true_stop).sum() >= 0.9 * true_stop.sum()
    # the train slows down before a stop and speeds up after it, so the seconds just around a
    # stop look still too; a dark tunnel looks still as well, and the split counts it as a tunnel.
    # Anything else would be a false stop.
    near_stop = np.zeros_like(true_stop)
    for start, end in layout.stops:
        near_stop[max(0, start - 8) : end + 8] = True
    assert not (stop & ~near_stop & ~tunnel).any()


def test_a_queued_experiment_missing_relative_data_says_why(tmp_path):
    queued = tmp_path / ".dvc/tmp/exps/tmp1"
    with pytest.raises(FileNotFoundError, match="data.frames_dir as an absolute path"):
        _check_outside_copy(Path("data/nordland/frames/summer"), "data.frames_dir", cwd=queued)
    _check_outside_copy(
        Path("data/nordland/frames/summer"), "data.frames_dir", cwd=tmp_path
    )  # not queued: no error here
    _check_outside_copy(tmp_path / "absent", "data.frames_dir", cwd=queued)  # absolute: the normal error later
