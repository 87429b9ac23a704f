"""Segmentation: fuzzy C-means classes, Otsu, fixed threshold, clutter removal."""

import cv2
import numpy as np
import pytest

from usvtool.chart.segment import segment
from usvtool.errors import UsvError

LANDA = (201, 185, 122)
DEPDW = (212, 234, 238)
DEPMS = (152, 197, 242)


def two_tone(h=60, w=80, land=LANDA, water=DEPDW):
    """Left half land, right half water."""
    img = np.empty((h, w, 3), np.uint8)
    img[:, : w // 2] = land
    img[:, w // 2 :] = water
    truth = np.zeros((h, w), bool)
    truth[:, : w // 2] = True
    return img, truth


def test_otsu_on_two_tone_grey_image_splits_between_the_tones():
    img, truth = two_tone()
    seg = segment(img, channel="grey", min_area=1)
    # grey = 0.299 R + 0.587 G + 0.114 B: LANDA 182.6 -> 183, DEPDW 227.9 -> 228
    assert 183 <= seg.threshold < 228
    assert (seg.land == truth).all()


@pytest.mark.parametrize("channel", ["membership", "chromatic"])
def test_land_found_by_membership_and_chromatic_channels(channel):
    img, truth = two_tone()
    seg = segment(img, channel=channel)
    assert (seg.land == truth).all()
    assert (seg.blocked == truth).all()


def test_fixed_threshold_is_used_as_given():
    img, truth = two_tone()
    seg = segment(img, threshold=100)
    assert seg.threshold == 100
    assert (seg.land == truth).all()


def test_plain_grey_otsu_fails_when_land_lies_between_two_water_shades():
    # dark water | land | light water: one grey threshold cannot isolate the middle band
    img = np.empty((40, 90, 3), np.uint8)
    img[:, :30], img[:, 30:60], img[:, 60:] = DEPMS, LANDA, DEPDW
    truth = np.zeros((40, 90), bool)
    truth[:, 30:60] = True
    grey = segment(img, channel="grey", min_area=1).land
    chroma = segment(img, channel="chromatic").land
    assert (chroma == truth).all()
    assert not (grey == truth).all()


def test_text_and_soundings_are_clutter_not_land_nor_water():
    img, truth = two_tone(120, 200)
    for x, y in [(110, 40), (140, 90), (160, 60)]:  # soundings on water
        cv2.putText(img, "23", (x, y), cv2.FONT_HERSHEY_PLAIN, 1.0, (0, 0, 0), 1)
    cv2.putText(img, "ISLE", (10, 60), cv2.FONT_HERSHEY_PLAIN, 1.2, (0, 0, 0), 1)  # on land
    cv2.line(img, (0, 100), (199, 100), (82, 90, 92), 1)  # a line across both
    seg = segment(img)
    assert (seg.land == truth).mean() > 0.998  # only the line's pixels at the edge may differ


def test_user_land_colour_makes_an_unknown_colour_land():
    purple = (120, 60, 160)
    img, truth = two_tone(land=purple, water=(255, 255, 255))
    with pytest.raises(UsvError, match="--land-colour"):
        segment(img)  # purple is nearest the chart palette's magenta ink: no land
    seg = segment(img, land_colours=[purple])
    assert (seg.land == truth).all()


def test_single_colour_and_no_water_are_refused():
    img, _ = two_tone(land=LANDA, water=LANDA)
    with pytest.raises(UsvError, match="single colour"):
        segment(img)
    img, _ = two_tone(land=LANDA, water=(244, 232, 193))  # two land colours
    with pytest.raises(UsvError, match="no navigable water"):
        segment(img)


def test_same_seed_same_result():
    rng = np.random.default_rng(3)
    img, _ = two_tone(100, 100)
    noise = rng.integers(-6, 7, img.shape)
    img = np.clip(img.astype(int) + noise, 0, 255).astype(np.uint8)
    a, b = segment(img, seed=5), segment(img, seed=5)
    assert (a.land == b.land).all() and a.clusters == b.clusters
