"""A run's player in the report (docs/report.md, "Players"): the player of a trace and events
already read (:func:`run_player`, a :class:`usvtool.report.document.Player` block placed HTML
only) and what the page adds once when it holds players (:func:`assets`): the player's styles
and its script, with :data:`REVEAL`, which opens the ``<details>`` a link of the page points
to. A player in a closed ``<details>`` starts when it opens (:data:`.player.SCRIPT`), so a page
of many folded players starts none at load.
"""

from __future__ import annotations

from pathlib import Path

from usvtool.report.animation.player import SCRIPT, STYLE, player
from usvtool.report.animation.scene import scene_of
from usvtool.report.document import Player
from usvtool.trace import Trace

#: A report player's pixels (it shrinks to the page) and speed (times real time).
SIZE = (640, 480)
SPEED = 10.0

#: Opens the element a link of the page points to (``href="#ID"``, or the page's address's
#: ``#ID``) and every ``<details>`` around it, so that a link to a folded player shows it; the
#: player starts as its ``<details>`` opens.
REVEAL = r"""
(function () {
  "use strict";
  function reveal(id) {
    var e = id ? document.getElementById(id) : null;
    for (var p = e; p; p = p.parentElement) { if (p.tagName === "DETAILS") { p.open = true; } }
  }
  document.addEventListener("click", function (e) {
    var a = e.target && e.target.closest ? e.target.closest("a[href^='#']") : null;
    if (a) { reveal(a.getAttribute("href").slice(1)); }
  });
  function fromAddress() { reveal(window.location.hash.slice(1)); }
  window.addEventListener("hashchange", fromAddress);
  fromAddress();
})();
"""


def run_player(trace: Trace, events: dict, events_path: Path | str, id: str, title: str,
               caption: str, size: tuple[int, int] = SIZE) -> Player:  # fmt: skip
    """The block of a run's player: its trace and events (already read:
    :func:`usvtool.report.runs.run_files`) and their file (which resolves the run's map)."""
    fragment = player(scene_of(trace, events, events_path), size=size, speed=SPEED).fragment
    return Player(id, title, caption, fragment)


def assets() -> tuple[str, str]:
    """The page's player styles and its one script (the players' and :data:`REVEAL`)."""
    return STYLE, SCRIPT + REVEAL
