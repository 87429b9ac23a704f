"""Regression reports: compare a current results table with a baseline (``usvtool compare``,
docs/compare.md).

Both tables are results tables (:mod:`usvtool.results`). Rows are matched by group (kind, case,
method, metric) and each side's value of a group is one figure over its jobs (seeds):

- ``median`` of the numbers (lengths, turns, times, costs, ...);
- ``mean`` when every value is ``True``/``False``: the rate of ``True`` (a median of 0/1 values
  is no rate);
- ``share`` for :data:`.sides.EVENTS` (``collision``, whose row is there only when the ship
  hit something, the value naming what): the fraction of the case and method's jobs with a row;
- ``words`` otherwise (``failed_rules``, ...): the sorted set of the ``;``-separated words.

A metric of :data:`.sides.ABSENT_IS_NONE` that a side lacks while it has the case and method is
that side's "none" (a share of 0, no words), not a missing group.

Each metric's values must be of its kind (:mod:`usvtool.report.values`: the contract's finite
numbers, ``True``/``False`` or words; a metric it does not list takes the baseline's kind). A
baseline holding a value that is not of its kind is refused; a group of the current table
holding one is ``invalid`` (its figure: those values), whatever the other values are.

Each metric has a :class:`.tolerances.Rule` (:data:`.tolerances.RULES`; unknown metrics are
informational): the better direction and a tolerance. With ``change = head - base`` and
``allowed = max(relative * |base|, absolute)``, a group is ``ok`` when ``|change| <= allowed``,
else ``improved`` or ``regressed`` by the direction, or ``changed`` for an informational metric
(words: ``ok`` when equal, else ``changed``); ``change`` and ``allowed`` are rounded to 12
significant digits first. A group only in the baseline is ``missing``, only in the current
table ``new``. Timings (:data:`usvtool.results.TIMING_METRICS`, from ``timings.csv`` beside
either table) are classified the same way but count towards the status only when the
tolerances file (``BASELINE`` with the suffix ``.tolerances.yaml`` unless given) says
``count_timings: true``. The status is 1 when a counted group is invalid, regressed or went
missing.

The modules, in the order of the work: :mod:`.tolerances` (the rules and the tolerances file),
:mod:`.sides` (a table as groups, each group's figure), :mod:`.groups` (one group compared: its
class), :mod:`.presentation` (the HTML page and the Markdown summary) and :mod:`.compare` (the
entry point, :func:`.compare.compare`: both tables compared, and with ``out_dir`` the outputs
``index.html``, ``regression.json`` and ``summary.md`` renamed into place together).
"""
