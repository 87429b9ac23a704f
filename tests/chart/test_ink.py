"""The ink rule on small drawn charts: each symbol's expected class is known by construction.

A 300 x 300 water image with a strip of land on the west, ordinary text (OpenCV's plain font,
1-pixel strokes; the chart's stroke width is then its floor, 2 px) and one symbol per test. The
same drawings scaled 2 and 3 times (every pixel a 2 x 2 or 3 x 3 block, as a chart scanned at a
higher resolution) must be read the same: the rule measures the chart's own strokes.
"""

import cv2
import numpy as np
import pytest

from usvtool.chart.ink import land_side, resolve, stroke_width

SIZE = 300


def chart():
    """(ink, land): land is the strip x < 30; text lines in the water set the stroke width."""
    ink = np.zeros((SIZE, SIZE), np.uint8)
    for row, text in ((40, "12 7 9 10"), (270, "Lake 4 5 so")):
        cv2.putText(ink, text, (120, row), cv2.FONT_HERSHEY_PLAIN, 1.2, 1, 1, cv2.LINE_8)
    land = np.zeros((SIZE, SIZE), bool)
    land[:, :30] = True
    return ink, land


def classify(draw, mode="auto", scale=1):
    ink, land = chart()
    symbol = np.zeros_like(ink)
    draw(symbol)
    ink = (ink | symbol).astype(bool)
    block = np.ones((scale, scale), np.uint8)
    ink, land, symbol = (np.kron(a.astype(np.uint8), block).astype(bool)
                         for a in (ink, land, symbol))  # fmt: skip
    new_land, hazard = resolve(ink, land, mode)
    return symbol, hazard, new_land


def bold_ring(im):
    """A pile ring of strokes 3 pixels wide (1.5 times the text's) with a tick below it."""
    cv2.circle(im, (150, 150), 4, 1, 2)
    im[156:158, 150] = 1


def light_dot(im):
    """An 8 x 8 dot with its corners off: the smallest solid an opening by an ellipse missed."""
    im[146:154, 146:154] = 1
    im[[146, 146, 153, 153], [146, 153, 146, 153]] = 0


def test_the_text_sets_a_two_pixel_stroke():
    ink, _ = chart()
    assert stroke_width(ink.astype(bool)) == 2.0


def test_text_and_soundings_are_clutter():
    ink, land = chart()
    _, hazard = resolve(ink.astype(bool), land)
    assert not hazard.any()


@pytest.mark.parametrize(
    "name, draw",
    [
        ("solid square", lambda im: cv2.rectangle(im, (150, 120), (161, 131), 1, -1)),
        ("filled dot", lambda im: cv2.circle(im, (150, 150), 5, 1, -1)),
        ("pile ring", lambda im: cv2.circle(im, (150, 150), 3, 1, 1)),
        ("bold pile ring with a tick", lambda im: bold_ring(im)),
        ("light dot", lambda im: light_dot(im)),
        # a wreck's hull: a filled triangle, twice as long as high (tapered, not a disc)
        ("hull", lambda im: cv2.fillPoly(im, [np.array([[138, 160], [162, 160], [150, 148]])], 1)),
        # a detached breakwater: a long straight thick bar of dark ink standing free
        ("breakwater", lambda im: cv2.line(im, (80, 200), (200, 200), 1, 4)),
        ("thick pier from the shore", lambda im: cv2.line(im, (30, 150), (90, 150), 1, 4)),
    ],
)
@pytest.mark.parametrize("scale", [1, 2, 3])
def test_hazards_are_obstacles_at_their_footprint(name, draw, scale):
    symbol, hazard, _ = classify(draw, scale=scale)
    assert hazard[symbol].mean() > 0.95, name
    assert not (hazard & ~symbol).any() or "ring" in name  # a ring also blocks its inside


def comb(im):
    """A marina's docks in ordinary 2-pixel strokes: a spine from the shore, fingers 30 pixels
    long every 8 pixels (ink about 4.5 times its box diagonal times the stroke width)."""
    im[120:122, 31:141] = 1
    for x in range(40, 141, 8):
        im[106:136, x : x + 2] = 1


def meander(im):
    """A winding contour leaving the shore: a sine of 10 pixels amplitude and 19 pixels period (ink
    1.6 times its box diagonal times the stroke width)."""
    x = np.arange(31, 151)
    pts = np.column_stack([x, 200 + 10 * np.sin((x - 31) / 3.0)]).astype(np.int32)
    cv2.polylines(im, [pts, pts + [0, 1]], False, 1, 1)  # 2 pixels wide, like the text


@pytest.mark.parametrize("scale", [1, 2, 3])
def test_a_dock_network_from_the_shore_is_a_hazard(scale):
    symbol, hazard, _ = classify(comb, scale=scale)
    assert hazard[symbol].mean() > 0.95


@pytest.mark.parametrize("scale", [1, 2, 3])
def test_a_winding_contour_from_the_shore_stays_clutter(scale):
    symbol, hazard, _ = classify(meander, scale=scale)
    assert not hazard[symbol].any()


def test_a_pile_ring_blocks_its_inside():
    symbol, hazard, _ = classify(lambda im: cv2.circle(im, (150, 150), 3, 1, 1))
    assert hazard[150, 150] and not symbol[150, 150]


