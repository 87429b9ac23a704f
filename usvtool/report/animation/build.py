"""``animate(AnimateOptions) -> AnimateResult``: a run as a GIF, an MP4 or an HTML player.

The run is read into a :class:`~usvtool.report.animation.scene.Scene`; a GIF or MP4 is the
frames of :mod:`.frames` encoded by :mod:`.encode`, an HTML player the page of :mod:`.player`.
The result holds the file's bytes: the caller writes them (``usvtool animate`` atomically), or
embeds the player (:attr:`AnimateResult.fragment`, docs/animate.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from usvtool.errors import UsvError

FORMATS = ("gif", "mp4", "html")
#: At most this many frames (a GIF or MP4): the run's seconds / speed x fps.
MAX_FRAMES = 20_000
#: --size limits, pixels.
MIN_SIDE, MAX_SIDE = 160, 4096
DEFAULT_SIZE = (800, 600)


@dataclass(frozen=True)
class AnimateOptions:
    """``trace``: the trace CSV; ``events``: its events JSON (default beside it:
    :func:`~usvtool.report.animation.scene.events_path_for`); ``map``: a grid GeoTIFF to draw
    beneath (default the run's map); ``format``: ``gif``, ``mp4`` or ``html``; ``speed``: times
    real time; ``size``: (width, height) pixels; ``wake``: seconds of track behind each ship;
    ``fps``: frames per second of a GIF or MP4; ``tolerance``: the player's decimation bound,
    metres (its heading bound :data:`~usvtool.report.animation.player.HEADING_BOUND_DEG`)."""

    trace: str
    format: str = "gif"
    events: str | None = None
    map: str | None = None
    speed: float = 10.0
    size: tuple[int, int] = DEFAULT_SIZE
    wake: float = 60.0
    fps: float = 10.0
    tolerance: float = 0.5


@dataclass
class AnimateResult:
    """The file's ``content``; for a player also its ``fragment`` (the markup to embed in a
    page that also holds :func:`~usvtool.report.animation.player.player_script`)."""

    content: bytes
    format: str
    frames: int | None  # a GIF's or MP4's
    ships: int
    duration_s: float
    events: str
    fragment: str | None = None
    keys: int | None = None  # the player's key samples, all ships
    extra: dict = field(default_factory=dict)

    def summary(self) -> dict:
        return {"format": self.format, "bytes": len(self.content), "frames": self.frames,
                "ships": self.ships, "duration_s": round(self.duration_s, 3),
                "events": self.events, "key_samples": self.keys, **self.extra}  # fmt: skip


def check_options(o: AnimateOptions) -> None:
    """Refuse options out of range, naming the option."""
    import math

    if o.format not in FORMATS:
        raise UsvError(f"format {o.format!r}: one of {', '.join(FORMATS)}")
    for name, value in (("--speed", o.speed), ("--fps", o.fps), ("--tolerance", o.tolerance)):
        if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
            raise UsvError(f"{name} must be a number > 0, not {value!r}")
    if not (math.isfinite(o.wake) and o.wake >= 0):
        raise UsvError(f"--wake must be a number >= 0, not {o.wake!r}")
    w, h = o.size
    if not (MIN_SIDE <= w <= MAX_SIDE and MIN_SIDE <= h <= MAX_SIDE):
        raise UsvError(f"--size {w}x{h}: each side {MIN_SIDE} to {MAX_SIDE} pixels")
    if o.format == "mp4" and (w % 2 or h % 2):
        raise UsvError(f"--size {w}x{h}: an MP4's width and height must be even")


def animate(options: AnimateOptions) -> AnimateResult:
    """The animation ``options`` ask for (module docstring)."""
    from pathlib import Path

    from usvtool.report.animation.scene import events_path_for, load_scene

    o = options
    check_options(o)
    if o.format == "mp4":
        from usvtool.report.animation.encode import ffmpeg

        ffmpeg()  # missing: said before any work
    events = o.events if o.events is not None else str(events_path_for(o.trace))
    scene = load_scene(o.trace, events, o.map)
    k = len(scene.ships)
    if o.format == "html":
        from usvtool.report.animation.player import player

        page = player(scene, size=o.size, speed=o.speed, wake=o.wake, tolerance=o.tolerance,
                      name=Path(o.trace).stem)  # fmt: skip
        return AnimateResult(page.html.encode("utf-8"), "html", None, k, scene.duration,
                             events, page.fragment, page.keys,
                             {"tolerance_m": o.tolerance, "bound_m": page.bound_m,
                              "bound_deg": page.bound_deg})  # fmt: skip
    from usvtool.report.animation import encode, frames

    times = frames.frame_times(scene, o.speed, o.fps)
    if times.size > MAX_FRAMES:
        raise UsvError(f"--speed {o.speed:g} at --fps {o.fps:g} makes {times.size} frames of "
                       f"a {scene.duration:g} s run, more than {MAX_FRAMES}: raise --speed or "
                       "lower --fps")  # fmt: skip
    w, h = o.size
    if o.format == "gif":
        content = encode.gif_bytes(frames.render(scene, w, h, times, o.wake), o.fps,
                                   frames.drawn_colours(k))  # fmt: skip
        extra = {"frame_ms": encode.gif_frame_ms(o.fps)}
    else:
        content = encode.mp4_bytes(frames.render(scene, w, h, times, o.wake), w, h, o.fps)
        extra = {"fps": o.fps}
    return AnimateResult(content, o.format, int(times.size), k, scene.duration, events,
                         extra=extra)  # fmt: skip
