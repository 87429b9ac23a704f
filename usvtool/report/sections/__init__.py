"""The comparison report's sections (``usvtool report``, docs/report.md), one module each.

Each section module has a ``section(results)`` that builds its part of the document
(:mod:`usvtool.report.document`) from the loaded results (:mod:`usvtool.report.data`), or
returns None when the results have nothing for it. :data:`SECTIONS` lists them in reading order;
:mod:`usvtool.report.build` builds them all and puts them together. Adding a section is one
module here and one entry in :data:`SECTIONS`. The helpers some sections share are not
sections: :mod:`.published` sets a paper's table beside our figures; the judging, the runs'
files and their outcome words are report-level modules (:mod:`usvtool.report.judging`,
:mod:`usvtool.report.runs`).
"""

from __future__ import annotations

from collections.abc import Callable

from usvtool.report.sections import (
    baselines,
    benchmark_functions,
    claims,
    encounters,
    imazu,
    methods,
    other_methods,
    planning,
    preprocessing,
    summary,
    traffic,
    wind,
    worst_runs,
    your_claims,
)

#: The section modules in reading order: the summary (page 1), the user's claims (a pipeline's
#: ``claims:``), the papers' claims, global path planning, the benchmark functions, collision
#: avoidance in encounters, the Imazu problem, every controller against the field's
#: baselines (vo, sbmpc), the worst run of each scene family per controller, runs in wind,
#: recorded traffic, the methods that are not the papers' (ours and plugins'), the charts'
#: preprocessing and the methods (last).
SECTIONS = (
    summary,
    your_claims,
    claims,
    planning,
    benchmark_functions,
    encounters,
    imazu,
    baselines,
    worst_runs,
    wind,
    traffic,
    other_methods,
    preprocessing,
    methods,
)


#: The sections as :func:`usvtool.report.build.sections` builds them on several processes: one
#: task a process, the largest first so that a short one ends the build (encounters 11-15 s,
#: planning 8-13 s of the 33-45 s the bundled `make report`'s sections take on one core, the
#: others 4 s or less), and together the sections that reuse what another read or computed
#: once per process: the runs' traces and events (:mod:`usvtool.report.runs`; the wind
#: section's come from the encounters'), the judging of the papers' claims and the baselines'
#: standings (the summary, the claims, the baselines). Built one a process, in reading order,
#: the sections took 1.5 times the CPU of one process building them all; so, the same.
TASKS = (
    (encounters, wind),
    (planning,),
    (summary, your_claims, claims, baselines),
    (imazu, worst_runs, traffic),
    (preprocessing,),
    (other_methods,),
    (benchmark_functions,),
    (methods,),
)


def builders() -> tuple[Callable, ...]:
    """Each section's builder (its module's ``section``), in reading order."""
    return tuple(m.section for m in SECTIONS)