@pytest.mark.parametrize(
    "name, draw",
    [
        ("thin line from the shore", lambda im: cv2.line(im, (31, 150), (120, 150), 1, 1)),
        ("graticule", lambda im: cv2.line(im, (150, 60), (150, 250), 1, 1)),
        # a dashed limit: thick dashes, each shorter than 25 strokes, off the shore
        ("dashes", lambda im: [cv2.line(im, (x, 150), (x + 20, 150), 1, 4)
                               for x in range(80, 260, 30)]),
        ("short dashes", lambda im: [cv2.line(im, (x, 150), (x + 10, 150), 1, 4)
                                     for x in range(80, 260, 20)]),
        ("a zero", lambda im: cv2.ellipse(im, (150, 150), (4, 7), 0, 0, 360, 1, 1)),
    ],
)
@pytest.mark.parametrize("scale", [1, 2, 3])
def test_clutter_stays_water(name, draw, scale):
    symbol, hazard, new_land = classify(draw, scale=scale)
    assert not hazard[symbol].any(), name
    assert not new_land[symbol].any()


@pytest.mark.parametrize("scale", [1, 2, 3])
def test_a_free_thick_line_of_a_light_ink_is_clutter(scale):
    """The same bar drawn in a lighter ink than the text (a range or limit line in magenta,
    which crosses channels) stays clutter."""
    ink, land = chart()
    bar = np.zeros_like(ink)
    cv2.line(bar, (80, 200), (200, 200), 1, 4)
    block = np.ones((scale, scale), np.uint8)
    ink, land, bar = (np.kron(a.astype(np.uint8), block).astype(bool)
                      for a in (ink | bar, land, bar))  # fmt: skip
    layers = bar.astype(np.uint8)  # the text in layer 0 (dark), the bar in layer 1
    _, hazard = resolve(ink, land, "auto", layers, dark_layers=[0])
    assert not hazard[bar].any()
    _, hazard = resolve(ink, land, "auto", layers, dark_layers=[0, 1])
    assert hazard[bar].mean() > 0.95


def test_a_pile_ring_on_a_contour_of_another_ink_is_a_hazard():
    """A black pile ring drawn where a grey depth contour passes: cut apart where the two inks
    meet, the ring stands alone; drawn in one ink, ring and line are one symbol and stay open."""
    ink, land = chart()
    ring, contour = np.zeros_like(ink), np.zeros_like(ink)
    cv2.circle(ring, (150, 150), 3, 1, 1)
    cv2.line(contour, (100, 146), (200, 146), 1, 1)  # touches the ring's top
    ink = (ink | ring | contour).astype(bool)
    layers = contour.astype(np.uint8)  # text and ring in layer 0, the contour in layer 1
    _, hazard = resolve(ink, land, "auto", layers, dark_layers=[0])
    assert hazard[150, 150]
    _, hazard = resolve(ink, land, "auto", np.zeros_like(layers), dark_layers=[0])
    assert not hazard[150, 150]


def test_modes():
    draw = lambda im: cv2.line(im, (30, 150), (120, 150), 1, 1)  # noqa: E731
    symbol, hazard, _ = classify(draw, "obstacle")
    assert hazard[symbol][1:].all()  # every ink pixel in water (its first touches the land)
    _, hazard, _ = classify(lambda im: cv2.circle(im, (150, 150), 5, 1, -1), "clutter")
    assert not hazard.any()
    with pytest.raises(ValueError):
        resolve(np.zeros((3, 3), bool), np.zeros((3, 3), bool), "maybe")


def test_ink_takes_the_side_of_its_nearest_non_ink_pixel():
    # a 6-pixel band: the three pixels next to land are land, the three next to water water
    ink = np.zeros((5, 20), bool)
    ink[:, 4:10] = True
    land = np.zeros((5, 20), bool)
    land[:, :4] = True
    side = land_side(ink, land)
    assert side[:, 4:7].all() and not side[:, 7:10].any()


def test_banded_distances_equal_the_whole_image_transform(monkeypatch):
    """Distances at the blobs' pixels, computed in bands of 16 rows grown by the tallest blob's
    height, are those of one transform over the whole image (blobs straddle the bands)."""
    import usvtool.chart.ink as ink_module

    rng = np.random.default_rng(3)
    mask = np.zeros((200, 150), np.uint8)
    for _ in range(40):
        x, y, r = int(rng.integers(5, 145)), int(rng.integers(5, 195)), int(rng.integers(1, 9))
        cv2.circle(mask, (x, y), r, 1, -1)
    mask = mask.astype(bool)
    at = np.flatnonzero(mask)
    monkeypatch.setattr(ink_module, "BAND", 16)
    banded = ink_module._distance_at(mask, at, 20)  # blobs are at most 17 rows high
    whole = ink_module._distance(mask).ravel()[at]
    # OpenCV's transform can differ in the last bit of a float between calls in a process
    assert np.allclose(banded, whole, rtol=0, atol=1e-5)


def test_banded_sides_equal_the_whole_image_transforms(monkeypatch):
    """The ink's side and the stroke width from bands of 16 rows grown by 8 equal those of the
    whole-image transforms; ink deeper than the bands reach (a 30-pixel solid) takes the
    whole-image path and gives the same answer."""
    import usvtool.chart.ink as ink_module

    ink, land = chart()
    ink = ink.astype(bool)
    ink[60:70, 40:140] = True  # a thick stroke leaving the shore band: both sides
    deep = ink.copy()
    deep[150:180, 150:180] = True
    for image in (ink, deep):
        dist = ink_module._distance(image)
        expected = (ink_module._distance(~(land & ~image)) <= dist) & image
        for band, reach in ((16, 8), (4096, 64)):
            monkeypatch.setattr(ink_module, "BAND", band)
            monkeypatch.setattr(ink_module, "REACH", reach)
            on_land, w = ink_module._sides(image, land, width=True)
            assert np.array_equal(on_land, expected)
            assert w == stroke_width(image)
