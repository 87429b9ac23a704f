"""Frames into a GIF (Pillow) or an MP4 (ffmpeg), byte for byte the same for the same frames.

GIF: one palette for every frame: the colours drawn (the ships', the timeline's, a grey ramp)
and Pillow's median cut (deterministic) of the first frame for the rest (the map, blends), each
frame mapped to it without dithering; the frame time in whole
hundredths of a second (GIF's unit), looping. MP4: ffmpeg's libx264 fed the raw RGB frames on
its standard input, fixed settings (preset ``medium``, CRF 23, yuv420p, one thread, no
metadata, bit-exact flags), written to a temporary folder and read back.
"""

from __future__ import annotations

import io
import shutil
import subprocess
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path

import numpy as np

from usvtool.errors import UsvError

FFMPEG_HINT = "install ffmpeg (Debian: apt-get install ffmpeg; make test installs it as root)"


def ffmpeg() -> str:
    """The ffmpeg program; a :class:`UsvError` saying what to install when it is missing."""
    program = shutil.which("ffmpeg")
    if program is None:
        raise UsvError(f"an MP4 needs ffmpeg, which is not installed: {FFMPEG_HINT}; or write a "
                       ".gif or .html")  # fmt: skip
    return program


def gif_bytes(frames: Iterator[np.ndarray], fps: float, colours=()) -> bytes:
    """The GIF of ``frames`` (module docstring); ``colours`` (``#rrggbb``) have entries of their
    own in its palette (a ship's colour, barely in the first frame, would be merged away)."""
    from PIL import Image

    frames = iter(frames)
    start = next(frames)
    fixed = [tuple(int(c[i:i + 2], 16) for i in (1, 3, 5)) for c in dict.fromkeys(colours)]
    fixed += [(v, v, v) for v in range(0, 256, 32)] + [(255, 255, 255)]
    cut = Image.fromarray(start).quantize(colors=255 - len(fixed), method=Image.Quantize.MEDIANCUT,
                                          dither=Image.Dither.NONE)  # fmt: skip
    entries = cut.getpalette()[: 3 * (255 - len(fixed))]
    palette = Image.new("P", (1, 1))
    palette.putpalette(entries + [v for rgb in fixed for v in rgb])

    def paletted(items: Iterable[np.ndarray]):
        for rgb in items:
            yield Image.fromarray(rgb).quantize(palette=palette, dither=Image.Dither.NONE)

    images = paletted(frames)
    first = next(paletted([start]))
    buf = io.BytesIO()
    first.save(buf, format="GIF", save_all=True, append_images=images, loop=0,
               duration=gif_frame_ms(fps), optimize=False, disposal=1)  # fmt: skip
    return buf.getvalue()


def gif_frame_ms(fps: float) -> int:
    """A GIF frame's time: 1/fps rounded to GIF's hundredths of a second (at least 2)."""
    return 10 * max(2, round(100 / fps))


def mp4_bytes(frames: Iterator[np.ndarray], width: int, height: int, fps: float) -> bytes:
    """The H.264 MP4 of ``frames`` (module docstring)."""
    program = ffmpeg()
    with tempfile.TemporaryDirectory(prefix="usvtool-mp4-") as tmp:
        out = Path(tmp) / "out.mp4"
        command = [
            program, "-hide_banner", "-loglevel", "error", "-nostdin",
            "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{width}x{height}",
            "-framerate", f"{fps:g}", "-i", "pipe:0", "-an",
            "-c:v", "libx264", "-preset", "medium", "-crf", "23", "-pix_fmt", "yuv420p",
            "-threads", "1", "-x264-params", "threads=1:lookahead-threads=1",
            "-fflags", "+bitexact", "-flags:v", "+bitexact", "-map_metadata", "-1",
            "-movflags", "+faststart", "-f", "mp4", str(out),
        ]  # fmt: skip
        process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.PIPE)  # fmt: skip
        try:
            for rgb in frames:
                process.stdin.write(np.ascontiguousarray(rgb).tobytes())
            process.stdin.close()
        except BrokenPipeError:
            pass
        except BaseException:
            process.kill()
            process.wait()
            raise
        errors = process.stderr.read().decode("utf-8", "replace")
        if process.wait() != 0 or not out.is_file():
            line = " ".join(errors.split())[:300] or f"exit status {process.returncode}"
            raise UsvError(f"ffmpeg could not write the MP4: {line}")
        return out.read_bytes()
